//! The inputs of an analysis: which Parquet files, what their footers say about the run, and
//! whether they belong together. Everything here reads only footers and manifests, so inputs
//! that do not belong together are refused before any row is read.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::AnalysisError;
use crate::explore::RunManifest;
use crate::model::Variant;
use crate::params::{ParamId, Params};
use crate::sampling::design::Design;
use crate::study::{text_hash, Scenario, Study};

/// What the files' metadata says about the run, read back typed.
#[derive(Debug, Clone)]
pub struct RunInfo {
    /// The study's `name` (the `study_name` metadata).
    pub study_name: String,
    /// The study's TOML text, from the manifest (chunk footers hold only its hash); "" when the
    /// inputs are chunk files without their directory's manifest.
    pub study_text: String,
    /// The study, parsed once from its recorded text on the run's recorded parameter values
    /// (and its operating-point file where the run found it); None without a recorded text, or
    /// for a text this version cannot read.
    pub study: Option<Study>,
    /// Fingerprint of the study text (`study_hash`).
    pub study_hash: String,
    /// The run's seed.
    pub seed: u64,
    /// Samples of the whole run (all shards).
    pub samples: u64,
    /// The sampling design.
    pub design: Design,
    /// The friction variants of the run, in the order of the rows.
    pub variants: Vec<Variant>,
    /// The polywear version that wrote the files (`polywear_version`).
    pub version: String,
    /// Names of the drawn parameters, in column order.
    pub drawn_names: Vec<ParamId>,
    /// Units of the columns (from the `units` metadata).
    pub units: BTreeMap<String, String>,
    /// The chunk files read, in order.
    pub files: Vec<PathBuf>,
    /// Distinct samples present in the files (each file holds a contiguous block of ids).
    pub samples_present: u64,
    /// Rows in the files.
    pub rows: u64,
    /// The values every parameter had before the draws (`params` metadata: the defaults, a
    /// parameter file and the study's fixed values).
    pub params: Params,
    /// The study's scenarios (`scenarios` metadata), in the order of each sample's row blocks
    /// after the baseline's; empty for a study without scenarios.
    pub scenarios: Vec<Scenario>,
}

impl RunInfo {
    /// The unit of column `name` from the `units` metadata ("" when none is recorded).
    pub fn unit(&self, name: &str) -> &str {
        self.units.get(name).map_or("", String::as_str)
    }

    /// The variants as the metadata writes them: `paper,combined`.
    pub fn variant_text(&self) -> String {
        self.variants
            .iter()
            .map(|v| v.as_str())
            .collect::<Vec<_>>()
            .join(",")
    }
}

/// One chunk file's footer, as far as the checks need it.
#[derive(Debug, Clone)]
struct FileFooter {
    path: PathBuf,
    meta: Vec<(String, String)>,
    /// The run as the footer records it (None when the metadata is not a run's).
    run: Option<RunManifest>,
    rows: u64,
    /// (min, max) of `sample_id` from the column statistics.
    id_range: Option<(i64, i64)>,
}

impl FileFooter {
    /// Whether the footer is an explore chunk's: it names the drawn values.
    fn is_explore(&self) -> bool {
        self.meta
            .iter()
            .any(|(k, _)| k == "drawn_names" || k == "drawn")
    }

    /// The run the footer records.
    fn run(&self) -> Result<&RunManifest, AnalysisError> {
        self.run.as_ref().ok_or_else(|| {
            let message = RunManifest::from_key_values(&self.meta)
                .err()
                .map_or_else(String::new, |e| e.to_string());
            AnalysisError::Metadata {
                path: self.path.clone(),
                message,
            }
        })
    }
}

/// The study's identity: `study_hash`, or the hash of the `study` text for older files.
fn study_hash(run: &RunManifest) -> String {
    run.study_hash
        .clone()
        .unwrap_or_else(|| text_hash(run.study.as_deref().unwrap_or("")))
}

/// The Parquet files behind the given inputs (files or directories), and the explore manifests
/// of the directories. A directory with a manifest and no chunk files (an empty shard) adds no
/// files; one with neither is not an explore output.
pub fn parquet_files(inputs: &[PathBuf]) -> Result<(Vec<PathBuf>, Vec<PathBuf>), AnalysisError> {
    let mut files = Vec::new();
    let mut manifests = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(input)
                .map_err(|e| AnalysisError::io(input, e))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.extension().is_some_and(|x| x == "parquet")
                        && !p
                            .file_name()
                            .is_some_and(|n| n.to_string_lossy().starts_with('_'))
                })
                .collect();
            found.sort();
            let manifest = input.join("_manifest.json");
            if manifest.is_file() {
                manifests.push(manifest);
            }
            files.extend(found);
        } else if input.is_file() {
            files.push(input.clone());
        } else {
            return Err(AnalysisError::NoSuchInput(input.clone()));
        }
    }
    if files.is_empty() {
        let inputs = inputs
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ");
        return Err(if manifests.is_empty() {
            AnalysisError::NoParquet { inputs }
        } else {
            AnalysisError::NoRows { inputs }
        });
    }
    Ok((files, manifests))
}

fn read_footer(path: &Path) -> Result<FileFooter, AnalysisError> {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::file::statistics::Statistics;
    let f = std::fs::File::open(path).map_err(|e| AnalysisError::io(path, e))?;
    let r = SerializedFileReader::new(f).map_err(|e| AnalysisError::io(path, e))?;
    let md = r.metadata();
    let meta: Vec<(String, String)> = md
        .file_metadata()
        .key_value_metadata()
        .map(|kv| {
            kv.iter()
                .map(|k| (k.key.clone(), k.value.clone().unwrap_or_default()))
                .collect()
        })
        .unwrap_or_default();
    let schema = md.file_metadata().schema_descr();
    let id_col = (0..schema.num_columns()).find(|&i| schema.column(i).name() == "sample_id");
    let mut id_range: Option<(i64, i64)> = None;
    let mut rows = 0u64;
    let mut stats_complete = true;
    for rg in md.row_groups() {
        rows += rg.num_rows() as u64;
        let Some(c) = id_col else {
            stats_complete = false;
            continue;
        };
        match rg.column(c).statistics() {
            Some(Statistics::Int64(s)) => match (s.min_opt(), s.max_opt()) {
                (Some(lo), Some(hi)) => {
                    id_range = Some(match id_range {
                        None => (*lo, *hi),
                        Some((a, b)) => (a.min(*lo), b.max(*hi)),
                    })
                }
                _ => stats_complete = rg.num_rows() == 0 && stats_complete,
            },
            _ => stats_complete = false,
        }
    }
    Ok(FileFooter {
        path: path.to_path_buf(),
        run: RunManifest::from_key_values(&meta).ok(),
        meta,
        rows,
        id_range: if stats_complete { id_range } else { None },
    })
}

/// Reads every footer and manifest and checks that the inputs belong together: the same study
/// text (`study_hash`), seed, variant set and sample count, and no sample's rows twice.
/// Returns what the metadata says about the run. Errors name both files and the key.
pub fn check_inputs(inputs: &[PathBuf]) -> Result<RunInfo, AnalysisError> {
    let (files, manifests) = parquet_files(inputs)?;
    let footers: Vec<FileFooter> = files
        .iter()
        .map(|p| read_footer(p))
        .collect::<Result<_, _>>()?;
    let first = &footers[0];
    if !first.is_explore() {
        return Err(AnalysisError::NotExplore {
            path: first.path.clone(),
        });
    }
    let run = first.run()?;
    let mismatch = |other: &Path, key: &'static str, ours: String, theirs: String| {
        if ours == theirs {
            return Ok(());
        }
        Err(AnalysisError::Mismatch {
            first: first.path.clone(),
            other: other.to_path_buf(),
            key,
            ours: short(&ours),
            theirs: short(&theirs),
        })
    };
    // The same run: compare every file with the first.
    for f in &footers[1..] {
        let theirs = f.run()?;
        // The specific keys first: two studies that differ only in their variants name `variant`.
        mismatch(
            &f.path,
            "seed",
            run.seed.to_string(),
            theirs.seed.to_string(),
        )?;
        mismatch(
            &f.path,
            "variant",
            run.variant_text(),
            theirs.variant_text(),
        )?;
        mismatch(
            &f.path,
            "samples",
            run.samples.to_string(),
            theirs.samples.to_string(),
        )?;
        mismatch(&f.path, "study_hash", study_hash(run), study_hash(theirs))?;
    }
    // Manifests (empty shards have only these) must describe the same run.
    let mut manifest_study: Option<String> = None;
    for m in &manifests {
        let text = std::fs::read_to_string(m).map_err(|e| AnalysisError::io(m, e))?;
        let recorded = RunManifest::from_json_text(&text).map_err(|e| AnalysisError::Metadata {
            path: m.clone(),
            message: e.to_string(),
        })?;
        let recorded_study = recorded.study.clone().unwrap_or_default();
        mismatch(m, "seed", run.seed.to_string(), recorded.seed.to_string())?;
        mismatch(
            m,
            "samples",
            run.samples.to_string(),
            recorded.samples.to_string(),
        )?;
        mismatch(m, "study_hash", study_hash(run), text_hash(&recorded_study))?;
        manifest_study.get_or_insert(recorded_study);
    }
    let variants = run.variants.clone().unwrap_or_else(|| vec![Variant::Paper]);
    let scenarios = scenarios_of(run, &first.path)?;
    let rows_per_sample = 2 * variants.len().max(1) as u64 * (1 + scenarios.len() as u64);
    // Each explore file holds a contiguous block of sample ids, every variant and wheel once:
    // rows = ids × rows per sample. Blocks of different files must not overlap.
    let mut blocks: Vec<(i64, i64, &FileFooter)> = Vec::new();
    let mut present = 0u64;
    let mut rows = 0u64;
    for f in &footers {
        rows += f.rows;
        let Some((lo, hi)) = f.id_range else {
            if f.rows == 0 {
                continue;
            }
            return Err(AnalysisError::NoIdStatistics {
                path: f.path.clone(),
            });
        };
        let ids = (hi - lo + 1) as u64;
        if f.rows != ids * rows_per_sample {
            return Err(AnalysisError::RowCount {
                path: f.path.clone(),
                rows: f.rows,
                ids: (lo, hi),
                per_sample: rows_per_sample,
            });
        }
        present += ids;
        blocks.push((lo, hi, f));
    }
    blocks.sort_by_key(|b| (b.0, b.1));
    for w in blocks.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        if b.0 <= a.1 {
            return Err(AnalysisError::Overlap {
                first: a.2.path.clone(),
                other: b.2.path.clone(),
                ids: (b.0, a.1.min(b.1)),
            });
        }
    }
    let drawn_names = match &run.drawn_names {
        Some(names) => names.clone(),
        // Files without `drawn_names` lead each `drawn` entry with its name (`name:...`).
        None => serde_json::from_value::<Vec<String>>(run.drawn.clone().unwrap_or_default())
            .unwrap_or_default()
            .iter()
            .filter_map(|d| d.split(':').next()?.parse().ok())
            .collect(),
    };
    let units = first
        .meta
        .iter()
        .find(|(k, _)| k == "units")
        .and_then(|(_, v)| serde_json::from_str(v).ok())
        .unwrap_or_default();
    let study_text = run.study.clone().or(manifest_study).unwrap_or_default();
    let dir = run
        .operating_points
        .as_ref()
        .and_then(|o| o.dir())
        .unwrap_or_default();
    let study = Study::parse_at(&study_text, run.params, &dir).ok();
    Ok(RunInfo {
        study_name: run.study_name.clone(),
        study_text,
        study,
        study_hash: study_hash(run),
        seed: run.seed,
        samples: run.samples,
        design: run.design.ok_or_else(|| AnalysisError::Metadata {
            path: first.path.clone(),
            message: "no `design` recorded".into(),
        })?,
        variants,
        version: run.polywear_version.clone(),
        drawn_names,
        units,
        files,
        samples_present: present,
        rows,
        params: run.params,
        scenarios,
    })
}

/// The scenarios a chunk footer records (none without the key).
fn scenarios_of(run: &RunManifest, path: &Path) -> Result<Vec<Scenario>, AnalysisError> {
    let Some(v) = &run.scenarios else {
        return Ok(Vec::new());
    };
    v.as_array()
        .and_then(|a| {
            a.iter()
                .map(Scenario::from_json)
                .collect::<Option<Vec<_>>>()
        })
        .ok_or_else(|| AnalysisError::Metadata {
            path: path.to_path_buf(),
            message: "`scenarios` is not a list of scenarios".into(),
        })
}

fn short(s: &str) -> String {
    let one_line = s.replace('\n', " ");
    if one_line.chars().count() > 60 {
        format!("{}…", one_line.chars().take(60).collect::<String>())
    } else {
        one_line
    }
}
