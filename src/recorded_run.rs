//! What an explore output directory remembers of its run: the manifest read back (study text,
//! parameters, seed, samples, shard), how much of it the journal says is saved, and the lines in
//! which another study text differs from it. `explore --resume --out DIR` continues a run from
//! these alone, and a directory that is refused is described by them ("finished", "k of N
//! samples saved").

use std::path::{Path, PathBuf};

use crate::output_dir::{self, MANIFEST};
use crate::params::Params;

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
    /// Shard `(k, N)`: the run owns the chunks whose index is k mod N.
    pub shard: (u64, u64),
    /// The folder a relative `[operating_points]` file was found in (the recorded path less
    /// the file name the study gives), so that the recorded study reads the same file again.
    pub operating_points_dir: Option<PathBuf>,
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
    pub fn read(dir: &Path) -> Result<Option<RecordedRun>, String> {
        let path = dir.join(MANIFEST);
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(format!("{}: {e}", path.display())),
        };
        let bad = |what: &str| format!("{}: {what}", path.display());
        let v: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| bad(&format!("unreadable: {e}")))?;
        let field_u64 = |k: &str| {
            v[k].as_u64()
                .ok_or_else(|| bad(&format!("`{k}` is missing or not a whole number")))
        };
        let mut params = Params::default();
        let recorded = v["params"]
            .as_object()
            .ok_or_else(|| bad("`params` is missing"))?;
        for (name, x) in recorded {
            let x = x
                .as_f64()
                .ok_or_else(|| bad(&format!("`params.{name}` is not a number")))?;
            params
                .set(name, x)
                .map_err(|e| bad(&format!("`params`: {e}")))?;
        }
        let shard = v["shard"]
            .as_str()
            .and_then(|s| s.split_once('/'))
            .and_then(|(k, n)| Some((k.parse().ok()?, n.parse().ok()?)))
            .filter(|(k, n): &(u64, u64)| k < n)
            .ok_or_else(|| bad("`shard` is missing or not k/N"))?;
        Ok(Some(RecordedRun {
            study_name: v["study_name"].as_str().unwrap_or("").to_string(),
            study: v["study"]
                .as_str()
                .ok_or_else(|| bad("`study` is missing"))?
                .to_string(),
            params,
            seed: field_u64("seed")?,
            samples: field_u64("samples")?,
            chunk_size: field_u64("chunk_size")?.max(1),
            shard,
            operating_points_dir: operating_points_dir(&v["operating_points"]),
        }))
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
        let (k, n) = self.shard;
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

/// `path` = dir.join(`file`) as the manifest and the chunks record an operating-point file:
/// gives back dir, where the recorded study finds its file again.
pub fn operating_points_dir(op: &serde_json::Value) -> Option<PathBuf> {
    let (file, path) = (op["file"].as_str()?, op["path"].as_str()?);
    let dir = path.strip_suffix(file)?;
    Some(PathBuf::from(dir))
}

/// Why a non-empty `--out` is refused for a new run, and what to do instead: a finished run is
/// named as finished with `polywear analyze` suggested, an unfinished one with its progress and
/// `--resume`.
pub fn occupied(dir: &Path) -> String {
    let d = shell_word(&dir.display().to_string());
    let another = "or choose another --out for a new run";
    match RecordedRun::read(dir) {
        Ok(Some(run)) => {
            let saved = run.saved(dir);
            let what = format!(
                "study `{}`, seed {}, {} samples",
                run.study_name, run.seed, run.samples
            );
            if saved.finished() {
                format!(
                    "holds a finished run ({what}); analyse it with `polywear analyze {d}`, {another}"
                )
            } else {
                format!(
                    "holds an unfinished run ({what}; {} of {} samples saved); continue it with `polywear explore --resume --out {d}`, {another}",
                    saved.samples, saved.samples_owned
                )
            }
        }
        Ok(None) => "is not empty and holds no polywear run; accepted: an empty or absent directory (for a new run), or a run's directory with --resume".to_string(),
        Err(e) => format!("holds an unreadable run ({e}); choose another --out"),
    }
}

/// The lines in which `new` differs from `old`, in order: `- line` only in `old`, `+ line` only
/// in `new` (a longest-common-subsequence diff; studies are a few dozen lines). Blank lines and
/// trailing spaces are ignored, so a changed value is shown as its two lines and nothing else.
pub fn changed_lines(old: &str, new: &str) -> Vec<String> {
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

/// The parameters whose values differ between two recorded `params` objects, as
/// "g_mod 855700, now 900000".
pub fn param_changes(old: &serde_json::Value, new: &serde_json::Value) -> String {
    let changed: Vec<String> = crate::params::SPECS
        .iter()
        .filter(|s| old[s.name] != new[s.name])
        .map(|s| format!("{} {}, now {}", s.name, old[s.name], new[s.name]))
        .collect();
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
