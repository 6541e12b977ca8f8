//! What each scenario changes, against the baseline on the same samples: per scenario, variant
//! and wheel, the probability of an outcome (vibration; a visible polygon within a distance)
//! under both, the paired difference with its 95% interval (Newcombe's square-and-add interval
//! for paired proportions, [`newcombe_paired`]), McNemar's test, and how many samples change
//! outcome in each direction. Beside it, the interval two independent runs of the same size
//! would give ([`newcombe_independent`]), which is what pairing saves.

use super::outcome::{Outcome as _, Vibrates, VisibleWithin};
use super::rows::{scenario_pairs, OutcomeColumn, Rows, ScenarioPairCounts};
use super::stats::{mcnemar, newcombe_independent, newcombe_paired};
use super::{AnalysisError, RunInfo};
use polywear_core::model::{Variant, Wheel};

pub use polywear_core::records::DISTANCE_COLUMN;

/// The outcome a scenario is compared on: vibration, or a visible polygon within a distance
/// (the outcomes of [`crate::analysis::outcome`], by their row column).
pub type Outcome = OutcomeColumn<'static>;

/// One scenario's effect on one wheel under one variant.
#[derive(Debug, Clone, PartialEq)]
pub struct ScenarioEffect {
    /// The scenario's name.
    pub scenario: String,
    /// Its changes in words.
    pub changes: String,
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// What is compared.
    pub outcome: Outcome,
    /// Samples with a verdict under both the baseline and the scenario.
    pub pairs: u64,
    /// Samples with the outcome under both.
    pub both: u64,
    /// Samples with the outcome under the baseline only (the scenario removes it).
    pub only_baseline: u64,
    /// Samples with the outcome under the scenario only (the scenario brings it).
    pub only_scenario: u64,
    /// Samples with the outcome under neither.
    pub neither: u64,
    /// Samples without a verdict under one or both (failed, no traction, undefined).
    pub unclassified: u64,
    /// McNemar's continuity-corrected χ² of the discordant samples.
    pub chi2: f64,
    /// McNemar's two-sided p-value.
    pub p_value: f64,
    /// Which McNemar test gave it (`exact` or `chi2`).
    pub method: &'static str,
}

impl ScenarioEffect {
    /// The probability under the baseline, over the paired samples.
    pub fn p_baseline(&self) -> f64 {
        (self.both + self.only_baseline) as f64 / self.pairs as f64
    }
    /// The probability under the scenario, over the paired samples.
    pub fn p_scenario(&self) -> f64 {
        (self.both + self.only_scenario) as f64 / self.pairs as f64
    }
    /// Scenario minus baseline.
    pub fn difference(&self) -> f64 {
        (self.only_scenario as f64 - self.only_baseline as f64) / self.pairs as f64
    }
    /// The paired difference's 95% interval.
    pub fn interval(&self) -> (f64, f64) {
        newcombe_paired(
            self.both,
            self.only_scenario,
            self.only_baseline,
            self.neither,
        )
    }
    /// The 95% interval the same difference would have from two independent runs of the same
    /// size.
    pub fn unpaired_interval(&self) -> (f64, f64) {
        let n = self.pairs;
        newcombe_independent(
            self.both + self.only_scenario,
            n,
            self.both + self.only_baseline,
            n,
        )
    }
    /// How many times narrower the paired interval is than the unpaired one (NaN without width).
    pub fn narrowing(&self) -> f64 {
        let (a, b) = self.interval();
        let (c, d) = self.unpaired_interval();
        (d - c) / (b - a)
    }
}

/// The effect of every scenario of the run, per variant, wheel and outcome: a visible polygon
/// within `within_km` first when the rows have [`DISTANCE_COLUMN`] (else a note says why not),
/// then vibration. Empty for a run without scenarios.
pub fn compare(
    info: &RunInfo,
    within_km: f64,
    batch_rows: u64,
    notes: &mut Vec<String>,
) -> Result<Vec<ScenarioEffect>, AnalysisError> {
    if info.scenarios.is_empty() {
        return Ok(Vec::new());
    }
    let names: Vec<&str> = info.scenarios.iter().map(|s| s.name.as_str()).collect();
    let mut outcomes = Vec::new();
    if Rows::scan(&info.files)?.has_column(DISTANCE_COLUMN)? {
        let weight = super::rows::SampleWeight::Equal;
        outcomes.push(
            VisibleWithin {
                km: within_km,
                weight,
            }
            .column(),
        );
    } else {
        notes.push(format!(
            "the scenarios are compared on vibration only: the rows have no `{DISTANCE_COLUMN}` column (the wear stage's), so there is no risk of a visible polygon to compare"
        ));
    }
    outcomes.push(Vibrates.column());
    let mut out = Vec::new();
    for outcome in outcomes {
        let counts = scenario_pairs(&info.files, batch_rows, &names, outcome)?;
        out.extend(effects(info, outcome, &counts));
    }
    Ok(out)
}

/// The effects of one outcome from its pair counts, in scenario, variant and wheel order.
pub fn effects(
    info: &RunInfo,
    outcome: Outcome,
    counts: &ScenarioPairCounts,
) -> Vec<ScenarioEffect> {
    let mut out = Vec::new();
    for (k, s) in info.scenarios.iter().enumerate() {
        for &variant in &info.variants {
            for wheel in Wheel::BOTH {
                let get =
                    |b: i64, c: i64| counts.get(&(k, variant, wheel, b, c)).copied().unwrap_or(0);
                let total: u64 = counts
                    .iter()
                    .filter(|((kk, v, w, _, _), _)| *kk == k && *v == variant && *w == wheel)
                    .map(|(_, n)| n)
                    .sum();
                if total == 0 {
                    continue;
                }
                let (both, only_baseline, only_scenario, neither) =
                    (get(1, 1), get(1, 0), get(0, 1), get(0, 0));
                let pairs = both + only_baseline + only_scenario + neither;
                let (chi2, p_value, method) = mcnemar(only_baseline, only_scenario);
                out.push(ScenarioEffect {
                    scenario: s.name.clone(),
                    changes: s.words(),
                    variant,
                    wheel,
                    outcome,
                    pairs,
                    both,
                    only_baseline,
                    only_scenario,
                    neither,
                    unclassified: total - pairs,
                    chi2,
                    p_value,
                    method,
                });
            }
        }
    }
    out
}
