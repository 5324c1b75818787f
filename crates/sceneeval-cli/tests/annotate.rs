//! `sceneeval annotations annotate|generate` against a mock chat-completions server on
//! 127.0.0.1 (`sceneeval_test_support::mock_endpoint`): good answers, answers with findings
//! (fixed on the re-ask, or rejected), refusals, near duplicates, and a resumed run.

#![allow(clippy::unwrap_used)]

mod common;

use std::path::Path;
use std::time::Duration;

use assert_cmd::Command;
use predicates::prelude::*;
use sceneeval_test_support::mock_endpoint::{MockEndpoint, Reply, completion, task_of, user_text};
use serde_json::{Value, json};

/// The key the tests send: it must reach no file and no output.
const SECRET: &str = "sk-annotate-test-secret-0123456789";

fn row(description: &str, difficulty: &str, counts: &[&str], attrs: &[&str], oa: &[&str]) -> Value {
    json!({"description": description, "difficulty": difficulty, "obj_count": counts, "obj_attr": attrs,
           "oo_rel": [], "oa_rel": oa})
}

fn refusal() -> Reply {
    let body = json!({
        "id": "chatcmpl-mock", "object": "chat.completion", "model": "mock",
        "choices": [{"index": 0, "message": {"role": "assistant", "content": null,
                     "refusal": "I cannot help with that."}, "finish_reason": "stop"}],
        "usage": {"prompt_tokens": 10, "completion_tokens": 5, "total_tokens": 15}
    });
    Reply {
        status: 200,
        headers: Vec::new(),
        body: body.to_string(),
    }
}

/// A server answering the n-th request with `answers[n]` (a refusal for `Value::Null`).
fn server(answers: Vec<Value>) -> MockEndpoint {
    MockEndpoint::start(Duration::ZERO, move |n, _| match answers.get(n) {
        Some(Value::Null) | None => refusal(),
        Some(answer) => completion(answer),
    })
}

fn sceneeval(server: &MockEndpoint, args: &[&str]) -> Command {
    let mut cmd = Command::cargo_bin("sceneeval").unwrap();
    cmd.arg("annotations")
        .args(args)
        .args(["--vlm-base-url", &server.url(), "--vlm-model", "test-model"])
        .args(["--vlm-api-key-env", "ANNOTATE_TEST_KEY"])
        .env("ANNOTATE_TEST_KEY", SECRET);
    cmd
}

const DESCRIPTION: &str = "A bedroom with a bed against the wall and a wardrobe in the corner.";

fn good() -> Value {
    row(
        DESCRIPTION,
        "easy",
        &["eq,1,bed", "eq,1,wardrobe"],
        &[],
        &["eq,1,against,bed,wall", "eq,1,corner,wardrobe,room"],
    )
}

#[test]
fn annotate_prints_a_row_that_check_and_evaluate_accept() {
    let server = server(vec![good()]);
    let out = sceneeval(
        &server,
        &["annotate", DESCRIPTION, "--difficulty", "easy", "--id", "2"],
    )
    .assert()
    .success();
    let csv = String::from_utf8(out.get_output().stdout.clone()).unwrap();
    assert_eq!(
        csv,
        format!(
            "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n2,easy,{DESCRIPTION},\"eq,1,bed; eq,1,wardrobe\",,,\
             \"eq,1,against,bed,wall; eq,1,corner,wardrobe,room\"\n"
        )
    );
    let bodies = server.bodies();
    assert_eq!(bodies.len(), 1);
    assert_eq!(task_of(&bodies[0]), "annotate_description");
    assert!(
        bodies[0]["messages"][0]["content"]
            .as_str()
            .unwrap()
            .starts_with("You are tasked to generate annotations for scenes given a text description")
    );
    assert_eq!(
        bodies[0]["response_format"]["json_schema"]["schema"]["required"],
        json!([
            "description",
            "difficulty",
            "obj_count",
            "obj_attr",
            "oo_rel",
            "oa_rel"
        ])
    );

    // `annotations check` accepts it, and `evaluate --annotations` reads it: scene 2 is in
    // the row's difficulty group.
    let (dir, scenes, rows) = common::scenes_2_and_8(&csv);
    Command::cargo_bin("sceneeval")
        .unwrap()
        .args(["annotations", "check"])
        .arg(&rows)
        .assert()
        .success()
        .stdout(predicate::str::contains("1 rows, 0 error(s), 0 warning(s)"));
    let run = dir.path().join("run");
    common::evaluate(
        &scenes,
        &common::fixtures().join("assets"),
        &run,
        &["--annotations", rows.to_str().unwrap(), "--plan", "OOB"],
    )
    .success();
    let summary = std::fs::read_to_string(run.join("summary.csv")).unwrap();
    assert!(summary.lines().any(|l| l.starts_with("easy,1,")), "{summary}");
}

#[test]
fn annotate_asks_again_once_with_the_findings() {
    // The first answer swaps attribute and category and names the wall "wal"; the second is
    // right.
    let bad = row(
        DESCRIPTION,
        "easy",
        &["eq,1,bed", "eq,1,wardrobe"],
        &["eq,1,large,wardrobe", "eq,1,wooden,bed"],
        &["eq,1,against,bed,wal"],
    );
    let server = server(vec![bad.clone(), good()]);
    sceneeval(&server, &["annotate", DESCRIPTION])
        .assert()
        .success()
        .stdout(predicate::str::contains("eq,1,against,bed,wall"));
    let second = user_text(&server.bodies()[1]).to_owned();
    assert!(
        second.contains("- the answer: unknown-arch-reference in OARel \"eq,1,against,bed,wal\""),
        "{second}"
    );
    assert!(second.contains("Your previous answer was:"));

    // Still with findings after the re-ask: rejected, with the findings, exit status 1.
    let server = self::server(vec![bad.clone(), bad]);
    sceneeval(&server, &["annotate", DESCRIPTION])
        .assert()
        .failure()
        .stdout("")
        .stderr(predicate::str::contains("\"reason\":\"findings\""))
        .stderr(predicate::str::contains("unknown-arch-reference"))
        .stderr(predicate::str::contains(SECRET).not());
    assert_eq!(server.requests(), 2);
}

#[test]
fn annotate_records_a_refusal_and_a_changed_description() {
    let server = server(vec![Value::Null]);
    sceneeval(&server, &["annotate", DESCRIPTION])
        .assert()
        .failure()
        .stderr(predicate::str::contains("\"reason\":\"refused\""))
        .stderr(predicate::str::contains("I cannot help with that."));
    assert_eq!(server.requests(), 1, "a refusal is not asked again");

    // The model rewrites the description twice: rejected.
    let rewritten = row("A bedroom.", "easy", &["eq,1,bed"], &[], &[]);
    let server = self::server(vec![rewritten.clone(), rewritten]);
    sceneeval(&server, &["annotate", DESCRIPTION])
        .assert()
        .failure()
        .stderr(predicate::str::contains("copy it word for word"));
}

#[test]
fn annotate_a_list_of_descriptions_then_check_and_continue() {
    let dir = tempfile::tempdir().unwrap();
    let list = dir.path().join("mine.txt");
    let other = "A kitchen with a fridge next to the stove.";
    std::fs::write(&list, format!("{DESCRIPTION}\n\n{other}\n")).unwrap();
    let out = dir.path().join("mine.csv");
    let out_arg = out.to_str().unwrap();
    // The first description is annotated (ID 3), the model refuses the second (ID 4).
    let server = server(vec![good(), Value::Null]);
    let args = [
        "annotate",
        "--descriptions",
        list.to_str().unwrap(),
        // -o: the short --out of every command that writes.
        "-o",
        out_arg,
        "--id",
        "3",
        "--difficulty",
        "easy",
        "--no-progress",
    ];
    let run = sceneeval(&server, &args)
        .assert()
        .failure()
        .stdout(predicate::str::contains(
            "1 rows (1 accepted now); 1 descriptions of 2 without a row",
        ))
        .stdout(predicate::str::contains("sceneeval annotations review"));
    let stderr = String::from_utf8(run.get_output().stderr.clone()).unwrap();
    assert!(stderr.contains("\"reason\":\"refused\""), "{stderr}");
    assert_eq!(server.requests(), 2);
    let csv = std::fs::read_to_string(&out).unwrap();
    assert!(csv.starts_with("ID,Difficulty,Description,"), "{csv}");
    assert!(csv.contains(&format!("3,easy,{DESCRIPTION},")), "{csv}");
    let rejected = std::fs::read_to_string(dir.path().join("mine.csv.rejected.jsonl")).unwrap();
    assert!(
        rejected.contains("\"id\":\"4\"") && rejected.contains("\"reason\":\"refused\""),
        "{rejected}"
    );
    Command::cargo_bin("sceneeval")
        .unwrap()
        .args(["annotations", "check", out_arg])
        .assert()
        .success();

    // A re-run asks again only for the refused description, and replaces its rejection.
    let kitchen = row(other, "easy", &["eq,1,fridge", "eq,1,stove"], &[], &[]);
    let server = self::server(vec![kitchen]);
    sceneeval(&server, &args)
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "2 rows (1 accepted now); 0 descriptions of 2 without a row",
        ));
    assert_eq!(server.requests(), 1);
    let rows = std::fs::read_to_string(&out).unwrap();
    assert_eq!(rows.lines().count(), 3, "{rows}");
    assert!(rows.contains(&format!("4,easy,{other},")), "{rows}");
    let rejected = std::fs::read_to_string(dir.path().join("mine.csv.rejected.jsonl")).unwrap();
    assert!(rejected.is_empty(), "{rejected}");
    for file in [&out, &dir.path().join("mine.csv.rejected.jsonl")] {
        assert!(!std::fs::read_to_string(file).unwrap().contains(SECRET));
    }

    // Bad lists are named.
    std::fs::write(&list, "\n").unwrap();
    sceneeval(&server, &args[..5])
        .assert()
        .failure()
        .stderr(predicate::str::contains("holds no description"));
    sceneeval(&server, &[&args[..5], &["--id", "x"]].concat())
        .assert()
        .failure()
        .stderr(predicate::str::contains("must be a non-negative integer"));
    Command::cargo_bin("sceneeval")
        .unwrap()
        .args(["annotations", "annotate", "--descriptions", "mine.txt"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("--out"));
}

fn examples(dir: &Path) -> std::path::PathBuf {
    let path = dir.join("examples.csv");
    std::fs::write(
        &path,
        "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
         40,easy,A bedroom with a bed and a wardrobe.,\"eq,1,bed; eq,1,wardrobe\",,,\n\
         41,easy,A kitchen with a fridge and a stove.,\"eq,1,fridge; eq,1,stove\",,,\n",
    )
    .unwrap();
    path
}

#[test]
fn annotate_draws_its_examples_with_the_seed() {
    // One example of the two easy rows, drawn with the seed as `generate` draws them: the
    // same seed shows the same one, and over seeds 0..8 both are shown.
    let dir = tempfile::tempdir().unwrap();
    let examples = examples(dir.path());
    let shown = |seed: &str| {
        let server = server(vec![good()]);
        sceneeval(
            &server,
            &[
                "annotate",
                DESCRIPTION,
                "--difficulty",
                "easy",
                "--examples",
                examples.to_str().unwrap(),
            ],
        )
        .args(["--examples-per-request", "1", "--seed", seed])
        .assert()
        .success();
        let text = user_text(&server.bodies()[0]).to_owned();
        assert!(text.contains("Here are 1 manually annotated examples"), "{text}");
        text.contains("A kitchen with a fridge")
    };
    let kitchen: Vec<bool> = (0..8).map(|seed| shown(&seed.to_string())).collect();
    assert!(kitchen.contains(&true) && kitchen.contains(&false), "{kitchen:?}");
    assert_eq!(shown("3"), kitchen[3]);
}

#[test]
fn generate_filters_near_duplicates_and_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let examples = examples(dir.path());
    let out = dir.path().join("generated.csv");
    let first = row(
        "A study with a desk and a chair facing it.",
        "easy",
        &["eq,1,desk", "eq,1,chair"],
        &[],
        &[],
    );
    // A near copy of example 40, then a refusal, then a new row.
    let near = row(
        "A bedroom with beds and a wardrobe.",
        "easy",
        &["eq,2,bed", "eq,1,wardrobe"],
        &[],
        &[],
    );
    let second = row(
        "A garage with a workbench.",
        "easy",
        &["eq,1,workbench"],
        &[],
        &[],
    );
    let server = server(vec![first, near, Value::Null, second.clone()]);
    let args = |count: &str| -> Vec<String> {
        [
            "generate",
            "--examples",
            examples.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--difficulty",
            "easy",
            "--no-progress",
            // The first ID, named as `annotate --id` names it (default: the examples' largest
            // ID plus one, 42).
            "--id",
            "142",
            "--count",
            count,
        ]
        .iter()
        .map(|s| (*s).to_owned())
        .collect()
    };
    let a = args("1");
    let a: Vec<&str> = a.iter().map(String::as_str).collect();
    sceneeval(&server, &a)
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "1 rows (1 accepted now, 0 already there)",
        ));
    // The run ended at its count, as if it had been interrupted there; a re-run with a larger
    // count continues: the near copy and the refusal are rejected, then ID 143 is accepted.
    let a = args("2");
    let a: Vec<&str> = a.iter().map(String::as_str).collect();
    sceneeval(&server, &a)
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "2 rows (1 accepted now, 1 already there), 2 rejected now",
        ))
        .stderr(predicate::str::contains("too_similar"));
    let written = std::fs::read_to_string(&out).unwrap();
    let ids: Vec<&str> = written
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(ids, ["142", "143"], "{written}");
    let rejected = std::fs::read_to_string(dir.path().join("generated.csv.rejected.jsonl")).unwrap();
    let lines: Vec<Value> = rejected
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[0]["reason"], "too_similar");
    assert_eq!(lines[0]["near_id"], "40");
    assert_eq!(lines[0]["score"], 1.0);
    assert_eq!(lines[1]["reason"], "refused");
    let bodies = server.bodies();
    assert_eq!(bodies.len(), 4);
    // The second run's first request names the row already written; the one after the near
    // copy asks for variety and names it.
    assert!(user_text(&bodies[1]).contains("\"A study with a desk and a chair facing it.\""));
    assert!(user_text(&bodies[2]).contains("rejected as too similar"));
    assert!(user_text(&bodies[2]).contains("\"A bedroom with beds and a wardrobe.\""));
    assert!(user_text(&bodies[0]).contains("Here are 2 manually annotated examples"));
    for body in &bodies {
        assert_eq!(task_of(body), "generate_annotated_description");
    }
    // A third run has nothing to do.
    sceneeval(&server, &a)
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "2 rows (0 accepted now, 2 already there)",
        ));
    assert_eq!(server.requests(), 4);
    for file in [&out, &dir.path().join("generated.csv.rejected.jsonl")] {
        assert!(!std::fs::read_to_string(file).unwrap().contains(SECRET));
    }
    Command::cargo_bin("sceneeval")
        .unwrap()
        .args(["annotations", "check"])
        .arg(&out)
        .assert()
        .success();
}

#[test]
fn generate_stops_after_its_candidate_limit() {
    let dir = tempfile::tempdir().unwrap();
    let examples = examples(dir.path());
    let out = dir.path().join("g.json");
    let server = server(vec![Value::Null, Value::Null]);
    sceneeval(
        &server,
        &[
            "generate",
            "--examples",
            examples.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--count",
            "1",
            "--max-candidates",
            "2",
            "--no-progress",
        ],
    )
    .assert()
    .failure()
    .stdout(predicate::str::contains("0 rows").and(predicate::str::contains("stopped after 2 candidates")));
    assert!(!out.exists(), "no row, no file");
    assert_eq!(server.requests(), 2);
}

#[test]
fn the_model_options_are_required() {
    Command::cargo_bin("sceneeval")
        .unwrap()
        .args(["annotations", "annotate", "A den."])
        .assert()
        .failure()
        .stderr(predicate::str::contains("pass --vlm-base-url and --vlm-model"));
}
