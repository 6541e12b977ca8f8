//! Runs an analysis: the queries (queries.rs), then the tables (CSV and Parquet, written here),
//! the figures (figures.rs) and `report.md` (markdown.rs).

use std::path::{Path, PathBuf};

use super::figures;
use super::inputs::RunInfo;
use super::queries::{
    self, BinStat, ClassCounts, Occurrence, Paired, RiskMap, Robustness, RobustnessSummary,
    Sensitivity, Severity, SEVERITY_QUANTITIES,
};
use crate::classify::Class;
use crate::model::{Variant, Wheel};
use crate::parquet_out::{write_csv, write_table, Column};

/// Settings of one analysis.
#[derive(Debug, Clone)]
pub struct ReportOptions {
    /// Where the tables, figures and `report.md` go.
    pub out_dir: PathBuf,
    /// Bins per axis of the conditional probabilities.
    pub bins: usize,
    /// Bins per axis of the risk maps.
    pub map_bins: usize,
    /// Cells with fewer classified samples are shown as "too few", not as a probability.
    pub min_count: u64,
    /// Pairs of axes for risk maps (those absent from the run are skipped with a note).
    pub pairs: Vec<(String, String)>,
    /// Bootstrap resamples behind the Sobol indices' intervals.
    pub bootstrap: usize,
    /// File type of the figures: `png` or `svg` ([`crate::plot::backend::FORMATS`]).
    pub figure_format: &'static str,
}

impl ReportOptions {
    /// Default bins per axis of the conditional probabilities.
    pub const DEFAULT_BINS: usize = 20;
    /// Default bins per axis of the risk maps.
    pub const DEFAULT_MAP_BINS: usize = 24;
    /// Default smallest classified count of a shown cell.
    pub const DEFAULT_MIN_COUNT: u64 = 30;
    /// Default bootstrap resamples of the Sobol indices' intervals.
    pub const DEFAULT_BOOTSTRAP: usize = 200;

    /// The risk maps always drawn: speed × toe-in and load × pressure.
    pub fn default_pairs() -> Vec<(String, String)> {
        vec![
            ("speed_kmh".to_string(), "toe_deg".to_string()),
            ("load_n".to_string(), "pressure_kpa".to_string()),
        ]
    }

    /// The default settings, writing into `out_dir` (`explore`'s closing report).
    pub fn defaults(out_dir: PathBuf) -> Self {
        ReportOptions {
            out_dir,
            bins: Self::DEFAULT_BINS,
            map_bins: Self::DEFAULT_MAP_BINS,
            min_count: Self::DEFAULT_MIN_COUNT,
            pairs: Self::default_pairs(),
            bootstrap: Self::DEFAULT_BOOTSTRAP,
            figure_format: "png",
        }
    }
}

/// Everything computed, for the command's printed summary and the page.
pub struct Analysis {
    /// What the files' metadata says about the run.
    pub info: RunInfo,
    /// P(limit cycle) per variant and wheel.
    pub occurrence: Vec<Occurrence>,
    /// Driving against follower on the same samples, per variant.
    pub paired: Vec<Paired>,
    /// P(limit cycle) per bin of every drawn parameter.
    pub conditional: Vec<BinStat>,
    /// Risk maps over pairs of axes.
    pub maps: Vec<RiskMap>,
    /// Cycle quantities among the vibrating rows.
    pub severity: Vec<Severity>,
    /// Sobol indices (only for a Saltelli design).
    pub sensitivity: Option<Vec<Sensitivity>>,
    /// P(limit cycle) per lost-digit decoding (only when the study draws decodings).
    pub robustness: Option<Robustness>,
    /// How often the driving wheel is less exposed, per variant.
    pub robustness_summary: Vec<RobustnessSummary>,
    /// Remarks for the report (skipped pairs, missing samples, ...).
    pub notes: Vec<String>,
    /// Every file written.
    pub files: Vec<PathBuf>,
}

impl Analysis {
    /// Class counts over every variant and wheel.
    pub fn totals(&self) -> ClassCounts {
        let mut t = ClassCounts::default();
        for o in &self.occurrence {
            t.merge(&o.counts);
        }
        t
    }

    /// True when no row has a verdict (every row failed or had no traction).
    pub fn nothing_classified(&self) -> bool {
        self.totals().classified() == 0
    }
}

/// Rows of the paired comparison in a sample's outcome table use this many rows per file batch.
const PAIRED_BATCH_ROWS: u64 = 400_000;

/// Runs the whole analysis of checked inputs and writes it under `opts.out_dir`.
pub fn analyze(info: RunInfo, opts: &ReportOptions) -> Result<Analysis, String> {
    std::fs::create_dir_all(&opts.out_dir)
        .map_err(|e| format!("{}: {e}", opts.out_dir.display()))?;
    let dir = &opts.out_dir;
    let mut files = Vec::new();
    let mut notes = Vec::new();
    // The largest group-by: a risk map's cells for every variant and both wheels.
    let variants_in_run = info.variant.split(',').count().max(1);
    queries::size_group_tables(variants_in_run * 2 * opts.map_bins * opts.map_bins);
    let lf = queries::scan(&info.files)?;

    let occurrence = queries::occurrence(&lf)?;
    let paired = queries::paired(&info.files, PAIRED_BATCH_ROWS)?;
    let quantities: Vec<&str> = SEVERITY_QUANTITIES.iter().map(|q| q.0).collect();
    let ranges = queries::ranges(&lf, &info.drawn_names, &quantities)?;
    let mut conditional = Vec::new();
    for axis in &info.drawn_names {
        let bins = queries::axis_bins(&info, &ranges, axis, opts.bins);
        conditional.extend(queries::conditional(&lf, axis, &bins)?);
    }
    let mut maps = Vec::new();
    for (x, y) in &opts.pairs {
        if !info.drawn_names.contains(x) || !info.drawn_names.contains(y) {
            notes.push(format!(
                "risk map {x} × {y} skipped: the run does not draw both (it draws {})",
                info.drawn_names.join(", ")
            ));
            continue;
        }
        let xb = queries::axis_bins(&info, &ranges, x, opts.map_bins);
        let yb = queries::axis_bins(&info, &ranges, y, opts.map_bins);
        maps.extend(queries::risk_maps(&lf, x, y, &xb, &yb)?);
    }
    let severity = queries::severity(&lf, &ranges)?;
    let sensitivity = queries::sensitivity(&lf, &info, opts.bootstrap)?;
    let robustness = queries::robustness(&lf, &info)?;
    let robustness_summary = robustness
        .as_ref()
        .map(|r| r.summary(opts.min_count))
        .unwrap_or_default();
    let variants: Vec<Variant> = {
        let mut v: Vec<Variant> = occurrence.iter().map(|o| o.variant).collect();
        v.sort();
        v.dedup();
        v
    };
    if sensitivity.is_none() {
        notes.push("Sobol indices need a Saltelli design (`design = \"saltelli\"` in the study); this run used another.".into());
    }

    // Tables.
    let meta = table_metadata(&info, opts);
    write_tables(
        dir,
        "occurrence",
        &occurrence_columns(&occurrence),
        &meta,
        &mut files,
    )?;
    write_tables(dir, "paired", &paired_columns(&paired), &meta, &mut files)?;
    write_tables(
        dir,
        "conditional",
        &conditional_columns(&conditional, opts.min_count),
        &meta,
        &mut files,
    )?;
    for (x, y) in &opts.pairs {
        let of_pair: Vec<&RiskMap> = maps.iter().filter(|m| &m.x == x && &m.y == y).collect();
        if !of_pair.is_empty() {
            write_tables(
                dir,
                &format!("riskmap_{x}_{y}"),
                &riskmap_columns(&of_pair, opts.min_count),
                &meta,
                &mut files,
            )?;
        }
    }
    write_tables(
        dir,
        "severity",
        &severity_columns(&severity),
        &meta,
        &mut files,
    )?;
    if let Some(sens) = &sensitivity {
        write_tables(
            dir,
            "sensitivity",
            &sensitivity_columns(sens),
            &meta,
            &mut files,
        )?;
    }
    if let Some(r) = &robustness {
        write_tables(
            dir,
            "robustness",
            &robustness_columns(r, opts.min_count),
            &meta,
            &mut files,
        )?;
    }

    // Figures.
    let label = |name: &str| crate::params::axis_label(name, info.unit(name));
    let ext = opts.figure_format;
    for &variant in &variants {
        let p = dir.join(format!("conditional_{variant}.{ext}"));
        figures::conditional(
            &p,
            variant,
            &info.drawn_names,
            &label,
            &conditional,
            opts.min_count,
        )?;
        files.push(p);
    }
    let study = info.parsed_study();
    for map in &maps {
        let p = dir.join(format!("riskmap_{}_{}_{}.{ext}", map.x, map.y, map.variant));
        let nominal = study.as_ref().and_then(|s| {
            crate::chart::nominal_curves(
                s,
                map.variant,
                &map.x,
                &map.y,
                &figures::draw_edges(&map.x_bins),
                &figures::draw_edges(&map.y_bins),
            )
        });
        figures::risk_map(&p, map, &label, opts.min_count, nominal.as_deref())?;
        files.push(p);
    }
    for &variant in &variants {
        let p = dir.join(format!("severity_{variant}.{ext}"));
        figures::severity(&p, variant, &severity)?;
        files.push(p);
    }

    let mut analysis = Analysis {
        info,
        occurrence,
        paired,
        conditional,
        maps,
        severity,
        sensitivity,
        robustness,
        robustness_summary,
        notes,
        files,
    };
    let md = super::markdown::page(opts, &analysis);
    let p = dir.join("report.md");
    std::fs::write(&p, md).map_err(|e| format!("{}: {e}", p.display()))?;
    analysis.files.push(p);
    Ok(analysis)
}

/// Footer metadata of the Parquet tables: which run and settings they come from.
fn table_metadata(info: &RunInfo, opts: &ReportOptions) -> Vec<(String, String)> {
    vec![
        ("study_name".into(), info.study_name.clone()),
        ("study_hash".into(), info.study_hash.clone()),
        ("seed".into(), info.seed.clone()),
        ("variant".into(), info.variant.clone()),
        ("samples".into(), info.samples.to_string()),
        ("samples_present".into(), info.samples_present.to_string()),
        ("min_count".into(), opts.min_count.to_string()),
        (
            "polywear_version".into(),
            env!("CARGO_PKG_VERSION").to_string(),
        ),
    ]
}

/// Writes one table as `stem.csv` (RFC 4180) and `stem.parquet`.
fn write_tables(
    dir: &Path,
    stem: &str,
    cols: &[Column],
    meta: &[(String, String)],
    files: &mut Vec<PathBuf>,
) -> Result<(), String> {
    let csv = dir.join(format!("{stem}.csv"));
    write_csv(&csv, cols).map_err(|e| e.to_string())?;
    files.push(csv);
    let pq = dir.join(format!("{stem}.parquet"));
    write_table(&pq, cols, meta).map_err(|e| e.to_string())?;
    files.push(pq);
    Ok(())
}

fn count_col<T>(name: &str, rows: &[T], f: impl Fn(&T) -> u64) -> Column {
    Column::i64(name, "", rows.iter().map(|r| f(r) as i64).collect())
}

fn f64_col<T>(name: &str, rows: &[T], f: impl Fn(&T) -> f64) -> Column {
    Column::f64(name, "", rows.iter().map(f).collect())
}

fn str_col<T>(name: &str, rows: &[T], f: impl Fn(&T) -> String) -> Column {
    Column::str(name, rows.iter().map(f).collect())
}

/// The class-count columns every probability table carries: classified rows (`samples`),
/// vibrating rows, p with its Wilson interval, and the unclassified rows on their own.
fn class_columns<T>(rows: &[T], counts: impl Fn(&T) -> ClassCounts, min_count: u64) -> Vec<Column> {
    let c = |r: &T| counts(r);
    vec![
        count_col("samples", rows, |r| c(r).classified()),
        count_col("vibrating", rows, |r| c(r).vibrating()),
        f64_col("p", rows, |r| {
            if c(r).classified() >= min_count.max(1) {
                c(r).p()
            } else {
                f64::NAN
            }
        }),
        f64_col("wilson95_lo", rows, |r| c(r).wilson().0),
        f64_col("wilson95_hi", rows, |r| c(r).wilson().1),
        count_col(Class::Stable.as_str(), rows, |r| c(r).get(Class::Stable)),
        count_col(Class::LimitCycle.as_str(), rows, |r| {
            c(r).get(Class::LimitCycle)
        }),
        count_col(Class::Bistable.as_str(), rows, |r| {
            c(r).get(Class::Bistable)
        }),
        count_col(Class::NoTraction.as_str(), rows, |r| c(r).no_traction()),
        count_col(Class::Failed.as_str(), rows, |r| c(r).failed()),
    ]
}

fn occurrence_columns(o: &[Occurrence]) -> Vec<Column> {
    let mut cols = vec![
        str_col("variant", o, |x| x.variant.to_string()),
        str_col("wheel", o, |x| x.wheel.to_string()),
    ];
    cols.extend(class_columns(o, |x| x.counts, 1));
    cols
}

fn paired_columns(p: &[Paired]) -> Vec<Column> {
    vec![
        str_col("variant", p, |x| x.variant.to_string()),
        count_col("pairs", p, |x| x.pairs),
        count_col("only_follower", p, |x| x.only_follower),
        count_col("only_driving", p, |x| x.only_driving),
        count_col("both", p, |x| x.both),
        count_col("neither", p, |x| x.neither),
        count_col("unclassified_pairs", p, |x| x.unclassified),
        f64_col("mcnemar_chi2", p, |x| x.chi2),
        f64_col("p_value", p, |x| x.p_value),
        str_col("method", p, |x| x.method.to_string()),
    ]
}

fn conditional_columns(b: &[BinStat], min_count: u64) -> Vec<Column> {
    let mut cols = vec![
        str_col("variant", b, |x| x.variant.to_string()),
        str_col("wheel", b, |x| x.wheel.to_string()),
        str_col("axis", b, |x| x.axis.clone()),
        f64_col("bin_lo", b, |x| x.lo),
        f64_col("bin_hi", b, |x| x.hi),
        f64_col("bin_mid", b, |x| x.mid),
    ];
    cols.extend(class_columns(b, |x| x.counts, min_count));
    cols
}

fn riskmap_columns(maps: &[&RiskMap], min_count: u64) -> Vec<Column> {
    // (variant, wheel, x_lo, x_hi, y_lo, y_hi, counts)
    type Cell = (Variant, Wheel, f64, f64, f64, f64, ClassCounts);
    let mut rows: Vec<Cell> = Vec::new();
    for map in maps {
        for (wheel, grid) in &map.cells {
            for (ix, col) in grid.iter().enumerate() {
                for (iy, c) in col.iter().enumerate() {
                    let (xl, xh, _) = map.x_bins.range(ix);
                    let (yl, yh, _) = map.y_bins.range(iy);
                    rows.push((map.variant, *wheel, xl, xh, yl, yh, *c));
                }
            }
        }
    }
    let (x, y) = (&maps[0].x, &maps[0].y);
    let mut cols = vec![
        str_col("variant", &rows, |r| r.0.to_string()),
        str_col("wheel", &rows, |r| r.1.to_string()),
        f64_col(&format!("{x}_lo"), &rows, |r| r.2),
        f64_col(&format!("{x}_hi"), &rows, |r| r.3),
        f64_col(&format!("{y}_lo"), &rows, |r| r.4),
        f64_col(&format!("{y}_hi"), &rows, |r| r.5),
    ];
    cols.extend(class_columns(&rows, |r| r.6, min_count));
    cols
}

fn severity_columns(s: &[Severity]) -> Vec<Column> {
    vec![
        str_col("variant", s, |x| x.variant.to_string()),
        str_col("wheel", s, |x| x.wheel.to_string()),
        str_col("quantity", s, |x| x.quantity.to_string()),
        str_col("unit", s, |x| x.unit.to_string()),
        count_col("limit_cycles", s, |x| x.n),
        f64_col("mean", s, |x| x.mean),
        f64_col("q05", s, |x| x.quantiles[0]),
        f64_col("q25", s, |x| x.quantiles[1]),
        f64_col("median", s, |x| x.quantiles[2]),
        f64_col("q75", s, |x| x.quantiles[3]),
        f64_col("q95", s, |x| x.quantiles[4]),
    ]
}

fn sensitivity_columns(s: &[Sensitivity]) -> Vec<Column> {
    vec![
        str_col("variant", s, |x| x.variant.to_string()),
        str_col("wheel", s, |x| x.wheel.to_string()),
        str_col("output", s, |x| x.output.to_string()),
        str_col("param", s, |x| x.param.clone()),
        count_col("base_samples", s, |x| x.base_samples),
        f64_col("first_order", s, |x| x.s.0),
        f64_col("first_order_lo", s, |x| x.s.1),
        f64_col("first_order_hi", s, |x| x.s.2),
        f64_col("total", s, |x| x.st.0),
        f64_col("total_lo", s, |x| x.st.1),
        f64_col("total_hi", s, |x| x.st.2),
        count_col("base_samples_left_out", s, |x| x.left_out),
    ]
}

fn robustness_columns(r: &Robustness, min_count: u64) -> Vec<Column> {
    let d = &r.decodings;
    let mut cols = vec![str_col("variant", d, |x| x.variant.to_string())];
    for (i, p) in r.params.iter().enumerate() {
        cols.push(f64_col(p, d, |x| x.values[i]));
    }
    let enough = |x: &queries::Decoding| {
        x.follower.classified() >= min_count.max(1) && x.driving.classified() >= min_count.max(1)
    };
    cols.extend([
        count_col("follower_samples", d, |x| x.follower.classified()),
        count_col("follower_vibrating", d, |x| x.follower.vibrating()),
        f64_col("follower_p", d, |x| x.follower.p()),
        count_col("driving_samples", d, |x| x.driving.classified()),
        count_col("driving_vibrating", d, |x| x.driving.vibrating()),
        f64_col("driving_p", d, |x| x.driving.p()),
        count_col("unclassified", d, |x| {
            x.follower.total() - x.follower.classified() + x.driving.total()
                - x.driving.classified()
        }),
        str_col("driving_less_exposed", d, |x| {
            if !enough(x) {
                "too few samples".into()
            } else if x.driving.p() < x.follower.p() {
                "yes".into()
            } else {
                "no".into()
            }
        }),
    ]);
    cols
}
