//! Helpers shared by the command-line tests: the fixture folder, running `sceneeval evaluate`
//! and reading a scene's record.

#![allow(dead_code, clippy::unwrap_used, clippy::panic)]

pub mod browser;
pub mod page;

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use serde_json::Value;

/// The renderer, or `None` on a machine without a Vulkan driver: a test that renders (through
/// the library or the `sceneeval` binary) is then skipped, saying so once, unless
/// `SCENEEVAL_REQUIRE_GPU=1` (CI) makes that a failure ([`sceneeval_test_support::system`]).
pub fn renderer() -> Option<sceneeval::render::Renderer> {
    use sceneeval_test_support::system::{GPU, available};
    available(
        &GPU,
        sceneeval::render::Renderer::new(),
        sceneeval::render::RenderError::is_missing_driver,
    )
}

/// The bundled `fixtures/` folder.
pub fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// `sceneeval evaluate SCENES --assets fixture=ASSETS --no-progress --out OUT EXTRA...`.
pub fn evaluate(scenes: &Path, assets: &Path, out: &Path, extra: &[&str]) -> assert_cmd::assert::Assert {
    evaluate_command(scenes, assets, out, extra).assert()
}

/// The command [`evaluate`] runs, to add environment variables before running it.
pub fn evaluate_command(scenes: &Path, assets: &Path, out: &Path, extra: &[&str]) -> Command {
    let spec = format!("fixture={}", assets.display());
    let mut cmd = Command::cargo_bin("sceneeval").unwrap();
    cmd.arg("evaluate")
        .arg(scenes)
        .args(["--assets", &spec, "--no-progress", "--out"])
        .arg(out)
        .args(extra);
    cmd
}

/// Fixture scenes 2 and 8 copied into `<tmp>/scenes`, and the annotation rows `csv` written to
/// `<tmp>/annotations.csv`: the folder (kept while it lives), the scene folder and the rows.
pub fn scenes_2_and_8(csv: &str) -> (tempfile::TempDir, PathBuf, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    for n in [2, 8] {
        let name = format!("scene_{n}.json");
        std::fs::copy(fixtures().join("scenes").join(&name), scenes.join(&name)).unwrap();
    }
    let rows = dir.path().join("annotations.csv");
    std::fs::write(&rows, csv).unwrap();
    (dir, scenes, rows)
}

/// The options of the full plan with the rows `csv` and the VLM `test-model` at `url` (views of
/// 64 px, relations by the lexicon, one thread), then `extra`.
pub fn full_plan_args(csv: &Path, url: &str, extra: &[&str]) -> Vec<String> {
    full_plan_args_of_model(csv, url, "test-model", extra)
}

/// As [`full_plan_args`], with the VLM model `model`.
pub fn full_plan_args_of_model(csv: &Path, url: &str, model: &str, extra: &[&str]) -> Vec<String> {
    let args = [
        "--annotations",
        csv.to_str().unwrap(),
        "--plan",
        "full",
        "--vlm-base-url",
        url,
        "--vlm-model",
        model,
        "--relation-mapping",
        "lexicon",
        "--render-size",
        "64",
        "--threads",
        "1",
    ];
    args.iter().chain(extra).map(|a| (*a).to_owned()).collect()
}

/// `sceneeval evaluate SCENES` of the fixture assets into `out` with [`full_plan_args`].
pub fn full_plan_command(scenes: &Path, csv: &Path, out: &Path, url: &str, extra: &[&str]) -> Command {
    let args = full_plan_args(csv, url, extra);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    evaluate_command(scenes, &fixtures().join("assets"), out, &args)
}

/// The `eval.json` of `scene` under `out`.
pub fn record(out: &Path, scene: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(out.join(scene).join("eval.json")).unwrap()).unwrap()
}
