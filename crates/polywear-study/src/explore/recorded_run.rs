//! What an explore output directory remembers of its run: the manifest read back (study text,
//! parameters, seed, samples, shard), how much of it the journal says is saved, and the lines in
//! which another study text differs from it. `explore --resume --out DIR` continues a run from
//! these alone, and a directory that is refused is described by them ("finished", "k of N
//! samples saved").

use std::path::{Path, PathBuf};

use super::{RunManifest, Shard};
use crate::output_dir::{self, MANIFEST};
use polywear_core::params::Params;
use polywear_core::wear::{retired_level, WearSettings};

/// The run recorded in an output directory's manifest.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedRun {
    /// The study's name.
    pub study_name: String,
    /// The study file's text.
    pub study: String,
    /// Every parameter's value the run started from (the study's fixed values applied).
    pub params: Params,
    /// The run's seed.
    pub seed: u64,
    /// Rows per wheel and variant, i.e. evaluations (a saltelli design's base samples times
    /// k + 2).
    pub samples: u64,
    /// Samples per chunk file.
    pub chunk_size: u64,
    /// The shard that wrote the run: it owns the chunks whose index is k mod N.
    pub shard: Shard,
    /// The folder a relative `[operating_points]` file was found in (the recorded path less
    /// the file name the study gives), so that the recorded study reads the same file again.
    pub operating_points_dir: Option<PathBuf>,
    /// The wear stage's settings, as the manifest records them (`None`: the run has no wear
    /// columns).
    pub wear: Option<WearSettings>,
}

/// Why a directory's manifest cannot be read back.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {message}", path.display())]
pub struct ManifestReadError {
    /// The manifest file.
    pub path: PathBuf,
    /// What is wrong.
    pub message: String,
    /// The run cannot continue with this build, and no other check of the directory says
    /// more: it was answered on a retired wear level (MODEL.md#one-wear-answer), or written
    /// before rows named their axle (its chunks lack the `axle` column, which new chunks would
    /// have: MODEL.md#the-car-axles-and-drivetrain).
    pub retired_level: bool,
}

/// How much of a recorded run the journal holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Saved {
    /// Chunks of the run's shard recorded as finished.
    pub chunks: u64,
    /// Chunks the run's shard owns.
    pub chunks_owned: u64,
    /// Samples in the finished chunks.
    pub samples: u64,
    /// Samples in the chunks the shard owns.
    pub samples_owned: u64,
}

impl Saved {
    /// Every chunk the run owns is recorded as finished.
    pub fn finished(&self) -> bool {
        self.chunks == self.chunks_owned
    }
}

impl RecordedRun {
    /// Reads the manifest of `dir`: `Ok(None)` when there is none, an error naming the file when
    /// it cannot be read or lacks a field.
    pub fn read(dir: &Path) -> Result<Option<RecordedRun>, ManifestReadError> {
        let path = dir.join(MANIFEST);
        let bad = |message: String| ManifestReadError {
            path: path.clone(),
            message,
            retired_level: false,
        };
        let text = match crate::safe_read::read_text(&path, crate::safe_read::Limit::Text) {
            Ok(t) => t,
            Err(e) if e.is_not_found() => return Ok(None),
            Err(e) => return Err(bad(e.to_string())),
        };
        let m = RunManifest::from_json_text(&text).map_err(|e| bad(e.to_string()))?;
        let run = RecordedRun {
            study: m
                .study
                .clone()
                .ok_or_else(|| bad("`study` is missing".into()))?,
            study_name: m.study_name,
            params: m.params,
            seed: m.seed,
            samples: m.samples,
            chunk_size: m.chunk_size.max(1),
            shard: m.shard,
            operating_points_dir: m.operating_points.as_ref().and_then(|o| o.dir()),
            wear: match &m.wear {
                None => None,
                Some(w) => match retired_level(&w.wear_estimate) {
                    Some(why) => {
                        return Err(ManifestReadError {
                            retired_level: true,
                            ..bad(retired_wear_words(&w.wear_estimate, &why))
                        })
                    }
                    None => Some(w.settings()),
                },
            },
        };
        // After the retired level, which says more of an old run.
        if written_before_axles(&text) {
            return Err(ManifestReadError {
                retired_level: true,
                ..bad("the run was written before polywear knew the car's axles: its rows have no `axle` column, and chunks written now would; start it again with another --out".into())
            });
        }
        Ok(Some(run))
    }

    /// Samples in chunk `c` (the last one may be short).
    fn chunk_len(&self, c: u64) -> u64 {
        (self.samples - c * self.chunk_size).min(self.chunk_size)
    }

    /// How many of the run's own chunks and samples the journal of `dir` records as finished
    /// (the chunk files themselves are verified only when the run is resumed).
    pub fn saved(&self, dir: &Path) -> Saved {
        let journal = output_dir::read_journal(dir).unwrap_or_default();
        let n_chunks = self.samples.div_ceil(self.chunk_size);
        let Shard { index: k, count: n } = self.shard;
        let owned = || (k..n_chunks).step_by(n as usize);
        let done = || owned().filter(|c| journal.contains_key(c));
        Saved {
            chunks: done().count() as u64,
            chunks_owned: owned().count() as u64,
            samples: done().map(|c| self.chunk_len(c)).sum(),
            samples_owned: owned().map(|c| self.chunk_len(c)).sum(),
        }
    }
}

/// Whether a manifest's parameters lack the drivetrain, as every run's before the car's axles
/// did (a run that cannot be resumed without mixing rows with and without `axle`).
fn written_before_axles(manifest: &str) -> bool {
    serde_json::from_str::<serde_json::Value>(manifest)
        .ok()
        .and_then(|v| v.get("params").map(|p| p.get("drivetrain").is_none()))
        .unwrap_or(false)
}

/// What a non-empty output directory holds, for the message that refuses it to a new run.
#[derive(Debug, Clone, PartialEq)]
pub enum DirState {
    /// A run whose chunks are all saved.
    Finished {
        /// The run as its manifest records it.
        run: Box<RecordedRun>,
    },
    /// A run with chunks still to do.
    Unfinished {
        /// The run as its manifest records it.
        run: Box<RecordedRun>,
        /// How much of it is saved.
        saved: Saved,
    },
    /// Files, but no polywear run.
    Foreign,
    /// A manifest that cannot be read.
    Unreadable(ManifestReadError),
}

impl DirState {
    /// "study `x`, seed 1, 600 samples" for a run; None for a directory without one.
    pub fn run_summary(&self) -> Option<String> {
        match self {
            DirState::Finished { run } | DirState::Unfinished { run, .. } => Some(format!(
                "study `{}`, seed {}, {} samples",
                run.study_name, run.seed, run.samples
            )),
            _ => None,
        }
    }
}

impl std::fmt::Display for DirState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let what = self.run_summary().unwrap_or_default();
        match self {
            DirState::Finished { .. } => write!(f, "holds a finished run ({what})"),
            DirState::Unfinished { saved, .. } => write!(
                f,
                "holds an unfinished run ({what}; {} of {} samples saved)",
                saved.samples, saved.samples_owned
            ),
            DirState::Foreign => f.write_str("is not empty and holds no polywear run"),
            DirState::Unreadable(e) => write!(f, "holds an unreadable run ({e})"),
        }
    }
}

/// What the non-empty directory `dir` holds: a finished or unfinished run (with its progress),
/// something else, or an unreadable manifest.
pub(crate) fn directory_state(dir: &Path) -> DirState {
    match RecordedRun::read(dir) {
        Ok(Some(run)) => {
            let saved = run.saved(dir);
            let run = Box::new(run);
            if saved.finished() {
                DirState::Finished { run }
            } else {
                DirState::Unfinished { run, saved }
            }
        }
        Ok(None) => DirState::Foreign,
        Err(e) => DirState::Unreadable(e),
    }
}

/// The lines in which `new` differs from `old`, in order: `- line` only in `old`, `+ line` only
/// in `new` (a longest-common-subsequence diff; studies are a few dozen lines). Blank lines and
/// trailing spaces are ignored, so a changed value is shown as its two lines and nothing else.
pub(crate) fn changed_lines(old: &str, new: &str) -> Vec<String> {
    let keep = |t: &str| -> Vec<String> {
        t.lines()
            .map(|l| l.trim_end().to_string())
            .filter(|l| !l.is_empty())
            .collect()
    };
    let (a, b) = (keep(old), keep(new));
    // lcs[i][j]: length of the longest common subsequence of a[i..] and b[j..].
    let mut lcs = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for i in (0..a.len()).rev() {
        for j in (0..b.len()).rev() {
            lcs[i][j] = if a[i] == b[j] {
                lcs[i + 1][j + 1] + 1
            } else {
                lcs[i + 1][j].max(lcs[i][j + 1])
            };
        }
    }
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < a.len() || j < b.len() {
        if i < a.len() && j < b.len() && a[i] == b[j] {
            (i, j) = (i + 1, j + 1);
        } else if j == b.len() || (i < a.len() && lcs[i + 1][j] >= lcs[i][j + 1]) {
            out.push(format!("- {}", a[i]));
            i += 1;
        } else {
            out.push(format!("+ {}", b[j]));
            j += 1;
        }
    }
    out
}

/// The parameters whose values differ between two sets, as "g_mod 855700.0, now 900000.0"
/// (the values as the manifest writes them).
pub(crate) fn param_changes(old: &Params, new: &Params) -> String {
    let json = |x: f64| serde_json::to_string(&x).expect("json");
    let mut changed: Vec<String> = polywear_core::params::ParamId::ALL
        .iter()
        .filter(|&&id| old.differs(new, id))
        .map(|&id| format!("{id} {}, now {}", json(old[id]), json(new[id])))
        .collect();
    if old.drivetrain != new.drivetrain {
        changed.push(format!(
            "drivetrain {}, now {}",
            old.drivetrain, new.drivetrain
        ));
    }
    if changed.is_empty() {
        "parameters differ".into()
    } else {
        format!("parameters: {}", changed.join("; "))
    }
}

/// A path as a shell word: unchanged when it holds only safe characters, else single-quoted.
pub fn shell_word(s: &str) -> String {
    let safe = |c: char| c.is_ascii_alphanumeric() || "/._-+=:,@%".contains(c);
    if !s.is_empty() && s.chars().all(safe) {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

/// Why a run recorded on the retired wear level `level` no longer continues or reads (`why`:
/// what retired it, and what replaced it).
fn retired_wear_words(level: &str, why: &str) -> String {
    format!(
        "`wear.wear_estimate` = \"{level}\": {why}; run explore again for this version's answer"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn changed_lines_show_only_what_differs() {
        let old = "name = \"a\"\nseed = 1\nsamples = 600\n\n[params]\nx = 1\n";
        let new = "name = \"a\"\nseed = 1\nsamples = 700\n[params]\nx = 1\ny = 2\n";
        assert_eq!(
            changed_lines(old, new),
            ["- samples = 600", "+ samples = 700", "+ y = 2"]
        );
        assert!(changed_lines(old, old).is_empty());
    }

    #[test]
    fn shell_words_are_quoted_when_needed() {
        assert_eq!(shell_word("data/run_1"), "data/run_1");
        assert_eq!(shell_word("my runs/a"), "'my runs/a'");
        assert_eq!(shell_word("it's"), r"'it'\''s'");
    }
}
