//! Every file polywear writes is created here, so that none is written through a link planted
//! in its place. A file is first written as a fresh `_NAME.partial` beside its final name,
//! created with `O_CREAT | O_EXCL | O_NOFOLLOW` (a new inode that no link can redirect: an
//! entry of that name, a killed run's leftover or a planted link, is unlinked first, which
//! leaves a link's target alone), and then renamed over the final name (a rename replaces a
//! link itself, never its target). Files that are opened in place (the journal, appended to;
//! the lock) are opened with `O_NOFOLLOW` and must be regular files. A directory polywear names
//! itself inside an output directory (`_report`) is refused when it is a link ([`create_dir`]).
//!
//! `NewFile` is the one way to create a file: [`write_file`] and [`write_durably`] write
//! whole files through it, [`crate::parquet_out`] streams Parquet and CSV into it.

use std::fs::{File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// `O_NOFOLLOW | O_NONBLOCK` where the system has them: a link is refused, and a FIFO planted
/// in a file's place neither blocks the open nor is written (it is then refused as not a
/// regular file).
#[cfg(unix)]
fn no_follow(o: &mut OpenOptions) -> &mut OpenOptions {
    use std::os::unix::fs::OpenOptionsExt;
    o.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK)
}

#[cfg(not(unix))]
fn no_follow(o: &mut OpenOptions) -> &mut OpenOptions {
    o
}

/// The error of an open that met a link (`ELOOP` under `O_NOFOLLOW`) or another kind of file
/// than a regular one, in words; any other error as it is, with the folder named when the
/// folder refuses new files (read-only, no permission, full).
fn explain(path: &Path, e: io::Error) -> io::Error {
    #[cfg(unix)]
    if e.raw_os_error() == Some(libc::ELOOP) {
        return io::Error::other(format!(
            "{} is a symbolic link; polywear never writes through a link: remove it",
            path.display()
        ));
    }
    explain_dir(path, e)
}

/// An error of creating or renaming a file in `path`'s folder, naming the folder when it is
/// read-only or out of space.
fn explain_dir(path: &Path, e: io::Error) -> io::Error {
    let dir = parent(path);
    // A path that exists but is no folder, or that runs through a file: say which, not the bare
    // "File exists" / "Not a directory" of the system call.
    if let Ok(m) = std::fs::symlink_metadata(path) {
        if m.file_type().is_symlink() && std::fs::metadata(path).is_err() {
            return io::Error::new(
                e.kind(),
                format!(
                    "{} is a symbolic link to nothing: give a folder",
                    path.display()
                ),
            );
        }
        if !path.is_dir() {
            return io::Error::new(
                e.kind(),
                format!(
                    "{} exists and is not a folder: give a folder",
                    path.display()
                ),
            );
        }
    }
    if e.kind() == io::ErrorKind::NotADirectory {
        let file = path
            .ancestors()
            .skip(1)
            .find(|a| a.is_file())
            .unwrap_or(dir);
        return io::Error::new(
            e.kind(),
            format!(
                "{} cannot be a folder: {} is a file",
                path.display(),
                file.display()
            ),
        );
    }
    let why = match e.kind() {
        io::ErrorKind::PermissionDenied | io::ErrorKind::ReadOnlyFilesystem => "is read-only",
        io::ErrorKind::StorageFull => "is on a full disk",
        _ => return e,
    };
    io::Error::new(
        e.kind(),
        format!(
            "cannot create files in {}: the folder {why} ({e})",
            dir.display()
        ),
    )
}

/// The folder of `path` (`.` for a bare name).
fn parent(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// The hidden temporary name of `path` while it is written: `_NAME.partial` beside it. The
/// leading underscore hides it from pyarrow/pandas directory reads.
pub fn partial_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!("_{name}.partial"))
}

/// Refuses `file` unless it is a regular file (a FIFO, device or directory in its place).
fn regular(path: &Path, file: File) -> io::Result<File> {
    let kind = file.metadata()?.file_type();
    if kind.is_file() {
        return Ok(file);
    }
    Err(io::Error::other(format!(
        "{} is {}, not a regular file; polywear writes only files it creates: remove it",
        path.display(),
        crate::safe_read::kind_name(&kind)
    )))
}

/// A file being written under its temporary name, published under its final name by
/// [`NewFile::commit`] or [`NewFile::commit_durably`]; dropped uncommitted, the temporary
/// file is removed.
#[derive(Debug)]
pub(crate) struct NewFile {
    file: Option<File>,
    tmp: PathBuf,
    path: PathBuf,
}

impl NewFile {
    /// Starts writing `path`: creates `_NAME.partial` beside it as a new file (see the module
    /// comment for why this never writes through a link).
    pub fn create(path: &Path) -> io::Result<NewFile> {
        let tmp = partial_path(path);
        let open = || no_follow(OpenOptions::new().write(true).create_new(true)).open(&tmp);
        let file = match open() {
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
                std::fs::remove_file(&tmp).map_err(|e| explain_dir(&tmp, e))?;
                open()
            }
            r => r,
        }
        .map_err(|e| explain_dir(&tmp, e))?;
        Ok(NewFile {
            file: Some(file),
            tmp,
            path: path.to_path_buf(),
        })
    }

    fn file(&mut self) -> &mut File {
        self.file
            .as_mut()
            .expect("a NewFile holds its file until it is committed")
    }

    /// Renames the temporary file to its final name (replacing a file or a link there).
    pub fn commit(mut self) -> io::Result<()> {
        let mut f = self.file.take().expect("committed once");
        f.flush()?;
        drop(f);
        std::fs::rename(&self.tmp, &self.path).map_err(|e| explain_dir(&self.path, e))
    }

    /// Fsyncs the file, renames it to its final name and fsyncs the folder: after a crash the
    /// final name holds the old file or the whole new one.
    pub fn commit_durably(mut self) -> io::Result<()> {
        let mut f = self.file.take().expect("committed once");
        f.flush()?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&self.tmp, &self.path).map_err(|e| explain_dir(&self.path, e))?;
        sync_dir(parent(&self.path))
    }
}

impl Write for NewFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.file().write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file().flush()
    }
}

impl Drop for NewFile {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Fsyncs a directory, so that a rename or a new file in it survives a crash.
pub fn sync_dir(dir: &Path) -> io::Result<()> {
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    File::open(dir)?.sync_all()
}

/// Writes `bytes` as the file `path` (temporary name, then rename). Readers see the old file or
/// the new one, never a torn one; the file is not fsynced.
pub fn write_file(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut f = NewFile::create(path)?;
    f.write_all(bytes)?;
    f.commit()
}

/// Writes `bytes` as the file `path` crash-safely: temporary name, fsync, rename, directory
/// fsync. A reader (or a resumed run) sees the old file or the new one, never a torn one.
pub fn write_durably(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut f = NewFile::create(path)?;
    f.write_all(bytes)?;
    f.commit_durably()
}

/// Opens `path` to append to it, creating it when absent; a link or anything but a regular file
/// in its place is refused.
pub(crate) fn open_append(path: &Path) -> io::Result<File> {
    let f = no_follow(OpenOptions::new().create(true).append(true))
        .open(path)
        .map_err(|e| explain(path, e))?;
    regular(path, f)
}

/// Opens the lock file `path` for reading and writing in place (its inode is what is locked),
/// creating it when `create`; a link or anything but a regular file in its place is refused.
pub(crate) fn open_lock(path: &Path, create: bool) -> io::Result<File> {
    let f = no_follow(
        OpenOptions::new()
            .read(true)
            .write(true)
            .create(create)
            .truncate(false),
    )
    .open(path)
    .map_err(|e| explain(path, e))?;
    regular(path, f)
}

/// Creates the folder `dir` (and its parents) when missing. A folder the user names may be a
/// link of their choosing; one whose name starts with `_` is polywear's own inside an output
/// directory (`_report`), where a link would send every file elsewhere, and is refused when it
/// is a link.
pub fn create_dir(dir: &Path) -> io::Result<()> {
    let own = dir
        .file_name()
        .is_some_and(|n| n.to_string_lossy().starts_with('_'));
    if own {
        if let Ok(m) = std::fs::symlink_metadata(dir) {
            if m.file_type().is_symlink() {
                return Err(io::Error::other(format!(
                    "{} is a symbolic link; polywear writes its own folders only where it created them: remove the link",
                    dir.display()
                )));
            }
        }
    }
    std::fs::create_dir_all(dir).map_err(|e| explain_dir(dir, e))
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("polywear-safe-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_link_at_the_name_or_the_temporary_name_is_replaced_never_followed() {
        let d = dir("links");
        let target = d.join("target");
        std::fs::write(&target, b"keep").unwrap();
        let path = d.join("out.csv");
        std::os::unix::fs::symlink(&target, &path).unwrap();
        std::os::unix::fs::symlink(&target, partial_path(&path)).unwrap();
        write_file(&path, b"new").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"keep");
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        assert!(!std::fs::symlink_metadata(&path)
            .unwrap()
            .file_type()
            .is_symlink());
        assert!(!partial_path(&path).exists());
        // Files opened in place refuse a link.
        let journal = d.join("journal");
        std::os::unix::fs::symlink(&target, &journal).unwrap();
        let e = open_append(&journal).unwrap_err().to_string();
        assert!(e.contains("symbolic link"), "{e}");
        let e = open_lock(&journal, true).unwrap_err().to_string();
        assert!(e.contains("symbolic link"), "{e}");
        assert_eq!(std::fs::read(&target).unwrap(), b"keep");
        // An own folder that is a link is refused.
        let sub = d.join("_report");
        std::os::unix::fs::symlink(&d, &sub).unwrap();
        assert!(create_dir(&sub).is_err());
        assert!(create_dir(&d.join("plain")).is_ok());
        std::fs::remove_dir_all(&d).ok();
    }

    #[test]
    fn an_uncommitted_file_leaves_nothing_behind() {
        let d = dir("drop");
        let path = d.join("x");
        let mut f = NewFile::create(&path).unwrap();
        f.write_all(b"half").unwrap();
        drop(f);
        assert!(!path.exists() && !partial_path(&path).exists());
        std::fs::remove_dir_all(&d).ok();
    }
}
