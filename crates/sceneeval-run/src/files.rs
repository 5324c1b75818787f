//! A run's output folder: checked for writing before any work ([`check_output_dir`]) and held
//! by one run at a time ([`OutputLock`]). Every file is written through
//! `sceneeval_files::write_atomic`.

use std::path::Path;

use crate::RunError;

/// Checks that results can be written to `dir` before any work is done: creates it if
/// missing, then writes, syncs and removes a probe file in it.
///
/// # Errors
/// [`RunError::OutputNotWritable`] when the folder cannot be created or written (read-only,
/// vanished, a file in its place, no space left).
pub fn check_output_dir(dir: &Path) -> Result<(), RunError> {
    sceneeval_files::check_writable_dir(dir).map_err(|source| RunError::OutputNotWritable {
        path: dir.to_owned(),
        source,
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
    /// let first = sceneeval_run::OutputLock::acquire(dir.path()).unwrap();
    /// let err = sceneeval_run::OutputLock::acquire(dir.path()).unwrap_err();
    /// assert!(err.to_string().contains("another sceneeval run"), "{err}");
    /// drop(first);
    /// assert!(sceneeval_run::OutputLock::acquire(dir.path()).is_ok());
    /// ```
    ///
    /// # Errors
    /// [`RunError::OutputInUse`] when another run holds it; [`RunError::File`] when the lock
    /// file cannot be opened or locked.
    pub fn acquire(dir: &Path) -> Result<Self, RunError> {
        let path = dir.join(LOCK_FILE);
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(|e| RunError::file(&path, e))?;
        match file.try_lock() {
            Ok(()) => Ok(OutputLock { _file: file }),
            Err(std::fs::TryLockError::WouldBlock) => Err(RunError::OutputInUse { path: dir.to_owned() }),
            Err(std::fs::TryLockError::Error(e)) => Err(RunError::file(&path, e)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unwritable_output_folders_are_found_before_work() {
        let dir = tempfile::tempdir().unwrap();
        // A file where the folder should be.
        let file = dir.path().join("out");
        std::fs::write(&file, "x").unwrap();
        let err = check_output_dir(&file).unwrap_err();
        assert!(matches!(err, RunError::OutputNotWritable { .. }), "{err}");
        assert!(err.to_string().contains("out"), "{err}");
        // A folder below a file cannot be created either (also for root, unlike permissions).
        assert!(matches!(
            check_output_dir(&file.join("sub")),
            Err(RunError::OutputNotWritable { .. })
        ));
        assert!(check_output_dir(&dir.path().join("new")).is_ok());
        assert!(dir.path().join("new").is_dir());
        assert_eq!(std::fs::read_dir(dir.path().join("new")).unwrap().count(), 0);
    }
}
