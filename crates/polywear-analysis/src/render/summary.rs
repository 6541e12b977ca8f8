//! The analysis in words for the terminal: the lines `analyze` (and `explore`'s closing report)
//! print, the wear answer first.

use std::path::{Path, PathBuf};

use super::{answer_words, band};
use crate::analysis::Analysis;
use polywear_core::params::Params;
use polywear_core::wear::FittedConstants;
use polywear_core::wording::plain;

/// Why an analysis has no probability to give, with its `report`: every row failed or had no
/// traction. None where some row has a verdict.
pub(crate) fn no_verdict(a: &Analysis, report: &Path) -> Option<String> {
    if !a.nothing_classified() {
        return None;
    }
    let t = a.totals();
    Some(format!(
        "no row has a verdict: all {} rows failed ({}) or had no traction ({}), so there is no probability to give; report: {}",
        t.total(),
        t.failed(),
        t.no_traction(),
        report.display()
    ))
}

/// The analysis's last line: the rows analysed in `secs` and where the report is.
pub fn analysed_line(a: &Analysis, secs: f64, report: &Path) -> String {
    format!(
        "analysed {} rows in {secs:.1} s; report: {}",
        a.info.rows,
        report.display()
    )
}

/// Where an analysis's report goes by default, beside its `first` input: `DIR/_report` for a
/// folder (the underscore keeps pyarrow and pandas from reading it, so `pd.read_parquet(DIR)`
/// still reads only the rows), `FILE.report` beside a file.
pub fn default_report_dir(first: &Path) -> PathBuf {
    if first.is_dir() {
        first.join("_report")
    } else {
        first.with_extension("report")
    }
}

/// The analysis in a few lines, as `analyze` and `explore` print it: failures first when they
/// are many, the samples present, the wear answer, then vibration, fleet and scenarios.
pub fn summary_lines(a: &Analysis) -> Vec<String> {
    let mut lines = Vec::new();
    let i = &a.info;
    print_failures(a, &mut lines);
    lines.push(format!(
        "{} of {} samples present ({} rows in {} files)",
        i.samples_present,
        i.samples,
        i.rows,
        i.files.len()
    ));
    if i.samples_present < i.samples {
        lines.push(format!(
            "  note: {} samples missing (chunks not in the inputs); the tables cover the samples present",
            i.samples - i.samples_present
        ));
    }
    print_wear(a, &mut lines);
    let weighted = a
        .fleet
        .as_ref()
        .map_or(String::new(), |f| format!(", {}", f.weight.words()));
    lines.push(format!(
        "P(vibration) over classified rows{weighted}, with 95% Wilson interval:"
    ));
    let v = &a.vibration;
    let occurrence: Vec<_> = v.occurrence.iter().map(|o| (f64::NAN, o)).collect();
    answer_words::occurrence_lines(&mut lines, &occurrence, i.params.drivetrain);
    let paired: Vec<_> = v.paired.iter().map(|p| (f64::NAN, p)).collect();
    answer_words::paired_lines(&mut lines, &paired);
    print_fleet(a, &mut lines);
    if !a.scenarios.is_empty() {
        lines.push(
            "What the changes do (paired on the same samples; 95% Newcombe interval):".to_string(),
        );
    }
    for e in &a.scenarios {
        let banded = a
            .band
            .as_ref()
            .and_then(|b| b.effect_of(e))
            .map_or(String::new(), |r| format!("; {}", band::points(r)));
        lines.push(format!(
            "  {} ({}, {}): {}{banded}",
            e.scenario,
            e.variant,
            e.outcome.name(),
            crate::render::scenarios::sentence(e)
        ));
    }
    for r in &a.robustness_summary {
        lines.push(format!(
            "  {:>8} lost digits: driving less exposed in {} of {} decodings ({:.1}%, 95% [{:.1}%, {:.1}%]); {} with too few samples",
            r.variant,
            r.driving_less,
            r.compared,
            100.0 * r.share,
            100.0 * r.lo,
            100.0 * r.hi,
            r.too_few
        ));
    }
    for n in &a.notes {
        lines.push(format!("  note: {n}"));
    }
    lines
}

/// The wear answer first: P(visible polygon within each distance) per wheel and the paired
/// comparison at each; one line where the run has no wear stage.
fn print_wear(a: &Analysis, lines: &mut Vec<String>) {
    let Some(w) = &a.wear else {
        lines.push("wear: the wear stage was left out of this run (--no-wear or `wear = false`); vibration only".to_string());
        return;
    };
    let (how, fitted) = (
        "over the tread's life at each sample's operating point, each speed's print saturated",
        "calibrated on these answers",
    );
    // The label says whose constants these are: the fitted ones, or the run's own (a study's
    // or --set's φ_s = 1 is no fit, and the band's sets replace it).
    let own = FittedConstants::of(&a.info.params);
    let drawn = a
        .info
        .drawn_names
        .iter()
        .any(|id| FittedConstants::PARAMS.contains(id));
    let departures = own.departures_from(&FittedConstants::of(&Params::default()));
    let fitted = if drawn {
        "drawn by the study, not the fitted constants".to_string()
    } else if departures.is_empty() {
        fitted.to_string()
    } else {
        let given: Vec<String> = departures
            .iter()
            .map(|(id, v, f)| format!("{id} = {} where the fit has {}", plain(*v, 6), plain(*f, 6)))
            .collect();
        format!(
            "as the run gives them, not the fitted constants: {}",
            given.join(", ")
        )
    };
    lines.push(format!(
        "P(visible polygonal wear within X km, before the tire is worn out), {how} (phi_s = {}, sigma_V = {} km/h, {fitted}), with 95% Wilson interval:",
        plain(w.share_straight, 6),
        plain(w.speed_spread_kmh, 6)
    ));
    let rows = w.occurrence_rows();
    let start = lines.len();
    answer_words::occurrence_lines(lines, &rows, a.info.params.drivetrain);
    let paired = w.paired_rows();
    let middle = lines.len();
    answer_words::paired_lines(lines, &paired);
    let Some(b) = &a.band else {
        lines.push(format!("  {}", band::NO_BAND));
        return;
    };
    for (line, (km, o)) in lines[start..middle].iter_mut().zip(&rows) {
        if let Some(r) = b.occurrence_of(o.variant, o.wheel, *km) {
            line.push_str(&format!("  ({})", band::percent(r)));
        }
    }
    for (line, (km, p)) in lines[middle..].iter_mut().zip(&paired) {
        if let Some(pb) = b.paired_of(p.variant, *km) {
            line.push_str(&format!("; {}", band::paired_words(pb, b.sets.len())));
        }
    }
    lines.push(format!("  calibration band: {}", band::about(b)));
}

/// When more than 1% of the rows have no verdict, the first thing printed: how many, and why.
fn print_failures(a: &Analysis, lines: &mut Vec<String>) {
    let f = &a.failures;
    if !f.loud() {
        return;
    }
    lines.push(format!(
        "WARNING: {} of {} rows ({:.1}%) have no verdict; every probability below is over the other {} only. Why:",
        f.unclassified,
        f.rows,
        100.0 * f.share(),
        f.rows - f.unclassified
    ));
    for g in &f.groups {
        lines.push(format!("  {:>9} {}: {}", g.rows, g.class, g.pattern));
    }
}

/// For a fleet run: how many operating points carry half of the fleet's risk, and which.
fn print_fleet(a: &Analysis, lines: &mut Vec<String>) {
    let Some(fleet) = &a.fleet else {
        return;
    };
    for variant in a.variants() {
        let rows: Vec<_> = fleet.rows.iter().filter(|r| r.variant == variant).collect();
        let Some((k, weight)) = crate::render::fleet::half_the_risk(&rows) else {
            continue;
        };
        let names: Vec<String> = rows[..k].iter().map(|r| r.row.to_string()).collect();
        lines.push(format!(
            "  {:>8} operating points: {k} of {} carry half of the fleet's risk (rows {}; {:.1}% of the {}); every row in fleet_rows.csv",
            variant,
            rows.len(),
            names.join(", "),
            100.0 * weight,
            fleet.weight.short()
        ));
    }
}
