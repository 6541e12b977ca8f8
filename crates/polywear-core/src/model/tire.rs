//! Tire geometry and the tread block (MODEL.md#step-1-deflection to #step-3-tread-block; paper
//! Eqs. 13, 14, 16).

use crate::params::Params;

/// The tire–road contact patch under load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPatch {
    /// Maximum radial deflection δ (Eq. 14).
    pub deflection_m: f64,
    /// Contact length a (Eq. 13).
    pub length_m: f64,
    /// Contact width b (Eq. 13).
    pub width_m: f64,
}

/// No contact patch: the deflection is so large that the contact length is undefined.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("contact patch undefined: xi*deflection = {xi_deflection_m:.4} m reaches the tire diameter 2*r_b = {diameter_m:.4} m")]
pub struct FlatTire {
    /// ξδ \[m\].
    pub xi_deflection_m: f64,
    /// 2 r_B \[m\].
    pub diameter_m: f64,
}

/// Contact patch from load and pressure (steps 1–2). Fails when the deflection is so large that
/// the contact length is undefined (ξδ ≥ 2 r_B): the tire would be flat.
pub fn contact_patch(p: &Params) -> Result<ContactPatch, FlatTire> {
    let alpha1 = 1.0 / (2.0 * std::f64::consts::PI * (p.r_b * p.r_w).sqrt());
    let t = alpha1 * p.load_n / (2.0 * p.pressure_pa());
    let deflection_m = t + (t * t + p.alpha2 * p.load_n).sqrt();
    let xd = p.xi * deflection_m;
    let chord_sq = 2.0 * p.r_b * xd - xd * xd;
    if chord_sq.is_nan() || chord_sq <= 0.0 {
        return Err(FlatTire {
            xi_deflection_m: xd,
            diameter_m: 2.0 * p.r_b,
        });
    }
    Ok(ContactPatch {
        deflection_m,
        length_m: 2.0 * chord_sq.sqrt(),
        width_m: p.b0 * (1.0 - (-p.psi * deflection_m).exp()),
    })
}

/// Lateral stiffness and mass of the tread block in the contact patch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreadBlock {
    /// K_s, which is also the LuGre bristle stiffness σ0 (step 3).
    pub stiffness_n_per_m: f64,
    /// m = ρ a b h.
    pub mass_kg: f64,
}

/// Tread block shear stiffness with the bending correction of Eq. 16 (reconstructed form).
pub(crate) fn tread_block(p: &Params, patch: &ContactPatch) -> TreadBlock {
    let beta = patch.length_m / p.tread_height;
    let pi2 = std::f64::consts::PI * std::f64::consts::PI;
    let stiffness_n_per_m =
        p.g_mod * patch.width_m * beta * (1.0 - 6.0 / (6.0 + pi2 * beta * beta));
    TreadBlock {
        stiffness_n_per_m,
        mass_kg: p.rho * patch.length_m * patch.width_m * p.tread_height,
    }
}
