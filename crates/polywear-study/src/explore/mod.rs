//! The batch engine behind `polywear explore`: draws samples of a study, classifies every
//! sample for both wheels (and each variant) in parallel with rayon, and streams the rows to
//! Parquet, one file per chunk of samples.
//!
//! A chunk is the unit of output, resume and sharding. Its file is written under a temporary
//! name, fsynced and renamed when complete, then recorded (rows, size, CRC-32) in the manifest's
//! journal ([`crate::output_dir`]); `--resume` keeps the chunks that match their record, redoes
//! the rest and says which and why, giving exactly the rows of an uninterrupted run.
//! Shard k of N owns the chunks whose index is k mod N; chunk files carry their global index,
//! so the shards' files together are the single-machine output.

use std::collections::BTreeMap;
use std::path::PathBuf;

use crate::output_dir;
use crate::study::Study;
use polywear_core::classify::{Class, ClassifierOptions};
use polywear_core::evaluate::WearStage;
use polywear_core::model::{Variant, Wheel};

pub mod manifest;
mod output;
mod pipeline;
pub mod recorded_run;
mod request;
mod session;

pub use manifest::{OperatingPointsRecord, RunManifest, WearRecord};
pub use output::PreparedOutput;
pub use pipeline::{chunk_columns, evaluate_params, evaluate_sample, SampleRows, CHUNKS_IN_FLIGHT};
pub use request::{chunk_size_warning, default_out_dir, empty_shard_report, ExploreRequest};
pub use session::{BandChoice, ExploreEnd, ExploreObserver, ExploreSession, ExploreSessionError};

/// The part of a run one machine evaluates: the chunks whose index ≡ `index` (mod `count`),
/// shard k of N with k counted from 0 (as Slurm array and Kubernetes indexed-job indices).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard's index k, from 0.
    pub index: u64,
    /// The number of shards N.
    pub count: u64,
}

impl Shard {
    /// The whole run on one machine (0/1).
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// Shard `index` of `count`; None unless 0 <= index < count.
    pub fn new(index: u64, count: u64) -> Option<Shard> {
        (index < count).then_some(Shard { index, count })
    }

    /// Whether chunk `chunk` belongs to this shard.
    pub fn owns(self, chunk: u64) -> bool {
        chunk % self.count == self.index
    }
}

/// `k/N` as typed (k counted from 0); a refusal starts with the text quoted, for the caller to
/// prefix with its flag.
impl std::str::FromStr for Shard {
    type Err = ShardError;

    fn from_str(s: &str) -> Result<Shard, ShardError> {
        let text = || s.to_string();
        let (k, n) = s.split_once('/').ok_or_else(|| ShardError::Form(text()))?;
        let whole = |x: &str, which: &'static str| {
            x.trim().parse::<u64>().map_err(|_| ShardError::NotWhole {
                text: text(),
                which,
            })
        };
        let (k, n) = (whole(k, "k")?, whole(n, "N")?);
        Shard::new(k, n).ok_or_else(|| ShardError::Outside(text()))
    }
}

/// A shard as typed (`k/N`) refused; the message starts with the text quoted.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ShardError {
    /// Not of the form k/N.
    #[error("`{0}`: expected k/N, e.g. 0/4")]
    Form(String),
    /// k or N not a whole number.
    #[error("`{text}`: {which} is not a whole number")]
    NotWhole {
        /// The text typed.
        text: String,
        /// `k` or `N`.
        which: &'static str,
    },
    /// k not below N.
    #[error("`{0}`: need 0 <= k < N")]
    Outside(String),
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// What one explore run does. Built and checked by [`ExploreRequest::plan`] (the
/// study, the output folder and every resume rule), never from literal fields outside this
/// crate.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct RunPlan {
    /// The study.
    pub study: Study,
    /// The seed of the random streams.
    pub seed: u64,
    /// Samples of the whole run (all shards).
    pub samples: u64,
    /// This run evaluates the chunks of this shard.
    pub shard: Shard,
    /// The output directory.
    pub out_dir: PathBuf,
    /// Keep verified chunks of an earlier run in `out_dir` and do the rest.
    pub resume: bool,
    /// The command line, stored in the metadata.
    pub command: String,
    /// The wear stage after the classifier ([`RunPlan::wear_stage`] of the study), or `None`
    /// for a run without wear columns.
    pub wear: Option<WearStage>,
}

/// Why a run cannot start or go on; all are reported with exit code 2. The messages name the
/// directory, never a command-line flag: the command line says which flag gave it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExploreError {
    /// The output directory cannot be created, locked, listed or written.
    #[error("{}: {message}", dir.display())]
    OutputDir {
        /// The output directory.
        dir: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// Another process changed the directory between the first look and the lock.
    #[error("{}: changed by another process while starting; try again", dir.display())]
    Raced {
        /// The output directory.
        dir: PathBuf,
    },
    /// A new run into a directory that is not empty.
    #[error("{}: {state}", dir.display())]
    Occupied {
        /// The output directory.
        dir: PathBuf,
        /// What the directory holds.
        state: recorded_run::DirState,
    },
    /// A resume into a directory without a readable manifest.
    #[error("{}: nothing to resume here ({manifest}: {message}); accepted: a directory written by `polywear explore`, or an empty or absent one", dir.display())]
    NothingToResume {
        /// The output directory.
        dir: PathBuf,
        /// The manifest's path, as shown.
        manifest: String,
        /// Why it cannot be read.
        message: String,
    },
    /// The manifest is there but cannot be read as a run's.
    #[error("{}: unreadable {}: {message}", dir.display(), output_dir::MANIFEST)]
    UnreadableManifest {
        /// The output directory.
        dir: PathBuf,
        /// What is wrong with it.
        message: String,
    },
    /// The recorded run drew with another random generator (None: none recorded).
    #[error("{}: this directory was written with another random generator ({}); this polywear uses {}, whose rows would differ: start a new directory", dir.display(), recorded.as_deref().unwrap_or("none recorded, polywear before 0.2.0"), polywear_core::sampling::RNG_NAME)]
    OtherGenerator {
        /// The output directory.
        dir: PathBuf,
        /// The generator the run recorded.
        recorded: Option<String>,
    },
    /// The recorded run was written by another polywear version: its rows might not be this
    /// build's, so it is not continued (resuming it again would say the same).
    #[error("{}: this run was written by polywear {recorded}; polywear {} cannot continue it (its rows could differ from the {recorded} rows already saved): finish it with polywear {recorded}, or start a new run in another --out", dir.display(), crate::provenance::POLYWEAR_VERSION)]
    OtherVersion {
        /// The output directory.
        dir: PathBuf,
        /// The version the run recorded.
        recorded: String,
    },
    /// The recorded run is of another study text.
    #[error("{}: this directory holds a run of another study; the lines that differ (- the run's, + this one's):\n    {}", dir.display(), lines.join("\n    "))]
    OtherStudy {
        /// The output directory.
        dir: PathBuf,
        /// The differing lines (`recorded_run::changed_lines`).
        lines: Vec<String>,
    },
    /// The operating-point file changed since the run started.
    #[error("{}: the operating-point file changed since this run started ({recorded_path} had hash {recorded_hash}, {path} now has hash {hash}); its rows decide every sample's draw, so the chunks would not fit together: restore the file or start a new directory", dir.display())]
    OperatingPointsChanged {
        /// The output directory.
        dir: PathBuf,
        /// The file the run read ("none" without one).
        recorded_path: String,
        /// Its hash then ("none" without one).
        recorded_hash: String,
        /// The file read now ("none" without one).
        path: String,
        /// Its hash now ("none" without one).
        hash: String,
    },
    /// The recorded run differs in a value other than the study (version, parameters, seed,
    /// samples, chunk size, shard).
    #[error("{}: this directory holds a different run (the run's {what})", dir.display())]
    DifferentRun {
        /// The output directory.
        dir: PathBuf,
        /// What differs, as "seed 1, now 2".
        what: String,
    },
    /// A chunk file in the directory is not one of this run's (shard).
    #[error("{}: {name} is not a chunk of this run (chunks 0..{chunks} of shard {shard}); move it away and resume again", dir.display())]
    ForeignChunk {
        /// The output directory.
        dir: PathBuf,
        /// The file's name.
        name: String,
        /// Chunks of the run.
        chunks: u64,
        /// This run's shard.
        shard: Shard,
    },
    /// The wear stage cannot be calibrated for the run's nominal tire.
    #[error("the wear stage: {0} (leave it out with --no-wear or `wear = false`)")]
    Wear(String),
    /// A chunk file or the journal cannot be written.
    #[error("cannot write output: {0}")]
    Write(String),
}

/// Counts of classes per (variant, wheel) among the samples evaluated by this run.
#[derive(Debug, Clone, Default)]
pub struct RunSummary {
    /// Samples this run evaluated.
    pub samples_evaluated: u64,
    /// Samples of kept chunks (resume).
    pub samples_skipped: u64,
    /// Chunk files this run wrote.
    pub chunks_written: u64,
    /// Rows per class of the evaluated samples, per (variant, wheel).
    pub classes: BTreeMap<(Variant, Wheel), BTreeMap<Class, u64>>,
}

impl RunPlan {
    /// The wear stage of a run of `study`: its settings and the calibration at the reference
    /// follower of the study's base parameters (`None` when the study leaves wear out). The
    /// reference is one point of the run, not a sample: it is classified within the default
    /// budget, whatever the study's per-wheel budget.
    pub fn wear_stage(study: &Study) -> Result<Option<WearStage>, ExploreError> {
        let Some(settings) = study.wear else {
            return Ok(None);
        };
        let opts = ClassifierOptions::default();
        WearStage::for_run(&study.base, study.variants[0], settings, &opts)
            .map(Some)
            .map_err(|e| ExploreError::Wear(e.to_string()))
    }

    /// Chunks of the whole run.
    pub fn n_chunks(&self) -> u64 {
        self.samples.div_ceil(self.study.chunk_size)
    }

    /// Global chunk indices this shard owns.
    pub fn owned_chunks(&self) -> impl Iterator<Item = u64> + '_ {
        let Shard { index: k, count: n } = self.shard;
        (k..self.n_chunks()).step_by(n as usize)
    }

    /// Samples in the chunks this shard owns (closed form: no loop over the chunks).
    pub fn owned_samples(&self) -> u64 {
        let Shard { index: k, count: n } = self.shard;
        let chunks = self.n_chunks();
        if k >= chunks {
            return 0;
        }
        let owned = (chunks - 1 - k) / n + 1;
        let last = chunks - 1;
        let short_by = self.study.chunk_size - self.chunk_len(last);
        owned * self.study.chunk_size - if last % n == k { short_by } else { 0 }
    }

    /// Samples in chunk `chunk` (the last one may be short).
    pub fn chunk_len(&self, chunk: u64) -> u64 {
        (self.samples - chunk * self.study.chunk_size).min(self.study.chunk_size)
    }

    /// Path of chunk `chunk`'s file.
    pub fn chunk_path(&self, chunk: u64) -> PathBuf {
        self.out_dir.join(output_dir::chunk_file_name(chunk))
    }

    /// What the run is, as its manifest records it (written before the first chunk).
    pub fn manifest(&self) -> RunManifest {
        RunManifest {
            polywear_version: crate::provenance::POLYWEAR_VERSION.to_string(),
            command: None,
            rng: Some(polywear_core::sampling::RNG_NAME.to_string()),
            study_name: self.study.name.clone(),
            study: Some(self.study.source.clone()),
            study_hash: Some(self.study.source_hash()),
            seed: self.seed,
            samples: self.samples,
            design: None,
            variants: None,
            chunk: None,
            drawn_names: None,
            chunk_size: self.study.chunk_size,
            shard: self.shard,
            params: self.study.base,
            drawn: None,
            operating_points: self
                .study
                .operating_points
                .as_ref()
                .map(OperatingPointsRecord::of),
            chunks: Some(output_dir::JOURNAL.to_string()),
            checksum: Some("CRC-32 (IEEE) of each whole chunk file".to_string()),
            columns: None,
            scenarios: None,
            wear: self.wear.as_ref().map(WearRecord::of),
        }
    }

    /// What chunk `chunk`'s footer records: the run (the study text only by its hash, as the
    /// manifest keeps it once), the writing command, and what the rows hold.
    pub fn chunk_metadata(&self, chunk: u64) -> RunManifest {
        RunManifest {
            command: Some(self.command.clone()),
            study: None,
            design: Some(self.study.design),
            variants: Some(self.study.variants.clone()),
            chunk: Some(chunk),
            drawn_names: Some(value_params(&self.study)),
            drawn: Some(self.study.drawn_json()),
            chunks: None,
            checksum: None,
            columns: Some(if self.study.scenarios.is_empty() {
                "one row per sample, variant and wheel; sample_id identifies the sample".into()
            } else {
                "one row per sample, scenario, variant and wheel; sample_id identifies the sample, scenario the changes (baseline: none)".into()
            }),
            scenarios: (!self.study.scenarios.is_empty()).then(|| self.study.scenarios_json()),
            ..self.manifest()
        }
    }

    /// Rows of chunk `chunk`: one per sample, scenario (the baseline and each of the study's),
    /// variant and wheel.
    pub fn chunk_rows(&self, chunk: u64) -> u64 {
        let blocks = 1 + self.study.scenarios.len() as u64;
        self.chunk_len(chunk) * blocks * 2 * self.study.variants.len() as u64
    }
}

/// The parameters of a sample's drawn values, in [`Study::value_names`] order: the drawn
/// parameters, then the operating-point file's columns (named by the file's header).
pub(crate) fn value_params(study: &Study) -> Vec<polywear_core::params::ParamId> {
    let op = study.operating_points.iter().flat_map(|o| o.names.iter());
    study
        .drawn
        .iter()
        .map(|d| d.param)
        .chain(op.map(|n| n.parse().expect("an operating-point column is a parameter")))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn owned_samples_match_the_chunks() {
        let mut study = Study::parse(crate::study::DEFAULT_STUDY).unwrap();
        for (samples, chunk_size, n) in
            [(1, 1, 1), (10, 3, 2), (100, 7, 3), (64, 64, 5), (65, 8, 4)]
        {
            study.chunk_size = chunk_size;
            for k in 0..n {
                let plan = RunPlan {
                    study: study.clone(),
                    seed: 1,
                    samples,
                    shard: Shard::new(k, n).unwrap(),
                    out_dir: PathBuf::new(),
                    resume: false,
                    command: String::new(),
                    wear: None,
                };
                let by_loop: u64 = plan.owned_chunks().map(|c| plan.chunk_len(c)).sum();
                assert_eq!(
                    plan.owned_samples(),
                    by_loop,
                    "{samples} {chunk_size} {k}/{n}"
                );
            }
        }
    }

    fn plan() -> RunPlan {
        RunPlan {
            study: Study::parse(crate::study::DEFAULT_STUDY).unwrap(),
            seed: 2014,
            samples: 100,
            shard: Shard::new(1, 3).unwrap(),
            out_dir: PathBuf::new(),
            resume: false,
            command: "polywear explore --shard 1/3".into(),
            wear: None,
        }
    }

    #[test]
    fn a_chunk_footer_has_the_keys_pandas_users_read_and_reads_back_the_same() {
        let meta = plan().chunk_metadata(4);
        let kv = meta.to_key_values();
        let keys: Vec<&str> = kv.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(
            keys,
            [
                "polywear_version",
                "command",
                "rng",
                "study_name",
                "study_hash",
                "seed",
                "samples",
                "design",
                "variant",
                "chunk",
                "drawn_names",
                "chunk_size",
                "shard",
                "params",
                "drawn",
                "columns"
            ]
        );
        let get = |k: &str| kv.iter().find(|(key, _)| key == k).unwrap().1.as_str();
        assert_eq!(get("seed"), "2014");
        assert_eq!(get("shard"), "1/3");
        assert_eq!(get("chunk"), "4");
        assert_eq!(get("variant"), "sliding_share");
        assert!(
            get("drawn_names").starts_with("[\"speed_kmh\""),
            "{}",
            get("drawn_names")
        );
        assert!(get("params").starts_with('{'));
        assert_eq!(RunManifest::from_key_values(&kv).unwrap(), meta);
    }

    #[test]
    fn the_manifest_reads_back_the_same_and_holds_the_study_once() {
        let m = plan().manifest();
        let text = m.to_json_text();
        assert_eq!(RunManifest::from_json_text(&text).unwrap(), m);
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let keys: Vec<&String> = v.as_object().unwrap().keys().collect();
        assert_eq!(
            keys,
            [
                "checksum",
                "chunk_size",
                "chunks",
                "operating_points",
                "params",
                "polywear_version",
                "rng",
                "samples",
                "seed",
                "shard",
                "study",
                "study_hash",
                "study_name"
            ]
        );
        assert!(v["operating_points"].is_null());
        assert_eq!(v["seed"], 2014);
        // The chunks carry the study's hash, not its text.
        assert!(plan().chunk_metadata(0).study.is_none());
    }

    #[test]
    fn explore_errors_name_no_command_line_flag() {
        let dir = PathBuf::from("runs/a");
        let errors = [
            ExploreError::OtherGenerator {
                dir: dir.clone(),
                recorded: None,
            },
            ExploreError::OtherStudy {
                dir: dir.clone(),
                lines: vec!["- samples = 1".into()],
            },
            ExploreError::DifferentRun {
                dir: dir.clone(),
                what: "seed 1, now 2".into(),
            },
            ExploreError::Occupied {
                dir: dir.clone(),
                state: recorded_run::DirState::Foreign,
            },
            ExploreError::NothingToResume {
                dir: dir.clone(),
                manifest: "runs/a/_manifest.json".into(),
                message: "not found".into(),
            },
            ExploreError::ForeignChunk {
                dir,
                name: "chunk-0000009.parquet".into(),
                chunks: 3,
                shard: Shard::WHOLE,
            },
        ];
        for e in errors {
            let text = e.to_string();
            assert!(text.starts_with("runs/a: "), "{text}");
            assert!(!text.contains("--"), "{text}");
        }
    }
}
