//! The wear stage (MODEL.md#step-10-wear-law, #step-11-wear-zone, #step-12-feedback): from a
//! wheel's vibration to the wear it lays on the tread, and from the worn profile back to the
//! friction levels. One file per job: [`law`] (friction power, even wear, laying one revolution
//! of wear onto the circumference), [`slip`] (the driving wheel's longitudinal slip power),
//! [`zone`] (where on the patch the wear goes, its kernels and
//! transfers), [`feedback`] (the profile's action on the friction levels), [`calibration`] (the
//! abradability γ, once per run), [`fitted`] (the field-fitted constants as one value, for the
//! calibration band), [`cycle`] (one sampled period of a limit cycle). The
//! per-sample estimator (MODEL.md#the-per-sample-estimator) builds on them: [`transfer`] (the
//! response to ε at a state and at the equilibrium, as poles), [`periodic`] (the cycle's
//! response, Floquet modes and harmonic balance), [`spread`] (exact means of poles over a normal
//! speed spread), [`estimator`] (the growth of each order, the dominant one, the distance to a
//! visible polygon). The long-term loop (MODEL.md#the-long-term-loop) runs the wear by brute
//! force: [`profile`] (the worn depth on cells, the seed), [`window`] (a few revolutions at a
//! fixed profile), [`lock`] (the rotation number and the weights of the mean revolution),
//! [`deposit`] (the energy laid element by element), [`edge`] (how finely a lock edge is placed), [`legs`] (the speeds driven),
//! [`long_term`] (the loop), and [`accelerated`] (the oracle by another road).
//!
//! Conventions, everywhere in this module:
//!
//! - **Units**: SI inside (m, s, N, W, m³/J); depth per distance in m/m, growth in 1/m. Output
//!   columns convert to mm/1000 km and 1/1000 km ([`law::MM_PER_1000KM_PER_M_PER_M`],
//!   [`law::PER_1000KM_PER_PER_M`]).
//! - **Power**: P = F·w ≥ 0 \[W\], F = σ0 z + σ1 ż the friction force the tread exerts on the
//!   road, w = v − U its sliding speed ([`law::friction_power_w`]).
//! - **Angles**: θ ∈ \[0, 2π) is fixed to the tyre. The tread element at θ passes the patch
//!   coordinate x (trailing edge −a/2, leading edge +a/2) at the time when the element at the
//!   patch centre is at angle Ωt = θ − x/r_B, Ω = 2π f_rot.
//! - **Profile**: d(θ) is the worn depth; only its deviation from the mean acts back. The radius
//!   deviation is r(θ) = −(d(θ) − d̄): r > 0 is a high spot, less worn, under more pressure.
//! - **Harmonics**: R_n is the complex amplitude of order n of r, r(θ) = Σ_n Re\[R_n e^{inθ}\];
//!   D_n = 2|R_n| is the polygon's peak-to-valley depth.
//! - **ε**: the relative change of both friction levels, F_{m,s} → F_{m,s}·(1 + ε); a profile
//!   harmonic R_n forces ε(t) = Re\[e_n R_n e^{inΩt}\] with e_n = κ H_w(n) + ∂ln(F_Z L)/∂F_Z ·
//!   k_r H_p(n) ([`feedback::Feedback::forcing_per_radius`]).
//! - **Transfers**: H(n) = ∫K(x) e^{inx/r_B} dx for a kernel K of the patch ([`zone`]); the
//!   wear laid back onto the tyre by the zone carries conj(H_w(n)).
//! - **Growth**: β_n \[1/m\] is the rate of |R_n| per metre travelled: |R_n| ∝ e^{β_n s}.

pub mod accelerated;
pub mod calibration;
pub mod cycle;
pub mod deposit;
pub mod edge;
mod error;
pub mod estimator;
pub mod feedback;
pub mod fitted;
pub mod forced_orbit;
pub mod law;
pub mod legs;
pub mod lock;
pub mod long_term;
pub mod normal_form;
pub mod periodic;
pub mod profile;
pub mod slip;
pub mod spread;
mod step_rule;
pub mod tongue;
pub mod transfer;
pub mod wheel_wear;
pub mod window;
pub mod zone;

pub use calibration::Calibration;
pub use error::WearError;
pub use estimator::{
    estimate, retired_level, LifeAnswer, LifeProfile, WearEstimate, WearInputs, WearSettings,
    WheelGrowth, LIFE_PROFILE_INTERVALS, SHIPPED_LEVEL,
};
pub use feedback::Feedback;
pub use fitted::{FittedConstants, WearAnswer};
pub use slip::WearPower;
pub use zone::{WearZone, ZoneGeometry};

/// The wear stage's category settings as rows of `polywear params`: name, default,
/// provenance, accepted names, meaning.
pub fn setting_rows() -> [[String; 5]; 2] {
    fn row(
        name: &str,
        default: &str,
        names: &[&str],
        what: &str,
        each: Vec<String>,
    ) -> [String; 5] {
        [
            name.into(),
            default.into(),
            "judgement".into(),
            names.join(", "),
            format!("{what}, a category: {}.", each.join("; ")),
        ]
    }
    [
        row(
            "wear_zone",
            WearZone::DEFAULT.as_str(),
            <WearZone as strum::VariantNames>::VARIANTS,
            "Where on the contact patch the friction power wears the tread",
            WearZone::ALL
                .iter()
                .map(|z| format!("{} = {}", z.as_str(), z.description()))
                .collect(),
        ),
        row(
            "wear_power",
            WearPower::DEFAULT.as_str(),
            <WearPower as strum::VariantNames>::VARIANTS,
            "Which friction power wears the tread",
            WearPower::ALL
                .iter()
                .map(|z| format!("{} = {}", z.as_str(), z.description()))
                .collect(),
        ),
    ]
}

/// Complex numbers of the transfers (nalgebra's, which the eigenvalues already use).
pub type Complex64 = nalgebra::Complex<f64>;
