//! The user's question in wear: how likely is a visible polygon within a distance, per wheel
//! (Wilson intervals), driving against follower on the same samples (McNemar), per bin of each
//! axis, over the risk maps' cells, how fast polygons grow and which orders they have. It reads
//! the wear stage's columns ([`crate::records::WEAR_COLUMNS`], MODEL.md#wear-columns); a run
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
use super::counts::WithinCounts;
use super::fleet::{WeightKind, ROW_COLUMN};
use super::paired::{self, Paired};
use super::risk_map::RiskMap;
use super::rows::{GroupKey, OrderCount, OutcomeColumn, Rows, SampleWeight};
use super::{AnalysisError, RunInfo};
use crate::chart::WheelCurves;
use crate::model::{Variant, Wheel};
use crate::params::ParamId;
use crate::records::WearColumn;

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
#[derive(Debug, Clone, PartialEq)]
pub struct WearBin {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The drawn parameter binned.
    pub axis: ParamId,
    /// Lower edge of the bin (the level itself for levels).
    pub lo: f64,
    /// Upper edge of the bin (the level itself for levels).
    pub hi: f64,
    /// Middle of the bin.
    pub mid: f64,
    /// The wheels within the distance, among the known.
    pub counts: WithinCounts,
}

/// Wear counts per cell, indexed `[ix][iy]`.
pub type WearGrid = Vec<Vec<WithinCounts>>;

/// A risk map of polygonal-wear likelihood: P(visible polygon within [`HEADLINE_WITHIN_KM`])
/// over the cells of a vibration risk map, per wheel, with the same stability boundaries.
#[derive(Debug, Clone)]
pub struct WearMap {
    /// The friction variant.
    pub variant: Variant,
    /// The parameter on the horizontal axis.
    pub x: ParamId,
    /// The parameter on the vertical axis.
    pub y: ParamId,
    /// Bins of the horizontal axis.
    pub x_bins: Bins,
    /// Bins of the vertical axis.
    pub y_bins: Bins,
    /// The distance \[km\].
    pub within_km: f64,
    /// (wheel, `counts[ix][iy]`).
    pub cells: Vec<(Wheel, WearGrid)>,
    /// The nominal tire's Hopf curves over the map's box, as on the vibration map.
    pub nominal: Option<Vec<WheelCurves>>,
}

impl WearMap {
    /// Probability per cell, NaN where fewer than `min_count` wheels have a known distance.
    pub fn probability(&self, wheel: Wheel, min_count: u64) -> Vec<Vec<f64>> {
        let Some((_, grid)) = self.cells.iter().find(|(w, _)| *w == wheel) else {
            return vec![vec![f64::NAN; self.y_bins.count()]; self.x_bins.count()];
        };
        grid.iter()
            .map(|col| {
                col.iter()
                    .map(|c| if c.enough(min_count) { c.p() } else { f64::NAN })
                    .collect()
            })
            .collect()
    }
}

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
    let mut map: BTreeMap<(Variant, Wheel), Vec<WithinCounts>> = BTreeMap::new();
    for g in &groups {
        let per_bin = map
            .entry((g.variant, g.wheel))
            .or_insert_with(|| vec![WithinCounts::default(); bins.count()]);
        if let Some(c) = usize::try_from(g.bins[0])
            .ok()
            .and_then(|i| per_bin.get_mut(i))
        {
            c.merge(&g.counts[0]);
        }
    }
    let mut out = Vec::new();
    for ((variant, wheel), per_bin) in map {
        for (i, counts) in per_bin.into_iter().enumerate() {
            let (lo, hi, mid) = bins.range(i);
            out.push(WearBin {
                variant,
                wheel,
                axis,
                lo,
                hi,
                mid,
                counts,
            });
        }
    }
    Ok(out)
}

/// The wear risk map over the cells of the vibration map `m`, each variant of the rows.
fn wear_map(rows: &Rows, m: &RiskMap, weight: SampleWeight) -> Result<Vec<WearMap>, AnalysisError> {
    let (xb, yb) = (&m.x_bins, &m.y_bins);
    let ny = yb.count() as i64;
    let empty = || vec![vec![WithinCounts::default(); yb.count()]; xb.count()];
    let mut grids: BTreeMap<Wheel, WearGrid> = BTreeMap::new();
    let key = GroupKey::Cell(m.x.name(), xb, m.y.name(), yb);
    for g in rows.within_counts(&[key], &[HEADLINE_WITHIN_KM], weight)? {
        if g.variant != m.variant {
            continue;
        }
        let grid = grids.entry(g.wheel).or_insert_with(empty);
        let cell = g.bins[0];
        if let (Ok(ix), Ok(iy)) = (usize::try_from(cell / ny), usize::try_from(cell % ny)) {
            if ix < xb.count() && iy < yb.count() {
                grid[ix][iy].merge(&g.counts[0]);
            }
        }
    }
    if grids.is_empty() {
        return Ok(Vec::new());
    }
    Ok(vec![WearMap {
        variant: m.variant,
        x: m.x,
        y: m.y,
        x_bins: xb.clone(),
        y_bins: yb.clone(),
        within_km: HEADLINE_WITHIN_KM,
        cells: Wheel::BOTH
            .iter()
            .map(|w| (*w, grids.get(w).cloned().unwrap_or_else(empty)))
            .collect(),
        nominal: m.nominal.clone(),
    }])
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
