//! Golden outputs: the fixture scenes through the command line (the geometry plan, the
//! reference preset, a metric list with stability and text fidelity without a VLM, the full
//! plan against a mock VLM on 127.0.0.1, `summarize`, `compare` in every format, `report`,
//! `settle`, `inspect --format json`), every text file written and every standard output
//! compared byte for byte with the files under `tests/golden/`, which the code wrote before.
//!
//! Timings (`timing.json`), images, caches and standard error are not compared; the
//! temporary folder the commands run in and the mock server's address are replaced by
//! `$TMP` and `$VLM` before comparing. A change that alters an output on purpose regenerates
//! the files:
//!
//! ```text
//! SCENEEVAL_BLESS=1 cargo test -p sceneeval-cli --test golden
//! ```
//!
//! and its commit shows the difference. Blessing needs the renderer (the full plan's object
//! views): without a Vulkan driver the full-plan case is skipped when checking, and blessing
//! refuses to run.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

use sceneeval_test_support::fidelity_model::{self, answer, pictured_category};
use sceneeval_test_support::mock_endpoint::{MockEndpoint, completion, task_of, user_text};
use serde_json::{Value, json};

/// The folder of the expected files.
fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// Whether this run rewrites the expected files.
fn blessing() -> bool {
    std::env::var("SCENEEVAL_BLESS").is_ok_and(|v| !v.is_empty() && v != "0")
}

/// The commands' working folder and what they printed.
struct Work {
    dir: tempfile::TempDir,
    /// Text to replace by a placeholder in every output, longest first.
    volatile: Vec<(String, &'static str)>,
    /// Standard output of each command, and the command lines with their exit status.
    printed: BTreeMap<String, String>,
    commands: String,
}

impl Work {
    /// A folder holding `scenes/` (fixture scenes 0 to 11), `scenes28/` (scenes 2 and 8),
    /// `assets/` (the fixture assets), `annotations.csv` (one row per fixture scene) and
    /// `annotations28.csv` (the full plan's rows of scenes 2 and 8).
    fn new() -> Self {
        let dir = tempfile::tempdir().unwrap();
        let fixtures = common::fixtures();
        // Every fixture scene but the 108-object benchmark office (scene 12), whose results
        // alone would outweigh the others'.
        copy_dir(&fixtures.join("scenes"), &dir.path().join("scenes"));
        std::fs::remove_file(dir.path().join("scenes/scene_12.json")).unwrap();
        copy_dir(&fixtures.join("assets"), &dir.path().join("assets"));
        std::fs::copy(
            fixtures.join("annotations/fixture_scenes.csv"),
            dir.path().join("annotations.csv"),
        )
        .unwrap();
        std::fs::create_dir(dir.path().join("scenes28")).unwrap();
        fidelity_model::copy_scenes(&dir.path().join("scenes28"));
        std::fs::write(dir.path().join("annotations28.csv"), fidelity_model::CSV).unwrap();
        let mut volatile = Vec::new();
        for path in [dir.path().to_path_buf(), dir.path().canonicalize().unwrap()] {
            volatile.push((path.display().to_string(), "$TMP"));
        }
        Work {
            dir,
            volatile,
            printed: BTreeMap::new(),
            commands: String::new(),
        }
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }

    /// Runs `sceneeval ARGS` in the folder, keeping its standard output as `stdout/<name>`
    /// and its exit status in `commands.txt`.
    fn run(&mut self, name: &str, args: &[&str]) {
        let output = assert_cmd::Command::cargo_bin("sceneeval")
            .unwrap()
            .current_dir(self.path())
            .env_remove("RUST_LOG")
            .env_remove("OPENAI_API_KEY")
            .args(args)
            .output()
            .unwrap();
        let code = output.status.code().unwrap_or(-1);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            code == 0 || code == 1,
            "sceneeval {args:?} ended with {code}: {stderr}"
        );
        self.commands
            .push_str(&format!("{name}: sceneeval {} -> exit {code}\n", args.join(" ")));
        let stdout = String::from_utf8(output.stdout).unwrap();
        self.printed.insert(format!("stdout/{name}.txt"), stdout);
    }

    /// Every compared file: the text files the commands wrote (see [`compared`]) and what they
    /// printed, placeholders in place of the volatile text.
    fn outputs(&self) -> BTreeMap<String, String> {
        let mut files = BTreeMap::new();
        collect(self.path(), self.path(), &mut files);
        files.extend(self.printed.clone());
        files.insert("commands.txt".to_owned(), self.commands.clone());
        let mut volatile = self.volatile.clone();
        volatile.sort_by_key(|(text, _)| std::cmp::Reverse(text.len()));
        files
            .into_iter()
            .map(|(name, text)| {
                let text = volatile
                    .iter()
                    .fold(text, |t, (from, to)| t.replace(from.as_str(), to));
                (name, text)
            })
            .collect()
    }
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
    }
}

/// Whether a file the commands wrote is compared: text results, not the inputs copied in,
/// timings, images, caches or lock files.
fn compared(relative: &str) -> bool {
    let inputs = [
        "scenes/",
        "scenes28/",
        "assets/",
        "annotations.csv",
        "annotations28.csv",
    ];
    let skipped_dirs = ["/vlm-cache/", "/physics-cache/", "/views/", "/diagnostics/"];
    !inputs.iter().any(|p| relative.starts_with(p))
        && !skipped_dirs.iter().any(|d| format!("/{relative}").contains(d))
        && !relative.ends_with("timing.json")
        && !relative.ends_with(".png")
        && !relative.ends_with(".lock")
}

fn collect(root: &Path, dir: &Path, files: &mut BTreeMap<String, String>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let relative = path
            .strip_prefix(root)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        if path.is_dir() {
            collect(root, &path, files);
        } else if compared(&relative) {
            let bytes = std::fs::read(&path).unwrap();
            let text = String::from_utf8(bytes).unwrap_or_else(|_| panic!("{relative} is not text"));
            files.insert(relative, text);
        }
    }
}

/// The expected files, by path relative to [`golden_dir`].
fn expected() -> BTreeMap<String, String> {
    let mut files = BTreeMap::new();
    if golden_dir().is_dir() {
        collect(&golden_dir(), &golden_dir(), &mut files);
    }
    files
}

/// A mock OpenAI-compatible endpoint answering as [`answer`] (the endpoint check a run sends
/// first with the colour it asks for); `out` is the run's folder, where a matching request's
/// object is recognised by its front view.
fn vlm(out: PathBuf) -> MockEndpoint {
    MockEndpoint::start(Duration::ZERO, move |_, body: &Value| {
        let task = task_of(body).to_owned();
        if task == "endpoint_check" {
            return completion(&json!({"colour": "red", "reason": "a red square"}));
        }
        let pictured = body["messages"][1]["content"][1]["image_url"]["url"]
            .as_str()
            .and_then(|url| url.split_once("base64,"))
            .and_then(|(_, data)| {
                use base64::Engine;
                base64::engine::general_purpose::STANDARD.decode(data).ok()
            })
            .and_then(|png| pictured_category(&out, &png));
        completion(&answer(&task, user_text(body), pictured.as_deref()))
    })
}

const ASSETS: &str = "fixture=assets";

/// The commands whose outputs are compared; `full` adds the full plan against the mock VLM
/// (it renders the object views the model is shown).
fn run_all(work: &mut Work, full: bool) {
    let common = [
        "--assets",
        ASSETS,
        "--annotations",
        "annotations.csv",
        "--no-progress",
        "--threads",
        "1",
    ];
    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut args = vec!["evaluate", "scenes"];
        args.extend(common);
        args.extend(extra);
        args
    };
    work.run("evaluate-geometry", &with(&["--out", "runs/geometry"]));
    work.run(
        "evaluate-reference",
        &with(&[
            "--preset",
            "reference",
            "--shard",
            "1/2",
            "--out",
            "runs/reference",
        ]),
    );
    work.run(
        "evaluate-list",
        &with(&[
            "--plan",
            "collision,support,out_of_bounds,stability,cnt,oor,oar",
            "--shard",
            "1/3",
            "--out",
            "runs/list",
        ]),
    );
    if full {
        let server = vlm(work.path().join("runs/full"));
        let url = server.url();
        work.volatile.push((url.clone(), "$VLM"));
        work.run(
            "evaluate-full",
            &[
                "evaluate",
                "scenes28",
                "--assets",
                ASSETS,
                "--annotations",
                "annotations28.csv",
                "--plan",
                "full",
                "--vlm-base-url",
                &url,
                "--vlm-model",
                "test-model",
                "--relation-mapping",
                "lexicon",
                "--render-size",
                "64",
                "--threads",
                "1",
                "--no-progress",
                "--out",
                "runs/full",
            ],
        );
        work.run(
            "report-full",
            &[
                "report",
                "runs/full",
                "--scenes",
                "scenes28",
                "--assets",
                ASSETS,
                "--annotations",
                "annotations28.csv",
                "--out",
                "reports/full",
            ],
        );
    }
    work.run(
        "summarize",
        &[
            "summarize",
            "runs/geometry",
            "--annotations",
            "annotations.csv",
            "--out",
            "summaries/geometry",
        ],
    );
    let runs = ["runs/geometry", "runs/reference"];
    work.run("compare-md", &["compare", runs[0], runs[1], "--ci", "0.95"]);
    work.run(
        "compare-md-by-difficulty",
        &[
            "compare",
            runs[0],
            runs[1],
            "--by",
            "difficulty",
            "--names",
            "geometry,reference",
        ],
    );
    work.run("compare-csv", &["compare", runs[0], runs[1], "--format", "csv"]);
    work.run(
        "compare-latex",
        &["compare", runs[0], runs[1], "--format", "latex"],
    );
    work.run(
        "compare-html",
        &[
            "compare",
            runs[0],
            runs[1],
            "--format",
            "html",
            "--paired",
            "--out",
            "compare/compare.html",
        ],
    );
    reports_and_scene_tools(work);
}

/// The reports of two runs (given the annotations the runs used), `settle` and `inspect`.
fn reports_and_scene_tools(work: &mut Work) {
    for (name, run) in [("geometry", "runs/geometry"), ("list", "runs/list")] {
        let out = format!("reports/{name}");
        work.run(
            &format!("report-{name}"),
            &[
                "report",
                run,
                "--scenes",
                "scenes",
                "--assets",
                ASSETS,
                "--annotations",
                "annotations.csv",
                "--out",
                &out,
            ],
        );
    }
    work.run(
        "settle",
        &[
            "settle",
            "scenes/scene_3.json",
            "--assets",
            ASSETS,
            "--out",
            "settled/scene_3.json",
        ],
    );
    work.run(
        "inspect",
        &["inspect", "scenes/scene_4.json", "--assets", ASSETS, "--json"],
    );
}

#[test]
fn the_fixture_outputs_are_the_golden_files() {
    let full = common::renderer().is_some();
    let bless = blessing();
    assert!(
        full || !bless,
        "blessing needs the renderer for the full plan's object views"
    );
    let mut work = Work::new();
    run_all(&mut work, full);
    let outputs = work.outputs();
    if bless {
        let dir = golden_dir();
        if dir.exists() {
            std::fs::remove_dir_all(&dir).unwrap();
        }
        for (name, text) in &outputs {
            let path = dir.join(name);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(&path, text).unwrap();
        }
        eprintln!("blessed {} files into {}", outputs.len(), dir.display());
        return;
    }
    let mut expected = expected();
    if !full {
        // Without a renderer the full plan did not run: its files are not expected.
        let full_only = |name: &str| {
            name.starts_with("runs/full/") || name.starts_with("reports/full/") || name.contains("-full.txt")
        };
        expected.retain(|name, _| !full_only(name));
        let commands = expected.get_mut("commands.txt").unwrap();
        *commands = commands
            .lines()
            .filter(|l| !l.contains("-full:"))
            .map(|l| format!("{l}\n"))
            .collect();
    }
    assert!(
        !expected.is_empty(),
        "no golden files in {}: bless them (see the module docs)",
        golden_dir().display()
    );
    let mut problems = Vec::new();
    for (name, want) in &expected {
        match outputs.get(name) {
            None => problems.push(format!("{name}: not written")),
            Some(got) if got != want => {
                problems.push(format!("{name}: differs\n{}", first_difference(want, got)))
            }
            Some(_) => {}
        }
    }
    for name in outputs.keys().filter(|n| !expected.contains_key(*n)) {
        problems.push(format!("{name}: written, not expected"));
    }
    assert!(
        problems.is_empty(),
        "{} of {} golden files differ (SCENEEVAL_BLESS=1 regenerates them when the change is meant):\n{}",
        problems.len(),
        expected.len(),
        problems.join("\n")
    );
}

/// The first differing line of two texts, with its neighbours.
fn first_difference(want: &str, got: &str) -> String {
    let (w, g): (Vec<&str>, Vec<&str>) = (want.lines().collect(), got.lines().collect());
    let at = w
        .iter()
        .zip(&g)
        .position(|(a, b)| a != b)
        .unwrap_or(w.len().min(g.len()));
    let around = |lines: &[&str]| {
        lines[at.saturating_sub(2)..(at + 3).min(lines.len())]
            .iter()
            .map(|l| format!("    {}", l.chars().take(200).collect::<String>()))
            .collect::<Vec<_>>()
            .join("\n")
    };
    format!(
        "  at line {}; expected:\n{}\n  got:\n{}",
        at + 1,
        around(&w),
        around(&g)
    )
}
