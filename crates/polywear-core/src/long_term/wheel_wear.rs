//! What the long-term loop found for one wheel (MODEL.md#the-long-term-loop): its history of
//! depths, growth and lock per step, a few profiles, and the figures the summary reads from
//! them (the dominant order, the distance to a visible polygon, the growth in the linear
//! regime).

use super::profile::Profile;
use crate::model::Wheel;
use crate::numeric::Complex64;
use crate::wear::response::legs::Leg;

/// The state of the run after one accepted step.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct HistoryPoint {
    /// Distance run \[km\].
    pub distance_km: f64,
    /// Tread height h \[m\].
    pub tread_height_m: f64,
    /// D_n = 2|R_n| of orders 1 ..= [`super::wheel_loop::FEEDBACK_ORDERS`] \[m\].
    pub depths_m: Vec<f64>,
    /// dD_n/ds of the same orders over the step that led here \[m/m\] (0 at the start).
    pub depth_rate_m_per_m: Vec<f64>,
    /// β_n = d ln|R_n|/ds over that step \[1/m\] (0 at the start).
    pub growth_per_m: Vec<f64>,
    /// The rotation number ρ of each leg's window in that step (NaN: no cycle).
    pub rho: Vec<f64>,
    /// Whether each leg's window was locked (ρ a whole number to 1e-3).
    pub locked: Vec<bool>,
}

/// The result of the loop for one wheel.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WheelWear {
    /// The wheel.
    pub wheel: Wheel,
    /// The usage it ran.
    pub legs: Vec<Leg>,
    /// The start and every accepted step.
    pub history: Vec<HistoryPoint>,
    /// The depth profile d(θ) \[m\] at a few distances \[km\], the start and the end included.
    pub profiles: Vec<(f64, Vec<f64>)>,
    /// The first order to reach d_visible and the distance \[km\] at which it did (interpolated
    /// exponentially within its step).
    pub visible: Option<(u32, f64)>,
    /// The distance \[km\] at which the tread lost its usable depth, `tread_depth_new_mm` −
    /// `tread_depth_worn_out_mm` (interpolated linearly within its step), where it did: the run
    /// ends there, the tyre worn out before a polygon became visible.
    pub worn_out_km: Option<f64>,
    /// Straight-running friction energy laid onto the tread over the run \[J\].
    pub energy_j: f64,
    /// The volume that energy wore \[m³\] (γ times the energy, to rounding).
    pub straight_volume_m3: f64,
    /// The tread band b·2π r_B \[m²\] of the new tyre (volume / band / distance = even wear).
    pub band_area_m2: f64,
    /// The run's mean straight-running even wear \[m/m\].
    pub even_wear_m_per_m: f64,
    /// The seed's run-out per order R⁰ \[m\].
    pub seed_m: f64,
    /// Right-hand-side evaluations spent.
    pub rhs_evals: u64,
    /// Accepted steps.
    pub steps: usize,
    /// Steps redone at half length.
    pub redone: usize,
    /// The ODE state (z, y, v) each leg's last window ended in (`None`: never driven).
    pub end_states: Vec<Option<[f64; 3]>>,
}

/// The depth, in seed depths 2R⁰, below which an order still growing at the end is not
/// extrapolated to a visible polygon ([`WheelWear::distance_to_visible_km`]).
const EXTRAPOLATION_FLOOR_SEEDS: f64 = 1e-3;

/// How a run ended (MODEL.md#the-long-term-loop).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunEnd {
    /// A polygon of `order` sides became visible after `km`.
    Visible {
        /// Its sides.
        order: u32,
        /// Where \[km\].
        km: f64,
    },
    /// The tread lost its usable depth after `km`, before any polygon became visible.
    WornOut {
        /// Where \[km\].
        km: f64,
    },
    /// The distance asked was run with no visible polygon and tread left.
    Distance,
}

impl RunEnd {
    /// The summary's word for it: `visible`, `worn_out`, `distance`.
    pub fn as_str(self) -> &'static str {
        match self {
            RunEnd::Visible { .. } => "visible",
            RunEnd::WornOut { .. } => "worn_out",
            RunEnd::Distance => "distance",
        }
    }
}

impl WheelWear {
    /// How the run ended: a visible polygon first, else the tyre worn out, else the distance.
    pub fn ended(&self) -> RunEnd {
        match (self.visible, self.worn_out_km) {
            (Some((order, km)), _) => RunEnd::Visible { order, km },
            (None, Some(km)) => RunEnd::WornOut { km },
            (None, None) => RunEnd::Distance,
        }
    }

    /// The last history point.
    pub fn end(&self) -> &HistoryPoint {
        self.history.last().expect("the start is always there")
    }

    /// The order with the deepest polygon at the end (1-based), among the orders the new tyre's
    /// run-out seeds: an order without a seed starts at rounding noise (1e-17 mm), and where
    /// every order has levelled out to the noise of a depth summed over 60,000 km (1e-11 mm of
    /// 12 mm) such an order could otherwise come out deepest, with a "growth from the seed"
    /// that is noise over noise.
    pub fn dominant_order(&self) -> u32 {
        let d = &self.end().depths_m;
        let seeded = |i: &usize| self.history[0].depths_m[*i] >= self.seed_m;
        (0..d.len())
            .filter(seeded)
            .max_by(|a, b| d[*a].total_cmp(&d[*b]))
            .or_else(|| (0..d.len()).max_by(|a, b| d[*a].total_cmp(&d[*b])))
            .map(|i| i as u32 + 1)
            .unwrap_or(1)
    }

    /// The distance run \[km\].
    pub fn distance_km(&self) -> f64 {
        self.end().distance_km
    }

    /// Whether every order is at most its seed depth 2R⁰ at the end and none grows: no polygon.
    pub fn levels_out(&self) -> bool {
        let e = self.end();
        let seed = 2.0 * self.seed_m;
        e.depths_m.iter().all(|d| *d <= seed * (1.0 + 1e-9))
            && e.growth_per_m.iter().all(|b| *b <= 0.0)
    }

    /// The distance to a visible polygon \[km\]: where one became visible; else +inf where the
    /// tyre wore out first; else, if the dominant order still grows, the end of the run plus its
    /// exponential extrapolation; else +inf.
    pub fn distance_to_visible_km(&self, visible_m: f64) -> f64 {
        if let Some((_, km)) = self.visible {
            return km;
        }
        if self.worn_out_km.is_some() {
            // The tyre is worn out first: no polygon on this tyre.
            return f64::INFINITY;
        }
        let n = self.dominant_order() as usize - 1;
        let e = self.end();
        let (d, beta) = (e.depths_m[n], e.growth_per_m[n]);
        // An order a thousandth of its seed deep or less has levelled out to where the depth's
        // rounding (1e-14 m of 12 mm worn) makes its growth noise: nothing to extrapolate.
        if beta > 0.0 && d > EXTRAPOLATION_FLOOR_SEEDS * 2.0 * self.seed_m {
            e.distance_km + (visible_m / d).ln() / beta / 1e3
        } else {
            f64::INFINITY
        }
    }

    /// The tread's life \[km\]: where the run wore out its `usable_m` of tread, else that depth
    /// over the run's mean rate of wear (the tread height's fall over the distance run); +inf
    /// where the height did not fall (a loop that holds it, or no distance).
    pub fn tread_life_km(&self, usable_m: f64) -> f64 {
        if let Some(km) = self.worn_out_km {
            return km;
        }
        let (start, e) = (&self.history[0], self.end());
        let worn_m = start.tread_height_m - e.tread_height_m;
        if worn_m > 0.0 && e.distance_km > 0.0 {
            usable_m / worn_m * e.distance_km
        } else {
            f64::INFINITY
        }
    }

    /// The depth \[m\] at which the dominant order stopped growing: its depth at the end where
    /// its growth fell below a tenth of its largest, NaN where it still grows or never grew.
    pub fn saturation_depth_m(&self) -> f64 {
        let n = self.dominant_order() as usize - 1;
        let peak = self
            .history
            .iter()
            .fold(0.0f64, |m, h| m.max(h.growth_per_m[n]));
        let e = self.end();
        if peak > 0.0 && e.growth_per_m[n] < 0.1 * peak && e.depths_m[n] > 2.0 * self.seed_m {
            e.depths_m[n]
        } else {
            f64::NAN
        }
    }

    /// The growth rate of `order` in its linear regime \[1/m\]: ln(D(s₁)/D(0))/s₁ from the start
    /// to the first history point where the order is [`LINEAR_REGIME_SEEDS`] seeds deep (the end
    /// if it never is), the figure the estimator's β̄ predicts (MODEL.md#the-per-sample-estimator);
    /// NaN where the order has no seed.
    pub fn linear_growth_per_m(&self, order: u32) -> f64 {
        let n = order as usize - 1;
        let start = &self.history[0];
        let deep = LINEAR_REGIME_SEEDS * 2.0 * self.seed_m;
        let stop = self
            .history
            .iter()
            .skip(1)
            .find(|h| h.depths_m[n] >= deep)
            .unwrap_or_else(|| self.end());
        let ds_m = (stop.distance_km - start.distance_km) * 1e3;
        if start.depths_m[n] <= 0.0 || ds_m <= 0.0 {
            return f64::NAN;
        }
        (stop.depths_m[n] / start.depths_m[n]).ln() / ds_m
    }

    /// The leg locked at the end with the largest share: its index, speed \[km/h\] and the
    /// order it is locked to.
    pub fn locked_leg(&self) -> Option<(usize, f64, u32)> {
        let e = self.end();
        (0..self.legs.len())
            .filter(|i| e.locked[*i])
            .max_by(|a, b| self.legs[*a].share.total_cmp(&self.legs[*b].share))
            .map(|i| (i, self.legs[i].speed_kmh, e.rho[i].round() as u32))
    }

    /// The leg locked at the end with the largest share, as its speed \[km/h\].
    pub fn locked_speed_kmh(&self) -> Option<f64> {
        let e = self.end();
        self.legs
            .iter()
            .zip(&e.locked)
            .filter(|(_, l)| **l)
            .max_by(|a, b| a.0.share.total_cmp(&b.0.share))
            .map(|(leg, _)| leg.speed_kmh)
    }
}

/// How many seeds deep an order may grow before its growth is no longer linear
/// ([`WheelWear::linear_growth_per_m`]).
pub const LINEAR_REGIME_SEEDS: f64 = 5.0;

/// The growth rate of harmonic `n` from the history between two distances \[1/m\]:
/// ln(D(s₂)/D(s₁))/(s₂ − s₁) at the nearest history points.
pub fn measured_growth_per_m(wear: &WheelWear, order: u32, from_km: f64, to_km: f64) -> f64 {
    let near = |km: f64| {
        wear.history
            .iter()
            .min_by(|a, b| {
                (a.distance_km - km)
                    .abs()
                    .total_cmp(&(b.distance_km - km).abs())
            })
            .expect("the start")
    };
    let (a, b) = (near(from_km), near(to_km));
    let n = order as usize - 1;
    (b.depths_m[n] / a.depths_m[n]).ln() / ((b.distance_km - a.distance_km) * 1e3)
}

/// The complex harmonic amplitudes R_1..=R_`orders` of a depth profile (r = −(d − d̄)).
pub fn profile_harmonics(depth_m: &[f64], orders: usize) -> Vec<Complex64> {
    Profile {
        depth_m: depth_m.to_vec(),
    }
    .harmonics(orders)
}

/// At most `count` of `profiles`: the first, the last and those nearest to evenly spaced
/// distances between.
pub(super) fn pick_profiles(profiles: Vec<(f64, Vec<f64>)>, count: usize) -> Vec<(f64, Vec<f64>)> {
    if profiles.len() <= count {
        return profiles;
    }
    let last = profiles.last().map(|p| p.0).unwrap_or(0.0);
    let mut picked: Vec<usize> = (0..count)
        .map(|k| {
            let target = last * k as f64 / (count - 1) as f64;
            (0..profiles.len())
                .min_by(|a, b| {
                    (profiles[*a].0 - target)
                        .abs()
                        .total_cmp(&(profiles[*b].0 - target).abs())
                })
                .expect("not empty")
        })
        .collect();
    picked.dedup();
    picked.into_iter().map(|i| profiles[i].clone()).collect()
}
