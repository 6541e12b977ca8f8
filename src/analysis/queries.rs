//! The analysis as polars lazy queries on the streaming engine: every table is a group-by over
//! the chunk files that returns a few hundred rows at most, so memory does not grow with the
//! number of rows. Only these small tables come back to Rust, for the intervals and tests
//! (stats.rs), the figures (figures.rs) and the page (markdown.rs).
//!
//! Classes: a wheel *vibrates* when it settles on a limit cycle or is bistable. Rows that
//! `failed` or have `no_traction` are counted on their own and never folded in: probabilities
//! are over the classified rows (stable, limit cycle, bistable).

use std::collections::BTreeMap;
use std::path::PathBuf;

use polars::prelude::*;

use super::inputs::RunInfo;
use super::stats::{mcnemar, sobol_with_bootstrap, wilson};
use crate::model::{Variant, Wheel};
use crate::sampling::design::Design;
use crate::sampling::distribution::Distribution;

/// The class of a row is the classifier's own [`Class`]; names are parsed into it, and a
/// name this version does not know is refused, never counted as something else.
use crate::classify::Class;

/// Rows per class.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ClassCounts(pub [u64; 5]);

impl ClassCounts {
    /// Counts `n` more rows of `class`.
    pub fn add(&mut self, class: Class, n: u64) {
        self.0[class as usize] += n;
    }
    /// Rows of `class`.
    pub fn get(&self, class: Class) -> u64 {
        self.0[class as usize]
    }
    /// Adds another set of counts to this one.
    pub fn merge(&mut self, other: &ClassCounts) {
        for (a, b) in self.0.iter_mut().zip(other.0) {
            *a += b;
        }
    }
    /// Rows that vibrate (limit cycle or bistable).
    pub fn vibrating(&self) -> u64 {
        self.get(Class::LimitCycle) + self.get(Class::Bistable)
    }
    /// Rows with a verdict: stable, limit cycle or bistable (the denominator of probabilities).
    pub fn classified(&self) -> u64 {
        self.vibrating() + self.get(Class::Stable)
    }
    /// Rows whose model or numerics failed.
    pub fn failed(&self) -> u64 {
        self.get(Class::Failed)
    }
    /// Driving-wheel rows that cannot transmit the drive force.
    pub fn no_traction(&self) -> u64 {
        self.get(Class::NoTraction)
    }
    /// All rows, whatever their class.
    pub fn total(&self) -> u64 {
        self.0.iter().sum()
    }
    /// P(vibration) over the classified rows; NaN when there are none.
    pub fn p(&self) -> f64 {
        let n = self.classified();
        if n == 0 {
            f64::NAN
        } else {
            self.vibrating() as f64 / n as f64
        }
    }
    /// 95% Wilson interval of [`ClassCounts::p`].
    pub fn wilson(&self) -> (f64, f64) {
        wilson(self.vibrating(), self.classified())
    }
}

fn pl_err(e: PolarsError) -> String {
    format!("analysis query: {e}")
}

/// The chunk files as one lazy frame (only the columns a query names are read).
pub fn scan(files: &[PathBuf]) -> Result<LazyFrame, String> {
    let paths: Vec<PlRefPath> = files
        .iter()
        .map(|p| PlRefPath::new(p.to_string_lossy().as_ref()))
        .collect();
    LazyFrame::scan_parquet_files(
        paths.into_iter().collect(),
        ScanArgsParquet {
            low_memory: true,
            ..ScanArgsParquet::default()
        },
    )
    .map_err(pl_err)
}

/// Runs a query on polars' streaming engine.
pub fn collect(lf: LazyFrame) -> Result<DataFrame, String> {
    let df = lf
        .collect_with_engine(Engine::Streaming)
        .map(|r| r.unwrap_single())
        .map_err(pl_err);
    release_freed_memory();
    df
}

/// Sizes polars' per-thread "hot" group tables for queries of up to `max_groups` groups. The
/// streaming group-by keeps a fixed-size table of hot groups per thread (4096 by default); a
/// key that collides or overflows is evicted as a partial aggregate that is only merged at the
/// end, so with many groups memory grows with the rows. Sixteen slots per group (at least
/// 16384) keep evictions rare, and the peak flat in the row count. A value the user set in
/// `POLARS_HOT_TABLE_SIZE` is kept.
pub fn size_group_tables(max_groups: usize) {
    if std::env::var_os("POLARS_HOT_TABLE_SIZE").is_some() {
        return;
    }
    let size = (16 * max_groups).next_power_of_two().clamp(16_384, 1 << 22);
    // Set before any query of this analysis runs, from the thread that runs them; polars reads
    // it when it builds a group-by node.
    std::env::set_var("POLARS_HOT_TABLE_SIZE", size.to_string());
}

/// Hands the memory a finished query freed back to the system. glibc's malloc keeps freed
/// blocks in its per-thread arenas, so without this the resident size creeps up with every
/// query and every file although the live data stays the same.
fn release_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only returns free heap pages to the kernel; no pointer is touched.
    unsafe {
        libc::malloc_trim(0);
    }
}

fn vib_expr() -> Expr {
    col("class")
        .eq(lit(Class::LimitCycle.as_str()))
        .or(col("class").eq(lit(Class::Bistable.as_str())))
}

fn strs(df: &DataFrame, name: &str) -> Result<Vec<String>, String> {
    Ok(df
        .column(name)
        .map_err(pl_err)?
        .str()
        .map_err(pl_err)?
        .iter()
        .map(|s| s.unwrap_or("").to_string())
        .collect())
}

fn ints(df: &DataFrame, name: &str) -> Result<Vec<i64>, String> {
    let c = df
        .column(name)
        .map_err(pl_err)?
        .cast(&DataType::Int64)
        .map_err(pl_err)?;
    Ok(c.i64()
        .map_err(pl_err)?
        .iter()
        .map(|v| v.unwrap_or(-1))
        .collect())
}

fn floats(df: &DataFrame, name: &str) -> Result<Vec<f64>, String> {
    let c = df
        .column(name)
        .map_err(pl_err)?
        .cast(&DataType::Float64)
        .map_err(pl_err)?;
    Ok(c.f64()
        .map_err(pl_err)?
        .iter()
        .map(|v| v.unwrap_or(f64::NAN))
        .collect())
}

/// Rows per class for each combination of `keys`: one group per key combination with a count
/// column per class (grouping by class as well would multiply the groups by five, and polars'
/// streaming group-by keeps rows of groups beyond its 4096-entry hot table in memory until the
/// end). Rows of a class this version does not know are refused.
fn class_counts_by(
    lf: LazyFrame,
    keys: Vec<Expr>,
) -> Result<(DataFrame, Vec<ClassCounts>), String> {
    let known = Class::ALL;
    let mut aggs = vec![len().cast(DataType::Int64).alias("n")];
    aggs.extend(known.iter().map(|c| {
        col("class")
            .eq(lit(c.as_str()))
            .cast(DataType::Int64)
            .sum()
            .alias(format!("n_{}", c.as_str()))
    }));
    let df = collect(lf.group_by(keys).agg(aggs))?;
    let total = ints(&df, "n")?;
    let per_class: Vec<Vec<i64>> = known
        .iter()
        .map(|c| ints(&df, &format!("n_{}", c.as_str())))
        .collect::<Result<_, _>>()?;
    let mut counts = Vec::with_capacity(df.height());
    for i in 0..df.height() {
        let mut c = ClassCounts::default();
        let mut known_rows = 0;
        for (k, class) in known.iter().enumerate() {
            c.add(*class, per_class[k][i] as u64);
            known_rows += per_class[k][i];
        }
        if known_rows != total[i] {
            return Err(format!(
                "{} rows have a `class` this version does not know; accepted: {}",
                total[i] - known_rows,
                known.map(|c| c.as_str()).join(", ")
            ));
        }
        counts.push(c);
    }
    Ok((df, counts))
}

/// Variant and wheel of each row of a grouped table.
fn variant_wheel(df: &DataFrame) -> Result<Vec<(Variant, Wheel)>, String> {
    let v = strs(df, "variant")?;
    let w = strs(df, "wheel")?;
    v.iter()
        .zip(&w)
        .map(|(v, w)| Ok((v.parse::<Variant>()?, w.parse::<Wheel>()?)))
        .collect()
}

/// Probability of self-excited vibration for one variant and wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct Occurrence {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// Rows per class.
    pub counts: ClassCounts,
}

impl Occurrence {
    /// P(vibration) over the classified rows; NaN when there are none.
    pub fn p(&self) -> f64 {
        self.counts.p()
    }
}

/// Rows per class for each variant and wheel.
pub fn occurrence(lf: &LazyFrame) -> Result<Vec<Occurrence>, String> {
    let (df, counts) = class_counts_by(lf.clone(), vec![col("variant"), col("wheel")])?;
    let mut map: BTreeMap<(Variant, Wheel), ClassCounts> = BTreeMap::new();
    for (i, vw) in variant_wheel(&df)?.into_iter().enumerate() {
        map.entry(vw).or_default().merge(&counts[i]);
    }
    Ok(map
        .into_iter()
        .map(|((variant, wheel), counts)| Occurrence {
            variant,
            wheel,
            counts,
        })
        .collect())
}

/// The paired comparison on the same samples (McNemar), over samples whose two wheels are
/// both classified.
#[derive(Debug, Clone, PartialEq)]
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

/// 0 = not vibrating, 1 = vibrating, 2 = unclassified (failed or no traction).
fn outcome_code() -> Expr {
    when(vib_expr())
        .then(lit(1i64))
        .when(col("class").eq(lit(Class::Stable.as_str())))
        .then(lit(0i64))
        .otherwise(lit(2i64))
}

/// Driving vs follower on the same samples, in one streaming pass: explore writes each
/// sample's rows together, variant by variant, follower then driving, so the row after a
/// follower row is its driving wheel. The query checks that (same sample_id and variant,
/// driving wheel) for every follower row; files whose rows are ordered otherwise are paired by
/// [`paired_by_group`] instead.
pub fn paired(files: &[PathBuf], batch_rows: u64) -> Result<Vec<Paired>, String> {
    let lf = scan(files)?;
    let next = |c: &str| col(c).shift(lit(-1i64));
    let df = collect(
        lf.select([
            col("variant"),
            col("wheel"),
            col("sample_id"),
            outcome_code().alias("code"),
        ])
        .select([
            col("variant"),
            col("code"),
            next("code").alias("next_code"),
            col("wheel").eq(lit("follower")).alias("is_follower"),
            next("sample_id")
                .eq(col("sample_id"))
                .and(next("variant").eq(col("variant")))
                .and(next("wheel").eq(lit("driving")))
                .fill_null(lit(false))
                .alias("pair_ok"),
        ])
        .filter(col("is_follower"))
        .group_by([
            col("variant"),
            col("pair_ok"),
            col("code"),
            col("next_code"),
        ])
        .agg([len().cast(DataType::Int64).alias("n")]),
    )?;
    let ok: Vec<bool> = df
        .column("pair_ok")
        .map_err(pl_err)?
        .bool()
        .map_err(pl_err)?
        .iter()
        .map(|v| v.unwrap_or(false))
        .collect();
    if ok.iter().any(|v| !v) {
        return paired_by_group(files, batch_rows);
    }
    let (v, f, d, n) = (
        strs(&df, "variant")?,
        ints(&df, "code")?,
        ints(&df, "next_code")?,
        ints(&df, "n")?,
    );
    let mut combos: BTreeMap<(Variant, i64), u64> = BTreeMap::new();
    for i in 0..df.height() {
        *combos.entry((v[i].parse()?, f[i] + 3 * d[i])).or_default() += n[i] as u64;
    }
    Ok(paired_from(&combos))
}

/// Driving vs follower by grouping the rows by sample, for files not in explore's row order.
/// The two wheels of a sample always lie in the same chunk file, so the files are grouped in
/// batches of about `batch_rows` rows: the group-by never holds more than one batch's samples.
pub fn paired_by_group(files: &[PathBuf], batch_rows: u64) -> Result<Vec<Paired>, String> {
    // Per sample: follower + 3 × driving.
    let code = outcome_code();
    let weight = when(col("wheel").eq(lit("follower")))
        .then(lit(1i64))
        .otherwise(lit(3i64));
    let mut combos: BTreeMap<(Variant, i64), u64> = BTreeMap::new();
    let mut start = 0;
    while start < files.len() {
        let mut end = start;
        let mut rows = 0u64;
        while end < files.len() && (end == start || rows < batch_rows) {
            rows += file_rows(&files[end]);
            end += 1;
        }
        let lf = scan(&files[start..end])?;
        let df = collect(
            lf.select([
                col("variant"),
                col("sample_id"),
                (code.clone() * weight.clone()).alias("code"),
            ])
            .group_by([col("variant"), col("sample_id")])
            .agg([col("code").sum().alias("combo")])
            .group_by([col("variant"), col("combo")])
            .agg([len().cast(DataType::Int64).alias("n")]),
        )?;
        let v = strs(&df, "variant")?;
        let c = ints(&df, "combo")?;
        let n = ints(&df, "n")?;
        for i in 0..df.height() {
            *combos.entry((v[i].parse()?, c[i])).or_default() += n[i] as u64;
        }
        start = end;
    }
    Ok(paired_from(&combos))
}

/// The paired table from sample counts per (variant, follower code + 3 × driving code).
fn paired_from(combos: &BTreeMap<(Variant, i64), u64>) -> Vec<Paired> {
    let mut out = Vec::new();
    let variants: Vec<Variant> = {
        let mut v: Vec<Variant> = combos.keys().map(|k| k.0).collect();
        v.sort();
        v.dedup();
        v
    };
    for variant in variants {
        let get = |c: i64| combos.get(&(variant, c)).copied().unwrap_or(0);
        // follower + 3 × driving
        let (neither, only_f, only_d, both) = (get(0), get(1), get(3), get(4));
        let unclassified: u64 = combos
            .iter()
            .filter(|((v, c), _)| *v == variant && ![0, 1, 3, 4].contains(c))
            .map(|(_, n)| n)
            .sum();
        let (chi2, p_value, method) = mcnemar(only_f, only_d);
        out.push(Paired {
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
        });
    }
    out
}

fn file_rows(path: &std::path::Path) -> u64 {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    std::fs::File::open(path)
        .ok()
        .and_then(|f| SerializedFileReader::new(f).ok())
        .map(|r| r.metadata().file_metadata().num_rows() as u64)
        .unwrap_or(0)
}

/// Bins of one axis: the levels of a `levels` distribution (or a grid's values), else equal
/// widths between the observed minimum and maximum.
#[derive(Debug, Clone, PartialEq)]
pub struct Bins {
    /// Bin edges (len = bins + 1), or the levels themselves when `levels` is true.
    pub edges: Vec<f64>,
    /// True when the bins are the levels of a `levels` distribution or a grid.
    pub levels: bool,
}

impl Bins {
    /// `n_bins` bins of equal width between `lo` and `hi`.
    pub fn equal_width(lo: f64, hi: f64, n_bins: usize) -> Bins {
        Bins {
            edges: (0..=n_bins)
                .map(|i| lo + (hi - lo) * i as f64 / n_bins as f64)
                .collect(),
            levels: false,
        }
    }

    /// One bin per distinct level, in increasing order.
    pub fn levels(mut levels: Vec<f64>) -> Bins {
        levels.sort_by(f64::total_cmp);
        levels.dedup();
        Bins {
            edges: levels,
            levels: true,
        }
    }

    /// Number of bins.
    pub fn count(&self) -> usize {
        if self.levels {
            self.edges.len()
        } else {
            self.edges.len() - 1
        }
    }

    /// Bin index of a value (the same rule as [`Bins::expr`]).
    pub fn index(&self, v: f64) -> Option<usize> {
        if !v.is_finite() {
            return None;
        }
        if self.levels {
            return Some(
                self.edges
                    .windows(2)
                    .filter(|w| v > 0.5 * (w[0] + w[1]))
                    .count(),
            );
        }
        let (lo, hi) = (self.edges[0], *self.edges.last().unwrap());
        if v < lo || v > hi {
            return None;
        }
        let n = self.count();
        if hi == lo {
            return Some(0);
        }
        Some((((v - lo) * (n as f64 / (hi - lo))) as usize).min(n - 1))
    }

    /// The bin index as a polars expression (Int64).
    pub fn expr(&self, x: Expr) -> Expr {
        if self.levels {
            return self.edges.windows(2).fold(lit(0i64), |acc, w| {
                acc + x.clone().gt(lit(0.5 * (w[0] + w[1]))).cast(DataType::Int64)
            });
        }
        let (lo, hi) = (self.edges[0], *self.edges.last().unwrap());
        let n = self.count() as i64;
        if hi <= lo {
            return lit(0i64);
        }
        let raw = ((x - lit(lo)) * lit(n as f64 / (hi - lo))).cast(DataType::Int64);
        when(raw.clone().gt_eq(lit(n)))
            .then(lit(n - 1))
            .when(raw.clone().lt(lit(0i64)))
            .then(lit(0i64))
            .otherwise(raw)
    }

    /// (low, high, centre) of bin `i`; a level is its own centre with zero width.
    pub fn range(&self, i: usize) -> (f64, f64, f64) {
        if self.levels {
            let v = self.edges[i];
            (v, v, v)
        } else {
            let (a, b) = (self.edges[i], self.edges[i + 1]);
            (a, b, 0.5 * (a + b))
        }
    }
}

/// Observed minimum and maximum of each column, in one streaming pass; the severity quantities
/// only over vibrating rows with a finite value.
pub fn ranges(
    lf: &LazyFrame,
    axes: &[String],
    quantities: &[&str],
) -> Result<BTreeMap<String, (f64, f64)>, String> {
    let mut exprs = Vec::new();
    for a in axes {
        exprs.push(col(a.as_str()).min().alias(format!("{a}\u{1}min")));
        exprs.push(col(a.as_str()).max().alias(format!("{a}\u{1}max")));
    }
    for q in quantities {
        let keep = vib_expr().and(col(*q).is_finite());
        exprs.push(
            col(*q)
                .filter(keep.clone())
                .min()
                .alias(format!("{q}\u{1}min")),
        );
        exprs.push(col(*q).filter(keep).max().alias(format!("{q}\u{1}max")));
    }
    let df = collect(lf.clone().select(exprs))?;
    let mut out = BTreeMap::new();
    for name in axes
        .iter()
        .map(String::as_str)
        .chain(quantities.iter().copied())
    {
        let lo = floats(&df, &format!("{name}\u{1}min"))?;
        let hi = floats(&df, &format!("{name}\u{1}max"))?;
        out.insert(
            name.to_string(),
            (
                lo.first().copied().unwrap_or(f64::NAN),
                hi.first().copied().unwrap_or(f64::NAN),
            ),
        );
    }
    Ok(out)
}

/// The bins of each drawn parameter: the study's levels where it draws `levels` (or a grid's
/// counted values), else `n_bins` equal widths over the observed range.
pub fn axis_bins(
    info: &RunInfo,
    ranges: &BTreeMap<String, (f64, f64)>,
    name: &str,
    n_bins: usize,
) -> Bins {
    if let Some(levels) = study_levels(info, name) {
        return Bins::levels(levels);
    }
    let (lo, hi) = ranges.get(name).copied().unwrap_or((0.0, 1.0));
    Bins::equal_width(lo, hi, n_bins)
}

/// At most this many distinct values of an operating-point column are used as its levels; a
/// column with more (raw telematics rather than bins) is binned in equal widths.
pub const MAX_OPERATING_POINT_LEVELS: usize = 40;

/// The levels a study draws a parameter from: `levels`, or a grid's `count` values, as the
/// sampler itself lists them ([`Distribution::grid_values`]), so a label is always a sampled
/// value; for a column of `[operating_points]`, its distinct values among the rows that can be
/// drawn (positive weight), when there are few.
pub fn study_levels(info: &RunInfo, name: &str) -> Option<Vec<f64>> {
    let study = info.parsed_study()?;
    if let Some(op) = &study.operating_points {
        if let Some(j) = op.names.iter().position(|n| *n == name) {
            let mut levels: Vec<f64> = op
                .values
                .iter()
                .zip(&op.weights)
                .filter(|(_, w)| **w > 0.0)
                .map(|(row, _)| row[j])
                .collect();
            levels.sort_by(f64::total_cmp);
            levels.dedup();
            return (levels.len() <= MAX_OPERATING_POINT_LEVELS).then_some(levels);
        }
    }
    let d = study.drawn.iter().find(|d| d.param.name() == name)?;
    match &d.dist {
        Distribution::Levels(_) => d.dist.grid_values(),
        Distribution::Uniform { count: Some(_), .. } if study.design == Design::Grid => {
            d.dist.grid_values()
        }
        _ => None,
    }
}

/// Probability in one bin of one axis.
#[derive(Debug, Clone, PartialEq)]
pub struct BinStat {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The drawn parameter binned.
    pub axis: String,
    /// Lower edge of the bin (the level itself for levels).
    pub lo: f64,
    /// Upper edge of the bin (the level itself for levels).
    pub hi: f64,
    /// Middle of the bin, where the figure plots it.
    pub mid: f64,
    /// Rows per class in the bin.
    pub counts: ClassCounts,
}

/// P(vibration | axis in bin), per variant, wheel and bin of one axis.
pub fn conditional(lf: &LazyFrame, axis: &str, bins: &Bins) -> Result<Vec<BinStat>, String> {
    let (df, counts) = class_counts_by(
        lf.clone(),
        vec![
            col("variant"),
            col("wheel"),
            bins.expr(col(axis)).alias("bin"),
        ],
    )?;
    let mut map: BTreeMap<(Variant, Wheel, i64), ClassCounts> = BTreeMap::new();
    let b = ints(&df, "bin")?;
    let groups = variant_wheel(&df)?;
    for (i, (v, w)) in groups.iter().enumerate() {
        map.entry((*v, *w, b[i])).or_default().merge(&counts[i]);
    }
    let mut keys: Vec<(Variant, Wheel)> = groups;
    keys.sort();
    keys.dedup();
    let mut out = Vec::new();
    for (variant, wheel) in keys {
        for i in 0..bins.count() {
            let (lo, hi, mid) = bins.range(i);
            out.push(BinStat {
                variant,
                wheel,
                axis: axis.to_string(),
                lo,
                hi,
                mid,
                counts: map
                    .get(&(variant, wheel, i as i64))
                    .copied()
                    .unwrap_or_default(),
            });
        }
    }
    Ok(out)
}

/// Class counts per cell, indexed `[ix][iy]`.
pub type CountGrid = Vec<Vec<ClassCounts>>;

/// A risk map: class counts over a 2-D grid of bins of two axes, per wheel.
#[derive(Debug, Clone)]
pub struct RiskMap {
    /// The friction variant.
    pub variant: Variant,
    /// The parameter on the horizontal axis.
    pub x: String,
    /// The parameter on the vertical axis.
    pub y: String,
    /// Bins of the horizontal axis.
    pub x_bins: Bins,
    /// Bins of the vertical axis.
    pub y_bins: Bins,
    /// (wheel, `counts[ix][iy]`).
    pub cells: Vec<(Wheel, CountGrid)>,
}

impl RiskMap {
    /// Probability per cell, NaN where fewer than `min_count` classified samples fell.
    pub fn probability(&self, wheel: Wheel, min_count: u64) -> Vec<Vec<f64>> {
        let Some((_, grid)) = self.cells.iter().find(|(w, _)| *w == wheel) else {
            return vec![vec![f64::NAN; self.y_bins.count()]; self.x_bins.count()];
        };
        grid.iter()
            .map(|col| {
                col.iter()
                    .map(|c| {
                        if c.classified() >= min_count.max(1) {
                            c.p()
                        } else {
                            f64::NAN
                        }
                    })
                    .collect()
            })
            .collect()
    }
}

/// Risk maps of every variant over the axes `x` × `y`.
pub fn risk_maps(
    lf: &LazyFrame,
    x: &str,
    y: &str,
    xb: &Bins,
    yb: &Bins,
) -> Result<Vec<RiskMap>, String> {
    let (df, counts) = class_counts_by(
        lf.clone(),
        vec![
            col("variant"),
            col("wheel"),
            // One key per cell: bx · (y bins) + by.
            (xb.expr(col(x)) * lit(yb.count() as i64) + yb.expr(col(y))).alias("cell"),
        ],
    )?;
    let cell = ints(&df, "cell")?;
    let ny = yb.count() as i64;
    let (bx, by): (Vec<i64>, Vec<i64>) = cell.iter().map(|c| (c / ny, c % ny)).unzip();
    let mut maps: BTreeMap<Variant, BTreeMap<Wheel, CountGrid>> = BTreeMap::new();
    for (i, (v, w)) in variant_wheel(&df)?.into_iter().enumerate() {
        let grid = maps
            .entry(v)
            .or_default()
            .entry(w)
            .or_insert_with(|| vec![vec![ClassCounts::default(); yb.count()]; xb.count()]);
        if let (Ok(ix), Ok(iy)) = (usize::try_from(bx[i]), usize::try_from(by[i])) {
            if ix < xb.count() && iy < yb.count() {
                grid[ix][iy].merge(&counts[i]);
            }
        }
    }
    Ok(maps
        .into_iter()
        .map(|(variant, wheels)| RiskMap {
            variant,
            x: x.into(),
            y: y.into(),
            x_bins: xb.clone(),
            y_bins: yb.clone(),
            cells: Wheel::BOTH
                .iter()
                .map(|w| {
                    (
                        *w,
                        wheels.get(w).cloned().unwrap_or_else(|| {
                            vec![vec![ClassCounts::default(); yb.count()]; xb.count()]
                        }),
                    )
                })
                .collect(),
        })
        .collect())
}

/// The severity quantities: (column, unit).
pub const SEVERITY_QUANTITIES: [(&str, &str); 4] = [
    ("amp_y_m", "m"),
    ("amp_v_mps", "m/s"),
    ("energy_per_cycle_j", "J"),
    ("polygon_order", "-"),
];

/// Fine histogram bins behind the severity quantiles.
pub const SEVERITY_FINE_BINS: usize = 4000;

/// Distribution of one cycle quantity among the vibrating rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Severity {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The cycle quantity (a column of [`SEVERITY_QUANTITIES`]).
    pub quantity: &'static str,
    /// Its unit.
    pub unit: &'static str,
    /// Vibrating rows with a finite value of the quantity.
    pub n: u64,
    /// Mean of the quantity over those rows.
    pub mean: f64,
    /// 5, 25, 50, 75, 95 %, read from the fine histogram (linear within a bin).
    pub quantiles: [f64; 5],
    /// The fine histogram: equal-width bins over the quantity's range among all vibrating rows.
    pub hist: Bins,
    /// Rows in each bin of `hist`.
    pub counts: Vec<u64>,
}

/// Severity quantiles from a `SEVERITY_FINE_BINS`-bin histogram per variant and wheel: exact to
/// 1/4000 of the range, in memory independent of the row count.
pub fn severity(
    lf: &LazyFrame,
    ranges: &BTreeMap<String, (f64, f64)>,
) -> Result<Vec<Severity>, String> {
    let mut out = Vec::new();
    for (quantity, unit) in SEVERITY_QUANTITIES {
        let (lo, hi) = ranges
            .get(quantity)
            .copied()
            .unwrap_or((f64::NAN, f64::NAN));
        if !(lo.is_finite() && hi.is_finite()) {
            continue;
        }
        let bins = Bins::equal_width(lo, hi, SEVERITY_FINE_BINS);
        let df = collect(
            lf.clone()
                .filter(vib_expr().and(col(quantity).is_finite()))
                .group_by([
                    col("variant"),
                    col("wheel"),
                    bins.expr(col(quantity)).alias("bin"),
                ])
                .agg([
                    len().cast(DataType::Int64).alias("n"),
                    fixed_point(col(quantity), lo, hi).sum().alias("sum"),
                ]),
        )?;
        let (b, n, sum) = (ints(&df, "bin")?, ints(&df, "n")?, ints(&df, "sum")?);
        let mut groups: BTreeMap<(Variant, Wheel), (Vec<u64>, i128)> = BTreeMap::new();
        for (i, vw) in variant_wheel(&df)?.into_iter().enumerate() {
            let g = groups
                .entry(vw)
                .or_insert_with(|| (vec![0; bins.count()], 0));
            if let Ok(k) = usize::try_from(b[i]) {
                g.0[k.min(bins.count() - 1)] += n[i] as u64;
            }
            g.1 += i128::from(sum[i]);
        }
        for ((variant, wheel), (counts, sum)) in groups {
            let n: u64 = counts.iter().sum();
            let mean_fixed = sum as f64 / n.max(1) as f64;
            out.push(Severity {
                variant,
                wheel,
                quantity,
                unit,
                n,
                mean: if n == 0 {
                    f64::NAN
                } else {
                    lo + (hi - lo) * mean_fixed / FIXED_POINT_SCALE
                },
                quantiles: [0.05, 0.25, 0.5, 0.75, 0.95].map(|q| hist_quantile(&bins, &counts, q)),
                hist: bins.clone(),
                counts,
            });
        }
    }
    Ok(out)
}

/// Units of the fixed-point sums: 2^32 per range, so up to 2^31 rows sum without overflow.
const FIXED_POINT_SCALE: f64 = 4_294_967_296.0;

/// A value in [lo, hi] as a whole number of 2^-32 ranges above `lo`: integer sums are exact and
/// do not depend on the order polars adds the rows in, so the mean is the same whatever the
/// threads, shards or files (a float sum is not).
fn fixed_point(x: Expr, lo: f64, hi: f64) -> Expr {
    let scale = if hi > lo {
        FIXED_POINT_SCALE / (hi - lo)
    } else {
        0.0
    };
    ((x - lit(lo)) * lit(scale) + lit(0.5)).cast(DataType::Int64)
}

/// The q-quantile of a histogram, linear within the bin that holds it.
pub fn hist_quantile(bins: &Bins, counts: &[u64], q: f64) -> f64 {
    let n: u64 = counts.iter().sum();
    if n == 0 {
        return f64::NAN;
    }
    let target = q * n as f64;
    let mut below = 0.0;
    for (i, c) in counts.iter().enumerate() {
        let c = *c as f64;
        if c > 0.0 && below + c >= target {
            let (a, b, _) = bins.range(i);
            return a + (b - a) * ((target - below) / c).clamp(0.0, 1.0);
        }
        below += c;
    }
    *bins.edges.last().unwrap()
}

/// First-order and total Sobol indices of one output with respect to one parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensitivity {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// `limit_cycle` (the 0/1 indicator) or `amp_v_mps` (0 without a cycle).
    pub output: &'static str,
    /// The drawn parameter the indices belong to.
    pub param: String,
    /// Base points of the Saltelli design used.
    pub base_samples: u64,
    /// Base points left out because a block is missing or unclassified.
    pub left_out: u64,
    /// First-order index (Saltelli 2010) with its bootstrap 95% interval: (estimate, lo, hi).
    pub s: (f64, f64, f64),
    /// Total index (Jansen 1999) with its bootstrap 95% interval: (estimate, lo, hi).
    pub st: (f64, f64, f64),
}

/// Sobol indices from a Saltelli design (sample_id = j·(k+2) + block); None for other designs.
/// Polars hands over, per variant and wheel, the two outputs of each row in (j, block) order;
/// the estimators and their bootstrap need those vectors (3 numbers a row).
pub fn sensitivity(
    lf: &LazyFrame,
    info: &RunInfo,
    resamples: usize,
) -> Result<Option<Vec<Sensitivity>>, String> {
    if Design::parse(&info.design) != Some(Design::Saltelli) {
        return Ok(None);
    }
    let k = info.drawn_names.len();
    let stride = k as i64 + 2;
    let df = collect(
        lf.clone()
            .select([
                col("variant"),
                col("wheel"),
                col("sample_id"),
                col("class"),
                col("amp_v_mps"),
            ])
            .sort(
                ["variant", "wheel", "sample_id"],
                SortMultipleOptions::default(),
            ),
    )?;
    let groups = variant_wheel(&df)?;
    let (sid, class, amp) = (
        ints(&df, "sample_id")?,
        strs(&df, "class")?,
        floats(&df, "amp_v_mps")?,
    );
    let mut out = Vec::new();
    let mut i = 0;
    while i < groups.len() {
        let (variant, wheel) = groups[i];
        // rows[j][block] = Some((indicator, amplitude)) for classified rows, None otherwise.
        type Block = Option<Option<(f64, f64)>>;
        let mut rows: BTreeMap<i64, Vec<Block>> = BTreeMap::new();
        while i < groups.len() && groups[i] == (variant, wheel) {
            let c: Class = class[i].parse()?;
            let v = if c.vibrates() {
                Some((1.0, amp[i]))
            } else if c == Class::Stable {
                Some((0.0, 0.0))
            } else {
                None
            };
            rows.entry(sid[i] / stride)
                .or_insert_with(|| vec![None; k + 2])[(sid[i] % stride) as usize] = Some(v);
            i += 1;
        }
        let total = rows.len() as u64;
        // Only complete base points, every block classified.
        let complete: Vec<Vec<(f64, f64)>> = rows
            .into_values()
            .filter_map(|r| r.into_iter().collect::<Option<Option<Vec<_>>>>().flatten())
            .collect();
        if complete.len() < 2 {
            continue;
        }
        for (output, pick) in [(Class::LimitCycle.as_str(), 0usize), ("amp_v_mps", 1usize)] {
            let raw = |r: &Vec<(f64, f64)>, b: usize| if pick == 0 { r[b].0 } else { r[b].1 };
            // Outputs centred on the mean of every evaluated row (A, B and all AB blocks), as
            // SALib's `sobol.analyze` does: the first-order estimator mean(f_B (f_ABi − f_A))
            // is not shift-invariant, and centring lowers its variance. Total indices and the
            // variance are unchanged by the shift.
            let mean = complete
                .iter()
                .map(|r| (0..k + 2).map(|b| raw(r, b)).sum::<f64>())
                .sum::<f64>()
                / (complete.len() * (k + 2)) as f64;
            let f = |r: &Vec<(f64, f64)>, b: usize| raw(r, b) - mean;
            let fa: Vec<f64> = complete.iter().map(|r| f(r, 0)).collect();
            let fb: Vec<f64> = complete.iter().map(|r| f(r, 1)).collect();
            for (m, name) in info.drawn_names.iter().enumerate() {
                let fab: Vec<f64> = complete.iter().map(|r| f(r, 2 + m)).collect();
                let (s, st) = sobol_with_bootstrap(&fa, &fb, &fab, resamples, 17 + m as u64);
                out.push(Sensitivity {
                    variant,
                    wheel,
                    output,
                    param: name.clone(),
                    base_samples: complete.len() as u64,
                    left_out: total - complete.len() as u64,
                    s,
                    st,
                });
            }
        }
    }
    Ok(Some(out))
}

/// The operating axes: never part of a "decoding".
pub const OPERATING_AXES: [&str; 4] = ["speed_kmh", "toe_deg", "load_n", "pressure_kpa"];

/// One decoding of the paper's lost digits: a combination of the levels of the parameters the
/// study draws with `levels` (operating axes aside), with the class counts of both wheels.
#[derive(Debug, Clone, PartialEq)]
pub struct Decoding {
    /// The friction variant.
    pub variant: Variant,
    /// Values of the decoded parameters, in [`Robustness::params`] order.
    pub values: Vec<f64>,
    /// The follower's rows per class in this decoding.
    pub follower: ClassCounts,
    /// The driving wheel's rows per class in this decoding.
    pub driving: ClassCounts,
}

/// P(limit cycle) per wheel for each decoding, and how often the driving wheel is less exposed.
#[derive(Debug, Clone, PartialEq)]
pub struct Robustness {
    /// The decoded parameters (those drawn with `levels`, operating axes aside).
    pub params: Vec<String>,
    /// Every decoding present in the rows.
    pub decodings: Vec<Decoding>,
}

/// The share of decodings (of one variant) with the driving wheel less exposed than the
/// follower, over the decodings with at least `min_count` classified rows on each wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct RobustnessSummary {
    /// The friction variant.
    pub variant: Variant,
    /// Decodings present.
    pub decodings: u64,
    /// Decodings with at least `min_count` classified rows on each wheel.
    pub compared: u64,
    /// Compared decodings where the driving wheel vibrates less often than the follower.
    pub driving_less: u64,
    /// Decodings left out for too few classified rows.
    pub too_few: u64,
    /// `driving_less / compared`.
    pub share: f64,
    /// Lower end of the 95% Wilson interval of `share`.
    pub lo: f64,
    /// Upper end of the 95% Wilson interval of `share`.
    pub hi: f64,
}

impl Robustness {
    /// The summary of each variant, comparing decodings with at least `min_count` classified rows on each wheel.
    pub fn summary(&self, min_count: u64) -> Vec<RobustnessSummary> {
        let mut variants: Vec<Variant> = self.decodings.iter().map(|d| d.variant).collect();
        variants.sort();
        variants.dedup();
        variants
            .into_iter()
            .map(|variant| {
                let ds: Vec<&Decoding> = self
                    .decodings
                    .iter()
                    .filter(|d| d.variant == variant)
                    .collect();
                let enough: Vec<&&Decoding> = ds
                    .iter()
                    .filter(|d| {
                        d.follower.classified() >= min_count.max(1)
                            && d.driving.classified() >= min_count.max(1)
                    })
                    .collect();
                let less = enough
                    .iter()
                    .filter(|d| d.driving.p() < d.follower.p())
                    .count() as u64;
                let n = enough.len() as u64;
                let (lo, hi) = wilson(less, n);
                RobustnessSummary {
                    variant,
                    decodings: ds.len() as u64,
                    compared: n,
                    driving_less: less,
                    too_few: ds.len() as u64 - n,
                    share: if n == 0 {
                        f64::NAN
                    } else {
                        less as f64 / n as f64
                    },
                    lo,
                    hi,
                }
            })
            .collect()
    }
}

/// The parameters a study draws with `levels`, the operating axes aside: the decoded constants.
pub fn decoded_params(info: &RunInfo) -> Vec<String> {
    let Some(study) = info.parsed_study() else {
        return Vec::new();
    };
    study
        .drawn
        .iter()
        .filter(|d| {
            matches!(d.dist, Distribution::Levels(_)) && !OPERATING_AXES.contains(&d.param.name())
        })
        .map(|d| d.param.name().to_string())
        .collect()
}

/// Class counts per decoding and wheel; None when the study draws no parameter with `levels`
/// besides the operating axes.
pub fn robustness(lf: &LazyFrame, info: &RunInfo) -> Result<Option<Robustness>, String> {
    let params = decoded_params(info);
    if params.is_empty() {
        return Ok(None);
    }
    let mut keys = vec![col("variant"), col("wheel")];
    keys.extend(params.iter().map(|p| col(p.as_str())));
    let (df, counts) = class_counts_by(lf.clone(), keys)?;
    let values: Vec<Vec<f64>> = params
        .iter()
        .map(|p| floats(&df, p))
        .collect::<Result<_, _>>()?;
    // (variant, value bits) -> (values, follower, driving)
    type Entry = (Vec<f64>, ClassCounts, ClassCounts);
    let mut map: BTreeMap<(Variant, Vec<u64>), Entry> = BTreeMap::new();
    for (i, (v, w)) in variant_wheel(&df)?.into_iter().enumerate() {
        let vals: Vec<f64> = values.iter().map(|col| col[i]).collect();
        let key: Vec<u64> = vals.iter().map(|x| x.to_bits()).collect();
        let e = map
            .entry((v, key))
            .or_insert_with(|| (vals.clone(), ClassCounts::default(), ClassCounts::default()));
        let slot = if w == Wheel::Follower {
            &mut e.1
        } else {
            &mut e.2
        };
        slot.merge(&counts[i]);
    }
    let mut decodings: Vec<Decoding> = map
        .into_iter()
        .map(|((variant, _), (values, follower, driving))| Decoding {
            variant,
            values,
            follower,
            driving,
        })
        .collect();
    decodings.sort_by(|a, b| {
        a.variant.cmp(&b.variant).then_with(|| {
            a.values
                .iter()
                .zip(&b.values)
                .map(|(x, y)| x.total_cmp(y))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        })
    });
    Ok(Some(Robustness { params, decodings }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_use_levels_for_grids_and_widths_otherwise() {
        let b = Bins::levels(vec![3.0, 1.0, 2.0, 2.0]);
        assert!(b.levels && b.count() == 3);
        assert_eq!(b.index(2.0), Some(1));
        assert_eq!(b.index(1.0), Some(0));
        assert_eq!(b.index(3.0), Some(2));
        let b = Bins::equal_width(0.0, 99.9, 10);
        assert!(!b.levels && b.count() == 10);
        assert_eq!(b.index(0.0), Some(0));
        assert_eq!(b.index(99.9), Some(9));
        assert_eq!(b.index(50.0), Some(5));
    }

    #[test]
    fn polars_bin_expression_agrees_with_index() {
        let values: Vec<f64> = (0..=200).map(|i| i as f64 * 0.5).collect();
        for bins in [
            Bins::equal_width(0.0, 100.0, 7),
            Bins::levels(vec![0.0, 10.0, 55.5, 100.0]),
        ] {
            let df = df!("x" => values.clone()).unwrap();
            let out = df
                .lazy()
                .select([bins.expr(col("x")).alias("b")])
                .collect()
                .unwrap();
            let got = ints(&out, "b").unwrap();
            for (v, b) in values.iter().zip(got) {
                assert_eq!(Some(b as usize), bins.index(*v), "{v} in {bins:?}");
            }
        }
    }

    #[test]
    fn histogram_quantiles_are_within_a_bin() {
        let values: Vec<f64> = (0..10_000).map(|i| (i as f64 / 9999.0).powi(2)).collect();
        let bins = Bins::equal_width(0.0, 1.0, SEVERITY_FINE_BINS);
        let mut counts = vec![0u64; bins.count()];
        for v in &values {
            counts[bins.index(*v).unwrap()] += 1;
        }
        for q in [0.05f64, 0.5, 0.95] {
            let exact = q.powi(2);
            assert!(
                (hist_quantile(&bins, &counts, q) - exact).abs() < 2.0 / SEVERITY_FINE_BINS as f64,
                "q = {q}"
            );
        }
    }
}
