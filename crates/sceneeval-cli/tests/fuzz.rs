//! Mutation fuzzing of every input format, driven by proptest: sceneState JSON, GLB, glTF,
//! OBJ, the annotation CSV, plan files and `relate` JSON lines. Each target starts from a
//! valid input, applies a few random byte edits (flips, insertions of JSON/CSV punctuation and
//! awkward tokens, deletions, truncation) and checks that reading it never panics and that any
//! error names the input it came from (the file name, or `line N` for `relate`).
//!
//! The number of cases per target is fixed (`SCENEEVAL_FUZZ_CASES`, default 256; 16 runs of
//! 32 lines for `relate`) and the random generator is seeded deterministically, so CI runs
//! the same cases every time in a few seconds. Raise the count for a longer local run:
//! `SCENEEVAL_FUZZ_CASES=20000 cargo test -p sceneeval-cli --test fuzz --release`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::path::Path;

use assert_cmd::Command;
use common::fixtures;
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use sceneeval::annotation::Annotations;
use sceneeval::io::mesh_load::read_mesh_file_with;
use sceneeval::io::{AssetLibrary, Limits, ReadOptions, read_scene_state};
use sceneeval::{EvaluationPlan, Preset};
use serde_json::Value;

fn cases() -> u32 {
    std::env::var("SCENEEVAL_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256)
}

/// A runner with a fixed seed and no failure files (a failure prints its minimal input).
fn runner(cases: u32) -> TestRunner {
    let config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha))
}

/// One byte edit.
#[derive(Debug, Clone)]
enum Edit {
    Set(Index, u8),
    Insert(Index, Vec<u8>),
    Delete(Index, usize),
    Truncate(Index),
}

/// Bytes and tokens that tend to break parsers.
fn token() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        any::<u8>().prop_map(|b| vec![b]),
        prop::sample::select(vec![
            "\"",
            "{",
            "}",
            "[",
            "]",
            ",",
            ":",
            ";",
            "\n",
            "\r\n",
            "\\",
            "-",
            ".",
            "e",
            "0",
            "9",
            " ",
            "null",
            "true",
            "1e999",
            "-1",
            "NaN",
            "99999999999999999999999",
            "\"\"",
            "[]",
            "{}",
            "\u{feff}",
            "\u{0}",
            "f 1 2 3\n",
            "l 1 2 3\n",
            "v 1e308 0 0\n",
            "eq,1,bed",
            "\"x",
            "glTF",
        ])
        .prop_map(|s| s.as_bytes().to_vec()),
        Just(vec![0xff, 0xfe]),
    ]
}

fn edits() -> impl Strategy<Value = Vec<Edit>> {
    let edit = prop_oneof![
        4 => (any::<Index>(), any::<u8>()).prop_map(|(i, b)| Edit::Set(i, b)),
        4 => (any::<Index>(), token()).prop_map(|(i, t)| Edit::Insert(i, t)),
        2 => (any::<Index>(), 1usize..16).prop_map(|(i, n)| Edit::Delete(i, n)),
        1 => any::<Index>().prop_map(Edit::Truncate),
    ];
    prop::collection::vec(edit, 1..5)
}

fn apply(original: &[u8], edits: &[Edit]) -> Vec<u8> {
    let mut b = original.to_vec();
    for e in edits {
        let len = b.len();
        match e {
            Edit::Set(i, v) if len > 0 => {
                let k = i.index(len);
                b[k] = *v;
            }
            Edit::Insert(i, t) => {
                let k = i.index(len + 1);
                b.splice(k..k, t.iter().copied());
            }
            Edit::Delete(i, n) if len > 0 => {
                let k = i.index(len);
                b.drain(k..(k + n).min(len));
            }
            Edit::Truncate(i) => b.truncate(i.index(len + 1)),
            _ => {}
        }
    }
    b
}

/// Runs `target` on mutations of `original` written to `dir/<name>`; the target returns the
/// error text, if any, which must mention `name`.
fn fuzz(original: &[u8], dir: &Path, name: &str, target: impl Fn(&Path) -> Option<String>) {
    let path = dir.join(name);
    runner(cases())
        .run(&edits(), |edits| {
            std::fs::write(&path, apply(original, &edits)).unwrap();
            if let Some(message) = target(&path) {
                prop_assert!(
                    message.contains(name),
                    "the error does not name its input {name}: {message}"
                );
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn scene_state_json() {
    let dir = tempfile::tempdir().unwrap();
    let original = std::fs::read(fixtures().join("scenes/scene_0.json")).unwrap();
    let assets =
        AssetLibrary::from_specs(&[format!("fixture={}", fixtures().join("assets").display())]).unwrap();
    fuzz(&original, dir.path(), "scene_77.json", |p| {
        read_scene_state(p, &assets, &ReadOptions::default())
            .err()
            .map(|e| e.to_string())
    });
}

#[test]
fn glb() {
    let dir = tempfile::tempdir().unwrap();
    let original = std::fs::read(fixtures().join("assets/chair.glb")).unwrap();
    let limits = Limits {
        max_triangles: 100_000,
        ..Limits::default()
    };
    fuzz(&original, dir.path(), "fuzzed_chair.glb", |p| {
        read_mesh_file_with(p, &limits).err().map(|e| e.to_string())
    });
}

#[test]
fn gltf_json() {
    use base64::Engine;
    let dir = tempfile::tempdir().unwrap();
    // Two triangles sharing an edge, indexed, in a data: buffer.
    let mut bytes: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    bytes.extend([0u16, 1, 2, 2, 1, 3].iter().flat_map(|v| v.to_le_bytes()));
    let data = base64::engine::general_purpose::STANDARD.encode(&bytes);
    let original = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"children":[1],"translation":[0,1,0]}},{{"mesh":0,"scale":[2,2,2]}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
{{"bufferView":1,"componentType":5123,"count":6,"type":"SCALAR"}}],
"bufferViews":[{{"buffer":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":12}}],
"buffers":[{{"byteLength":60,"uri":"data:application/octet-stream;base64,{data}"}}]}}"#
    );
    let limits = Limits {
        max_triangles: 100_000,
        ..Limits::default()
    };
    assert_eq!(
        {
            std::fs::write(dir.path().join("ok.gltf"), &original).unwrap();
            read_mesh_file_with(&dir.path().join("ok.gltf"), &limits)
                .unwrap()
                .triangles
                .len()
        },
        2
    );
    fuzz(original.as_bytes(), dir.path(), "fuzzed.gltf", |p| {
        read_mesh_file_with(p, &limits).err().map(|e| e.to_string())
    });
}

#[test]
fn obj() {
    let dir = tempfile::tempdir().unwrap();
    let original = "# a unit cube\nmtllib cube.mtl\no cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                    v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nvn 0 0 1\nusemtl wood\n\
                    f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\nl 1 7\n";
    let limits = Limits {
        max_triangles: 100_000,
        ..Limits::default()
    };
    fuzz(original.as_bytes(), dir.path(), "fuzzed.obj", |p| {
        read_mesh_file_with(p, &limits).err().map(|e| e.to_string())
    });
}

#[test]
fn annotation_csv() {
    let dir = tempfile::tempdir().unwrap();
    let original = std::fs::read(fixtures().join("annotations/paper_examples.csv")).unwrap();
    fuzz(
        &original,
        dir.path(),
        "fuzzed_annotations.csv",
        |p| match Annotations::read_csv(p) {
            Ok(a) => {
                // Whatever reads must validate and summarise without panicking.
                let _ = a.validate();
                let _ = a.stats();
                None
            }
            Err(e) => Some(e.to_string()),
        },
    );
}

#[test]
fn plan_files() {
    let dir = tempfile::tempdir().unwrap();
    let original =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plans/quick-check.json"))
            .unwrap();
    fuzz(&original, dir.path(), "fuzzed_plan.json", |p| {
        EvaluationPlan::read_with_preset(p, Some(Preset::Reference))
            .err()
            .map(|e| e.to_string())
    });
}

#[test]
fn relate_json_lines() {
    const BED: &str = r#"{"center":[0,0,0.3],"half_size":[0.8,1.0,0.3],"yaw":0}"#;
    let originals = [
        format!(
            r#"{{"id":"q1","relation":"side_of","side":"left","target":{{"center":[-1.05,0.5,0.3],"half_size":[0.25,0.2,0.3],"yaw":1.5708}},"anchor":{BED}}}"#
        ),
        format!(
            r#"{{"id":2,"relation":"surround","anchor":{BED},"targets":[{BED},{BED},{{"center":[3,0,0.3],"half_size":[0.2,0.2,0.3],"rotation":[1,0,0,0,1,0,0,0,1]}}]}}"#
        ),
        r#"{"id":[3],"relation":"against_wall","target":{"center":[2,4,0.3],"half_size":[0.8,1,0.3],"yaw":0},"room":{"floor":[[0,0],[4,0],[4,5],[0,5]],"openings":[{"kind":"door","wall":0,"along":[1.0,1.9],"height":[0.0,2.1]}]}}"#.to_owned(),
    ];
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("queries.jsonl");
    let lines = prop::collection::vec((0..originals.len(), edits()), 32);
    runner(16)
        .run(&lines, |lines| {
            let mut text = Vec::new();
            let mut expected = 0;
            for (k, e) in &lines {
                let mut line = apply(originals[*k].as_bytes(), e);
                line.retain(|&b| b != b'\n' && b != b'\r');
                if !String::from_utf8_lossy(&line).trim().is_empty() {
                    expected += 1;
                }
                text.extend(line);
                text.push(b'\n');
            }
            std::fs::write(&input, &text).unwrap();
            let out = Command::cargo_bin("sceneeval")
                .unwrap()
                .args(["relate", "--input"])
                .arg(&input)
                .output()
                .unwrap();
            prop_assert!(
                matches!(out.status.code(), Some(0 | 2)),
                "status {:?}: {}",
                out.status,
                String::from_utf8_lossy(&out.stderr)
            );
            let answers: Vec<Value> = String::from_utf8(out.stdout)
                .unwrap()
                .lines()
                .map(|l| serde_json::from_str(l).unwrap())
                .collect();
            prop_assert_eq!(answers.len(), expected, "one answer per non-blank line");
            for a in &answers {
                let has_score = a.get("score").is_some_and(Value::is_number);
                let error_names_line = a
                    .get("error")
                    .and_then(Value::as_str)
                    .is_some_and(|e| e.starts_with("line "));
                prop_assert!(has_score != error_names_line, "{}", a);
                prop_assert!(a.get("id").is_some(), "{}", a);
            }
            Ok(())
        })
        .unwrap();
}
