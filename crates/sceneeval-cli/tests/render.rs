//! `sceneeval render` on a fixture scene: file names, sizes, options and errors. Needs a
//! Vulkan driver (Mesa's lavapipe on CI); without one the tests that render are skipped,
//! saying so once, unless `SCENEEVAL_REQUIRE_GPU=1` (CI) makes that a failure.

#![allow(clippy::unwrap_used)]

mod common;

use std::path::PathBuf;

use assert_cmd::Command;
use predicates::prelude::*;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

fn render() -> Command {
    let mut cmd = Command::cargo_bin("sceneeval").unwrap();
    cmd.arg("render")
        .arg(fixtures().join("scenes/scene_0.json"))
        .arg("--assets")
        .arg(format!("fixture={}", fixtures().join("assets").display()));
    cmd
}

#[test]
fn writes_the_requested_views_with_inspect_ids_as_file_names() {
    if common::renderer().is_none() {
        return;
    }
    let out = tempfile::tempdir().unwrap();
    let assert = render()
        .args(["--out"])
        .arg(out.path())
        .args([
            "--views",
            "front,size,top",
            "--objects",
            "idx0_fixture.bed,idx3_fixture.table_lamp",
        ])
        .args(["--render-size", "65"])
        .assert()
        .success();
    let stdout = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
    let names = sceneeval_test_support::file_names(out.path());
    assert_eq!(
        names,
        [
            "front_idx0_fixture.bed.png",
            "front_idx3_fixture.table_lamp.png",
            "size_idx0_fixture.bed.png",
            "size_idx3_fixture.table_lamp.png",
            "top.png",
        ]
    );
    for name in &names {
        let path = out.path().join(name);
        assert!(stdout.contains(&path.display().to_string()), "{name} not printed");
        let img = image::open(&path).unwrap();
        assert_eq!((img.width(), img.height()), (65, 65), "{name}");
        assert_eq!(img.color(), image::ColorType::Rgba8, "{name}");
    }
    let one = tempfile::tempdir().unwrap();
    render()
        .args(["--out"])
        .arg(one.path())
        .args(["--views", "top", "--size", "8"])
        .assert()
        .success()
        .stderr(predicate::str::contains("1 image written to"))
        // The option's old name works and says so.
        .stderr(predicate::str::contains(
            "warning: --size is the old name of --render-size",
        ));
}

#[test]
fn every_object_by_default() {
    if common::renderer().is_none() {
        return;
    }
    let out = tempfile::tempdir().unwrap();
    render()
        .arg("--out")
        .arg(out.path())
        .args(["--views", "surroundings", "--render-size", "16"])
        .assert()
        .success()
        .stderr(predicate::str::contains("9 images written"));
    assert!(
        out.path()
            .join("surroundings_idx8_fixture.ceiling_lamp.png")
            .is_file()
    );
}

#[test]
fn bad_arguments_are_clear_errors() {
    let out = tempfile::tempdir().unwrap();
    render()
        .arg("--out")
        .arg(out.path())
        .args(["--objects", "idx0_fixture.bed,idx99_nothing"])
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("no object idx99_nothing")
                .and(predicate::str::contains("idx0_fixture.bed")),
        );
    render()
        .arg("--out")
        .arg(out.path())
        .args(["--views", "front,side"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("unknown view \"side\""));
    render()
        .arg("--out")
        .arg(out.path())
        .args(["--render-size", "0"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("--render-size"));
}

#[test]
fn a_missing_driver_names_the_packages_to_install() {
    // DirectX 12 does not exist here: no adapter, as on a machine without a Vulkan driver.
    let out = tempfile::tempdir().unwrap();
    render()
        .env("WGPU_BACKEND", "dx12")
        .arg("--out")
        .arg(out.path())
        .args(["--views", "top", "--render-size", "8"])
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("mesa-vulkan-drivers libvulkan1")
                .and(predicate::str::contains("WGPU_BACKEND"))
                .and(predicate::str::contains("panicked").not()),
        );
}

/// Mesa's device-select layer made every successful render print `error: XDG_RUNTIME_DIR is
/// invalid or not set in the environment.` where that variable is unset (containers, CI): the
/// binary keeps the driver's noise out of its output.
#[test]
fn a_successful_render_prints_no_driver_noise() {
    if common::renderer().is_none() {
        return;
    }
    let out = tempfile::tempdir().unwrap();
    let assert = render()
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("NODEVICE_SELECT")
        .args(["--views", "top", "--render-size", "32", "--out"])
        .arg(out.path())
        .assert()
        .success();
    let stderr = String::from_utf8_lossy(&assert.get_output().stderr).into_owned();
    assert!(!stderr.contains("error"), "{stderr}");
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{stderr}");
}
