//! Driving against follower on the same samples: how many samples vibrate on one wheel only, on
//! both, on neither, and McNemar's test of the discordant ones. The counts come from the chunk
//! files (`paired_on`) or from records in memory (`PairTally`, as `reproduce` has them).

use std::path::PathBuf;

use super::counts::outcome_code;
use super::rows::{pairs_by_sample, pairs_in_row_order, OutcomeColumn, PairCounts};
use super::stats::mcnemar;
use super::AnalysisError;
use polywear_core::classify::Class;
use polywear_core::model::Variant;

/// The paired comparison on the same samples (McNemar), over samples whose two wheels are
/// both classified. Two are equal when every count and the test are (a test without data, NaN,
/// equal to another without data).
#[derive(Debug, Clone)]
pub struct Paired {
    /// The friction variant.
    pub variant: Variant,
    /// Samples whose two wheels are both classified.
    pub pairs: u64,
    /// Samples where only the follower vibrates.
    pub only_follower: u64,
    /// Samples where only the driving wheel vibrates.
    pub only_driving: u64,
    /// Samples where both wheels vibrate.
    pub both: u64,
    /// Samples where neither wheel vibrates.
    pub neither: u64,
    /// Samples where a wheel failed or had no traction: left out of the comparison.
    pub unclassified: u64,
    /// McNemar's continuity-corrected χ² statistic (computed under either test).
    pub chi2: f64,
    /// McNemar's two-sided p-value.
    pub p_value: f64,
    /// Which McNemar test gave `p_value`: `exact` (binomial, up to 10,000 discordant pairs) or
    /// `chi2`.
    pub method: &'static str,
}

impl PartialEq for Paired {
    fn eq(&self, o: &Self) -> bool {
        let same = |a: f64, b: f64| a == b || (a.is_nan() && b.is_nan());
        (
            self.variant,
            self.pairs,
            self.only_follower,
            self.only_driving,
        ) == (o.variant, o.pairs, o.only_follower, o.only_driving)
            && (self.both, self.neither, self.unclassified, self.method)
                == (o.both, o.neither, o.unclassified, o.method)
            && same(self.chi2, o.chi2)
            && same(self.p_value, o.p_value)
    }
}

impl Paired {
    /// McNemar's p-value in words, with the test that gave it: "n/a (no discordant pairs)"
    /// when there is nothing to test.
    pub fn mcnemar_text(&self) -> String {
        if self.p_value.is_nan() {
            "n/a (no discordant pairs)".into()
        } else {
            format!("{} ({})", super::stats::format_p(self.p_value), self.method)
        }
    }

    /// The discordant and concordant counts in words: "only follower a, only driving b, both
    /// c, neither d".
    pub fn counts_text(&self) -> String {
        format!(
            "only follower {}, only driving {}, both {}, neither {}",
            self.only_follower, self.only_driving, self.both, self.neither
        )
    }

    /// Compared samples where the follower vibrates.
    pub fn follower_vibrating(&self) -> u64 {
        self.both + self.only_follower
    }
    /// Compared samples where the driving wheel vibrates.
    pub fn driving_vibrating(&self) -> u64 {
        self.both + self.only_driving
    }
    /// Share of compared samples where the follower vibrates.
    pub fn p_follower(&self) -> f64 {
        self.follower_vibrating() as f64 / self.pairs as f64
    }
    /// Share of compared samples where the driving wheel vibrates.
    pub fn p_driving(&self) -> f64 {
        self.driving_vibrating() as f64 / self.pairs as f64
    }
}

/// Samples per variant and pair of outcomes, counted one sample at a time.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct PairTally {
    combos: PairCounts,
}

impl PairTally {
    /// Counts one sample of `variant` whose follower has class `follower` and driving wheel
    /// class `driving`.
    pub fn add(&mut self, variant: Variant, follower: Class, driving: Class) {
        let combo = outcome_code(follower) + 3 * outcome_code(driving);
        *self.combos.entry((variant, combo)).or_default() += 1;
    }

    /// The paired table of each variant counted, in variant order.
    pub fn paired(&self) -> Vec<Paired> {
        paired_from(&self.combos)
    }
}

/// Driving vs follower on the same samples of the chunk files, per variant (the baseline's rows
/// when the run has scenarios), on any outcome: vibration, or a visible polygon within a
/// distance (the wear stage's); a wheel whose outcome is unknown makes its sample
/// unclassified. In one streaming pass when the files are in explore's row order, else grouped
/// by sample in batches of about `batch_rows` rows.
pub(crate) fn paired_on(
    files: &[PathBuf],
    batch_rows: u64,
    has_scenarios: bool,
    outcome: OutcomeColumn<'_>,
) -> Result<Vec<Paired>, AnalysisError> {
    match pairs_in_row_order(files, has_scenarios, outcome)? {
        Some(combos) => Ok(paired_from(&combos)),
        None => Ok(paired_from(&pairs_by_sample(
            files,
            batch_rows,
            has_scenarios,
            outcome,
        )?)),
    }
}

/// The paired table from sample counts per (variant, follower code + 3 × driving code).
fn paired_from(combos: &PairCounts) -> Vec<Paired> {
    let mut variants: Vec<Variant> = combos.keys().map(|k| k.0).collect();
    variants.dedup();
    variants
        .into_iter()
        .map(|variant| {
            let get = |c: i64| combos.get(&(variant, c)).copied().unwrap_or(0);
            // follower + 3 × driving
            let (neither, only_f, only_d, both) = (get(0), get(1), get(3), get(4));
            let unclassified: u64 = combos
                .iter()
                .filter(|((v, c), _)| *v == variant && ![0, 1, 3, 4].contains(c))
                .map(|(_, n)| n)
                .sum();
            let (chi2, p_value, method) = mcnemar(only_f, only_d);
            Paired {
                variant,
                pairs: neither + only_f + only_d + both,
                only_follower: only_f,
                only_driving: only_d,
                both,
                neither,
                unclassified,
                chi2,
                p_value,
                method,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tally_counts_each_pair_of_outcomes_once() {
        use Class::*;
        let mut t = PairTally::default();
        for (f, d) in [
            (LimitCycle, Stable),
            (Bistable, Stable),
            (Stable, LimitCycle),
            (LimitCycle, Bistable),
            (Stable, Stable),
            (Stable, NoTraction),
            (Failed, Failed),
        ] {
            t.add(Variant::SlidingShare, f, d);
        }
        t.add(Variant::Paper, Stable, Stable);
        let p = t.paired();
        assert_eq!(p.len(), 2);
        let s = p
            .iter()
            .find(|p| p.variant == Variant::SlidingShare)
            .unwrap();
        assert_eq!(
            (
                s.only_follower,
                s.only_driving,
                s.both,
                s.neither,
                s.unclassified
            ),
            (2, 1, 1, 1, 2)
        );
        assert_eq!(s.pairs, 5);
        assert_eq!((s.follower_vibrating(), s.driving_vibrating()), (3, 2));
        assert_eq!(mcnemar(2, 1).1, s.p_value);
    }

    /// The vibration's paired table, as the analysis computes it.
    fn paired(
        files: &[PathBuf],
        batch_rows: u64,
        has_scenarios: bool,
    ) -> Result<Vec<Paired>, AnalysisError> {
        paired_on(files, batch_rows, has_scenarios, OutcomeColumn::Vibration)
    }

    /// The same table by grouping the rows by sample, whatever their order: the oracle of the
    /// streaming pass over rows in explore's order.
    fn paired_by_group(
        files: &[PathBuf],
        batch_rows: u64,
        has_scenarios: bool,
    ) -> Result<Vec<Paired>, AnalysisError> {
        Ok(paired_from(&pairs_by_sample(
            files,
            batch_rows,
            has_scenarios,
            OutcomeColumn::Vibration,
        )?))
    }

    /// A run of 3 chunks of 100 samples, both variants, some samples failed (a tyre at 2.3 kPa),
    /// so every outcome combination occurs; written by the library as `explore` writes it.
    fn explore_run_with_failures(dir: &std::path::Path) -> PathBuf {
        use polywear_study::explore::ExploreRequest;
        use polywear_study::refusal::Refusal;
        let _ = std::fs::remove_dir_all(dir);
        std::fs::create_dir_all(dir).unwrap();
        let study = dir.join("run.toml");
        std::fs::write(
            &study,
            "accept_implausible = true\nname = \"small\"\nseed = 5\nsamples = 300\n\
             chunk_size = 100\nvariants = [\"paper\", \"combined\"]\n[params]\n\
             speed_kmh = { dist = \"uniform\", min = 60, max = 250 }\n\
             toe_deg = { dist = \"uniform\", min = 0.1, max = 0.5 }\n\
             pressure_kpa = { dist = \"levels\", levels = [240, 240, 2.3] }\n",
        )
        .unwrap();
        let request = ExploreRequest {
            study: Some(study),
            out: Some(dir.join("run")),
            no_wear: true,
            ..ExploreRequest::default()
        };
        let plan = request.plan(&|b| Ok::<_, Refusal>(b)).unwrap().0;
        let prepared = plan.prepare_output().unwrap();
        plan.run(&prepared, &|_| {}).unwrap();
        plan.out_dir.clone()
    }

    /// Moved from the integration tests (analyze.rs): the streaming pass over rows in row
    /// order counts what grouping by sample id counts.
    #[test]
    fn pairing_by_row_order_equals_pairing_by_sample_id() {
        let dir = std::env::temp_dir().join(format!("polywear-pairing-{}", std::process::id()));
        let run = explore_run_with_failures(&dir);
        let (files, _) = crate::analysis::inputs::parquet_files(&[run]).unwrap();
        let by_order = paired(&files, 1000, false).unwrap();
        let by_group = paired_by_group(&files, 1000, false).unwrap();
        assert_eq!(by_order, by_group);
        assert_eq!(by_order.len(), 2);
        for p in &by_order {
            assert!(p.unclassified > 0 && p.pairs > 0, "{p:?}");
            assert_eq!(p.pairs + p.unclassified, 300, "{p:?}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
