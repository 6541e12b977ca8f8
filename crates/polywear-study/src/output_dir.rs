//! The explore output directory as a crash-safe store: an exclusive lock held by the running
//! process, the run's manifest written durably, and an append-only journal of finished chunks
//! (file, rows, size, CRC-32) against which `--resume` verifies every chunk it keeps.
//!
//! Layout of `--out DIR`:
//! - `chunk-NNNNNNN.parquet`: the rows, one file per chunk (written by [`crate::parquet_out`]:
//!   temporary name, fsync, rename, directory fsync);
//! - `_manifest.json`: the run (study text, seed, samples, chunk size, shard), written once,
//!   durably;
//! - `_manifest.chunks.jsonl`: one JSON line per finished chunk, appended and fsynced after the
//!   chunk file is in place. A torn last line (a kill mid-append) is ignored: that chunk is redone;
//! - `_lock`: holds the PID of the running process, `flock`ed while it runs (the kernel drops
//!   the lock when the process ends, however it ends). A run that finishes removes it; one that
//!   is killed leaves it, and the next run takes it over.
//!
//! Names starting with `_` are skipped by pyarrow/pandas when the directory is read as a dataset.

use std::collections::HashMap;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use crate::parquet_out::FileDigest;
use crate::safe_read::{self, Limit};
use crate::safe_write::{self, write_durably};

/// The run's manifest in an output directory.
pub(crate) const MANIFEST: &str = "_manifest.json";
/// The journal of finished chunks beside the manifest.
pub const JOURNAL: &str = "_manifest.chunks.jsonl";
/// The lock file.
pub(crate) const LOCK: &str = "_lock";

/// Why an output directory cannot be taken or continued.
#[derive(Debug, thiserror::Error)]
pub enum OutputDirError {
    /// The lock file cannot be created or opened.
    #[error("cannot create the lock file {}: {source}", path.display())]
    CreateLock {
        /// The lock file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// `flock` failed for another reason than another holder.
    #[error("cannot lock {}: {source}", path.display())]
    Lock {
        /// The lock file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// Another process holds the lock.
    #[error("is in use by another polywear run (PID {holder}, lock file {}); wait for it to end or choose another directory", path.display())]
    InUse {
        /// The holder's PID as its lock file says (`unknown` when empty).
        holder: String,
        /// The lock file.
        path: PathBuf,
    },
    /// Our PID cannot be written into the lock file.
    #[error("cannot write the lock file {}: {source}", path.display())]
    WriteLock {
        /// The lock file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
}

/// Why a chunk file kept from an earlier run cannot be trusted.
#[derive(Debug, thiserror::Error)]
pub enum ChunkMismatch {
    /// The journal has no entry for it.
    #[error("not recorded in the manifest (the run ended before it was recorded)")]
    NotRecorded,
    /// The journal's row count differs from the chunk size of this run.
    #[error("the manifest records {recorded} rows, this run expects {expected}")]
    Rows {
        /// Rows in the journal.
        recorded: u64,
        /// Rows this run puts in the chunk.
        expected: u64,
    },
    /// The file cannot be read.
    #[error("unreadable: {0}")]
    Unreadable(std::io::Error),
    /// A link, a directory or another kind of file than the regular file polywear wrote.
    #[error("{0}, not a file polywear wrote")]
    NotAFile(&'static str),
    /// Its size differs from the journal's.
    #[error("{found} bytes, the manifest records {recorded} (truncated or replaced)")]
    Bytes {
        /// The file's size.
        found: u64,
        /// The journal's size.
        recorded: u64,
    },
    /// Its CRC-32 differs from the journal's.
    #[error("CRC-32 {found:08x}, the manifest records {recorded:08x} (corrupted or replaced)")]
    Crc32 {
        /// The file's CRC-32.
        found: u32,
        /// The journal's CRC-32.
        recorded: u32,
    },
}

/// An exclusive lock on an output directory, released when dropped or when the process ends.
/// Dropping it removes the lock file first, while the lock is still held: a process that opened
/// the old file meanwhile finds it no longer at the path once it has the lock, and takes the
/// new one instead ([`lock`] checks the path against the file it locked).
#[derive(Debug)]
pub struct DirLock {
    file: File,
    path: PathBuf,
}

impl Drop for DirLock {
    fn drop(&mut self) {
        if same_file(&self.file, &self.path) {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// Whether `path` still names the file `f` is open on (not removed or replaced).
#[cfg(unix)]
fn same_file(f: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (f.metadata(), std::fs::symlink_metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(_f: &File, path: &Path) -> bool {
    path.exists()
}

/// The lock is `flock` through `libc` (already a dependency), not `fs4` or `fd-lock` (5 and
/// 6 crates, 2.3 CPU-s of release build each, for the same call); the standard library's
/// `File::try_lock` does the same without `unsafe` once the minimum Rust is 1.89.
#[cfg(unix)]
fn try_flock(f: &File) -> std::io::Result<bool> {
    use std::os::unix::io::AsRawFd;
    // SAFETY: flock on a valid, open file descriptor owned by `f`.
    let rc = unsafe { libc::flock(f.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
    if rc == 0 {
        return Ok(true);
    }
    let e = std::io::Error::last_os_error();
    if e.raw_os_error() == Some(libc::EWOULDBLOCK) {
        Ok(false)
    } else {
        Err(e)
    }
}

#[cfg(not(unix))]
fn try_flock(_f: &File) -> std::io::Result<bool> {
    Ok(true)
}

/// Takes the exclusive lock of `dir` (which must exist), creating the lock file when
/// `create`; `Ok(None)` when `create` is false and there is no lock file. Refused with the
/// holder's PID when another process holds it, and when the lock file is a link or not a
/// regular file (it is never written through, see `crate::safe_write::open_lock`).
pub fn lock(dir: &Path, create: bool) -> Result<Option<DirLock>, OutputDirError> {
    // A finishing run removes the file while it holds the lock: a file locked here that is no
    // longer at the path was that one, so open the path again (a few tries: each needs another
    // run to finish in between).
    for _ in 0..8 {
        match lock_once(dir, create)? {
            Locked::Got(l) => return Ok(Some(l)),
            Locked::NoFile => return Ok(None),
            Locked::Stale => continue,
        }
    }
    Err(OutputDirError::InUse {
        holder: "runs that keep finishing and removing it".to_string(),
        path: dir.join(LOCK),
    })
}

/// What one attempt at the lock found.
enum Locked {
    Got(DirLock),
    NoFile,
    /// The file locked was removed from the path meanwhile.
    Stale,
}

fn lock_once(dir: &Path, create: bool) -> Result<Locked, OutputDirError> {
    let path = dir.join(LOCK);
    let mut f = match safe_write::open_lock(&path, create) {
        Ok(f) => f,
        Err(e) if !create && e.kind() == std::io::ErrorKind::NotFound => return Ok(Locked::NoFile),
        Err(source) => return Err(OutputDirError::CreateLock { path, source }),
    };
    let got = match try_flock(&f) {
        Ok(got) => got,
        Err(source) => return Err(OutputDirError::Lock { path, source }),
    };
    if !got {
        let mut holder = String::new();
        let _ = (&mut f).take(64).read_to_string(&mut holder);
        let holder = holder.trim();
        let holder = if holder.is_empty() { "unknown" } else { holder };
        return Err(OutputDirError::InUse {
            holder: holder.to_string(),
            path,
        });
    }
    if !same_file(&f, &path) {
        return Ok(Locked::Stale);
    }
    let pid = std::process::id();
    if let Err(source) = f
        .set_len(0)
        .and_then(|_| f.seek(SeekFrom::Start(0)))
        .and_then(|_| writeln!(f, "{pid}"))
    {
        return Err(OutputDirError::WriteLock { path, source });
    }
    Ok(Locked::Got(DirLock { file: f, path }))
}

/// Whether a directory entry is bookkeeping that does not make a directory "in use": the lock
/// file and temporary files of a killed run.
pub(crate) fn is_leftover(name: &str) -> bool {
    name == LOCK || (name.starts_with('_') && name.ends_with(".partial"))
}

/// The entries of `dir` (names), or `None` when it does not exist.
pub fn entries(dir: &Path) -> std::io::Result<Option<Vec<String>>> {
    match std::fs::read_dir(dir) {
        Ok(rd) => {
            let mut names = Vec::new();
            for e in rd {
                names.push(e?.file_name().to_string_lossy().into_owned());
            }
            Ok(Some(names))
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e),
    }
}

/// The global chunk index of a chunk file name (`chunk-0000042.parquet` → 42).
pub fn chunk_index(name: &str) -> Option<u64> {
    let digits = name.strip_prefix("chunk-")?.strip_suffix(".parquet")?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// The file name of chunk `chunk`.
pub(crate) fn chunk_file_name(chunk: u64) -> String {
    format!("chunk-{chunk:07}.parquet")
}

/// One finished chunk as the journal records it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChunkEntry {
    /// The chunk's index.
    pub chunk: u64,
    /// Rows in its file.
    pub rows: u64,
    /// Size and CRC-32 of its file.
    pub digest: FileDigest,
}

impl ChunkEntry {
    fn to_line(self) -> String {
        format!(
            "{}\n",
            serde_json::json!({
                "chunk": self.chunk,
                "file": chunk_file_name(self.chunk),
                "rows": self.rows,
                "bytes": self.digest.bytes,
                "crc32": format!("{:08x}", self.digest.crc32),
            })
        )
    }

    fn from_line(line: &str) -> Option<ChunkEntry> {
        let v: serde_json::Value = serde_json::from_str(line).ok()?;
        Some(ChunkEntry {
            chunk: v["chunk"].as_u64()?,
            rows: v["rows"].as_u64()?,
            digest: FileDigest {
                bytes: v["bytes"].as_u64()?,
                crc32: u32::from_str_radix(v["crc32"].as_str()?, 16).ok()?,
            },
        })
    }
}

/// Reads the journal of `dir`: the last entry of each chunk. Lines that do not parse (a torn
/// last line after a kill) are skipped; their chunks count as not finished.
pub fn read_journal(dir: &Path) -> std::io::Result<HashMap<u64, ChunkEntry>> {
    let text = match safe_read::read_bytes(&dir.join(JOURNAL), Limit::Table) {
        Ok(b) => String::from_utf8_lossy(&b).into_owned(),
        Err(e) if e.is_not_found() => String::new(),
        Err(e) => return Err(std::io::Error::other(e.to_string())),
    };
    let mut out = HashMap::new();
    for e in text.lines().filter_map(ChunkEntry::from_line) {
        out.insert(e.chunk, e);
    }
    Ok(out)
}

/// Replaces the journal with exactly `entries`, durably (used when a resume starts).
pub(crate) fn rewrite_journal(dir: &Path, entries: &[ChunkEntry]) -> std::io::Result<()> {
    let text: String = entries.iter().map(|e| e.to_line()).collect();
    write_durably(&dir.join(JOURNAL), text.as_bytes())
}

/// Appends one finished chunk to the journal and fsyncs it.
pub(crate) fn append_journal(dir: &Path, entry: ChunkEntry) -> std::io::Result<()> {
    let mut f = safe_write::open_append(&dir.join(JOURNAL))?;
    f.write_all(entry.to_line().as_bytes())?;
    f.sync_data()
}

/// Why a chunk file kept from an earlier run cannot be trusted (`None`: it matches its entry).
/// A link in a chunk's place is never followed: it is not a file polywear wrote.
pub fn verify_chunk(path: &Path, entry: Option<&ChunkEntry>, rows: u64) -> Option<ChunkMismatch> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if !m.is_file() => {
            return Some(ChunkMismatch::NotAFile(safe_read::kind_name(
                &m.file_type(),
            )))
        }
        Ok(_) => {}
        Err(e) => return Some(ChunkMismatch::Unreadable(e)),
    }
    let Some(entry) = entry else {
        return Some(ChunkMismatch::NotRecorded);
    };
    if entry.rows != rows {
        return Some(ChunkMismatch::Rows {
            recorded: entry.rows,
            expected: rows,
        });
    }
    let d = match FileDigest::of_file(path) {
        Ok(d) => d,
        Err(e) => return Some(ChunkMismatch::Unreadable(e)),
    };
    if d.bytes != entry.digest.bytes {
        return Some(ChunkMismatch::Bytes {
            found: d.bytes,
            recorded: entry.digest.bytes,
        });
    }
    if d.crc32 != entry.digest.crc32 {
        return Some(ChunkMismatch::Crc32 {
            found: d.crc32,
            recorded: entry.digest.crc32,
        });
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn journal_lines_round_trip_and_torn_lines_are_skipped() {
        let e = ChunkEntry {
            chunk: 7,
            rows: 256,
            digest: FileDigest {
                bytes: 1234,
                crc32: 0xdead_beef,
            },
        };
        let line = e.to_line();
        assert_eq!(ChunkEntry::from_line(line.trim()), Some(e));
        assert_eq!(ChunkEntry::from_line(&line[..line.len() / 2]), None);
        assert_eq!(chunk_index("chunk-0000042.parquet"), Some(42));
        assert_eq!(chunk_index("chunk-.parquet"), None);
        assert_eq!(chunk_index("chunk-00x1.parquet"), None);
        assert_eq!(chunk_file_name(42), "chunk-0000042.parquet");
    }

    #[test]
    fn crc32_is_the_standard_one() {
        // The check value of CRC-32/IEEE.
        let dir = std::env::temp_dir().join(format!("polywear-crc-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("x");
        std::fs::write(&f, b"123456789").unwrap();
        let d = FileDigest::of_file(&f).unwrap();
        assert_eq!((d.bytes, d.crc32), (9, 0xcbf4_3926));
        std::fs::remove_dir_all(&dir).ok();
    }
}
