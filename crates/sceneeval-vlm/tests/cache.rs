//! The disk cache: second runs from the cache, the file format, atomic writes shared by
//! several writers, damaged entries, replay misses, and key sensitivity.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;
use std::sync::Arc;

use proptest::prelude::*;
use sceneeval_vlm::cache::{CACHE_FORMAT, CacheRecord, cache_key};
use sceneeval_vlm::check::{EndpointCheck, test_image};
use sceneeval_vlm::tasks::SupportTypeTask;
use sceneeval_vlm::{
    AnswerContent, Cached, DiskCache, Replay, ResponseSchema, Scripted, Session, Single, TokenUsage, Vlm,
    VlmError, VlmRequest, encode_rgb_png,
};
use serde_json::json;

fn support_answer() -> AnswerContent {
    AnswerContent::Json {
        value: json!({"support_type": "wall", "reason": "A painting."}),
    }
}

fn files(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.is_dir() {
            out.extend(files(&p));
        } else {
            out.push(p);
        }
    }
    out.sort();
    out
}

#[test]
fn second_run_is_served_from_the_cache() {
    let dir = tempfile::tempdir().unwrap();
    let inner = Arc::new(Scripted::from_fn("painter-1", |_| Ok(support_answer())));
    let task = SupportTypeTask::new(test_image(), test_image());

    let first = Session::new(Cached::new(inner.clone(), dir.path()));
    let a = pollster::block_on(first.ask(&task)).unwrap();
    assert_eq!(inner.requests().len(), 1);
    assert_eq!(first.usage().cache_hits, 0);

    let second = Session::new(Cached::new(inner.clone(), dir.path()));
    let b = pollster::block_on(second.ask(&task)).unwrap();
    assert_eq!(inner.requests().len(), 1, "no request reached the model");
    assert_eq!(a, b);
    assert_eq!((second.usage().requests, second.usage().cache_hits), (1, 1));

    // Replay gives the same answer without any model.
    let replay = Session::new(Replay::new(dir.path(), "painter-1"));
    let c = pollster::block_on(replay.ask(&task)).unwrap();
    assert_eq!(a, c);

    // One file, no temporary files left behind.
    assert_eq!(files(dir.path()).len(), 1);
}

#[test]
fn answers_given_with_other_settings_are_not_reused() {
    let dir = tempfile::tempdir().unwrap();
    let task = SupportTypeTask::new(test_image(), test_image());
    let low = Arc::new(Scripted::from_fn("painter-1", |_| Ok(support_answer())).with_settings("detail=low"));
    let high =
        Arc::new(Scripted::from_fn("painter-1", |_| Ok(support_answer())).with_settings("detail=high"));

    pollster::block_on(Session::new(Cached::new(low.clone(), dir.path())).ask(&task)).unwrap();
    // Same model, same request, other image detail: asked again, stored beside the first.
    pollster::block_on(Session::new(Cached::new(high.clone(), dir.path())).ask(&task)).unwrap();
    assert_eq!((low.requests().len(), high.requests().len()), (1, 1));
    assert_eq!(files(dir.path()).len(), 2);
    // Each setting is served from its own entry afterwards.
    pollster::block_on(Session::new(Cached::new(high.clone(), dir.path())).ask(&task)).unwrap();
    assert_eq!(high.requests().len(), 1);

    // The record says which settings answered; Replay finds it only with the same settings.
    let request = Session::new(&*low).request(&task).unwrap();
    let key = cache_key("painter-1", "detail=low", &request);
    let record = DiskCache::new(dir.path()).load(&key).unwrap().unwrap();
    assert_eq!(record.settings, "detail=low");
    let replay = Session::new(Replay::new(dir.path(), "painter-1").with_settings("detail=low"));
    assert!(pollster::block_on(replay.ask(&task)).is_ok());
    let without = Session::new(Replay::new(dir.path(), "painter-1"));
    assert!(matches!(
        pollster::block_on(without.ask(&task)),
        Err(VlmError::CacheMiss { .. })
    ));
}

#[test]
fn cache_files_are_readable_records() {
    let dir = tempfile::tempdir().unwrap();
    let vlm = Cached::new(Scripted::queue("model-x", [support_answer()]), dir.path());
    let session = Session::new(&vlm);
    let task = SupportTypeTask::new(test_image(), test_image());
    let request = session.request(&task).unwrap();
    pollster::block_on(session.ask(&task)).unwrap();

    let key = cache_key("model-x", "", &request);
    let path = DiskCache::new(dir.path()).path_of(&key);
    assert_eq!(path, dir.path().join(&key[..2]).join(format!("{key}.json")));
    let text = std::fs::read_to_string(&path).unwrap();
    let record: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(record["format"], CACHE_FORMAT);
    assert_eq!(record["key"], key.as_str());
    assert_eq!(record["model"], "model-x");
    assert_eq!(record["task"], "obj_support_type");
    assert_eq!(
        record["answer"],
        json!({"kind": "json", "value": {"support_type": "wall", "reason": "A painting."}})
    );
    assert_eq!(
        record["usage"],
        json!({"prompt_tokens": 0, "completion_tokens": 0})
    );
    let images = record["request"]["images"].as_array().unwrap();
    assert_eq!(images.len(), 2);
    assert_eq!(images[0]["width"], 64);
    assert_eq!(images[0]["blake3"], test_image().blake3_hex());
    assert!(
        record["request"]["user_text"]
            .as_str()
            .unwrap()
            .contains("support type")
    );
    // The schema is stored with its properties in declaration order.
    assert!(text.find("\"support_type\": {").unwrap() < text.find("\"reason\": {").unwrap());
    // The record reads back.
    let loaded = DiskCache::new(dir.path()).load(&key).unwrap().unwrap();
    assert_eq!(loaded.request.schema, request.schema);
}

#[test]
fn refusals_are_cached_too() {
    let dir = tempfile::tempdir().unwrap();
    let refusal = AnswerContent::Refusal { text: "no".into() };
    let task = SupportTypeTask::new(test_image(), test_image());
    let session = Session::new(Cached::new(Scripted::queue("m", [refusal]), dir.path()));
    pollster::block_on(session.ask(&task)).unwrap();
    let replay = Session::new(Replay::new(dir.path(), "m"));
    let why = pollster::block_on(replay.ask(&task))
        .unwrap()
        .into_single()
        .unwrap()
        .into_result()
        .unwrap_err();
    assert_eq!(why.reason, "no");
}

#[test]
fn replay_miss_names_the_request() {
    let dir = tempfile::tempdir().unwrap();
    let session = Session::new(Replay::new(dir.path(), "gpt-4o-2024-08-06"));
    let err = pollster::block_on(session.ask(&EndpointCheck::new())).unwrap_err();
    let VlmError::CacheMiss { task, model, key, .. } = &err else {
        panic!("{err}")
    };
    assert_eq!(
        (task.as_str(), model.as_str(), key.len()),
        ("endpoint_check", "gpt-4o-2024-08-06", 64)
    );
    let text = err.to_string();
    assert!(
        text.contains("endpoint_check") && text.contains(key.as_str()) && text.contains("white"),
        "{text}"
    );
}

#[test]
fn damaged_entries_are_replaced_by_cached_and_reported_by_replay() {
    let dir = tempfile::tempdir().unwrap();
    let task = SupportTypeTask::new(test_image(), test_image());
    let inner = Scripted::from_fn("m", |_| Ok(support_answer()));
    let request = Session::new(&inner).request(&task).unwrap();
    let path = DiskCache::new(dir.path()).path_of(&cache_key("m", "", &request));
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(&path, "{\"format\": \"sceneeval.vlm-cache/1\", \"trunc").unwrap();

    let err = pollster::block_on(Session::new(Replay::new(dir.path(), "m")).ask(&task)).unwrap_err();
    assert!(matches!(err, VlmError::CacheRecord { .. }), "{err}");

    let session = Session::new(Cached::new(&inner, dir.path()));
    assert!(
        pollster::block_on(session.ask(&task))
            .unwrap()
            .get(&Single)
            .unwrap()
            .is_answered()
    );
    assert_eq!(inner.requests().len(), 1);
    let record: CacheRecord = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(record.answer, support_answer());
}

#[test]
fn concurrent_writers_leave_complete_files() {
    // Several "processes" (threads with their own cache handles) answer the same and different
    // requests at once; every file ends complete and no temporary file remains.
    let dir = tempfile::tempdir().unwrap();
    let threads: Vec<_> = (0..8)
        .map(|t| {
            let dir = dir.path().to_path_buf();
            std::thread::spawn(move || {
                let vlm = Cached::new(Scripted::from_fn("m", |_| Ok(support_answer())), dir);
                for i in 0..20u8 {
                    // Requests 0..10 are shared by all threads; the rest are per thread.
                    let n = if i < 10 { i } else { 100 + t * 10 + i };
                    let png = encode_rgb_png(1, 1, &[n, 0, 0]).unwrap();
                    let task = SupportTypeTask::new(png.clone(), png);
                    pollster::block_on(Session::new(&vlm).ask(&task)).unwrap();
                }
            })
        })
        .collect();
    for t in threads {
        t.join().unwrap();
    }
    let all = files(dir.path());
    assert_eq!(all.len(), 10 + 8 * 10);
    for f in all {
        assert!(
            f.extension().unwrap() == "json" && !f.file_name().unwrap().to_str().unwrap().starts_with('.'),
            "{f:?}"
        );
        let record: CacheRecord = serde_json::from_str(&std::fs::read_to_string(&f).unwrap()).unwrap();
        assert_eq!(record.usage, TokenUsage::default());
    }
}

#[test]
fn two_writers_of_one_entry_never_fail_and_leave_one_whole_answer() {
    // Two models (same name, same request, so the same key) store different answers into one
    // entry 50 times each; every store succeeds and the entry is one of the two answers.
    let dir = tempfile::tempdir().unwrap();
    let cache = DiskCache::new(dir.path());
    let request = request("the same question", vec![7]);
    let answers = ["wall", "ground"].map(|t| {
        let answer = sceneeval_vlm::Answer::new(
            AnswerContent::Json {
                value: json!({"support_type": t, "reason": "x".repeat(20_000)}),
            },
            TokenUsage::default(),
        );
        DiskCache::record("m", "", &request, &answer)
    });
    std::thread::scope(|s| {
        for record in &answers {
            let cache = &cache;
            s.spawn(move || {
                for _ in 0..50 {
                    cache.store(record).unwrap();
                }
            });
        }
    });
    let stored = cache.load(&answers[0].key).unwrap().unwrap();
    assert!(stored == answers[0] || stored == answers[1]);
    assert_eq!(files(dir.path()).len(), 1, "no temporary file left");
}

fn request(text: &str, images: Vec<u8>) -> VlmRequest {
    VlmRequest {
        task: "t".into(),
        system: "s".into(),
        user_text: text.into(),
        images: images
            .into_iter()
            .map(|v| encode_rgb_png(1, 1, &[v, v, v]).unwrap())
            .collect(),
        schema: ResponseSchema {
            name: "t".into(),
            schema: json!({"type": "object"}),
        },
    }
}

proptest! {
    /// The key changes with the text, with the images and their order, and not otherwise.
    #[test]
    fn key_depends_on_content(text in "[a-z ]{0,20}", images in proptest::collection::vec(0u8..4, 0..4)) {
        let r = request(&text, images.clone());
        prop_assert_eq!(cache_key("m", "", &r), cache_key("m", "", &request(&text, images.clone())));
        let mut other = text.clone();
        other.push('x');
        prop_assert_ne!(cache_key("m", "", &r), cache_key("m", "", &request(&other, images.clone())));
        let mut more = images.clone();
        more.push(9);
        prop_assert_ne!(cache_key("m", "", &r), cache_key("m", "", &request(&text, more)));
        if images.len() >= 2 && images[0] != images[1] {
            let mut swapped = images.clone();
            swapped.swap(0, 1);
            prop_assert_ne!(cache_key("m", "", &r), cache_key("m", "", &request(&text, swapped)));
        }
        // Moving a boundary between fields changes the key (length prefixes).
        let mut shifted = r.clone();
        shifted.system = format!("s{text}");
        shifted.user_text = String::new();
        if !text.is_empty() {
            prop_assert_ne!(cache_key("m", "", &r), cache_key("m", "", &shifted));
        }
    }
}

#[test]
fn cached_is_a_vlm_through_references_and_arcs() {
    fn model_of(v: impl Vlm) -> String {
        v.model().to_owned()
    }
    let inner = Arc::new(Scripted::queue("shared", []));
    assert_eq!(model_of(Cached::new(inner.clone(), "unused")), "shared");
    assert_eq!(model_of(&*inner), "shared");
    assert_eq!(model_of(Box::new(Replay::new("unused", "r"))), "r");
}
