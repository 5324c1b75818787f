//! The committed `fixtures/` folder is exactly what the generator writes: same file set, same
//! bytes. Regenerating twice gives the same bytes too.

// Test helpers outside `#[test]` functions may fail loudly too.
#![allow(clippy::unwrap_used, clippy::panic)]

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

const HOW_TO_FIX: &str =
    "run `cargo run -p sceneeval-fixtures` to regenerate fixtures/ and commit the result";

/// Every file under `root`, relative to it, sorted.
fn files_under(root: &Path) -> BTreeSet<PathBuf> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeSet<PathBuf>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                out.insert(p.strip_prefix(root).unwrap().to_owned());
            }
        }
    }
    let mut out = BTreeSet::new();
    walk(root, root, &mut out);
    out
}

/// Compares two folders file by file; returns the differences in words.
fn differences(committed: &Path, fresh: &Path) -> Vec<String> {
    let (a, b) = (files_under(committed), files_under(fresh));
    let mut out = Vec::new();
    for f in a.difference(&b) {
        out.push(format!(
            "fixtures/{} is not generated any more (delete it)",
            f.display()
        ));
    }
    for f in b.difference(&a) {
        out.push(format!("fixtures/{} is missing", f.display()));
    }
    for f in a.intersection(&b) {
        let (x, y) = (
            std::fs::read(committed.join(f)).unwrap(),
            std::fs::read(fresh.join(f)).unwrap(),
        );
        if x != y {
            let at = x
                .iter()
                .zip(&y)
                .position(|(p, q)| p != q)
                .unwrap_or(x.len().min(y.len()));
            out.push(format!(
                "fixtures/{} differs ({} vs {} bytes, first difference at byte {at})",
                f.display(),
                x.len(),
                y.len()
            ));
        }
    }
    out
}

#[test]
fn committed_fixtures_are_byte_identical_to_a_fresh_generation() {
    let committed = sceneeval_fixtures::default_output_dir();
    assert!(
        committed.join("expected.json").is_file(),
        "{} has no generated fixtures: {HOW_TO_FIX}",
        committed.display()
    );
    let fresh = tempfile::tempdir().unwrap();
    let generated = sceneeval_fixtures::generate(fresh.path()).unwrap();
    // Every file the generator reports is on disk, and nothing else is.
    let on_disk: Vec<PathBuf> = files_under(fresh.path()).into_iter().collect();
    assert_eq!(generated.files, on_disk);
    let diffs = differences(&committed, fresh.path());
    assert!(diffs.is_empty(), "{}\n{HOW_TO_FIX}", diffs.join("\n"));
}

#[test]
fn two_generations_are_byte_identical() {
    let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    sceneeval_fixtures::generate(a.path()).unwrap();
    sceneeval_fixtures::generate(b.path()).unwrap();
    let diffs = differences(a.path(), b.path());
    assert!(diffs.is_empty(), "{}", diffs.join("\n"));
}

#[test]
fn fixtures_stay_small() {
    let fresh = tempfile::tempdir().unwrap();
    let generated = sceneeval_fixtures::generate(fresh.path()).unwrap();
    let total: u64 = generated
        .files
        .iter()
        .map(|f| std::fs::metadata(fresh.path().join(f)).unwrap().len())
        .sum();
    assert!(total < 1_000_000, "fixtures take {total} bytes");
}
