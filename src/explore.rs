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

use std::collections::{BTreeMap, HashSet};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use crate::classify::{classify_point_hinted, Class, ClassifierOptions, WheelVerdict};
use crate::model::{ModelFailure, Variant, Wheel};
use crate::output_dir::{self, DirLock};
use crate::parquet_out::{write_durably, write_table_digest, Column};
use crate::recorded_run::{changed_lines, occupied, param_changes, shell_word};
use crate::records::{record_columns, WheelRecord};
use crate::study::{Sampler, Study};

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

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// What one explore run does.
#[derive(Debug, Clone)]
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

/// The output directory, checked and locked for this run; the lock lasts as long as this value.
#[derive(Debug)]
pub struct PreparedOutput {
    _lock: DirLock,
    /// Chunks kept from an earlier run (verified); every other owned chunk is to do. A set of
    /// the kept ones, not a list of the pending ones: `--samples 1e10` starts at once.
    pub kept: HashSet<u64>,
    /// For a resume: each chunk that was found wanting and is redone, with the reason.
    pub redone: Vec<String>,
}

impl PreparedOutput {
    /// Owned chunks still to do, in order.
    pub fn pending<'a>(&'a self, plan: &'a RunPlan) -> impl Iterator<Item = u64> + 'a {
        plan.owned_chunks().filter(|c| !self.kept.contains(c))
    }

    /// Samples still to do.
    pub fn pending_samples(&self, plan: &RunPlan) -> u64 {
        plan.owned_samples() - self.kept_samples(plan)
    }

    /// Samples of the chunks kept from an earlier run.
    pub fn kept_samples(&self, plan: &RunPlan) -> u64 {
        self.kept.iter().map(|c| plan.chunk_len(*c)).sum()
    }
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

    fn manifest(&self) -> serde_json::Value {
        serde_json::json!({
            "polywear_version": env!("CARGO_PKG_VERSION"),
            "rng": crate::sampling::RNG_NAME,
            "study_name": self.study.name,
            "study": self.study.source,
            "study_hash": self.study.source_hash(),
            "params": serde_json::to_value(self.study.base).expect("json"),
            "seed": self.seed,
            "samples": self.samples,
            "chunk_size": self.study.chunk_size,
            "shard": self.shard.to_string(),
            "chunks": output_dir::JOURNAL,
            "checksum": "CRC-32 (IEEE) of each whole chunk file",
            "operating_points": self.study.operating_points.as_ref().map(|o| o.to_json()),
        })
    }

    /// Rows of chunk `chunk`: one per sample, variant and wheel.
    pub fn chunk_rows(&self, chunk: u64) -> u64 {
        self.chunk_len(chunk) * 2 * self.study.variants.len() as u64
    }

    /// Checks the output directory before any work and takes its lock: empty or absent for a
    /// new run (the manifest is then written); for `--resume`, holding the manifest of the same
    /// run, whose kept chunks are then verified against the journal (see
    /// [`RunPlan::verify_kept_chunks`]). `--resume` into an empty or absent directory starts
    /// the run, so a scheduler can always pass it. A directory locked by a running process is
    /// refused with its PID.
    pub fn prepare_output(&self) -> Result<PreparedOutput, ExploreError> {
        let dir = &self.out_dir;
        let e = |m: String| ExploreError(format!("--out {}: {m}", dir.display()));
        // An existing lock file is tried first (opening it creates nothing), so that a second
        // run is told who holds the directory. The lock is taken before the contents are
        // checked for good below; this first look only avoids creating a lock file in a
        // directory that is refused anyway.
        let mut lock = if dir.is_dir() {
            output_dir::lock(dir, false).map_err(|err| e(err.to_string()))?
        } else {
            None
        };
        let resuming = self.check_contents()?;
        if lock.is_none() {
            std::fs::create_dir_all(dir).map_err(|err| e(err.to_string()))?;
            lock = output_dir::lock(dir, true).map_err(|err| e(err.to_string()))?;
        }
        let lock = lock.expect("lock taken");
        // The authoritative check, under the lock.
        if self.check_contents()? != resuming {
            return Err(e(
                "changed by another process while starting; try again".into()
            ));
        }
        if resuming {
            let (kept, redone) = self.verify_kept_chunks()?;
            return Ok(PreparedOutput {
                _lock: lock,
                kept,
                redone,
            });
        }
        // A new run: temporary files of a run killed before its manifest existed go.
        for name in output_dir::entries(dir)
            .map_err(|err| e(err.to_string()))?
            .unwrap_or_default()
        {
            if name.ends_with(".partial") {
                std::fs::remove_file(dir.join(&name)).map_err(|err| e(err.to_string()))?;
            }
        }
        let text = serde_json::to_string_pretty(&self.manifest()).expect("json");
        write_durably(&dir.join(output_dir::MANIFEST), text.as_bytes())
            .map_err(|err| e(format!("cannot write: {err}")))?;
        Ok(PreparedOutput {
            _lock: lock,
            kept: HashSet::new(),
            redone: Vec::new(),
        })
    }

    /// Whether the directory holds a run to resume (`true`), or nothing (`false`: a new run);
    /// an error when it holds something else, or a different run.
    fn check_contents(&self) -> Result<bool, ExploreError> {
        let dir = &self.out_dir;
        let e = |m: String| ExploreError(format!("--out {}: {m}", dir.display()));
        let existing: Vec<String> = output_dir::entries(dir)
            .map_err(|err| e(err.to_string()))?
            .unwrap_or_default()
            .into_iter()
            .filter(|n| !output_dir::is_leftover(n))
            .collect();
        if existing.is_empty() {
            return Ok(false);
        }
        if !self.resume {
            return Err(e(occupied(dir)));
        }
        let manifest_path = dir.join(output_dir::MANIFEST);
        let text = std::fs::read_to_string(&manifest_path).map_err(|err| {
            e(format!(
                "nothing to resume here ({}: {err}); accepted: a directory written by `polywear explore`, or an empty or absent one",
                manifest_path.display()
            ))
        })?;
        let old: serde_json::Value = serde_json::from_str(&text)
            .map_err(|err| e(format!("unreadable {}: {err}", output_dir::MANIFEST)))?;
        let new = self.manifest();
        // A directory written by another generator (or with none recorded) holds rows this
        // build would not reproduce: never mix them.
        if old["rng"] != new["rng"] {
            return Err(e(format!(
                "--resume: this directory was written with another random generator ({}); this polywear uses {}, whose rows would differ: start a new directory",
                old["rng"].as_str().unwrap_or("none recorded, polywear before 0.2.0"),
                crate::sampling::RNG_NAME
            )));
        }
        if old["study"] != new["study"] {
            let lines = changed_lines(
                old["study"].as_str().unwrap_or(""),
                new["study"].as_str().unwrap_or(""),
            );
            return Err(e(format!(
                "--resume: this directory holds a run of another study; the lines that differ (- the run's, + this one's):\n    {}\nleave the study file out to continue the run with its own study, or choose another --out",
                lines.join("\n    ")
            )));
        }
        output_dir::same_operating_points(&old, &new)
            .map_err(|err| e(format!("--resume: {err}")))?;
        for key in [
            "polywear_version",
            "params",
            "seed",
            "samples",
            "chunk_size",
            "shard",
        ] {
            if old[key] != new[key] {
                let what = if key == "params" {
                    param_changes(&old[key], &new[key])
                } else {
                    format!("{key} {}, now {}", old[key], new[key])
                };
                return Err(e(format!(
                    "--resume: this directory holds a different run (the run's {what}); continue it with `--resume --out {}` alone, or choose another --out",
                    shell_word(&dir.display().to_string())
                )));
            }
        }
        Ok(true)
    }

    /// For `--resume`: checks every chunk file against the journal (row count, size, CRC-32),
    /// deletes those that fail and the leftovers of a killed run, and returns the chunks kept,
    /// with one line per redone chunk saying which and why. Linear in the files present.
    pub fn verify_kept_chunks(&self) -> Result<(HashSet<u64>, Vec<String>), ExploreError> {
        let dir = &self.out_dir;
        let e = |m: String| ExploreError(format!("--out {}: {m}", dir.display()));
        let journal = output_dir::read_journal(dir).map_err(|err| e(err.to_string()))?;
        let names = output_dir::entries(dir)
            .map_err(|err| e(err.to_string()))?
            .unwrap_or_default();
        let shard = self.shard;
        let mut present = HashSet::new();
        for name in &names {
            if name.ends_with(".partial") {
                // Leftovers of files that were being written when the run was killed.
                std::fs::remove_file(dir.join(name)).map_err(|err| e(err.to_string()))?;
            } else if let Some(c) = output_dir::chunk_index(name) {
                if c >= self.n_chunks() || !shard.owns(c) {
                    return Err(e(format!(
                        "{name} is not a chunk of this run (chunks 0..{} of shard {shard}); move it away and resume again",
                        self.n_chunks()
                    )));
                }
                present.insert(c);
            }
        }
        let mut kept = Vec::new();
        let mut redone = Vec::new();
        let mut kept_set = HashSet::new();
        let mut sorted: Vec<u64> = present.iter().copied().collect();
        sorted.sort_unstable();
        for c in sorted {
            let path = self.chunk_path(c);
            match output_dir::verify_chunk(&path, journal.get(&c), self.chunk_rows(c)) {
                None => {
                    kept.push(journal[&c]);
                    kept_set.insert(c);
                }
                Some(why) => {
                    redone.push(format!(
                        "{}: {why}; redoing it",
                        output_dir::chunk_file_name(c)
                    ));
                    std::fs::remove_file(&path).map_err(|err| e(err.to_string()))?;
                }
            }
        }
        let mut missing: Vec<u64> = journal
            .keys()
            .filter(|c| !present.contains(c) && **c < self.n_chunks() && shard.owns(**c))
            .copied()
            .collect();
        missing.sort_unstable();
        for c in missing {
            redone.push(format!(
                "{}: recorded in the manifest but missing; redoing it",
                output_dir::chunk_file_name(c)
            ));
        }
        output_dir::rewrite_journal(dir, &kept).map_err(|err| e(format!("cannot write: {err}")))?;
        Ok((kept_set, redone))
    }

    /// Runs the chunks still to do in `out` (from [`RunPlan::prepare_output`]); `progress` is
    /// called with each finished sample count.
    ///
    /// Chunks are pipelined: up to [`CHUNKS_IN_FLIGHT`] chunks have their samples queued on the
    /// worker pool at once, and the task that finishes a chunk writes its file and queues the
    /// next chunk, so no worker idles while a chunk's slowest samples finish. Each sample's rows
    /// go to their fixed place in their chunk, so the files are the same whatever the threads.
    pub fn run(
        &self,
        out: &PreparedOutput,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<RunSummary, ExploreError> {
        self.run_until(out, progress, &|| false)
    }

    /// [`RunPlan::run`] that stops early once `stop` returns true (a signal arrived): no chunk
    /// starts after that, samples not yet begun are skipped, and a chunk in flight is written
    /// only when all its samples were evaluated, else dropped. The journal thus records exactly
    /// the chunks on disk, and `--resume` redoes the dropped ones.
    pub fn run_until(
        &self,
        out: &PreparedOutput,
        progress: &(dyn Fn(u64) + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<RunSummary, ExploreError> {
        let sampler = self.study.sampler(self.seed, self.samples);
        let opts = ClassifierOptions {
            budget: self.study.budget,
            ..ClassifierOptions::default()
        };
        let summary = RunSummary {
            samples_skipped: out.kept_samples(self),
            ..RunSummary::default()
        };
        let pipe = Pipeline {
            plan: self,
            sampler: &sampler,
            opts: &opts,
            progress,
            stop,
            pending: Mutex::new(Box::new(out.pending(self))),
            summary: Mutex::new(summary),
            failure: Mutex::new(None),
        };
        rayon::scope_fifo(|s| {
            for _ in 0..CHUNKS_IN_FLIGHT {
                pipe.launch_next(s);
            }
        });
        if let Some(e) = pipe.failure.into_inner().expect("no panic holds the lock") {
            return Err(e);
        }
        Ok(pipe.summary.into_inner().expect("no panic holds the lock"))
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
            // The study text is kept once, in the manifest; its hash ties the chunk to it.
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
                serde_json::Value::from(self.study.value_names()).to_string(),
            ),
            ("chunk_size".into(), self.study.chunk_size.to_string()),
            ("shard".into(), self.shard.to_string()),
            (
                "params".into(),
                serde_json::to_string(&self.study.base).expect("json"),
            ),
            ("drawn".into(), self.study.drawn_json().to_string()),
        ];
        if let Some(op) = &self.study.operating_points {
            meta.push(("operating_points".into(), op.to_json().to_string()));
        }
        meta.push((
            "columns".into(),
            "one row per sample, variant and wheel; sample_id identifies the sample".into(),
        ));
        self.write_chunk_durably(chunk, &cols, &meta)
    }

    /// Writes a chunk crash-safely and records it in the journal (rows, size, CRC-32): a chunk
    /// is finished once its journal line is fsynced.
    fn write_chunk_durably(
        &self,
        chunk: u64,
        cols: &[Column],
        meta: &[(String, String)],
    ) -> Result<(), ExploreError> {
        let e = |m: String| ExploreError(format!("cannot write output: {m}"));
        let digest = write_table_digest(&self.chunk_path(chunk), cols, meta)
            .map_err(|err| e(err.to_string()))?;
        let rows = cols.first().map_or(0, |c| c.data.len() as u64);
        output_dir::append_journal(
            &self.out_dir,
            output_dir::ChunkEntry {
                chunk,
                rows,
                digest,
            },
        )
        .map_err(|err| {
            e(format!(
                "{}: {err}",
                self.out_dir.join(output_dir::JOURNAL).display()
            ))
        })
    }
}

/// Chunks whose samples are queued on the workers at once (see [`RunPlan::run`]).
pub const CHUNKS_IN_FLIGHT: usize = 2;

/// The shared state of one pipelined run.
struct Pipeline<'a> {
    plan: &'a RunPlan,
    sampler: &'a Sampler<'a>,
    opts: &'a ClassifierOptions,
    progress: &'a (dyn Fn(u64) + Sync),
    stop: &'a (dyn Fn() -> bool + Sync),
    /// The chunks still to launch, in order (lazily: a huge run starts at once).
    pending: Mutex<Box<dyn Iterator<Item = u64> + Send + 'a>>,
    summary: Mutex<RunSummary>,
    failure: Mutex<Option<ExploreError>>,
}

/// One chunk in flight: a slot per sample and how many are still running.
struct ChunkWork {
    chunk: u64,
    lo: u64,
    rows: Mutex<Vec<Option<SampleRows>>>,
    remaining: AtomicU64,
    /// A sample was skipped because the run is stopping: the chunk is not written.
    dropped: AtomicBool,
}

impl<'a> Pipeline<'a> {
    /// Queues every sample of the next pending chunk, unless none is left or a write failed.
    /// FIFO spawns: a worker runs its own queued samples oldest first, so the oldest chunk in
    /// flight always finishes first (LIFO spawns starved chunk 0 on one thread, forever).
    fn launch_next<'s>(&'s self, s: &rayon::ScopeFifo<'s>)
    where
        'a: 's,
    {
        if self.failure.lock().expect("lock").is_some() || (self.stop)() {
            return;
        }
        let Some(chunk) = self.pending.lock().expect("lock").next() else {
            return;
        };
        let plan = self.plan;
        let lo = chunk * plan.study.chunk_size;
        let hi = (lo + plan.study.chunk_size).min(plan.samples);
        let work = Arc::new(ChunkWork {
            chunk,
            lo,
            rows: Mutex::new((lo..hi).map(|_| None).collect()),
            remaining: AtomicU64::new(hi - lo),
            dropped: AtomicBool::new(false),
        });
        for i in lo..hi {
            let work = Arc::clone(&work);
            s.spawn_fifo(move |s| {
                if (self.stop)() {
                    work.dropped.store(true, Ordering::Release);
                } else {
                    let r = evaluate_sample(&plan.study, self.sampler, i, self.opts);
                    (self.progress)(1);
                    work.rows.lock().expect("lock")[(i - work.lo) as usize] = Some(r);
                }
                if work.remaining.fetch_sub(1, Ordering::AcqRel) == 1 {
                    if !work.dropped.load(Ordering::Acquire) {
                        self.finish(&work);
                    }
                    self.launch_next(s);
                }
            });
        }
    }

    /// Writes a complete chunk and counts its classes.
    fn finish(&self, work: &ChunkWork) {
        let rows: Vec<SampleRows> = std::mem::take(&mut *work.rows.lock().expect("lock"))
            .into_iter()
            .map(|r| r.expect("all samples done"))
            .collect();
        let mut counts: BTreeMap<(Variant, Wheel), BTreeMap<Class, u64>> = BTreeMap::new();
        for r in rows.iter().flat_map(|s| &s.records) {
            *counts
                .entry((r.variant, r.wheel))
                .or_default()
                .entry(r.class)
                .or_default() += 1;
        }
        if let Err(e) = self.plan.write_chunk(work.chunk, &rows) {
            self.failure.lock().expect("lock").get_or_insert(e);
            return;
        }
        let mut summary = self.summary.lock().expect("lock");
        for (key, classes) in counts {
            let entry = summary.classes.entry(key).or_default();
            for (class, n) in classes {
                *entry.entry(class).or_default() += n;
            }
        }
        summary.samples_evaluated += rows.len() as u64;
        summary.chunks_written += 1;
    }
}

/// The rows of one sample: its drawn values and one record per variant and wheel.
pub struct SampleRows {
    /// The sample's index.
    pub sample_id: u64,
    /// Values in [`Study::value_names`] order: drawn parameters, then operating-point columns.
    pub drawn: Vec<f64>,
    /// The operating-point row drawn (0-based), when the study has `[operating_points]`.
    pub operating_point_row: Option<usize>,
    /// One record per variant and wheel.
    pub records: Vec<WheelRecord>,
}

/// Draws sample `index` and classifies it for every variant and both wheels. A parameter set
/// that breaks a cross-parameter rule (e.g. mu_s > mu_m) becomes `failed` rows with the reason.
/// Each wheel's shooting starts from the last cycle found in the same sample (the follower's
/// for the driving wheel, the first variant's for the second), which saves Newton iterations.
pub fn evaluate_sample(
    study: &Study,
    sampler: &Sampler<'_>,
    index: u64,
    opts: &ClassifierOptions,
) -> SampleRows {
    let (p, drawn, operating_point_row) = sampler.sample_with_row(index);
    let invalid = p.validate().err();
    let mut records = Vec::with_capacity(2 * study.variants.len());
    let mut hint = None;
    for &variant in &study.variants {
        for wheel in Wheel::BOTH {
            let (model, verdict) = match &invalid {
                None => {
                    let (model, verdict, next) =
                        classify_point_hinted(&p, wheel, variant, opts, hint);
                    hint = next.or(hint);
                    (model, verdict)
                }
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
        operating_point_row,
        records,
    }
}

/// Operating-point parameters already present as record columns.
const RECORD_PARAMS: [&str; 4] = ["speed_kmh", "toe_deg", "load_n", "pressure_kpa"];

/// Columns of a chunk: sample_id, the operating-point row (1-based, as error messages count
/// the file's rows) when the study has one, the drawn values that are not record columns, then
/// the record columns.
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
    if study.operating_points.is_some() {
        let row = |s: &SampleRows| s.operating_point_row.map_or(0, |r| r as i64 + 1);
        let rows = flat.iter().map(|(s, _)| row(s)).collect();
        cols.push(Column::i64("operating_point_row", "", rows));
    }
    for (k, name) in study.value_names().into_iter().enumerate() {
        if !RECORD_PARAMS.contains(&name) {
            let unit = crate::params::spec(name).map_or("", |s| s.unit);
            cols.push(Column::f64(
                name,
                unit,
                flat.iter().map(|(s, _)| s.drawn[k]).collect(),
            ));
        }
    }
    let records: Vec<WheelRecord> = flat.iter().map(|(_, r)| (*r).clone()).collect();
    cols.extend(record_columns(&records));
    cols
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
}
