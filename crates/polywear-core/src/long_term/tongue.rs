//! The lock-in tongue at the end of a long-term run, measured (MODEL.md#the-long-term-loop): at
//! the run's final profile and tread height, the speeds around the locked speed at which the
//! cycle still runs at exactly n cycles per revolution. The tongue's half-width grows with the
//! polygon's depth, far beyond the seed's ±0.5 km/h, so the estimator's seed tongue scaled
//! linearly is no measure of it at a visible depth.

use super::lock::{is_locked, rotation_number};
use super::profile::{harmonics_of, Profile};
use super::window::{integrate_window, EpsilonTable, WindowRequest};
use crate::model::{Variant, Wheel, WheelModel};
use crate::params::Params;
use crate::wear::physics::feedback::Feedback;
use crate::wear::physics::zone::WearZone;
use crate::wear::WearError;

/// Revolutions integrated at each speed before the rotation number is read (onto the cycle
/// from the run's last state). Near a tongue's edge the phase relaxes slowly (Adler's equation:
/// at a rate falling as √(1 − (δ/δ_lock)²)), and the amplitude mode about as slowly (its
/// multiplier 0.987 a period is 0.78 a revolution at order 19), so a short settling reads a
/// speed that does lock as unlocked: 20 revolutions put the default point's band at 4 µm deep
/// (R = 2 µm) at −0.20…+0.375 km/h, where 300 and 600 give −0.35…+0.375 km/h
/// (MODEL.md#growth-of-a-vibrating-wheel).
const SETTLE_REVS: usize = 300;
/// Revolutions whose rotation number decides: ρ within [`super::lock::LOCK_TOLERANCE`] of a
/// whole number over 40 revolutions is a phase drift under 0.04 of a period.
const MEASURE_REVS: usize = 40;
/// Steps outward on each side, each an eighth of one order's window V/n.
const OUTWARD_STEPS: usize = 8;
/// Halvings of the bracket between the last locked and the first unlocked speed.
const BISECTIONS: usize = 4;

/// What the measurement needs.
#[derive(Debug, Clone, Copy)]
pub struct TongueRequest<'a> {
    /// The run's parameters, the new tyre's (the speed is replaced by each probe's).
    pub params: &'a Params,
    /// Which wheel.
    pub wheel: Wheel,
    /// Friction variant.
    pub variant: Variant,
    /// The wear zone (its feedback kernel).
    pub zone: WearZone,
    /// The final depth profile \[m\].
    pub depth_m: &'a [f64],
    /// The final tread height \[m\].
    pub tread_height_m: f64,
    /// The state (z, y, v) the run ended in at the locked speed.
    pub start: [f64; 3],
    /// The locked speed \[km/h\] and the order it is locked to.
    pub locked: (f64, u32),
    /// Profile orders that act back.
    pub orders: usize,
    /// Relative tolerance of the windows.
    pub rtol: f64,
}

/// The measured tongue: half-width in forcing frequency \[Hz\] and in speed \[km/h\], and
/// whether it reached the bound of one order's window V/n on a side (then it is at least this).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Tongue {
    /// Half-width in the forcing frequency n·f_rot \[Hz\].
    pub halfwidth_hz: f64,
    /// Half-width in speed \[km/h\].
    pub halfwidth_kmh: f64,
    /// The tongue reached V/n on a side: the figures are lower bounds.
    pub at_bound: bool,
    /// RHS evaluations spent.
    pub rhs_evals: u64,
}

/// Measures the tongue of `req` (None where the centre speed itself is not locked to the order).
pub fn measure(req: &TongueRequest<'_>) -> Result<Option<Tongue>, WearError> {
    let profile = Profile {
        depth_m: req.depth_m.to_vec(),
    };
    let harmonics = harmonics_of(&profile.radius_m(), req.orders);
    let (centre_kmh, order) = req.locked;
    let mut rhs_evals = 0u64;
    let mut locked_at = |speed_kmh: f64| -> Result<bool, WearError> {
        let new = Params {
            speed_kmh,
            ..*req.params
        };
        let p = Params {
            tread_height: req.tread_height_m,
            ..new
        };
        let fail = |reason: String| WearError::Loop {
            speed_kmh,
            distance_km: f64::NAN,
            reason: format!("measuring the tongue: {reason}"),
        };
        // The worn tread block, as the loop built it (MODEL.md#the-ageing-tread).
        let model = WheelModel::build_worn(&new, req.tread_height_m, req.wheel, req.variant)
            .map_err(|e| fail(e.to_string()))?;
        let fb = Feedback::new(&p, &model, req.zone);
        let table = EpsilonTable::new(&fb, &harmonics, 8 * req.orders);
        let rotation_hz = WheelModel::rotation_hz(&p);
        let window = integrate_window(&WindowRequest {
            ode: &model.ode,
            epsilon: &table,
            rotation_hz,
            start: req.start,
            skip_revs: SETTLE_REVS,
            revs: MEASURE_REVS,
            samples_per_rev: 16,
            rtol: req.rtol,
            period_s: 1.0 / model.ode.linear_stability().eig_freq_hz,
            max_steps: 50_000_000,
        })
        .map_err(|e| fail(e.to_string()))?;
        rhs_evals += window.rhs_evals as u64;
        let rho = rotation_number(&window.crossings_s, 1.0 / rotation_hz);
        Ok(is_locked(rho) && rho.round() as u32 == order)
    };
    if !locked_at(centre_kmh)? {
        return Ok(None);
    }
    let window_kmh = centre_kmh / order as f64;
    let step_kmh = window_kmh / OUTWARD_STEPS as f64;
    let mut edges = [0.0; 2];
    let mut at_bound = false;
    for (side, sign) in [(0, -1.0), (1, 1.0)] {
        // Outward until unlocked (or the bound), then bisect the last step.
        let (mut inside, mut outside) = (0.0, f64::NAN);
        for k in 1..=OUTWARD_STEPS {
            let d = k as f64 * step_kmh;
            if locked_at(centre_kmh + sign * d)? {
                inside = d;
            } else {
                outside = d;
                break;
            }
        }
        if outside.is_nan() {
            at_bound = true;
        } else {
            for _ in 0..BISECTIONS {
                let mid = 0.5 * (inside + outside);
                if locked_at(centre_kmh + sign * mid)? {
                    inside = mid;
                } else {
                    outside = mid;
                }
            }
        }
        edges[side] = inside;
    }
    let halfwidth_kmh = 0.5 * (edges[0] + edges[1]);
    let p = Params {
        speed_kmh: centre_kmh,
        ..*req.params
    };
    let hz_per_kmh = order as f64 * WheelModel::rotation_hz(&p) / centre_kmh;
    Ok(Some(Tongue {
        halfwidth_hz: halfwidth_kmh * hz_per_kmh,
        halfwidth_kmh,
        at_bound,
        rhs_evals,
    }))
}
