//! `report.md`: the page that ties the tables and figures together, in words. It leads with
//! what could make the numbers mislead (rows without a verdict, missing samples), then answers
//! in order: how likely, for which operating points (a fleet's rows), where, how severe, and
//! which parameters drive it. `VIBRATION_DEFINITION` says once what every probability is.

use std::fmt::Write as _;

use super::answer_words;
use super::drivers::{drivers_section, robustness_section, severity_section};
use super::fleet::fleet_section;
use super::words::{pct, rel};
use super::Figures;
use crate::analysis::Analysis;
use polywear_core::model::Variant;

/// What P(vibration) is, said once at the top of the page and the printed summary.
pub(crate) const VIBRATION_DEFINITION: &str = "**P(vibration)** is the share of classified rows \
    (stable, limit cycle or bistable) in which the wheel vibrates: its tread settles on a limit \
    cycle (self-excited vibration, the mechanism the wear model builds on: whether a vibrating \
    wheel wears a visible polygon is the wear answer's question) or is bistable (a kick puts it \
    on one). Rows that failed or have no traction are counted apart and left out.";

/// The report page, showing `figures`.
pub(crate) fn page(a: &Analysis, figures: &Figures) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Polygonal-wear risk: study `{}`\n", a.info.study_name);
    failures_block(&mut s, a);
    header(&mut s, a);
    super::wear::section(&mut s, a, figures);
    occurrence_section(&mut s, a);
    paired_section(&mut s, a);
    s.push_str(&super::scenarios::section(a, figures.scenarios.as_deref()));
    fleet_section(&mut s, a);
    where_section(&mut s, a, figures);
    robustness_section(&mut s, a);
    severity_section(&mut s, a, figures);
    drivers_section(&mut s, a);
    let _ = writeln!(
        s,
        "\n## The study\n\n```toml\n{}\n```",
        a.info.study_text.trim_end()
    );
    s
}

/// When more than 1% of the rows have no verdict: how many, and why, grouped by reason,
/// before any probability.
fn failures_block(s: &mut String, a: &Analysis) {
    let f = &a.failures;
    if !f.loud() {
        return;
    }
    let _ = writeln!(
        s,
        "> **{} of {} rows ({}) have no verdict.** Every probability below is over the other {} \
         rows only, which may be a different population from the one the study describes \
         (a unit mistake, such as a pressure in bar, leaves only the samples where the model \
         still holds). Why, by reason (numbers blanked as …):\n>",
        f.unclassified,
        f.rows,
        pct(f.share()),
        f.rows - f.unclassified
    );
    let _ = writeln!(s, "> | rows | class | reason | for example |");
    let _ = writeln!(s, "> |---:|---|---|---|");
    for g in &f.groups {
        let _ = writeln!(
            s,
            "> | {} | {} | {} | {} |",
            g.rows,
            g.class,
            g.pattern.replace('|', "\\|"),
            g.example.replace('|', "\\|")
        );
    }
    let _ = writeln!(s, "\nTable: `failures.csv`, `failures.parquet`.\n");
}

/// The run in one paragraph, the definition of P(vibration) and its weighting, and the notes
/// that qualify every table (missing samples, no verdict at all, the `paper` variant).
fn header(s: &mut String, a: &Analysis) {
    let i = &a.info;
    let _ = writeln!(
        s,
        "**{} of {} samples present** ({} rows in {} files) of study `{}`, design `{}`, seed {}, \
         friction variant(s) **{}**, polywear {}.\n",
        i.samples_present,
        i.samples,
        i.rows,
        i.files.len(),
        i.study_name,
        i.design,
        i.seed,
        i.variant_text(),
        i.version
    );
    let _ = write!(s, "{VIBRATION_DEFINITION}");
    match &a.fleet {
        Some(fleet) => {
            let _ = writeln!(
                s,
                " Here P(vibration) is {}: samples draw the operating points of `{}` in \
                 proportion to their weight.\n",
                fleet.weight.words(),
                fleet.file
            );
        }
        None => {
            let _ = writeln!(s, "\n");
        }
    }
    if i.samples_present < i.samples {
        let _ = writeln!(
            s,
            "> **{} samples are missing** (chunks not in the inputs: a run still going or killed, \
             or shards not given). Every table below is computed on the {} samples present.\n",
            i.samples - i.samples_present,
            i.samples_present
        );
    }
    let totals = a.totals();
    if a.nothing_classified() {
        let _ = writeln!(
            s,
            "> **No row has a verdict: all {} rows failed ({}) or had no traction ({}).** There is \
             no probability to give; see the `reason` column of the rows.\n",
            totals.total(),
            totals.failed(),
            totals.no_traction()
        );
    } else if totals.failed() + totals.no_traction() > 0 && !a.failures.loud() {
        let _ = writeln!(
            s,
            "> {} rows failed and {} had no traction (the driving wheel cannot transmit the drive \
             force). They are counted on their own in every table and left out of every \
             probability.\n",
            totals.failed(),
            totals.no_traction()
        );
    }
    if i.variants.contains(&Variant::Paper) {
        let _ = writeln!(
            s,
            "> Under the `paper` variant the driving wheel comes out almost identical to the follower: \
             the paper's Eq. 19 scales both friction levels by the same factor, so the drive force \
             barely moves the stability boundary. The `combined` variant (2-D LuGre) makes the \
             driving wheel far more stable. Read every driving-vs-follower comparison with its variant.\n"
        );
    }
}

fn occurrence_section(s: &mut String, a: &Analysis) {
    let _ = writeln!(s, "## How likely is self-excited vibration?\n");
    let rows: Vec<_> = a
        .vibration
        .occurrence
        .iter()
        .map(|o| (f64::NAN, o))
        .collect();
    answer_words::occurrence_table(s, &rows, false, a.info.params.drivetrain);
    let _ = writeln!(s, "\nTables: `occurrence.csv`, `occurrence.parquet`.\n");
}

fn paired_section(s: &mut String, a: &Analysis) {
    let _ = writeln!(s, "### Driving vs follower on the same samples\n");
    let rows: Vec<_> = a.vibration.paired.iter().map(|p| (f64::NAN, p)).collect();
    answer_words::paired_table(
        s,
        &rows,
        false,
        "a wheel unclassified",
        a.info.params.drivetrain,
    );
    let _ = writeln!(
        s,
        "\nMcNemar's test asks whether the discordant samples (one wheel vibrates, the other not) \
         split evenly; a small p-value means one wheel is significantly more exposed. Samples with \
         a failed or no-traction wheel are counted apart, not compared.\n"
    );
}

/// P(vibration) along each parameter, and the risk maps that have data.
fn where_section(s: &mut String, a: &Analysis, figures: &Figures) {
    let opts = &a.options;
    let _ = writeln!(s, "## Where does the risk live?\n");
    let _ = write!(s, "P(vibration) as a function of each drawn parameter ({} bins, or the study's levels), with 95% Wilson bands; bins with fewer than {} classified samples are left out. Tables: `conditional.csv`, `conditional.parquet`.", opts.bins, opts.min_count);
    if let Some(fleet) = &a.fleet {
        let _ = write!(
            s,
            " The columns of `{}` ({}) move together in the fleet's data: each point of their \
             curves averages the rows that share the value, so it mixes in the effect of the \
             other columns. The table above answers per operating point; the figure shows only \
             the parameters drawn per sample.",
            fleet.file,
            fleet.columns.join(", ")
        );
    }
    let _ = writeln!(s, "\n");
    for (_, f) in &figures.conditional {
        let _ = writeln!(s, "![]({})\n", rel(f));
    }
    let _ = writeln!(s, "### Risk maps\n");
    let _ = writeln!(s, "P(vibration) over pairs of axes, per wheel, and the driving-minus-follower difference. Grey cells hold fewer than {} classified samples: unknown, not zero. Tables: `riskmap_<x>_<y>.csv` and `.parquet`.\n", opts.min_count);
    for f in &figures.risk_maps {
        let _ = writeln!(s, "![]({})\n", rel(&f.path));
    }
    for m in &a.sparse_maps {
        let _ = writeln!(
            s,
            "- Risk map {} × {} ({}) not drawn: only {} of its {} cells hold {} or more \
             classified samples (`riskmap_{}_{}.csv` has them all).",
            m.x.label().to_lowercase(),
            m.y.label().to_lowercase(),
            m.variant,
            m.filled,
            m.cells,
            opts.min_count,
            m.x,
            m.y
        );
    }
    for n in &a.notes {
        let _ = writeln!(s, "- {n}");
    }
}
