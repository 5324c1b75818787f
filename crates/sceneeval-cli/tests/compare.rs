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
            &[
                "--names",
                "--format",
                "--by",
                "--out",
                "--annotations",
                "--ci",
                "--paired",
                "--against-first",
                "--alpha",
                "--rank",
                "--failed",
            ][..],
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
            "group,scenes,run,column,better,value,n,ci_low,ci_high,rank,points,missing,failed\nall,1,a,COL_ob,lower,"
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
            "--ci: confidence level 1.5 is not between 0 and 1",
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

/// A run folder `root/name` written from records: per scene `Some((SUP, OOB))` in [0, 1], or
/// `None` for a failed scene; every scene also ran accessibility without a value (no object
/// has functional sides), a column no run has a value in.
fn written_run(
    root: &Path,
    name: &str,
    scenes: &[(u32, Option<(f64, f64)>)],
    plan: &str,
) -> std::path::PathBuf {
    use sceneeval::plausibility::{Metric as P, PlausibilityReport, PlausibilitySummary};
    use sceneeval::results::{FileDigest, Fingerprint, Preset, SceneName, SceneRecord, SceneReport, Stage};
    let dir = root.join(name);
    for (k, values) in scenes {
        let scene = format!("scene_{k}");
        let record = match values {
            Some((sup, oob)) => {
                let geometry = PlausibilityReport::of_summary(
                    Some(scene.clone()),
                    vec![P::Support, P::Accessibility, P::OutOfBounds],
                    PlausibilitySummary {
                        sup: Some(*sup),
                        oob: Some(*oob),
                        ..PlausibilitySummary::default()
                    },
                );
                SceneRecord::ok(
                    SceneName::new(&scene),
                    SceneReport::new(Some(scene.clone()), geometry, None),
                )
            }
            None => SceneRecord::failed(
                SceneName::new(&scene),
                Stage::Load,
                &std::io::Error::other("crashed"),
            ),
        };
        let fingerprint = Fingerprint {
            tool: sceneeval::results::TOOL_VERSION.to_owned(),
            schema: sceneeval::results::RECORD_SCHEMA.to_owned(),
            scene: FileDigest {
                path: format!("scenes/{scene}.json"),
                blake3: None,
            },
            plan: plan.to_owned(),
            preset: Some(if plan == "other" {
                Preset::Reference
            } else {
                Preset::Default
            }),
            annotation: None,
            assets: vec![],
        };
        std::fs::create_dir_all(dir.join(&scene)).unwrap();
        record
            .with_fingerprint(fingerprint)
            .write(&dir.join(&scene).join("eval.json"))
            .unwrap();
    }
    dir
}

/// Runs A (SUP 50 on six scenes), B (SUP 60, 70, 80, 90, 100, 55: six positive untied
/// differences, exact Wilcoxon p = 2 / 2^6 = 0.03125; another plan and preset) and C (scene_0
/// at SUP 90, scene_1 failed, the rest missing). OOB 0 everywhere.
fn three_written_runs(root: &Path) -> [std::path::PathBuf; 3] {
    let a: Vec<(u32, Option<(f64, f64)>)> = (0..6).map(|k| (k, Some((0.5, 0.0)))).collect();
    let b: Vec<(u32, Option<(f64, f64)>)> = [0.6, 0.7, 0.8, 0.9, 1.0, 0.55]
        .into_iter()
        .zip(0..)
        .map(|(s, k)| (k, Some((s, 0.0))))
        .collect();
    [
        written_run(root, "A", &a, "plan"),
        written_run(root, "B", &b, "other"),
        written_run(root, "C", &[(0, Some((0.9, 0.0))), (1, None)], "plan"),
    ]
}

fn stdout_of(args: &[&std::ffi::OsStr]) -> (String, String) {
    let out = sceneeval().arg("compare").args(args).assert().success();
    let o = out.get_output();
    (
        String::from_utf8(o.stdout.clone()).unwrap(),
        String::from_utf8(o.stderr.clone()).unwrap(),
    )
}

#[test]
fn paired_rows_tests_and_warnings() {
    let root = tempfile::tempdir().unwrap();
    let [a, b, c] = three_written_runs(root.path());
    let os = |s: &'static str| std::ffi::OsStr::new(s);
    let (csv, err) = stdout_of(&[
        a.as_os_str(),
        b.as_os_str(),
        c.as_os_str(),
        os("--paired"),
        os("--format=csv"),
    ]);
    let lines: Vec<&str> = csv.lines().collect();
    assert!(
        lines[0].starts_with("kind,a,b,metric,n,mean_diff,diff_low,diff_high,p_value,p_holm,"),
        "{csv}"
    );
    // Every pair, SUP then OOB (ACC has no value in any run: left out).
    let keys: Vec<String> = lines[1..]
        .iter()
        .map(|l| l.split(',').take(4).collect::<Vec<_>>().join(","))
        .collect();
    assert_eq!(
        keys,
        [
            "paired,A,B,SUP",
            "paired,A,B,OOB",
            "paired,A,C,SUP",
            "paired,A,C,OOB",
            "paired,B,C,SUP",
            "paired,B,C,OOB"
        ]
    );
    // A-B SUP: mean (10 + 20 + 30 + 40 + 50 + 5) / 6 = 25.833333; p = 0.03125, Holm over the
    // one p-value of the pair (OOB has none) unchanged.
    let ab: Vec<&str> = lines[1].split(',').collect();
    assert_eq!(&ab[4..6], ["6", "25.833333"]);
    assert_eq!(&ab[8..12], ["0.03125", "0.03125", "higher", "exact"]);
    // A-C SUP: one scene, one non-zero difference: no p-value, and the note says why.
    assert!(
        lines[3].starts_with("paired,A,C,SUP,1,40.000000,40.000000,40.000000,,,higher,none,0,"),
        "{csv}"
    );
    assert!(
        lines[3].contains("no p-value: 1 non-zero difference(s) of 1 scene(s)"),
        "{csv}"
    );
    // Different plans and presets: warned, and compared.
    assert!(
        err.contains("warning: A and B used different plans (result digests): A plan, B other"),
        "{err}"
    );
    assert!(
        err.contains("warning: A and B used different presets: A default, B reference"),
        "{err}"
    );
    assert!(
        err.contains("warning: A and C: 5 scene(s) not evaluated by both"),
        "{err}"
    );

    // Against the first: (A, B) and (A, C) only.
    let (csv, _) = stdout_of(&[
        a.as_os_str(),
        b.as_os_str(),
        c.as_os_str(),
        os("--paired"),
        os("--against-first"),
        os("--format=csv"),
    ]);
    assert!(!csv.contains("paired,B,C"), "{csv}");
    assert_eq!(csv.lines().count(), 5);

    // Markdown: the differences with a significance mark; the missing and failed scenes named
    // under every table; no ACC column.
    let (md, _) = stdout_of(&[
        a.as_os_str(),
        b.as_os_str(),
        c.as_os_str(),
        os("--paired"),
        os("--ci=0.9"),
    ]);
    assert!(md.contains("| A | B | SUP ↑ | 6 | +25.83* | ["), "{md}");
    assert!(md.contains("| 0.031 | 0.031 | B |"), "{md}");
    assert!(md.contains("90% paired bootstrap interval"), "{md}");
    assert!(
        md.contains(
            "- C: 4 of 6 scenes missing (scene\\_2, scene\\_3, scene\\_4, scene\\_5), 1 failed (scene\\_1)"
        ),
        "{md}"
    );
    assert!(
        !md.contains("ACC ↑") && md.contains("- ACC left out: no run has a value in it."),
        "{md}"
    );
    assert!(md.contains("C - A, SUP: no p-value"), "{md}");
    // A stricter alpha: no mark.
    let (md, _) = stdout_of(&[a.as_os_str(), b.as_os_str(), os("--paired"), os("--alpha=0.01")]);
    assert!(md.contains("| A | B | SUP ↑ | 6 | +25.83 | ["), "{md}");
    // LaTeX: the missing scenes in the table, no ACC column, the paired table.
    let (latex, _) = stdout_of(&[a.as_os_str(), c.as_os_str(), os("--paired"), os("--format=latex")]);
    assert!(
        latex.contains(r"\footnotesize C: 4 of 6 scenes missing (scene\_2, scene\_3, scene\_4, scene\_5), 1 failed (scene\_1)}"),
        "{latex}"
    );
    assert!(!latex.contains("ACC $"), "{latex}");
    assert!(
        latex.contains(r"A & C & SUP $\uparrow$ & 1 & +40.00 & [+40.00, +40.00] & - & - \\"),
        "{latex}"
    );
    // HTML: the table of differences and the coverage.
    let html = root.path().join("c.html");
    sceneeval()
        .arg("compare")
        .args([&a, &b, &c])
        .args(["--paired", "--format", "html", "--out"])
        .arg(&html)
        .assert()
        .success();
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.contains("<table id=\"paired\">"), "{page}");
    assert!(page.contains("<li>C: 4 of 6 scenes missing"), "{page}");

    sceneeval()
        .arg("compare")
        .args([&a, &b])
        .arg("--against-first")
        .assert()
        .failure()
        .stderr(predicate::str::contains("--paired"));
    sceneeval()
        .arg("compare")
        .args([&a, &b])
        .arg("--alpha=0")
        .assert()
        .failure()
        .stderr(predicate::str::contains(
            "--alpha: significance level 0 is not between 0 and 1",
        ));
}

#[test]
fn tested_and_mean_ranks_and_failed_scenes_at_worst() {
    let root = tempfile::tempdir().unwrap();
    let [a, b, c] = three_written_runs(root.path());
    let os = |s: &'static str| std::ffi::OsStr::new(s);
    let rank = |csv: &str, run: &str, column: &str| -> String {
        let line = csv
            .lines()
            .find(|l| l.starts_with(&format!("all,6,{run},{column},")))
            .unwrap_or_else(|| panic!("{csv}"));
        line.split(',').nth(9).unwrap().to_owned()
    };
    // B beats A on SUP by the test (p = 0.03125 < 0.05): ranks 2 and 1; OOB: tied first.
    let (csv, _) = stdout_of(&[a.as_os_str(), b.as_os_str(), os("--format=csv")]);
    assert_eq!(
        (rank(&csv, "A", "SUP"), rank(&csv, "B", "SUP")),
        ("2".into(), "1".into())
    );
    assert_eq!(
        (rank(&csv, "A", "OOB"), rank(&csv, "B", "OOB")),
        ("1".into(), "1".into())
    );
    // --alpha 0.01: no test separates them, they share the first rank.
    let (csv, _) = stdout_of(&[
        a.as_os_str(),
        b.as_os_str(),
        os("--format=csv"),
        os("--alpha=0.01"),
    ]);
    assert_eq!(
        (rank(&csv, "A", "SUP"), rank(&csv, "B", "SUP")),
        ("1".into(), "1".into())
    );
    // --rank mean: by the means alone.
    let (csv, _) = stdout_of(&[
        a.as_os_str(),
        b.as_os_str(),
        os("--format=csv"),
        os("--alpha=0.01"),
        os("--rank=mean"),
    ]);
    assert_eq!(
        (rank(&csv, "A", "SUP"), rank(&csv, "B", "SUP")),
        ("2".into(), "1".into())
    );
    let (md, _) = stdout_of(&[a.as_os_str(), b.as_os_str(), os("--rank=mean")]);
    assert!(md.contains("Ranks by mean (--rank mean)"), "{md}");

    // --failed worst: C over the six scenes, its failed and missing ones at the worst value:
    // SUP (90 + 0 * 5) / 6 = 15, OOB (0 + 100 * 5) / 6 = 83.33.
    let (csv, err) = stdout_of(&[
        a.as_os_str(),
        c.as_os_str(),
        os("--format=csv"),
        os("--failed=worst"),
    ]);
    assert!(csv.contains("\nall,6,C,SUP,higher,15.0000,6,"), "{csv}");
    assert!(csv.contains("\nall,6,C,OOB,lower,83.3333,6,"), "{csv}");
    assert!(
        csv.contains(",scene_2 scene_3 scene_4 scene_5,scene_1\n"),
        "{csv}"
    );
    assert!(
        err.contains("note: Values over every scene of any run (6)"),
        "{err}"
    );
    assert!(err.contains("note: C: 4 of 6 scenes missing"), "{err}");
    // Skipped (the default): over scene_0 alone, C's 90 against A's 50.
    let (csv, _) = stdout_of(&[a.as_os_str(), c.as_os_str(), os("--format=csv")]);
    assert!(csv.contains("\nall,1,C,SUP,higher,90.0000,1,"), "{csv}");
}
