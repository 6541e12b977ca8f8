//! The two questions an analysis answers, asked one way: does a wheel *vibrate* (settles on a
//! limit cycle or is bistable, `Vibrates`), and does it get a *visible polygon within X km*
//! (`VisibleWithin`). Each is an `Outcome`: what it counts per group of rows (its polars
//! aggregation), the per-row column the paired comparison reads, and its words. One function,
//! `answer`, computes every answer the two share (occurrence per wheel, driving against
//! follower on the same samples, per bin of each axis, over the risk maps' cells, per row of
//! an operating-point file) into one [`OutcomeAnswer`], and one set of tables and figures draws
//! it, so an answer added later (a calibration band, say) is written once for both.

use std::collections::BTreeMap;

use super::bins::Bins;
use super::conditional::{self, BinStat};
use super::counts::{ClassCounts, RiskCounts, WithinCounts};
use super::paired::{self, Paired};
use super::risk_map::{self, RiskMap};
use super::rows::{Group, GroupKey, OutcomeColumn, Rows, SampleWeight};
use super::{AnalysisError, RunInfo, Step};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::ParamId;
use polywear_core::records::{WearColumn, OPERATING_POINT_ROW};
use polywear_core::wording::km;

/// An outcome of a wheel that an analysis estimates the probability of.
pub(crate) trait Outcome {
    /// What a group of rows counts: its numerator, denominator and the rows counted apart.
    type Counts: RiskCounts + std::fmt::Debug + PartialEq;
    /// The counts per variant, wheel and combination of `keys`, in one streaming group-by.
    fn counts(
        &self,
        rows: &Rows,
        keys: &[GroupKey<'_>],
    ) -> Result<Vec<Group<Self::Counts>>, AnalysisError>;
    /// The outcome of one row, as the paired comparison reads it (yes, no, unknown).
    fn column(&self) -> OutcomeColumn<'static>;
    /// The outcome in words, as a sentence names it: "vibration", "a visible polygon within
    /// 40,000 km".
    fn words(&self) -> String;
}

/// The wheel vibrates: settles on a limit cycle, or is bistable (MODEL.md#classes).
/// Counted over the classified rows; failed and no-traction rows apart ([`ClassCounts`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Vibrates;

impl Outcome for Vibrates {
    type Counts = ClassCounts;
    fn counts(
        &self,
        rows: &Rows,
        keys: &[GroupKey<'_>],
    ) -> Result<Vec<Group<ClassCounts>>, AnalysisError> {
        rows.class_counts(keys)
    }
    fn column(&self) -> OutcomeColumn<'static> {
        OutcomeColumn::Vibration
    }
    fn words(&self) -> String {
        "vibration".into()
    }
}

/// The wheel reaches a visible polygon within `km` (its `distance_to_visible_km` at most
/// `km`), its samples weighed by `weight` (MODEL.md#the-per-sample-estimator). A wheel whose
/// distance is NaN is unknown and counted apart ([`WithinCounts`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct VisibleWithin {
    /// The distance \[km\].
    pub km: f64,
    /// How the samples are weighed.
    pub weight: SampleWeight,
}

impl Outcome for VisibleWithin {
    type Counts = WithinCounts;
    fn counts(
        &self,
        rows: &Rows,
        keys: &[GroupKey<'_>],
    ) -> Result<Vec<Group<WithinCounts>>, AnalysisError> {
        Ok(rows
            .within_counts(keys, &[self.km], self.weight)?
            .into_iter()
            .map(|g| Group {
                variant: g.variant,
                wheel: g.wheel,
                bins: g.bins,
                values: g.values,
                counts: g.counts[0],
            })
            .collect())
    }
    fn column(&self) -> OutcomeColumn<'static> {
        OutcomeColumn::WithinKm {
            column: WearColumn::DistanceToVisibleKm.name(),
            km: self.km,
        }
    }
    fn words(&self) -> String {
        format!("a visible polygon within {}", km(self.km))
    }
}

/// The probability of an outcome for one variant and wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct Occurrence<C = ClassCounts> {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// What the wheel's rows count.
    pub counts: C,
}

impl<C: RiskCounts> Occurrence<C> {
    /// The probability; NaN without a denominator.
    pub fn p(&self) -> f64 {
        self.counts.p()
    }
}

/// One row of an operating-point file: what each wheel's samples drawn from it count.
#[derive(Debug, Clone, PartialEq)]
pub struct RowCounts<C = ClassCounts> {
    /// The friction variant.
    pub variant: Variant,
    /// The row of the file, counted from 1.
    pub row: u64,
    /// Follower, driving.
    pub counts: [C; 2],
}

impl<C> RowCounts<C> {
    /// The counts of `wheel`.
    pub fn of(&self, wheel: Wheel) -> &C {
        &self.counts[usize::from(wheel == Wheel::Driving)]
    }
}

/// Every answer the two outcomes share, for one outcome.
#[derive(Debug, Clone)]
pub struct OutcomeAnswer<C = ClassCounts> {
    /// The outcome in words (`Outcome::words`).
    pub words: String,
    /// The probability per variant and wheel, in (variant, wheel) order.
    pub occurrence: Vec<Occurrence<C>>,
    /// Driving against follower on the same samples (McNemar), per variant.
    pub paired: Vec<Paired>,
    /// Per bin of each axis of `AnswerPlan::axis_bins`.
    pub conditional: Vec<BinStat<C>>,
    /// Over the cells of each map of `AnswerPlan::maps`, every variant.
    pub maps: Vec<RiskMap<C>>,
    /// Per row of the operating-point file, in variant and row order (only when
    /// `AnswerPlan::fleet`).
    pub fleet: Vec<RowCounts<C>>,
}

impl<C: RiskCounts> OutcomeAnswer<C> {
    /// The occurrence of `variant` and `wheel`.
    pub fn occurrence_of(&self, variant: Variant, wheel: Wheel) -> Option<&Occurrence<C>> {
        self.occurrence
            .iter()
            .find(|o| o.variant == variant && o.wheel == wheel)
    }

    /// The paired comparison of `variant`.
    pub fn paired_of(&self, variant: Variant) -> Option<&Paired> {
        self.paired.iter().find(|p| p.variant == variant)
    }

    /// The counts of every variant and wheel added up.
    pub fn totals(&self) -> C {
        let mut t = C::default();
        self.occurrence.iter().for_each(|o| t.merge(&o.counts));
        t
    }
}

/// The two axes and bins of a risk map.
#[derive(Debug, Clone)]
pub(crate) struct MapAxes {
    /// The horizontal axis and its bins.
    pub x: (ParamId, Bins),
    /// The vertical axis and its bins.
    pub y: (ParamId, Bins),
}

/// What [`answer`] computes, beside the occurrence and the paired comparison it always does.
pub(crate) struct AnswerPlan<'a> {
    /// The run the rows come from (its files, variants and sample count).
    pub info: &'a RunInfo,
    /// Per axis, its bins (empty: no conditional probabilities).
    pub axis_bins: &'a [(ParamId, Bins)],
    /// The risk maps' axes (empty: no maps).
    pub maps: &'a [MapAxes],
    /// Whether to count per row of the operating-point file.
    pub fleet: bool,
    /// Rows per file batch of the paired comparison when the files are not in row order.
    pub batch_rows: u64,
}

/// Every answer of [`OutcomeAnswer`] for `outcome`, calling `progress` after each step.
/// The occurrence is checked against the footers first (every variant and wheel one row per
/// sample, [`AnalysisError::RowsDisagree`] otherwise), so rows that do not belong to the run
/// are refused before the slower queries run.
pub(crate) fn answer<O: Outcome>(
    outcome: &O,
    rows: &Rows,
    plan: &AnswerPlan<'_>,
    progress: &mut dyn FnMut(Step),
) -> Result<OutcomeAnswer<O::Counts>, AnalysisError> {
    let info = plan.info;
    let occurrence = occurrence(outcome, rows)?;
    check_rows_agree(outcome, info, &occurrence)?;
    progress(Step::Occurrence);
    let paired = paired::paired_on(
        &info.files,
        plan.batch_rows,
        !info.scenarios.is_empty(),
        outcome.column(),
    )?;
    progress(Step::Paired);
    let fleet = if plan.fleet {
        row_counts(outcome, rows)?
    } else {
        Vec::new()
    };
    progress(Step::Fleet);
    let mut per_bin = Vec::new();
    for (axis, bins) in plan.axis_bins {
        let groups = outcome.counts(rows, &[GroupKey::Bin(axis.name(), bins)])?;
        per_bin.extend(conditional::bins_of_groups(
            groups
                .iter()
                .map(|g| (g.variant, g.wheel, g.bins[0], &g.counts)),
            *axis,
            bins,
        ));
        progress(Step::Conditional);
    }
    let mut maps = Vec::new();
    for m in plan.maps {
        let (x, y) = ((m.x.0, &m.x.1), (m.y.0, &m.y.1));
        let key = GroupKey::Cell(x.0.name(), x.1, y.0.name(), y.1);
        let groups = outcome.counts(rows, &[key])?;
        maps.extend(risk_map::maps_of_cells(
            groups
                .iter()
                .map(|g| (g.variant, g.wheel, g.bins[0], &g.counts)),
            x,
            y,
        ));
        progress(Step::RiskMap);
    }
    Ok(OutcomeAnswer {
        words: outcome.words(),
        occurrence,
        paired,
        conditional: per_bin,
        maps,
        fleet,
    })
}

/// The outcome's counts per variant and wheel, in (variant, wheel) order.
pub(crate) fn occurrence<O: Outcome>(
    outcome: &O,
    rows: &Rows,
) -> Result<Vec<Occurrence<O::Counts>>, AnalysisError> {
    let mut map: BTreeMap<(Variant, Wheel), O::Counts> = BTreeMap::new();
    for g in outcome.counts(rows, &[])? {
        map.entry((g.variant, g.wheel))
            .or_default()
            .merge(&g.counts);
    }
    Ok(map
        .into_iter()
        .map(|((variant, wheel), counts)| Occurrence {
            variant,
            wheel,
            counts,
        })
        .collect())
}

/// The outcome's counts per row of the operating-point file, in variant and row order (groups
/// without a row, or before the first, are left out).
fn row_counts<O: Outcome>(
    outcome: &O,
    rows: &Rows,
) -> Result<Vec<RowCounts<O::Counts>>, AnalysisError> {
    let mut per_row: BTreeMap<(Variant, u64), [O::Counts; 2]> = BTreeMap::new();
    for g in outcome.counts(rows, &[GroupKey::Value(OPERATING_POINT_ROW.name)])? {
        let row = g.values[0];
        if row.is_nan() || row < 1.0 {
            continue;
        }
        let k = usize::from(g.wheel == Wheel::Driving);
        per_row.entry((g.variant, row as u64)).or_default()[k].merge(&g.counts);
    }
    Ok(per_row
        .into_iter()
        .map(|((variant, row), counts)| RowCounts {
            variant,
            row,
            counts,
        })
        .collect())
}

/// Refuses rows whose variant or wheel the footers do not describe: each variant of the footers
/// and each wheel hold exactly one row per sample present, and no other pair has rows. The file
/// at fault is found by a query of each file, on this error's path only.
fn check_rows_agree<O: Outcome>(
    outcome: &O,
    info: &RunInfo,
    occurrence: &[Occurrence<O::Counts>],
) -> Result<(), AnalysisError> {
    let agree = |occ: &[Occurrence<O::Counts>], samples: Option<u64>| {
        let counts: Vec<u64> = occ.iter().map(|o| o.counts.rows()).collect();
        occ.len() == 2 * info.variants.len()
            && occ.iter().all(|o| info.variants.contains(&o.variant))
            && counts.windows(2).all(|w| w[0] == w[1])
            && samples.is_none_or(|n| counts.first() == Some(&n))
    };
    if agree(occurrence, Some(info.samples_present)) {
        return Ok(());
    }
    let what = |occ: &[Occurrence<O::Counts>]| {
        occ.iter()
            .map(|o| format!("{} {} rows of {}", o.counts.rows(), o.wheel, o.variant))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let culprit = info
        .files
        .iter()
        .map(|f| {
            let rows = Rows::scan(std::slice::from_ref(f))?;
            Ok((f, self::occurrence(outcome, &rows)?))
        })
        .find(|r: &Result<_, AnalysisError>| r.as_ref().map_or(true, |(_, o)| !agree(o, None)))
        .transpose()?;
    let (path, occ) = match &culprit {
        Some((f, occ)) => ((*f).clone(), occ.as_slice()),
        None => (info.files[0].clone(), occurrence),
    };
    Err(AnalysisError::RowsDisagree {
        path,
        what: format!("holds {}", what(occ)),
        variants: info.variant_text(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_outcomes_name_themselves_and_their_row_column() {
        assert_eq!(Vibrates.words(), "vibration");
        assert_eq!(Vibrates.column(), OutcomeColumn::Vibration);
        let w = VisibleWithin {
            km: 40_000.0,
            weight: SampleWeight::Equal,
        };
        assert_eq!(w.words(), "a visible polygon within 40,000 km");
        assert_eq!(
            w.column(),
            OutcomeColumn::WithinKm {
                column: "distance_to_visible_km",
                km: 40_000.0
            }
        );
    }

    #[test]
    fn an_answer_adds_its_wheels_up_and_finds_them_by_variant() {
        let mut c = ClassCounts::default();
        c.add(polywear_core::classify::Class::LimitCycle, 2);
        c.add(polywear_core::classify::Class::Stable, 6);
        let a = OutcomeAnswer {
            words: Vibrates.words(),
            occurrence: Wheel::BOTH
                .map(|wheel| Occurrence {
                    variant: Variant::Paper,
                    wheel,
                    counts: c,
                })
                .to_vec(),
            paired: Vec::new(),
            conditional: Vec::new(),
            maps: Vec::new(),
            fleet: Vec::new(),
        };
        assert_eq!(a.totals().classified(), 16);
        assert_eq!(a.totals().p(), 0.25);
        assert!(a.occurrence_of(Variant::Paper, Wheel::Driving).is_some());
        assert!(a.occurrence_of(Variant::Combined, Wheel::Driving).is_none());
    }
}
