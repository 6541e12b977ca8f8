//! The inputs of an analysis: which Parquet files, what their footers say about the run, and
//! whether they belong together. Everything here reads only footers and manifests, so inputs
//! that do not belong together are refused before any row is read.

use std::path::{Path, PathBuf};

use crate::params::Params;
use crate::study::{text_hash, Study};

/// What the files' metadata says about the run.
#[derive(Debug, Clone, Default)]
pub struct RunInfo {
    /// The study's `name` (the `study_name` metadata).
    pub study_name: String,
    /// The study's TOML text, from the manifest (chunk footers hold only its hash).
    pub study: String,
    /// Fingerprint of the study text (`study_hash`).
    pub study_hash: String,
    /// The run's seed, as written in the metadata.
    pub seed: String,
    /// Samples of the whole run (all shards), from the metadata.
    pub samples: u64,
    /// The sampling design's name (the `design` metadata).
    pub design: String,
    /// The variants of the run, as written in the metadata.
    pub variant: String,
    /// The polywear version that wrote the files (`polywear_version`).
    pub version: String,
    /// Names of the drawn parameters, in column order.
    pub drawn_names: Vec<String>,
    /// Units of the columns (from the `units` metadata).
    pub units: serde_json::Map<String, serde_json::Value>,
    /// The chunk files read, in order.
    pub files: Vec<PathBuf>,
    /// Distinct samples present in the files (each file holds a contiguous block of ids).
    pub samples_present: u64,
    /// Rows in the files.
    pub rows: u64,
    /// The values every parameter had before the draws (`params` metadata: the defaults, a
    /// `--params` file and the study's fixed values); None where the files do not record them.
    pub params: Option<Params>,
    /// The folder the run found a relative `[operating_points]` file in (from the recorded
    /// path), so that the study re-read here reads the same file.
    pub operating_points_dir: Option<PathBuf>,
}

impl RunInfo {
    /// The study as parsed from the metadata text, on the run's recorded parameter values (None
    /// for text this version cannot read).
    pub fn parsed_study(&self) -> Option<Study> {
        let dir = self.operating_points_dir.clone().unwrap_or_default();
        Study::parse_at(&self.study, self.params.unwrap_or_default(), &dir).ok()
    }

    /// The unit of column `name` from the `units` metadata ("" when none is recorded).
    pub fn unit(&self, name: &str) -> &str {
        self.units.get(name).and_then(|u| u.as_str()).unwrap_or("")
    }
}

/// One chunk file's footer, as far as the checks need it.
#[derive(Debug, Clone)]
struct FileFooter {
    path: PathBuf,
    meta: Vec<(String, String)>,
    rows: u64,
    /// (min, max) of `sample_id` from the column statistics.
    id_range: Option<(i64, i64)>,
}

impl FileFooter {
    fn get(&self, key: &str) -> Option<&str> {
        self.meta
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// The study's identity: `study_hash`, or the hash of the `study` text for older files.
    fn study_hash(&self) -> String {
        self.get("study_hash")
            .map(str::to_string)
            .unwrap_or_else(|| text_hash(self.get("study").unwrap_or("")))
    }
}

/// The Parquet files behind the given inputs (files or directories), and the explore manifests
/// of the directories. A directory with a manifest and no chunk files (an empty shard) adds no
/// files; one with neither is not an explore output.
pub fn parquet_files(inputs: &[PathBuf]) -> Result<(Vec<PathBuf>, Vec<PathBuf>), String> {
    let mut files = Vec::new();
    let mut manifests = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(input)
                .map_err(|e| format!("{}: {e}", input.display()))?
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
            return Err(format!("{}: no such file or directory", input.display()));
        }
    }
    if files.is_empty() {
        let names: Vec<String> = inputs.iter().map(|p| p.display().to_string()).collect();
        return Err(if manifests.is_empty() {
            format!(
                "no Parquet files in {}; accepted: an explore output directory (chunk-*.parquet), Parquet files, or several of them",
                names.join(", ")
            )
        } else {
            format!(
                "{} hold no rows: every directory is an explore output without chunk files (empty shards or a run stopped before its first chunk; `polywear explore --resume --out DIR` continues one)",
                names.join(", ")
            )
        });
    }
    Ok((files, manifests))
}

/// Footer key–value metadata of one Parquet file.
pub fn file_metadata(path: &Path) -> Result<Vec<(String, String)>, String> {
    Ok(read_footer(path)?.meta)
}

fn read_footer(path: &Path) -> Result<FileFooter, String> {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::file::statistics::Statistics;
    let f = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let r = SerializedFileReader::new(f).map_err(|e| format!("{}: {e}", path.display()))?;
    let md = r.metadata();
    let meta = md
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
        meta,
        rows,
        id_range: if stats_complete { id_range } else { None },
    })
}

/// Reads every footer and manifest and checks that the inputs belong together: the same study
/// text (`study_hash`), seed, variant set and sample count, and no sample's rows twice.
/// Returns what the metadata says about the run. Errors name both files and the key.
pub fn check_inputs(inputs: &[PathBuf]) -> Result<RunInfo, String> {
    let (files, manifests) = parquet_files(inputs)?;
    let footers: Vec<FileFooter> = files
        .iter()
        .map(|p| read_footer(p))
        .collect::<Result<_, _>>()?;
    let first = &footers[0];
    if first.get("drawn_names").is_none() && first.get("drawn").is_none() {
        return Err(format!(
            "{}: not an explore output (no `drawn_names` metadata); analyze reads what `polywear explore` writes",
            first.path.display()
        ));
    }
    // The same run: compare every file with the first.
    for f in &footers[1..] {
        let differs = |key: &str, a: String, b: String| -> Result<(), String> {
            if a != b {
                return Err(format!(
                    "{} and {} do not belong together: their `{key}` differs ({} vs {}); analyze one run at a time",
                    first.path.display(),
                    f.path.display(),
                    short(&a),
                    short(&b)
                ));
            }
            Ok(())
        };
        // The specific keys first: two studies that differ only in their variants name `variant`.
        for key in ["seed", "variant", "samples"] {
            differs(
                key,
                first.get(key).unwrap_or("").into(),
                f.get(key).unwrap_or("").into(),
            )?;
        }
        differs("study_hash", first.study_hash(), f.study_hash())?;
    }
    // Manifests (empty shards have only these) must describe the same run.
    let mut manifest_study: Option<String> = None;
    for m in &manifests {
        let text = std::fs::read_to_string(m).map_err(|e| format!("{}: {e}", m.display()))?;
        let v: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", m.display()))?;
        if manifest_study.is_none() {
            manifest_study = v["study"].as_str().map(str::to_string);
        }
        let as_text = |x: &serde_json::Value| match x {
            serde_json::Value::String(s) => s.clone(),
            other => other.to_string(),
        };
        for (key, theirs) in [
            ("seed", as_text(&v["seed"])),
            ("samples", as_text(&v["samples"])),
            ("study_hash", text_hash(v["study"].as_str().unwrap_or(""))),
        ] {
            let ours = if key == "study_hash" {
                first.study_hash()
            } else {
                first.get(key).unwrap_or("").to_string()
            };
            if ours != theirs {
                return Err(format!(
                    "{} and {} do not belong together: their `{key}` differs ({} vs {}); analyze one run at a time",
                    first.path.display(),
                    m.display(),
                    short(&ours),
                    short(&theirs)
                ));
            }
        }
    }
    let variants = first.get("variant").unwrap_or("paper").split(',').count() as u64;
    let rows_per_sample = 2 * variants.max(1);
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
            return Err(format!(
                "{}: no `sample_id` statistics in the footer; analyze reads what `polywear explore` writes",
                f.path.display()
            ));
        };
        let ids = (hi - lo + 1) as u64;
        if f.rows != ids * rows_per_sample {
            return Err(format!(
                "{}: {} rows for sample_id {lo}..={hi}, expected {} ({} per sample): duplicate or missing (sample_id, variant, wheel) rows",
                f.path.display(),
                f.rows,
                ids * rows_per_sample,
                rows_per_sample
            ));
        }
        present += ids;
        blocks.push((lo, hi, f));
    }
    blocks.sort_by_key(|b| (b.0, b.1));
    for w in blocks.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        if b.0 <= a.1 {
            return Err(format!(
                "{} and {} hold the same rows: duplicate (sample_id, variant, wheel) rows for sample_id {}..={} (the same directory given twice, or overlapping shards)",
                a.2.path.display(),
                b.2.path.display(),
                b.0,
                a.1.min(b.1)
            ));
        }
    }
    let get = |k: &str| first.get(k).unwrap_or("").to_string();
    let mut drawn_names: Vec<String> =
        serde_json::from_str(&get("drawn_names")).unwrap_or_default();
    if drawn_names.is_empty() {
        // Files without `drawn_names` lead each `drawn` entry with its name (`name:...`).
        let drawn: Vec<String> = serde_json::from_str(&get("drawn")).unwrap_or_default();
        drawn_names = drawn
            .iter()
            .filter_map(|d| d.split(':').next().map(str::to_string))
            .collect();
    }
    Ok(RunInfo {
        study_name: get("study_name"),
        study: first
            .get("study")
            .map(str::to_string)
            .or(manifest_study)
            .unwrap_or_default(),
        study_hash: first.study_hash(),
        seed: get("seed"),
        samples: get("samples").parse().unwrap_or(present),
        design: get("design"),
        variant: get("variant"),
        version: get("polywear_version"),
        drawn_names,
        units: serde_json::from_str(&get("units")).unwrap_or_default(),
        files,
        samples_present: present,
        rows,
        params: recorded_params(&get("params")),
        operating_points_dir: serde_json::from_str(&get("operating_points"))
            .ok()
            .and_then(|op| crate::recorded_run::operating_points_dir(&op)),
    })
}

/// The `params` metadata (a JSON object of every parameter's value) as [`Params`]; None when it
/// is missing or names a value this version cannot take.
fn recorded_params(json: &str) -> Option<Params> {
    let values: serde_json::Map<String, serde_json::Value> = serde_json::from_str(json).ok()?;
    let mut params = Params::default();
    for (name, value) in &values {
        params.set(name, value.as_f64()?).ok()?;
    }
    Some(params)
}

fn short(s: &str) -> String {
    let one_line = s.replace('\n', " ");
    if one_line.chars().count() > 60 {
        format!("{}…", one_line.chars().take(60).collect::<String>())
    } else {
        one_line
    }
}
