//! The scales of the tread's three states at its equilibrium (MODEL.md#step-6-tread-ode): what
//! the classifier's tolerances and convergence tests are relative to.

use crate::model::TreadOde;

/// Scales of the three states at one equilibrium, for tolerances and convergence tests.
#[derive(Debug, Clone, Copy)]
pub struct Scales {
    /// z at the equilibrium \[m\].
    pub z_eq: f64,
    /// y at the equilibrium \[m\].
    pub y_eq: f64,
    /// |z0| \[m\].
    pub z: f64,
    /// |y0| \[m\].
    pub y: f64,
    /// Road lateral speed U [m/s].
    pub v: f64,
}

impl Scales {
    /// The scales at `ode`'s equilibrium.
    pub fn new(ode: &TreadOde) -> Self {
        let eq = ode.equilibrium();
        Scales {
            z_eq: eq[0],
            y_eq: eq[1],
            z: eq[0].abs(),
            y: eq[1].abs(),
            v: ode.u_mps.abs(),
        }
    }

    /// Absolute tolerances matching `rtol` at these scales.
    pub fn atol(&self, rtol: f64) -> [f64; 3] {
        [rtol * self.z, rtol * self.y, rtol * self.v]
    }
}
