//! The one place that speaks to polars: the chunk files as a lazy frame, and the few kinds of
//! streaming query the analysis asks of them (class counts per group, ranges, histograms, the
//! paired outcomes, a Saltelli design's rows, the calibration band's counts). Each is a group-by
//! or selection of a few hundred rows at most: memory does not grow with the rows.
//!
//! polars 0.55 sizes the streaming group-by's per-thread table of "hot" groups from
//! `POLARS_HOT_TABLE_SIZE`, read when a query is built, with no API for it: the binary sets
//! [`hot_table_size`] at its start, before any thread exists.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use polars::prelude::*;

use super::bins::Bins;
use super::counts::{outcome_code, ClassCounts};
use super::AnalysisError;
use polywear_core::classify::Class;
use polywear_core::model::{Variant, Wheel};
use polywear_core::records::{RecordColumn, SAMPLE_ID};
use polywear_core::text_enum::UnknownName;
use polywear_study::study::BASELINE;

mod band_counts;
mod renamed;
mod scenario_pairs;
mod wear_counts;
mod wear_values;
pub(crate) use band_counts::{band_counts, BandCount};
pub(crate) use renamed::deprecation_notes;
use scenario_pairs::code_expr;
pub use scenario_pairs::OutcomeColumn;
pub(crate) use scenario_pairs::{scenario_pairs, ScenarioPairCounts};
pub(crate) use wear_counts::{decade_bins, decades, NEAR_MISS_SHARES, WEIGHT_UNITS_PER_KMH};
pub use wear_counts::{NearMisses, OrderCount, SampleWeight, WearSpread};
pub(crate) use wear_values::check_wear_values;

/// The columns the queries name, from the one column table ([`polywear_core::records`]).
const VARIANT: &str = RecordColumn::Variant.name();
const WHEEL: &str = RecordColumn::Wheel.name();
const CLASS: &str = RecordColumn::Class.name();
const AMP_V: &str = RecordColumn::AmpVMps.name();
const SAMPLE: &str = SAMPLE_ID.name;

fn pl_err(e: PolarsError) -> AnalysisError {
    AnalysisError::Query(e.to_string())
}

/// The size of polars' per-thread "hot" group tables for queries of up to `max_groups` groups.
/// The streaming group-by keeps a fixed-size table of hot groups per thread (4096 by default);
/// a key that collides or overflows is evicted as a partial aggregate that is only merged at
/// the end, so with many groups memory grows with the rows. Sixteen slots per group (at least
/// 16384) keep evictions rare, and the peak flat in the row count.
pub(crate) fn hot_table_size(max_groups: usize) -> usize {
    (16 * max_groups).next_power_of_two().clamp(16_384, 1 << 22)
}

/// The chunk files of a run as one lazy frame (only the columns a query names are read).
#[derive(Clone)]
pub(crate) struct Rows {
    lf: LazyFrame,
}

/// An extra key of a class count, besides variant and wheel.
#[derive(Debug, Clone, Copy)]
pub(crate) enum GroupKey<'a> {
    /// The bin of a column (its index in [`Group::bins`]).
    Bin(&'a str, &'a Bins),
    /// The cell of two binned columns, `x bin × (y bins) + y bin` (one key, not two).
    Cell(&'a str, &'a Bins, &'a str, &'a Bins),
    /// The value of a column itself (in [`Group::values`]).
    Value(&'a str),
}

/// The counts of one group: its variant, wheel and keys, and what the query counted in it (rows
/// per class by default, [`Rows::class_counts`]; the wear stage's counts per distance,
/// [`wear_counts::WearGroup`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Group<C = ClassCounts> {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The bin or cell indices of the `Bin` and `Cell` keys, in key order.
    pub bins: Vec<i64>,
    /// The values of the `Value` keys, in key order.
    pub values: Vec<f64>,
    /// What the query counted.
    pub counts: C,
}

/// A bin of a severity histogram.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HistogramBin {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The bin index.
    pub bin: i64,
    /// Rows in the bin.
    pub n: i64,
    /// The sum of the rows' values in fixed point (`FIXED_POINT_SCALE` units of the range
    /// above its low end).
    pub fixed_sum: i64,
}

/// One row's outcome, for estimators that need every row (Sobol indices).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RowOutcome {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The sample.
    pub sample_id: i64,
    /// The row's class.
    pub class: Class,
    /// The velocity amplitude \[m/s\].
    pub amp_v_mps: f64,
}

impl Rows {
    /// The chunk files as one lazy frame.
    /// Columns renamed for one version are read under their new names ([`deprecation_notes`]).
    pub fn scan(files: &[PathBuf]) -> Result<Rows, AnalysisError> {
        let lf = renamed::with_new_names(Rows::scan_raw(files)?)?;
        Ok(Rows { lf })
    }

    /// The chunk files as they are.
    fn scan_raw(files: &[PathBuf]) -> Result<LazyFrame, AnalysisError> {
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

    /// The rows whose `sample_id` modulo `stride` is below `blocks` (of a Saltelli design,
    /// `stride` = k + 2 blocks per base point: blocks 0 and 1 are its independent base
    /// matrices A and B).
    pub fn sample_blocks_below(&self, stride: i64, blocks: i64) -> Rows {
        Rows {
            lf: self
                .lf
                .clone()
                .filter((col(SAMPLE) % lit(stride)).lt(lit(blocks))),
        }
    }

    /// The baseline's rows of the chunk files: all rows for a study without scenarios (no
    /// `scenario` column), else those of scenario `baseline`.
    pub fn scan_baseline(files: &[PathBuf], has_scenarios: bool) -> Result<Rows, AnalysisError> {
        let rows = Rows::scan(files)?;
        Ok(if has_scenarios {
            Rows {
                lf: rows.lf.filter(col("scenario").eq(lit(BASELINE))),
            }
        } else {
            rows
        })
    }

    /// Whether the files have a column `name` (from their schema; no row is read).
    pub fn has_column(&self, name: &str) -> Result<bool, AnalysisError> {
        let schema = self.lf.clone().collect_schema().map_err(pl_err)?;
        Ok(schema.contains(name))
    }

    /// Rows per class for each variant, wheel and combination of `keys`: one group per key
    /// combination with a count column per class (grouping by class as well would multiply the
    /// groups by five, and polars' streaming group-by keeps rows of groups beyond its hot table
    /// in memory until the end). Rows of a class this version does not know are refused.
    pub fn class_counts(&self, keys: &[GroupKey<'_>]) -> Result<Vec<Group>, AnalysisError> {
        let known = Class::ALL;
        let mut aggs = vec![len().cast(DataType::Int64).alias("n")];
        aggs.extend(known.iter().map(|c| {
            col(CLASS)
                .eq(lit(c.as_str()))
                .cast(DataType::Int64)
                .sum()
                .alias(format!("n_{}", c.as_str()))
        }));
        let df = self.grouped(keys, aggs)?;
        let total = ints(&df, "n")?;
        let per_class: Vec<Vec<i64>> = known
            .iter()
            .map(|c| ints(&df, &format!("n_{}", c.as_str())))
            .collect::<Result<_, _>>()?;
        groups_of(&df, keys, |i| {
            let mut counts = ClassCounts::default();
            let mut known_rows = 0;
            for (k, class) in known.iter().enumerate() {
                counts.add(*class, per_class[k][i] as u64);
                known_rows += per_class[k][i];
            }
            if known_rows != total[i] {
                return Err(AnalysisError::UnknownClass {
                    rows: (total[i] - known_rows) as u64,
                });
            }
            Ok(counts)
        })
    }

    /// The aggregates `aggs` per variant, wheel and combination of `keys` ([`key_exprs`]), in
    /// one streaming group-by.
    fn grouped(&self, keys: &[GroupKey<'_>], aggs: Vec<Expr>) -> Result<DataFrame, AnalysisError> {
        collect(self.lf.clone().group_by(key_exprs(keys)).agg(aggs))
    }

    /// Observed minimum and maximum of each column, in one streaming pass; the `quantities`
    /// only over vibrating rows with a finite value.
    pub fn ranges(
        &self,
        axes: &[&str],
        quantities: &[&str],
    ) -> Result<BTreeMap<String, (f64, f64)>, AnalysisError> {
        let mut exprs = Vec::new();
        for a in axes {
            exprs.push(col(*a).min().alias(format!("{a}\u{1}min")));
            exprs.push(col(*a).max().alias(format!("{a}\u{1}max")));
            exprs.push(
                col(*a)
                    .is_finite()
                    .not()
                    .cast(DataType::Int64)
                    .sum()
                    .alias(format!("{a}\u{1}bad")),
            );
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
        let df = collect(self.lf.clone().select(exprs))?;
        // A drawn value that is NaN or infinite has no bin and no place on a figure.
        for a in axes {
            let bad = ints(&df, &format!("{a}\u{1}bad"))?;
            if let Some(&rows) = bad.first().filter(|n| **n > 0) {
                return Err(AnalysisError::NotFinite {
                    column: a.to_string(),
                    rows: rows as u64,
                });
            }
        }
        let mut out = BTreeMap::new();
        for name in axes.iter().chain(quantities) {
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

    /// The histogram of `quantity` over the vibrating rows with a finite value, per variant and
    /// wheel, on `bins` (equal widths over `[lo, hi]`), with each bin's fixed-point sum.
    pub fn histogram(
        &self,
        quantity: &str,
        bins: &Bins,
        (lo, hi): (f64, f64),
    ) -> Result<Vec<HistogramBin>, AnalysisError> {
        let df = collect(
            self.lf
                .clone()
                .filter(vib_expr().and(col(quantity).is_finite()))
                .group_by([
                    col(VARIANT),
                    col(WHEEL),
                    bin_expr(bins, col(quantity)).alias("bin"),
                ])
                .agg([
                    len().cast(DataType::Int64).alias("n"),
                    fixed_point(col(quantity), lo, hi).sum().alias("sum"),
                ]),
        )?;
        histogram_bins(&df, Some(&ints(&df, "sum")?))
    }

    /// Every row's outcome, sorted by variant, wheel and sample.
    pub fn outcomes_by_sample(&self) -> Result<Vec<RowOutcome>, AnalysisError> {
        let df = collect(
            self.lf
                .clone()
                .select([
                    col(VARIANT),
                    col(WHEEL),
                    col(SAMPLE),
                    col(CLASS),
                    col(AMP_V),
                ])
                .sort([VARIANT, WHEEL, SAMPLE], SortMultipleOptions::default()),
        )?;
        let groups = variant_wheel(&df)?;
        let (sid, class, amp) = (ints(&df, SAMPLE)?, strs(&df, CLASS)?, floats(&df, AMP_V)?);
        groups
            .into_iter()
            .enumerate()
            .map(|(i, (variant, wheel))| {
                Ok(RowOutcome {
                    variant,
                    wheel,
                    sample_id: sid[i],
                    class: class[i]
                        .parse()
                        .map_err(|e: UnknownName| AnalysisError::Row(e.to_string()))?,
                    amp_v_mps: amp[i],
                })
            })
            .collect()
    }
}

/// The group-by keys of a grouped query: variant, wheel, then `key0`, `key1`, … for `keys`.
fn key_exprs(keys: &[GroupKey<'_>]) -> Vec<Expr> {
    let mut exprs = vec![col(VARIANT), col(WHEEL)];
    for (k, key) in keys.iter().enumerate() {
        let name = format!("key{k}");
        exprs.push(match *key {
            GroupKey::Bin(c, b) => bin_expr(b, col(c)).alias(name),
            GroupKey::Cell(x, xb, y, yb) => {
                (bin_expr(xb, col(x)) * lit(yb.count() as i64) + bin_expr(yb, col(y))).alias(name)
            }
            GroupKey::Value(c) => col(c).alias(name),
        });
    }
    exprs
}

/// The bin indices and the values of the keys of [`key_exprs`] in a grouped table, key by key.
type KeyColumns = (Vec<Vec<i64>>, Vec<Vec<f64>>);

fn key_values(df: &DataFrame, keys: &[GroupKey<'_>]) -> Result<KeyColumns, AnalysisError> {
    let mut bins: Vec<Vec<i64>> = Vec::new();
    let mut values: Vec<Vec<f64>> = Vec::new();
    for (k, key) in keys.iter().enumerate() {
        let name = format!("key{k}");
        match key {
            GroupKey::Value(_) => values.push(floats(df, &name)?),
            _ => bins.push(ints(df, &name)?),
        }
    }
    Ok((bins, values))
}

/// The groups of `df`, a table grouped by [`key_exprs`] of `keys`: each row's variant, wheel
/// and keys, with `counts` of its row index.
fn groups_of<C>(
    df: &DataFrame,
    keys: &[GroupKey<'_>],
    mut counts: impl FnMut(usize) -> Result<C, AnalysisError>,
) -> Result<Vec<Group<C>>, AnalysisError> {
    let (bins, values) = key_values(df, keys)?;
    variant_wheel(df)?
        .into_iter()
        .enumerate()
        .map(|(i, (variant, wheel))| {
            Ok(Group {
                variant,
                wheel,
                bins: bins.iter().map(|b| b[i]).collect(),
                values: values.iter().map(|v| v[i]).collect(),
                counts: counts(i)?,
            })
        })
        .collect()
}

/// The bins of `df`, a histogram grouped by variant, wheel and `bin` with its rows in `n`, each
/// with its fixed-point sum from `sums` (0 without).
fn histogram_bins(
    df: &DataFrame,
    sums: Option<&[i64]>,
) -> Result<Vec<HistogramBin>, AnalysisError> {
    let (b, n) = (ints(df, "bin")?, ints(df, "n")?);
    Ok(variant_wheel(df)?
        .into_iter()
        .enumerate()
        .map(|(i, (variant, wheel))| HistogramBin {
            variant,
            wheel,
            bin: b[i],
            n: n[i],
            fixed_sum: sums.map_or(0, |s| s[i]),
        })
        .collect())
}

/// Samples per (variant, follower code + 3 × driving code) ([`outcome_code`]).
pub(crate) type PairCounts = BTreeMap<(Variant, i64), u64>;

/// Samples per (variant, follower code + 3 × driving code) (the codes of [`outcome_code`] for
/// `outcome`: 0 no, 1 yes, 2 unclassified or unknown) in one streaming pass, pairing each follower row with the row after it: explore writes each sample's rows
/// together, variant by variant, follower then driving. The query checks that (same sample_id
/// and variant, driving wheel) for every follower row; None when the files are ordered
/// otherwise (then [`pairs_by_sample`] pairs them).
pub(crate) fn pairs_in_row_order(
    files: &[PathBuf],
    has_scenarios: bool,
    outcome: OutcomeColumn<'_>,
) -> Result<Option<PairCounts>, AnalysisError> {
    let lf = Rows::scan_baseline(files, has_scenarios)?.lf;
    let next = |c: &str| col(c).shift(lit(-1i64));
    let df = collect(
        lf.select([
            col(VARIANT),
            col(WHEEL),
            col(SAMPLE),
            code_expr(outcome).alias("code"),
        ])
        .select([
            col(VARIANT),
            col("code"),
            next("code").alias("next_code"),
            col(WHEEL)
                .eq(lit(Wheel::Follower.as_str()))
                .alias("is_follower"),
            next(SAMPLE)
                .eq(col(SAMPLE))
                .and(next(VARIANT).eq(col(VARIANT)))
                .and(next(WHEEL).eq(lit(Wheel::Driving.as_str())))
                .fill_null(lit(false))
                .alias("pair_ok"),
        ])
        .filter(col("is_follower"))
        .group_by([col(VARIANT), col("pair_ok"), col("code"), col("next_code")])
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
        return Ok(None);
    }
    let (v, f, d, n) = (
        strs(&df, VARIANT)?,
        ints(&df, "code")?,
        ints(&df, "next_code")?,
        ints(&df, "n")?,
    );
    let mut combos = PairCounts::new();
    for i in 0..df.height() {
        let variant = v[i]
            .parse()
            .map_err(|e: UnknownName| AnalysisError::Row(e.to_string()))?;
        *combos.entry((variant, f[i] + 3 * d[i])).or_default() += n[i] as u64;
    }
    Ok(Some(combos))
}

/// [`pairs_in_row_order`] by grouping the rows by sample, for files in any row order. The two
/// wheels of a sample always lie in the same chunk file, so the files are grouped in batches of
/// about `batch_rows` rows: the group-by never holds more than one batch's samples.
pub(crate) fn pairs_by_sample(
    files: &[PathBuf],
    batch_rows: u64,
    has_scenarios: bool,
    outcome: OutcomeColumn<'_>,
) -> Result<PairCounts, AnalysisError> {
    // Per sample: follower + 3 × driving.
    let weight = when(col(WHEEL).eq(lit(Wheel::Follower.as_str())))
        .then(lit(1i64))
        .otherwise(lit(3i64));
    let mut combos = PairCounts::new();
    let mut start = 0;
    while start < files.len() {
        let mut end = start;
        let mut rows = 0u64;
        while end < files.len() && (end == start || rows < batch_rows) {
            rows += file_rows(&files[end]);
            end += 1;
        }
        let lf = Rows::scan_baseline(&files[start..end], has_scenarios)?.lf;
        let df = collect(
            lf.select([
                col(VARIANT),
                col(SAMPLE),
                (code_expr(outcome) * weight.clone()).alias("code"),
            ])
            .group_by([col(VARIANT), col(SAMPLE)])
            .agg([col("code").sum().alias("combo")])
            .group_by([col(VARIANT), col("combo")])
            .agg([len().cast(DataType::Int64).alias("n")]),
        )?;
        let v = strs(&df, VARIANT)?;
        let c = ints(&df, "combo")?;
        let n = ints(&df, "n")?;
        for i in 0..df.height() {
            let variant = v[i]
                .parse()
                .map_err(|e: UnknownName| AnalysisError::Row(e.to_string()))?;
            *combos.entry((variant, c[i])).or_default() += n[i] as u64;
        }
        start = end;
    }
    Ok(combos)
}

/// Rows per (class, reason) among the rows of `classes`, one file at a time (a file's distinct
/// reasons at most in memory: reasons carry numbers, so a run can have as many as rows), each
/// group handed to `each`.
pub(crate) fn reason_counts(
    files: &[PathBuf],
    classes: &[Class],
    each: &mut dyn FnMut(Class, &str, u64),
) -> Result<(), AnalysisError> {
    let wanted = classes.iter().fold(lit(false), |acc, c| {
        acc.or(col("class").eq(lit(c.as_str())))
    });
    for file in files {
        let df = collect(
            Rows::scan(std::slice::from_ref(file))?
                .lf
                .filter(wanted.clone())
                .group_by([col("class"), col("reason")])
                .agg([len().cast(DataType::Int64).alias("n")]),
        )?;
        let (class, reason, n) = (strs(&df, "class")?, strs(&df, "reason")?, ints(&df, "n")?);
        for i in 0..df.height() {
            let c = class[i]
                .parse()
                .map_err(|e: UnknownName| AnalysisError::Row(e.to_string()))?;
            each(c, &reason[i], n[i] as u64);
        }
    }
    Ok(())
}

/// Rows of a Parquet file, from its footer (0 when it cannot be read: the scan then says why).
fn file_rows(path: &Path) -> u64 {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    polywear_study::safe_read::open(path, polywear_study::safe_read::Limit::Chunk)
        .ok()
        .and_then(|(f, _)| SerializedFileReader::new(f).ok())
        .map(|r| r.metadata().file_metadata().num_rows() as u64)
        .unwrap_or(0)
}

/// Units of the fixed-point sums: 2^32 per range, so up to 2^31 rows sum without overflow.
pub(crate) const FIXED_POINT_SCALE: f64 = 4_294_967_296.0;

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

/// The bin index as a polars expression (Int64), by the rule of [`Bins::index`].
fn bin_expr(bins: &Bins, x: Expr) -> Expr {
    if bins.levels {
        return bins.midpoints().fold(lit(0i64), |acc, m| {
            acc + x.clone().gt(lit(m)).cast(DataType::Int64)
        });
    }
    let (lo, hi) = (bins.edges[0], *bins.edges.last().unwrap());
    let n = bins.count() as i64;
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

/// Runs a query on polars' streaming engine.
fn collect(lf: LazyFrame) -> Result<DataFrame, AnalysisError> {
    lf.collect_with_engine(Engine::Streaming)
        .map(|r| r.unwrap_single())
        .map_err(pl_err)
}

fn vib_expr() -> Expr {
    col(CLASS)
        .eq(lit(Class::LimitCycle.as_str()))
        .or(col(CLASS).eq(lit(Class::Bistable.as_str())))
}

/// [`outcome_code`] of the row's class; a class this version does not know is unclassified.
fn outcome_expr() -> Expr {
    Class::ALL.iter().rev().fold(lit(2i64), |otherwise, c| {
        when(col(CLASS).eq(lit(c.as_str())))
            .then(lit(outcome_code(*c)))
            .otherwise(otherwise)
    })
}

fn strs(df: &DataFrame, name: &str) -> Result<Vec<String>, AnalysisError> {
    Ok(df
        .column(name)
        .map_err(pl_err)?
        .str()
        .map_err(pl_err)?
        .iter()
        .map(|s| s.unwrap_or("").to_string())
        .collect())
}

fn ints(df: &DataFrame, name: &str) -> Result<Vec<i64>, AnalysisError> {
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

fn floats(df: &DataFrame, name: &str) -> Result<Vec<f64>, AnalysisError> {
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

/// Variant and wheel of each row of a grouped table.
fn variant_wheel(df: &DataFrame) -> Result<Vec<(Variant, Wheel)>, AnalysisError> {
    let v = strs(df, VARIANT)?;
    let w = strs(df, WHEEL)?;
    v.iter()
        .zip(&w)
        .map(|(v, w)| {
            Ok((
                v.parse::<Variant>()
                    .map_err(|e| AnalysisError::Row(e.to_string()))?,
                w.parse::<Wheel>()
                    .map_err(|e| AnalysisError::Row(e.to_string()))?,
            ))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

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
                .select([bin_expr(&bins, col("x")).alias("b")])
                .collect()
                .unwrap();
            let got = ints(&out, "b").unwrap();
            for (v, b) in values.iter().zip(got) {
                assert_eq!(Some(b as usize), bins.index(*v), "{v} in {bins:?}");
            }
        }
    }
}
