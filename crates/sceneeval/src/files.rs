//! Writing result files so that a crash never leaves a truncated or empty file in place of a
//! good one.

use std::io::Write;
use std::path::Path;

use crate::EvalError;

/// Writes `bytes` to `path` atomically; see [`write_atomic_with`].
///
/// # Errors
/// [`EvalError::File`] naming the file when the folder cannot be created or written.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), EvalError> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// Writes a file atomically: `write` fills a temporary file with a unique name in the same
/// folder (`.<name>.<random>.tmp`), which is flushed to disk (`fsync`) and then renamed over
/// `path`, and the folder is synced so that the rename itself survives a power cut. Readers
/// see either the old file or the complete new one, never a part; if `write` fails or the
/// process dies, the old file stays and the temporary file is removed (or left behind, named
/// as above, when the process died). The folder is created if missing. Every crate writes
/// its files this way ([`sceneeval_files::write_atomic_with`]).
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// let path = dir.path().join("summary.md");
/// sceneeval::write_atomic(&path, b"old").unwrap();
/// // A write that fails half way leaves the old content.
/// let r = sceneeval::write_atomic_with(&path, |w| {
///     use std::io::Write;
///     w.write_all(b"new, but")?;
///     Err(std::io::Error::other("killed"))
/// });
/// assert!(r.is_err());
/// assert_eq!(std::fs::read(&path).unwrap(), b"old");
/// assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "no temporary file left");
/// ```
///
/// # Errors
/// [`EvalError::File`] naming the file.
pub fn write_atomic_with(
    path: &Path,
    write: impl FnOnce(&mut std::fs::File) -> std::io::Result<()>,
) -> Result<(), EvalError> {
    sceneeval_files::write_atomic_with(path, write).map_err(|e| EvalError::file(path, e))
}

/// Checks that results can be written to `dir` before any work is done: creates it if
/// missing, then writes, syncs and removes a probe file in it.
///
/// # Errors
/// [`EvalError::OutputNotWritable`] when the folder cannot be created or written (read-only,
/// vanished, a file in its place, no space left).
pub fn check_output_dir(dir: &Path) -> Result<(), EvalError> {
    let not_writable = |source| EvalError::OutputNotWritable {
        path: dir.to_owned(),
        source,
    };
    std::fs::create_dir_all(dir).map_err(not_writable)?;
    let probe = dir.join(format!(".sceneeval-write-check.{}", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&probe)?;
        f.write_all(b"ok")?;
        f.sync_all()?;
        drop(f);
        std::fs::remove_file(&probe)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&probe);
        not_writable(e)
    })
}

/// The lock file of an output folder (see [`OutputLock`]).
pub const LOCK_FILE: &str = ".sceneeval.lock";

/// An output folder held by one run: [`LOCK_FILE`] in it, locked (an advisory lock of the
/// operating system, released when the run ends or its process dies) while the run lasts, so
/// that a second run on the same folder stops at once with a clear error instead of racing
/// the first one for its files. The file itself stays (empty) after the run.
#[derive(Debug)]
pub struct OutputLock {
    _file: std::fs::File,
}

impl OutputLock {
    /// Locks `dir` (which must exist) for this run.
    ///
    /// ```
    /// let dir = tempfile::tempdir().unwrap();
    /// let first = sceneeval::OutputLock::acquire(dir.path()).unwrap();
    /// let err = sceneeval::OutputLock::acquire(dir.path()).unwrap_err();
    /// assert!(err.to_string().contains("another sceneeval run"), "{err}");
    /// drop(first);
    /// assert!(sceneeval::OutputLock::acquire(dir.path()).is_ok());
    /// ```
    ///
    /// # Errors
    /// [`EvalError::OutputInUse`] when another run holds it; [`EvalError::File`] when the lock
    /// file cannot be opened or locked.
    pub fn acquire(dir: &Path) -> Result<Self, EvalError> {
        let path = dir.join(LOCK_FILE);
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(|e| EvalError::file(&path, e))?;
        match file.try_lock() {
            Ok(()) => Ok(OutputLock { _file: file }),
            Err(std::fs::TryLockError::WouldBlock) => Err(EvalError::OutputInUse { path: dir.to_owned() }),
            Err(std::fs::TryLockError::Error(e)) => Err(EvalError::file(&path, e)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_writes_replace_whole_files() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sub").join("eval.json");
        write_atomic(&path, b"first").unwrap();
        write_atomic(&path, b"second").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"second");
        let names = sceneeval_test_support::file_names(path.parent().unwrap());
        assert_eq!(names, vec!["eval.json"]);
    }

    #[test]
    fn unwritable_output_folders_are_found_before_work() {
        let dir = tempfile::tempdir().unwrap();
        // A file where the folder should be.
        let file = dir.path().join("out");
        std::fs::write(&file, "x").unwrap();
        let err = check_output_dir(&file).unwrap_err();
        assert!(matches!(err, EvalError::OutputNotWritable { .. }), "{err}");
        assert!(err.to_string().contains("out"), "{err}");
        // A folder below a file cannot be created either (also for root, unlike permissions).
        assert!(matches!(
            check_output_dir(&file.join("sub")),
            Err(EvalError::OutputNotWritable { .. })
        ));
        assert!(check_output_dir(&dir.path().join("new")).is_ok());
        assert!(dir.path().join("new").is_dir());
        assert_eq!(std::fs::read_dir(dir.path().join("new")).unwrap().count(), 0);
    }
}
