//! The physics of MODEL.md#the-physics-step-by-step, steps 1–8: from an operating point and a wheel
//! kind to the coefficients of the tread ODE. Pure functions of [`Params`]; no integration happens
//! here.

pub mod brush;
pub mod jet;
pub mod tire;
pub mod tread;
mod variational;

use std::fmt;

use crate::params::Params;
pub use brush::{FrictionLevels, NoTraction};
pub use jet::TreadSystem;
pub use tire::{ContactPatch, TreadBlock};
pub use tread::{LinearStability, State, TreadOde};
pub use variational::{SectionVariational, Variational};

// The wheel's role is declared beside the axles and drivetrain that place it on the car
// (params::axle), which the model reads and never the other way round.
pub use crate::params::axle::Wheel;

named_enum! {
    /// How the Stribeck curve sees sliding (MODEL.md#step-6-tread-ode).
    pub enum Variant: "variant" {
        /// The paper's Eq. 21: only the lateral sliding speed, w_t = |w|.
        Paper,
        /// 2-D LuGre extension: w_t = sqrt(w² + V_sx²) with the driving wheel's full longitudinal
        /// sliding speed V_sx = V cos α S/(1+S).
        Combined,
        /// 2-D LuGre over the patch (MODEL.md#step-6-tread-ode, the shipped default): as `Combined`,
        /// but with the patch-mean longitudinal sliding speed q·V cos α S/(1+S), since only the sliding
        /// share q of the contact length slides lengthwise. The one reading that reproduces the paper's
        /// driving-wheel results (MODEL.md#the-default-sliding-share).
        SlidingShare,
    }
}

impl Variant {
    /// Every variant.
    pub const ALL: [Variant; 3] = [Variant::Paper, Variant::Combined, Variant::SlidingShare];
    /// The variant every command and built-in study uses unless told otherwise.
    pub const DEFAULT: Variant = Variant::SlidingShare;
}

/// Longitudinal sliding speed seen by the Stribeck curve (MODEL.md#step-6-tread-ode) [m/s]: none
/// under `paper` (Eq. 21), V cos α S/(1+S) under `combined`, and its patch mean q·V cos α S/(1+S)
/// under `sliding_share`. Zero for the follower (S = 0) in every variant.
pub fn longitudinal_sliding_mps(
    variant: Variant,
    speed_mps: f64,
    toe_rad: f64,
    slip_ratio: f64,
    sliding_share: f64,
) -> f64 {
    let full = speed_mps * toe_rad.cos() * slip_ratio / (1.0 + slip_ratio);
    match variant {
        Variant::Paper => 0.0,
        Variant::Combined => full,
        Variant::SlidingShare => sliding_share * full,
    }
}

/// Everything steps 1–8 say about one wheel at one operating point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelModel {
    /// The wheel.
    pub wheel: Wheel,
    /// The friction variant.
    pub variant: Variant,
    /// The contact patch (steps 1–2).
    pub patch: ContactPatch,
    /// The tread block (step 3).
    pub tread: TreadBlock,
    /// The slip ratio S (step 4; 0 for the follower).
    pub slip_ratio: f64,
    /// The friction levels (step 5).
    pub friction: FrictionLevels,
    /// The tread ODE (step 6).
    pub ode: TreadOde,
}

/// Why no tread ODE exists for a wheel.
#[derive(Debug, Clone, PartialEq)]
pub enum ModelFailure {
    /// The driving wheel cannot transmit the drive force
    /// (MODEL.md#step-4-brush-model-and-slip-ratio): a result.
    NoTraction {
        /// The contact patch.
        patch: ContactPatch,
        /// The tread block.
        tread: TreadBlock,
        /// The drive force against the largest force the contact transmits.
        limit: NoTraction,
    },
    /// The static model is undefined at this point (e.g. no contact patch).
    Invalid(String),
}

impl fmt::Display for ModelFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModelFailure::NoTraction { limit, .. } => write!(
                f,
                "drive force {:.1} N exceeds the adhesion limit {:.1} N",
                limit.drive_force_n, limit.max_force_n
            ),
            ModelFailure::Invalid(msg) => f.write_str(msg),
        }
    }
}

impl WheelModel {
    /// Evaluates steps 1–5 of MODEL.md#the-physics-step-by-step and assembles the step-6 ODE.
    pub fn build(p: &Params, wheel: Wheel, variant: Variant) -> Result<Self, ModelFailure> {
        Self::assemble(p, wheel, variant, |patch| tire::tread_block(p, patch))
    }

    /// [`WheelModel::build`] for a worn tyre whose tread is `height_m` high, `p.tread_height`
    /// being the new tyre's (MODEL.md#the-ageing-tread): the tread block of
    /// `tire::worn_tread_block`, everything else as the new tyre's. At `height_m` =
    /// `p.tread_height` it is [`WheelModel::build`] exactly.
    pub fn build_worn(
        p: &Params,
        height_m: f64,
        wheel: Wheel,
        variant: Variant,
    ) -> Result<Self, ModelFailure> {
        Self::assemble(p, wheel, variant, |patch| {
            tire::worn_tread_block(p, patch, height_m)
        })
    }

    fn assemble(
        p: &Params,
        wheel: Wheel,
        variant: Variant,
        tread_of: impl Fn(&ContactPatch) -> TreadBlock,
    ) -> Result<Self, ModelFailure> {
        // The wheel's own axle's toe-in, load and pressure (MODEL.md#the-car-axles-and-drivetrain).
        let p = &p.at_wheel(wheel);
        let patch = tire::contact_patch(p).map_err(|e| ModelFailure::Invalid(e.to_string()))?;
        let tread = tread_of(&patch);
        let slip_ratio = match wheel {
            Wheel::Follower => 0.0,
            Wheel::Driving => brush::slip_ratio_for_force(p, &patch, brush::drive_force_n(p))
                .map_err(|limit| ModelFailure::NoTraction {
                    patch,
                    tread,
                    limit,
                })?,
        };
        let friction = brush::friction_levels(p, &patch, slip_ratio);
        let alpha = p.toe_rad();
        let v = p.speed_mps();
        let ode = TreadOde {
            sigma0: tread.stiffness_n_per_m,
            k_s: tread.stiffness_n_per_m,
            mass_kg: tread.mass_kg,
            c_s: p.c_s,
            sigma1: p.sigma1,
            f_m: friction.f_m,
            f_s: friction.f_s,
            v_s: p.v_s,
            phi: p.phi,
            u_mps: v * alpha.sin(),
            v_sx_mps: longitudinal_sliding_mps(variant, v, alpha, slip_ratio, friction.q),
            variant,
        };
        let ok = [ode.sigma0, ode.mass_kg, ode.f_m, ode.f_s]
            .iter()
            .all(|x| x.is_finite() && *x > 0.0);
        if !ok {
            return Err(ModelFailure::Invalid(format!(
                "static model degenerate: K_s = {:.4e} N/m, m = {:.4e} kg, F_m = {:.4e} N, F_s = {:.4e} N",
                ode.sigma0, ode.mass_kg, ode.f_m, ode.f_s
            )));
        }
        Ok(WheelModel {
            wheel,
            variant,
            patch,
            tread,
            slip_ratio,
            friction,
            ode,
        })
    }

    /// Wheel rotation frequency f_rot = V / (2π r_B) \[Hz\] (MODEL.md#step-9-attractor).
    pub fn rotation_hz(p: &Params) -> f64 {
        p.speed_mps() / (2.0 * std::f64::consts::PI * p.r_b)
    }
}
