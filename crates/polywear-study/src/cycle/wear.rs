//! The distance to a visible polygon for a car that drives a cycle all its life
//! (MODEL.md#along-a-drive-cycle), on the level the wear stage asks for.
//!
//! As the new tire: each step's closed-loop growth of every order 1..=[`CYCLE_ORDERS_MAX`], at
//! the step's own speed (the cycle's speeds are its speed spread, so no further spread is laid
//! over a step), averaged over the distance the cycle covers at each step. Repeating the cycle
//! multiplies |R_n| by exp(Σ β_n(k) Δs_k) per lap, so the order whose distance-weighted mean
//! β̄_n is largest is the one that becomes visible, after ln(d_visible / 2R⁰) / β̄_n.
//!
//! Over the tread's life (the default): the steps share one tread, whose depth falls at the
//! cycle's mean whole even wear; at each worn depth every step reads its closed loop at the
//! order its drifting tread frequency puts there ([`LifeProfile`]). The steps' profiles,
//! summed by the distance covered at each ([`CycleLife`]), give ln D_n along the depth, and the
//! first order to reach the visible depth before the tire is worn out is the polygon.
//!
//! With each speed's print saturated (`tread_life_saturated`,
//! MODEL.md#the-forced-response-saturates): the steps' profiles are summed by speed bin of
//! [`SATURATED_SPEED_BIN_KMH`], and each bin prints at most what sliding can modulate, on its
//! own ([`polywear_core::wear::estimator::answer_saturated_per_step`]).

use super::{DriveCycle, StepWheel};
use polywear_core::classify::budget::Meter;
use polywear_core::classify::ClassifierOptions;
use polywear_core::evaluate::{WearStage, WheelSolution};
use polywear_core::params::Params;
use polywear_core::wear::estimator::{distance_to_visible_km, print_log_ratio, tread_life_km};
use polywear_core::wear::estimator::{SaturatedSteps, SLIDING_MODULATION_MAX};
use polywear_core::wear::law::MM_PER_1000KM_PER_M_PER_M;
use polywear_core::wear::{
    EstimateLevel, FittedConstants, LifeProfile, WheelGrowth, LIFE_PROFILE_INTERVALS,
};

/// The highest order followed along a cycle: the seed's band (MODEL.md#step-12-feedback). A step
/// slower than about 25 km/h puts ν above it; its orders near ν are not followed (their
/// distance at such speeds is small).
pub const CYCLE_ORDERS_MAX: u32 = 64;

/// The width of the speed bins whose steps saturate together on the `tread_life_saturated`
/// level \[km/h\]: a bin's steps share one bound (the min of their sum, weaker than each
/// step's own). A step's resonance is sharp in speed, so the bins must be fine: against every
/// step on its own on HWFET at φ_s = 1 (`examples/saturation_probe.rs`), bins of 1 km/h put the
/// polygon 5–7% early, 0.5 km/h 2–3%, 0.25 km/h under 0.5%, and 0.1 km/h (a cycle's own
/// resolution: HWFET's 766 steps hold 250 speeds) not at all. A bin holds one profile a wheel
/// (66 KB).
pub const SATURATED_SPEED_BIN_KMH: f64 = 0.1;

/// What a step's wear gives the calibration band: β_n at φ_s = 1 for orders
/// 1..=[`CYCLE_ORDERS_MAX`], and λ_other per unit (1 − φ_s) as `(a, b)`, a + b k_d. With no
/// speed spread (a cycle's speeds are its spread) β_n(φ_s, k_d) = φ_s β_n(1) − (1 − φ_s)(a + b
/// k_d) exactly: the loop, the locked print and the slip power all scale with φ_s, and λ_other
/// is the same for every order (MODEL.md#the-calibration-band).
#[derive(Debug, Clone, PartialEq)]
pub struct BandGrowth {
    /// β_n(φ_s = 1) \[1/1000 km\], orders 1..=[`CYCLE_ORDERS_MAX`].
    pub full_share_per_1000km: Vec<f64>,
    /// λ_other per unit (1 − φ_s) \[1/1000 km\]: (at k_d = 0, per unit k_d).
    pub other_levelling_per_1000km: (f64, f64),
}

impl BandGrowth {
    /// β_n \[1/1000 km\] of order `k + 1` under `c` (σ_V does not enter: no spread).
    pub fn growth_per_1000km(&self, k: usize, c: &FittedConstants) -> f64 {
        let (a, b) = self.other_levelling_per_1000km;
        let phi = c.wear_share_straight;
        phi * self.full_share_per_1000km[k] - (1.0 - phi) * (a + b * c.wear_rate_driven_factor)
    }
}

/// What one wheel's wear gives at one step: β_n of orders 1..=[`CYCLE_ORDERS_MAX`] \[1/1000
/// km\] as the new tire, its terms for the calibration band and, over the tread's life, its
/// profile in the worn depth. Empty and None where the wheel has no figures (no model, failed,
/// standstill).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StepGrowth {
    /// β_n \[1/1000 km\], orders 1..=[`CYCLE_ORDERS_MAX`], with no speed spread.
    pub orders_per_1000km: Vec<f64>,
    /// The same for the calibration band.
    pub band: Option<BandGrowth>,
    /// The profile over the tread's life (only when the wear stage answers on that level).
    pub life: Option<LifeProfile>,
}

/// One wheel's [`StepGrowth`] at one step, with no speed spread.
pub fn step_growth(
    p: &Params,
    wheel: &WheelSolution,
    stage: &WearStage,
    options: &ClassifierOptions,
) -> StepGrowth {
    let Ok(growth) = WheelGrowth::new(&stage.inputs(p, wheel), &Meter::new(options.budget)) else {
        return StepGrowth::default();
    };
    let orders = 1..=CYCLE_ORDERS_MAX;
    let at = |share: f64| -> Vec<f64> {
        orders
            .clone()
            .map(|n| growth.order_with(n, share, 0.0).growth_rate_per_1000km)
            .collect()
    };
    let a = growth.other_levelling_per_1000km(0.0);
    let band = BandGrowth {
        full_share_per_1000km: at(1.0),
        other_levelling_per_1000km: (a, growth.other_levelling_per_1000km(1.0) - a),
    };
    let life = (stage.settings.estimate != EstimateLevel::NewTire)
        .then(|| growth.life_profile(CYCLE_ORDERS_MAX, LIFE_PROFILE_INTERVALS));
    // Past the wheel's wall-clock limit the step has no figures, as a failed step (its
    // distance counted as without figures), never a profile laid out in part.
    if growth.out_of_time().is_some() {
        return StepGrowth::default();
    }
    StepGrowth {
        orders_per_1000km: at(p.wear_share_straight),
        band: Some(band),
        life,
    }
}

/// One wheel's profiles over the tread's life summed over a cycle's steps, each by the
/// distance covered at it \[km\], and the distance at steps without figures.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CycleLife {
    /// Σ km_k · profile_k over the steps with figures (None before the first).
    pub profile_km: Option<LifeProfile>,
    /// With each speed's print saturated ([`CycleLife::on`] that level; None otherwise): the same
    /// sums by speed bin of [`SATURATED_SPEED_BIN_KMH`], rising: (bin, Σ km_k · profile_k,
    /// Σ km_k \[km\]).
    pub by_speed: Option<Vec<(i64, LifeProfile, f64)>>,
    /// The distance at those steps \[km\].
    pub known_km: f64,
    /// The distance at moving steps without figures (failed, no traction) \[km\].
    pub unknown_km: f64,
}

impl CycleLife {
    /// An empty sum whose steps saturate by speed bin (the `tread_life_saturated` level), or
    /// not.
    pub fn on(level: EstimateLevel) -> Self {
        CycleLife {
            by_speed: (level == EstimateLevel::TreadLifeSaturated).then(Vec::new),
            ..CycleLife::default()
        }
    }

    /// Adds a step of `km` at `speed_kmh` whose profile is `profile` (None: no figures).
    pub fn add_step(&mut self, profile: Option<&LifeProfile>, km: f64, speed_kmh: f64) {
        if km <= 0.0 {
            return;
        }
        let Some(profile) = profile else {
            self.unknown_km += km;
            return;
        };
        self.known_km += km;
        self.sum_like(profile).add(profile, km);
        if let Some(bins) = &mut self.by_speed {
            let bin = (speed_kmh / SATURATED_SPEED_BIN_KMH).round() as i64;
            add_to_bin(bins, bin, profile, km, km);
        }
    }

    /// The sum, started empty on `like`'s grid before the first profile.
    fn sum_like(&mut self, like: &LifeProfile) -> &mut LifeProfile {
        self.profile_km
            .get_or_insert_with(|| LifeProfile::zero(like.max_order, like.intervals, like.usable_m))
    }

    /// Adds the steps of `other` (the next block of the same structure).
    pub fn merge(&mut self, other: &CycleLife) {
        if let Some(profile) = &other.profile_km {
            self.sum_like(profile).add(profile, 1.0);
        }
        if let (Some(bins), Some(theirs)) = (&mut self.by_speed, &other.by_speed) {
            for (bin, sum, km) in theirs {
                add_to_bin(bins, *bin, sum, 1.0, *km);
            }
        }
        self.known_km += other.known_km;
        self.unknown_km += other.unknown_km;
    }

    /// The cycle's wear over the tread's life under `c` (the structure `base`'s seed and
    /// visible depth): the steps' distance-weighted mean profile's answer. Its growth rate is
    /// the visible order's mean from the seed to the visible depth (NaN where none is visible
    /// before the tire is worn out).
    pub fn wear(&self, base: &Params, c: &FittedConstants) -> CycleWear {
        self.wear_with(base, std::slice::from_ref(c))
            .pop()
            .expect("one set, one answer")
    }

    /// [`CycleLife::wear`] under each of `sets` (the structure's own constants, the
    /// calibration band's): the mean profile and the speed bins' means are formed once for all
    /// of them, and each set reads its answer off them.
    pub fn wear_with(&self, base: &Params, sets: &[FittedConstants]) -> Vec<CycleWear> {
        let unknown_distance_share = if self.known_km + self.unknown_km > 0.0 {
            self.unknown_km / (self.known_km + self.unknown_km)
        } else {
            0.0
        };
        let Some(sum) = self.profile_km.as_ref().filter(|_| self.known_km > 0.0) else {
            let unknown = CycleWear {
                unknown_distance_share,
                ..CycleWear::UNKNOWN
            };
            return vec![unknown; sets.len()];
        };
        let mut mean = sum.clone();
        mean.scale(1.0 / self.known_km);
        let bins = self
            .by_speed
            .as_ref()
            .filter(|b| !b.is_empty())
            .map(|bins| {
                SaturatedSteps::new(
                    bins.iter()
                        .map(|(_, sum, km)| {
                            let mut mean = sum.clone();
                            mean.scale(1.0 / km);
                            (*km, mean)
                        })
                        .collect(),
                )
            });
        let target = print_log_ratio(base);
        sets.iter()
            .map(|c| {
                let life = match &bins {
                    Some(bins) => {
                        let mut bounded = bins.answer(c, base, SLIDING_MODULATION_MAX);
                        // The bins share the cycle's even wear: its tread's life is the whole
                        // sum's (what `mean.answer` gives, without walking its orders).
                        bounded.answer.tread_life_km = tread_life_km(
                            base,
                            mean.tread_wear_m_per_m(c) * MM_PER_1000KM_PER_M_PER_M,
                        );
                        bounded
                    }
                    None => mean.answer(c, base),
                };
                let distance = life.answer.distance_to_visible_km;
                CycleWear {
                    dominant_order: life.answer.polygon_order_wear,
                    growth_rate_per_1000km: if distance.is_finite() && distance > 0.0 {
                        target / distance * 1000.0
                    } else {
                        f64::NAN
                    },
                    distance_to_visible_km: distance,
                    unknown_distance_share,
                    tread_life_km: life.answer.tread_life_km,
                    peak_share_of_visible: life.peak_share_of_visible,
                }
            })
            .collect()
    }
}

/// The memory \[bytes\] one wheel's speed bins take on the `tread_life_saturated` level over
/// `cycle`: one profile of orders 1..=[`CYCLE_ORDERS_MAX`] on [`LIFE_PROFILE_INTERVALS`] for
/// each bin of [`SATURATED_SPEED_BIN_KMH`] its moving steps fill.
pub fn saturated_bins_bytes(cycle: &DriveCycle) -> u64 {
    let mut bins: Vec<i64> = (0..cycle.len())
        .filter(|&i| !cycle.standstill(i))
        .map(|i| (cycle.speed_kmh[i] / SATURATED_SPEED_BIN_KMH).round() as i64)
        .collect();
    bins.sort_unstable();
    bins.dedup();
    let profile = CYCLE_ORDERS_MAX as u64 * (LIFE_PROFILE_INTERVALS as u64 + 1) * 8;
    bins.len() as u64 * profile
}

/// Adds `weight` times `profile` and `km` to bin `bin` of `bins` (rising), opening it where
/// there is none.
fn add_to_bin(
    bins: &mut Vec<(i64, LifeProfile, f64)>,
    bin: i64,
    profile: &LifeProfile,
    weight: f64,
    km: f64,
) {
    let at = match bins.binary_search_by_key(&bin, |b| b.0) {
        Ok(at) => at,
        Err(at) => {
            let empty = LifeProfile::zero(profile.max_order, profile.intervals, profile.usable_m);
            bins.insert(at, (bin, empty, 0.0));
            at
        }
    };
    bins[at].1.add(profile, weight);
    bins[at].2 += km;
}

/// One wheel's polygon over a lifetime of the cycle (one tire structure).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CycleWear {
    /// The order with the largest distance-weighted growth (NaN where no step has figures).
    pub dominant_order: f64,
    /// Its β̄ \[1/1000 km\].
    pub growth_rate_per_1000km: f64,
    /// Distance to a polygon `visible_depth_mm` deep \[km\]; +inf when every order levels out.
    pub distance_to_visible_km: f64,
    /// Share of the cycle's distance at steps without figures (failed, no traction): left out
    /// of the mean, and said.
    pub unknown_distance_share: f64,
    /// Over the tread's life: the distance at which the tire is worn out \[km\] (NaN as the
    /// new tire).
    pub tread_life_km: f64,
    /// Over the tread's life: the deepest order's largest depth as a share of the visible
    /// depth, 1 where visible (NaN as the new tire).
    pub peak_share_of_visible: f64,
}

impl CycleWear {
    /// No figures at any step.
    pub const UNKNOWN: CycleWear = CycleWear {
        dominant_order: f64::NAN,
        growth_rate_per_1000km: f64::NAN,
        distance_to_visible_km: f64::NAN,
        unknown_distance_share: 0.0,
        tread_life_km: f64::NAN,
        peak_share_of_visible: f64::NAN,
    };
}

/// The cycle's wear of wheel `w` (0 follower, 1 driving) on the structure `base`.
pub fn cycle_wear(
    cycle: &DriveCycle,
    steps: &[[StepWheel; 2]],
    w: usize,
    base: &Params,
) -> CycleWear {
    let terms = mean_terms(
        cycle,
        steps,
        w,
        CYCLE_ORDERS_MAX as usize,
        &|s: &StepWheel| {
            (!s.order_growth_per_1000km.is_empty()).then(|| s.order_growth_per_1000km.clone())
        },
    );
    terms.wear(base, terms.mean.clone())
}

/// [`cycle_wear`] under each of the fitted constants `sets` instead of the structure's own (the
/// calibration band), from each step's [`BandGrowth`]. β_n is linear in its two terms, so their
/// distance-weighted means are taken once and each set costs one pass over the orders.
pub fn cycle_wear_band(
    cycle: &DriveCycle,
    steps: &[[StepWheel; 2]],
    w: usize,
    base: &Params,
    sets: &[FittedConstants],
) -> Vec<CycleWear> {
    // The means of β_n(φ_s = 1), then of a and b, as one "growth" vector of the steps.
    let n = CYCLE_ORDERS_MAX as usize;
    let terms = mean_terms(cycle, steps, w, n + 2, &|s: &StepWheel| {
        s.band_growth.as_ref().map(|g| {
            let (a, b) = g.other_levelling_per_1000km;
            g.full_share_per_1000km
                .iter()
                .copied()
                .chain([a, b])
                .collect()
        })
    });
    sets.iter()
        .map(|c| {
            let growth = terms.mean.as_ref().map(|m| {
                let band = BandGrowth {
                    full_share_per_1000km: m[..n].to_vec(),
                    other_levelling_per_1000km: (m[n], m[n + 1]),
                };
                (0..n).map(|k| band.growth_per_1000km(k, c)).collect()
            });
            terms.wear(base, growth)
        })
        .collect()
}

/// The distance-weighted means of a per-step vector over a wheel's steps with figures, and the
/// share of the distance without.
struct MeanTerms {
    mean: Option<Vec<f64>>,
    unknown_distance_share: f64,
}

impl MeanTerms {
    /// The wear of the mean growth `growth` of orders 1.. (None: no step with figures).
    fn wear(&self, base: &Params, growth: Option<Vec<f64>>) -> CycleWear {
        let best = growth.and_then(|g| {
            g.iter()
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(b.1))
                .map(|(k, b)| (k as f64 + 1.0, *b))
        });
        let unknown_distance_share = self.unknown_distance_share;
        match best {
            Some((order, beta)) => CycleWear {
                dominant_order: order,
                growth_rate_per_1000km: beta,
                distance_to_visible_km: distance_to_visible_km(base, beta),
                unknown_distance_share,
                ..CycleWear::UNKNOWN
            },
            None => CycleWear {
                unknown_distance_share,
                ..CycleWear::UNKNOWN
            },
        }
    }
}

/// The distance-weighted mean of `value` (a vector of `len`, or None without figures) over wheel
/// `w`'s moving steps.
fn mean_terms(
    cycle: &DriveCycle,
    steps: &[[StepWheel; 2]],
    w: usize,
    len: usize,
    value: &dyn Fn(&StepWheel) -> Option<Vec<f64>>,
) -> MeanTerms {
    let dt = cycle.step_durations_s();
    let mut sum = vec![0.0; len];
    let (mut known_km, mut unknown_km) = (0.0, 0.0);
    for (i, s) in steps.iter().enumerate() {
        let km = cycle.speed_kmh[i] * dt[i] / 3600.0;
        if km <= 0.0 {
            continue;
        }
        let Some(g) = value(&s[w]) else {
            unknown_km += km;
            continue;
        };
        known_km += km;
        for (acc, b) in sum.iter_mut().zip(&g) {
            *acc += km * b;
        }
    }
    MeanTerms {
        mean: (known_km > 0.0).then(|| sum.iter().map(|x| x / known_km).collect()),
        unknown_distance_share: if known_km + unknown_km > 0.0 {
            unknown_km / (known_km + unknown_km)
        } else {
            0.0
        },
    }
}
