//! `sceneeval annotations check|stats` on the annotation fixtures (written into a temporary
//! folder by `sceneeval_fixtures::annotations::write_all`) and on small hand-made files.

use std::path::{Path, PathBuf};

use assert_cmd::cargo::cargo_bin_cmd;
use predicates::prelude::*;
use sceneeval_fixtures::annotations::{FILES, MALFORMED_FILE, PAPER_EXAMPLES_FILE, write_all};
use serde_json::Value;

const CODES: [&str; 25] = [
    "missing-id",
    "duplicate-id",
    "non-integer-id",
    "unknown-difficulty",
    "empty-description",
    "description-semicolon",
    "ragged-row",
    "unknown-quantifier",
    "bad-quantity",
    "wrong-field-count",
    "empty-name",
    "bad-anchor-index",
    "bad-reference",
    "undefined-category",
    "arch-as-object",
    "anchor-out-of-range",
    "non-atomic-attribute",
    "attribute-category-swapped",
    "duplicate-entry",
    "contradictory-counts",
    "attribute-exceeds-count",
    "relationship-exceeds-count",
    "unknown-arch-reference",
    "name-format",
    "difficulty-object-count",
];

fn fixtures() -> std::io::Result<(tempfile::TempDir, PathBuf, PathBuf)> {
    let dir = tempfile::tempdir()?;
    write_all(dir.path())?;
    for f in FILES {
        assert!(dir.path().join(f).is_file());
    }
    let paper = dir.path().join(PAPER_EXAMPLES_FILE);
    let malformed = dir.path().join(MALFORMED_FILE);
    Ok((dir, paper, malformed))
}

fn sceneeval(args: &[&str], file: &Path) -> assert_cmd::assert::Assert {
    cargo_bin_cmd!("sceneeval")
        .arg("annotations")
        .args(args)
        .arg(file)
        .assert()
}

/// What `sceneeval annotations ARGS FILE` prints on standard output, failing with status 1.
fn failure_stdout(args: &[&str], file: &Path) -> Vec<u8> {
    sceneeval(args, file)
        .failure()
        .code(1)
        .get_output()
        .stdout
        .clone()
}

#[test]
fn check_passes_on_the_paper_examples() {
    let (_dir, paper, _) = fixtures().unwrap();
    sceneeval(&["check"], &paper)
        .success()
        .stdout(predicate::str::contains("5 rows, 0 error(s), 1 warning(s)"))
        .stdout(predicate::str::contains(
            "warning[description-semicolon] row \"4\"",
        ));
}

#[test]
fn check_fails_on_the_malformed_rows_and_names_every_code() {
    let (_dir, _, malformed) = fixtures().unwrap();
    let text = String::from_utf8(failure_stdout(&["check"], &malformed)).unwrap();
    for code in CODES {
        assert!(text.contains(&format!("[{code}]")), "no {code} in:\n{text}");
    }
    assert!(text.contains("(suggestion: eq,1,bed,red)"), "{text}");
    assert!(text.lines().last().unwrap().contains("26 rows"), "{text}");
}

#[test]
fn check_json_is_one_document_with_every_finding() {
    let (_dir, _, malformed) = fixtures().unwrap();
    let report: Value = serde_json::from_slice(&failure_stdout(&["check", "--json"], &malformed)).unwrap();
    assert_eq!(report["rows"], 26);
    let findings = report["findings"].as_array().unwrap();
    let errors = findings.iter().filter(|f| f["severity"] == "error").count();
    let warnings = findings.iter().filter(|f| f["severity"] == "warning").count();
    assert_eq!(report["errors"], errors);
    assert_eq!(report["warnings"], warnings);
    assert!(errors > 0 && warnings > 0);
    for code in CODES {
        assert!(findings.iter().any(|f| f["code"] == code), "no {code}");
    }
    for f in findings {
        for key in ["code", "severity", "row", "row_index", "field", "message"] {
            assert!(!f[key].is_null(), "{key} missing in {f}");
        }
    }
    // The swapped entry of the data-generation prompt, located precisely.
    let swapped = findings
        .iter()
        .find(|f| f["code"] == "attribute-category-swapped")
        .unwrap();
    assert_eq!(swapped["row"], "18");
    assert_eq!(swapped["field"], "ObjAttr");
    assert_eq!(swapped["entry"], "eq,1,red,bed");
    assert_eq!(swapped["entry_index"], 0);
}

#[test]
fn check_reads_the_json_form() {
    let (dir, paper, _) = fixtures().unwrap();
    let json = dir.path().join("paper_examples.json");
    sceneeval_fixtures::annotations::paper_examples()
        .write_json(&json)
        .unwrap();
    sceneeval(&["check"], &json)
        .success()
        .stdout(predicate::str::contains("5 rows, 0 error(s)"));
    // Same statistics from both forms.
    let a = sceneeval(&["stats"], &paper)
        .success()
        .get_output()
        .stdout
        .clone();
    let b = sceneeval(&["stats"], &json).success().get_output().stdout.clone();
    assert_eq!(a, b);
}

#[test]
fn unreadable_files_are_reported() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nope.csv");
    sceneeval(&["check"], &missing)
        .failure()
        .stderr(predicate::str::contains("nope.csv"));
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "ID,Description\n0,A bed.\n").unwrap();
    sceneeval(&["check"], &bad)
        .failure()
        .stderr(predicate::str::contains("missing required column \"Difficulty\""));
    sceneeval(&["stats", "--json"], &bad).failure();
}

#[test]
fn stats_markdown_matches_hand_counts() {
    let (_dir, paper, _) = fixtures().unwrap();
    // Easy example: 27 words; ObjCount bed, wardrobe, desk (3 entries, 3 objects); ObjAttr 1;
    // OORel 0; OARel 3.
    // Medium example: 51 words; monitors eq,2 + five eq,1 = 7 objects in 6 entries; ObjAttr 3;
    // OORel 5; OARel 1.
    sceneeval(&["stats"], &paper)
        .success()
        .stdout(predicate::str::starts_with(
            "| Difficulty | Scenes | Words | Obj | ObjCount | ObjAttr | OORel | OARel |",
        ))
        .stdout(predicate::str::contains(
            "| Easy | 1 | 27.00 | 3.00 | 3.00 | 1.00 | 0.00 | 3.00 |",
        ))
        .stdout(predicate::str::contains(
            "| Medium | 1 | 51.00 | 7.00 | 6.00 | 3.00 | 5.00 | 1.00 |",
        ))
        .stdout(predicate::str::contains("| Hard | 3 |"))
        .stdout(predicate::str::contains("| All | 5 |"));
}

#[test]
fn stats_json() {
    let (_dir, paper, _) = fixtures().unwrap();
    let out = sceneeval(&["stats", "--json"], &paper)
        .success()
        .get_output()
        .stdout
        .clone();
    let stats: Value = serde_json::from_slice(&out).unwrap();
    let groups = stats["groups"].as_array().unwrap();
    let labels: Vec<&str> = groups.iter().map(|g| g["difficulty"].as_str().unwrap()).collect();
    assert_eq!(labels, ["easy", "medium", "hard", "all"]);
    // Hard rows: the paper's hard example (27 objects), the teenager's bedroom and the master
    // bedroom; their mean objects is (27 + a + b) / 3 with a, b >= 9.
    assert_eq!(groups[2]["scenes"], 3);
    assert!(groups[2]["objects"].as_f64().unwrap() >= (27.0 + 9.0 + 9.0) / 3.0);
    assert_eq!(groups[0]["words"], 27.0);
}

#[test]
fn help_lists_both_subcommands() {
    cargo_bin_cmd!("sceneeval")
        .args(["annotations", "--help"])
        .assert()
        .success()
        .stdout(predicate::str::contains("check").and(predicate::str::contains("stats")));
}

/// A file of one row whose OORel entry has 2,000 undefined references and whose OARel entry
/// has 2,000 unknown architecture references (a 30 KB file).
fn thousands_of_extra_references(dir: &Path) -> std::io::Result<PathBuf> {
    let refs: Vec<String> = (0..2_000).map(|i| format!("x{i}")).collect();
    let arch: Vec<String> = (0..2_000).map(|i| format!("wall_{i}x")).collect();
    let file = dir.join("extra.csv");
    std::fs::write(
        &file,
        format!(
            "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
             0,easy,A bedroom.,\"eq,1,bed\",,\"eq,1,near,0,bed,{}\",\"eq,1,against,bed,{}\"\n",
            refs.join(","),
            arch.join(",")
        ),
    )?;
    Ok(file)
}

#[test]
fn check_reports_an_entry_with_thousands_of_extra_references_in_a_few_short_lines() {
    // Issue 29: one finding per extra reference, each quoting the whole entry, made the output
    // grow with the square of the entry (4,000 lines, 64 MB, here; 1.1 GB for a 109 KB file).
    // Now: one finding per problem and entry, with its count, quoting 80 characters.
    let dir = tempfile::tempdir().unwrap();
    let file = thousands_of_extra_references(dir.path()).unwrap();
    let text = String::from_utf8(failure_stdout(&["check"], &file)).unwrap();
    assert!(text.len() <= 2_000, "{} bytes:\n{text}", text.len());
    assert_eq!(text.lines().count(), 3, "{text}");
    assert!(
        text.contains("reference 1 `x0` has no ObjCount entry in this row (and 1999 more like it)"),
        "{text}"
    );
    assert!(text.contains("(and 1999 more like it)"), "{text}");
    assert!(
        text.lines()
            .last()
            .unwrap()
            .contains("1 rows, 2 error(s), 0 warning(s)"),
        "{text}"
    );

    let out = failure_stdout(&["check", "--json"], &file);
    assert!(out.len() <= 3_000, "{} bytes", out.len());
    let report: Value = serde_json::from_slice(&out).unwrap();
    let findings = report["findings"].as_array().unwrap();
    let occurrences: Vec<(&str, u64)> = findings
        .iter()
        .map(|f| (f["code"].as_str().unwrap(), f["occurrences"].as_u64().unwrap()))
        .collect();
    assert_eq!(
        occurrences,
        [("undefined-category", 2_000), ("unknown-arch-reference", 2_000)]
    );
    for f in findings {
        let entry = f["entry"].as_str().unwrap();
        assert_eq!(
            entry.chars().count(),
            sceneeval::annotation::MAX_QUOTE_CHARS,
            "{entry}"
        );
        assert!(entry.ends_with('…'), "{entry}");
    }
}
