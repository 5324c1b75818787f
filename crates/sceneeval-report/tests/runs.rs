//! Two runs of the bundled fixture scenes, evaluated here (the geometry metrics and CNT, ATR,
//! OOR, OAR with labels and the lexicon, against the test-support annotation rows, as the
//! facade's pipeline test does), then compared and reported; the pages are loaded in a
//! headless browser when one is installed.
//!
//! - `method-a`: scenes 2, 5, 7, 8, preset `default`, with diagnostic images.
//! - `method-b`: scenes 2, 5, 8, preset `reference` (an unmapped relation counts as satisfied).

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use sceneeval_annotation::Annotations;
use sceneeval_report::compare::Verdict;
use sceneeval_report::{
    CompareOptions, NoTopView, ReportOptions, Run, compare, recorded_assets, write_report,
};
use sceneeval_results::{Metric, Preset, SceneName, SceneRecord, Stage};
use sceneeval_run::EvaluationRequest;
use sceneeval_test_support::fidelity_model::CSV;
use sceneeval_test_support::system::{BROWSER, available, chromium as system_chromium};

struct Runs {
    root: PathBuf,
    a: PathBuf,
    b: PathBuf,
}

impl Runs {
    /// What `sceneeval report RUN --scenes DIR --assets fixture=...` gives for run `name`.
    fn options(&self, name: &str) -> ReportOptions {
        ReportOptions {
            assets: vec![fixture_assets()],
            scenes: Some(self.root.join(format!("scenes-{name}"))),
        }
    }
}

/// The `--assets` of the fixture assets.
fn fixture_assets() -> String {
    format!(
        "fixture={}",
        fixtures().join("assets").canonicalize().unwrap().display()
    )
}

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// Evaluates the two runs once per test binary, under the target's temporary folder.
fn runs() -> &'static Runs {
    static RUNS: OnceLock<Runs> = OnceLock::new();
    RUNS.get_or_init(|| {
        let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sceneeval-report-runs");
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(&root).unwrap();
        let annotations = root.join("annotations.csv");
        std::fs::write(&annotations, CSV).unwrap();
        let run = |name: &str, scenes: &[u32], preset: Preset, diagnostics: bool| {
            let dir = root.join(format!("scenes-{name}"));
            std::fs::create_dir_all(&dir).unwrap();
            for n in scenes {
                let file = format!("scene_{n}.json");
                std::fs::copy(fixtures().join("scenes").join(&file), dir.join(&file)).unwrap();
            }
            let out = root.join(name);
            let mut request = EvaluationRequest::new(&dir, &out);
            request.assets = vec![fixture_assets()];
            request.annotations = Some(annotations.clone());
            request.plan.plan = Some("full".into());
            request.plan.preset = Some(preset);
            request.diagnostics = diagnostics;
            // With physics, method-a runs the stability metric too (method-b does not).
            if diagnostics {
                request.plan.metrics = Some(Metric::ALL.to_vec());
            }
            let outcome = request.run(&|_| {}).unwrap();
            assert_eq!(outcome.batch.failed, 0);
            out
        };
        let a = run("method-a", &[2, 5, 7, 8], Preset::Default, true);
        let b = run("method-b", &[2, 5, 8], Preset::Reference, false);
        // The report of each run where `sceneeval report RUN --scenes DIR --assets ...` writes it.
        for (name, dir) in [("method-a", &a), ("method-b", &b)] {
            let options = ReportOptions {
                assets: vec![fixture_assets()],
                scenes: Some(root.join(format!("scenes-{name}"))),
            };
            // method-a's report is given the annotations the run used (descriptions), method-b's not.
            let mut run = Run::open(dir).unwrap();
            if name == "method-a" {
                run = run.with_annotations(&Annotations::from_csv_str(CSV).unwrap());
            }
            let written = write_report(&run, &dir.join("report"), &options).unwrap();
            assert!(
                written.without_top_view.is_empty(),
                "{:?}",
                written.without_top_view
            );
        }
        Runs { root, a, b }
    })
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn two_fixture_runs_compared_on_what_they_share() {
    let r = runs();
    let a = Run::open(&r.a).unwrap();
    let b = Run::open(&r.b).unwrap();
    // Difficulties come from each run's summary_scenes.csv: scene 8 easy, scene 2 hard.
    assert_eq!(
        (a.difficulty("scene_8"), a.difficulty("scene_2")),
        (Some("easy"), Some("hard"))
    );
    assert_eq!(a.difficulty("scene_5"), None);
    let c = compare(
        &[a, b],
        &CompareOptions {
            by_difficulty: true,
            rank: sceneeval_report::compare::RankBy::Mean,
            ..CompareOptions::default()
        },
    )
    .unwrap();
    assert_eq!(c.scenes, ["scene_2", "scene_5", "scene_8"]);
    // Both runs ran the ten metrics (12 columns); ATR, without a VLM, has no value in either
    // run and is left out with a note (issue 37: no all-"-" column).
    assert_eq!(c.columns.len(), 11);
    assert!(c.columns.iter().all(|c| c.name != "ATR"));
    assert!(
        c.notes
            .contains(&"ATR left out: no run has a value in it.".to_owned()),
        "{:?}",
        c.notes
    );
    let notes = c.notes.join("\n");
    assert!(
        notes.contains("different presets: method-a default, method-b reference"),
        "{notes}"
    );
    assert!(notes.contains("different plans"), "{notes}");
    assert!(notes.contains("left out: scene_7 (not in method-b)"), "{notes}");
    let groups: Vec<(&str, usize)> = c.tables.iter().map(|t| (t.group.as_str(), t.scenes)).collect();
    assert_eq!(groups, [("all", 3), ("easy", 1), ("hard", 1), ("unannotated", 1)]);
    // method-a's CNT (the pipeline test's numbers): scene 8 5/6, scene 2 7/7, scene 5 has no
    // row. Over every common scene: (5/6 + 1) / 2 = 91.67 % from 2 scenes; easy: 83.33 %.
    let cnt = c.columns.iter().position(|c| c.metric == Metric::Cnt).unwrap();
    let all = &c.tables[0].cells[0][cnt];
    assert!((all.value.unwrap() - 100.0 * (5.0 / 6.0 + 1.0) / 2.0).abs() < 1e-9);
    assert_eq!(all.n, 2);
    assert!((c.tables[1].cells[0][cnt].value.unwrap() - 500.0 / 6.0).abs() < 1e-9);
    assert!(all.rank.is_some());
    // Scene 8's in_harmony_with is unmapped: not satisfied by default, satisfied under the
    // reference preset (unmapped_is_satisfied).
    let d = c
        .differences
        .iter()
        .find(|d| d.scene == "scene_8" && d.spec.contains("in_harmony_with"))
        .unwrap_or_else(|| panic!("{:?}", c.differences));
    assert_eq!(d.metric, Metric::Oor);
    assert_eq!(d.verdicts, [Verdict::NotSatisfied, Verdict::Satisfied]);
    // The HTML page links each run's report and its scene page.
    let html = c.to_html(&r.root);
    assert!(html.contains("href=\"method-a/report/index.html\""), "{html}");
    assert!(html.contains("href=\"method-b/report/scenes/scene_8.html\">satisfied</a>"));
}

#[test]
fn scene_pages_show_what_is_wrong_where() {
    let r = runs();
    let report = r.a.join("report");
    let index = read(&report.join("index.html"));
    for scene in ["scene_2", "scene_5", "scene_7", "scene_8"] {
        assert!(
            index.contains(&format!("<a href=\"scenes/{scene}.html\">{scene}</a>")),
            "{scene}"
        );
    }
    // Scene 5: the wardrobe and the nightstand collide, in the scene list's filter tokens and
    // on the page.
    assert!(
        index.contains("data-scene=\"scene_5\" data-fails=\"COL_ob COL_sc"),
        "{index}"
    );
    let s5 = read(&report.join("scenes/scene_5.html"));
    assert!(s5.contains("<g class=\"object\" data-object=\"idx0_fixture.wardrobe\"><title>1. idx0_fixture.wardrobe (wardrobe)\nin collision with idx1_fixture.nightstand"), "{s5}");
    // Scene 7: the sofa is out of bounds (purple), half of its surface over no floor.
    let s7 = read(&report.join("scenes/scene_7.html"));
    assert!(s7.contains("fill=\"#9467bd\""), "{s7}");
    assert!(s7.contains("idx0_fixture.sofa"), "{s7}");
    // Scene 8: the door is blocked by the wardrobe, drawn dashed red; the navigability map of
    // the diagnostics lies under the objects; the fidelity specs with their verdicts.
    let s8 = read(&report.join("scenes/scene_8.html"));
    assert!(s8.contains("blocked by idx0_fixture.wardrobe"), "{s8}");
    assert!(
        s8.contains("<image class=\"navigable\" href=\"../../scene_8/diagnostics/navigability.png\""),
        "{s8}"
    );
    assert!(s8.contains("id=\"specs-cnt\""));
    assert!(
        s8.contains("<code>eq,2,chair</code></td><td class=\"bad\">not satisfied</td>"),
        "{s8}"
    );
    assert!(s8.contains("mapping: unmapped (none)"), "{s8}");
    assert!(s8.contains("<figcaption>navigability.png</figcaption>"));
}

/// Each scene page: the description of its annotation row (or why there is none), links to
/// the previous and next pages in the overview's order, and the views (none kept here: the
/// fixture runs judge with labels and the lexicon, no VLM renders).
#[test]
fn scene_pages_describe_the_scene_and_link_their_neighbours() {
    let r = runs();
    let pages = r.a.join("report/scenes");
    let s8 = read(&pages.join("scene_8.html"));
    assert!(
        s8.contains("<blockquote class=\"box\" id=\"description\">A small bedroom.</blockquote>"),
        "{s8}"
    );
    assert!(s8.contains("the run evaluated with a row for this scene"), "{s8}");
    // Scenes 5 and 7 have no row in the annotations: the run recorded none.
    let s5 = read(&pages.join("scene_5.html"));
    assert!(
        s5.contains(
            "<p class=\"unknown\" id=\"description\">no description: the run has no annotation row</p>"
        ),
        "{s5}"
    );
    // method-b's report was given no annotations: it says what to pass.
    let b8 = read(&r.b.join("report/scenes/scene_8.html"));
    assert!(
        b8.contains("no description: the run records only a digest"),
        "{b8}"
    );
    assert!(b8.contains("(--annotations FILE)"), "{b8}");
    // The overview's order: 2, 5, 7, 8; the first and last pages say so.
    let order = ["scene_2", "scene_5", "scene_7", "scene_8"];
    for (k, scene) in order.iter().enumerate() {
        let page = read(&pages.join(format!("{scene}.html")));
        match k.checked_sub(1).map(|p| order[p]) {
            Some(p) => assert!(
                page.contains(&format!("<a rel=\"prev\" href=\"{p}.html\">&larr; {p}</a>")),
                "{scene}: {page}"
            ),
            None => assert!(
                page.contains("<span class=\"muted\">first scene</span>"),
                "{page}"
            ),
        }
        match order.get(k + 1) {
            Some(n) => {
                assert!(
                    page.contains(&format!("<a rel=\"next\" href=\"{n}.html\">{n} &rarr;</a>")),
                    "{scene}: {page}"
                );
                assert!(pages.join(format!("{n}.html")).is_file());
            }
            None => assert!(page.contains("<span class=\"muted\">last scene</span>"), "{page}"),
        }
        assert!(page.contains("id=\"no-views\""), "{scene}: {page}");
    }
}

/// Physics: scene 5's wardrobe and nightstand, which interpenetrate, are pushed apart by the
/// simulation (unstable, olive in the top view); scene 8's ceiling lamp is welded.
#[test]
fn scene_pages_show_stability() {
    let r = runs();
    let report = r.a.join("report");
    let index = read(&report.join("index.html"));
    assert!(index.contains("STAB"), "{index}");
    assert!(
        index.contains(
            "<option value=\"unstable\">scenes with an object unstable (moves under physics)</option>"
        ),
        "{index}"
    );
    let s5 = read(&report.join("scenes/scene_5.html"));
    assert!(
        s5.contains(
            "<h2>Physical stability</h2><p>Weld mode <code>architectural</code>: 2 of 5 free objects"
        ),
        "{s5}"
    );
    assert!(
        s5.contains("<tr><td><code>idx1_fixture.nightstand</code></td><td class=\"bad\">unstable</td>"),
        "{s5}"
    );
    assert!(s5.contains("under physics moved "), "{s5}");
    let s8 = read(&report.join("scenes/scene_8.html"));
    assert!(
        s8.contains("<tr><td><code>idx3_fixture.ceiling_lamp</code></td><td class=\"good\">welded</td>"),
        "{s8}"
    );
    assert!(s8.contains("<td>yes: on the ceiling</td>"), "{s8}");
    // method-b did not run it: compared without STAB, and the note says so.
    let c = compare(
        &[Run::open(&r.a).unwrap(), Run::open(&r.b).unwrap()],
        &CompareOptions::default(),
    )
    .unwrap();
    assert!(c.columns.iter().all(|c| c.metric != Metric::Stability));
    assert!(
        c.notes
            .iter()
            .any(|n| n == "STAB (stability) left out: not evaluated by method-b."),
        "{:?}",
        c.notes
    );
}

#[test]
fn a_report_outside_its_run_copies_the_images_and_escapes_everything() {
    let r = runs();
    let mut run = Run::open(&r.a)
        .unwrap()
        .with_name("<script>alert('name')</script>");
    let err = std::io::Error::other("<img src=x onerror=alert(1)> & \"quotes\"");
    run.records.push(SceneRecord::failed(
        SceneName::new("scene_9<b>"),
        Stage::Load,
        &err,
    ));
    let out = tempfile::tempdir().unwrap();
    let written = write_report(&run, out.path(), &r.options("method-a")).unwrap();
    assert_eq!(written.pages, 5);
    // The failed scene has no file in the scene folder: its page says why there is no top view.
    assert_eq!(written.without_top_view.len(), 1);
    assert!(
        matches!(&written.without_top_view[0].1, NoTopView::Unreadable { path, .. } if path.ends_with("scene_9<b>.json")),
        "{:?}",
        written.without_top_view
    );
    assert!(
        out.path()
            .join("files/scene_8/diagnostics/navigability.png")
            .is_file()
    );
    let index = read(&out.path().join("index.html"));
    assert!(!index.contains("<script>alert"), "the run's name is escaped");
    assert!(index.contains("&lt;script&gt;alert(&#39;name&#39;)&lt;/script&gt;"));
    assert!(index.contains("href=\"scenes/scene_9~3Cb~3E.html\""), "{index}");
    let failed = read(&out.path().join("scenes/scene_9~3Cb~3E.html"));
    assert!(!failed.contains("<img src=x"), "{failed}");
    assert!(
        failed.contains("&lt;img src=x onerror=alert(1)&gt; &amp; &quot;quotes&quot;"),
        "{failed}"
    );
    let s8 = read(&out.path().join("scenes/scene_8.html"));
    assert!(
        s8.contains("href=\"../files/scene_8/diagnostics/navigability.png\""),
        "{s8}"
    );
}

/// A copy of run `method-a` in a folder of its own, next to a "secret" file outside it, then
/// tampered with: scene 2's record names the secret file as its scene, scene 5's views hold a
/// symbolic link to it, scene 7's record says its scene is `../..`, scene 8's record is not
/// JSON, `scene_9/eval.json` is a link to a record outside the run and `scene_11/eval.json` a
/// link to nothing.
#[cfg(unix)]
fn tampered_run() -> (tempfile::TempDir, PathBuf, PathBuf) {
    let r = runs();
    let root = tempfile::tempdir().unwrap();
    let run = root.path().join("run");
    let copied = Command::new("cp").arg("-r").arg(&r.a).arg(&run).status().unwrap();
    assert!(copied.success());
    std::fs::remove_dir_all(run.join("report")).unwrap();
    let secret = root.path().join("secret.json");
    std::fs::write(
        &secret,
        r#"{"version": "TOP-SECRET-VALUE", "objects": "TOP-SECRET-VALUE"}"#,
    )
    .unwrap();
    let edit = |scene: &str, f: &dyn Fn(&mut serde_json::Value)| {
        let path = run.join(scene).join("eval.json");
        let mut record: serde_json::Value = serde_json::from_str(&read(&path)).unwrap();
        f(&mut record);
        std::fs::write(&path, record.to_string()).unwrap();
    };
    let secret_path = secret.display().to_string();
    edit("scene_2", &|r| {
        r["fingerprint"]["scene"]["path"] = secret_path.clone().into();
        r["fingerprint"]["scene"]["blake3"] = serde_json::Value::Null;
    });
    let views = run.join("scene_5/views");
    std::fs::create_dir_all(&views).unwrap();
    std::fs::copy(
        run.join("scene_8/diagnostics/navigability.png"),
        views.join("ok.png"),
    )
    .unwrap();
    std::os::unix::fs::symlink(&secret, views.join("evil.png")).unwrap();
    edit("scene_7", &|r| r["scene"] = "../..".into());
    std::fs::write(run.join("scene_8/eval.json"), "{\"schema\": ").unwrap();
    std::fs::create_dir_all(run.join("scene_9")).unwrap();
    std::fs::copy(r.b.join("scene_2/eval.json"), root.path().join("elsewhere.json")).unwrap();
    std::os::unix::fs::symlink(root.path().join("elsewhere.json"), run.join("scene_9/eval.json")).unwrap();
    std::fs::create_dir_all(run.join("scene_11")).unwrap();
    std::os::unix::fs::symlink(root.path().join("nowhere.json"), run.join("scene_11/eval.json")).unwrap();
    (root, run, secret)
}

/// Every file below `dir`, as text.
fn texts(dir: &Path) -> Vec<(PathBuf, String)> {
    sceneeval_test_support::files_below(dir)
        .into_iter()
        .map(|path| {
            let text = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
            (path, text)
        })
        .collect()
}

#[cfg(unix)]
#[test]
fn a_tampered_run_folder_makes_the_report_read_nothing_outside_it() {
    let (root, run_dir, secret) = tampered_run();
    let run = Run::open(&run_dir).unwrap();
    // The corrupted record, the one of another scene and the link out are listed, with why.
    let unreadable: Vec<(&str, &str)> = run
        .unreadable
        .iter()
        .map(|u| (u.scene.as_str(), u.reason.as_str()))
        .collect();
    assert_eq!(unreadable.len(), 4, "{unreadable:?}");
    assert_eq!(unreadable[0].0, "scene_7");
    assert!(
        unreadable[0]
            .1
            .contains("the record is of scene \"../..\", not of the folder \"scene_7\""),
        "{unreadable:?}"
    );
    assert_eq!(unreadable[1].0, "scene_8");
    assert!(
        unreadable[1]
            .1
            .contains("not a valid result file: EOF while parsing"),
        "{unreadable:?}"
    );
    assert_eq!(unreadable[3], ("scene_11", "a symbolic link to nothing"));
    assert_eq!(unreadable[2].0, "scene_9");
    assert!(
        unreadable[2].1.contains("leads out of the run folder"),
        "{unreadable:?}"
    );
    let names: Vec<&str> = run.records.iter().map(|r| r.scene.as_str()).collect();
    assert_eq!(names, ["scene_2", "scene_5"]);

    // Inside the run (links) and outside it (copies), without a scene folder.
    for out in [run_dir.join("report"), root.path().join("copy")] {
        let written = write_report(&run, &out, &ReportOptions::default()).unwrap();
        assert_eq!(written.pages, 2);
        let why: Vec<(&str, &NoTopView)> = written
            .without_top_view
            .iter()
            .map(|(s, w)| (s.as_str(), w))
            .collect();
        assert_eq!(
            why,
            [
                ("scene_2", &NoTopView::OutsideRun),
                ("scene_5", &NoTopView::OutsideRun)
            ]
        );
        for (path, text) in texts(&out) {
            assert!(
                !text.contains("TOP-SECRET"),
                "{} quotes the secret file",
                path.display()
            );
            assert!(
                !text.contains(&secret.display().to_string()),
                "{} names the secret file",
                path.display()
            );
        }
        let s5 = read(&out.join("scenes/scene_5.html"));
        assert!(s5.contains("ok.png"), "{s5}");
        assert!(
            !s5.contains("href=\"../../scene_5/views/evil.png\"") && !s5.contains("views/evil.png\""),
            "{s5}"
        );
        assert!(
            s5.contains(
                "The image views/evil.png is a symbolic link that leads out of the run folder: not shown."
            ),
            "{s5}"
        );
        assert!(!out.join("files/scene_5/views/evil.png").exists());
        let index = read(&out.join("index.html"));
        assert!(index.contains("<ul id=\"unreadable\">"), "{index}");
        assert!(index.contains("scene_8/eval.json</code>: "), "{index}");
        assert!(index.contains("EOF while parsing"), "{index}");
    }
    // Nothing was written outside the report folders.
    let mut top = sceneeval_test_support::file_names(root.path());
    top.sort();
    assert_eq!(top, ["copy", "elsewhere.json", "run", "secret.json"]);

    // A record whose name would leave the folder, in a run made in memory: no path is built.
    let mut escaping = run.records[0].clone();
    escaping.scene = SceneName::new("../..");
    let mem = Run::from_records("mem", &run_dir, vec![escaping]);
    assert_eq!(mem.scene_dir("../.."), None);
    let out = root.path().join("mem-report");
    let written = write_report(
        &mem,
        &out,
        &ReportOptions {
            assets: Vec::new(),
            scenes: Some(root.path().to_owned()),
        },
    )
    .unwrap();
    assert_eq!(written.without_top_view[0].1, NoTopView::NotAFileName);
    assert!(
        out.join("scenes/~2E~2E~2F~2E~2E.html").is_file(),
        "{:?}",
        sceneeval_test_support::file_names(&out.join("scenes"))
    );

    // The asset folders the records name are used only inside the folders given.
    let assets = fixtures().join("assets").canonicalize().unwrap();
    let a = Run::open(&runs().a).unwrap();
    assert_eq!(
        recorded_assets(&a.records, &[run_dir.canonicalize().unwrap().as_path()])
            .prefixes()
            .count(),
        0
    );
    let found: Vec<String> = recorded_assets(&a.records, &[assets.as_path()])
        .prefixes()
        .map(str::to_owned)
        .collect();
    assert_eq!(found, ["fixture"]);

    // The comparison lists the unreadable records with the parse error and leaves their scenes out.
    let c = compare(&[run, Run::open(&runs().b).unwrap()], &CompareOptions::default()).unwrap();
    assert_eq!(c.scenes, ["scene_2", "scene_5"]);
    let notes = c.notes.join("\n");
    assert!(
        notes.contains("run: 4 record(s) could not be read, their scenes are left out: "),
        "{notes}"
    );
    assert!(notes.contains("EOF while parsing"), "{notes}");
    assert!(notes.contains("scene_8 (unreadable in run)"), "{notes}");
    assert!(
        notes.contains("scene_7 (unreadable in run; not in method-b)"),
        "{notes}"
    );
}

/// Runs chromium headless on `url` with `args`, returning its standard output and error; fails
/// the test after two minutes.
fn chromium(profile: &Path, url: &str, args: &[String]) -> (String, String) {
    let mut child = Command::new("chromium")
        .args([
            "--headless=new",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--allow-file-access-from-files",
            "--enable-logging=stderr",
            "--hide-scrollbars",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(args)
        .arg(url)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("chromium did not finish on {url} in two minutes");
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "chromium on {url}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn the_pages_work_in_a_browser_from_disk() {
    let probe = Command::new("chromium")
        .arg("--version")
        .output()
        .map_err(|e| format!("chromium: {e}"))
        .and_then(|o| {
            if o.status.success() {
                Ok(())
            } else {
                Err(format!("chromium --version: {}", o.status))
            }
        });
    if available(&BROWSER, probe, |_| true).is_none() {
        return;
    }
    let r = runs();
    // The comparison page next to the runs.
    let c = compare(
        &[Run::open(&r.a).unwrap(), Run::open(&r.b).unwrap()],
        &CompareOptions::default(),
    )
    .unwrap();
    std::fs::write(r.root.join("compare.html"), c.to_html(&r.root)).unwrap();
    let shots = Path::new(env!("CARGO_TARGET_TMPDIR")).join("../report-screenshots");
    std::fs::create_dir_all(&shots).unwrap();
    let profile = tempfile::tempdir().unwrap();
    let pages = [
        (
            "overview",
            r.a.join("report/index.html"),
            vec![
                "id=\"summary\"",
                "class=\"chart\"",
                "id=\"scenes\"",
                "<span id=\"shown\">4</span>",
            ],
        ),
        (
            "scene_8",
            r.a.join("report/scenes/scene_8.html"),
            vec![
                "id=\"topview\"",
                "class=\"navigable\"",
                "data-object=\"idx0_fixture.wardrobe\"",
                "id=\"specs-oor\"",
            ],
        ),
        (
            "compare",
            r.root.join("compare.html"),
            vec!["id=\"runs\"", "id=\"values-0\"", "id=\"differences\""],
        ),
    ];
    for (name, path, expected) in pages {
        let url = format!("file://{}", path.canonicalize().unwrap().display());
        let (dom, log) = chromium(profile.path(), &url, &["--dump-dom".to_owned()]);
        // The page's script ran to its end and saw no error.
        let root = dom.lines().find(|l| l.starts_with("<html")).unwrap_or_default();
        assert!(
            root.contains("data-script=\"ok\""),
            "{name}: the script did not finish: {root}\n{log}"
        );
        assert!(!root.contains("data-script-error"), "{name}: {root}");
        assert!(!log.contains("Uncaught"), "{name}: {log}");
        for e in expected {
            assert!(dom.contains(e), "{name}: {e} is missing from the DOM");
        }
        let shot = shots.join(format!("{name}.png"));
        let _ = std::fs::remove_file(&shot);
        chromium(
            profile.path(),
            &url,
            &[
                format!("--screenshot={}", shot.display()),
                "--window-size=1280,1600".to_owned(),
            ],
        );
        assert!(
            std::fs::metadata(&shot).map(|m| m.len() > 1000).unwrap_or(false),
            "{name}: no screenshot"
        );
    }
}

/// A headless chromium with a 1400 x 1000 px window.
fn browser_1400(chromium: PathBuf, profile: &Path) -> headless_chrome::Browser {
    let user_data = format!("--user-data-dir={}", profile.display());
    headless_chrome::Browser::new(
        headless_chrome::LaunchOptions::default_builder()
            .path(Some(chromium))
            .headless(true)
            .sandbox(false)
            .window_size(Some((1400, 1000)))
            .args(vec![
                std::ffi::OsStr::new(&user_data),
                std::ffi::OsStr::new("--no-first-run"),
                std::ffi::OsStr::new("--allow-file-access-from-files"),
            ])
            .idle_browser_timeout(Duration::from_secs(60))
            .build()
            .unwrap(),
    )
    .unwrap()
}

/// Opens `path` in a new tab and returns what `script` (an expression giving a JSON string)
/// evaluates to, parsed.
fn measure(browser: &headless_chrome::Browser, path: &Path, script: &str) -> serde_json::Value {
    let tab = browser.new_tab().unwrap();
    tab.set_default_timeout(Duration::from_secs(30));
    let url = format!("file://{}", path.canonicalize().unwrap().display());
    tab.navigate_to(&url).unwrap().wait_until_navigated().unwrap();
    let value = tab.evaluate(script, false).unwrap().value.unwrap();
    serde_json::from_str(value.as_str().unwrap()).unwrap()
}

/// Per `div.wide` table: whether it is wider than its container, the container's overflow,
/// and, scrolled to its right end, whether the last heading lies inside the container and the
/// first one is still in view; the page's own width.
const WIDE_TABLES: &str = r#"(() => {
  const tables = [];
  for (const div of document.querySelectorAll("div.wide")) {
    const table = div.querySelector("table");
    if (!table || !table.tHead) { continue; }
    const heads = table.tHead.rows[0].cells;
    const box = div.getBoundingClientRect();
    const scrolls = div.scrollWidth > div.clientWidth + 1;
    div.scrollLeft = div.scrollWidth;
    const first = heads[0].getBoundingClientRect();
    const last = heads[heads.length - 1].getBoundingClientRect();
    tables.push({
      id: table.id || table.className,
      scrolls: scrolls,
      overflow: getComputedStyle(div).overflowX,
      last_reachable: last.right <= box.right + 1 && last.left >= box.left - 1,
      first_in_view: first.left >= box.left - 1 && first.right <= box.right + 1,
      inside_window: box.right <= window.innerWidth + 1
    });
    div.scrollLeft = 0;
  }
  return JSON.stringify({ tables: tables, page: document.documentElement.scrollWidth, window: window.innerWidth });
})()"#;

/// At a 1400 px window no column of a wide table is cut off: the page is no wider than the
/// window, every table wider than its container scrolls inside it with its last heading
/// reachable, and its first column (the row's name) stays in view when scrolled.
#[test]
fn wide_tables_stay_readable_at_1400_px() {
    let Some(chromium) = system_chromium() else { return };
    let r = runs();
    let profile = tempfile::tempdir().unwrap();
    let browser = browser_1400(chromium, profile.path());
    let mut scrolled = 0;
    for page in [
        r.a.join("report/index.html"),
        r.a.join("report/scenes/scene_8.html"),
    ] {
        let m = measure(&browser, &page, WIDE_TABLES);
        assert_eq!(m["window"], 1400, "{m}");
        assert!(
            m["page"].as_u64().unwrap() <= 1400,
            "{}: the page is wider than the window: {m}",
            page.display()
        );
        for t in m["tables"].as_array().unwrap() {
            assert_eq!(t["inside_window"], true, "{t}");
            if t["scrolls"] == true {
                scrolled += 1;
                assert_eq!(t["overflow"], "auto", "{t}");
                assert_eq!(t["last_reachable"], true, "{t}");
                assert_eq!(t["first_in_view"], true, "the first column scrolled away: {t}");
            }
        }
    }
    // The overview's scene table has every metric column: wider than the page's column.
    assert!(scrolled > 0, "no table was wide enough to test");
}

/// A `file://` URL's path, percent-decoded.
fn file_url_path(url: &str) -> PathBuf {
    let raw = url.strip_prefix("file://").unwrap_or_else(|| panic!("{url}"));
    let bytes = raw.as_bytes();
    let mut out = Vec::new();
    let mut k = 0;
    while k < bytes.len() {
        if bytes[k] == b'%' && k + 2 < bytes.len() {
            out.push(u8::from_str_radix(&raw[k + 1..k + 3], 16).unwrap());
            k += 3;
        } else {
            out.push(bytes[k]);
            k += 1;
        }
    }
    PathBuf::from(String::from_utf8(out).unwrap())
}

/// The compare page's per-scene differences of each pair, in the browser: sorted by size,
/// each value linking to an existing scene page of its run.
#[test]
fn the_compare_page_lists_scene_differences_by_size_with_working_links() {
    let Some(chromium) = system_chromium() else { return };
    let r = runs();
    let options = CompareOptions {
        paired: Some(sceneeval_report::compare::Pairing::All),
        ..CompareOptions::default()
    };
    let c = compare(&[Run::open(&r.a).unwrap(), Run::open(&r.b).unwrap()], &options).unwrap();
    let page = r.root.join("compare-paired.html");
    std::fs::write(&page, c.to_html(&r.root)).unwrap();
    let profile = tempfile::tempdir().unwrap();
    let browser = browser_1400(chromium, profile.path());
    let m = measure(
        &browser,
        &page,
        r#"(() => JSON.stringify(Array.prototype.map.call(document.querySelectorAll("table.scene-differences tbody tr"), tr => ({
            scene: tr.getAttribute("data-scene"),
            diff: parseFloat(tr.cells[4].getAttribute("data-v")),
            links: Array.prototype.map.call(tr.querySelectorAll("a"), a => a.href)
        }))))()"#,
    );
    let rows = m.as_array().unwrap();
    assert!(!rows.is_empty(), "no scene differences: {m}");
    let sizes: Vec<f64> = rows.iter().map(|r| r["diff"].as_f64().unwrap().abs()).collect();
    assert!(
        sizes.windows(2).all(|w| w[0] >= w[1]),
        "not sorted by size: {sizes:?}"
    );
    assert!(sizes.iter().all(|s| *s > 0.0), "{sizes:?}");
    for row in rows {
        let links = row["links"].as_array().unwrap();
        // Both runs have a report: a link to each run's page of the scene.
        assert_eq!(links.len(), 2, "{row}");
        let scene = row["scene"].as_str().unwrap();
        for (link, run) in links.iter().zip([&r.a, &r.b]) {
            let path = file_url_path(link.as_str().unwrap());
            assert!(path.is_file(), "{} does not exist", path.display());
            assert_eq!(
                path.canonicalize().unwrap(),
                run.join(format!("report/scenes/{scene}.html"))
                    .canonicalize()
                    .unwrap()
            );
        }
    }
}

/// `sceneeval report RUN --labels LABELS`: two people agree with method-a on every spec but
/// scene 8's CNT `eq,2,chair`, which the run says is not satisfied and both say is. The
/// overview shows the table `agreement` computes for the same labels and run (one `ft` item of
/// the run's, agreement (n - 1) / n); scene 8's page marks that spec, scene 2's marks none; a
/// report without labels has no such section; in a browser the mark shows.
#[test]
fn a_report_with_labels_shows_the_agreement_and_marks_disagreements() {
    use sceneeval_fidelity::FidelityMetric;
    use sceneeval_report::agreement::RowKind;
    use sceneeval_report::labels::LabelFile;
    use sceneeval_report::{AgreementOptions, Source, agreement};

    let r = runs();
    let run = Run::open(&r.a).unwrap();
    let mut text = String::new();
    for record in &run.records {
        let Some(f) = record.report().and_then(|x| x.fidelity.as_ref()) else {
            continue;
        };
        for metric in FidelityMetric::ALL {
            for (index, (spec, v)) in f.verdicts(metric).into_iter().enumerate() {
                let Some(v) = v else { continue };
                let v = if record.scene.as_str() == "scene_8" && spec == "eq,2,chair" {
                    !v
                } else {
                    v
                };
                for who in ["alice", "bob"] {
                    text.push_str(&format!(
                        "{{\"scene\": \"{}\", \"metric\": \"{}\", \"index\": {index}, \"spec\": \"{spec}\", \
                         \"satisfied\": {v}, \"annotator\": \"{who}\"}}\n",
                        record.scene.as_str(),
                        metric.name()
                    ));
                }
            }
        }
    }
    let labels = LabelFile::from_jsonl_str(Path::new("people.jsonl"), &text).unwrap();
    let options = AgreementOptions::default();
    let with = run
        .clone()
        .with_labels(std::slice::from_ref(&labels), &options)
        .unwrap();
    let table = agreement(&[labels], &[Source::Run(run)], &options).unwrap();
    assert_eq!(with.labels(), Some(&table));
    let all = table
        .rows
        .iter()
        .find(|row| row.kind == RowKind::Judge && row.metric == "all")
        .unwrap();
    assert_eq!((all.tf, all.ft), (Some(0), Some(1)));
    let out = r.root.join("report-labels");
    write_report(&with, &out, &r.options("method-a")).unwrap();
    let index = read(&out.join("index.html"));
    assert!(index.contains("id=\"agreement\""), "{index}");
    let pct = format!("<td class=\"num\">{:.1}</td>", all.agreement.unwrap() * 100.0);
    assert!(index.contains(&pct), "{pct} in {index}");
    assert!(
        index.contains("Specs where the run and the people disagree (1)"),
        "{index}"
    );
    assert!(
        index.contains("<a href=\"scenes/scene_8.html\">scene_8</a>, CNT"),
        "{index}"
    );
    let s8 = read(&out.join("scenes/scene_8.html"));
    assert!(
        s8.contains("<tr class=\"disagree\">")
            && s8.contains("<code>eq,2,chair</code></td><td>not satisfied</td><td>satisfied</td>"),
        "{s8}"
    );
    let s2 = read(&out.join("scenes/scene_2.html"));
    assert!(
        s2.contains("No spec of this scene where the run and the people disagree."),
        "{s2}"
    );
    assert!(!read(&r.a.join("report/index.html")).contains("id=\"labels\""));

    let probe = Command::new("chromium")
        .arg("--version")
        .output()
        .map_err(|e| format!("chromium: {e}"));
    if available(&BROWSER, probe.map(|_| ()), |_| true).is_none() {
        return;
    }
    let profile = tempfile::tempdir().unwrap();
    let url = format!(
        "file://{}",
        out.join("scenes/scene_8.html").canonicalize().unwrap().display()
    );
    let (dom, log) = chromium(profile.path(), &url, &["--dump-dom".to_owned()]);
    assert!(dom.contains("data-script=\"ok\""), "{log}");
    assert!(
        dom.contains("<tr class=\"disagree\">"),
        "the mark is missing from the DOM"
    );
}
