//! The user's question in wear: how likely is a visible polygon within a distance, per wheel
//! (Wilson intervals), driving against follower on the same samples (McNemar), per bin of each
//! axis, over the risk maps' cells, how fast polygons grow and which orders they have. It reads
//! the wear stage's columns ([`polywear_core::records::WEAR_COLUMNS`], MODEL.md#wear-columns); a run
//! without them has no wear answer.
//!
//! A wheel's distance to a visible polygon means cruising at its sample's operating point, with
//! the study's speed spread, all its life (MODEL.md#the-per-sample-estimator). A wheel whose
//! distance is NaN (failed, no traction, standstill) is unknown: left out of numerator and
//! denominator and counted apart; +inf (every order levels out) is known and never within.
//!
//! Wear is weighed by distance: samples of a fleet weighted by hours stand for time, so each
//! counts in proportion to its speed (distance = hours × speed_kmh); every other run's samples
//! count once ([`SampleWeight`]).

mod severity;

use super::bins::Bins;
use super::counts::WithinCounts;
use super::fleet::WeightKind;
use super::outcome::{self, AnswerPlan, MapAxes, Occurrence, OutcomeAnswer, VisibleWithin};
use super::paired::Paired;
use super::risk_map::RiskMap;
use super::rows::Rows;
use super::{AnalysisError, RunInfo, Step};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::ParamId;
use polywear_core::records::WearColumn;

/// What [`WearAnalysis`] and [`WearSeverity`] hold beside their probabilities: how the samples
/// are weighed, the dominant orders, the near misses and the spread of a severity quantity.
pub use super::rows::{NearMisses, OrderCount, SampleWeight, WearSpread};
pub use severity::{WearQuantity, WearSeverity};

/// The distance of the headline, the conditional probabilities and the wear risk maps \[km\].
pub(crate) const HEADLINE_WITHIN_KM: f64 = 40_000.0;

/// The dominant orders are counted among the wheels with a visible polygon within this
/// distance \[km\].
pub(crate) const ORDERS_WITHIN_KM: f64 = 60_000.0;

/// The distances of `--within-km` by default \[km\].
pub(crate) const DEFAULT_WITHIN_KM: [f64; 4] = [10_000.0, 25_000.0, 40_000.0, 60_000.0];

/// The wear answer at one distance: [`OutcomeAnswer`] of `VisibleWithin` `within_km`.
#[derive(Debug, Clone)]
pub struct DistanceAnswer {
    /// The distance \[km\].
    pub within_km: f64,
    /// The answer: at `HEADLINE_WITHIN_KM` every one (per bin, over the maps' cells, per row
    /// of an operating-point file), at the other distances the occurrence and the paired
    /// comparison only.
    pub answer: OutcomeAnswer<WithinCounts>,
}

/// The wear answer of a run.
#[derive(Debug, Clone)]
pub struct WearAnalysis {
    /// How the samples are weighed.
    pub weight: SampleWeight,
    /// φ_s of the run, before any draw (`wear_share_straight`).
    pub share_straight: f64,
    /// σ_V of the run, before any draw \[km/h\] (`speed_spread_kmh`).
    pub speed_spread_kmh: f64,
    /// The visible depth \[mm\] (`visible_depth_mm`).
    pub visible_depth_mm: f64,
    /// The answer at each distance asked, increasing (`HEADLINE_WITHIN_KM` among them).
    pub by_distance: Vec<DistanceAnswer>,
    /// Growth rate and distance quantiles per variant and wheel.
    pub severity: Vec<WearSeverity>,
    /// Wheels per dominant order among those within `ORDERS_WITHIN_KM`.
    pub orders: Vec<OrderCount>,
    /// How near the deepest orders came to the visible depth over the tread's life, per
    /// variant and wheel (empty on the new tire's level).
    pub near_misses: Vec<NearMisses>,
}

impl WearAnalysis {
    /// The distances asked, increasing \[km\].
    pub fn within_km(&self) -> Vec<f64> {
        self.by_distance.iter().map(|d| d.within_km).collect()
    }

    /// The answer at `HEADLINE_WITHIN_KM`, with its bins, maps and rows.
    pub fn headline_answer(&self) -> &OutcomeAnswer<WithinCounts> {
        let d = self
            .by_distance
            .iter()
            .find(|d| d.within_km == HEADLINE_WITHIN_KM)
            .expect("the headline distance is always asked for");
        &d.answer
    }

    /// The headline of `variant` and `wheel`: the occurrence at `HEADLINE_WITHIN_KM`.
    pub fn headline(&self, variant: Variant, wheel: Wheel) -> Option<&Occurrence<WithinCounts>> {
        self.headline_answer().occurrence_of(variant, wheel)
    }

    /// The paired comparison of `variant` at `within_km`.
    pub fn paired_at(&self, variant: Variant, within_km: f64) -> Option<&Paired> {
        self.by_distance
            .iter()
            .find(|d| d.within_km == within_km)
            .and_then(|d| d.answer.paired_of(variant))
    }

    /// Every occurrence in the tables' order: by variant and wheel, then by distance.
    pub fn occurrence_rows(&self) -> Vec<(f64, &Occurrence<WithinCounts>)> {
        let mut rows: Vec<(f64, &Occurrence<WithinCounts>)> = self
            .by_distance
            .iter()
            .flat_map(|d| d.answer.occurrence.iter().map(move |o| (d.within_km, o)))
            .collect();
        rows.sort_by(|a, b| {
            (a.1.variant, a.1.wheel)
                .cmp(&(b.1.variant, b.1.wheel))
                .then(a.0.total_cmp(&b.0))
        });
        rows
    }

    /// Every paired comparison in the tables' order: by distance, then by variant.
    pub fn paired_rows(&self) -> Vec<(f64, &Paired)> {
        self.by_distance
            .iter()
            .flat_map(|d| d.answer.paired.iter().map(move |p| (d.within_km, p)))
            .collect()
    }

    /// Wheels with a distance that is unknown, over all variants and wheels.
    pub fn unknown(&self) -> u64 {
        self.headline_answer().totals().unknown
    }
}

/// The distances to ask for: `asked` with `HEADLINE_WITHIN_KM` added, increasing, without
/// repeats.
pub(crate) fn distances(asked: &[f64]) -> Vec<f64> {
    let mut d: Vec<f64> = asked.to_vec();
    d.push(HEADLINE_WITHIN_KM);
    d.sort_by(f64::total_cmp);
    d.dedup();
    d
}

/// How a run's samples are weighed for wear: by speed where a fleet's weights are hours.
pub(crate) fn sample_weight(info: &RunInfo) -> SampleWeight {
    let Some(op) = &info.operating_points else {
        return SampleWeight::Equal;
    };
    let hours = op.weight_kind.as_deref() == Some("time")
        || matches!(
            WeightKind::of(op.weight.as_deref(), None),
            WeightKind::Hours(_)
        );
    if hours {
        SampleWeight::SpeedKmh
    } else {
        SampleWeight::Equal
    }
}

/// Whether the rows hold the wear stage's columns.
pub(crate) fn has_wear(rows: &Rows) -> Result<bool, AnalysisError> {
    rows.has_column(WearColumn::DistanceToVisibleKm.name())
}

/// What the wear answer is computed from: the drawn axes' bins of the conditional
/// probabilities, and the vibration risk maps that are drawn.
pub(crate) struct WearInputs<'a> {
    /// Per drawn parameter, its bins.
    pub axis_bins: &'a [(ParamId, Bins)],
    /// The drawn vibration maps (their axes, bins and Hopf curves).
    pub maps: Vec<&'a RiskMap>,
    /// Rows of the paired comparison per file batch.
    pub batch_rows: u64,
}

/// The wear answer at the distances `within_km` (with `HEADLINE_WITHIN_KM` added): one
/// [`outcome::answer`] per distance, the headline's over the bins, the drawn vibration maps'
/// cells (each keeps its map's Hopf curves) and the rows of an operating-point file.
pub(crate) fn wear(
    rows: &Rows,
    info: &RunInfo,
    within_km: &[f64],
    inputs: &WearInputs<'_>,
    progress: &mut dyn FnMut(Step),
) -> Result<WearAnalysis, AnalysisError> {
    let weight = sample_weight(info);
    let mut pairs: Vec<MapAxes> = Vec::new();
    for m in &inputs.maps {
        if !pairs.iter().any(|p| (p.x.0, p.y.0) == (m.x, m.y)) {
            pairs.push(MapAxes {
                x: (m.x, m.x_bins.clone()),
                y: (m.y, m.y_bins.clone()),
            });
        }
    }
    let mut by_distance = Vec::new();
    for km in distances(within_km) {
        let headline = km == HEADLINE_WITHIN_KM;
        let plan = AnswerPlan {
            info,
            axis_bins: if headline { inputs.axis_bins } else { &[] },
            maps: if headline { &pairs } else { &[] },
            fleet: headline && info.operating_points.is_some(),
            batch_rows: inputs.batch_rows,
        };
        let mut answer = outcome::answer(&VisibleWithin { km, weight }, rows, &plan, progress)?;
        // Only the drawn vibration maps' variants, each with that map's Hopf curves.
        answer.maps = std::mem::take(&mut answer.maps)
            .into_iter()
            .filter_map(|map| {
                let m = inputs
                    .maps
                    .iter()
                    .find(|m| (m.variant, m.x, m.y) == (map.variant, map.x, map.y))?;
                Some(RiskMap {
                    nominal: m.nominal.clone(),
                    ..map
                })
            })
            .collect();
        by_distance.push(DistanceAnswer {
            within_km: km,
            answer,
        });
    }
    let p = &info.params;
    Ok(WearAnalysis {
        weight,
        share_straight: p.wear_share_straight,
        speed_spread_kmh: p.speed_spread_kmh,
        visible_depth_mm: p.visible_depth_mm,
        by_distance,
        severity: severity::wear_severity(rows)?,
        orders: rows.dominant_orders(ORDERS_WITHIN_KM)?,
        near_misses: rows.near_misses()?,
    })
}
