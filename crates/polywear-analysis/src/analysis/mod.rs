//! Analysis stage: reads explore output (Parquet) and answers what users ask of an overnight
//! run: how likely is self-excited vibration (and so polygonal wear) on driving and follower
//! wheels, where in the operating space does the risk live, how severe is it, and which
//! parameters drive it.
//!
//! Problem → result: [`inputs::check_inputs`] reads the footers and manifests (inputs that do
//! not belong together are refused before any row is read) into a [`RunInfo`]; [`run`] answers
//! every question for [`AnalysisOptions`] and returns an [`Analysis`], plain data.
//! [`crate::render`] writes its tables, figures and page.
//!
//! Vibration and wear are asked the same questions through one `outcome::Outcome` each
//! (`outcome::Vibrates`, `outcome::VisibleWithin`): `outcome::answer` computes the
//! probability per wheel, [`paired`] driving against follower, [`conditional`] per bin (on
//! [`bins`]), [`risk_map`] over pairs of axes and the counts per row of an operating-point
//! file into one [`outcome::OutcomeAnswer`], so [`Analysis::vibration`] and
//! [`Analysis::wear`] ([`wear_risk`], at each distance) are one type, drawn by one renderer.
//! The rest is one module per question: [`failures`] (why rows have no verdict), [`fleet`]
//! (each row's values, weight and share of the risk), [`severity`], [`given_data`]
//! (first-order indices from any design), [`sensitivity`] (Sobol indices of a Saltelli
//! design), [`robustness`], [`scenarios`] (each scenario against its reference, the baseline
//! or its `compare_to`, on the same samples); `rows` alone speaks to polars, and
//! `polywear_study::stats` holds the intervals and tests. In a run with scenarios every question but the last is
//! answered on the baseline's rows.
//!
//! P(vibration), the probability every table gives, is the share of classified rows (stable,
//! limit cycle, bistable) whose wheel vibrates: settles on a limit cycle, or is bistable (can be
//! kicked onto one). Rows that failed or have no traction are counted apart ([`counts`]).

pub mod band;
pub mod bins;
pub mod conditional;
pub mod counts;
pub mod failures;
pub mod fleet;
mod footer;
pub mod given_data;
pub mod inputs;
pub mod outcome;
pub mod paired;
pub(crate) mod quantities;
pub mod risk_map;
pub mod robustness;
pub(crate) mod rows;
mod same_run;
pub mod scenarios;
pub mod sensitivity;
pub mod severity;
pub(crate) use polywear_study::stats;
pub mod wear_risk;

use std::path::{Path, PathBuf};

use bins::Bins;
use counts::ClassCounts;
use failures::Failures;
use fleet::Fleet;
use given_data::FirstOrder;
pub(crate) use inputs::RunInfo;
use outcome::{AnswerPlan, MapAxes, OutcomeAnswer, Vibrates};
use risk_map::RiskMap;
use robustness::{Robustness, RobustnessSummary};
use rows::Rows;
use scenarios::ScenarioEffect;
use sensitivity::Sensitivity;
use severity::{Severity, SEVERITY_QUANTITIES};
use wear_risk::WearAnalysis;

use polywear_core::classify::Class;
use polywear_core::model::Variant;
use polywear_core::params::ParamId;

/// What an analysis computes: bins, risk maps, the smallest count shown, bootstrap resamples.
#[derive(Debug, Clone, PartialEq)]
pub struct AnalysisOptions {
    /// Bins per axis of the conditional probabilities.
    pub bins: usize,
    /// Bins per axis of the risk maps.
    pub map_bins: usize,
    /// Cells with fewer classified samples are shown as "too few", not as a probability.
    pub min_count: u64,
    /// Pairs of axes for risk maps (those absent from the run are skipped with a note).
    pub pairs: Vec<(ParamId, ParamId)>,
    /// Bootstrap resamples behind the Sobol indices' intervals.
    pub bootstrap: usize,
    /// The scenarios are compared on the risk of a visible polygon within this distance \[km\].
    pub scenario_within_km: f64,
    /// P(visible polygon within each of these distances) \[km\] (the wear stage's columns;
    /// `wear_risk::HEADLINE_WITHIN_KM` is always among them).
    pub within_km: Vec<f64>,
}

impl AnalysisOptions {
    /// Default bins per axis of the conditional probabilities.
    pub const DEFAULT_BINS: usize = 20;
    /// Default bins per axis of the risk maps.
    pub const DEFAULT_MAP_BINS: usize = 24;
    /// Default smallest classified count of a shown cell.
    pub const DEFAULT_MIN_COUNT: u64 = 30;
    /// Default bootstrap resamples of the Sobol indices' intervals.
    pub const DEFAULT_BOOTSTRAP: usize = 200;
    /// Default distance of the scenarios' wear comparison \[km\].
    pub const DEFAULT_SCENARIO_WITHIN_KM: f64 = 40_000.0;

    /// The risk maps always drawn: speed × toe-in and load × pressure.
    pub fn default_pairs() -> Vec<(ParamId, ParamId)> {
        vec![
            (ParamId::SpeedKmh, ParamId::ToeDeg),
            (ParamId::LoadN, ParamId::PressureKpa),
        ]
    }

    /// The size polars' streaming group-by should give its per-thread hot tables for this
    /// analysis: its largest group-by is a risk map's cells for every variant and both wheels
    /// (counted for every variant there is, as the run's are not known before its files are
    /// read). polars reads it from `POLARS_HOT_TABLE_SIZE`; see `rows::hot_table_size`.
    pub fn hot_table_size(&self) -> usize {
        rows::hot_table_size(Variant::ALL.len() * 2 * self.map_bins * self.map_bins)
    }
}

impl Default for AnalysisOptions {
    fn default() -> Self {
        AnalysisOptions {
            bins: Self::DEFAULT_BINS,
            map_bins: Self::DEFAULT_MAP_BINS,
            min_count: Self::DEFAULT_MIN_COUNT,
            pairs: Self::default_pairs(),
            bootstrap: Self::DEFAULT_BOOTSTRAP,
            scenario_within_km: Self::DEFAULT_SCENARIO_WITHIN_KM,
            within_km: wear_risk::DEFAULT_WITHIN_KM.to_vec(),
        }
    }
}

/// Everything an analysis computes: plain data for the printed summary and for
/// [`crate::render`].
#[derive(Debug, Clone)]
pub struct Analysis {
    /// What the files' metadata says about the run.
    pub info: RunInfo,
    /// The options it was computed with.
    pub options: AnalysisOptions,
    /// The vibration answer (`Vibrates`): P(vibration) per variant and wheel, driving
    /// against follower on the same samples, per bin of every drawn parameter, the risk maps
    /// over pairs of axes (their tables are written whether or not they are drawn), and per row
    /// of an operating-point file.
    pub vibration: OutcomeAnswer<ClassCounts>,
    /// The rows without a verdict, grouped by reason.
    pub failures: Failures,
    /// P(vibration) per row of the operating-point file with its values, weight and share of
    /// the fleet's risk (only for a study with one).
    pub fleet: Option<Fleet>,
    /// The maps of the vibration answer not drawn because too few of their cells hold enough
    /// samples.
    pub sparse_maps: Vec<SparseMap>,
    /// Cycle quantities among the vibrating rows.
    pub severity: Vec<Severity>,
    /// First-order indices of the vibration indicator from the rows (every design).
    pub first_order: Vec<FirstOrder>,
    /// The same indices for the wear outcome, a visible polygon within
    /// [`AnalysisOptions::scenario_within_km`] (empty without the wear stage's columns).
    pub first_order_wear: Vec<FirstOrder>,
    /// Sobol indices (only for a Saltelli design).
    pub sensitivity: Option<Vec<Sensitivity>>,
    /// P(vibration) per lost-digit decoding (only when the study draws decodings).
    pub robustness: Option<Robustness>,
    /// How often the driving wheel is less exposed, per variant.
    pub robustness_summary: Vec<RobustnessSummary>,
    /// Each scenario against its reference (empty without scenarios).
    pub scenarios: Vec<ScenarioEffect>,
    /// The wear answer (None for a run without the wear stage's columns).
    pub wear: Option<WearAnalysis>,
    /// The wear answer's calibration band (None without the band's file: a run with
    /// `--calibration-band off`, without the wear stage, or by an older polywear).
    pub band: Option<band::CalibrationBand>,
    /// Remarks for the report (skipped pairs, a design without Sobol indices, ...).
    pub notes: Vec<String>,
}

impl Analysis {
    /// Whether the map is drawn: not one of [`Analysis::sparse_maps`].
    pub fn is_drawn<C>(&self, map: &RiskMap<C>) -> bool {
        !is_sparse(&self.sparse_maps, map)
    }

    /// Class counts over every variant and wheel.
    pub fn totals(&self) -> ClassCounts {
        self.vibration.totals()
    }

    /// True when no row has a verdict (every row failed or had no traction).
    pub fn nothing_classified(&self) -> bool {
        self.totals().classified() == 0
    }

    /// The variants present in the rows, in order.
    pub fn variants(&self) -> Vec<Variant> {
        let mut v: Vec<Variant> = self
            .vibration
            .occurrence
            .iter()
            .map(|o| o.variant)
            .collect();
        v.sort();
        v.dedup();
        v
    }
}

/// A risk map left out: its axes, and how many of its cells hold at least `min_count`
/// classified samples on some wheel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SparseMap {
    /// The friction variant.
    pub variant: Variant,
    /// The horizontal axis.
    pub x: ParamId,
    /// The vertical axis.
    pub y: ParamId,
    /// Cells with enough samples.
    pub filled: usize,
    /// All cells.
    pub cells: usize,
}

/// A risk map is drawn only when at least this share of its cells holds enough samples: the
/// few rows of an operating-point file fill a handful of cells of a speed × toe-in grid, and a
/// map that is mostly grey says less than the per-row table.
pub(crate) const MIN_MAP_COVERAGE: f64 = 0.25;

/// Why an analysis cannot be done: inputs that do not belong together (named by file and key),
/// rows this version cannot read, or a failed query.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AnalysisError {
    /// A file or directory cannot be read.
    #[error("{}: {message}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// An input that does not exist.
    #[error("{}: no such file or directory", .0.display())]
    NoSuchInput(PathBuf),
    /// No Parquet file among the inputs.
    #[error("no Parquet files in {inputs}; accepted: an explore output directory (chunk-*.parquet), Parquet files, or several of them")]
    NoParquet {
        /// The inputs, comma-separated.
        inputs: String,
    },
    /// Only explore directories without chunk files (empty shards, or runs stopped before
    /// their first chunk, which a resume continues).
    #[error("{inputs} hold no rows: every directory is an explore output without chunk files (empty shards or a run stopped before its first chunk)")]
    NoRows {
        /// The inputs, comma-separated.
        inputs: String,
    },
    /// A Parquet file that explore did not write.
    #[error("{}: not an explore output (no `drawn_names` metadata); analyze reads what `polywear explore` writes", path.display())]
    NotExplore {
        /// The file.
        path: PathBuf,
    },
    /// A footer or manifest whose run metadata cannot be read.
    #[error("{}: the run's metadata cannot be read: {message}", path.display())]
    Metadata {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The run's calibration band cannot be used: unfinished, changed, of another run, or not
    /// a file explore wrote (the message says what to do).
    #[error("{}: {message}", path.display())]
    Band {
        /// The band's file or digest.
        path: PathBuf,
        /// What is wrong, and what to do.
        message: String,
    },
    /// Two inputs of different runs.
    #[error("{} and {} do not belong together: their `{key}` differs ({ours} vs {theirs}); analyze one run at a time", first.display(), other.display())]
    Mismatch {
        /// The first input file.
        first: PathBuf,
        /// The file that differs from it.
        other: PathBuf,
        /// The metadata key that differs (a field of a JSON value as `params.phi_s`).
        key: String,
        /// The first file's value (shortened).
        ours: String,
        /// The other file's value (shortened).
        theirs: String,
    },
    /// A file without `sample_id` statistics.
    #[error("{}: no `sample_id` statistics in the footer; analyze reads what `polywear explore` writes", path.display())]
    NoIdStatistics {
        /// The file.
        path: PathBuf,
    },
    /// A file whose rows are not every variant and wheel of each sample once.
    #[error("{}: {rows} rows for sample_id {}..={}, expected {} ({per_sample} per sample): duplicate or missing (sample_id, variant, wheel) rows", path.display(), ids.0, ids.1, (ids.1 - ids.0 + 1) as u64 * per_sample)]
    RowCount {
        /// The file.
        path: PathBuf,
        /// Its rows.
        rows: u64,
        /// Its sample ids, first and last.
        ids: (i64, i64),
        /// Rows per sample (two wheels per variant).
        per_sample: u64,
    },
    /// Two files holding rows of the same samples.
    #[error("{} and {} hold the same rows: duplicate (sample_id, variant, wheel) rows for sample_id {}..={} (the same directory given twice, or overlapping shards)", first.display(), other.display(), ids.0, ids.1)]
    Overlap {
        /// One file.
        first: PathBuf,
        /// The other.
        other: PathBuf,
        /// The shared sample ids, first and last.
        ids: (i64, i64),
    },
    /// A column the analysis reads that is missing or of another type than explore writes.
    #[error("{}: column `{column}` is {found}, expected {expected}; analyze reads the columns `polywear explore` writes (a rewritten file must keep their types)", path.display())]
    ColumnType {
        /// The file.
        path: PathBuf,
        /// The column.
        column: String,
        /// Its type in the file, or `missing`.
        found: String,
        /// The type explore writes.
        expected: String,
    },
    /// A chunk file that does not match the run's journal.
    #[error("{}: {why}; `polywear explore --resume --out {}` verifies every chunk and re-evaluates this one", path.display(), polywear_study::explore::recorded_run::shell_word(&dir.display().to_string()))]
    Damaged {
        /// The chunk file.
        path: PathBuf,
        /// How it differs from its journal entry.
        why: String,
        /// The run's directory.
        dir: PathBuf,
    },
    /// Sample ids outside the run's `[0, samples)`.
    #[error("{}: sample_id {}..={} lies outside the run's [0, {samples}) (`samples` = {samples} in its metadata)", path.display(), ids.0, ids.1)]
    SampleIds {
        /// The file.
        path: PathBuf,
        /// Its sample ids, first and last.
        ids: (i64, i64),
        /// The run's sample count.
        samples: u64,
    },
    /// Rows whose variant or wheel the footers do not describe.
    #[error("{}: {what}; every row's variant must be one of the footer's `variant` ({variants}), with one follower and one driving row per sample", path.display())]
    RowsDisagree {
        /// The file.
        path: PathBuf,
        /// What the rows hold.
        what: String,
        /// The footer's variants.
        variants: String,
    },
    /// A drawn value that is NaN or infinite (explore writes only finite ones).
    #[error("column `{column}` holds {rows} NaN or infinite values; explore writes only finite drawn values, so the files were changed after the run")]
    NotFinite {
        /// The column.
        column: String,
        /// Rows with such a value.
        rows: u64,
    },
    /// A wear column's value that the wear stage never writes.
    #[error("{}: column `{column}` holds {what} in {rows} rows; accepted: {accepted}; the file was changed after the run", path.display())]
    WearValue {
        /// The file.
        path: PathBuf,
        /// The column.
        column: &'static str,
        /// Rows with such a value.
        rows: u64,
        /// What they hold.
        what: &'static str,
        /// What the column accepts.
        accepted: &'static str,
    },
    /// Rows of a class this version does not know.
    #[error("{rows} rows have a `class` this version does not know; accepted: {}", Class::ALL.map(|c| c.as_str()).join(", "))]
    UnknownClass {
        /// How many.
        rows: u64,
    },
    /// A variant, wheel or class name this version does not know.
    #[error("{0}")]
    Row(String),
    /// polars failed.
    #[error("analysis query: {0}")]
    Query(String),
}

impl AnalysisError {
    fn io(path: &Path, e: impl std::fmt::Display) -> AnalysisError {
        AnalysisError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        }
    }
}

/// Rows of the paired comparison in a sample's outcome table use this many rows per file batch.
const PAIRED_BATCH_ROWS: u64 = 400_000;

/// A step of an analysis, reported when it is done (each is one or a few streaming queries).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// Rows per class, per variant and wheel.
    Occurrence,
    /// The paired comparison.
    Paired,
    /// The reasons of the rows without a verdict.
    Failures,
    /// The per-row table of an operating-point file.
    Fleet,
    /// The observed ranges of the axes and cycle quantities.
    Ranges,
    /// The conditional probabilities along one axis.
    Conditional,
    /// The risk maps of one pair of axes.
    RiskMap,
    /// The severity histograms.
    Severity,
    /// The first-order indices from the rows.
    FirstOrder,
    /// The Sobol indices.
    Sensitivity,
    /// The lost-digit decodings.
    Robustness,
    /// The scenarios against their references.
    Scenarios,
    /// The wear answer.
    Wear,
}

/// Answers every question of the analysis on checked inputs. polars' group tables are sized by
/// the process ([`AnalysisOptions::hot_table_size`]).
pub fn run(info: RunInfo, opts: &AnalysisOptions) -> Result<Analysis, AnalysisError> {
    run_with_progress(info, opts, &mut |_| {})
}

/// [`run`], calling `progress` after each [`Step`]: a caller can report progress, or hand the
/// memory a finished query freed back to the system (as the command line does).
pub fn run_with_progress(
    info: RunInfo,
    opts: &AnalysisOptions,
    progress: &mut dyn FnMut(Step),
) -> Result<Analysis, AnalysisError> {
    let mut notes = rows::deprecation_notes(&info.files)?;
    let has_scenarios = !info.scenarios.is_empty();
    let rows = Rows::scan_baseline(&info.files, has_scenarios)?;
    let quantities: Vec<&str> = SEVERITY_QUANTITIES.iter().map(|q| q.name()).collect();
    let axes: Vec<&str> = info.drawn_names.iter().map(|p| p.name()).collect();
    let ranges = rows.ranges(&axes, &quantities)?;
    progress(Step::Ranges);
    let axis_bins: Vec<(ParamId, Bins)> = info
        .drawn_names
        .iter()
        .map(|&axis| (axis, bins::axis_bins(&info, &ranges, axis, opts.bins)))
        .collect();
    let map_axes = map_axes(&info, &ranges, opts, &mut notes);
    let plan = AnswerPlan {
        info: &info,
        axis_bins: &axis_bins,
        maps: &map_axes,
        fleet: info.operating_points.is_some(),
        batch_rows: PAIRED_BATCH_ROWS,
    };
    let mut vibration = outcome::answer(&Vibrates, &rows, &plan, progress)?;
    let totals = vibration.totals();
    let unclassified = totals.total() - totals.classified();
    let failures = failures::failures(&info.files, totals.total(), unclassified)?;
    progress(Step::Failures);
    let fleet = fleet::fleet(&vibration.fleet, &info);
    let sparse_maps = sparse_maps(&vibration.maps, opts.min_count);
    draw_nominal_curves(&info, &mut vibration.maps, &sparse_maps);
    let severity = severity::severity(&rows, &ranges)?;
    progress(Step::Severity);
    let first_order = given_data::first_order_indices(&rows, &info, &ranges, opts.bootstrap)?;
    progress(Step::FirstOrder);
    let sensitivity = sensitivity::sensitivity(&rows, &info, opts.bootstrap)?;
    progress(Step::Sensitivity);
    let robustness = robustness::robustness(&rows, &info)?;
    progress(Step::Robustness);
    let robustness_summary = robustness
        .as_ref()
        .map(|r| r.summary(opts.min_count))
        .unwrap_or_default();
    let scenarios = scenarios::compare(
        &info,
        opts.scenario_within_km,
        PAIRED_BATCH_ROWS,
        &mut notes,
    )?;
    progress(Step::Scenarios);
    let has_wear = wear_risk::has_wear(&rows)?;
    if has_wear {
        rows::check_wear_values(&info.files)?;
    }
    let first_order_wear = if has_wear {
        let km = opts.scenario_within_km;
        given_data::first_order_wear_indices(&rows, &info, &ranges, opts.bootstrap, km)?
    } else {
        Vec::new()
    };
    let wear = if has_wear {
        Some(wear_on_drawn_maps(
            &rows,
            &info,
            opts,
            &axis_bins,
            &vibration.maps,
            &sparse_maps,
            progress,
        )?)
    } else {
        None
    };
    progress(Step::Wear);
    let band = calibration_band(wear.as_ref(), &info, &scenarios, opts)?;
    Ok(Analysis {
        info,
        options: opts.clone(),
        vibration,
        failures,
        fleet,
        sparse_maps,
        severity,
        first_order,
        first_order_wear,
        sensitivity,
        robustness,
        robustness_summary,
        scenarios,
        wear,
        band,
        notes,
    })
}

/// The wear answer on the maps that are drawn (the sparse ones left out), at each of the
/// options' distances.
fn wear_on_drawn_maps(
    rows: &Rows,
    info: &RunInfo,
    opts: &AnalysisOptions,
    axis_bins: &[(ParamId, Bins)],
    maps: &[RiskMap],
    sparse_maps: &[SparseMap],
    progress: &mut dyn FnMut(Step),
) -> Result<WearAnalysis, AnalysisError> {
    let drawn: Vec<&RiskMap> = maps.iter().filter(|m| !is_sparse(sparse_maps, m)).collect();
    let inputs = wear_risk::WearInputs {
        axis_bins,
        maps: drawn,
        batch_rows: PAIRED_BATCH_ROWS,
    };
    wear_risk::wear(rows, info, &opts.within_km, &inputs, progress)
}

/// The calibration band of the wear answer `wear` and the scenarios' effects, where the run
/// has both a wear answer and a band file (the band file is looked for, and checked, either
/// way).
fn calibration_band(
    wear: Option<&WearAnalysis>,
    info: &RunInfo,
    scenarios: &[ScenarioEffect],
    opts: &AnalysisOptions,
) -> Result<Option<band::CalibrationBand>, AnalysisError> {
    Ok(match (wear, band::band_file(info)?) {
        (Some(w), Some(footer)) => Some(band::band(
            &footer,
            info,
            w,
            scenarios,
            opts.scenario_within_km,
        )?),
        _ => None,
    })
}

/// The axes and bins of the risk maps of every pair of `opts.pairs` the run draws; a pair it
/// does not draw is a note.
fn map_axes(
    info: &RunInfo,
    ranges: &std::collections::BTreeMap<String, (f64, f64)>,
    opts: &AnalysisOptions,
    notes: &mut Vec<String>,
) -> Vec<MapAxes> {
    let mut out = Vec::new();
    for &(x, y) in &opts.pairs {
        if !info.drawn_names.contains(&x) || !info.drawn_names.contains(&y) {
            let axes: Vec<&str> = info.drawn_names.iter().map(|p| p.name()).collect();
            notes.push(format!(
                "risk map {x} × {y} skipped: the run does not draw both (it draws {})",
                axes.join(", ")
            ));
            continue;
        }
        out.push(MapAxes {
            x: (x, bins::axis_bins(info, ranges, x, opts.map_bins)),
            y: (y, bins::axis_bins(info, ranges, y, opts.map_bins)),
        });
    }
    out
}

/// The maps with too few filled cells to be drawn ([`MIN_MAP_COVERAGE`]).
fn sparse_maps(maps: &[RiskMap], min_count: u64) -> Vec<SparseMap> {
    maps.iter()
        .filter_map(|map| {
            let (filled, cells) = map.coverage(min_count);
            ((filled as f64) < MIN_MAP_COVERAGE * cells as f64).then_some(SparseMap {
                variant: map.variant,
                x: map.x,
                y: map.y,
                filled,
                cells,
            })
        })
        .collect()
}

/// Whether `map` is one of `sparse`.
fn is_sparse<C>(sparse: &[SparseMap], map: &RiskMap<C>) -> bool {
    sparse
        .iter()
        .any(|s| (s.variant, s.x, s.y) == (map.variant, map.x, map.y))
}

/// The nominal tire's Hopf curves over the box of each map that is drawn (the study's, when
/// it can be read back).
fn draw_nominal_curves(info: &RunInfo, maps: &mut [RiskMap], sparse: &[SparseMap]) {
    let Some(study) = &info.study else {
        return;
    };
    for map in maps.iter_mut().filter(|m| !is_sparse(sparse, m)) {
        map.nominal = polywear_study::chart::nominal_curves(
            study,
            map.variant,
            map.x.name(),
            map.y.name(),
            &risk_map::draw_edges(&map.x_bins),
            &risk_map::draw_edges(&map.y_bins),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn analysis_errors_name_files_and_keys_but_no_command_line_flag() {
        let e = AnalysisError::NoRows {
            inputs: "runs/a".into(),
        };
        assert!(!e.to_string().contains("--"), "{e}");
        let e = AnalysisError::Mismatch {
            first: "a.parquet".into(),
            other: "b.parquet".into(),
            key: "seed".into(),
            ours: "1".into(),
            theirs: "2".into(),
        };
        assert_eq!(
            e.to_string(),
            "a.parquet and b.parquet do not belong together: their `seed` differs (1 vs 2); analyze one run at a time"
        );
    }

    #[test]
    fn hot_tables_grow_with_the_risk_maps_within_bounds() {
        let size = |map_bins| {
            AnalysisOptions {
                map_bins,
                ..AnalysisOptions::default()
            }
            .hot_table_size()
        };
        assert_eq!(size(2), 16_384);
        assert_eq!(size(24), 65_536);
        assert_eq!(size(200), 1 << 22);
    }
}
