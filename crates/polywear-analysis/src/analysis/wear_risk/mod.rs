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

use std::collections::BTreeMap;

use super::bins::Bins;
use super::conditional::{self, BinStat};
use super::counts::WithinCounts;
use super::fleet::{WeightKind, ROW_COLUMN};
use super::paired::{self, Paired};
use super::risk_map::{self, RiskMap};
use super::rows::{GroupKey, OrderCount, OutcomeColumn, Rows, SampleWeight};
use super::{AnalysisError, RunInfo};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::ParamId;
use polywear_core::records::WearColumn;

pub use severity::{WearSeverity, WEAR_QUANTITIES};

/// The distance of the headline, the conditional probabilities and the wear risk maps \[km\].
pub const HEADLINE_WITHIN_KM: f64 = 40_000.0;

/// The dominant orders are counted among the wheels with a visible polygon within this
/// distance \[km\].
pub const ORDERS_WITHIN_KM: f64 = 60_000.0;

/// The distances of `--within-km` by default \[km\].
pub const DEFAULT_WITHIN_KM: [f64; 4] = [10_000.0, 25_000.0, 40_000.0, 60_000.0];

/// P(visible polygon within a distance) for one variant and wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct WearOccurrence {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The distance \[km\].
    pub within_km: f64,
    /// The wheels within it, among the known.
    pub counts: WithinCounts,
}

/// Driving against follower on "a visible polygon within `within_km`", on the same samples;
/// `paired`'s "vibrates" reads "reaches a visible polygon within the distance", its
/// "unclassified" samples have a wheel whose distance is unknown.
#[derive(Debug, Clone, PartialEq)]
pub struct WearPaired {
    /// The distance \[km\].
    pub within_km: f64,
    /// The paired table and McNemar's test.
    pub paired: Paired,
}

/// P(visible polygon within [`HEADLINE_WITHIN_KM`]) in one bin of one axis.
pub type WearBin = BinStat<WithinCounts>;

/// A risk map of polygonal-wear likelihood: P(visible polygon within [`HEADLINE_WITHIN_KM`])
/// over the cells of a vibration risk map, per wheel, with the same stability boundaries.
pub type WearMap = RiskMap<WithinCounts>;

/// One row of an operating-point file: P(visible polygon within [`HEADLINE_WITHIN_KM`]) per
/// wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct WearFleetRow {
    /// The friction variant.
    pub variant: Variant,
    /// The row of the file, counted from 1.
    pub row: u64,
    /// Follower, driving.
    pub counts: [WithinCounts; 2],
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
    /// The distances asked for, increasing \[km\] ([`HEADLINE_WITHIN_KM`] among them).
    pub within_km: Vec<f64>,
    /// P(visible polygon within each distance), per variant, wheel and distance.
    pub occurrence: Vec<WearOccurrence>,
    /// Driving against follower at each distance, per variant.
    pub paired: Vec<WearPaired>,
    /// P(visible polygon within [`HEADLINE_WITHIN_KM`]) per bin of every drawn parameter.
    pub conditional: Vec<WearBin>,
    /// The wear risk maps, one per drawn vibration map.
    pub maps: Vec<WearMap>,
    /// Growth rate and distance quantiles per variant and wheel.
    pub severity: Vec<WearSeverity>,
    /// Wheels per dominant order among those within [`ORDERS_WITHIN_KM`].
    pub orders: Vec<OrderCount>,
    /// Per row of an operating-point file (a fleet run only).
    pub fleet: Vec<WearFleetRow>,
}

impl WearAnalysis {
    /// The headline of `variant` and `wheel`: the occurrence at [`HEADLINE_WITHIN_KM`].
    pub fn headline(&self, variant: Variant, wheel: Wheel) -> Option<&WearOccurrence> {
        self.occurrence
            .iter()
            .find(|o| o.variant == variant && o.wheel == wheel && o.within_km == HEADLINE_WITHIN_KM)
    }

    /// The paired comparison of `variant` at `within_km`.
    pub fn paired_at(&self, variant: Variant, within_km: f64) -> Option<&Paired> {
        self.paired
            .iter()
            .find(|p| p.paired.variant == variant && p.within_km == within_km)
            .map(|p| &p.paired)
    }

    /// Wheels with a distance that is unknown, over all variants and wheels.
    pub fn unknown(&self) -> u64 {
        self.occurrence
            .iter()
            .filter(|o| o.within_km == HEADLINE_WITHIN_KM)
            .map(|o| o.counts.unknown)
            .sum()
    }
}

/// The distances to ask for: `asked` with [`HEADLINE_WITHIN_KM`] added, increasing, without
/// repeats.
pub fn distances(asked: &[f64]) -> Vec<f64> {
    let mut d: Vec<f64> = asked.to_vec();
    d.push(HEADLINE_WITHIN_KM);
    d.sort_by(f64::total_cmp);
    d.dedup();
    d
}

/// How a run's samples are weighed for wear: by speed where a fleet's weights are hours.
pub fn sample_weight(info: &RunInfo) -> SampleWeight {
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
pub fn has_wear(rows: &Rows) -> Result<bool, AnalysisError> {
    rows.has_column(WearColumn::DistanceToVisibleKm.name())
}

/// What the wear answer is computed from: the drawn axes' bins of the conditional
/// probabilities, and the vibration risk maps that are drawn.
pub struct WearInputs<'a> {
    /// Per drawn parameter, its bins.
    pub axis_bins: Vec<(ParamId, Bins)>,
    /// The drawn vibration maps (their axes, bins and Hopf curves).
    pub maps: Vec<&'a RiskMap>,
    /// Rows of the paired comparison per file batch.
    pub batch_rows: u64,
}

/// The wear answer at the distances `within_km` (with [`HEADLINE_WITHIN_KM`] added).
pub fn wear(
    rows: &Rows,
    info: &RunInfo,
    within_km: &[f64],
    inputs: &WearInputs<'_>,
) -> Result<WearAnalysis, AnalysisError> {
    let within_km = distances(within_km);
    let weight = sample_weight(info);
    let has_scenarios = !info.scenarios.is_empty();
    let mut occurrence = Vec::new();
    let mut totals: BTreeMap<(Variant, Wheel), Vec<WithinCounts>> = BTreeMap::new();
    for g in rows.within_counts(&[], &within_km, weight)? {
        let t = totals
            .entry((g.variant, g.wheel))
            .or_insert_with(|| vec![WithinCounts::default(); within_km.len()]);
        t.iter_mut().zip(&g.counts).for_each(|(a, b)| a.merge(b));
    }
    for ((variant, wheel), counts) in totals {
        for (km, c) in within_km.iter().zip(counts) {
            occurrence.push(WearOccurrence {
                variant,
                wheel,
                within_km: *km,
                counts: c,
            });
        }
    }
    let mut paired = Vec::new();
    for &km in &within_km {
        let outcome = OutcomeColumn::WithinKm {
            column: WearColumn::DistanceToVisibleKm.name(),
            km,
        };
        for p in paired::paired_on(&info.files, inputs.batch_rows, has_scenarios, outcome)? {
            paired.push(WearPaired {
                within_km: km,
                paired: p,
            });
        }
    }
    let mut conditional = Vec::new();
    for (axis, bins) in &inputs.axis_bins {
        conditional.extend(wear_conditional(rows, *axis, bins, weight)?);
    }
    let mut maps = Vec::new();
    for m in &inputs.maps {
        maps.extend(wear_map(rows, m, weight)?);
    }
    let fleet = if info.operating_points.is_some() {
        wear_fleet(rows, weight)?
    } else {
        Vec::new()
    };
    let p = &info.params;
    Ok(WearAnalysis {
        weight,
        share_straight: p.wear_share_straight,
        speed_spread_kmh: p.speed_spread_kmh,
        visible_depth_mm: p.visible_depth_mm,
        within_km,
        occurrence,
        paired,
        conditional,
        maps,
        severity: severity::wear_severity(rows)?,
        orders: rows.dominant_orders(ORDERS_WITHIN_KM)?,
        fleet,
    })
}

/// P(visible polygon within [`HEADLINE_WITHIN_KM`] | axis in bin), every bin of every (variant,
/// wheel) present, empty bins included.
fn wear_conditional(
    rows: &Rows,
    axis: ParamId,
    bins: &Bins,
    weight: SampleWeight,
) -> Result<Vec<WearBin>, AnalysisError> {
    let groups = rows.within_counts(
        &[GroupKey::Bin(axis.name(), bins)],
        &[HEADLINE_WITHIN_KM],
        weight,
    )?;
    Ok(conditional::bins_of_groups(
        groups
            .iter()
            .map(|g| (g.variant, g.wheel, g.bins[0], &g.counts[0])),
        axis,
        bins,
    ))
}

/// The wear risk map over the cells of the vibration map `m`, each variant of the rows.
fn wear_map(rows: &Rows, m: &RiskMap, weight: SampleWeight) -> Result<Vec<WearMap>, AnalysisError> {
    let (x, y) = ((m.x, &m.x_bins), (m.y, &m.y_bins));
    let key = GroupKey::Cell(m.x.name(), x.1, m.y.name(), y.1);
    let groups = rows.within_counts(&[key], &[HEADLINE_WITHIN_KM], weight)?;
    let cells = groups
        .iter()
        .filter(|g| g.variant == m.variant)
        .map(|g| (g.variant, g.wheel, g.bins[0], &g.counts[0]));
    Ok(risk_map::maps_of_cells(cells, x, y)
        .into_iter()
        .map(|map| WearMap {
            nominal: m.nominal.clone(),
            ..map
        })
        .collect())
}

/// Per row of the operating-point file: P(visible polygon within [`HEADLINE_WITHIN_KM`]) per
/// wheel, in variant and row order.
fn wear_fleet(rows: &Rows, weight: SampleWeight) -> Result<Vec<WearFleetRow>, AnalysisError> {
    let mut per_row: BTreeMap<(Variant, u64), [WithinCounts; 2]> = BTreeMap::new();
    let groups = rows.within_counts(
        &[GroupKey::Value(ROW_COLUMN)],
        &[HEADLINE_WITHIN_KM],
        weight,
    )?;
    for g in groups {
        let row = g.values[0];
        if row.is_nan() || row < 1.0 {
            continue;
        }
        let k = usize::from(g.wheel == Wheel::Driving);
        per_row.entry((g.variant, row as u64)).or_default()[k].merge(&g.counts[0]);
    }
    Ok(per_row
        .into_iter()
        .map(|((variant, row), counts)| WearFleetRow {
            variant,
            row,
            counts,
        })
        .collect())
}
