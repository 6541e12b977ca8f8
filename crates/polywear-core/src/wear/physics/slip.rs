//! The driving wheel's longitudinal sliding in its wear (MODEL.md#the-driving-wheels-slip-power).
//! Under the parabolic pressure of Eq. 3 a bristle enters the patch undeflected and leaves it
//! undeflected, so all the work the wheel does on the bristles against the road is dissipated by
//! sliding friction in the rear sliding zone: the brush model's longitudinal friction power is
//! the slip power
//!
//! ```text
//! P_x = F_X · V cos α · S / (1 + S)      [W]
//! ```
//!
//! with F_X = F_drive the force of Eq. 11 at the wheel's slip ratio S (step 4). It wears the same
//! zone as the lateral power, each element by its pressure. A polygon modulates the pressure at
//! n·f_rot (270 Hz at the default point), far faster than the wheel's rotation can follow, so S
//! is frozen over a modulation: the sliding speed stays, and the zone total follows only F_X's own
//! dependence on the friction level, G_x = ∂ln F_X/∂ε at fixed S (Eq. 11; +0.054 at the default
//! point). F_X is mostly the adhesion zone's elastic force, so G_x is small: a tenth of the
//! lateral tread's G(0) = 1.

use crate::model::brush::{drive_force_n, longitudinal_force_n};
use crate::model::{Wheel, WheelModel};
use crate::params::Params;

named_enum! {
    /// Which friction power wears the tread (the `wear_power` setting;
    /// MODEL.md#the-driving-wheels-slip-power).
    pub enum WearPower: "wear power" {
        /// The tread's lateral power, and the driving wheel's longitudinal slip power
        /// F_X·V cos α·S/(1 + S) in the same zone; the driven position's other wear at
        /// `wear_rate_driven_factor` times w′₀. The shipped default.
        WithSlip,
        /// The tread's lateral power alone, both wheels at w′₀: the reading before the slip
        /// power was counted, on which the worst-case checks at φ_s = 1 run.
        LateralOnly,
    }
}

impl WearPower {
    /// Every reading, in the order of the declaration.
    pub const ALL: [WearPower; 2] = [WearPower::WithSlip, WearPower::LateralOnly];
    /// The reading every command uses unless told otherwise.
    pub const DEFAULT: WearPower = WearPower::WithSlip;

    /// What the reading is, in a sentence (for `polywear params`).
    pub fn description(self) -> &'static str {
        match self {
            WearPower::WithSlip => {
                "the lateral friction power and the driving wheel's longitudinal slip power; the driven position's other wear scaled by wear_rate_driven_factor"
            }
            WearPower::LateralOnly => {
                "the lateral friction power alone, the same even-wear rate on both wheels"
            }
        }
    }
}

impl Default for WearPower {
    fn default() -> Self {
        WearPower::DEFAULT
    }
}

/// The slip power of one wheel and its response to a relative change ε of the friction levels.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SlipPower {
    /// P_x \[W\]: 0 for the follower, and under [`WearPower::LateralOnly`].
    pub power_w: f64,
    /// G_x = ∂ln P_x/∂ε at fixed S (0 where P_x = 0).
    pub gain: f64,
}

impl SlipPower {
    /// The slip power of `model`'s wheel at `p` under the reading `power`.
    pub fn of(p: &Params, model: &WheelModel, power: WearPower) -> Self {
        let s = model.slip_ratio;
        if power == WearPower::LateralOnly || model.wheel == Wheel::Follower || s <= 0.0 {
            return SlipPower::default();
        }
        let force_n = drive_force_n(p);
        let power_w = force_n * p.speed_mps() * p.toe_rad().cos() * s / (1.0 + s);
        SlipPower {
            power_w,
            gain: gain(p, model),
        }
    }
}

/// G_x = ∂ln P_x/∂ε = ∂ln F_X/∂ε at fixed S: ε scales both friction coefficients of Eq. 11
/// (μ_m through q, μ_s in the sliding term); a central difference.
fn gain(p: &Params, model: &WheelModel) -> f64 {
    let s = model.slip_ratio;
    let force = |eps: f64| {
        let q = Params {
            mu_m: p.mu_m * (1.0 + eps),
            mu_s: p.mu_s * (1.0 + eps),
            ..*p
        };
        longitudinal_force_n(&q, &model.patch, s)
    };
    let h = 1e-6;
    let f0 = force(0.0);
    if f0 <= 0.0 {
        return 0.0;
    }
    (force(h) - force(-h)) / (2.0 * h) / f0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Variant;

    /// At the default point the driving wheel's slip power is F_drive·V cos α·S/(1 + S), as
    /// large as its lateral power, and its gain is Eq. 11's relative change at the frozen S
    /// when both friction coefficients rise by 1%: small and positive.
    #[test]
    fn slip_power_is_the_drive_force_times_the_sliding_speed_and_rises_a_little_with_friction() {
        let p = Params::default();
        let m = WheelModel::build(&p, Wheel::Driving, Variant::DEFAULT).unwrap();
        let sp = SlipPower::of(&p, &m, WearPower::WithSlip);
        let expected = drive_force_n(&p) * p.speed_mps() * p.toe_rad().cos() * m.slip_ratio
            / (1.0 + m.slip_ratio);
        assert_eq!(sp.power_w, expected);
        assert!((sp.power_w - 37.06).abs() < 0.01, "{}", sp.power_w);
        assert!(sp.gain > 0.0 && sp.gain < 0.1, "{}", sp.gain);
        // Both friction coefficients 1% higher at the same S: ln F_X moves by G_x·0.01.
        let eps = 1e-2;
        let q = Params {
            mu_m: p.mu_m * (1.0 + eps),
            mu_s: p.mu_s * (1.0 + eps),
            ..p
        };
        let f = |p: &Params| longitudinal_force_n(p, &m.patch, m.slip_ratio);
        let measured = (f(&q) / f(&p)).ln() / eps;
        assert!(
            (measured - sp.gain).abs() < 0.02 * sp.gain.abs() + 1e-4,
            "{measured} vs {}",
            sp.gain
        );
        // The follower and the lateral-only reading have none.
        let f = WheelModel::build(&p, Wheel::Follower, Variant::DEFAULT).unwrap();
        assert_eq!(
            SlipPower::of(&p, &f, WearPower::WithSlip),
            SlipPower::default()
        );
        assert_eq!(
            SlipPower::of(&p, &m, WearPower::LateralOnly),
            SlipPower::default()
        );
    }
}
