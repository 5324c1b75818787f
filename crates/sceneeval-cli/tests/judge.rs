//! `sceneeval judge`: the items of a run of fixture scenes 2 and 8 (the full plan without a
//! VLM), the sample, blind and shown verdicts, resuming, a second judge on the same label file
//! refused, the top view and the object views served; and the page driven in headless
//! Chromium when it is installed (`SCENEEVAL_REQUIRE_BROWSER=1` makes a missing browser a
//! failure): a verdict clicked and one typed land in the label file.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::LazyLock;
use std::time::Duration;

use common::page::{PageProcess, token_in};
use serde_json::{Value, json};

/// The run, its scene folder and its annotations, made once for every test of this file.
struct Fixture {
    run: PathBuf,
    scenes: PathBuf,
    annotations: PathBuf,
    _keep: tempfile::TempDir,
}

static FIXTURE: LazyLock<Fixture> = LazyLock::new(|| {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("judge");
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let (keep, scenes, annotations) = common::scenes_2_and_8(sceneeval_test_support::fidelity_model::CSV);
    let run = root.join("run");
    common::evaluate(
        &scenes,
        &common::fixtures().join("assets"),
        &run,
        &["--annotations", annotations.to_str().unwrap(), "--plan", "full"],
    )
    .success();
    Fixture {
        run,
        scenes,
        annotations,
        _keep: keep,
    }
});

/// Every spec of the run, in the judge's order: (scene, metric, index, text, run's verdict).
fn run_specs() -> Vec<(String, String, usize, String, Option<bool>)> {
    let mut out = Vec::new();
    for scene in ["scene_2", "scene_8"] {
        let record = common::record(&FIXTURE.run, scene);
        for metric in ["cnt", "atr", "oor", "oar"] {
            let Some(specs) = record["report"]["fidelity"][metric]["specs"].as_array() else {
                continue;
            };
            for (k, spec) in specs.iter().enumerate() {
                let text = spec["spec"].as_str().unwrap().to_owned();
                out.push((
                    scene.to_owned(),
                    metric.to_owned(),
                    k,
                    text,
                    spec["satisfied"].as_bool(),
                ));
            }
        }
    }
    out
}

/// A running `sceneeval judge RUN --no-open ...`, killed when dropped.
struct Judge(PageProcess);

impl std::ops::Deref for Judge {
    type Target = PageProcess;
    fn deref(&self) -> &PageProcess {
        &self.0
    }
}

fn judge_command(out: &Path, extra: &[&str]) -> Command {
    judge_command_on(&FIXTURE.run, out, extra)
}

/// `sceneeval judge RUN` with the fixture's scenes, assets and annotations.
fn judge_command_on(run: &Path, out: &Path, extra: &[&str]) -> Command {
    let assets = format!("fixture={}", common::fixtures().join("assets").display());
    let mut command = Command::new(assert_cmd::cargo::cargo_bin("sceneeval"));
    command
        .arg("judge")
        .arg(run)
        .args([
            "--annotator",
            "alice",
            "--no-open",
            "--assets",
            &assets,
            "--scenes",
        ])
        .arg(&FIXTURE.scenes)
        .arg("--annotations")
        .arg(&FIXTURE.annotations)
        .arg("--out")
        .arg(out)
        .args(extra);
    command
}

impl Judge {
    fn start(out: &Path, extra: &[&str]) -> Judge {
        Judge::spawn(judge_command(out, extra))
    }

    fn spawn(command: Command) -> Judge {
        Judge(PageProcess::spawn(command))
    }

    /// Sends a request and reads the response: status, content type, body bytes.
    fn raw(&self, head: &str, body: &str) -> (u16, String, Vec<u8>) {
        let request = format!(
            "{head}\r\nHost: 127.0.0.1:{}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
            self.port,
            body.len()
        );
        let mut stream = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        stream.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        stream.write_all(request.as_bytes()).unwrap();
        let mut response = Vec::new();
        stream.read_to_end(&mut response).unwrap();
        let split = response.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
        let head = String::from_utf8_lossy(&response[..split]).into_owned();
        let status = head.split(' ').nth(1).unwrap().parse().unwrap();
        let kind = head
            .lines()
            .find_map(|l| {
                l.to_ascii_lowercase()
                    .strip_prefix("content-type: ")
                    .map(str::to_owned)
            })
            .unwrap_or_default();
        (status, kind, response[split + 4..].to_vec())
    }

    fn token(&self) -> String {
        let (status, _, page) = self.raw("GET / HTTP/1.1", "");
        assert_eq!(status, 200);
        token_in(&String::from_utf8(page).unwrap())
    }

    fn get(&self, token: &str, path: &str) -> (u16, String, Vec<u8>) {
        self.raw(&format!("GET {path} HTTP/1.1\r\nX-Sceneeval-Token: {token}"), "")
    }

    fn items(&self, token: &str) -> Value {
        let (status, _, body) = self.get(token, "/api/items");
        assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
        serde_json::from_slice(&body).unwrap()
    }

    fn verdict(&self, token: &str, item: usize, satisfied: Value) -> Value {
        let (status, _, body) = self.raw(
            &format!(
                "POST /api/verdict HTTP/1.1\r\nX-Sceneeval-Token: {token}\r\nContent-Type: application/json"
            ),
            &json!({"item": item, "satisfied": satisfied}).to_string(),
        );
        assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
        serde_json::from_slice(&body).unwrap()
    }

    /// Ctrl-C, then the rest of standard output (the process ended well).
    fn interrupt(self) -> String {
        let (status, rest) = self.0.interrupt();
        assert!(status.success());
        rest
    }
}

/// (scene, metric, index, spec) of the page's items.
fn keys(items: &Value) -> Vec<(String, String, usize, String)> {
    items["items"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| {
            (
                i["scene"].as_str().unwrap().to_owned(),
                i["metric"].as_str().unwrap().to_owned(),
                usize::try_from(i["index"].as_u64().unwrap()).unwrap(),
                i["spec"].as_str().unwrap().to_owned(),
            )
        })
        .collect()
}

fn lines(path: &Path) -> Vec<Value> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn the_items_are_the_runs_specs_in_order_blind_unless_asked() {
    let specs = run_specs();
    // CNT, OOR and OAR of both scenes, and ATR's specs (not judged without a VLM, but people
    // can judge them).
    assert!(specs.len() > 21, "{specs:?}");
    let dir = tempfile::tempdir().unwrap();
    let judge = Judge::start(&dir.path().join("labels.jsonl"), &[]);
    assert!(
        judge
            .first_line
            .contains(&format!("({} specs, 0 judged by alice", specs.len())),
        "{}",
        judge.first_line
    );
    let token = judge.token();
    let items = judge.items(&token);
    let expected: Vec<(String, String, usize, String)> = specs
        .iter()
        .map(|(s, m, k, t, _)| (s.clone(), m.clone(), *k, t.clone()))
        .collect();
    assert_eq!(keys(&items), expected);
    assert_eq!(
        (items["judged"].as_u64(), items["total"].as_u64()),
        (Some(0), Some(specs.len() as u64))
    );
    // The description of each scene from its annotation row.
    let description = items["descriptions"]["scene_2"].as_str().unwrap();
    assert!(
        sceneeval_test_support::fidelity_model::CSV.contains(description),
        "{description}"
    );
    // Blind: no item carries the run's verdict, and no response names it.
    let text = items.to_string();
    assert!(!text.contains("run_verdict"), "{text}");
    // The spec in words, and the objects it names.
    let first = &items["items"][0];
    assert_ne!(first["words"], first["spec"]);
    assert!(!first["objects"].as_array().unwrap().is_empty(), "{first}");
    // The top view: an SVG with the spec's objects outlined.
    let (status, kind, svg) = judge.get(&token, "/api/topview?item=0");
    assert_eq!(
        (status, kind.as_str()),
        (200, "image/svg+xml"),
        "{}",
        String::from_utf8_lossy(&svg)
    );
    let svg = String::from_utf8(svg).unwrap();
    let object = first["objects"][0].as_str().unwrap();
    assert!(
        svg.contains(&format!("class=\"outline\" data-object=\"{object}\"")),
        "{svg}"
    );
    // An object the item does not name, and a view that is not the VLM's, are refused.
    let (status, _, _) = judge.get(&token, "/api/view?item=0&object=nope&kind=front");
    assert_eq!(status, 404);
    let (status, _, _) = judge.get(&token, &format!("/api/view?item=0&object={object}&kind=top"));
    assert_eq!(status, 400);
    // The object views, rendered on demand (the run kept none: it had no VLM).
    if common::renderer().is_some() {
        let (status, kind, png) = judge.get(&token, &format!("/api/view?item=0&object={object}&kind=front"));
        assert_eq!(
            (status, kind.as_str()),
            (200, "image/png"),
            "{}",
            String::from_utf8_lossy(&png)
        );
        assert_eq!(&png[1..4], b"PNG");
        let (status, _, size) = judge.get(&token, &format!("/api/view?item=0&object={object}&kind=size"));
        assert_eq!(status, 200);
        assert_ne!(png, size);
    }
    drop(judge);
    // --show-verdicts: each item carries the run's verdict.
    let shown = Judge::start(&dir.path().join("labels.jsonl"), &["--show-verdicts"]);
    let token = shown.token();
    let items = shown.items(&token);
    for (item, spec) in items["items"].as_array().unwrap().iter().zip(&specs) {
        let expected = match spec.4 {
            Some(true) => "satisfied",
            Some(false) => "not satisfied",
            None => "undecided",
        };
        assert_eq!(item["run_verdict"], expected, "{item}");
    }
}

#[test]
fn metrics_and_a_seeded_sample_choose_the_items() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("labels.jsonl");
    let items_of = |extra: &[&str]| {
        let judge = Judge::start(&out, extra);
        let token = judge.token();
        keys(&judge.items(&token))
    };
    let oor = items_of(&["--metrics", "oor,OAR"]);
    assert!(!oor.is_empty());
    assert!(oor.iter().all(|k| k.1 == "oor" || k.1 == "oar"), "{oor:?}");
    let expected: Vec<_> = run_specs()
        .into_iter()
        .filter(|s| s.1 == "oor" || s.1 == "oar")
        .map(|(s, m, k, t, _)| (s, m, k, t))
        .collect();
    assert_eq!(oor, expected);
    // One scene of two, drawn with seed 7: the documented rule's choice, every time.
    let scenes = ["scene_2", "scene_8"];
    for seed in [7u64, 8] {
        let chosen = scenes[sceneeval::stats::sample::sample(2, 1, seed)[0]];
        let sampled = items_of(&["--sample", "1", "--seed", &seed.to_string()]);
        assert!(!sampled.is_empty());
        assert!(sampled.iter().all(|k| k.0 == chosen), "{seed}: {sampled:?}");
        assert_eq!(sampled, items_of(&["--sample", "1", "--seed", &seed.to_string()]));
    }
    // N at least the number of scenes: every scene.
    assert_eq!(items_of(&["--sample", "5"]), items_of(&[]));
    // A bad metric and --seed without --sample are refused before anything starts.
    let out_of = |extra: &[&str]| judge_command(&out, extra).output().unwrap();
    let bad = out_of(&["--metrics", "size"]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("unknown fidelity metric \"size\""));
    assert!(!out_of(&["--seed", "3"]).status.success());
}

#[test]
fn verdicts_are_appended_at_once_and_a_second_session_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("labels.jsonl");
    let specs = run_specs();
    let judge = Judge::start(&out, &[]);
    let token = judge.token();
    assert_eq!(
        judge.verdict(&token, 0, json!(true)),
        json!({"judged": 1, "total": specs.len()})
    );
    // On disk at once, while the page runs.
    let written = lines(&out);
    assert_eq!(
        written,
        [
            json!({"scene": specs[0].0, "metric": specs[0].1, "index": specs[0].2, "spec": specs[0].3,
                "satisfied": true, "annotator": "alice"})
        ]
    );
    judge.verdict(&token, 1, Value::Null);
    judge.verdict(&token, 0, json!(false));
    // A second judge on the same label file is refused while this one runs, naming the file.
    let second = judge_command(&out, &[]).output().unwrap();
    assert!(!second.status.success());
    let err = String::from_utf8_lossy(&second.stderr);
    assert!(err.contains(&out.display().to_string()), "{err}");
    assert!(
        err.contains("another sceneeval judge is writing this label file"),
        "{err}"
    );
    let (status, _, _) = judge.raw(
        &format!(
            "POST /api/verdict HTTP/1.1\r\nX-Sceneeval-Token: {token}\r\nContent-Type: application/json"
        ),
        &json!({"item": specs.len(), "satisfied": true}).to_string(),
    );
    assert_eq!(status, 404);
    let rest = judge.interrupt();
    assert!(
        rest.contains(&format!(
            "stopped: 2 of {} specs judged by alice; 3 verdicts written",
            specs.len()
        )),
        "{rest}"
    );
    assert_eq!(lines(&out).len(), 3);
    // The next session knows what alice judged (her changed mind on item 0 in force).
    let judge = Judge::start(&out, &[]);
    assert!(
        judge
            .first_line
            .contains(&format!("({} specs, 2 judged by alice", specs.len())),
        "{}",
        judge.first_line
    );
    let token = judge.token();
    let items = judge.items(&token);
    assert_eq!(items["judged"], 2);
    assert_eq!(items["items"][0]["verdict"], false);
    assert_eq!(items["items"][1]["verdict"], Value::Null);
    assert!(items["items"][2].get("verdict").is_none());
    // The labels are the run's: agreement reads them against it.
    drop(judge);
    let agreement = assert_cmd::Command::cargo_bin("sceneeval")
        .unwrap()
        .arg("agreement")
        .arg(&FIXTURE.run)
        .arg(&out)
        .args(["--format", "csv", "--bootstrap", "0"])
        .assert()
        .success();
    let csv = String::from_utf8_lossy(&agreement.get_output().stdout).into_owned();
    assert!(csv.contains("alice"), "{csv}");
}

/// Copies the folder `from` into `to`, recursively.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

#[test]
fn the_views_the_run_kept_are_served_and_links_out_of_it_are_not_followed() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    copy_dir(&FIXTURE.run, &run);
    let judge = Judge::start(&dir.path().join("probe.jsonl"), &[]);
    let token = judge.token();
    let items = judge.items(&token);
    drop(judge);
    let first = &items["items"][0];
    let scene = first["scene"].as_str().unwrap();
    let object = first["objects"][0].as_str().unwrap();
    // The run's own front view (bytes no renderer makes), and a size view that is a link out
    // of the run folder.
    let views = run.join(scene).join("views");
    std::fs::create_dir_all(&views).unwrap();
    std::fs::write(
        views.join(format!("front_{object}.png")),
        b"the run's own front view",
    )
    .unwrap();
    let outside = dir.path().join("secret.png");
    std::fs::write(&outside, b"not the run's").unwrap();
    std::os::unix::fs::symlink(&outside, views.join(format!("size_{object}.png"))).unwrap();
    let judge = Judge::spawn(judge_command_on(&run, &dir.path().join("labels.jsonl"), &[]));
    let token = judge.token();
    let (status, kind, bytes) = judge.get(&token, &format!("/api/view?item=0&object={object}&kind=front"));
    assert_eq!((status, kind.as_str()), (200, "image/png"));
    assert_eq!(bytes, b"the run's own front view");
    // The link is not read: the view is rendered instead (or refused without a renderer).
    let (status, _, bytes) = judge.get(&token, &format!("/api/view?item=0&object={object}&kind=size"));
    assert_ne!(bytes, b"not the run's");
    if common::renderer().is_some() {
        assert_eq!(status, 200);
        assert_eq!(&bytes[1..4], b"PNG");
    }
}

/// Waits until `check` holds, for at most 60 seconds.
fn wait_for(what: &str, check: impl FnMut() -> bool) {
    common::page::wait_for(what, Duration::from_secs(60), check);
}

mod browser {
    use headless_chrome::Tab;

    use super::*;

    /// The page in headless Chromium, and every error it reports.
    fn open(
        chromium: PathBuf,
        url: &str,
        profile: &Path,
    ) -> (
        headless_chrome::Browser,
        std::sync::Arc<Tab>,
        std::sync::Arc<std::sync::Mutex<Vec<String>>>,
    ) {
        common::browser::open(chromium, url, profile, Duration::from_secs(60))
    }

    fn text(tab: &Tab, selector: &str) -> String {
        tab.find_element(selector)
            .and_then(|e| e.get_inner_text())
            .unwrap_or_default()
    }

    #[test]
    fn a_verdict_clicked_and_one_typed_land_in_the_file_blind() {
        let Some(chromium) = sceneeval_test_support::system::chromium() else {
            return;
        };
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("labels.jsonl");
        let specs = run_specs();
        let judge = Judge::start(&out, &[]);
        let profile = tempfile::tempdir().unwrap();
        let (_browser, tab, errors) = open(chromium.clone(), &judge.url(), profile.path());
        wait_for("the first spec", || text(&tab, "#where").starts_with("Spec 1 of"));
        assert_eq!(text(&tab, "#progress"), format!("0 / {} judged", specs.len()));
        assert_eq!(text(&tab, "#spec"), format!("as annotated: {}", specs[0].3));
        assert!(!text(&tab, "#description").is_empty());
        // Blind: the run's verdict is nowhere on the page.
        let body = text(&tab, "body");
        assert!(!body.contains("The run's verdict"), "{body}");
        // The top view is shown (an image made of the SVG the server drew).
        wait_for("the top view", || {
            tab.evaluate("document.getElementById('topview').naturalWidth > 0", false)
                .is_ok_and(|r| r.value == Some(json!(true)))
        });
        // A click: satisfied, on disk at once; the page moves on.
        tab.wait_for_element("#yes").unwrap().click().unwrap();
        wait_for("the clicked verdict", || out.exists() && lines(&out).len() == 1);
        assert_eq!(lines(&out)[0]["satisfied"], true);
        assert_eq!(lines(&out)[0]["spec"], specs[0].3.as_str());
        wait_for("the second spec", || {
            text(&tab, "#where").starts_with("Spec 2 of")
        });
        // A key: n is not satisfied.
        tab.press_key("n").unwrap();
        wait_for("the typed verdict", || lines(&out).len() == 2);
        assert_eq!(lines(&out)[1]["satisfied"], false);
        assert_eq!(lines(&out)[1]["spec"], specs[1].3.as_str());
        assert_eq!(lines(&out)[1]["index"], specs[1].2);
        wait_for("the progress", || {
            text(&tab, "#progress") == format!("2 / {} judged", specs.len())
        });
        // Back to the first: the page shows the verdict given.
        tab.press_key("b").unwrap();
        tab.press_key("b").unwrap();
        wait_for("the first spec again", || {
            text(&tab, "#where").starts_with("Spec 1 of")
        });
        assert!(text(&tab, "#your-verdict").starts_with("Your verdict: satisfied"));
        if common::renderer().is_some() {
            wait_for("an object view", || {
                tab.evaluate(
                    "Array.from(document.querySelectorAll('#views img')).some(i => i.naturalWidth > 0)",
                    false,
                )
                .is_ok_and(|r| r.value == Some(json!(true)))
            });
        }
        let errors = errors.lock().unwrap().clone();
        assert!(errors.is_empty(), "{errors:?}");
        drop(judge);
        // With --show-verdicts the run's verdict is on the page; the page resumes at the
        // first spec not judged (the third).
        let shown = Judge::start(&out, &["--show-verdicts"]);
        let profile = tempfile::tempdir().unwrap();
        let (_browser, tab, _) = open(chromium, &shown.url(), profile.path());
        wait_for("the third spec", || text(&tab, "#where").starts_with("Spec 3 of"));
        let expected = match specs[2].4 {
            Some(true) => "satisfied",
            Some(false) => "not satisfied",
            None => "undecided",
        };
        assert_eq!(
            text(&tab, "#run-verdict"),
            format!("The run's verdict: {expected}")
        );
    }
}
