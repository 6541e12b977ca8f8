//! Every file polywear reads is opened here: only a regular file is read (a device such as
//! `/dev/zero`, a FIFO or a directory is refused at once, before a byte is read, so that no
//! input hangs or fills memory), and no more than the limit of its kind, which the refusal
//! names. The open itself never blocks (`O_NONBLOCK`, which a regular file ignores).

use std::fs::{File, FileType, OpenOptions};
use std::io::{self, Read};
use std::path::{Path, PathBuf};

/// The kinds of file polywear reads, each with its size limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// A TOML or JSON file people write or polywear writes about a run (study, parameter and
    /// targets files, a run's manifest): 16 MiB, far above any real one (a study's text is
    /// stored in every output's metadata).
    Text,
    /// A table of numbers (operating points, a drive cycle, classify's points) or a run's
    /// journal: 1 GiB, read whole into memory.
    Table,
    /// A Parquet chunk of a run: 64 GiB (read in streaming queries, never whole).
    Chunk,
}

impl Limit {
    /// The largest accepted size \[bytes\].
    pub fn bytes(self) -> u64 {
        match self {
            Limit::Text => 16 << 20,
            Limit::Table => 1 << 30,
            Limit::Chunk => 64 << 30,
        }
    }

    /// The limit as people read it (`16 MiB`).
    pub fn text(self) -> &'static str {
        match self {
            Limit::Text => "16 MiB",
            Limit::Table => "1 GiB",
            Limit::Chunk => "64 GiB",
        }
    }
}

/// Why a file is not read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// An empty path (`file = ""`).
    #[error("no file named (the path is empty)")]
    EmptyPath,
    /// The system refused to open or read it.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: io::Error,
    },
    /// Not a regular file.
    #[error("{}: is {kind}, not a regular file; accepted: a regular file", path.display())]
    NotAFile {
        /// The file.
        path: PathBuf,
        /// What it is, in words (`a directory`, `a character device`).
        kind: &'static str,
    },
    /// Larger than its kind's limit.
    #[error("{}: {bytes} bytes is larger than the {limit} accepted for this kind of file", path.display())]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size (or what was read of it) \[bytes\].
        bytes: u64,
        /// The limit, in words.
        limit: &'static str,
    },
    /// Not UTF-8 text.
    #[error("{}: not UTF-8 text (byte {valid_up_to} is not part of a character)", path.display())]
    NotUtf8 {
        /// The file.
        path: PathBuf,
        /// Bytes before the first that breaks the text.
        valid_up_to: usize,
    },
}

impl ReadError {
    /// The reason alone, without the file's name (for a message that names it already).
    pub fn reason(&self) -> String {
        let text = self.to_string();
        let path = match self {
            ReadError::EmptyPath => return text,
            ReadError::Io { path, .. }
            | ReadError::NotAFile { path, .. }
            | ReadError::TooLarge { path, .. }
            | ReadError::NotUtf8 { path, .. } => path,
        };
        let prefix = format!("{}: ", path.display());
        text.strip_prefix(&prefix)
            .map_or(text.clone(), str::to_string)
    }

    /// Whether the file does not exist.
    pub fn is_not_found(&self) -> bool {
        matches!(self, ReadError::Io { source, .. } if source.kind() == io::ErrorKind::NotFound)
    }
}

/// What a file that is not regular is, in words.
pub(crate) fn kind_name(t: &FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a directory"
    } else if t.is_symlink() {
        "a symbolic link"
    } else if t.is_file() {
        "a regular file"
    } else {
        "not a regular file"
    }
}

#[cfg(unix)]
fn non_blocking(o: &mut OpenOptions) -> &mut OpenOptions {
    use std::os::unix::fs::OpenOptionsExt;
    o.custom_flags(libc::O_NONBLOCK)
}

#[cfg(not(unix))]
fn non_blocking(o: &mut OpenOptions) -> &mut OpenOptions {
    o
}

/// Opens `path` for reading when it is a regular file within `limit`; returns it with its size.
pub fn open(path: &Path, limit: Limit) -> Result<(File, u64), ReadError> {
    if path.as_os_str().is_empty() {
        return Err(ReadError::EmptyPath);
    }
    let io = |source| ReadError::Io {
        path: path.to_path_buf(),
        source,
    };
    let f = non_blocking(OpenOptions::new().read(true))
        .open(path)
        .map_err(io)?;
    let m = f.metadata().map_err(io)?;
    if !m.is_file() {
        return Err(ReadError::NotAFile {
            path: path.to_path_buf(),
            kind: kind_name(&m.file_type()),
        });
    }
    if m.len() > limit.bytes() {
        return Err(ReadError::TooLarge {
            path: path.to_path_buf(),
            bytes: m.len(),
            limit: limit.text(),
        });
    }
    Ok((f, m.len()))
}

/// Checks that `path` is a regular file within `limit` (for a file another library opens).
pub fn check(path: &Path, limit: Limit) -> Result<u64, ReadError> {
    open(path, limit).map(|(_, n)| n)
}

/// The bytes of `path`, a regular file within `limit` (a file that grows while it is read is
/// cut at the limit and refused).
pub(crate) fn read_bytes(path: &Path, limit: Limit) -> Result<Vec<u8>, ReadError> {
    let (f, len) = open(path, limit)?;
    let mut bytes = Vec::with_capacity(len as usize);
    f.take(limit.bytes() + 1)
        .read_to_end(&mut bytes)
        .map_err(|source| ReadError::Io {
            path: path.to_path_buf(),
            source,
        })?;
    if bytes.len() as u64 > limit.bytes() {
        return Err(ReadError::TooLarge {
            path: path.to_path_buf(),
            bytes: bytes.len() as u64,
            limit: limit.text(),
        });
    }
    Ok(bytes)
}

/// The text of `path`, a regular UTF-8 file within `limit`.
pub fn read_text(path: &Path, limit: Limit) -> Result<String, ReadError> {
    let bytes = read_bytes(path, limit)?;
    String::from_utf8(bytes).map_err(|e| ReadError::NotUtf8 {
        path: path.to_path_buf(),
        valid_up_to: e.utf8_error().valid_up_to(),
    })
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn only_regular_files_within_the_limit_are_read() {
        let e = read_bytes(Path::new("/dev/zero"), Limit::Table).unwrap_err();
        assert!(e.to_string().contains("a character device"), "{e}");
        let e = read_text(Path::new("/"), Limit::Text).unwrap_err();
        assert!(e.to_string().contains("a directory"), "{e}");
        let e = read_text(Path::new(""), Limit::Text).unwrap_err();
        assert!(e.to_string().contains("empty"), "{e}");
        let dir = std::env::temp_dir().join(format!("polywear-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("fifo");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: mkfifo on a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        let e = read_text(&fifo, Limit::Text).unwrap_err();
        assert!(e.to_string().contains("FIFO"), "{e}");
        let big = dir.join("big");
        let f = File::create(&big).unwrap();
        f.set_len(Limit::Text.bytes() + 1).unwrap();
        let e = read_text(&big, Limit::Text).unwrap_err().to_string();
        assert!(e.contains("16 MiB"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
