//! `sceneeval convert`: from each generator's fixture batch folder to a folder `sceneeval
//! evaluate` reads, with what was skipped printed; `inspect --json` shows the turned fronts;
//! bad input fails naming the file and leaves no output.

// Set-up helpers outside `#[test]` functions may stop the test on failure.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use assert_cmd::cargo::cargo_bin_cmd;
use predicates::prelude::*;
use serde_json::Value;

fn native(sub: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/native")
        .join(sub)
}

fn spec(prefix: &str, dir: &Path) -> String {
    format!("{prefix}={}", dir.display())
}

#[test]
fn help_exits_zero_and_names_the_formats() {
    cargo_bin_cmd!("sceneeval")
        .args(["convert", "--help"])
        .assert()
        .success()
        .stdout(predicate::str::contains("holodeck").and(predicate::str::contains("scene-agent")))
        .stdout(predicate::str::contains("--id-map"));
}

#[test]
fn holodeck_converts_prints_what_was_skipped_and_evaluates() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("holodeck");
    let objathor = spec("objaverse", &native("holodeck/objathor"));
    cargo_bin_cmd!("sceneeval")
        .args(["convert", "holodeck"])
        .arg(native("holodeck/scenes"))
        .arg("--out")
        .arg(&out)
        .args(["--assets", &objathor, "--id-map", r#"{"0": 106, "1": 56}"#])
        .assert()
        .success()
        .stdout(predicate::str::contains("converted 2 holodeck scenes"))
        .stdout(predicate::str::contains(
            "bedroom-2024-05-01 -> scene_106.json: 6 objects, 1 room",
        ))
        .stdout(predicate::str::contains("skipped object \"Chair (bedroom)\""))
        .stdout(predicate::str::contains("AI2-THOR"))
        .stdout(predicate::str::contains(format!(
            "evaluate with: sceneeval evaluate {} --assets {objathor}",
            out.display()
        )));
    assert!(out.join("scene_106.json").is_file() && out.join("scene_56.json").is_file());
    let results = tmp.path().join("results");
    cargo_bin_cmd!("sceneeval")
        .arg("evaluate")
        .arg(&out)
        .args(["--assets", &objathor, "--no-progress", "--out"])
        .arg(&results)
        .assert()
        .success();
    for scene in ["scene_106", "scene_56"] {
        let record: Value =
            serde_json::from_str(&std::fs::read_to_string(results.join(scene).join("eval.json")).unwrap())
                .unwrap();
        assert!(record.is_object(), "{record}");
    }
    assert!(results.join("summary.csv").is_file());
}

#[test]
fn scene_agent_converts_and_inspect_shows_the_fronts() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("sceneagent");
    cargo_bin_cmd!("sceneeval")
        .args(["convert", "scenesmith"])
        .arg(native("scene-agent/scenes"))
        .arg("--out")
        .arg(&out)
        .assert()
        .success()
        .stdout(predicate::str::contains("converted 1 scene-agent scene"))
        .stdout(predicate::str::contains(format!(
            "--assets scene-agent={}",
            out.display()
        )));
    let assets = spec("scene-agent", &out);
    let json = cargo_bin_cmd!("sceneeval")
        .arg("inspect")
        .arg(out.join("scene_0.json"))
        .args(["--assets", &assets, "--json"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let doc: Value = serde_json::from_slice(&json).unwrap();
    let objects = doc["objects"].as_array().unwrap();
    assert_eq!(objects.len(), 3);
    // The bed faces world -y once its declared front (+y) is turned; the desk faces -x.
    let close = |v: &Value, want: [f64; 3]| {
        v.as_array()
            .unwrap()
            .iter()
            .zip(want)
            .all(|(a, b)| (a.as_f64().unwrap() - b).abs() < 1e-9)
    };
    assert!(close(&objects[0]["front"], [0.0, -1.0, 0.0]), "{}", objects[0]);
    assert!(close(&objects[1]["front"], [-1.0, 0.0, 0.0]), "{}", objects[1]);
    assert!(
        close(&objects[0]["asset_front"], [0.0, 1.0, 0.0]),
        "{}",
        objects[0]
    );
    // The tables say it too.
    cargo_bin_cmd!("sceneeval")
        .arg("inspect")
        .arg(out.join("scene_0.json"))
        .args(["--assets", &assets])
        .assert()
        .success()
        .stdout(predicate::str::contains("asset front").and(predicate::str::contains("+y")));
    let results = tmp.path().join("results");
    cargo_bin_cmd!("sceneeval")
        .arg("evaluate")
        .arg(&out)
        .args(["--assets", &assets, "--no-progress", "--out"])
        .arg(&results)
        .assert()
        .success();
}

#[test]
fn bad_input_fails_naming_the_file_and_leaves_no_output() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("layoutvlm");
    std::fs::create_dir_all(input.join("scene_000")).unwrap();
    std::fs::write(input.join("scene_000/scene.json"), "{\"boundary\": ").unwrap();
    std::fs::write(input.join("scene_000/layout.json"), "{}").unwrap();
    let out = tmp.path().join("out");
    cargo_bin_cmd!("sceneeval")
        .args(["convert", "layoutvlm"])
        .arg(&input)
        .arg("--out")
        .arg(&out)
        .args([
            "--assets",
            &spec("layoutvlm-objaverse", &native("layoutvlm/assets")),
        ])
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("scene_000/scene.json:1:")
                .and(predicate::str::contains("malformed JSON")),
        );
    assert!(!out.exists());
    let left: Vec<_> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, vec![std::ffi::OsString::from("layoutvlm")]);
    // An unknown format is a usage error.
    cargo_bin_cmd!("sceneeval")
        .args(["convert", "sceneweaver"])
        .arg(&input)
        .args(["--out", "x"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("unknown format"));
}

/// A SceneAgent batch folder of `n` copies of the fixture scene: enough work to interrupt.
fn scene_agent_batch(root: &Path, n: usize) -> PathBuf {
    fn copy_tree(from: &Path, to: &Path) {
        std::fs::create_dir_all(to).unwrap();
        for entry in std::fs::read_dir(from).unwrap() {
            let path = entry.unwrap().path();
            let target = to.join(path.file_name().unwrap());
            if path.is_dir() {
                copy_tree(&path, &target);
            } else {
                std::fs::copy(&path, &target).unwrap();
            }
        }
    }
    let input = root.join(format!("batch_{n}"));
    for k in 0..n {
        copy_tree(
            &native("scene-agent/scenes/scene_000"),
            &input.join(format!("scene_{k:03}")),
        );
    }
    input
}

/// The temporary folders of conversions into `<parent>/out`.
fn temporary_folders(parent: &Path) -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(parent)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with(".out.convert-"))
        })
        .collect();
    found.sort();
    found
}

/// `sceneeval convert scene-agent INPUT --out <parent>/out`, running.
fn start_convert(input: &Path, parent: &Path) -> std::process::Child {
    std::process::Command::new(assert_cmd::cargo::cargo_bin("sceneeval"))
        .args(["convert", "scene-agent"])
        .arg(input)
        .arg("--out")
        .arg(parent.join("out"))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap()
}

/// The temporary folder of the running `child`, once it holds a converted scene (it is then
/// mid-way through the batch); not one of `old`.
fn working_folder(child: &mut std::process::Child, parent: &Path, old: &[PathBuf]) -> PathBuf {
    let start = std::time::Instant::now();
    loop {
        for dir in temporary_folders(parent) {
            if !old.contains(&dir) && dir.join("scene_1.json").is_file() {
                return dir;
            }
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the conversion ended before it could be interrupted: make the batch larger"
        );
        assert!(start.elapsed().as_secs() < 120, "no temporary folder appeared");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}

#[cfg(unix)]
fn kill(child: &std::process::Child, signal: &str) {
    assert!(
        std::process::Command::new("kill")
            .args([signal, &child.id().to_string()])
            .status()
            .unwrap()
            .success()
    );
}

#[cfg(unix)]
#[test]
fn an_interrupted_conversion_removes_its_temporary_folder() {
    let tmp = tempfile::tempdir().unwrap();
    let input = scene_agent_batch(tmp.path(), 200);
    let parent = tmp.path().join("results");
    std::fs::create_dir(&parent).unwrap();
    for (signal, code) in [("-INT", 130), ("-TERM", 143)] {
        let mut child = start_convert(&input, &parent);
        let working = working_folder(&mut child, &parent, &[]);
        kill(&child, signal);
        let status = child.wait().unwrap();
        assert_eq!(status.code(), Some(code), "{signal}");
        assert!(!working.exists(), "{signal}: {} is left", working.display());
        assert!(temporary_folders(&parent).is_empty());
        assert!(!parent.join("out").exists());
    }
}

#[cfg(unix)]
#[test]
fn a_killed_conversion_s_folder_is_removed_by_the_next_one_and_a_running_one_s_is_kept() {
    let tmp = tempfile::tempdir().unwrap();
    let big = scene_agent_batch(tmp.path(), 200);
    let small = scene_agent_batch(tmp.path(), 1);
    let parent = tmp.path().join("results");
    std::fs::create_dir(&parent).unwrap();
    // Killed: nothing could remove its folder.
    let mut killed = start_convert(&big, &parent);
    let abandoned = working_folder(&mut killed, &parent, &[]);
    kill(&killed, "-KILL");
    killed.wait().unwrap();
    assert!(abandoned.is_dir());
    // The next conversion into the same output removes it as it starts.
    let mut running = start_convert(&big, &parent);
    let live = working_folder(&mut running, &parent, std::slice::from_ref(&abandoned));
    assert!(!abandoned.exists(), "the abandoned folder is removed");
    // Another conversion meanwhile finishes, and leaves the running one's folder alone,
    // however old it is: its lock says it is in use.
    cargo_bin_cmd!("sceneeval")
        .args(["convert", "scene-agent"])
        .arg(&small)
        .arg("--out")
        .arg(parent.join("out"))
        .assert()
        .success();
    assert!(parent.join("out/scene_0.json").is_file());
    assert!(live.is_dir(), "a running conversion's folder was removed");
    kill(&running, "-INT");
    running.wait().unwrap();
    assert!(temporary_folders(&parent).is_empty());
}

#[cfg(unix)]
#[test]
fn converted_folders_get_the_mode_the_umask_gives() {
    use std::os::unix::fs::PermissionsExt;
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    let tmp = tempfile::tempdir().unwrap();
    for (umask, want) in [("022", 0o755), ("077", 0o700)] {
        let out = tmp.path().join(format!("out_{umask}"));
        let status = std::process::Command::new("sh")
            .arg("-c")
            .arg(format!("umask {umask} && exec \"$0\" \"$@\""))
            .arg(assert_cmd::cargo::cargo_bin("sceneeval"))
            .args(["convert", "scene-agent"])
            .arg(native("scene-agent/scenes"))
            .arg("--out")
            .arg(&out)
            .stdout(std::process::Stdio::null())
            .status()
            .unwrap();
        assert!(status.success());
        // The output folder was the temporary folder (tempfile makes those 0700).
        for dir in [
            out.clone(),
            out.join("scene_0"),
            out.join("scene_0/assets"),
            out.join("scene_0/assets/furniture/sdf/bed_1717171717"),
        ] {
            assert_eq!(mode(&dir), want, "umask {umask}: {}", dir.display());
        }
    }
}
