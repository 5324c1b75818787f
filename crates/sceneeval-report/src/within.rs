//! The folders the report reads from: a path written in a record or found in the run folder is
//! followed only when it stays inside the run folder (or a folder the caller gave), so a
//! tampered run folder cannot make the report read, copy or quote another file.

use std::path::{Component, Path, PathBuf};

/// Where a path leads, with symbolic links followed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Inside {
    /// Inside the folder: the path with every link resolved.
    Yes(PathBuf),
    /// Outside it (or through a link that leads out of it).
    No,
    /// Nothing there (or a link to nothing).
    Missing,
}

/// Where `path` leads relative to `root` (which must be canonical): inside it, outside it, or
/// nowhere. Relative paths are relative to the current folder.
pub(crate) fn inside(root: &Path, path: &Path) -> Inside {
    match path.canonicalize() {
        Ok(p) if p.starts_with(root) => Inside::Yes(p),
        Ok(_) => Inside::No,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Inside::Missing,
        // A folder on the way that cannot be entered: not followed.
        Err(_) => Inside::No,
    }
}

/// Whether `name` is one file name: not empty, not `.` or `..`, no separator, no NUL.
pub(crate) fn is_file_name(name: &str) -> bool {
    let mut parts = Path::new(name).components();
    matches!((parts.next(), parts.next()), (Some(Component::Normal(_)), None))
        && !name.contains(['/', '\\', '\0'])
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn names_that_would_leave_a_folder_are_not_file_names() {
        for ok in ["scene_0", "scene 0.json", "..scene", "a.b"] {
            assert!(is_file_name(ok), "{ok}");
        }
        for bad in ["", ".", "..", "../..", "a/b", "/etc", "a\\b", "a\0b", "./a"] {
            assert!(!is_file_name(bad), "{bad:?}");
        }
    }

    #[cfg(unix)]
    #[test]
    fn links_out_of_the_folder_are_outside() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("run");
        std::fs::create_dir(&root).unwrap();
        let root = root.canonicalize().unwrap();
        std::fs::write(root.join("a.json"), "{}").unwrap();
        std::fs::write(dir.path().join("secret.json"), "{}").unwrap();
        std::os::unix::fs::symlink(dir.path().join("secret.json"), root.join("link.json")).unwrap();
        std::os::unix::fs::symlink(root.join("a.json"), root.join("inner.json")).unwrap();
        assert_eq!(
            inside(&root, &root.join("a.json")),
            Inside::Yes(root.join("a.json"))
        );
        assert_eq!(
            inside(&root, &root.join("inner.json")),
            Inside::Yes(root.join("a.json"))
        );
        assert_eq!(inside(&root, &root.join("link.json")), Inside::No);
        assert_eq!(inside(&root, &root.join("../secret.json")), Inside::No);
        assert_eq!(inside(&root, &root.join("none.json")), Inside::Missing);
    }
}
