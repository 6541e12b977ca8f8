//! The pipelined evaluation of a run's chunks: samples classified in parallel on the worker
//! pool, each finished chunk written crash-safely and recorded in the journal.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use super::output::PreparedOutput;
use super::{ExploreError, RunPlan, RunSummary};
use crate::classify::{classify_point_hinted, Class, ClassifierOptions, WheelVerdict};
use crate::model::{ModelFailure, Variant, Wheel};
use crate::output_dir;
use crate::params::Params;
use crate::parquet_out::{write_table_digest, Column};
use crate::records::{record_columns, WheelRecord};
use crate::study::{Sampler, Study};

impl RunPlan {
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
        let meta = self.chunk_metadata(chunk).to_key_values();
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
        let e = ExploreError::Write;
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
        // The baseline's rows: the first block of each sample's records.
        let block = 2 * self.plan.study.variants.len();
        for r in rows.iter().flat_map(|s| &s.records[..block]) {
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

/// Draws sample `index` and classifies it for every variant and both wheels, the baseline and
/// then each of the study's scenarios (the same draw with the scenario's changes: common random
/// numbers), each evaluated exactly as [`evaluate_params`] evaluates a plain sample.
pub fn evaluate_sample(
    study: &Study,
    sampler: &Sampler<'_>,
    index: u64,
    opts: &ClassifierOptions,
) -> SampleRows {
    let (p, drawn, operating_point_row) = sampler.sample_with_row(index);
    let mut records = evaluate_params(&p, &study.variants, opts);
    for scenario in &study.scenarios {
        records.extend(evaluate_params(&scenario.apply(&p), &study.variants, opts));
    }
    SampleRows {
        sample_id: index,
        drawn,
        operating_point_row,
        records,
    }
}

/// Classifies one parameter set for every variant and both wheels, one record each. A set that
/// breaks a cross-parameter rule (e.g. mu_s > mu_m) becomes `failed` rows with the reason.
/// Each wheel's shooting starts from the last cycle found for the same set (the follower's for
/// the driving wheel, the first variant's for the second), which saves Newton iterations.
pub fn evaluate_params(
    p: &Params,
    variants: &[Variant],
    opts: &ClassifierOptions,
) -> Vec<WheelRecord> {
    let invalid = p.validate().err();
    let mut records = Vec::with_capacity(2 * variants.len());
    let mut hint = None;
    for &variant in variants {
        for wheel in Wheel::BOTH {
            let (model, verdict) = match &invalid {
                None => {
                    let (model, verdict, next) =
                        classify_point_hinted(p, wheel, variant, opts, hint);
                    hint = next.or(hint);
                    (model, verdict)
                }
                Some(e) => {
                    let f = ModelFailure::Invalid(format!("invalid parameter set: {e}"));
                    let v = WheelVerdict::from_model_failure(&f);
                    (Err(f), v)
                }
            };
            records.push(WheelRecord::new(p, wheel, variant, &model, &verdict));
        }
    }
    records
}

/// Columns of a chunk: sample_id, the operating-point row (1-based, as error messages count
/// the file's rows) when the study has one, the scenario when the study has scenarios, the
/// drawn values that are not record columns (as the row's scenario changed them), then the
/// record columns.
pub fn chunk_columns(study: &Study, rows: &[SampleRows]) -> Vec<Column> {
    // A sample's records are blocks of one per variant and wheel: the baseline's, then each
    // scenario's.
    let block = 2 * study.variants.len();
    let names = super::value_params(study);
    let flat: Vec<(&SampleRows, usize, &WheelRecord)> = rows
        .iter()
        .flat_map(|s| {
            s.records
                .iter()
                .enumerate()
                .map(move |(k, r)| (s, k / block, r))
        })
        .collect();
    let mut cols = vec![Column::i64(
        "sample_id",
        "",
        flat.iter().map(|(s, _, _)| s.sample_id as i64).collect(),
    )];
    if study.operating_points.is_some() {
        let row = |s: &SampleRows| s.operating_point_row.map_or(0, |r| r as i64 + 1);
        let rows = flat.iter().map(|(s, _, _)| row(s)).collect();
        cols.push(Column::i64("operating_point_row", "", rows));
    }
    if !study.scenarios.is_empty() {
        let all = study.scenario_names();
        let names = flat.iter().map(|(_, b, _)| all[*b].to_string()).collect();
        cols.push(Column::str("scenario", names));
    }
    // Each row's drawn values as its scenario changes them (block 0: the baseline's, as drawn).
    let values = |s: &SampleRows, b: usize| -> Vec<f64> {
        match b {
            0 => s.drawn.clone(),
            _ => study.scenarios[b - 1].apply_values(&names, &s.drawn),
        }
    };
    let changed: Vec<Vec<f64>> = flat.iter().map(|(s, b, _)| values(s, *b)).collect();
    // The operating axes are record columns already.
    for (k, id) in names.iter().enumerate() {
        if !id.is_operating_axis() {
            let v = changed.iter().map(|row| row[k]).collect();
            cols.push(Column::f64(id.name(), id.spec().unit, v));
        }
    }
    let records: Vec<WheelRecord> = flat.iter().map(|(_, _, r)| (*r).clone()).collect();
    cols.extend(record_columns(&records));
    cols
}
