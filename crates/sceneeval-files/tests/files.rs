//! Regular files only on input (a named pipe is refused without being opened), atomic writes
//! on output (concurrent writers never fail and never mix, a failed write leaves the old file).

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::io::{ErrorKind, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use sceneeval_files::{NotRegularFile, check_regular, open_regular, write_atomic, write_atomic_with};

/// Runs `f` on another thread and fails the test if it does not return within 20 s (a FIFO
/// opened for reading would block forever).
fn within_20s<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(Duration::from_secs(20))
        .expect("the call blocked (a named pipe was opened)")
}

#[cfg(unix)]
fn mkfifo(path: &Path) {
    let status = std::process::Command::new("mkfifo").arg(path).status().unwrap();
    assert!(status.success(), "mkfifo {}", path.display());
}

#[cfg(unix)]
#[test]
fn a_named_pipe_is_refused_without_being_opened() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.json");
    mkfifo(&fifo);
    let link = dir.path().join("link.json");
    std::os::unix::fs::symlink(&fifo, &link).unwrap();
    for path in [fifo, link] {
        let p = path.clone();
        let err = within_20s(move || open_regular(&p).unwrap_err());
        assert_eq!(err.kind(), ErrorKind::InvalidInput, "{err}");
        assert_eq!(err.to_string(), "is a named pipe (FIFO), not a regular file");
        let inner = err.get_ref().unwrap().downcast_ref::<NotRegularFile>().unwrap();
        assert_eq!(inner.kind, "a named pipe (FIFO)");
        let p = path.clone();
        assert!(within_20s(move || check_regular(&p).is_err()));
    }
}

#[test]
fn regular_files_and_links_to_them_open_and_missing_files_say_so() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a.txt");
    std::fs::write(&file, "text").unwrap();
    let mut s = String::new();
    open_regular(&file).unwrap().read_to_string(&mut s).unwrap();
    assert_eq!(s, "text");
    #[cfg(unix)]
    {
        let link = dir.path().join("b.txt");
        std::os::unix::fs::symlink(&file, &link).unwrap();
        assert_eq!(check_regular(&link).unwrap().len(), 4);
    }
    let missing = open_regular(&dir.path().join("missing.txt")).unwrap_err();
    assert_eq!(missing.kind(), ErrorKind::NotFound);
    let folder = open_regular(dir.path()).unwrap_err();
    assert_eq!(folder.to_string(), "is a directory, not a regular file");
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn concurrent_writers_of_one_file_never_fail_and_never_mix() {
    // Two writers replace the same file 200 times each with 256 KiB of one byte ('a' or 'b')
    // while a reader checks that every read is one writer's whole content.
    const LEN: usize = 256 * 1024;
    let dir = tempfile::tempdir().unwrap();
    let path: PathBuf = dir.path().join("matching.json");
    write_atomic(&path, &vec![b'a'; LEN]).unwrap();
    let writers: Vec<_> = [b'a', b'b']
        .into_iter()
        .map(|byte| {
            let path = path.clone();
            std::thread::spawn(move || {
                let content = vec![byte; LEN];
                for _ in 0..200 {
                    write_atomic(&path, &content).unwrap();
                }
            })
        })
        .collect();
    let reader = {
        let path = path.clone();
        std::thread::spawn(move || {
            for _ in 0..400 {
                let bytes = std::fs::read(&path).unwrap();
                assert_eq!(bytes.len(), LEN);
                assert!(bytes.iter().all(|&b| b == bytes[0]), "mixed content");
            }
        })
    };
    for w in writers {
        w.join().unwrap();
    }
    reader.join().unwrap();
    let last = std::fs::read(&path).unwrap();
    assert!(last == vec![b'a'; LEN] || last == vec![b'b'; LEN]);
    assert_eq!(names(dir.path()), ["matching.json"], "no temporary file left");
}

#[test]
fn a_failed_write_leaves_the_old_file_and_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sub").join("view.png");
    write_atomic(&path, b"old").unwrap();
    let err = write_atomic_with(&path, |f| {
        f.write_all(b"half of the new")?;
        Err(std::io::Error::new(
            ErrorKind::StorageFull,
            "no space left on device",
        ))
    })
    .unwrap_err();
    assert_eq!(err.kind(), ErrorKind::StorageFull);
    assert_eq!(std::fs::read(&path).unwrap(), b"old");
    assert_eq!(names(path.parent().unwrap()), ["view.png"]);
}

/// The mode bits of `path` (permissions only).
#[cfg(unix)]
fn mode(path: &Path) -> u32 {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(path).unwrap().permissions().mode() & 0o7777
}

/// New files get the mode the umask gives, as `touch` would create them; a replaced file keeps
/// its own mode, whatever the umask. One test: the umask belongs to the whole process, and the
/// other tests of this binary do not depend on it (each umask here leaves the owner read and
/// write).
#[cfg(unix)]
#[test]
fn new_files_get_the_umask_s_mode_and_replaced_files_keep_theirs() {
    use std::os::unix::fs::PermissionsExt;

    use rustix::fs::Mode;
    use rustix::process::umask;

    let dir = tempfile::tempdir().unwrap();
    let before = umask(Mode::from_raw_mode(0o022));
    for (mask, expected) in [(0o022, 0o644), (0o002, 0o664), (0o077, 0o600), (0o027, 0o640)] {
        umask(Mode::from_raw_mode(mask));
        let path = dir.path().join(format!("new-{mask:o}.json"));
        write_atomic(&path, b"{}").unwrap();
        assert_eq!(mode(&path), expected, "umask {mask:o}");
        // What `std::fs::write` (open with 0666) gives under the same umask.
        let plain = dir.path().join(format!("plain-{mask:o}"));
        std::fs::write(&plain, b"").unwrap();
        assert_eq!(mode(&plain), expected);
    }
    // Rewritten under a strict umask: each keeps its mode (a user's 0644 file, a shared 0664
    // one, a read-only 0444 one, a private 0600 one).
    umask(Mode::from_raw_mode(0o077));
    for old in [0o644, 0o664, 0o444, 0o600, 0o755] {
        let path = dir.path().join(format!("old-{old:o}.csv"));
        std::fs::write(&path, b"old").unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(old)).unwrap();
        write_atomic_with(&path, |f| f.write_all(b"new")).unwrap();
        assert_eq!(mode(&path), old, "{old:o}");
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
    }
    // Through a symbolic link: the mode of the file it points to.
    let target = dir.path().join("target.md");
    std::fs::write(&target, b"").unwrap();
    std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o664)).unwrap();
    let link = dir.path().join("link.md");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    write_atomic(&link, b"via the link").unwrap();
    assert_eq!(mode(&link), 0o664);
    umask(before);
}
