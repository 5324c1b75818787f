//! The permissions of the files the tool writes: a new file gets the mode the umask gives (as
//! `touch` would make it), a rewritten file keeps its own. Each command runs under an explicit
//! umask (`sh -c 'umask M && exec sceneeval ...'`).

#![cfg(unix)]
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::os::unix::fs::PermissionsExt;
use std::path::Path;
use std::process::{Command, Output};

use common::fixtures;

/// `sceneeval ARGS...` under `umask MASK`.
fn under_umask(mask: &str, args: &[&std::ffi::OsStr]) -> Output {
    let output = Command::new("sh")
        .arg("-c")
        .arg(format!("umask {mask} && exec \"$0\" \"$@\""))
        .arg(assert_cmd::cargo::cargo_bin("sceneeval"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn mode(path: &Path) -> u32 {
    std::fs::metadata(path).unwrap().permissions().mode() & 0o7777
}

#[test]
fn results_and_reports_get_the_umask_s_mode() {
    let scenes = tempfile::tempdir().unwrap();
    for n in [0, 5] {
        let name = format!("scene_{n}.json");
        std::fs::copy(fixtures().join("scenes").join(&name), scenes.path().join(&name)).unwrap();
    }
    let assets = format!("fixture={}", fixtures().join("assets").display());
    for (mask, expected) in [("022", 0o644), ("002", 0o664), ("077", 0o600)] {
        let out = tempfile::tempdir().unwrap();
        let run = out.path().join("run");
        under_umask(
            mask,
            &[
                "evaluate".as_ref(),
                scenes.path().as_os_str(),
                "--assets".as_ref(),
                assets.as_ref(),
                "--no-progress".as_ref(),
                "--report".as_ref(),
                "--out".as_ref(),
                run.as_os_str(),
            ],
        );
        let written = sceneeval_test_support::files_below(&run);
        // eval.json and timing.json of two scenes, the summaries, the report's pages, the lock.
        assert!(written.len() >= 10, "{written:?}");
        for file in &written {
            assert_eq!(mode(file), expected, "umask {mask}: {}", file.display());
        }
        assert_eq!(
            mode(&run.join("report")) & 0o777,
            0o777 & !u32::from_str_radix(mask, 8).unwrap()
        );
    }
}

#[test]
fn a_scene_settled_in_place_keeps_its_mode() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene_6.json");
    std::fs::copy(fixtures().join("scenes/scene_6.json"), &scene).unwrap();
    std::fs::set_permissions(&scene, std::fs::Permissions::from_mode(0o664)).unwrap();
    let assets = format!("fixture={}", fixtures().join("assets").display());
    let settle = |out: &Path| {
        under_umask(
            "077",
            &[
                "settle".as_ref(),
                scene.as_os_str(),
                "--assets".as_ref(),
                assets.as_ref(),
                "--out".as_ref(),
                out.as_os_str(),
            ],
        )
    };
    let before = std::fs::read(&scene).unwrap();
    settle(&scene);
    assert_ne!(std::fs::read(&scene).unwrap(), before, "the chair fell");
    assert_eq!(mode(&scene), 0o664);
    // A new file under the same umask: private, as the umask says.
    let new = dir.path().join("settled.json");
    settle(&new);
    assert_eq!(mode(&new), 0o600);
    assert_eq!(
        sceneeval_test_support::file_names(dir.path()),
        ["scene_6.json", "settled.json"]
    );
}
