//! The output directory of a run: checked and locked before any work; for `--resume`, compared
//! with the recorded [`RunManifest`] and its chunk files verified against the journal.

use std::collections::HashSet;

use super::manifest::{OperatingPointsRecord, RunManifest};
use super::recorded_run::{changed_lines, directory_state, param_changes};
use super::{ExploreError, RunPlan};
use crate::output_dir::{self, DirLock};
use crate::parquet_out::write_durably;

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

impl RunPlan {
    /// Checks the output directory before any work and takes its lock: empty or absent for a
    /// new run (the manifest is then written); for `--resume`, holding the manifest of the same
    /// run, whose kept chunks are then verified against the journal (see
    /// [`RunPlan::verify_kept_chunks`]). `--resume` into an empty or absent directory starts
    /// the run, so a scheduler can always pass it. A directory locked by a running process is
    /// refused with its PID.
    pub fn prepare_output(&self) -> Result<PreparedOutput, ExploreError> {
        let dir = &self.out_dir;
        let e = |message: String| ExploreError::OutputDir {
            dir: dir.clone(),
            message,
        };
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
            crate::safe_write::create_dir(dir).map_err(|err| e(err.to_string()))?;
            lock = output_dir::lock(dir, true).map_err(|err| e(err.to_string()))?;
        }
        let lock = lock.expect("lock taken");
        // The authoritative check, under the lock.
        if self.check_contents()? != resuming {
            return Err(ExploreError::Raced { dir: dir.clone() });
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
        let text = self.manifest().to_json_text();
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
        let existing: Vec<String> = output_dir::entries(dir)
            .map_err(|err| ExploreError::OutputDir {
                dir: dir.clone(),
                message: err.to_string(),
            })?
            .unwrap_or_default()
            .into_iter()
            .filter(|n| !output_dir::is_leftover(n))
            .collect();
        if existing.is_empty() {
            return Ok(false);
        }
        if !self.resume {
            return Err(ExploreError::Occupied {
                dir: dir.clone(),
                state: directory_state(dir),
            });
        }
        let manifest_path = dir.join(output_dir::MANIFEST);
        let text = crate::safe_read::read_text(&manifest_path, crate::safe_read::Limit::Text)
            .map_err(|err| ExploreError::NothingToResume {
                dir: dir.clone(),
                manifest: manifest_path.display().to_string(),
                message: err.reason(),
            })?;
        let old =
            RunManifest::from_json_text(&text).map_err(|err| ExploreError::UnreadableManifest {
                dir: dir.clone(),
                message: err.to_string(),
            })?;
        let new = self.manifest();
        // A directory written by another generator (or with none recorded) holds rows this
        // build would not reproduce: never mix them.
        if old.rng != new.rng {
            return Err(ExploreError::OtherGenerator {
                dir: dir.clone(),
                recorded: old.rng,
            });
        }
        if old.polywear_version != new.polywear_version {
            return Err(ExploreError::OtherVersion {
                dir: dir.clone(),
                recorded: old.polywear_version,
            });
        }
        if old.study != new.study {
            return Err(ExploreError::OtherStudy {
                dir: dir.clone(),
                lines: changed_lines(
                    old.study.as_deref().unwrap_or(""),
                    new.study.as_deref().unwrap_or(""),
                ),
            });
        }
        let (o, n) = (&old.operating_points, &new.operating_points);
        let hash = |r: &Option<OperatingPointsRecord>| r.as_ref().map(|r| r.hash.clone());
        if hash(o) != hash(n) {
            let path = |r: &Option<OperatingPointsRecord>| {
                r.as_ref().map_or("none".to_string(), |r| r.path.clone())
            };
            let none = |h: Option<String>| h.unwrap_or_else(|| "none".into());
            return Err(ExploreError::OperatingPointsChanged {
                dir: dir.clone(),
                recorded_path: path(o),
                recorded_hash: none(hash(o)),
                path: path(n),
                hash: none(hash(n)),
            });
        }
        let what = if old.params != new.params {
            Some(param_changes(&old.params, &new.params))
        } else {
            None
        };
        let what = what
            .or_else(|| change("seed", &old.seed, &new.seed))
            .or_else(|| change("samples", &old.samples, &new.samples))
            .or_else(|| change("chunk_size", &old.chunk_size, &new.chunk_size))
            .or_else(|| change("shard", &old.shard.to_string(), &new.shard.to_string()))
            .or_else(|| change("wear stage", &old.wear, &new.wear));
        if let Some(what) = what {
            return Err(ExploreError::DifferentRun {
                dir: dir.clone(),
                what,
            });
        }
        Ok(true)
    }

    /// For `--resume`: checks every chunk file against the journal (row count, size, CRC-32),
    /// deletes those that fail and the leftovers of a killed run, and returns the chunks kept,
    /// with one line per redone chunk saying which and why. Linear in the files present.
    pub fn verify_kept_chunks(&self) -> Result<(HashSet<u64>, Vec<String>), ExploreError> {
        let dir = &self.out_dir;
        let e = |message: String| ExploreError::OutputDir {
            dir: dir.clone(),
            message,
        };
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
                    return Err(ExploreError::ForeignChunk {
                        dir: dir.clone(),
                        name: name.clone(),
                        chunks: self.n_chunks(),
                        shard,
                    });
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
}

/// "seed 1, now 2" when a recorded value differs from this run's, the values as JSON.
fn change<T: serde::Serialize + PartialEq>(name: &str, old: &T, new: &T) -> Option<String> {
    let json = |v: &T| serde_json::to_string(v).expect("json");
    (old != new).then(|| format!("{name} {}, now {}", json(old), json(new)))
}
