//! The fixture batches of the four formats convert to exactly the bytes they converted to
//! before the converters were rearranged (the `Converter` trait, issue 35): every output file's
//! BLAKE3 digest and size are compared with `tests/expected/converted.json`, written by the
//! converters as they were. A deliberate change of the output re-blesses the file with
//! `SCENEEVAL_BLESS=1 cargo test -p sceneeval-convert --test unchanged` (and says why in its
//! commit).

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use common::{convert_into, fixture_batches, native};

/// Every file under `dir`, relative to it (with `/`), to `"<blake3 hex> <size>"`.
fn digests(dir: &Path) -> BTreeMap<String, String> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<String, String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(root, &path, out);
            } else {
                let bytes = std::fs::read(&path).unwrap();
                let rel: Vec<String> = path
                    .strip_prefix(root)
                    .unwrap()
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                out.insert(
                    rel.join("/"),
                    format!("{} {}", blake3::hash(&bytes).to_hex(), bytes.len()),
                );
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

fn expected_file() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/expected/converted.json")
}

#[test]
fn fixture_conversions_are_byte_identical_to_the_blessed_outputs() {
    let mut actual: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    for (format, input, assets) in fixture_batches() {
        let (tmp, _) = convert_into(format, &native(input), assets, None);
        actual.insert(format.name().to_owned(), digests(&tmp.path().join("out")));
    }
    let path = expected_file();
    if std::env::var_os("SCENEEVAL_BLESS").is_some_and(|v| v == "1") {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        let mut text = serde_json::to_string_pretty(&actual).unwrap();
        text.push('\n');
        std::fs::write(&path, text).unwrap();
        return;
    }
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; run with SCENEEVAL_BLESS=1 to create it", path.display()));
    let expected: BTreeMap<String, BTreeMap<String, String>> = serde_json::from_str(&text).unwrap();
    for (format, files) in &expected {
        let got = &actual[format];
        for (file, digest) in files {
            assert_eq!(
                got.get(file),
                Some(digest),
                "{format}: {file} differs from the blessed output (or is missing)"
            );
        }
        let extra: Vec<&String> = got.keys().filter(|f| !files.contains_key(*f)).collect();
        assert!(
            extra.is_empty(),
            "{format}: files not in the blessed output: {extra:?}"
        );
    }
    assert_eq!(
        expected.keys().collect::<Vec<_>>(),
        actual.keys().collect::<Vec<_>>()
    );
}

#[test]
fn converted_and_fixture_scenes_have_only_known_keys() {
    // Reading them warns about nothing (and `--strict` accepts them): the keys the converters
    // write, those SceneSmith's exporter writes (copied by the SceneAgent conversion), and those
    // of the generated fixture scenes are all keys of the sceneState format.
    let mut files = Vec::new();
    let mut tmps = Vec::new();
    for (format, input, assets) in fixture_batches() {
        let (tmp, report) = convert_into(format, &native(input), assets, None);
        for s in &report.scenes {
            files.push(tmp.path().join("out").join(&s.files[0]));
        }
        tmps.push(tmp);
    }
    let scenes = sceneeval_fixtures::default_output_dir().join("scenes");
    for entry in std::fs::read_dir(&scenes).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "json") {
            files.push(path);
        }
    }
    assert!(files.len() > 10, "{files:?}");
    for file in files {
        let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
        let unknown = sceneeval_io::scene_state::unknown_keys(&doc);
        assert!(unknown.is_empty(), "{}: {unknown:?}", file.display());
    }
}
