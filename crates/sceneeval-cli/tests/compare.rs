//! `sceneeval compare`, `sceneeval report` and `sceneeval evaluate --report` on runs of the
//! fixture scenes (the tables' arithmetic is tested in `sceneeval-report`).

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::path::Path;

use assert_cmd::Command;
use common::{evaluate, fixtures};
use predicates::prelude::*;

/// Copies fixture scenes `numbers` into a new folder.
fn scenes(numbers: &[u32]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for n in numbers {
        let name = format!("scene_{n}.json");
        std::fs::copy(fixtures().join("scenes").join(&name), dir.path().join(&name)).unwrap();
    }
    dir
}

fn sceneeval() -> Command {
    Command::cargo_bin("sceneeval").unwrap()
}

#[test]
fn help_documents_every_option() {
    for (command, options) in [
        (
            "compare",
            &["--names", "--format", "--by", "--out", "--annotations", "--ci"][..],
        ),
        (
            "report",
            &["--out", "--assets", "--scenes", "--annotations", "--name"][..],
        ),
        ("evaluate", &["--report"][..]),
    ] {
        let out = sceneeval().args([command, "--help"]).assert().success();
        let text = String::from_utf8(out.get_output().stdout.clone()).unwrap();
        for option in options {
            assert!(text.contains(option), "{command} --help lacks {option}:\n{text}");
        }
    }
}

#[test]
fn evaluate_report_then_compare_two_runs() {
    let root = tempfile::tempdir().unwrap();
    let (a, b) = (root.path().join("a"), root.path().join("b"));
    let assets = fixtures().join("assets");
    // Run a: scenes 5 (a collision) and 10, with its report. Run b: scene 10 alone.
    evaluate(scenes(&[5, 10]).path(), &assets, &a, &["--report"])
        .success()
        .stderr(predicate::str::contains("report: ").and(predicate::str::contains("(2 scene pages)")));
    let index = std::fs::read_to_string(a.join("report/index.html")).unwrap();
    assert!(
        index.contains("<a href=\"scenes/scene_5.html\">scene_5</a>"),
        "{index}"
    );
    assert!(a.join("report/scenes/scene_10.html").is_file());
    // `evaluate --report` gives the report its scene folder: the top view is drawn.
    let s5 = std::fs::read_to_string(a.join("report/scenes/scene_5.html")).unwrap();
    assert!(s5.contains("id=\"topview\""), "{s5}");
    evaluate(scenes(&[10]).path(), &assets, &b, &[]).success();

    // The report of run b elsewhere, named, without its scene folder: the scene file the record
    // names is outside the run folder, so it is not read, and the command says what to pass.
    let out = root.path().join("b-report");
    sceneeval()
        .arg("report")
        .arg(&b)
        .arg("--out")
        .arg(&out)
        .args(["--name", "method <b>"])
        .assert()
        .success()
        .stderr(
            predicate::str::contains(
                "warning: no top view of scene_10: the scene file the record names lies outside the run folder",
            )
            .and(predicate::str::contains("hint: give the folder of scene files sceneeval evaluate read (--scenes DIR)")),
        );
    let index = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(index.contains("SceneEval report: method &lt;b&gt;"));

    // Markdown on standard output: scene 5 is only in a, so the table covers scene 10, and says so.
    sceneeval()
        .arg("compare")
        .args([&a, &b])
        .args(["--names", "A,B"])
        .assert()
        .success()
        .stdout(
            predicate::str::starts_with("### all (1 scene)\n")
                .and(predicate::str::contains("| A | **"))
                .and(predicate::str::contains("left out: scene\\_5 (not in B)")),
        );
    // CSV into a file: the notes go to standard error.
    let csv = root.path().join("t.csv");
    sceneeval()
        .arg("compare")
        .args([&a, &b])
        .arg("--format=csv")
        .arg("--out")
        .arg(&csv)
        .assert()
        .success()
        .stderr(predicate::str::contains("note: Compared on the 1 of 2 scenes"));
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        text.starts_with(
            "group,scenes,run,column,better,value,n,ci_low,ci_high,rank,points\nall,1,a,COL_ob,lower,"
        ),
        "{text}"
    );
    // HTML next to the runs links run a's report (run b's is elsewhere).
    let html = root.path().join("compare.html");
    sceneeval()
        .arg("compare")
        .args([&a, &b])
        .args(["--format", "html", "--out"])
        .arg(&html)
        .assert()
        .success();
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(
        page.contains("<a href=\"a/report/index.html\">report</a>"),
        "{page}"
    );
    assert!(page.contains("none (sceneeval report "), "{page}");
    // LaTeX.
    sceneeval()
        .arg("compare")
        .args([&a, &b])
        .args(["--format", "latex", "--ci", "0.9"])
        .assert()
        .success()
        .stdout(
            predicate::str::contains("\\begin{tabular}").and(predicate::str::contains("90\\% bootstrap")),
        );
}

#[test]
fn usage_errors_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let empty = dir.path();
    // The library's error names no option; the command line adds the hint.
    sceneeval().arg("compare").arg(empty).assert().failure().stderr(
        predicate::str::contains(
            "no <scene>/eval.json in this folder (not the output folder of an evaluation)",
        )
        .and(predicate::str::contains(
            "hint: give the --out folder of sceneeval evaluate",
        )),
    );
    let run = dir.path().join("run");
    evaluate(scenes(&[10]).path(), &fixtures().join("assets"), &run, &[]).success();
    sceneeval()
        .arg("compare")
        .args([&run, &run])
        .args(["--names", "A"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("--names gives 1 names for 2 runs"));
    sceneeval()
        .arg("compare")
        .args([&run, &run])
        .assert()
        .failure()
        .stderr(predicate::str::contains("two runs are named \"run\""));
    sceneeval()
        .arg("compare")
        .arg(&run)
        .args(["--ci", "1.5"])
        .assert()
        .failure()
        .stderr(predicate::str::contains(
            "confidence level 1.5 is not between 0 and 1",
        ));
    // A scene whose file moved: the page says why there is no top view; the report is written.
    let moved = dir.path().join("moved");
    sceneeval()
        .arg("report")
        .arg(&run)
        .arg("--scenes")
        .arg(Path::new("/nonexistent"))
        .arg("--out")
        .arg(&moved)
        .assert()
        .success()
        .stderr(predicate::str::contains(
            "warning: no top view of scene_10: reading /nonexistent/scene_10.json failed",
        ));
    let page = std::fs::read_to_string(moved.join("scenes/scene_10.html")).unwrap();
    assert!(page.contains("id=\"no-topview\""), "{page}");
    sceneeval()
        .arg("report")
        .arg(&run)
        .args(["--assets", "fixture"])
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("error: asset folders: ").and(predicate::str::contains(
                "hint: each --assets is PREFIX=DIR or PREFIX=LAYOUT:DIR",
            )),
        );
}

#[test]
fn a_corrupted_record_is_listed_and_the_rest_reported() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    evaluate(scenes(&[5, 10]).path(), &fixtures().join("assets"), &run, &[]).success();
    std::fs::write(
        run.join("scene_5/eval.json"),
        "{\"schema\": \"sceneeval.eval/2\", ",
    )
    .unwrap();
    let warning = "warning: ".to_owned()
        + &run.join("scene_5/eval.json").display().to_string()
        + " could not be read (";
    sceneeval().arg("report").arg(&run).assert().success().stderr(
        predicate::str::contains(warning.as_str())
            .and(predicate::str::contains("EOF while parsing"))
            .and(predicate::str::contains(
                "(1 scene pages; 1 unreadable records listed)",
            )),
    );
    let index = std::fs::read_to_string(run.join("report/index.html")).unwrap();
    assert!(index.contains("<ul id=\"unreadable\">"), "{index}");
    sceneeval()
        .arg("compare")
        .arg(&run)
        .assert()
        .success()
        .stderr(predicate::str::contains(warning.as_str()))
        .stdout(
            predicate::str::contains("### all (1 scene)")
                .and(predicate::str::contains("run: 1 record(s) could not be read"))
                .and(predicate::str::contains("EOF while parsing")),
        );
    // None readable: an error naming the first.
    std::fs::write(run.join("scene_10/eval.json"), "[]").unwrap();
    sceneeval()
        .arg("compare")
        .arg(&run)
        .assert()
        .failure()
        .stderr(predicate::str::contains("no record of this folder can be read; "));
}
