//! A run's wear answer under every calibrated set, on a subsample of its own samples (common
//! random numbers: the same draws, the same verdicts): the rows `analyze` turns into the
//! calibration band.
//!
//! Each wheel of a subsample's point is classified as in the run and its closed loop solved once
//! ([`WheelGrowth`]); its one wear answer under the run's own constants and under every set is
//! then the saturated walk over the tread's life per set, the ageing taken once per (c, μ_b)
//! and the legs built only where a set's plain answer has a polygon
//! ([`WheelGrowth::answers_on`]). The run's own answer equals the run's rows (tested), which
//! is what lets the report move the full run's figures by the band's differences on the
//! subsample.

use std::path::{Path, PathBuf};

use crate::parquet_out::Column;
use polywear_core::classify::budget::Meter;
use polywear_core::classify::ClassifierOptions;
use polywear_core::evaluate::{self, PointProblem, WearStage};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::Params;
use polywear_core::wear::{FittedConstants, LifeAnswer, WheelGrowth};
use rand::SeedableRng;
use rayon::prelude::*;

use super::CalibrationBand;
use crate::study::{Study, BASELINE};

/// The band's file in an explore output directory (a leading `_`, as the manifest's: not a
/// chunk, so `analyze` and `--resume` leave it out of the rows).
pub const BAND_FILE: &str = "_calibration_band.parquet";

/// The band file's size and CRC-32, written after it: a band without it, or that does not
/// match it, is refused by `analyze` (the chunks have their journal for the same job).
pub const BAND_DIGEST: &str = "_calibration_band.digest.json";

/// Samples the band is evaluated on by default: its sampling error (about ±0.4 points at 8%)
/// stays well inside a band of several points, and it costs a few percent of a 1e6 run.
pub const DEFAULT_BAND_SAMPLES: u64 = 20_000;

/// Samples per row group of the band's file: a batch's rows (both wheels, every set) are held
/// in memory at once, about 200,000 rows with the shipped 96 sets.
pub(crate) const BATCH_SAMPLES: usize = 1024;

/// The name of the run's own constants among the band's sets.
pub const RUN_SET: &str = "run";

/// The band's column of a set's distances is this prefix and the set's id (`d_run`,
/// `d_nominal`).
pub(crate) const SET_COLUMN_PREFIX: &str = "d_";

/// The band's column of set `id`.
pub fn set_column(id: &str) -> String {
    format!("{SET_COLUMN_PREFIX}{id}")
}

/// What a band column holds for an answer: its distance to a visible polygon where that comes
/// before the tire is worn out, +inf where it does not (later, or never), NaN where unknown (a
/// distance threshold then reads it as the rows' `wear_outcome` does).
fn visible_km(a: &LifeAnswer) -> f64 {
    match a.outcome() {
        polywear_core::wear::physics::fitted::WearOutcome::Visible => a.distance_to_visible_km,
        polywear_core::wear::physics::fitted::WearOutcome::NotWithinLife => f64::INFINITY,
        polywear_core::wear::physics::fitted::WearOutcome::Unknown => f64::NAN,
    }
}

/// Stream of the subsample's choice, apart from every stream of the draws.
const SUBSAMPLE_STREAM: u64 = 0xBA4D_0000_0000_0001;

/// The band's subsample of a run of `samples` drawn with `seed`: every sample when the run has
/// at most `band_samples`, else that many drawn without replacement from a stream of their own,
/// increasing (the same for explore's band and optimize's).
pub fn subsample(seed: u64, samples: u64, band_samples: u64) -> Vec<u64> {
    if samples <= band_samples {
        return (0..samples).collect();
    }
    let mut rng = chacha20::ChaCha12Rng::seed_from_u64(seed ^ SUBSAMPLE_STREAM);
    let mut chosen: Vec<u64> =
        rand::seq::index::sample(&mut rng, samples as usize, band_samples as usize)
            .into_iter()
            .map(|i| i as u64)
            .collect();
    chosen.sort_unstable();
    chosen
}

/// What to evaluate: a run's study and draws, its wear stage, the sets and how many samples.
pub struct BandPlan<'a> {
    /// The run's study.
    pub study: &'a Study,
    /// The run's seed.
    pub seed: u64,
    /// The run's samples (the draws depend on it).
    pub samples: u64,
    /// Samples of the band (all the run's when it has fewer).
    pub band_samples: u64,
    /// The run's wear stage.
    pub stage: &'a WearStage,
    /// The calibrated sets.
    pub band: &'a CalibrationBand,
    /// Where the sets come from (a file's path, or [`super::SHIPPED_NAME`]).
    pub band_source: String,
}

/// One wheel's answers: under the run's constants, then under each set in file order.
#[derive(Debug, Clone, PartialEq)]
pub struct BandWheel {
    /// 0 for the baseline, k for the study's k-th scenario.
    pub block: usize,
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The point's speed \[km/h\] (a fleet weighted by hours weighs wear by it).
    pub speed_kmh: f64,
    /// [`RUN_SET`]'s answer, then each set's.
    pub answers: Vec<LifeAnswer>,
}

/// One sample's wheels.
#[derive(Debug, Clone, PartialEq)]
pub struct BandSample {
    /// The sample's index in the run.
    pub sample_id: u64,
    /// Its wheels: blocks of one per variant and wheel, as the run's rows.
    pub wheels: Vec<BandWheel>,
}

impl BandPlan<'_> {
    /// The subsample: every sample when the run has at most `band_samples`, else that many
    /// drawn without replacement from a stream of their own, increasing (whatever the design,
    /// a grid's corner is never the band's whole subsample).
    pub fn indices(&self) -> Vec<u64> {
        subsample(self.seed, self.samples, self.band_samples)
    }

    /// Evaluates the subsample on the worker pool; `progress` is called with 1 for each
    /// finished sample. The rows are the same whatever the threads.
    pub fn evaluate(&self, progress: &(dyn Fn(u64) + Sync)) -> Vec<BandSample> {
        self.evaluate_indices(&self.indices(), progress, &|| false)
            .expect("never stopped")
    }

    /// [`BandPlan::evaluate`] of the samples `indices` only; None once `stop` says so (asked
    /// before each sample, so a stop waits for the samples in flight alone).
    fn evaluate_indices(
        &self,
        indices: &[u64],
        progress: &(dyn Fn(u64) + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Option<Vec<BandSample>> {
        let sampler = self.study.sampler(self.seed, self.samples);
        let opts = ClassifierOptions {
            budget: self.study.budget,
            ..ClassifierOptions::default()
        };
        indices
            .par_iter()
            .map(|&i| {
                if stop() {
                    return None;
                }
                let (p, _) = sampler.sample(i);
                let s = self.sample(i, &p, &opts);
                progress(1);
                Some(s)
            })
            .collect()
    }

    fn sample(&self, sample_id: u64, p: &Params, opts: &ClassifierOptions) -> BandSample {
        let sets: Vec<FittedConstants> = self.band.sets.iter().map(|s| s.constants()).collect();
        let mut wheels = Vec::new();
        // Block 0 is the baseline; a scenario's changes are made to each set's constants as to
        // the run's, so a scenario that moves φ_s moves every set's.
        let blocks = std::iter::once(None).chain(self.study.scenarios.iter().map(Some));
        for (block, scenario) in blocks.enumerate() {
            let apply = |q: &Params| scenario.map_or(*q, |s| s.apply(q));
            let point = apply(p);
            let constants: Vec<FittedConstants> = std::iter::once(FittedConstants::of(&point))
                .chain(
                    sets.iter()
                        .map(|c| FittedConstants::of(&apply(&c.applied_to(p)))),
                )
                .collect();
            let solution = evaluate::solve(&PointProblem::new(point, &self.study.variants, opts));
            for w in &solution.wheels {
                // None where the wheel has no figures (a standstill among them), as the rows.
                let growth =
                    WheelGrowth::new(&self.stage.problem(&point, w), &Meter::new(opts.budget)).ok();
                let answers = match &growth {
                    Some(g) => g.answers_on(&constants),
                    None => vec![LifeAnswer::UNKNOWN; constants.len()],
                };
                wheels.push(BandWheel {
                    block,
                    variant: w.record.variant,
                    wheel: w.record.wheel,
                    speed_kmh: point.speed_kmh,
                    answers,
                });
            }
        }
        BandSample { sample_id, wheels }
    }

    /// The rows as columns: one row per sample, scenario, variant and wheel, and one column per
    /// set (the run's own constants first, as [`RUN_SET`]) holding the wheel's distance to a
    /// visible polygon before the tire is worn out under it ([`set_column`]): what every later
    /// question of a band needs (any distance, any bins or map through `sample_id`, each
    /// scenario, the fleet's weights through `speed_kmh`, either wheel) in a fraction of the
    /// bytes of a row per set.
    pub fn columns(&self, rows: &[BandSample]) -> Vec<Column> {
        let names = self.study.scenario_names();
        let sets: Vec<&str> = std::iter::once(RUN_SET)
            .chain(self.band.sets.iter().map(|s| s.id.as_str()))
            .collect();
        let flat: Vec<(u64, &BandWheel)> = rows
            .iter()
            .flat_map(|s| s.wheels.iter().map(move |w| (s.sample_id, w)))
            .collect();
        let mut cols = vec![
            Column::i64("sample_id", "", flat.iter().map(|r| r.0 as i64).collect()),
            Column::str(
                "scenario",
                flat.iter().map(|r| names[r.1.block].to_string()).collect(),
            ),
            Column::str(
                "variant",
                flat.iter().map(|r| r.1.variant.to_string()).collect(),
            ),
            Column::str(
                "wheel",
                flat.iter().map(|r| r.1.wheel.to_string()).collect(),
            ),
            Column::f64(
                "speed_kmh",
                "km/h",
                flat.iter().map(|r| r.1.speed_kmh).collect(),
            ),
        ];
        for (k, set) in sets.iter().enumerate() {
            let km = flat
                .iter()
                .map(|r| visible_km(&r.1.answers[k]) as f32)
                .collect();
            cols.push(Column::f32(set_column(set), "km", km));
        }
        cols
    }

    /// What the band's footer records beside the run's own keys (`run`): the sets, their
    /// source and method, the subsample.
    pub fn metadata(&self, run: Vec<(String, String)>) -> Vec<(String, String)> {
        let sets: Vec<serde_json::Value> = self
            .band
            .sets
            .iter()
            .map(|s| {
                serde_json::json!({
                    "id": s.id,
                    "nominal": s.nominal,
                    "wear_share_straight": s.wear_share_straight,
                    "speed_spread_kmh": s.speed_spread_kmh,
                    "wear_rate_driven_factor": s.wear_rate_driven_factor,
                    "carcass_share": s.carcass_share,
                    "belt_mass_share": s.belt_mass_share,
                })
            })
            .collect();
        let mut meta = run;
        // Not a chunk: without `chunk` and the drawn names, `analyze` refuses the file as rows.
        meta.retain(|(k, _)| !matches!(k.as_str(), "columns" | "chunk" | "drawn_names" | "drawn"));
        meta.extend([
            ("band_sets".to_string(), serde_json::Value::Array(sets).to_string()),
            ("band_source".to_string(), self.band_source.clone()),
            ("band_method".to_string(), self.band.method.clone()),
            ("band_generated_by".to_string(), self.band.generated_by.clone()),
            ("band_region".to_string(), self.band.fit.region.clone()),
            ("band_samples".to_string(), self.indices().len().to_string()),
            (
                "band_subsample".to_string(),
                if self.samples <= self.band_samples {
                    "every sample of the run".to_string()
                } else {
                    format!(
                        "{} of the run's {} samples, drawn without replacement (ChaCha12, seed ^ {SUBSAMPLE_STREAM:#x})",
                        self.band_samples, self.samples
                    )
                },
            ),
            (
                "columns".to_string(),
                format!("one row per sample, scenario ({BASELINE}: none), variant and wheel; a column `{SET_COLUMN_PREFIX}SET` per set, the distance to a visible polygon before the tire is worn out under it [km] (+inf: none before it is worn out, NaN: unknown); set `{RUN_SET}` is the run's own constants, as its rows"),
            ),
        ]);
        meta
    }

    /// Evaluates the subsample and streams its rows crash-safely to `dir`/[`BAND_FILE`], one
    /// row group per `BATCH_SAMPLES` samples (so memory stays flat in the subsample's size),
    /// then writes its digest ([`BAND_DIGEST`]); the digest says `pending` until then
    /// (`mark_pending`), so a run stopped in between leaves a band that `analyze` refuses as
    /// unfinished, never one it trusts. `progress` is called with 1 for each finished sample;
    /// `stop` is asked between batches, and a stop leaves the band pending.
    pub fn write(
        &self,
        dir: &Path,
        run_metadata: Vec<(String, String)>,
        progress: &(dyn Fn(u64) + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<PathBuf, BandWriteError> {
        let path = dir.join(BAND_FILE);
        let digest_path = dir.join(BAND_DIGEST);
        let at = |p: &Path, e: &dyn std::fmt::Display| {
            BandWriteError::Io(format!("{}: {e}", p.display()))
        };
        mark_pending(dir, &self.band_source).map_err(|e| BandWriteError::Io(e.to_string()))?;
        let indices = self.indices();
        let meta = self.metadata(run_metadata);
        let mut writer: Option<crate::parquet_out::TableWriter> = None;
        for batch in indices.chunks(BATCH_SAMPLES) {
            let rows = self
                .evaluate_indices(batch, progress, stop)
                .ok_or(BandWriteError::Stopped)?;
            let cols = self.columns(&rows);
            if writer.is_none() {
                writer = Some(
                    crate::parquet_out::TableWriter::create(&path, &cols, &meta)
                        .map_err(|e| at(&path, &e))?,
                );
            }
            let w = writer.as_mut().expect("created above");
            w.write(&cols).map_err(|e| at(&path, &e))?;
        }
        if stop() {
            return Err(BandWriteError::Stopped);
        }
        let digest = writer
            .ok_or_else(|| at(&path, &"no sample to evaluate"))?
            .finish()
            .map_err(|e| at(&path, &e))?;
        let json = serde_json::json!({
            "file": BAND_FILE,
            "bytes": digest.bytes,
            "crc32": digest.crc32,
        });
        crate::safe_write::write_durably(&digest_path, format!("{json}\n").as_bytes())
            .map_err(|e| at(&digest_path, &e))?;
        Ok(path)
    }
}

/// Why the band was not written.
#[derive(Debug, thiserror::Error)]
pub enum BandWriteError {
    /// Stopped (a signal) between batches: the band stays pending, `--resume` writes it.
    #[error("stopped before the calibration band was finished")]
    Stopped,
    /// A file could not be written (the message names it).
    #[error("{0}")]
    Io(String),
}

/// What the band's digest says of the band ([`band_state`]).
#[derive(Debug, Clone, PartialEq)]
pub enum BandState {
    /// Neither a band nor its digest: the run asked for none (`--calibration-band off`, no
    /// wear stage), or polywear before the digest was written at the run's start.
    Absent,
    /// The digest says the band was asked for and is not finished: the run stopped before or
    /// during its band pass (`--resume` writes it).
    Pending,
    /// The band file matches its digest.
    Verified,
    /// The band or its digest cannot be trusted, and why.
    Refused(String),
}

/// The band's state in `dir` from its digest: the digest is written `pending` before the run's
/// first chunk where a band is asked for, and with the band file's size and CRC-32 once the
/// band is written, so that a run stopped anywhere never leaves a band (or its absence) that
/// `analyze` takes for finished. Only regular files are read, within a small bound: a link, a
/// FIFO or a device in the digest's or the band's place is refused, never followed or read.
pub fn band_state(dir: &Path) -> BandState {
    let digest_path = dir.join(BAND_DIGEST);
    let band_path = dir.join(BAND_FILE);
    let present = |p: &Path| std::fs::symlink_metadata(p).ok();
    let (digest_meta, band_meta) = (present(&digest_path), present(&band_path));
    for (name, meta) in [(BAND_DIGEST, &digest_meta), (BAND_FILE, &band_meta)] {
        if let Some(m) = meta {
            if !m.file_type().is_file() {
                return BandState::Refused(format!(
                    "{name} is {}, not the regular file explore writes",
                    crate::safe_read::kind_name(&m.file_type())
                ));
            }
        }
    }
    let Some(digest_meta) = digest_meta else {
        return match band_meta {
            None => BandState::Absent,
            Some(_) => BandState::Refused(format!(
                "no {BAND_DIGEST} beside it (the run was stopped while writing it)"
            )),
        };
    };
    if digest_meta.len() > MAX_DIGEST_BYTES {
        return BandState::Refused(format!(
            "{BAND_DIGEST} is damaged: {} bytes, where explore writes under {MAX_DIGEST_BYTES}",
            digest_meta.len()
        ));
    }
    let recorded = match crate::safe_read::read_text(&digest_path, crate::safe_read::Limit::Text)
        .map_err(|e| e.reason())
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).map_err(|e| e.to_string()))
    {
        Ok(v) => v,
        Err(e) => return BandState::Refused(format!("{BAND_DIGEST} is damaged: {e}")),
    };
    if recorded.get("status").and_then(|s| s.as_str()) == Some(PENDING) {
        return BandState::Pending;
    }
    let (bytes, crc) = (recorded["bytes"].as_u64(), recorded["crc32"].as_u64());
    let (Some(bytes), Some(crc)) = (bytes, crc) else {
        return BandState::Refused(format!(
            "{BAND_DIGEST} is damaged: it records neither `status` = \"{PENDING}\" nor the band's `bytes` and `crc32`"
        ));
    };
    if band_meta.is_none() {
        return BandState::Refused(format!(
            "{BAND_FILE} is missing where {BAND_DIGEST} records it"
        ));
    }
    let found = match crate::parquet_out::FileDigest::of_file(&band_path) {
        Ok(d) => d,
        Err(e) => return BandState::Refused(e.to_string()),
    };
    if bytes != found.bytes || crc != u64::from(found.crc32) {
        return BandState::Refused(format!(
            "its size and CRC-32 ({} bytes, {:08x}) differ from those recorded in {BAND_DIGEST} ({bytes} bytes, {crc:08x}): the file changed after the run",
            found.bytes, found.crc32,
        ));
    }
    BandState::Verified
}

/// The digest's `status` while the band is asked for and not written.
const PENDING: &str = "pending";

/// The largest digest explore writes is under 200 bytes: one far larger is not its.
const MAX_DIGEST_BYTES: u64 = 4096;

/// Marks `dir`'s band as asked for and not finished (its digest `pending`, the old band file
/// removed): written before the run's chunks, so that a run stopped anywhere before the band is
/// whole leaves a band `analyze` refuses with the command that finishes it.
pub(crate) fn mark_pending(dir: &Path, band_source: &str) -> Result<(), BandFileError> {
    let json = serde_json::json!({ "status": PENDING, "band_source": band_source });
    let digest_path = dir.join(BAND_DIGEST);
    crate::safe_write::write_durably(&digest_path, format!("{json}\n").as_bytes())
        .map_err(|e| BandFileError::at(&digest_path, e))?;
    remove_band_file(&dir.join(BAND_FILE))
}

/// Removes the band file `path` (absent is removed).
pub(crate) fn remove_band_file(path: &Path) -> Result<(), BandFileError> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(BandFileError::at(path, e)),
        _ => Ok(()),
    }
}

/// A band file or digest that cannot be written or removed.
#[derive(Debug, thiserror::Error)]
#[error("{}: {error}", path.display())]
pub struct BandFileError {
    /// The file.
    pub path: std::path::PathBuf,
    /// What the file system said.
    pub error: std::io::Error,
}

impl BandFileError {
    fn at(path: &Path, error: std::io::Error) -> Self {
        BandFileError {
            path: path.to_path_buf(),
            error,
        }
    }
}
