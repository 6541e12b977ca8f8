//! The pipelined evaluation of a run's chunks: samples classified in parallel on the worker
//! pool, each finished chunk written crash-safely and recorded in the journal.

use std::sync::Mutex;

use super::output::PreparedOutput;
use super::{ExploreError, RunPlan, RunSummary};
use crate::output_dir;
use crate::parquet_out::{write_table_digest, Column};
use crate::study::{Sampler, Study};
use polywear_core::classify::ClassifierOptions;
use polywear_core::ensemble::{self, Control};
use polywear_core::evaluate::{self, PointProblem, WearStage};
use polywear_core::model::Variant;
use polywear_core::params::Params;
use polywear_core::records::{record_columns, WheelRecord, OPERATING_POINT_ROW, SAMPLE_ID};

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
        let summary = Mutex::new(RunSummary {
            samples_skipped: out.kept_samples(self),
            ..RunSummary::default()
        });
        let size = self.study.chunk_size;
        // The baseline's records: the first block of each sample's.
        let block = 2 * self.study.variants.len();
        let chunks = out
            .pending(self)
            .map(|chunk| (chunk, chunk * size..(chunk * size + size).min(self.samples)));
        let finish = |chunk: u64, rows: Vec<SampleRows>| {
            self.write_chunk(chunk, &rows)?;
            summary.lock().expect("lock").count(&rows, block);
            Ok(())
        };
        let run = ensemble::solve_chunked(
            chunks,
            CHUNKS_IN_FLIGHT,
            |i| evaluate_sample(&self.study, &sampler, i, &opts, self.wear.as_ref()),
            finish,
            &Control { progress, stop },
        );
        if let Some((_, e)) = run.errors.into_iter().next() {
            return Err(e);
        }
        Ok(summary.into_inner().expect("no panic holds the lock"))
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

impl RunSummary {
    /// Counts a written chunk's samples, and the baseline's rows (the first `block` records of
    /// each sample) by variant, wheel and class.
    fn count(&mut self, rows: &[SampleRows], block: usize) {
        for r in rows.iter().flat_map(|s| &s.records[..block]) {
            *self
                .classes
                .entry((r.variant, r.wheel))
                .or_default()
                .entry(r.class)
                .or_default() += 1;
        }
        self.samples_evaluated += rows.len() as u64;
        self.chunks_written += 1;
    }
}

/// The rows of one sample: its drawn values and one record per scenario (the baseline first),
/// variant and wheel.
pub struct SampleRows {
    /// The sample's index.
    pub sample_id: u64,
    /// Values in [`Study::value_names`] order: drawn parameters, then operating-point columns.
    pub drawn: Vec<f64>,
    /// The operating-point row drawn (0-based), when the study has `[operating_points]`.
    pub operating_point_row: Option<usize>,
    /// One record per scenario, variant and wheel: blocks of one per variant and wheel, the
    /// baseline's, then each scenario's.
    pub records: Vec<WheelRecord>,
}

/// Draws sample `index` and evaluates it for every variant and both wheels, the baseline and
/// then each of the study's scenarios (the same draw with the scenario's changes: common random
/// numbers), each a point of its own on the one road ([`evaluate_params`]), with the wear stage
/// when `wear` is given.
pub fn evaluate_sample(
    study: &Study,
    sampler: &Sampler<'_>,
    index: u64,
    opts: &ClassifierOptions,
    wear: Option<&WearStage>,
) -> SampleRows {
    let (p, drawn, operating_point_row) = sampler.sample_with_row(index);
    let mut records = evaluate_params(&p, &study.variants, opts, wear);
    for scenario in &study.scenarios {
        records.extend(evaluate_params(
            &scenario.apply(&p),
            &study.variants,
            opts,
            wear,
        ));
    }
    SampleRows {
        sample_id: index,
        drawn,
        operating_point_row,
        records,
    }
}

/// One parameter set for every variant and both wheels, one record each: a point of the one
/// road ([`polywear_core::evaluate::solve`]), its wheels starting their shooting from the last cycle
/// found at the same point, then the wear stage when `wear` is given.
pub fn evaluate_params(
    p: &Params,
    variants: &[Variant],
    opts: &ClassifierOptions,
    wear: Option<&WearStage>,
) -> Vec<WheelRecord> {
    evaluate::solve(&PointProblem::new(*p, variants, opts).with_wear(wear)).into_records()
}

/// Columns of a chunk: sample_id, the operating-point row (1-based, as error messages count
/// the file's rows) and the passed-through columns when the study has one, the scenario when
/// the study has scenarios, the drawn values that are not record columns (as the row's
/// scenario changed them; none shares a record column's name), then the record columns.
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
        SAMPLE_ID.name,
        SAMPLE_ID.unit,
        flat.iter().map(|(s, _, _)| s.sample_id as i64).collect(),
    )];
    if let Some(op) = &study.operating_points {
        let row = |s: &SampleRows| s.operating_point_row.map_or(0, |r| r as i64 + 1);
        let rows = flat.iter().map(|(s, _, _)| row(s)).collect();
        cols.push(Column::i64(
            OPERATING_POINT_ROW.name,
            OPERATING_POINT_ROW.unit,
            rows,
        ));
        // The study's passed-through columns, at the row each sample drew.
        let drawn: Vec<usize> = flat
            .iter()
            .map(|(s, _, _)| s.operating_point_row.unwrap_or(0))
            .collect();
        cols.extend(op.pass_through_columns(&drawn));
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
    let records: Vec<WheelRecord> = flat.iter().map(|(_, _, r)| (*r).clone()).collect();
    let record_cols = record_columns(&records);
    // The operating axes are record columns already, and so is a drawn wear_share_straight
    // where the wear stage ran (its figures are the drawn value's): a file never holds one
    // name twice. A length in m gets a column whose name says so, its parameter's name kept
    // beside it for one version (`deprecated` metadata).
    for (k, id) in names.iter().enumerate() {
        let recorded = record_cols.iter().any(|c| c.name == id.name());
        if !id.is_operating_axis() && !recorded {
            let v: Vec<f64> = changed.iter().map(|row| row[k]).collect();
            if let Some(name) = polywear_core::records::unit_named_column(*id) {
                cols.push(Column::f64(name, id.spec().unit, v.clone()));
            }
            cols.push(Column::f64(id.name(), id.spec().unit, v));
        }
    }
    cols.extend(record_cols);
    cols
}
