//! The output folder: built whole in a temporary folder next to it and renamed into place,
//! so that a conversion that fails, is interrupted or is killed never leaves a half-written
//! output folder.
//!
//! The temporary folder `.<name>.convert-XXXXXX` is locked (an advisory `flock` on the folder
//! itself, Unix) for as long as its conversion runs. A conversion that fails or is interrupted
//! ([`crate::ConvertOptions::with_interrupt`]) removes its own; one that is killed cannot, and
//! the next conversion into the same output removes every such folder that no running
//! conversion holds: the lock, not the folder's age, tells an abandoned folder from a live one.
//! Folders are created with the permissions the umask gives (tempfile's own are 0700), so the
//! output is as readable as any folder the user makes.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use sceneeval_scene::{Room, Scene, SceneObject};

use crate::ConvertError;

/// Between the temporary folder's prefix (`.<name>`) and its random part.
const INFIX: &str = ".convert-";
/// Letters and digits in the random part of the temporary folder's name.
const RANDOM_CHARS: usize = 6;
/// How many temporary folders are tried when a cleaning conversion takes the new one away.
const ATTEMPTS: usize = 8;

/// A locked temporary folder beside the output folder, removed on drop unless committed.
#[derive(Debug)]
pub(crate) struct Staging {
    dir: tempfile::TempDir,
    out: PathBuf,
    /// The lock on `dir`, held until the staging is dropped (`None` where folders cannot be
    /// locked).
    _lock: Option<File>,
}

impl Staging {
    /// A temporary folder `.<name>.convert-XXXXXX` in `out`'s parent (created if needed),
    /// locked, after removing the abandoned ones of earlier conversions into `out`. `out` must
    /// not exist, or be an empty folder.
    pub(crate) fn new(out: &Path) -> Result<Staging, ConvertError> {
        if out.exists() {
            let empty = std::fs::read_dir(out)
                .map(|mut entries| entries.next().is_none())
                .unwrap_or(false);
            if !out.is_dir() || !empty {
                return Err(ConvertError::OutputExists { path: out.to_owned() });
            }
        }
        let parent = match out.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
            _ => PathBuf::from("."),
        };
        std::fs::create_dir_all(&parent).map_err(|e| ConvertError::output(&parent, e))?;
        let name = out
            .file_name()
            .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
        let prefix = format!(".{name}{INFIX}");
        remove_abandoned(&parent, &prefix);
        let mut builder = tempfile::Builder::new();
        builder.prefix(&prefix).rand_bytes(RANDOM_CHARS);
        #[cfg(unix)]
        builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o777));
        for _ in 0..ATTEMPTS {
            let dir = builder
                .tempdir_in(&parent)
                .map_err(|e| ConvertError::output(&parent, e))?;
            match lock::try_hold(dir.path()) {
                Ok(Some(lock)) => {
                    return Ok(Staging {
                        dir,
                        out: out.to_owned(),
                        _lock: lock,
                    });
                }
                // Another conversion, cleaning up, took it between its creation and the lock:
                // that one removes it.
                Ok(None) => {
                    let _ = dir.keep();
                }
                Err(e) => return Err(ConvertError::output(dir.path(), e)),
            }
        }
        Err(ConvertError::output(
            &parent,
            std::io::Error::other("cannot create and lock a temporary folder"),
        ))
    }

    /// The temporary folder, where every output file is written.
    pub(crate) fn path(&self) -> &Path {
        self.dir.path()
    }

    /// Moves the finished folder to the output path (one rename; an empty output folder is
    /// removed first).
    pub(crate) fn commit(self) -> Result<PathBuf, ConvertError> {
        if self.out.is_dir() {
            std::fs::remove_dir(&self.out).map_err(|e| ConvertError::output(&self.out, e))?;
        }
        std::fs::rename(self.dir.path(), &self.out).map_err(|e| ConvertError::output(&self.out, e))?;
        // The folder now lives at `out`; nothing is left to remove.
        let _ = self.dir.keep();
        Ok(self.out)
    }
}

/// Removes the temporary folders `<prefix>XXXXXX` in `parent` that no running conversion
/// holds. Problems are logged, never fatal: they cost disk space, not the conversion.
fn remove_abandoned(parent: &Path, prefix: &str) {
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(random) = name.to_str().and_then(|n| n.strip_prefix(prefix)) else {
            continue;
        };
        // A folder (not a link to one) named as this module names them.
        if random.len() != RANDOM_CHARS
            || !random.bytes().all(|b| b.is_ascii_alphanumeric())
            || !entry.file_type().is_ok_and(|t| t.is_dir())
        {
            continue;
        }
        let path = entry.path();
        match lock::try_hold(&path) {
            Ok(Some(_held)) => match std::fs::remove_dir_all(&path) {
                Ok(()) => tracing::info!(
                    folder = %path.display(),
                    "removed the temporary folder of an earlier conversion that did not finish"
                ),
                Err(e) => tracing::warn!(
                    folder = %path.display(),
                    error = %e,
                    "cannot remove the temporary folder of an earlier conversion"
                ),
            },
            Ok(None) => {
                tracing::debug!(folder = %path.display(), "in use by a running conversion; left alone")
            }
            Err(e) => {
                tracing::warn!(folder = %path.display(), error = %e, "cannot tell whether a conversion still uses this folder; left alone")
            }
        }
    }
}

#[cfg(unix)]
mod lock {
    use std::fs::{File, TryLockError};
    use std::io::ErrorKind;
    use std::os::unix::fs::MetadataExt;
    use std::path::Path;

    /// Locks the folder `dir` for this process: `Some(Some(file))` while the returned file is
    /// held, `None` when another process holds it or it is gone.
    pub(super) fn try_hold(dir: &Path) -> std::io::Result<Option<Option<File>>> {
        let file = match File::open(dir) {
            Ok(f) => f,
            Err(e) if e.kind() == ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(e),
        };
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => return Ok(None),
            Err(TryLockError::Error(e)) => return Err(e),
        }
        // Removed (and its name perhaps taken again) between the open and the lock?
        let held = file.metadata()?;
        match std::fs::symlink_metadata(dir) {
            Ok(now) if now.dev() == held.dev() && now.ino() == held.ino() => Ok(Some(Some(file))),
            Ok(_) => Ok(None),
            Err(e) if e.kind() == ErrorKind::NotFound => Ok(None),
            Err(e) => Err(e),
        }
    }
}

#[cfg(not(unix))]
mod lock {
    use std::fs::File;
    use std::path::Path;

    /// Folders are not locked here: a folder counts as held, so none is ever removed as
    /// abandoned, and the conversion's own goes unlocked.
    pub(super) fn try_hold(_dir: &Path) -> std::io::Result<Option<Option<File>>> {
        Ok(Some(None))
    }
}

/// Where a conversion writes: the temporary folder, and the flag that interrupts it. Every
/// file of the output is written through it, and each write first checks the flag.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Output<'a> {
    dir: &'a Path,
    interrupt: Option<&'a AtomicBool>,
}

impl<'a> Output<'a> {
    /// Writing into `dir`, interrupted once `interrupt` is set.
    pub(crate) fn new(dir: &'a Path, interrupt: Option<&'a AtomicBool>) -> Self {
        Output { dir, interrupt }
    }

    /// [`ConvertError::Interrupted`] once the flag is set.
    pub(crate) fn check(&self) -> Result<(), ConvertError> {
        match self.interrupt {
            Some(flag) if flag.load(Ordering::SeqCst) => Err(ConvertError::Interrupted),
            _ => Ok(()),
        }
    }

    /// `scene_<id>.json` in the folder.
    pub(crate) fn scene_file(&self, id: u64) -> PathBuf {
        self.dir.join(format!("scene_{id}.json"))
    }

    /// Writes a converted scene as `scene_<id>.json`; `file` is the generator's file it came
    /// from, named when the objects and rooms do not make a valid scene.
    pub(crate) fn write_scene(
        &self,
        objects: Vec<SceneObject>,
        rooms: Vec<Room>,
        file: &Path,
        id: u64,
    ) -> Result<(), ConvertError> {
        self.check()?;
        let path = self.scene_file(id);
        let scene = Scene::new(None, objects, rooms).map_err(|e| ConvertError::scene(file, "", e))?;
        sceneeval_io::write_scene_state(&scene, &path).map_err(|e| ConvertError::Verify {
            path,
            source: Box::new(e),
        })
    }

    /// Writes `text` to `rel` in the folder, creating its folder.
    pub(crate) fn write_text(&self, rel: &Path, text: &str) -> Result<(), ConvertError> {
        self.check()?;
        let path = self.dir.join(rel);
        if let Some(parent) = path.parent() {
            create_dir(parent)?;
        }
        std::fs::write(&path, text).map_err(|e| ConvertError::output(&path, e))
    }

    /// Copies the regular file `from` to `rel` in the folder, creating its folder.
    pub(crate) fn copy_file(&self, from: &Path, rel: &Path) -> Result<(), ConvertError> {
        self.check()?;
        let meta = std::fs::symlink_metadata(from).map_err(|e| ConvertError::output(from, e))?;
        if !meta.is_file() {
            return Err(ConvertError::output(
                from,
                std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a regular file"),
            ));
        }
        let to = self.dir.join(rel);
        if let Some(parent) = to.parent() {
            create_dir(parent)?;
        }
        std::fs::copy(from, &to).map_err(|e| ConvertError::output(from, e))?;
        Ok(())
    }
}

/// Creates `dir` and its parents.
fn create_dir(dir: &Path) -> Result<(), ConvertError> {
    std::fs::create_dir_all(dir).map_err(|e| ConvertError::output(dir, e))
}

/// Every regular file under `dir`, relative to it, sorted; symbolic links and other special
/// files are refused.
pub(crate) fn files_under(dir: &Path) -> Result<Vec<PathBuf>, ConvertError> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), ConvertError> {
        let entries = std::fs::read_dir(dir).map_err(|e| ConvertError::output(dir, e))?;
        for entry in entries {
            let entry = entry.map_err(|e| ConvertError::output(dir, e))?;
            let path = entry.path();
            let kind = entry.file_type().map_err(|e| ConvertError::output(&path, e))?;
            if kind.is_dir() {
                walk(root, &path, out)?;
            } else if kind.is_file() {
                out.push(path.strip_prefix(root).unwrap_or(&path).to_owned());
            } else {
                return Err(ConvertError::output(
                    &path,
                    std::io::Error::new(
                        std::io::ErrorKind::InvalidInput,
                        "not a regular file or folder (symbolic links are not followed)",
                    ),
                ));
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out)?;
    out.sort();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dropped_staging_folder_leaves_nothing() {
        let parent = tempfile::tempdir().unwrap();
        let out = parent.path().join("converted");
        let staging = Staging::new(&out).unwrap();
        let output = Output::new(staging.path(), None);
        output.write_text(Path::new("scene_1.json"), "{}").unwrap();
        drop(staging);
        assert_eq!(std::fs::read_dir(parent.path()).unwrap().count(), 0);
        assert!(!out.exists());
    }

    #[cfg(unix)]
    #[test]
    fn abandoned_temporary_folders_are_removed_and_live_ones_kept() {
        let parent = tempfile::tempdir().unwrap();
        let out = parent.path().join("converted");
        // A running conversion's folder: locked.
        let live = Staging::new(&out).unwrap();
        // A killed one's, with files in it.
        let dead = parent.path().join(".converted.convert-Ab12Cd");
        std::fs::create_dir_all(dead.join("scene_0/assets")).unwrap();
        std::fs::write(dead.join("scene_0.json"), "{}").unwrap();
        // What is not a temporary folder of this output: other names, a file, a link to a
        // folder (not followed).
        let keep = parent.path().join("keep");
        std::fs::create_dir(&keep).unwrap();
        std::fs::write(keep.join("mine.json"), "{}").unwrap();
        let others = [
            ".converted.convert-Ab12Cd7",
            ".other.convert-Ab12Cd",
            ".converted.convert-Ab-2Cd",
        ]
        .map(|n| parent.path().join(n));
        for o in &others {
            std::fs::create_dir(o).unwrap();
        }
        let file = parent.path().join(".converted.convert-Zz99Zy");
        std::fs::write(&file, "").unwrap();
        let link = parent.path().join(".converted.convert-Zz99Zz");
        std::os::unix::fs::symlink(&keep, &link).unwrap();

        let second = Staging::new(&out).unwrap();
        assert!(!dead.exists(), "the abandoned folder is removed");
        assert!(live.path().is_dir(), "the running conversion's folder is kept");
        assert!(second.path().is_dir() && second.path() != live.path());
        assert!(others.iter().all(|o| o.is_dir()) && file.is_file());
        assert!(link.is_symlink() && keep.join("mine.json").is_file());
        // Once its conversion is over (here: dropped as if killed, its lock released), a
        // folder left behind is removed by the next conversion.
        let left = live.path().to_owned();
        let _ = live.dir.keep();
        drop(live._lock);
        assert!(left.is_dir());
        let third = Staging::new(&out).unwrap();
        assert!(!left.exists());
        assert!(second.path().is_dir(), "still held");
        drop((second, third));
    }

    #[cfg(unix)]
    #[test]
    fn folders_get_the_mode_the_umask_gives() {
        use std::os::unix::fs::PermissionsExt;
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o7777;
        let parent = tempfile::tempdir().unwrap();
        // What this process's umask gives a new folder.
        let probe = parent.path().join("probe");
        std::fs::create_dir(&probe).unwrap();
        let expected = mode(&probe);
        let staging = Staging::new(&parent.path().join("converted")).unwrap();
        assert_eq!(mode(staging.path()), expected, "not tempfile's 0700");
        Output::new(staging.path(), None)
            .write_text(Path::new("scene_0/assets/a.json"), "{}")
            .unwrap();
        assert_eq!(mode(&staging.path().join("scene_0/assets")), expected);
    }

    #[test]
    fn an_interrupted_output_writes_nothing_more() {
        let dir = tempfile::tempdir().unwrap();
        let flag = AtomicBool::new(false);
        let output = Output::new(dir.path(), Some(&flag));
        output.write_text(Path::new("a.json"), "{}").unwrap();
        flag.store(true, Ordering::SeqCst);
        assert!(matches!(
            output.write_text(Path::new("b.json"), "{}"),
            Err(ConvertError::Interrupted)
        ));
        assert!(matches!(
            output.copy_file(&dir.path().join("a.json"), Path::new("c.json")),
            Err(ConvertError::Interrupted)
        ));
        assert_eq!(files_under(dir.path()).unwrap(), [PathBuf::from("a.json")]);
    }

    #[test]
    fn commit_renames_into_a_new_or_empty_folder_only() {
        let parent = tempfile::tempdir().unwrap();
        let out = parent.path().join("a/b/converted");
        let staging = Staging::new(&out).unwrap();
        Output::new(staging.path(), None)
            .write_text(Path::new("x/scene_1.json"), "{}")
            .unwrap();
        assert_eq!(staging.commit().unwrap(), out);
        assert_eq!(files_under(&out).unwrap(), vec![PathBuf::from("x/scene_1.json")]);
        // Only the output folder is left beside it.
        assert_eq!(std::fs::read_dir(out.parent().unwrap()).unwrap().count(), 1);
        assert!(matches!(
            Staging::new(&out),
            Err(ConvertError::OutputExists { .. })
        ));
        let empty = parent.path().join("empty");
        std::fs::create_dir(&empty).unwrap();
        let staging = Staging::new(&empty).unwrap();
        Output::new(staging.path(), None)
            .write_text(Path::new("scene_2.json"), "{}")
            .unwrap();
        staging.commit().unwrap();
        assert!(empty.join("scene_2.json").is_file());
    }
}
