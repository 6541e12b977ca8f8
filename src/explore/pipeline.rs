//! The pipelined evaluation of a run's chunks: samples classified in parallel on the worker
//! pool, each finished chunk written crash-safely and recorded in the journal.

use std::sync::Mutex;

use super::output::PreparedOutput;
use super::{ExploreError, RunPlan, RunSummary};
use crate::classify::ClassifierOptions;
use crate::ensemble::{self, Control};
use crate::evaluate::{self, PointProblem};
use crate::output_dir;
use crate::parquet_out::{write_table_digest, Column};
use crate::records::{record_columns, WheelRecord, OPERATING_POINT_ROW, SAMPLE_ID};
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
        let summary = Mutex::new(RunSummary {
            samples_skipped: out.kept_samples(self),
            ..RunSummary::default()
        });
        let size = self.study.chunk_size;
        let chunks = out
            .pending(self)
            .map(|chunk| (chunk, chunk * size..(chunk * size + size).min(self.samples)));
        let finish = |chunk: u64, rows: Vec<SampleRows>| {
            self.write_chunk(chunk, &rows)?;
            summary.lock().expect("lock").count(&rows);
            Ok(())
        };
        let run = ensemble::solve_chunked(
            chunks,
            CHUNKS_IN_FLIGHT,
            |i| evaluate_sample(&self.study, &sampler, i, &opts),
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
    /// Counts a written chunk's samples and rows by variant, wheel and class.
    fn count(&mut self, rows: &[SampleRows]) {
        for r in rows.iter().flat_map(|s| &s.records) {
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

/// Draws sample `index` and evaluates it for every variant and both wheels (the one road,
/// [`crate::evaluate::solve`]).
pub fn evaluate_sample(
    study: &Study,
    sampler: &Sampler<'_>,
    index: u64,
    opts: &ClassifierOptions,
) -> SampleRows {
    let (p, drawn, operating_point_row) = sampler.sample_with_row(index);
    let records = evaluate::solve(&PointProblem::new(p, &study.variants, opts)).into_records();
    SampleRows {
        sample_id: index,
        drawn,
        operating_point_row,
        records,
    }
}

/// Columns of a chunk: sample_id, the operating-point row (1-based, as error messages count
/// the file's rows) when the study has one, the drawn values that are not record columns, then
/// the record columns.
pub fn chunk_columns(study: &Study, rows: &[SampleRows]) -> Vec<Column> {
    let flat: Vec<(&SampleRows, &WheelRecord)> = rows
        .iter()
        .flat_map(|s| s.records.iter().map(move |r| (s, r)))
        .collect();
    let mut cols = vec![Column::i64(
        SAMPLE_ID.name,
        SAMPLE_ID.unit,
        flat.iter().map(|(s, _)| s.sample_id as i64).collect(),
    )];
    if let Some(op) = &study.operating_points {
        let row = |s: &SampleRows| s.operating_point_row.map_or(0, |r| r as i64 + 1);
        let rows = flat.iter().map(|(s, _)| row(s)).collect();
        cols.push(Column::i64(
            OPERATING_POINT_ROW.name,
            OPERATING_POINT_ROW.unit,
            rows,
        ));
        // The study's passed-through columns, at the row each sample drew.
        let drawn: Vec<usize> = flat
            .iter()
            .map(|(s, _)| s.operating_point_row.unwrap_or(0))
            .collect();
        cols.extend(op.pass_through_columns(&drawn));
    }
    // The operating axes are record columns already.
    for (k, id) in super::value_params(study).into_iter().enumerate() {
        if !id.is_operating_axis() {
            cols.push(Column::f64(
                id.name(),
                id.spec().unit,
                flat.iter().map(|(s, _)| s.drawn[k]).collect(),
            ));
        }
    }
    let records: Vec<WheelRecord> = flat.iter().map(|(_, r)| (*r).clone()).collect();
    cols.extend(record_columns(&records));
    cols
}
