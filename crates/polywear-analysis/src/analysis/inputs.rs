//! The inputs of an analysis: which Parquet files, what their footers say about the run, and
//! whether they belong together. Everything here reads only footers and manifests, so inputs
//! that do not belong together, or were damaged, are refused before any row is read.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::footer::{self, FileFooter};
use super::quantities::SEVERITY_QUANTITIES;
use super::AnalysisError;
use polywear_core::model::Variant;
use polywear_core::params::{ParamId, Params};
use polywear_core::sampling::design::Design;
use polywear_study::explore::manifest::OperatingPointsRecord;
use polywear_study::explore::RunManifest;
use polywear_study::study::{text_hash, Scenario, Study};

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
    /// The study's operating-point file as the run recorded it (file, columns, weight), when
    /// the study has `[operating_points]`.
    pub operating_points: Option<OperatingPointsRecord>,
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

/// The study's identity: `study_hash`, or the hash of the `study` text for older files.
fn study_hash(run: &RunManifest) -> String {
    run.study_hash
        .clone()
        .unwrap_or_else(|| text_hash(run.study.as_deref().unwrap_or("")))
}

/// The Parquet files behind the given inputs (files or directories), and the explore manifests
/// of the directories. A directory with a manifest and no chunk files (an empty shard) adds no
/// files; one with neither is not an explore output.
pub(crate) fn parquet_files(
    inputs: &[PathBuf],
) -> Result<(Vec<PathBuf>, Vec<PathBuf>), AnalysisError> {
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

/// Reads every footer and manifest and checks that the inputs belong together: the same study
/// text (`study_hash`), seed, variant set and sample count, no sample's rows twice, sample ids
/// within the run, the columns of the types explore writes, and every chunk of a directory as
/// its journal records it (CRC-32). Returns what the metadata says about the run. Errors name
/// the files and the key.
pub fn check_inputs(inputs: &[PathBuf]) -> Result<RunInfo, AnalysisError> {
    let (files, manifests) = parquet_files(inputs)?;
    // The journal first: a damaged chunk is named as damaged, with the way back, even when its
    // footer no longer reads.
    for input in inputs.iter().filter(|i| i.is_dir()) {
        footer::verify_chunks(input, &files)?;
    }
    let footers: Vec<FileFooter> = files
        .iter()
        .map(|p| FileFooter::read(p))
        .collect::<Result<_, _>>()?;
    let first = &footers[0];
    if !first.is_explore() {
        return Err(AnalysisError::NotExplore {
            path: first.path.clone(),
        });
    }
    let run = first.run()?;
    check_same_run(first, &footers[1..])?;
    let manifest_study = check_manifests(first, &manifests)?;
    let variants = run.variants.clone().unwrap_or_else(|| vec![Variant::Paper]);
    let scenarios = scenarios_of(run, &first.path)?;
    let rows_per_sample = 2 * variants.len().max(1) as u64 * (1 + scenarios.len() as u64);
    let (present, rows) = sample_blocks(&footers, rows_per_sample, run.samples)?;
    let drawn_names = drawn_names(first)?;
    let quantities = SEVERITY_QUANTITIES.map(|q| q.name());
    for f in &footers {
        f.check_columns(&drawn_names, &quantities)?;
    }
    let units = match first.value("units") {
        None => BTreeMap::new(),
        Some(text) => serde_json::from_str(text).map_err(|e| AnalysisError::Metadata {
            path: first.path.clone(),
            message: format!("`units`: {e}"),
        })?,
    };
    let study_text = run.study.clone().or(manifest_study).unwrap_or_default();
    let dir = run
        .operating_points
        .as_ref()
        .and_then(|o| o.dir())
        .unwrap_or_default();
    // The text is the one every footer's `study_hash` names (checked above), so a study that
    // does not parse is one this version cannot read, or whose operating-point file moved: only
    // the nominal curves of the risk maps need it, and they are then left out.
    let study = Study::parse_at(&study_text, run.params, &dir).ok();
    // The wear columns of a run written on a retired wear answer (`wear_estimate` other than
    // the one polywear gives, or none: before it was a setting, the new tire's) are not this
    // version's answer, and are not analysed as if they were.
    if let Some(w) = &run.wear {
        let level = &w.wear_estimate;
        if let Some(why) = polywear_core::wear::retired_level(level) {
            return Err(AnalysisError::Metadata {
                path: first.path.clone(),
                message: format!(
                    "`wear.wear_estimate` = \"{level}\": {why}; run explore again for this version's answer, or analyze it with the polywear that wrote it ({})",
                    run.polywear_version
                ),
            });
        }
    }
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
        operating_points: run.operating_points.clone(),
        scenarios,
    })
}

/// Refuses a footer whose run differs from the first's: the specific keys first, so that two
/// studies that differ only in their variants name `variant`.
fn check_same_run(first: &FileFooter, others: &[FileFooter]) -> Result<(), AnalysisError> {
    let run = first.run()?;
    for f in others {
        let theirs = f.run()?;
        let pairs = [
            ("seed", run.seed.to_string(), theirs.seed.to_string()),
            ("variant", run.variant_text(), theirs.variant_text()),
            (
                "samples",
                run.samples.to_string(),
                theirs.samples.to_string(),
            ),
            ("study_hash", study_hash(run), study_hash(theirs)),
        ];
        for (key, ours, theirs) in pairs {
            mismatch(first, &f.path, key, ours, theirs)?;
        }
        // Every other parameter value and stage setting the footers record.
        if let Some((key, ours, theirs)) = super::same_run::first_difference(first, f) {
            return Err(AnalysisError::Mismatch {
                first: first.path.clone(),
                other: f.path.clone(),
                key,
                ours: short(&ours),
                theirs: short(&theirs),
            });
        }
    }
    Ok(())
}

/// Checks that the manifests (empty shards have only these) describe the first footer's run;
/// returns the first manifest's study text.
fn check_manifests(
    first: &FileFooter,
    manifests: &[PathBuf],
) -> Result<Option<String>, AnalysisError> {
    let run = first.run()?;
    let mut manifest_study: Option<String> = None;
    for m in manifests {
        let text = polywear_study::safe_read::read_text(m, polywear_study::safe_read::Limit::Text)
            .map_err(|e| AnalysisError::Io {
                path: m.clone(),
                message: e.reason(),
            })?;
        let recorded = RunManifest::from_json_text(&text).map_err(|e| AnalysisError::Metadata {
            path: m.clone(),
            message: e.to_string(),
        })?;
        let recorded_study = recorded
            .study
            .clone()
            .ok_or_else(|| AnalysisError::Metadata {
                path: m.clone(),
                message: "no `study` recorded".into(),
            })?;
        mismatch(
            first,
            m,
            "seed",
            run.seed.to_string(),
            recorded.seed.to_string(),
        )?;
        let samples = (run.samples.to_string(), recorded.samples.to_string());
        mismatch(first, m, "samples", samples.0, samples.1)?;
        let hashes = (study_hash(run), text_hash(&recorded_study));
        mismatch(first, m, "study_hash", hashes.0, hashes.1)?;
        manifest_study.get_or_insert(recorded_study);
    }
    Ok(manifest_study)
}

/// A refusal of `other` when its `key` differs from the first file's.
fn mismatch(
    first: &FileFooter,
    other: &Path,
    key: &'static str,
    ours: String,
    theirs: String,
) -> Result<(), AnalysisError> {
    if ours == theirs {
        return Ok(());
    }
    Err(AnalysisError::Mismatch {
        first: first.path.clone(),
        other: other.to_path_buf(),
        key: key.to_string(),
        ours: short(&ours),
        theirs: short(&theirs),
    })
}

/// Each explore file holds a contiguous block of sample ids within `[0, samples)`, every
/// variant and wheel once: rows = ids × rows per sample. Blocks of different files must not
/// overlap. Returns the samples present and the rows.
fn sample_blocks(
    footers: &[FileFooter],
    rows_per_sample: u64,
    samples: u64,
) -> Result<(u64, u64), AnalysisError> {
    let mut blocks: Vec<(i64, i64, &FileFooter)> = Vec::new();
    let mut present = 0u64;
    let mut rows = 0u64;
    for f in footers {
        rows += f.rows;
        let Some((lo, hi)) = f.id_range else {
            if f.rows == 0 {
                continue;
            }
            return Err(AnalysisError::NoIdStatistics {
                path: f.path.clone(),
            });
        };
        if lo < 0 || hi < lo || hi as u64 >= samples {
            return Err(AnalysisError::SampleIds {
                path: f.path.clone(),
                ids: (lo, hi),
                samples,
            });
        }
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
    Ok((present, rows))
}

/// The drawn parameters of the first footer: `drawn_names`, or for files without it the name
/// that leads each `drawn` entry (`name:...`). A list that cannot be read is refused by key.
fn drawn_names(first: &FileFooter) -> Result<Vec<ParamId>, AnalysisError> {
    let run = first.run()?;
    if let Some(names) = &run.drawn_names {
        return Ok(names.clone());
    }
    let bad = |message: String| AnalysisError::Metadata {
        path: first.path.clone(),
        message,
    };
    let entries: Vec<String> = serde_json::from_value(run.drawn.clone().unwrap_or_default())
        .map_err(|e| bad(format!("`drawn`: {e}")))?;
    entries
        .iter()
        .map(|d| {
            let name = d.split(':').next().unwrap_or_default();
            name.parse()
                .map_err(|e: polywear_core::params::ParamError| bad(format!("`drawn`: {e}")))
        })
        .collect()
}

/// The scenarios a chunk footer records (none without the key), each `compare_to` naming
/// another of them.
fn scenarios_of(run: &RunManifest, path: &Path) -> Result<Vec<Scenario>, AnalysisError> {
    let Some(v) = &run.scenarios else {
        return Ok(Vec::new());
    };
    let bad = |message: String| AnalysisError::Metadata {
        path: path.to_path_buf(),
        message,
    };
    let scenarios = v
        .as_array()
        .and_then(|a| {
            a.iter()
                .map(Scenario::from_json)
                .collect::<Option<Vec<_>>>()
        })
        .ok_or_else(|| bad("`scenarios` is not a list of scenarios".into()))?;
    reference_blocks(&scenarios).map_err(|e| bad(format!("`scenarios`: {e}")))?;
    Ok(scenarios)
}

fn short(s: &str) -> String {
    let one_line = s.replace('\n', " ");
    if one_line.chars().count() > 60 {
        format!("{}…", one_line.chars().take(60).collect::<String>())
    } else {
        one_line
    }
}

/// The row block each scenario is compared with, as `scenario_pairs` takes it: 0 for the
/// baseline, j + 1 for the scenario j (in row order) that its `compare_to` names. A name the
/// run does not hold is refused: the footers were written by a study that checked it.
pub(crate) fn reference_blocks(scenarios: &[Scenario]) -> Result<Vec<usize>, AnalysisError> {
    scenarios
        .iter()
        .map(|s| match &s.compare_to {
            None => Ok(0),
            Some(r) => scenarios
                .iter()
                .position(|o| o.name == *r && o.name != s.name)
                .map(|j| j + 1)
                .ok_or_else(|| {
                    AnalysisError::Row(format!(
                        "scenario `{}` is compared with `{r}`, which is not a scenario of the run",
                        s.name
                    ))
                }),
        })
        .collect()
}
