//! Brush tire model with parabolic pressure (MODEL.md#step-4-brush-model-and-slip-ratio and
//! #step-5-friction-levels; paper Eqs. 1–12 and 19):
//! the sliding share of the contact, the longitudinal force, the driving wheel's slip ratio and
//! the friction levels that feed the LuGre law.

use super::tire::ContactPatch;
use crate::numeric::brent;
use crate::params::Params;

/// Combined slip magnitude r(S) for slip ratio S and toe angle (step 4).
pub(crate) fn combined_slip(slip_ratio: f64, tan_alpha: f64) -> f64 {
    ((1.0 + slip_ratio) * tan_alpha).hypot(slip_ratio)
}

/// Sliding share q of the contact length (step 4), 1 when the whole patch slides.
pub fn sliding_share(p: &Params, patch: &ContactPatch, slip_ratio: f64) -> f64 {
    let r = combined_slip(slip_ratio, p.toe_rad().tan());
    let a = patch.length_m;
    (p.c_brush * patch.width_m * a * a * r / (6.0 * p.mu_m * p.load_n)).min(1.0)
}

/// Longitudinal force F_X(S) transmitted by the contact (step 4), increasing in S.
pub fn longitudinal_force_n(p: &Params, patch: &ContactPatch, slip_ratio: f64) -> f64 {
    if slip_ratio == 0.0 {
        return 0.0;
    }
    let r = combined_slip(slip_ratio, p.toe_rad().tan());
    let q = sliding_share(p, patch, slip_ratio);
    let a = patch.length_m;
    0.5 * p.c_brush * patch.width_m * slip_ratio * a * a * (1.0 - q).powi(2)
        + p.mu_s * p.load_n * q * q * (3.0 - 2.0 * q) * slip_ratio / r
}

/// Drive force one driven wheel must transmit: rolling resistance of all wheels plus air drag,
/// shared by the driven wheels (step 4; 21.15 converts V in km/h). The wheels' load is the mean
/// over both axles (MODEL.md#the-car-axles-and-drivetrain), the shared load when neither axle
/// has its own.
pub fn drive_force_n(p: &Params) -> f64 {
    let v = p.speed_kmh;
    (p.n_wheels * (p.f0 + p.f1 * v) * p.mean_load_n() + p.c_d * p.area * v * v / 21.15) / p.n_driven
}

/// The largest slip ratio searched; beyond it the wheel is spinning, not rolling.
pub(crate) const MAX_SLIP_RATIO: f64 = 1.0e3;

/// Why a driving wheel has no slip ratio.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoTraction {
    /// The drive force the wheel must transmit \[N\].
    pub drive_force_n: f64,
    /// The largest force the contact transmits \[N\].
    pub max_force_n: f64,
}

/// Slip ratio S ≥ 0 at which the contact transmits `force_n` (step 4), solved with Brent's
/// method on the monotone F_X(S). A force beyond the adhesion limit is a result, not an error.
pub(crate) fn slip_ratio_for_force(
    p: &Params,
    patch: &ContactPatch,
    force_n: f64,
) -> Result<f64, NoTraction> {
    if force_n <= 0.0 {
        return Ok(0.0);
    }
    let residual = |s: f64| longitudinal_force_n(p, patch, s) - force_n;
    // Bracket by doubling so that ordinary points are solved on a tight interval.
    let mut hi = 1.0e-3;
    while residual(hi) < 0.0 {
        if hi >= MAX_SLIP_RATIO {
            return Err(NoTraction {
                drive_force_n: force_n,
                max_force_n: longitudinal_force_n(p, patch, MAX_SLIP_RATIO),
            });
        }
        hi = (hi * 4.0).min(MAX_SLIP_RATIO);
    }
    Ok(brent(residual, 0.0, hi, 1.0e-300, 200).unwrap_or(hi))
}

/// Static and sliding friction levels F_m, F_s of the LuGre law (step 5, Eq. 19).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionLevels {
    /// Sliding share q of the contact length.
    pub q: f64,
    /// Maximum static friction level F_m \[N\].
    pub f_m: f64,
    /// Sliding friction level F_s \[N\].
    pub f_s: f64,
}

/// The friction levels of Eq. 19 at slip ratio `slip_ratio`.
pub(crate) fn friction_levels(p: &Params, patch: &ContactPatch, slip_ratio: f64) -> FrictionLevels {
    let tan_a = p.toe_rad().tan();
    let q = sliding_share(p, patch, slip_ratio);
    let lateral_share =
        q * (3.0 - 2.0 * q) * (1.0 + slip_ratio) * tan_a / combined_slip(slip_ratio, tan_a);
    FrictionLevels {
        q,
        f_m: p.mu_m * p.load_n * lateral_share,
        f_s: p.mu_s * p.load_n * lateral_share,
    }
}

/// Lateral force F_Y(S) of the contact at slip ratio S: the brush model's lateral counterpart of
/// F_X (step 4 with S replaced by (1+S) tan α in the adhesion term; the sliding term is the
/// paper's Eq. 17). With F_X it traces the adhesion ellipse of the paper's Fig. 4.
pub fn lateral_force_n(p: &Params, patch: &ContactPatch, slip_ratio: f64) -> f64 {
    let tan_a = p.toe_rad().tan();
    let r = combined_slip(slip_ratio, tan_a);
    let q = sliding_share(p, patch, slip_ratio);
    let a = patch.length_m;
    let sy = (1.0 + slip_ratio) * tan_a;
    0.5 * p.c_brush * patch.width_m * sy * a * a * (1.0 - q).powi(2)
        + p.mu_s * p.load_n * q * q * (3.0 - 2.0 * q) * sy / r
}
