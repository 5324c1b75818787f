//! The output folder: built whole in a temporary folder next to it and renamed into place,
//! so that a conversion that fails (or is killed) never leaves a half-written folder.

use std::path::{Path, PathBuf};

use sceneeval_scene::{Room, Scene, SceneObject};

use crate::ConvertError;

/// A temporary folder beside the output folder, removed on drop unless committed.
#[derive(Debug)]
pub(crate) struct Staging {
    dir: tempfile::TempDir,
    out: PathBuf,
}

impl Staging {
    /// A temporary folder `.<name>.convert-XXXXXX` in `out`'s parent (created if needed).
    /// `out` must not exist, or be an empty folder.
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
        let dir = tempfile::Builder::new()
            .prefix(&format!(".{name}.convert-"))
            .tempdir_in(&parent)
            .map_err(|e| ConvertError::output(&parent, e))?;
        Ok(Staging {
            dir,
            out: out.to_owned(),
        })
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

/// Writes a converted scene as the sceneState file `path`; `file` is the generator's file it
/// came from, named when the objects and rooms do not make a valid scene.
pub(crate) fn write_scene(
    objects: Vec<SceneObject>,
    rooms: Vec<Room>,
    file: &Path,
    path: &Path,
) -> Result<(), ConvertError> {
    let scene = Scene::new(None, objects, rooms).map_err(|e| ConvertError::scene(file, "", e))?;
    sceneeval_io::write_scene_state(&scene, path).map_err(|e| ConvertError::Verify {
        path: path.to_owned(),
        source: Box::new(e),
    })
}

/// Creates `dir` and its parents.
pub(crate) fn create_dir(dir: &Path) -> Result<(), ConvertError> {
    std::fs::create_dir_all(dir).map_err(|e| ConvertError::output(dir, e))
}

/// Writes `text` to `path`, creating its folder.
pub(crate) fn write_text(path: &Path, text: &str) -> Result<(), ConvertError> {
    if let Some(parent) = path.parent() {
        create_dir(parent)?;
    }
    std::fs::write(path, text).map_err(|e| ConvertError::output(path, e))
}

/// Copies the regular file `from` to `to`, creating `to`'s folder.
pub(crate) fn copy_file(from: &Path, to: &Path) -> Result<(), ConvertError> {
    let meta = std::fs::symlink_metadata(from).map_err(|e| ConvertError::output(from, e))?;
    if !meta.is_file() {
        return Err(ConvertError::output(
            from,
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a regular file"),
        ));
    }
    if let Some(parent) = to.parent() {
        create_dir(parent)?;
    }
    std::fs::copy(from, to).map_err(|e| ConvertError::output(from, e))?;
    Ok(())
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
        write_text(&staging.path().join("scene_1.json"), "{}").unwrap();
        drop(staging);
        assert_eq!(std::fs::read_dir(parent.path()).unwrap().count(), 0);
        assert!(!out.exists());
    }

    #[test]
    fn commit_renames_into_a_new_or_empty_folder_only() {
        let parent = tempfile::tempdir().unwrap();
        let out = parent.path().join("a/b/converted");
        let staging = Staging::new(&out).unwrap();
        write_text(&staging.path().join("x/scene_1.json"), "{}").unwrap();
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
        write_text(&staging.path().join("scene_2.json"), "{}").unwrap();
        staging.commit().unwrap();
        assert!(empty.join("scene_2.json").is_file());
    }
}
