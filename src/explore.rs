//! The batch engine behind `polywear explore`: draws samples of a study, classifies every
//! sample for both wheels (and each variant) in parallel with rayon, and streams the rows to
//! Parquet, one file per chunk of samples.
//!
//! A chunk is the unit of output, resume and sharding. Its file is written under a temporary
//! name and renamed when complete, so after a kill a chunk is either whole or absent: `--resume`
//! skips whole chunks and redoes the rest, giving exactly the rows of an uninterrupted run.
//! Shard k of N owns the chunks whose index is k mod N; chunk files carry their global index,
//! so the shards' files together are the single-machine output.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::classify::{classify_point, ClassifierOptions, WheelVerdict};
use crate::model::{ModelFailure, Wheel};
use crate::parquet_out::{write_table, Column};
use crate::records::{record_columns, WheelRecord};
use crate::study::{Sampler, Study};

/// What one explore run does.
#[derive(Debug, Clone)]
pub struct RunPlan {
    pub study: Study,
    pub seed: u64,
    pub samples: u64,
    /// (k, N): this run evaluates chunks with index ≡ k (mod N).
    pub shard: (u64, u64),
    pub out_dir: PathBuf,
    pub resume: bool,
    /// The command line, stored in the metadata.
    pub command: String,
}

/// An explore problem; all are reported with exit code 2.
#[derive(Debug, Clone, PartialEq)]
pub struct ExploreError(pub String);

impl std::fmt::Display for ExploreError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ExploreError {}

/// Counts of classes per (variant, wheel) among the samples evaluated by this run.
#[derive(Debug, Clone, Default)]
pub struct RunSummary {
    pub samples_evaluated: u64,
    pub samples_skipped: u64,
    pub chunks_written: u64,
    pub classes: BTreeMap<(String, String), BTreeMap<String, u64>>,
}

impl RunPlan {
    pub fn n_chunks(&self) -> u64 {
        self.samples.div_ceil(self.study.chunk_size)
    }

    /// Global chunk indices this shard owns.
    pub fn owned_chunks(&self) -> impl Iterator<Item = u64> + '_ {
        let (k, n) = self.shard;
        (0..self.n_chunks()).filter(move |c| c % n == k)
    }

    /// Samples in chunk `chunk` (the last one may be short).
    pub fn chunk_len(&self, chunk: u64) -> u64 {
        (self.samples - chunk * self.study.chunk_size).min(self.study.chunk_size)
    }

    pub fn chunk_path(&self, chunk: u64) -> PathBuf {
        self.out_dir.join(format!("chunk-{chunk:07}.parquet"))
    }

    fn manifest(&self) -> serde_json::Value {
        serde_json::json!({
            "polywear_version": env!("CARGO_PKG_VERSION"),
            "rng": crate::sampling::RNG_NAME,
            "study_name": self.study.name,
            "study": self.study.source,
            "params": serde_json::to_value(self.study.base).expect("json"),
            "seed": self.seed,
            "samples": self.samples,
            "chunk_size": self.study.chunk_size,
            "shard": format!("{}/{}", self.shard.0, self.shard.1),
        })
    }

    /// Checks the output directory before any work: empty or absent for a new run; holding a
    /// manifest of the same run for `--resume` (which starts a new run in an empty or absent
    /// directory). Creates it and writes the manifest.
    pub fn prepare_output(&self) -> Result<(), ExploreError> {
        let dir = &self.out_dir;
        let e = |m: String| ExploreError(format!("--out {}: {m}", dir.display()));
        // Underscore: pyarrow and pandas skip it when reading the directory as a dataset.
        let manifest_path = dir.join("_manifest.json");
        let existing: Vec<_> = match std::fs::read_dir(dir) {
            Ok(rd) => rd.filter_map(|x| x.ok()).collect(),
            Err(err) if err.kind() == std::io::ErrorKind::NotFound => Vec::new(),
            Err(err) => return Err(e(err.to_string())),
        };
        // --resume on an absent or empty directory starts the run, so a scheduler can always pass it.
        if self.resume && !existing.is_empty() {
            let text = std::fs::read_to_string(&manifest_path).map_err(|err| {
                e(format!(
                    "nothing to resume here ({}: {err})",
                    manifest_path.display()
                ))
            })?;
            let old: serde_json::Value = serde_json::from_str(&text)
                .map_err(|err| e(format!("unreadable _manifest.json: {err}")))?;
            let new = self.manifest();
            // A directory written by another generator (or by a version before `rng` was
            // recorded) holds rows this build would not reproduce: never mix them.
            if old["rng"] != new["rng"] {
                return Err(e(format!(
                    "--resume: this directory was written with another random generator ({}); this polywear uses {}, whose rows would differ: start a new directory",
                    old["rng"].as_str().unwrap_or("none recorded, polywear before 0.2.0"),
                    crate::sampling::RNG_NAME
                )));
            }
            for key in [
                "polywear_version",
                "study",
                "params",
                "seed",
                "samples",
                "chunk_size",
                "shard",
            ] {
                if old[key] != new[key] {
                    return Err(e(format!(
                        "--resume: this directory holds a different run ({key} was {}, now {})",
                        short(&old[key]),
                        short(&new[key])
                    )));
                }
            }
            // Leftovers of chunks that were being written when the run was killed.
            for entry in existing {
                if entry.file_name().to_string_lossy().ends_with(".partial") {
                    std::fs::remove_file(entry.path()).map_err(|err| e(err.to_string()))?;
                }
            }
            return Ok(());
        }
        if !existing.is_empty() {
            return Err(e(
                "directory is not empty; use --resume to continue the run there, or choose another directory".into(),
            ));
        }
        std::fs::create_dir_all(dir).map_err(|err| e(err.to_string()))?;
        let text = serde_json::to_string_pretty(&self.manifest()).expect("json");
        std::fs::write(&manifest_path, text).map_err(|err| e(format!("cannot write: {err}")))?;
        Ok(())
    }

    /// Chunks still to do (all owned chunks, less complete files when resuming).
    pub fn pending_chunks(&self) -> Vec<u64> {
        self.owned_chunks()
            .filter(|c| !self.chunk_path(*c).exists())
            .collect()
    }

    /// Runs the pending chunks; `progress` is called with each finished sample count.
    pub fn run(&self, progress: &(dyn Fn(u64) + Sync)) -> Result<RunSummary, ExploreError> {
        let sampler = self.study.sampler(self.seed, self.samples);
        let opts = ClassifierOptions::default();
        let pending = self.pending_chunks();
        let mut summary = RunSummary {
            samples_skipped: self
                .owned_chunks()
                .filter(|c| !pending.contains(c))
                .map(|c| self.chunk_len(c))
                .sum(),
            ..RunSummary::default()
        };
        for chunk in pending {
            let lo = chunk * self.study.chunk_size;
            let hi = (lo + self.study.chunk_size).min(self.samples);
            let rows: Vec<SampleRows> = (lo..hi)
                .into_par_iter()
                .map(|i| {
                    let r = evaluate_sample(&self.study, &sampler, i, &opts);
                    progress(1);
                    r
                })
                .collect();
            for r in rows.iter().flat_map(|s| &s.records) {
                *summary
                    .classes
                    .entry((r.variant.to_string(), r.wheel.to_string()))
                    .or_default()
                    .entry(r.class.to_string())
                    .or_default() += 1;
            }
            summary.samples_evaluated += hi - lo;
            self.write_chunk(chunk, &rows)?;
            summary.chunks_written += 1;
        }
        Ok(summary)
    }

    fn write_chunk(&self, chunk: u64, rows: &[SampleRows]) -> Result<(), ExploreError> {
        let cols = chunk_columns(&self.study, rows);
        let mut meta = vec![
            (
                "polywear_version".to_string(),
                env!("CARGO_PKG_VERSION").to_string(),
            ),
            ("command".into(), self.command.clone()),
            ("rng".into(), crate::sampling::RNG_NAME.into()),
            ("study_name".into(), self.study.name.clone()),
            ("study".into(), self.study.source.clone()),
            ("study_hash".into(), self.study.source_hash()),
            ("seed".into(), self.seed.to_string()),
            ("samples".into(), self.samples.to_string()),
            ("design".into(), self.study.design.as_str().into()),
            (
                "variant".into(),
                self.study
                    .variants
                    .iter()
                    .map(|v| v.as_str())
                    .collect::<Vec<_>>()
                    .join(","),
            ),
            ("chunk".into(), chunk.to_string()),
            (
                "drawn_names".into(),
                serde_json::Value::from(
                    self.study.drawn.iter().map(|d| d.name).collect::<Vec<_>>(),
                )
                .to_string(),
            ),
            ("chunk_size".into(), self.study.chunk_size.to_string()),
            ("shard".into(), format!("{}/{}", self.shard.0, self.shard.1)),
            (
                "params".into(),
                serde_json::to_string(&self.study.base).expect("json"),
            ),
            (
                "drawn".into(),
                serde_json::Value::from(
                    self.study
                        .drawn
                        .iter()
                        .map(|d| format!("{}: {:?}", d.name, d.dist))
                        .collect::<Vec<_>>(),
                )
                .to_string(),
            ),
        ];
        meta.push((
            "columns".into(),
            "one row per sample, variant and wheel; sample_id identifies the sample".into(),
        ));
        write_table(&self.chunk_path(chunk), &cols, &meta)
            .map_err(|e| ExploreError(format!("cannot write output: {e}")))
    }
}

fn short(v: &serde_json::Value) -> String {
    let s = v.to_string();
    if s.len() > 60 {
        format!("{}…", &s[..60])
    } else {
        s
    }
}

/// The rows of one sample: its drawn values and one record per variant and wheel.
pub struct SampleRows {
    pub sample_id: u64,
    pub drawn: Vec<f64>,
    pub records: Vec<WheelRecord>,
}

/// Draws sample `index` and classifies it for every variant and both wheels. A parameter set
/// that breaks a cross-parameter rule (e.g. mu_s > mu_m) becomes `failed` rows with the reason.
pub fn evaluate_sample(
    study: &Study,
    sampler: &Sampler<'_>,
    index: u64,
    opts: &ClassifierOptions,
) -> SampleRows {
    let (p, drawn) = sampler.sample(index);
    let invalid = p.validate().err();
    let mut records = Vec::with_capacity(2 * study.variants.len());
    for &variant in &study.variants {
        for wheel in Wheel::BOTH {
            let (model, verdict) = match &invalid {
                None => classify_point(&p, wheel, variant, opts),
                Some(e) => {
                    let f = ModelFailure::Invalid(format!("invalid parameter set: {e}"));
                    let v = WheelVerdict::from_model_failure(&f);
                    (Err(f), v)
                }
            };
            records.push(WheelRecord::new(&p, wheel, variant, &model, &verdict));
        }
    }
    SampleRows {
        sample_id: index,
        drawn,
        records,
    }
}

/// Operating-point parameters already present as record columns.
const RECORD_PARAMS: [&str; 4] = ["speed_kmh", "toe_deg", "load_n", "pressure_kpa"];

/// Columns of a chunk: sample_id, the drawn parameters that are not record columns, then the
/// record columns.
pub fn chunk_columns(study: &Study, rows: &[SampleRows]) -> Vec<Column> {
    let flat: Vec<(&SampleRows, &WheelRecord)> = rows
        .iter()
        .flat_map(|s| s.records.iter().map(move |r| (s, r)))
        .collect();
    let mut cols = vec![Column::i64(
        "sample_id",
        "",
        flat.iter().map(|(s, _)| s.sample_id as i64).collect(),
    )];
    for (k, d) in study.drawn.iter().enumerate() {
        if !RECORD_PARAMS.contains(&d.name) {
            let unit = crate::params::spec(d.name).map_or("", |s| s.unit);
            cols.push(Column::f64(
                d.name,
                unit,
                flat.iter().map(|(s, _)| s.drawn[k]).collect(),
            ));
        }
    }
    let records: Vec<WheelRecord> = flat.iter().map(|(_, r)| (*r).clone()).collect();
    cols.extend(record_columns(&records));
    cols
}

/// Parses `--shard k/N` (k counted from 0, as Slurm array and Kubernetes indexed-job indices).
pub fn parse_shard(s: &str) -> Result<(u64, u64), String> {
    let (k, n) = s
        .split_once('/')
        .ok_or_else(|| format!("--shard `{s}`: expected k/N, e.g. 0/4"))?;
    let k: u64 = k
        .trim()
        .parse()
        .map_err(|_| format!("--shard `{s}`: k is not a whole number"))?;
    let n: u64 = n
        .trim()
        .parse()
        .map_err(|_| format!("--shard `{s}`: N is not a whole number"))?;
    if n == 0 || k >= n {
        return Err(format!("--shard `{s}`: need 0 <= k < N"));
    }
    Ok((k, n))
}

/// Parses `--samples`: 1e6, 1_000_000 and 1000000 all mean one million.
pub fn parse_samples(s: &str) -> Result<u64, String> {
    let t = s.trim().replace('_', "");
    let x: f64 = t
        .parse()
        .map_err(|_| format!("--samples `{s}` is not a number (e.g. 1e6, 1_000_000)"))?;
    if !x.is_finite() || x < 1.0 || x.fract() != 0.0 || x > (1u64 << 40) as f64 {
        return Err(format!(
            "--samples `{s}` must be a whole number in [1, 2^40]"
        ));
    }
    Ok(x as u64)
}

/// Default output directory for a study and seed.
pub fn default_out_dir(study: &Study, seed: u64) -> PathBuf {
    Path::new("data").join(format!("explore_{}_seed{seed}", study.name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_and_shards_parse() {
        assert_eq!(parse_samples("1e6"), Ok(1_000_000));
        assert_eq!(parse_samples("1_000_000"), Ok(1_000_000));
        assert_eq!(parse_samples("1000000"), Ok(1_000_000));
        assert!(parse_samples("1.5").is_err());
        assert!(parse_samples("0").is_err());
        assert!(parse_samples("-3").is_err());
        assert!(parse_samples("lots").is_err());
        assert_eq!(parse_shard("2/4"), Ok((2, 4)));
        assert!(parse_shard("4/4").is_err());
        assert!(parse_shard("1").is_err());
        assert!(parse_shard("0/0").is_err());
    }
}
