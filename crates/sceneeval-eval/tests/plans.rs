//! The example plan files under `examples/plans/` read without error, and `default.json`
//! spells out exactly the built-in defaults (so the file cannot drift from the code). After
//! changing a default, rewrite it with
//! `SCENEEVAL_BLESS=1 cargo test -p sceneeval-eval --test plans`.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use sceneeval_eval::{EvaluationPlan, Metric, Preset};
use sceneeval_plausibility::Resolution;

fn plans() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plans")
}

#[test]
fn example_plans_read_and_mean_what_they_say() {
    let written = serde_json::to_string_pretty(&EvaluationPlan::geometry_only()).unwrap() + "\n";
    if std::env::var_os("SCENEEVAL_BLESS").is_some() {
        std::fs::write(plans().join("default.json"), &written).unwrap();
    }
    assert_eq!(
        std::fs::read_to_string(plans().join("default.json")).unwrap(),
        written,
        "examples/plans/default.json is the serialised default plan (see the module docs)"
    );
    let default = EvaluationPlan::read(&plans().join("default.json")).unwrap();
    assert_eq!(default, EvaluationPlan::geometry_only());

    let reference = EvaluationPlan::read(&plans().join("reference.json")).unwrap();
    assert_eq!(reference, EvaluationPlan::reference());

    let quick = EvaluationPlan::read(&plans().join("quick-check.json")).unwrap();
    assert_eq!(quick.preset, Preset::Default);
    assert_eq!(
        quick.ordered_metrics(),
        vec![Metric::Collision, Metric::Navigability, Metric::OutOfBounds]
    );
    assert!(quick.params.collision.exclude_floor_coverings);
    assert_eq!(
        quick.params.navigability.resolution,
        Resolution::MetresPerPixel(0.02)
    );
    assert_eq!(quick.params.navigability.robot_width_m, 0.3);
    assert_eq!(
        quick.params.navigability.margin_m, 0.2,
        "unspecified values keep the preset's"
    );
    assert_eq!(quick.limits.max_triangles, 1_000_000);
    assert_eq!(quick.time_budget_s, Some(60.0));

    // The same plan written in TOML reads to the same value; TOML errors name their line.
    let quick_toml = EvaluationPlan::read(&plans().join("quick-check.toml")).unwrap();
    assert_eq!(quick_toml, quick);
    let typo =
        EvaluationPlan::from_toml_str("[params.collision]\nexclude_floor_covering = true\n").unwrap_err();
    assert!(
        typo.to_string()
            .contains("params.collision.exclude_floor_covering: unknown field"),
        "{typo}"
    );
    let broken = EvaluationPlan::from_toml_str("metrics = [\"collision\"\n").unwrap_err();
    assert!(broken.to_string().contains("malformed TOML"), "{broken}");
    assert!(broken.to_string().contains("line 1"), "{broken}");

    // Stability as close to the SceneSmith fork as the model allows: its `combined` weld
    // variant, 1 kg per object, no sleeping (the full 5 s simulated).
    let fork = EvaluationPlan::read(&plans().join("stability-fork.json")).unwrap();
    assert_eq!(
        fork.ordered_metrics(),
        vec![Metric::Collision, Metric::Support, Metric::Stability]
    );
    assert_eq!(fork.stability.weld, sceneeval_physics::WeldMode::Combined);
    assert_eq!(fork.stability.mass, sceneeval_physics::MassModel::PerObject(1.0));
    assert_eq!(fork.stability.sleep_speed_m_s, 0.0);
    assert_eq!(
        fork.stability.duration_s, 5.0,
        "unspecified values keep the preset's"
    );

    // The paper's ten metrics, VLM matching with the sizes in the prompt, lexicon mapping.
    let full = EvaluationPlan::read(&plans().join("full-vlm.json")).unwrap();
    assert_eq!(full.metrics.len(), 10);
    assert_eq!(full.fidelity.matching, sceneeval_fidelity::MatchingMethod::Vlm);
    assert!(full.fidelity.size_aware_matching);
    assert_eq!(full.fidelity.max_candidate_groups, 100_000);
    assert!(
        full.fidelity.presence_gate_respects_quantifier,
        "unspecified values keep the preset's"
    );
}

/// The example plans are written in the keys of today: no key of theirs is one that
/// `RENAMED_KEYS` reads as another (which would log a warning for every reader of the
/// examples).
#[test]
fn example_plans_use_no_renamed_key() {
    let mut names: Vec<_> = std::fs::read_dir(plans())
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    names.sort();
    assert!(names.len() >= 6, "{names:?}");
    for path in names {
        let text = std::fs::read_to_string(&path).unwrap();
        let value: serde_json::Value = if path.extension().is_some_and(|e| e == "toml") {
            serde_json::to_value(toml::from_str::<toml::Value>(&text).unwrap()).unwrap()
        } else {
            serde_json::from_str(&text).unwrap()
        };
        let mut plan = value.as_object().unwrap().clone();
        // The old top-level sections, were there any, would be under `params` first.
        assert!(
            !["stability", "fidelity", "relations"]
                .iter()
                .any(|k| plan.contains_key(*k)),
            "{}",
            path.display()
        );
        let renamed = sceneeval_eval::read_renamed_keys(&mut plan).unwrap();
        assert!(renamed.is_empty(), "{}: {renamed:?}", path.display());
        assert!(
            !text.contains("\"method\""),
            "{}: matching is written externally tagged",
            path.display()
        );
    }
}
