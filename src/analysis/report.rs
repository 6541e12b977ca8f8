//! Writes the analysis: tables (CSV, Parquet), figures (PNG) and `report.md` tying them together.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::compute::{self, BinStat, Occurrence, Paired, RiskMap, Sensitivity, Severity};
use super::load::Dataset;
use crate::model::{Variant, Wheel};
use crate::parquet_out::{write_csv, write_table, Column};
use crate::plot::{self, maps, Series};

/// Settings of one analysis.
#[derive(Debug, Clone)]
pub struct ReportOptions {
    pub out_dir: PathBuf,
    /// Bins per axis of the conditional probabilities.
    pub bins: usize,
    /// Bins per axis of the risk maps.
    pub map_bins: usize,
    /// Cells with fewer samples are shown as "too few", not as a probability.
    pub min_count: u64,
    /// Pairs of axes for risk maps (those absent from the run are skipped with a note).
    pub pairs: Vec<(String, String)>,
    pub bootstrap: usize,
}

/// Everything computed, for the command's printed summary.
pub struct Analysis {
    pub occurrence: Vec<Occurrence>,
    pub paired: Vec<Paired>,
    pub conditional: Vec<BinStat>,
    pub maps: Vec<RiskMap>,
    pub severity: Vec<Severity>,
    pub sensitivity: Option<Vec<Sensitivity>>,
    pub notes: Vec<String>,
    pub files: Vec<PathBuf>,
}

fn label(name: &str, ds: &Dataset) -> String {
    let unit = ds.axis(name).map_or("", |a| a.unit.as_str());
    if unit.is_empty() || unit == "-" {
        name.to_string()
    } else {
        format!("{name} [{unit}]")
    }
}

/// Edges for drawing: bin edges, or cells centred on grid levels.
fn draw_edges(b: &compute::Bins) -> Vec<f64> {
    if !b.levels {
        return b.edges.clone();
    }
    let l = &b.edges;
    if l.len() == 1 {
        let w = (l[0].abs() * 0.05).max(1e-9);
        return vec![l[0] - w, l[0] + w];
    }
    let mut e = vec![l[0] - 0.5 * (l[1] - l[0])];
    e.extend(l.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    e.push(l[l.len() - 1] + 0.5 * (l[l.len() - 1] - l[l.len() - 2]));
    e
}

/// Runs the whole analysis and writes it under `opts.out_dir`.
pub fn analyze(ds: &Dataset, opts: &ReportOptions) -> Result<Analysis, String> {
    std::fs::create_dir_all(&opts.out_dir)
        .map_err(|e| format!("{}: {e}", opts.out_dir.display()))?;
    let dir = &opts.out_dir;
    let mut files = Vec::new();
    let mut notes = Vec::new();
    let w = |e: crate::parquet_out::WriteError| e.to_string();

    let occurrence = compute::occurrence(ds);
    let paired = compute::paired(ds);
    let conditional = compute::conditional(ds, opts.bins);
    let severity = compute::severity(ds);
    let sensitivity = compute::sensitivity(ds, opts.bootstrap);
    let variants: Vec<Variant> = {
        let mut v: Vec<Variant> = ds.groups().into_iter().map(|g| g.0).collect();
        v.dedup();
        v
    };

    // Occurrence and paired tables.
    let p = dir.join("occurrence.csv");
    write_csv(
        &p,
        &[
            Column::str(
                "variant",
                occurrence.iter().map(|o| o.variant.to_string()).collect(),
            ),
            Column::str(
                "wheel",
                occurrence.iter().map(|o| o.wheel.to_string()).collect(),
            ),
            Column::i64(
                "samples",
                "",
                occurrence.iter().map(|o| o.n as i64).collect(),
            ),
            Column::i64(
                "vibrating",
                "",
                occurrence.iter().map(|o| o.k as i64).collect(),
            ),
            Column::f64("p", "", occurrence.iter().map(|o| o.p).collect()),
            Column::f64("wilson95_lo", "", occurrence.iter().map(|o| o.lo).collect()),
            Column::f64("wilson95_hi", "", occurrence.iter().map(|o| o.hi).collect()),
        ],
    )
    .map_err(w)?;
    files.push(p);
    let p = dir.join("paired.csv");
    write_csv(
        &p,
        &[
            Column::str(
                "variant",
                paired.iter().map(|x| x.variant.to_string()).collect(),
            ),
            Column::i64("pairs", "", paired.iter().map(|x| x.pairs as i64).collect()),
            Column::i64(
                "only_follower",
                "",
                paired.iter().map(|x| x.only_follower as i64).collect(),
            ),
            Column::i64(
                "only_driving",
                "",
                paired.iter().map(|x| x.only_driving as i64).collect(),
            ),
            Column::i64("both", "", paired.iter().map(|x| x.both as i64).collect()),
            Column::i64(
                "neither",
                "",
                paired.iter().map(|x| x.neither as i64).collect(),
            ),
            Column::f64("mcnemar_chi2", "", paired.iter().map(|x| x.chi2).collect()),
            Column::f64("p_value", "", paired.iter().map(|x| x.p_value).collect()),
            Column::str(
                "method",
                paired.iter().map(|x| x.method.to_string()).collect(),
            ),
        ],
    )
    .map_err(w)?;
    files.push(p);

    // Conditional probabilities: table and one figure per variant.
    let p = dir.join("conditional.parquet");
    write_table(
        &p,
        &[
            Column::str(
                "variant",
                conditional.iter().map(|b| b.variant.to_string()).collect(),
            ),
            Column::str(
                "wheel",
                conditional.iter().map(|b| b.wheel.to_string()).collect(),
            ),
            Column::str("axis", conditional.iter().map(|b| b.axis.clone()).collect()),
            Column::f64("bin_lo", "", conditional.iter().map(|b| b.lo).collect()),
            Column::f64("bin_hi", "", conditional.iter().map(|b| b.hi).collect()),
            Column::f64("bin_mid", "", conditional.iter().map(|b| b.mid).collect()),
            Column::i64(
                "samples",
                "",
                conditional.iter().map(|b| b.n as i64).collect(),
            ),
            Column::i64(
                "vibrating",
                "",
                conditional.iter().map(|b| b.k as i64).collect(),
            ),
            Column::f64("p", "", conditional.iter().map(|b| b.p).collect()),
            Column::f64(
                "wilson95_lo",
                "",
                conditional.iter().map(|b| b.ci_lo).collect(),
            ),
            Column::f64(
                "wilson95_hi",
                "",
                conditional.iter().map(|b| b.ci_hi).collect(),
            ),
        ],
        &[("study_name".into(), ds.info.study_name.clone())],
    )
    .map_err(w)?;
    files.push(p);
    for &variant in &variants {
        let axes: Vec<&str> = ds.axes.iter().map(|a| a.name.as_str()).collect();
        let cols = if axes.len() <= 4 { 2 } else { 3 };
        let rows = axes.len().div_ceil(cols);
        let p = dir.join(format!("conditional_{variant}.png"));
        plot::panels(
            &p,
            (520 * cols as u32, 360 * rows as u32 + 40),
            (rows, cols),
            &format!("P(limit cycle | parameter), {variant} variant, 95% Wilson bands"),
            |i, area| {
                let Some(axis) = axes.get(i) else {
                    return Ok(());
                };
                let bands: Vec<maps::Band<'_>> = Wheel::BOTH
                    .iter()
                    .map(|wh| maps::Band {
                        label: wh.as_str(),
                        points: conditional
                            .iter()
                            .filter(|b| {
                                b.variant == variant
                                    && b.wheel == *wh
                                    && b.axis == *axis
                                    && b.n >= opts.min_count.max(1)
                            })
                            .map(|b| (b.mid, b.p, b.ci_lo, b.ci_hi))
                            .collect(),
                    })
                    .collect();
                maps::band_panel(area, axis, &label(axis, ds), "P(limit cycle)", &bands)
            },
        )?;
        files.push(p);
    }

    // Risk maps.
    let mut risk_maps = Vec::new();
    for (x, y) in &opts.pairs {
        if ds.axis(x).is_none() || ds.axis(y).is_none() {
            notes.push(format!(
                "risk map {x} × {y} skipped: the run does not draw both (it draws {})",
                ds.info.drawn_names.join(", ")
            ));
            continue;
        }
        for &variant in &variants {
            let map = compute::risk_map(ds, variant, x, y, opts.map_bins)?;
            let (xe, ye) = (draw_edges(&map.x_bins), draw_edges(&map.y_bins));
            let pf = map.probability(Wheel::Follower, opts.min_count);
            let pd = map.probability(Wheel::Driving, opts.min_count);
            let diff: Vec<Vec<f64>> = pd
                .iter()
                .zip(&pf)
                .map(|(a, b)| a.iter().zip(b).map(|(d, f)| d - f).collect())
                .collect();
            let max_abs = diff
                .iter()
                .flatten()
                .filter(|v| v.is_finite())
                .fold(0.0f64, |m, v| m.max(v.abs()))
                .max(1e-3);
            let png = dir.join(format!("riskmap_{x}_{y}_{variant}.png"));
            let title = format!(
                "Risk of polygonal wear: P(limit cycle) over {x} × {y} ({variant} variant; grey: fewer than {} samples)",
                opts.min_count
            );
            plot::figure(&png, (1900, 620), &title, |area| {
                let parts = area.split_evenly((1, 3));
                for (k, (part, (name, values))) in parts
                    .iter()
                    .zip([
                        ("follower", &pf),
                        ("driving", &pd),
                        ("driving − follower", &diff),
                    ])
                    .enumerate()
                {
                    let (main, bar) = part.split_horizontally(part.dim_in_pixel().0 as i32 - 100);
                    let (range, cmap, bar_label): ((f64, f64), maps::ColorMap, &str) = if k < 2 {
                        ((0.0, 1.0), maps::viridis, "P(limit cycle)")
                    } else {
                        ((-max_abs, max_abs), maps::diverging, "difference")
                    };
                    maps::heatmap(
                        &main,
                        name,
                        &label(x, ds),
                        &label(y, ds),
                        &xe,
                        &ye,
                        values,
                        range,
                        cmap,
                    )?;
                    maps::colorbar(&bar, bar_label, range, cmap)?;
                }
                Ok(())
            })?;
            files.push(png);
            risk_maps.push(map);
        }
        // Table of all variants and wheels of this pair.
        // (variant, wheel, x_lo, x_hi, y_lo, y_hi, samples, vibrating)
        type CellRow = (String, String, f64, f64, f64, f64, u64, u64);
        let mut rows: Vec<CellRow> = Vec::new();
        for map in risk_maps.iter().filter(|m| &m.x == x && &m.y == y) {
            for (wheel, grid) in &map.cells {
                for (ix, col) in grid.iter().enumerate() {
                    for (iy, (n, k)) in col.iter().enumerate() {
                        let (xl, xh, _) = map.x_bins.range(ix);
                        let (yl, yh, _) = map.y_bins.range(iy);
                        rows.push((
                            map.variant.to_string(),
                            wheel.to_string(),
                            xl,
                            xh,
                            yl,
                            yh,
                            *n,
                            *k,
                        ));
                    }
                }
            }
        }
        let p = dir.join(format!("riskmap_{x}_{y}.parquet"));
        let min_count = opts.min_count.max(1);
        write_table(
            &p,
            &[
                Column::str("variant", rows.iter().map(|r| r.0.clone()).collect()),
                Column::str("wheel", rows.iter().map(|r| r.1.clone()).collect()),
                Column::f64(format!("{x}_lo"), "", rows.iter().map(|r| r.2).collect()),
                Column::f64(format!("{x}_hi"), "", rows.iter().map(|r| r.3).collect()),
                Column::f64(format!("{y}_lo"), "", rows.iter().map(|r| r.4).collect()),
                Column::f64(format!("{y}_hi"), "", rows.iter().map(|r| r.5).collect()),
                Column::i64("samples", "", rows.iter().map(|r| r.6 as i64).collect()),
                Column::i64("vibrating", "", rows.iter().map(|r| r.7 as i64).collect()),
                Column::f64(
                    "p",
                    "",
                    rows.iter()
                        .map(|r| {
                            if r.6 >= min_count {
                                r.7 as f64 / r.6 as f64
                            } else {
                                f64::NAN
                            }
                        })
                        .collect(),
                ),
            ],
            &[
                ("min_count".into(), opts.min_count.to_string()),
                ("study_name".into(), ds.info.study_name.clone()),
            ],
        )
        .map_err(w)?;
        files.push(p);
    }

    // Severity: quantile table and histograms.
    let p = dir.join("severity.csv");
    let q = |i: usize| {
        severity
            .iter()
            .map(|s| s.quantiles[i])
            .collect::<Vec<f64>>()
    };
    write_csv(
        &p,
        &[
            Column::str(
                "variant",
                severity.iter().map(|s| s.variant.to_string()).collect(),
            ),
            Column::str(
                "wheel",
                severity.iter().map(|s| s.wheel.to_string()).collect(),
            ),
            Column::str(
                "quantity",
                severity.iter().map(|s| s.quantity.to_string()).collect(),
            ),
            Column::str(
                "unit",
                severity.iter().map(|s| s.unit.to_string()).collect(),
            ),
            Column::i64(
                "limit_cycles",
                "",
                severity.iter().map(|s| s.n as i64).collect(),
            ),
            Column::f64("mean", "", severity.iter().map(|s| s.mean).collect()),
            Column::f64("q05", "", q(0)),
            Column::f64("q25", "", q(1)),
            Column::f64("median", "", q(2)),
            Column::f64("q75", "", q(3)),
            Column::f64("q95", "", q(4)),
        ],
    )
    .map_err(w)?;
    files.push(p);
    for &variant in &variants {
        let quantities = [
            "amp_y_m",
            "amp_v_mps",
            "energy_per_cycle_j",
            "polygon_order",
        ];
        let p = dir.join(format!("severity_{variant}.png"));
        plot::panels(
            &p,
            (1400, 900),
            (2, 2),
            &format!("Severity among limit cycles ({variant} variant): share of cycles per bin"),
            |i, area| {
                let quantity = quantities[i];
                let sets: Vec<&Severity> = severity
                    .iter()
                    .filter(|s| s.variant == variant && s.quantity == quantity)
                    .collect();
                let all: Vec<f64> = sets.iter().flat_map(|s| s.values.iter().cloned()).collect();
                if all.is_empty() {
                    return plot::line_panel(
                        area,
                        &format!("{quantity}: no limit cycles"),
                        quantity,
                        "share",
                        &[],
                        false,
                    );
                }
                let bins = compute::Bins::new(&all, 40);
                let series: Vec<Series<'_>> = sets
                    .iter()
                    .map(|s| {
                        let mut counts = vec![0u64; bins.count()];
                        for v in &s.values {
                            if let Some(b) = bins.index(*v) {
                                counts[b] += 1;
                            }
                        }
                        let n = s.values.len().max(1) as f64;
                        let points = counts
                            .iter()
                            .enumerate()
                            .flat_map(|(b, c)| {
                                let (lo, hi, mid) = bins.range(b);
                                if bins.levels {
                                    vec![(mid, *c as f64 / n)]
                                } else {
                                    vec![(lo, *c as f64 / n), (hi, *c as f64 / n)]
                                }
                            })
                            .collect();
                        Series {
                            label: s.wheel.as_str(),
                            points,
                        }
                    })
                    .collect();
                let unit = sets.first().map_or("", |s| s.unit);
                plot::line_panel(
                    area,
                    quantity,
                    &format!("{quantity} [{unit}]"),
                    "share of limit cycles",
                    &series,
                    false,
                )
            },
        )?;
        files.push(p);
    }

    // Sensitivity.
    if let Some(sens) = &sensitivity {
        let p = dir.join("sensitivity.csv");
        write_csv(
            &p,
            &[
                Column::str(
                    "variant",
                    sens.iter().map(|s| s.variant.to_string()).collect(),
                ),
                Column::str("wheel", sens.iter().map(|s| s.wheel.to_string()).collect()),
                Column::str(
                    "output",
                    sens.iter().map(|s| s.output.to_string()).collect(),
                ),
                Column::str("param", sens.iter().map(|s| s.param.clone()).collect()),
                Column::i64(
                    "base_samples",
                    "",
                    sens.iter().map(|s| s.base_samples as i64).collect(),
                ),
                Column::f64("first_order", "", sens.iter().map(|s| s.s.0).collect()),
                Column::f64("first_order_lo", "", sens.iter().map(|s| s.s.1).collect()),
                Column::f64("first_order_hi", "", sens.iter().map(|s| s.s.2).collect()),
                Column::f64("total", "", sens.iter().map(|s| s.st.0).collect()),
                Column::f64("total_lo", "", sens.iter().map(|s| s.st.1).collect()),
                Column::f64("total_hi", "", sens.iter().map(|s| s.st.2).collect()),
            ],
        )
        .map_err(w)?;
        files.push(p);
    } else {
        notes.push("Sobol indices need a Saltelli design (`design = \"saltelli\"` in the study); this run used another.".into());
    }

    let analysis = Analysis {
        occurrence,
        paired,
        conditional,
        maps: risk_maps,
        severity,
        sensitivity,
        notes,
        files,
    };
    let md = markdown(ds, opts, &analysis);
    let p = dir.join("report.md");
    std::fs::write(&p, md).map_err(|e| format!("{}: {e}", p.display()))?;
    let mut analysis = analysis;
    analysis.files.push(p);
    Ok(analysis)
}

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

/// The report page.
fn markdown(ds: &Dataset, opts: &ReportOptions, a: &Analysis) -> String {
    let mut s = String::new();
    let i = &ds.info;
    let _ = writeln!(s, "# Polygonal-wear risk: study `{}`\n", i.study_name);
    let samples = ds
        .sample_id
        .iter()
        .collect::<std::collections::HashSet<_>>()
        .len();
    let _ = writeln!(
        s,
        "{} samples ({} rows in {} files) of study `{}`, design `{}`, seed {}, friction variant(s) **{}**, \
         polywear {}. A wheel *vibrates* when its tread settles on a limit cycle (self-excited \
         vibration, the cause of polygonal wear) or can be kicked onto one (bistable).\n",
        samples,
        ds.len(),
        i.files,
        i.study_name,
        i.design,
        i.seed,
        i.variant,
        i.version
    );
    if i.variant.contains("paper") {
        let _ = writeln!(
            s,
            "> Under the `paper` variant the driving wheel comes out almost identical to the follower: \
             the paper's Eq. 19 scales both friction levels by the same factor, so the drive force \
             barely moves the stability boundary. The `combined` variant (2-D LuGre) makes the \
             driving wheel far more stable. Read every driving-vs-follower comparison with its variant.\n"
        );
    }
    let _ = writeln!(s, "## How likely is self-excited vibration?\n");
    let _ = writeln!(s, "| variant | wheel | samples | vibrating | P(limit cycle) | 95% Wilson interval | other classes |");
    let _ = writeln!(s, "|---|---|---:|---:|---:|---|---|");
    for o in &a.occurrence {
        let others: Vec<String> = o
            .counts
            .iter()
            .filter(|(c, _)| !c.vibrates())
            .map(|(c, n)| format!("{} {n}", c.as_str()))
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} – {} | {} |",
            o.variant,
            o.wheel,
            o.n,
            o.k,
            pct(o.p),
            pct(o.lo),
            pct(o.hi),
            others.join(", ")
        );
    }
    let _ = writeln!(s, "\n### Driving vs follower on the same samples\n");
    let _ = writeln!(
        s,
        "| variant | pairs | only follower | only driving | both | neither | McNemar p-value |"
    );
    let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|---:|");
    for p in &a.paired {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} ({}) |",
            p.variant,
            p.pairs,
            p.only_follower,
            p.only_driving,
            p.both,
            p.neither,
            super::stats::format_p(p.p_value),
            p.method
        );
    }
    let _ = writeln!(
        s,
        "\nMcNemar's test asks whether the discordant samples (one wheel vibrates, the other not) \
         split evenly; a small p-value means one wheel is significantly more exposed.\n"
    );
    let _ = writeln!(s, "## Where does the risk live?\n");
    let _ = writeln!(s, "Probability of a limit cycle as a function of each drawn parameter ({} bins, or the grid's levels), with 95% Wilson bands; bins with fewer than {} samples are left out. Table: `conditional.parquet`.\n", opts.bins, opts.min_count);
    for f in a
        .files
        .iter()
        .filter(|f| rel(f).starts_with("conditional_"))
    {
        let _ = writeln!(s, "![]({})\n", rel(f));
    }
    let _ = writeln!(s, "### Risk maps\n");
    let _ = writeln!(s, "P(limit cycle) over pairs of axes, per wheel, and the driving-minus-follower difference. Grey cells hold fewer than {} samples: unknown, not zero. Tables: `riskmap_<x>_<y>.parquet`.\n", opts.min_count);
    for f in a
        .files
        .iter()
        .filter(|f| rel(f).starts_with("riskmap_") && rel(f).ends_with(".png"))
    {
        let _ = writeln!(s, "![]({})\n", rel(f));
    }
    for n in &a.notes {
        let _ = writeln!(s, "- {n}");
    }
    let _ = writeln!(s, "\n## How severe is it?\n");
    let _ = writeln!(s, "Among the limit cycles: amplitude of the lateral displacement and velocity (half peak-to-peak), vibration energy per cycle (∮ C_s v² dt) and polygon order (cycle frequency over wheel rotation frequency: the number of wear facets).\n");
    let _ = writeln!(
        s,
        "| variant | wheel | quantity | cycles | mean | 5% | median | 95% |"
    );
    let _ = writeln!(s, "|---|---|---|---:|---:|---:|---:|---:|");
    for v in &a.severity {
        let _ = writeln!(
            s,
            "| {} | {} | {} [{}] | {} | {:.4e} | {:.4e} | {:.4e} | {:.4e} |",
            v.variant,
            v.wheel,
            v.quantity,
            v.unit,
            v.n,
            v.mean,
            v.quantiles[0],
            v.quantiles[2],
            v.quantiles[4]
        );
    }
    for f in a
        .files
        .iter()
        .filter(|f| rel(f).starts_with("severity_") && rel(f).ends_with(".png"))
    {
        let _ = writeln!(s, "\n![]({})", rel(f));
    }
    let _ = writeln!(s, "\n## Which parameters drive it?\n");
    match &a.sensitivity {
        Some(sens) if !sens.is_empty() => {
            let _ = writeln!(s, "First-order (S) and total (ST) Sobol indices from the Saltelli design, with percentile-bootstrap 95% intervals ({} resamples). Outputs: the limit-cycle indicator and the velocity amplitude (0 without a cycle).\n", opts.bootstrap);
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
                "Sobol indices need a run with `design = \"saltelli\"` in the study (see README)."
            );
        }
    }
    let _ = writeln!(s, "\n## The study\n\n```toml\n{}\n```", i.study.trim_end());
    s
}
