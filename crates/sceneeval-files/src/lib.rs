//! How SceneEval touches files, in one place for every crate that reads input or writes
//! results:
//!
//! - **Input is opened only when it is a regular file** ([`open_regular`], [`check_regular`]):
//!   a named pipe (FIFO) would block the reader forever (opening one waits for a writer), a
//!   device could be endless, a directory is not data. The kind is checked after following
//!   symbolic links and *before* the file is opened, so nothing blocks; the error says what the
//!   path is instead ([`NotRegularFile`]).
//! - **Output goes through a unique temporary file and an atomic rename** ([`write_atomic`],
//!   [`write_atomic_with`]): the bytes are written to a temporary file with a unique name in the
//!   target's folder, flushed to disk, then renamed over the target and the folder synced.
//!   Readers see the old file or the whole new one, never a part or an empty file (a full disk
//!   fails the write and leaves the old file); two processes writing the same file at once both
//!   succeed and leave one of the two contents whole.
//! - **Output has the permissions the user expects**: a new file gets the mode the umask gives
//!   (`0o666 & !umask`: 0644 under the usual umask 022, 0664 under 002), as `touch` or a shell
//!   redirection would create it, and a file that is replaced keeps its mode (a 0664 file
//!   rewritten in place stays 0664), so colleagues on a shared machine can read results.
//! - **CSV cells are safe to open in a spreadsheet** ([`csv_cell`]): a text cell that a
//!   spreadsheet would run as a formula is escaped by every CSV writer of the workspace, and
//!   unescaped by the readers of CSV files the tool wrote.
//!
//! Errors are [`std::io::Error`]s without the path; callers wrap them in their own error types,
//! which name the file. Every front end shows such an error with its causes one way:
//! [`ErrorChain`] (each cause the message before it does not already say, on one line or one per
//! line), the one printer of error chains of the workspace.
//!
//! ```
//! let dir = tempfile::tempdir().unwrap();
//! let path = dir.path().join("out").join("eval.json");
//! sceneeval_files::write_atomic(&path, b"{}").unwrap();
//! let mut text = String::new();
//! std::io::Read::read_to_string(&mut sceneeval_files::open_regular(&path).unwrap(), &mut text).unwrap();
//! assert_eq!(text, "{}");
//!
//! // A folder is not a regular file: refused before it is opened, saying what it is.
//! let err = sceneeval_files::open_regular(dir.path()).unwrap_err();
//! assert_eq!(err.to_string(), "is a directory, not a regular file");
//! ```

mod chain;

pub use chain::{ErrorChain, causes};
pub mod csv_cell;

use std::fmt;
use std::fs::{File, Metadata};
use std::io::{self, Write};
use std::path::Path;

/// What a path that is not a regular file is: the error [`check_regular`] and
/// [`open_regular`] return (as the [`io::Error`]'s inner error, kind
/// [`io::ErrorKind::InvalidInput`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NotRegularFile {
    /// `a directory`, `a named pipe (FIFO)`, `a socket`, `a block device`, `a character
    /// device`, or `not a regular file`.
    pub kind: &'static str,
}

impl fmt::Display for NotRegularFile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "is {}, not a regular file", self.kind)
    }
}

impl std::error::Error for NotRegularFile {}

/// What kind of file `meta` describes, in words, when it is not a regular file.
fn kind_of(meta: &Metadata) -> &'static str {
    let t = meta.file_type();
    if t.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a named pipe (FIFO)";
        }
        if t.is_socket() {
            return "a socket";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_char_device() {
            return "a character device";
        }
    }
    "something else"
}

/// Checks, without opening it, that `path` is a regular file once symbolic links are followed,
/// and returns its metadata.
///
/// # Errors
/// The operating system's error when the path cannot be looked up (not found, no
/// permission); an error of kind [`io::ErrorKind::InvalidInput`] holding a [`NotRegularFile`]
/// that says what it is otherwise.
pub fn check_regular(path: &Path) -> io::Result<Metadata> {
    let meta = std::fs::metadata(path)?;
    if meta.is_file() {
        Ok(meta)
    } else {
        Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            NotRegularFile { kind: kind_of(&meta) },
        ))
    }
}

/// Opens `path` for reading when it is a regular file ([`check_regular`] first, so a named
/// pipe is never opened and nothing blocks), and checks the opened file again (a file
/// swapped for something else between the check and the open is refused too).
///
/// # Errors
/// As [`check_regular`], and the operating system's error when the file cannot be opened.
pub fn open_regular(path: &Path) -> io::Result<File> {
    check_regular(path)?;
    let file = File::open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            NotRegularFile { kind: kind_of(&meta) },
        ));
    }
    Ok(file)
}

/// Checks that files can be written into `dir` before any work is done: creates it if
/// missing, then writes, syncs and removes a probe file in it.
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// sceneeval_files::check_writable_dir(&dir.path().join("new")).unwrap();
/// assert!(dir.path().join("new").is_dir());
/// // A file where the folder should be.
/// std::fs::write(dir.path().join("file"), "x").unwrap();
/// assert!(sceneeval_files::check_writable_dir(&dir.path().join("file")).is_err());
/// ```
///
/// # Errors
/// Why the folder cannot be created or written (read-only, vanished, a file in its place, no
/// space left).
pub fn check_writable_dir(dir: &Path) -> io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let probe = dir.join(format!(".sceneeval-write-check.{}", std::process::id()));
    let result = (|| {
        let mut f = File::create(&probe)?;
        f.write_all(b"ok")?;
        f.sync_all()?;
        drop(f);
        std::fs::remove_file(&probe)
    })();
    result.inspect_err(|_| {
        let _ = std::fs::remove_file(&probe);
    })
}

/// Writes `bytes` to `path` atomically; see [`write_atomic_with`].
///
/// # Errors
/// As [`write_atomic_with`].
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic_with(path, |file| file.write_all(bytes))
}

/// Writes a file atomically: `write` fills a temporary file with a unique name in `path`'s
/// folder (`.<name>.<random>.tmp`), which is flushed to disk (`fsync`) and then renamed over
/// `path`; the folder is synced so that the rename itself survives a power cut. The folder is
/// created if missing.
///
/// Readers see either the old file or the complete new one, never a part. If `write` fails
/// (a full disk, an encoder error) the old file stays and the temporary file is removed; if
/// the process dies, the temporary file is left behind under its temporary name, never under
/// `path`. Concurrent writers of one path each use their own temporary file: all succeed and
/// the file ends as one writer's whole content.
///
/// Permissions (Unix): the temporary file is created with mode `0o666` as `open(2)` applies
/// the umask to it, so a new file gets the mode the umask gives (0644 under umask 022), not
/// the 0600 of a private temporary file; when `path` exists, its mode (after following
/// symbolic links) is given to the new content before the rename, so a rewritten file keeps
/// its permissions.
///
/// # Errors
/// The error of `write`, or of creating, syncing or renaming the temporary file.
pub fn write_atomic_with(path: &Path, write: impl FnOnce(&mut File) -> io::Result<()>) -> io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir)?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // The mode `open(2)` is given; the kernel takes the umask off it.
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut tmp = builder.tempfile_in(dir)?;
    write(tmp.as_file_mut())?;
    tmp.as_file_mut().flush()?;
    #[cfg(unix)]
    if let Ok(old) = std::fs::metadata(path) {
        // The file being replaced keeps its mode (fchmod: the umask does not apply).
        tmp.as_file().set_permissions(old.permissions())?;
    }
    tmp.as_file().sync_all()?;
    // On failure the temporary file is dropped, which removes it.
    tmp.persist(path).map_err(|e| e.error)?;
    sync_dir(dir);
    Ok(())
}

/// Makes a rename in `dir` durable (a no-op where folders cannot be opened for syncing).
fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}
