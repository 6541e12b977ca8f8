//! What each scenario changes, against its reference on the same samples (the baseline, or the
//! scenario its `compare_to` names): per scenario, variant and wheel, the probability of an
//! outcome (vibration; a visible polygon within a distance) under both, the paired difference
//! with its 95% interval (Newcombe's square-and-add interval for paired proportions,
//! [`newcombe_paired`]), McNemar's test, and how many samples change outcome in each direction.
//! Beside it, the interval two independent runs of the same size would give
//! ([`newcombe_independent`]), which is what pairing saves.

use super::outcome::{Outcome as _, Vibrates, VisibleWithin};
use super::rows::{scenario_pairs, Rows, ScenarioPairCounts};
use super::stats::{mcnemar, newcombe_independent, newcombe_paired};
use super::{AnalysisError, RunInfo};
use polywear_core::model::{Variant, Wheel};
use polywear_study::study::{Scenario, BASELINE};

/// The outcome a scenario is compared on, as [`ScenarioEffect::outcome`] holds it.
pub use super::rows::OutcomeColumn;
pub(crate) use polywear_core::records::DISTANCE_COLUMN;

/// The outcome a scenario is compared on: vibration, or a visible polygon within a distance
/// (the outcomes of [`crate::analysis::outcome`], by their row column).
pub(crate) type Outcome = OutcomeColumn<'static>;

/// One scenario's effect on one wheel under one variant.
#[derive(Debug, Clone, PartialEq)]
pub struct ScenarioEffect {
    /// The scenario's name.
    pub scenario: String,
    /// Its changes in words.
    pub changes: String,
    /// What it is compared with: `baseline`, or the scenario its `compare_to` names. The
    /// `baseline` of the counts and probabilities below is this reference.
    pub reference: String,
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// What is compared.
    pub outcome: Outcome,
    /// Samples with a verdict under both the reference and the scenario.
    pub pairs: u64,
    /// Samples with the outcome under both.
    pub both: u64,
    /// Samples with the outcome under the reference only (the scenario removes it).
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
    /// Whether the scenario is compared with the baseline (no `compare_to`).
    pub fn against_baseline(&self) -> bool {
        self.reference == BASELINE
    }
    /// The probability under the reference, over the paired samples.
    pub fn p_baseline(&self) -> f64 {
        (self.both + self.only_baseline) as f64 / self.pairs as f64
    }
    /// The probability under the scenario, over the paired samples.
    pub fn p_scenario(&self) -> f64 {
        (self.both + self.only_scenario) as f64 / self.pairs as f64
    }
    /// Scenario minus reference.
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

/// The effect of every scenario of the run against its reference, per variant, wheel and
/// outcome: a visible polygon within `within_km` first when the rows have [`DISTANCE_COLUMN`]
/// (else a note says why not), then vibration. Empty for a run without scenarios.
pub(crate) fn compare(
    info: &RunInfo,
    within_km: f64,
    batch_rows: u64,
    notes: &mut Vec<String>,
) -> Result<Vec<ScenarioEffect>, AnalysisError> {
    if info.scenarios.is_empty() {
        return Ok(Vec::new());
    }
    let names: Vec<&str> = info.scenarios.iter().map(|s| s.name.as_str()).collect();
    let references = reference_blocks(&info.scenarios)?;
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
        let counts = scenario_pairs(&info.files, batch_rows, &names, &references, outcome)?;
        out.extend(effects(&info.scenarios, &info.variants, outcome, &counts));
    }
    Ok(out)
}

pub(crate) use super::inputs::reference_blocks;

/// The effects of one outcome from its pair counts, in scenario, variant and wheel order.
pub(crate) fn effects(
    scenarios: &[Scenario],
    variants: &[Variant],
    outcome: Outcome,
    counts: &ScenarioPairCounts,
) -> Vec<ScenarioEffect> {
    let mut out = Vec::new();
    for (k, s) in scenarios.iter().enumerate() {
        for &variant in variants {
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
                    reference: s.reference().to_string(),
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

#[cfg(test)]
mod tests {
    use super::*;
    use polywear_core::classify::Class;
    use polywear_study::parquet_out::{write_table, Column};
    use polywear_study::study::{Change, ParamChange};

    /// A scenario of toe-in changes compared with `compare_to`.
    fn scenario(name: &str, compare_to: Option<&str>) -> Scenario {
        Scenario {
            name: name.into(),
            changes: vec![ParamChange {
                param: polywear_core::params::ParamId::ToeDeg,
                change: Change::Shift(-0.01),
            }],
            compare_to: compare_to.map(str::to_string),
        }
    }

    /// A row's class and distance from its sample, block and wheel: a fixed scramble, so that
    /// the blocks disagree on many samples in both directions, with a few failures.
    fn outcome(sample: u64, block: u64, wheel: u64) -> (Class, f64) {
        let mut x = sample.wrapping_mul(0x9e37_79b9_7f4a_7c15)
            ^ block.wrapping_mul(0xbf58_476d_1ce4_e5b9)
            ^ wheel.wrapping_mul(0x94d0_49bb_1331_11eb);
        x ^= x >> 31;
        x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9);
        x ^= x >> 29;
        let h = x % 1009;
        let class = match h % 7 {
            0 => Class::Failed,
            1..=3 => Class::LimitCycle,
            _ => Class::Stable,
        };
        (class, (h as f64) * 100.0)
    }

    /// The effect of a scenario against a named reference is its rows' paired difference with
    /// the reference's rows, counted here sample by sample: the same counts, difference and
    /// interval as against the baseline, with the reference's rows in the baseline's place.
    #[test]
    fn an_effect_against_a_named_reference_is_the_paired_difference_of_their_rows() {
        let dir = std::env::temp_dir().join(format!("polywear-compare-to-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("chunk-0000000.parquet");
        let names = ["baseline", "a", "b", "c"];
        let samples = 60u64;
        let mut cols = (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for sample in 0..samples {
            for (block, name) in names.iter().enumerate() {
                for (w, wheel) in Wheel::BOTH.iter().enumerate() {
                    let (class, km) = outcome(sample, block as u64, w as u64);
                    cols.0.push(sample as i64);
                    cols.1.push(name.to_string());
                    cols.2.push(wheel.to_string());
                    cols.3.push(class.as_str().to_string());
                    cols.4.push(km);
                }
            }
        }
        let n = cols.0.len();
        let columns = [
            Column::i64("sample_id", "", cols.0),
            Column::str("scenario", cols.1),
            Column::str("variant", vec!["sliding_share".into(); n]),
            Column::str("wheel", cols.2),
            Column::str("class", cols.3),
            Column::f64(DISTANCE_COLUMN, "km", cols.4),
        ];
        write_table(&file, &columns, &[]).unwrap();
        // b against a, c against b (a reference compared with a third), a against the baseline.
        let scenarios = [
            scenario("a", None),
            scenario("b", Some("a")),
            scenario("c", Some("b")),
        ];
        let references = reference_blocks(&scenarios).unwrap();
        assert_eq!(references, [0, 1, 2]);
        let scenario_names = ["a", "b", "c"];
        let variants = [Variant::SlidingShare];
        for outcome_column in [
            Outcome::Vibration,
            Outcome::WithinKm {
                column: DISTANCE_COLUMN,
                km: 50_000.0,
            },
        ] {
            let counts = scenario_pairs(
                std::slice::from_ref(&file),
                1,
                &scenario_names,
                &references,
                outcome_column,
            )
            .unwrap();
            let got = effects(&scenarios, &variants, outcome_column, &counts);
            assert_eq!(got.len(), 3 * 2);
            for e in &got {
                let k = scenario_names
                    .iter()
                    .position(|s| *s == e.scenario)
                    .unwrap();
                let (scen, refb) = (k as u64 + 1, references[k] as u64);
                assert_eq!(e.reference, names[refb as usize]);
                let w = Wheel::BOTH.iter().position(|w| *w == e.wheel).unwrap() as u64;
                let yes = |block: u64, sample: u64| -> Option<bool> {
                    let (class, km) = outcome(sample, block, w);
                    match (class, outcome_column) {
                        (Class::Failed, _) => None,
                        (c, Outcome::Vibration) => Some(c != Class::Stable),
                        (_, Outcome::WithinKm { km: within, .. }) => Some(km <= within),
                    }
                };
                let (mut t, mut pairs) = ([[0u64; 2]; 2], 0u64);
                for sample in 0..samples {
                    if let (Some(r), Some(s)) = (yes(refb, sample), yes(scen, sample)) {
                        t[usize::from(r)][usize::from(s)] += 1;
                        pairs += 1;
                    }
                }
                let (both, only_ref, only_scen, neither) = (t[1][1], t[1][0], t[0][1], t[0][0]);
                assert_eq!(
                    (e.pairs, e.both, e.only_baseline, e.only_scenario, e.neither),
                    (pairs, both, only_ref, only_scen, neither),
                    "{} {}",
                    e.scenario,
                    e.wheel
                );
                assert_eq!(e.unclassified, samples - pairs);
                let p = |x: u64| x as f64 / pairs as f64;
                assert_eq!(e.p_baseline(), p(both + only_ref));
                assert_eq!(e.p_scenario(), p(both + only_scen));
                let direct = p(both + only_scen) - p(both + only_ref);
                assert!((e.difference() - direct).abs() < 1e-15, "{e:?}");
                assert_eq!(
                    e.interval(),
                    newcombe_paired(both, only_scen, only_ref, neither)
                );
                assert_eq!((e.chi2, e.p_value, e.method), mcnemar(only_ref, only_scen));
            }
            // The scrambled blocks do differ: the test compares something.
            assert!(
                got.iter()
                    .all(|e| e.only_baseline > 0 && e.only_scenario > 0),
                "{got:#?}"
            );
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn a_reference_the_run_does_not_hold_is_refused() {
        let e = reference_blocks(&[scenario("a", Some("z"))]).unwrap_err();
        assert!(e.to_string().contains("compared with `z`"), "{e}");
        assert!(reference_blocks(&[scenario("a", Some("a"))]).is_err());
    }
}
