//! The report's sections on how severe the vibration is (in µm, mm/s and µJ), which parameters
//! drive it (first-order indices from the rows of any design; Sobol indices of a Saltelli
//! design) and how robust the answer is to the paper's lost digits.

use std::fmt::Write as _;

use super::words::{pct, rel};
use super::Figures;
use crate::analysis::given_data::FirstOrder;
use crate::analysis::severity::{quantity, SEVERITY_FINE_BINS};
use crate::analysis::Analysis;
use polywear_core::wording::plain;

/// "How severe is it?": the severity quantiles of every quantity, in engineering units.
pub(crate) fn severity_section(s: &mut String, a: &Analysis, figures: &Figures) {
    let _ = writeln!(s, "\n## How severe is it?\n");
    let _ = writeln!(s, "Among the vibrating rows: the amplitude of the tread's lateral displacement and velocity (half peak-to-peak), the vibration energy friction feeds in per cycle (∮ C_s v² dt) and the polygon order (cycle frequency over wheel rotation frequency: the number of wear facets). Quantiles are read from a {SEVERITY_FINE_BINS}-bin histogram of each quantity (exact to 1/{SEVERITY_FINE_BINS} of its range). `severity.csv` holds the same in SI units (m, m/s, J).\n");
    let _ = writeln!(
        s,
        "| variant | wheel | quantity | vibrating rows | mean | 5% | median | 95% |"
    );
    let _ = writeln!(s, "|---|---|---|---:|---:|---:|---:|---:|");
    for v in &a.severity {
        let (label, scale) = quantity(v.quantity).map_or_else(
            || (format!("{} [{}]", v.quantity, v.unit), 1.0),
            |q| (q.label(), q.scale),
        );
        let shown = |x: f64| {
            if x.is_finite() {
                plain(x * scale, 4)
            } else {
                "n/a".into()
            }
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            v.variant,
            v.wheel,
            label,
            v.n,
            shown(v.mean),
            shown(v.quantiles[0]),
            shown(v.quantiles[2]),
            shown(v.quantiles[4])
        );
    }
    for (_, f) in &figures.severity {
        let _ = writeln!(s, "\n![]({})", rel(f));
    }
}

/// "Which parameters drive it?": first-order indices from the rows, then Sobol indices where
/// the design is Saltelli's.
pub(crate) fn drivers_section(s: &mut String, a: &Analysis) {
    let _ = writeln!(s, "\n## Which parameters drive it?\n");
    if !a.first_order_wear.is_empty() {
        let _ = writeln!(s, "### The wear outcome\n");
        let _ = writeln!(
            s,
            "The same first-order indices for the wear outcome: the indicator is 1 when the \
             wheel's polygon is visible within {} km, 0 when it is not (later, or never); rows \
             without wear figures are left out.\n",
            polywear_core::wording::thousands(a.options.scenario_within_km)
        );
        index_table(s, &a.first_order_wear);
        let _ = writeln!(s, "\n### Vibration\n");
    }
    first_order_section(s, a);
    match &a.sensitivity {
        Some(sens) if !sens.is_empty() => {
            let _ = writeln!(s, "\n### Sobol indices of the Saltelli design\n");
            let _ = writeln!(s, "First-order (S) and total (ST) Sobol indices, with percentile-bootstrap 95% intervals ({} resamples). Outputs: the vibration indicator (1 when the wheel vibrates) and the velocity amplitude in m/s (0 without a cycle). Base points with a missing or unclassified block are left out ({} here). Tables: `sensitivity.csv`, `sensitivity.parquet`.\n", a.options.bootstrap, sens.first().map_or(0, |x| x.left_out));
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
                "\nTotal indices (interactions included) need a run with `design = \"saltelli\"` \
                 in the study (docs/book/src/reference/analyze.md#analyze)."
            );
        }
    }
}

/// Whether an index is told apart from a parameter without influence: its interval lies
/// above the estimator's bias.
fn distinguishable(f: &FirstOrder) -> bool {
    f.s1 - f.conf > f.noise
}

fn first_order_section(s: &mut String, a: &Analysis) {
    if a.first_order.is_empty() {
        let _ = writeln!(s, "No classified rows to rank the parameters by.");
        return;
    }
    let _ = writeln!(
        s,
        "The first-order index S of a parameter is the share of the variance of the vibration \
         indicator (1 when the wheel vibrates, 0 when stable) that the parameter explains alone: \
         Var(E[vibrates | parameter]) / Var(vibrates). It is estimated from the rows already \
         there, whatever the design, by sorting them along the parameter into classes of equal \
         size (SALib's `delta` estimator of S1), with ±1.96 bootstrap standard deviations \
         ({} resamples). A parameter without influence still shows about (classes − 1) / rows, \
         the *noise* column; *within noise* marks an index whose interval reaches it. Tables: \
         `first_order.csv`, `first_order.parquet`.\n",
        a.options.bootstrap
    );
    if a.fleet.is_some() {
        let _ = writeln!(
            s,
            "The columns of the operating-point file move together: each of their indices also \
             carries the effect of the columns correlated with it.\n"
        );
    }
    index_table(s, &a.first_order);
}

/// The table of first-order indices, each variant and wheel's largest first.
fn index_table(s: &mut String, indices: &[FirstOrder]) {
    let _ = writeln!(
        s,
        "| variant | wheel | parameter | S | 95% interval | noise | rows |"
    );
    let _ = writeln!(s, "|---|---|---|---:|---|---:|---:|");
    let mut sorted: Vec<&FirstOrder> = indices.iter().collect();
    sorted.sort_by(|x, y| {
        (x.variant, x.wheel)
            .cmp(&(y.variant, y.wheel))
            .then(y.s1.total_cmp(&x.s1))
    });
    for f in sorted {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.3} – {:.3} | {:.4} | {} |",
            f.variant,
            f.wheel,
            f.param.label(),
            if distinguishable(f) {
                format!("{:.3}", f.s1)
            } else {
                format!("{:.3} (within noise)", f.s1)
            },
            (f.s1 - f.conf).max(0.0),
            f.s1 + f.conf,
            f.noise,
            f.rows
        );
    }
}

/// "Robustness to the lost digits": P(vibration) per wheel for each decoding of the paper's
/// lost digits, and for what share of decodings the driving wheel is less exposed.
pub(crate) fn robustness_section(s: &mut String, a: &Analysis) {
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
    let _ = writeln!(s, "\n## Robustness to the lost digits\n");
    let _ = writeln!(
        s,
        "The study draws {} with `levels`: each combination of levels is one *decoding* of the \
         paper's lost digits ({} decodings here). For each decoding, P(vibration) of both \
         wheels over its samples; the driving wheel counts as less exposed when its probability \
         is below the follower's. Decodings with fewer than {} classified samples on a wheel are \
         not compared. Table: `robustness.csv`, `robustness.parquet`.\n",
        r.params
            .iter()
            .map(|p| format!("`{p}`"))
            .collect::<Vec<_>>()
            .join(", "),
        r.decodings.len() / variants,
        a.options.min_count
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
    decodings_table(s, a);
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

/// The first decodings, one row each.
fn decodings_table(s: &mut String, a: &Analysis) {
    const SHOWN: usize = 60;
    let Some(r) = &a.robustness else {
        return;
    };
    let min_count = a.options.min_count;
    let _ = writeln!(
        s,
        "\n| variant | {} | follower P(vibration) | driving P(vibration) | driving less exposed |",
        r.params
            .iter()
            .map(|p| p.name())
            .collect::<Vec<_>>()
            .join(" | ")
    );
    let _ = writeln!(s, "|---|{}---:|---:|---|", "---:|".repeat(r.params.len()));
    for d in r.decodings.iter().take(SHOWN) {
        let verdict = if !d.comparable(min_count) {
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
                .map(|v| polywear_core::wording::plain(*v, 12))
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
}
