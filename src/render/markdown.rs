//! `report.md`: the page that ties the tables and figures together, in words.

use std::fmt::Write as _;
use std::path::Path;

use super::Figures;
use crate::analysis::severity::SEVERITY_FINE_BINS;
use crate::analysis::stats::format_p;
use crate::analysis::Analysis;
use crate::classify::Class;
use crate::model::Variant;
use crate::wording::plain;

fn pct(p: f64) -> String {
    if p.is_finite() {
        format!("{:.2}%", 100.0 * p)
    } else {
        "–".into()
    }
}

fn rel(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The report page, showing `figures`.
pub fn page(a: &Analysis, figures: &Figures) -> String {
    let mut s = String::new();
    let i = &a.info;
    let opts = &a.options;
    let _ = writeln!(s, "# Polygonal-wear risk: study `{}`\n", i.study_name);
    let _ = writeln!(
        s,
        "**{} of {} samples present** ({} rows in {} files) of study `{}`, design `{}`, seed {}, \
         friction variant(s) **{}**, polywear {}. A wheel *vibrates* when its tread settles on a \
         limit cycle (self-excited vibration, the cause of polygonal wear) or can be kicked onto \
         one (bistable).\n",
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
    } else if totals.failed() + totals.no_traction() > 0 {
        let _ = writeln!(
            s,
            "> {} rows failed and {} had no traction (the driving wheel cannot transmit the drive \
             force). They are counted on their own in every table and left out of every \
             probability, which is over the classified rows (stable, limit cycle, bistable).\n",
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
    let _ = writeln!(s, "## How likely is self-excited vibration?\n");
    let _ = writeln!(
        s,
        "| variant | wheel | classified | vibrating | P(limit cycle) | 95% Wilson interval | stable | no traction | failed |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---|---:|---:|---:|");
    for o in &a.occurrence {
        let (lo, hi) = o.counts.wilson();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} – {} | {} | {} | {} |",
            o.variant,
            o.wheel,
            o.counts.classified(),
            o.counts.vibrating(),
            pct(o.p()),
            pct(lo),
            pct(hi),
            o.counts.get(Class::Stable),
            o.counts.no_traction(),
            o.counts.failed()
        );
    }
    let _ = writeln!(s, "\nTables: `occurrence.csv`, `occurrence.parquet`.\n");
    let _ = writeln!(s, "### Driving vs follower on the same samples\n");
    let _ = writeln!(
        s,
        "| variant | pairs | only follower | only driving | both | neither | a wheel unclassified | McNemar p-value |"
    );
    let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|---:|---:|");
    for p in &a.paired {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} ({}) |",
            p.variant,
            p.pairs,
            p.only_follower,
            p.only_driving,
            p.both,
            p.neither,
            p.unclassified,
            format_p(p.p_value),
            p.method
        );
    }
    let _ = writeln!(
        s,
        "\nMcNemar's test asks whether the discordant samples (one wheel vibrates, the other not) \
         split evenly; a small p-value means one wheel is significantly more exposed. Samples with \
         a failed or no-traction wheel are counted apart, not compared.\n"
    );
    s.push_str(&super::scenarios::section(a, figures.scenarios.as_deref()));
    let _ = writeln!(s, "## Where does the risk live?\n");
    let _ = writeln!(s, "Probability of a limit cycle as a function of each drawn parameter ({} bins, or the study's levels), with 95% Wilson bands; bins with fewer than {} classified samples are left out. Tables: `conditional.csv`, `conditional.parquet`.\n", opts.bins, opts.min_count);
    for (_, f) in &figures.conditional {
        let _ = writeln!(s, "![]({})\n", rel(f));
    }
    let _ = writeln!(s, "### Risk maps\n");
    let _ = writeln!(s, "P(limit cycle) over pairs of axes, per wheel, and the driving-minus-follower difference. Grey cells hold fewer than {} classified samples: unknown, not zero. Tables: `riskmap_<x>_<y>.csv` and `.parquet`.\n", opts.min_count);
    for f in &figures.risk_maps {
        let _ = writeln!(s, "![]({})\n", rel(&f.path));
    }
    for n in &a.notes {
        let _ = writeln!(s, "- {n}");
    }
    robustness_section(&mut s, a);
    let _ = writeln!(s, "\n## How severe is it?\n");
    let _ = writeln!(s, "Among the limit cycles: amplitude of the lateral displacement and velocity (half peak-to-peak), vibration energy per cycle (∮ C_s v² dt) and polygon order (cycle frequency over wheel rotation frequency: the number of wear facets). Quantiles are read from a {}-bin histogram of each quantity (exact to 1/{} of its range).\n", SEVERITY_FINE_BINS, SEVERITY_FINE_BINS);
    let _ = writeln!(
        s,
        "| variant | wheel | quantity | cycles | mean | 5% | median | 95% |"
    );
    let _ = writeln!(s, "|---|---|---|---:|---:|---:|---:|---:|");
    for v in &a.severity {
        let _ = writeln!(
            s,
            "| {} | {} | {} [{}] | {} | {} | {} | {} | {} |",
            v.variant,
            v.wheel,
            v.quantity,
            v.unit,
            v.n,
            plain(v.mean, 4),
            plain(v.quantiles[0], 4),
            plain(v.quantiles[2], 4),
            plain(v.quantiles[4], 4)
        );
    }
    for (_, f) in &figures.severity {
        let _ = writeln!(s, "\n![]({})", rel(f));
    }
    let _ = writeln!(s, "\n## Which parameters drive it?\n");
    match &a.sensitivity {
        Some(sens) if !sens.is_empty() => {
            let _ = writeln!(s, "First-order (S) and total (ST) Sobol indices from the Saltelli design, with percentile-bootstrap 95% intervals ({} resamples). Outputs: the limit-cycle indicator and the velocity amplitude (0 without a cycle). Base points with a missing or unclassified block are left out ({} here).\n", opts.bootstrap, sens.first().map_or(0, |x| x.left_out));
            let _ = writeln!(
                s,
                "| variant | wheel | output | parameter | S | S 95% | ST | ST 95% |"
            );
            let _ = writeln!(s, "|---|---|---|---|---:|---|---:|---|");
            for x in sens {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {:.3} | {:.3} – {:.3} | {:.3} | {:.3} – {:.3} |",
                    x.variant,
                    x.wheel,
                    x.output,
                    x.param,
                    x.s.0,
                    x.s.1,
                    x.s.2,
                    x.st.0,
                    x.st.1,
                    x.st.2
                );
            }
        }
        _ => {
            let _ = writeln!(
                s,
                "Sobol indices need a run with `design = \"saltelli\"` in the study (see GUIDE.md#analyze)."
            );
        }
    }
    let _ = writeln!(
        s,
        "\n## The study\n\n```toml\n{}\n```",
        i.study_text.trim_end()
    );
    s
}

/// "Robustness to the lost digits": P(limit cycle) per wheel for each decoding of the paper's
/// lost digits, and for what share of decodings the driving wheel is less exposed.
fn robustness_section(s: &mut String, a: &Analysis) {
    let opts = &a.options;
    let Some(r) = &a.robustness else {
        return;
    };
    let variants = r
        .decodings
        .iter()
        .map(|d| d.variant)
        .collect::<std::collections::BTreeSet<_>>()
        .len()
        .max(1);
    let per_variant = r.decodings.len() / variants;
    let _ = writeln!(s, "\n## Robustness to the lost digits\n");
    let _ = writeln!(
        s,
        "The study draws {} with `levels`: each combination of levels is one *decoding* of the \
         paper's lost digits ({} decodings here). For each decoding, P(limit cycle) of both \
         wheels over its samples; the driving wheel counts as less exposed when its probability \
         is below the follower's. Decodings with fewer than {} classified samples on a wheel are \
         not compared. Table: `robustness.csv`, `robustness.parquet`.\n",
        r.params
            .iter()
            .map(|p| format!("`{p}`"))
            .collect::<Vec<_>>()
            .join(", "),
        per_variant,
        opts.min_count
    );
    let _ = writeln!(
        s,
        "| variant | decodings | compared | driving less exposed | share | 95% Wilson interval (over decodings) | too few samples |"
    );
    let _ = writeln!(s, "|---|---:|---:|---:|---:|---|---:|");
    for x in &a.robustness_summary {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} – {} | {} |",
            x.variant,
            x.decodings,
            x.compared,
            x.driving_less,
            pct(x.share),
            pct(x.lo),
            pct(x.hi),
            x.too_few
        );
    }
    const SHOWN: usize = 60;
    let _ = writeln!(
        s,
        "\n| variant | {} | follower P(limit cycle) | driving P(limit cycle) | driving less exposed |",
        r.params
            .iter()
            .map(|p| p.name())
            .collect::<Vec<_>>()
            .join(" | ")
    );
    let _ = writeln!(s, "|---|{}---:|---:|---|", "---:|".repeat(r.params.len()));
    for d in r.decodings.iter().take(SHOWN) {
        let verdict = if !d.comparable(opts.min_count) {
            "too few samples"
        } else if d.driving_less_exposed() {
            "yes"
        } else {
            "no"
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} ({} of {}) | {} ({} of {}) | {} |",
            d.variant,
            d.values
                .iter()
                .map(|v| format!("{v}"))
                .collect::<Vec<_>>()
                .join(" | "),
            pct(d.follower.p()),
            d.follower.vibrating(),
            d.follower.classified(),
            pct(d.driving.p()),
            d.driving.vibrating(),
            d.driving.classified(),
            verdict
        );
    }
    if r.decodings.len() > SHOWN {
        let _ = writeln!(
            s,
            "\n({} more decodings in `robustness.csv`.)",
            r.decodings.len() - SHOWN
        );
    }
    for x in &a.robustness_summary {
        let _ = writeln!(
            s,
            "\n**{}**: the driving wheel is less exposed than the follower in {} of {} decodings \
             ({}, 95% interval {} – {}).{}",
            x.variant,
            x.driving_less,
            x.compared,
            pct(x.share),
            pct(x.lo),
            pct(x.hi),
            if x.too_few > 0 {
                format!(
                    " {} decodings have too few samples to compare; more samples would settle them.",
                    x.too_few
                )
            } else {
                String::new()
            }
        );
    }
}
