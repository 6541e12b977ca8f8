//! The figures of one wheel's run that the summary table and the verdict quote.

use super::WheelLongTerm;
use crate::classify::Class;
use crate::long_term::wheel_loop::RunEnd;
use crate::model::WheelModel;
use crate::params::Params;

/// The summary's figures of one wheel (NaN where undefined: no run, no tongue).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LongTermFigures {
    /// The deepest order at the end.
    pub dominant_order: f64,
    /// The vibration's order ν minus the dominant order \[rev\].
    pub detuning_rev: f64,
    /// Whether a leg is locked at the end.
    pub locked: bool,
    /// The tongue's half-width at the end \[Hz\].
    pub lock_halfwidth_hz: f64,
    /// The even wear rate \[mm/1000 km\].
    pub even_mm_per_1000km: f64,
    /// The dominant order's depth rate at the end \[mm/1000 km\].
    pub growth_mm_per_1000km: f64,
    /// The dominant order's linear growth rate from the seed \[1/1000 km\].
    pub growth_rate_per_1000km: f64,
    /// The depth at which the growth saturates \[mm\].
    pub saturation_depth_mm: f64,
    /// The distance to a visible polygon \[km\] (+inf where every order levels out or the tyre
    /// wore out first).
    pub distance_to_visible_km: f64,
    /// How the run ended (`None`: no run).
    pub ended: Option<RunEnd>,
    /// Where the tread lost its usable depth \[km\] (NaN where it did not).
    pub worn_out_km: f64,
    /// The tread height at the end, at least the worn-out tyre's \[mm\].
    pub tread_height_end_mm: f64,
    /// The tread's linear frequency (step 8) of the new tyre at the point's speed \[Hz\].
    pub tread_freq_start_hz: f64,
    /// The same at the end's tread height, the worn tread block of MODEL.md#the-ageing-tread
    /// \[Hz\]; +inf for a tread worn to nothing (no mass left).
    pub tread_freq_end_hz: f64,
}

impl WheelLongTerm {
    /// The figures of this wheel's run.
    pub fn figures(&self, p: &Params) -> LongTermFigures {
        let nan = f64::NAN;
        let Ok(run) = &self.run else {
            return LongTermFigures {
                dominant_order: nan,
                detuning_rev: nan,
                locked: false,
                lock_halfwidth_hz: nan,
                even_mm_per_1000km: nan,
                growth_mm_per_1000km: nan,
                growth_rate_per_1000km: nan,
                saturation_depth_mm: nan,
                distance_to_visible_km: nan,
                ended: None,
                worn_out_km: nan,
                tread_height_end_mm: nan,
                tread_freq_start_hz: nan,
                tread_freq_end_hz: nan,
            };
        };
        let n = run.dominant_order();
        let e = run.end();
        let i = n as usize - 1;
        // ν = f/f_rot: the cycle's frequency where the wheel vibrates, else the linear one (a
        // stable tread grows the orders next to its resonance; MODEL.md#growth-of-a-stable-wheel).
        let v = &self.solution.verdict;
        let nu = match v.class {
            Class::LimitCycle | Class::Bistable => v.polygon_order,
            _ => v.eig_freq_hz / WheelModel::rotation_hz(p),
        };
        let lock_halfwidth_hz = match &self.tongue {
            Ok(Some(t)) => t.halfwidth_hz,
            _ => nan,
        };
        // The last step runs past the worn-out depth (so that it reaches it): the tread's end
        // is the worn-out tyre's. A tread worn to nothing has no mass left, and its frequency
        // √(K/m) is unbounded.
        let end_height_m = e
            .tread_height_m
            .max(p.tread_height - p.usable_wear_m())
            .max(0.0);
        let freq_at = |height_m: f64| {
            let Ok(m) = &self.solution.model else {
                return nan;
            };
            if height_m <= 0.0 {
                return f64::INFINITY;
            }
            WheelModel::build_worn(p, height_m, self.wheel, m.variant)
                .map_or(nan, |m| m.ode.linear_stability().eig_freq_hz)
        };
        LongTermFigures {
            dominant_order: n as f64,
            detuning_rev: nu - n as f64,
            locked: run.locked_speed_kmh().is_some(),
            lock_halfwidth_hz,
            even_mm_per_1000km: run.even_wear_m_per_m * 1e9,
            growth_mm_per_1000km: e.depth_rate_m_per_m[i] * 1e9,
            growth_rate_per_1000km: run.linear_growth_per_m(n) * 1e6,
            saturation_depth_mm: run.saturation_depth_m() * 1e3,
            distance_to_visible_km: run.distance_to_visible_km(p.visible_depth_mm * 1e-3),
            ended: Some(run.ended()),
            worn_out_km: run.worn_out_km.unwrap_or(nan),
            tread_height_end_mm: end_height_m * 1e3,
            tread_freq_start_hz: freq_at(p.tread_height),
            tread_freq_end_hz: freq_at(end_height_m),
        }
    }
}
