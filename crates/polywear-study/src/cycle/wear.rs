//! The distance to a visible polygon for a car that drives a cycle all its life
//! (MODEL.md#along-a-drive-cycle), over the tread's life with each speed's print saturated (the
//! one wear answer).
//!
//! The steps share one tread, whose depth falls at the cycle's mean whole even wear; at each
//! worn depth every step reads its closed loop at the order its drifting tread frequency puts
//! there ([`LifeProfile`]). The steps' profiles are summed by the distance covered at each
//! ([`CycleLife`]) and by speed bin of `SATURATED_SPEED_BIN_KMH`, each bin printing at most
//! what sliding can modulate, on its own
//! ([`polywear_core::wear::estimator::answer_saturated_per_step`]); the first order to reach the
//! visible depth before the tire is worn out is the polygon.

use super::DriveCycle;
use polywear_core::classify::budget::Meter;
use polywear_core::classify::ClassifierOptions;
use polywear_core::evaluate::{WearStage, WheelSolution};
use polywear_core::params::Params;
use polywear_core::wear::estimator::{print_log_ratio, tread_life_km};
use polywear_core::wear::estimator::{SaturatedSteps, SLIDING_MODULATION_MAX};
use polywear_core::wear::physics::law::MM_PER_1000KM_PER_M_PER_M;
use polywear_core::wear::{FittedConstants, LifeProfile, WheelGrowth, LIFE_PROFILE_INTERVALS};

/// The highest order followed along a cycle: the seed's band (MODEL.md#step-12-feedback). A step
/// slower than about 25 km/h puts ν above it; its orders near ν are not followed (their
/// distance at such speeds is small).
pub(crate) const CYCLE_ORDERS_MAX: u32 = 64;

/// The width of the speed bins whose steps saturate together \[km/h\]: a bin's steps share one bound (the min of their sum, weaker than each
/// step's own). A step's resonance is sharp in speed, so the bins must be fine: against every
/// step on its own on HWFET at φ_s = 1 (`crates/polywear-lab/examples/saturation_probe.rs`), bins of 1 km/h put the
/// polygon 5–7% early, 0.5 km/h 2–3%, 0.25 km/h under 0.5%, and 0.1 km/h (a cycle's own
/// resolution: HWFET's 766 steps hold 250 speeds) not at all. A bin holds one profile a wheel
/// (66 KB).
pub(crate) const SATURATED_SPEED_BIN_KMH: f64 = 0.1;

/// One wheel's profile over the tread's life at one step, with no speed spread (a cycle's
/// speeds are its spread); None where the wheel has no figures (no model, failed, standstill,
/// past its wall-clock limit: a step's distance then counts as without figures, never a profile
/// laid out in part).
pub fn step_life(
    p: &Params,
    wheel: &WheelSolution,
    stage: &WearStage,
    options: &ClassifierOptions,
) -> Option<LifeProfile> {
    let growth = WheelGrowth::new(&stage.problem(p, wheel), &Meter::new(options.budget)).ok()?;
    let life = growth.life_profile(CYCLE_ORDERS_MAX, LIFE_PROFILE_INTERVALS);
    growth.out_of_time().is_none().then_some(life)
}

/// One wheel's profiles over the tread's life summed over a cycle's steps, each by the
/// distance covered at it \[km\], and the distance at steps without figures.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CycleLife {
    /// Σ km_k · profile_k over the steps with figures (None before the first).
    pub profile_km: Option<LifeProfile>,
    /// The same sums by speed bin of `SATURATED_SPEED_BIN_KMH`, rising: (bin, Σ km_k ·
    /// profile_k, Σ km_k \[km\]).
    pub by_speed: Vec<(i64, LifeProfile, f64)>,
    /// The distance at those steps \[km\].
    pub known_km: f64,
    /// The distance at moving steps without figures (failed, no traction) \[km\].
    pub unknown_km: f64,
}

impl CycleLife {
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
        let bin = (speed_kmh / SATURATED_SPEED_BIN_KMH).round() as i64;
        add_to_bin(&mut self.by_speed, bin, profile, km, km);
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
        for (bin, sum, km) in &other.by_speed {
            add_to_bin(&mut self.by_speed, *bin, sum, 1.0, *km);
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
    /// of them, and each set reads its answer off them. The steps' profiles were laid out at the
    /// structure's own carcass and belt shares, which a set's do not replace: a cycle's band
    /// spans φ_s and k_d (σ_V does not enter: the cycle's speeds are its spread).
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
        let bins = (!self.by_speed.is_empty()).then(|| {
            SaturatedSteps::new(
                self.by_speed
                    .iter()
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
                        bounded.tread_life_km = tread_life_km(
                            base,
                            mean.tread_wear_m_per_m(c) * MM_PER_1000KM_PER_M_PER_M,
                        );
                        bounded
                    }
                    None => mean.answer(c, base),
                };
                let distance = life.distance_to_visible_km;
                CycleWear {
                    dominant_order: life.polygon_order_wear,
                    growth_rate_per_1000km: if distance.is_finite() && distance > 0.0 {
                        target / distance * 1000.0
                    } else {
                        f64::NAN
                    },
                    distance_to_visible_km: distance,
                    unknown_distance_share,
                    tread_life_km: life.tread_life_km,
                    peak_share_of_visible: life.peak_share_of_visible,
                }
            })
            .collect()
    }
}

/// The memory \[bytes\] one wheel's speed bins take over `cycle`: one profile of orders 1..=`CYCLE_ORDERS_MAX` on [`LIFE_PROFILE_INTERVALS`] for
/// each bin of `SATURATED_SPEED_BIN_KMH` its moving steps fill.
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
