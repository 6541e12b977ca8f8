//! "What the changes do": each scenario against its reference (the baseline, or the scenario
//! its `compare_to` names) in words, as a table (`scenarios.csv`, `.parquet`) and as one picture
//! of every effect with its interval. A run whose scenarios all compare with the baseline reads
//! as it did before `compare_to` existed: the reference is named only where it is another.

use polywear_core::wording::capitalise;
use std::fmt::Write as _;
use std::path::Path;

use super::RenderError;
use crate::analysis::scenarios::{Outcome, ScenarioEffect};
use crate::analysis::Analysis;
use crate::plot::effects::{effects_figure, Effect, EffectPanel};
use crate::plot::FigureFile;
use polywear_core::model::Wheel;
use polywear_study::parquet_out::Column;
use polywear_study::stats::format_p;

/// Percent with one decimal.
fn pct(p: f64) -> String {
    format!("{:.1}%", 100.0 * p)
}

/// Percentage points with a sign, as finely as the interval's width needs.
fn points(x: f64, width: f64) -> String {
    let digits = if width < 0.01 { 2 } else { 1 };
    let v = 100.0 * x;
    let text = format!("{v:+.digits$}");
    // "-0.0" and "+0.0" read as zero.
    if text
        .trim_start_matches(['+', '-'])
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        format!("{:.digits$}", 0.0)
    } else {
        text.replace('-', "−")
    }
}

/// What the outcome is, for the sentence: "risk of vibration".
fn risk(outcome: Outcome) -> String {
    match outcome {
        Outcome::Vibration => "risk of vibration".into(),
        Outcome::WithinKm { km: within_km, .. } => format!(
            "risk of a visible polygon within {} km",
            polywear_core::wording::thousands(within_km)
        ),
    }
}

/// One effect in words: "the follower's risk of vibration falls from 84.1% to 45.2% (−38.9
/// points, 95% interval −40.9 to −36.9; 790 samples lose it, 12 gain it)"; against another
/// scenario, the points say which: "(−4.1 points against `phi_014`, ...)".
pub(crate) fn sentence(e: &ScenarioEffect) -> String {
    let (lo, hi) = e.interval();
    let width = hi - lo;
    let whose = match e.wheel {
        Wheel::Follower => "the follower's",
        Wheel::Driving => "the driving wheel's",
    };
    let (from, to) = (e.p_baseline(), e.p_scenario());
    let against = if e.against_baseline() {
        String::new()
    } else {
        format!(" against `{}`", e.reference)
    };
    let moves = if e.only_baseline == 0 && e.only_scenario == 0 {
        return format!(
            "{whose} {} stays at {}{against} (no sample changes)",
            risk(e.outcome),
            pct(from)
        );
    } else if lo <= 0.0 && hi >= 0.0 {
        "does not change significantly"
    } else if to < from {
        "falls"
    } else {
        "rises"
    };
    let what = match e.outcome {
        Outcome::Vibration => ("stop vibrating", "start"),
        Outcome::WithinKm { .. } => ("lose it", "gain it"),
    };
    format!(
        "{whose} {} {moves} from {} to {} ({} points{against}, 95% interval {} to {}; {} samples {}, {} {}; McNemar p {})",
        risk(e.outcome),
        pct(from),
        pct(to),
        points(e.difference(), width),
        points(lo, width),
        points(hi, width),
        e.only_baseline,
        what.0,
        e.only_scenario,
        what.1,
        p_text(e.p_value)
    )
}

/// `= 1.2e-5`, or `< 1e-300`.
fn p_text(p: f64) -> String {
    let text = format_p(p);
    if text.starts_with('<') {
        text
    } else {
        format!("= {text}")
    }
}

/// The section "What the changes do", or nothing for a run without scenarios.
pub(crate) fn section(a: &Analysis, figure: Option<&Path>) -> String {
    let mut s = String::new();
    if a.scenarios.is_empty() {
        return s;
    }
    let _ = writeln!(s, "## What the changes do\n");
    let _ = writeln!(
        s,
        "Each scenario changes every sample of the baseline and is evaluated on the same samples \
         (the same operating points and tire structures), so the differences below are paired: \
         only the change differs. Intervals are Newcombe's square-and-add 95% intervals for the \
         difference of paired proportions (Newcombe 1998, method 10); McNemar's test asks whether \
         the samples that change go one way more than the other. Probabilities are over the \
         samples with a verdict under both. Every other section of this report is the baseline's."
    );
    if a.scenarios.iter().any(|e| !e.against_baseline()) {
        let _ = writeln!(
            s,
            "A scenario with `compare_to` is compared with the scenario it names instead of the \
             baseline, on the same samples: its figures are its own rows against that \
             scenario's, what it changes beyond it."
        );
    }
    let _ = writeln!(s);
    let variants = a.variants();
    for effect_group in group_by_scenario(&a.scenarios) {
        let first = effect_group[0];
        if first.against_baseline() {
            let _ = writeln!(s, "**{}** ({}):", first.scenario, first.changes);
        } else {
            let reference = a.info.scenarios.iter().find(|r| r.name == first.reference);
            let _ = writeln!(
                s,
                "**{}** ({}), against **{}** ({}):",
                first.scenario,
                first.changes,
                first.reference,
                reference.map(|r| r.words()).unwrap_or_default()
            );
        }
        for e in &effect_group {
            let variant = if variants.len() > 1 {
                format!(" [{}]", e.variant)
            } else {
                String::new()
            };
            let banded = a
                .band
                .as_ref()
                .and_then(|b| b.effect_of(e))
                .map_or(String::new(), |r| format!("; {}", super::band::points(r)));
            let _ = writeln!(s, "- {}{banded}{variant}.", capitalise(&sentence(e)));
        }
        if let Some(e) = effect_group
            .iter()
            .find(|e| e.wheel == Wheel::Follower && e.narrowing().is_finite())
        {
            let _ = writeln!(
                s,
                "- Pairing: the follower's interval is {} two separate runs of {} samples would give.",
                narrowing_words(e.narrowing()),
                e.pairs
            );
        }
        let _ = writeln!(s);
    }
    if let Some(f) = figure {
        let name = f.file_name().map(|n| n.to_string_lossy().into_owned());
        let _ = writeln!(s, "![]({})\n", name.unwrap_or_default());
    }
    let _ = writeln!(s, "Table: `scenarios.csv`, `scenarios.parquet`.\n");
    s
}

/// The effects of each scenario together, in the analysis' order (wear first where there).
fn group_by_scenario(effects: &[ScenarioEffect]) -> Vec<Vec<&ScenarioEffect>> {
    let mut names: Vec<&str> = Vec::new();
    for e in effects {
        if !names.contains(&e.scenario.as_str()) {
            names.push(&e.scenario);
        }
    }
    names
        .iter()
        .map(|n| {
            let mut of: Vec<&ScenarioEffect> =
                effects.iter().filter(|e| e.scenario == *n).collect();
            of.sort_by_key(|e| matches!(e.outcome, Outcome::Vibration));
            of
        })
        .collect()
}

/// The table: one row per scenario, variant, wheel and outcome.
pub(crate) fn columns(effects: &[ScenarioEffect]) -> Vec<Column> {
    let f = |name: &str, g: &dyn Fn(&ScenarioEffect) -> f64| {
        Column::f64(name, "-", effects.iter().map(g).collect())
    };
    let n = |name: &str, g: &dyn Fn(&ScenarioEffect) -> u64| {
        Column::i64(name, "", effects.iter().map(|e| g(e) as i64).collect())
    };
    let t = |name: &str, g: &dyn Fn(&ScenarioEffect) -> String| {
        Column::str(name, effects.iter().map(g).collect())
    };
    let mut cols = vec![
        t("scenario", &|e| e.scenario.clone()),
        t("changes", &|e| e.changes.clone()),
    ];
    // The table of a run without `compare_to` keeps its columns; with one, every row says what
    // `p_baseline` and `only_baseline` are of.
    if effects.iter().any(|e| !e.against_baseline()) {
        cols.push(t("reference", &|e| e.reference.clone()));
    }
    cols.extend([
        t("variant", &|e| e.variant.to_string()),
        t("wheel", &|e| e.wheel.to_string()),
        t("outcome", &|e| e.outcome.name()),
        n("pairs", &|e| e.pairs),
        f("p_baseline", &|e| e.p_baseline()),
        f("p_scenario", &|e| e.p_scenario()),
        f("difference", &|e| e.difference()),
        f("difference_low", &|e| e.interval().0),
        f("difference_high", &|e| e.interval().1),
        f("unpaired_low", &|e| e.unpaired_interval().0),
        f("unpaired_high", &|e| e.unpaired_interval().1),
        n("both", &|e| e.both),
        n("only_baseline", &|e| e.only_baseline),
        n("only_scenario", &|e| e.only_scenario),
        n("neither", &|e| e.neither),
        n("unclassified", &|e| e.unclassified),
        f("mcnemar_chi2", &|e| e.chi2),
        f("mcnemar_p", &|e| e.p_value),
        t("mcnemar_method", &|e| e.method.to_string()),
    ]);
    cols
}

/// The picture: every scenario's effect on each wheel with its interval, in percentage points,
/// one panel per outcome (and variant).
pub(crate) fn figure(file: &FigureFile, effects: &[ScenarioEffect]) -> Result<(), RenderError> {
    let mut keys: Vec<(Outcome, polywear_core::model::Variant)> = Vec::new();
    for e in effects {
        if !keys.contains(&(e.outcome, e.variant)) {
            keys.push((e.outcome, e.variant));
        }
    }
    let all_baseline = effects.iter().all(ScenarioEffect::against_baseline);
    let minus = if all_baseline {
        "scenario minus baseline"
    } else {
        "scenario minus its reference"
    };
    let panels: Vec<EffectPanel> = keys
        .iter()
        .map(|&(outcome, variant)| EffectPanel {
            title: format!("{} ({variant} variant)", capitalise(&risk(outcome))),
            x_label: format!("{minus} [percentage points]"),
            effects: effects
                .iter()
                .filter(|e| e.outcome == outcome && e.variant == variant)
                .map(|e| {
                    let (lo, hi) = e.interval();
                    let label = if e.against_baseline() {
                        format!("{} · {}", e.scenario, e.wheel)
                    } else {
                        format!("{} vs {} · {}", e.scenario, e.reference, e.wheel)
                    };
                    Effect {
                        label,
                        color: usize::from(e.wheel == Wheel::Driving),
                        estimate: 100.0 * e.difference(),
                        lo: 100.0 * lo,
                        hi: 100.0 * hi,
                    }
                })
                .collect(),
        })
        .collect();
    effects_figure(
        file,
        &format!("What the changes do: {minus}, 95% interval (blue: follower, red: driving wheel)"),
        &panels,
    )
    .map_err(RenderError::Figure)
}

#[cfg(test)]
mod tests {
    use super::*;
    use polywear_core::model::Variant;

    fn effect(only_baseline: u64, only_scenario: u64) -> ScenarioEffect {
        ScenarioEffect {
            scenario: "toe-in -0.15°".into(),
            changes: "toe_deg shifted by -0.15 deg".into(),
            reference: "baseline".into(),
            variant: Variant::SlidingShare,
            wheel: Wheel::Follower,
            outcome: Outcome::WithinKm {
                column: crate::analysis::scenarios::DISTANCE_COLUMN,
                km: 40_000.0,
            },
            pairs: 10_000,
            both: 600,
            only_baseline,
            only_scenario,
            neither: 10_000 - 600 - only_baseline - only_scenario,
            unclassified: 0,
            chi2: 0.0,
            p_value: 1e-5,
            method: "chi2",
        }
    }

    #[test]
    fn a_falling_risk_reads_as_the_issue_writes_it() {
        let text = sentence(&effect(1500, 10));
        assert!(
            text.starts_with(
                "the follower's risk of a visible polygon within 40,000 km falls from 21.0% to 6.1% (−14.9 points, 95% interval"
            ),
            "{text}"
        );
        assert!(text.contains("1500 samples lose it, 10 gain it"), "{text}");
        let none = sentence(&effect(0, 0));
        assert!(none.contains("stays at 6.0% (no sample changes)"), "{none}");
        let even = sentence(&effect(20, 21));
        assert!(even.contains("does not change significantly"), "{even}");
    }

    #[test]
    fn an_effect_against_another_scenario_names_it() {
        let e = ScenarioEffect {
            reference: "phi_014".into(),
            ..effect(1500, 10)
        };
        let text = sentence(&e);
        assert!(
            text.starts_with(
                "the follower's risk of a visible polygon within 40,000 km falls from 21.0% to 6.1% (−14.9 points against `phi_014`, 95% interval"
            ),
            "{text}"
        );
        let none = sentence(&ScenarioEffect {
            reference: "phi_014".into(),
            ..effect(0, 0)
        });
        assert!(
            none.contains("stays at 6.0% against `phi_014` (no sample changes)"),
            "{none}"
        );
        let names = |effects: &[ScenarioEffect]| -> Vec<String> {
            columns(effects).iter().map(|c| c.name.clone()).collect()
        };
        // The reference is a column only where a scenario names one.
        assert!(!names(&[effect(1, 2)]).contains(&"reference".to_string()));
        assert_eq!(names(&[effect(1, 2), e])[2], "reference");
    }
}

/// How the paired interval's width compares with the unpaired one's, `ratio` = unpaired /
/// paired: "2.3 times narrower than", "about as wide as" (within 15%, where "1.0 times
/// narrower" would say nothing true), "1.4 times wider than".
fn narrowing_words(ratio: f64) -> String {
    if ratio >= 1.15 {
        format!("{ratio:.1} times narrower than")
    } else if ratio > 1.0 / 1.15 {
        "about as wide as".to_string()
    } else {
        format!("{:.1} times wider than", 1.0 / ratio)
    }
}

#[cfg(test)]
mod narrowing_tests {
    use super::narrowing_words;

    #[test]
    fn a_ratio_near_one_is_about_as_wide() {
        assert_eq!(narrowing_words(2.34), "2.3 times narrower than");
        assert_eq!(narrowing_words(1.04), "about as wide as");
        assert_eq!(narrowing_words(0.96), "about as wide as");
        assert_eq!(narrowing_words(0.7), "1.4 times wider than");
        for r in [1.0, 1.049, 0.951] {
            assert!(!narrowing_words(r).contains("1.0 times"), "{r}");
        }
    }
}
