//! The ask protocol of `Session` with scripted models: validation, pairing by key, one
//! re-ask, unanswered outcomes, usage counts.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use sceneeval_geom::Side;
use sceneeval_relations::Relation;
use sceneeval_vlm::check::test_image;
use sceneeval_vlm::prompt::{Prompts, Template};
use sceneeval_vlm::tasks::*;
use sceneeval_vlm::{AnswerContent, Outcome, Scripted, Session, Single, TaskKind, UnansweredKind, VlmError};
use serde_json::{Value, json};

fn json_answer(value: Value) -> AnswerContent {
    AnswerContent::Json { value }
}

fn matching_answer(category: &str) -> AnswerContent {
    json_answer(json!({
        "provided_categories": ["bed", "nightstand"],
        "matched": true,
        "matched_category": category,
        "actual_category": category,
        "reason": "looks like it"
    }))
}

fn matching_task() -> ObjectMatchingTask {
    ObjectMatchingTask::new(test_image(), ["bed", "nightstand"]).unwrap()
}

#[test]
fn invalid_category_is_asked_again_once_then_unanswered() {
    let vlm = Scripted::queue("m", [matching_answer("sofa"), matching_answer("armchair")]);
    let session = Session::new(&vlm);
    let answers = pollster::block_on(session.ask(&matching_task())).unwrap();
    assert_eq!(answers.requests, 2);
    let Some(Outcome::Unanswered(why)) = answers.get(&Single) else {
        panic!("expected unanswered: {answers:?}")
    };
    assert_eq!(why.kind, UnansweredKind::Invalid);
    assert!(
        why.reason.contains("\"armchair\"") && why.reason.contains("\"sofa\""),
        "{}",
        why.reason
    );
    let requests = vlm.requests();
    assert_eq!(requests.len(), 2, "asked exactly twice");
    let second = &requests[1].user_text;
    assert!(
        second.starts_with(&requests[0].user_text),
        "the re-ask repeats the task"
    );
    assert!(
        second.contains("- the answer: matched_category \"sofa\" is not one of the offered categories"),
        "{second}"
    );
    assert!(
        second.contains("\"matched_category\":\"sofa\""),
        "the previous answer is shown"
    );
    let usage = session.usage();
    assert_eq!(
        (usage.requests, usage.re_asks, usage.answered, usage.unanswered),
        (2, 1, 0, 1)
    );
}

#[test]
fn valid_second_answer_is_used() {
    let vlm = Scripted::queue("m", [matching_answer("sofa"), matching_answer("Nightstand")]);
    let session = Session::new(&vlm);
    let outcome = pollster::block_on(session.ask(&matching_task()))
        .unwrap()
        .into_single()
        .unwrap();
    assert_eq!(
        outcome,
        Outcome::Answered {
            answer: ObjectMatch {
                category: Some("nightstand".into()),
                actual_category: "Nightstand".into(),
                reason: "looks like it".into()
            },
            attempt: 2
        }
    );
}

#[test]
fn refusals_and_truncation_are_not_asked_again() {
    for (content, kind) in [
        (
            AnswerContent::Refusal {
                text: "I can't help with that.".into(),
            },
            UnansweredKind::Refused,
        ),
        (
            AnswerContent::Truncated {
                text: "{\"support_ty".into(),
            },
            UnansweredKind::Truncated,
        ),
    ] {
        let vlm = Scripted::queue("m", [content]);
        let session = Session::new(&vlm);
        let task = SupportTypeTask::new(test_image(), test_image());
        let answers = pollster::block_on(session.ask(&task)).unwrap();
        assert_eq!(answers.requests, 1);
        let outcome = answers.into_single().unwrap();
        let why = outcome.into_result().unwrap_err();
        assert_eq!(why.kind, kind);
        assert_eq!(vlm.requests().len(), 1);
    }
}

#[test]
fn not_json_then_valid() {
    let vlm = Scripted::queue(
        "m",
        [
            AnswerContent::from_text("The object stands on the floor."),
            json_answer(json!({"support_type": "ground", "reason": "floor"})),
        ],
    );
    let session = Session::new(&vlm);
    let task = SupportTypeTask::new(test_image(), test_image());
    let answers = pollster::block_on(session.ask(&task)).unwrap();
    assert_eq!(answers.requests, 2);
    assert!(answers.get(&Single).unwrap().is_answered());
    assert!(
        vlm.requests()[1]
            .user_text
            .contains("the answer is not valid JSON")
    );
}

#[test]
fn schema_violations_are_validation_problems() {
    let vlm = Scripted::queue(
        "m",
        [
            json_answer(json!({"support_type": "ground"})),
            json_answer(json!({"support_type": 3, "reason": "x"})),
        ],
    );
    let session = Session::new(&vlm);
    let task = SupportTypeTask::new(test_image(), test_image());
    let why = pollster::block_on(session.ask(&task))
        .unwrap()
        .into_single()
        .unwrap()
        .into_result()
        .unwrap_err();
    assert!(why.reason.contains("missing field `reason`"), "{}", why.reason);
    assert!(
        why.reason.contains("does not follow the response schema"),
        "{}",
        why.reason
    );
}

fn relation_task() -> ObjectRelationTask {
    let spec = |key: &str, rel: &str, objects: &[&str]| ObjectRelationSpec {
        key: key.into(),
        relationship: rel.into(),
        objects: objects.iter().map(|s| s.to_string()).collect(),
        anchor_index: Some(0),
    };
    ObjectRelationTask::new(vec![
        spec("eq,1,left,0,bed,nightstand", "left", &["bed", "nightstand"]),
        spec("eq,1,on,0,desk,lamp", "on", &["desk", "lamp"]),
        spec("eq,1,face,0,tv,sofa", "face", &["tv", "sofa"]),
    ])
    .unwrap()
}

fn mapping(key: &str, anchor: &str, other: &str, types: Value, sides: Value) -> Value {
    json!({"key": key, "relationship": "", "anchor_object": anchor, "other_objects": [other],
           "other_object_counts": [1], "relationship_types": types, "sides": sides, "reason": "r"})
}

#[test]
fn shuffled_answers_are_paired_by_key() {
    let vlm = Scripted::queue(
        "m",
        [json_answer(json!({"assessments": [
            mapping("eq,1,face,0,tv,sofa", "tv", "sofa", json!(["face_to"]), json!([null])),
            mapping("eq,1,on,0,desk,lamp", "desk", "lamp", json!(["on_top"]), json!([null])),
            mapping("eq,1,left,0,bed,nightstand", "bed", "nightstand", json!(["side_of", "next_to"]), json!(["left", null])),
        ]}))],
    );
    let session = Session::new(&vlm);
    let answers = pollster::block_on(session.ask(&relation_task())).unwrap();
    assert_eq!(answers.requests, 1);
    let keys: Vec<&str> = answers.outcomes.iter().map(|(k, _)| k.as_str()).collect();
    assert_eq!(
        keys,
        [
            "eq,1,left,0,bed,nightstand",
            "eq,1,on,0,desk,lamp",
            "eq,1,face,0,tv,sofa"
        ],
        "question order"
    );
    let relations = |k: &str| {
        answers
            .get(&k.to_owned())
            .unwrap()
            .answer()
            .unwrap()
            .relations
            .clone()
    };
    assert_eq!(
        relations("eq,1,left,0,bed,nightstand"),
        Some(vec![Relation::SideOf(Side::Left), Relation::NextTo])
    );
    assert_eq!(relations("eq,1,on,0,desk,lamp"), Some(vec![Relation::OnTop]));
    assert_eq!(relations("eq,1,face,0,tv,sofa"), Some(vec![Relation::FaceTo]));
}

#[test]
fn partly_valid_answers_keep_the_valid_part_and_reask_the_rest() {
    let vlm = Scripted::queue(
        "m",
        [
            // First: one valid, one with a predicate that does not exist, one missing.
            json_answer(json!({"assessments": [
                mapping("eq,1,on,0,desk,lamp", "desk", "lamp", json!(["on_top"]), json!([null])),
                mapping("eq,1,face,0,tv,sofa", "tv", "sofa", json!(["looking_at"]), json!([null])),
            ]})),
            // Second: the face relation fixed, the left one answered twice, the on one changed.
            json_answer(json!({"assessments": [
                mapping("eq,1,on,0,desk,lamp", "desk", "lamp", json!(["middle_of"]), json!([null])),
                mapping("eq,1,face,0,tv,sofa", "tv", "sofa", json!(["face_to"]), json!([null])),
                mapping("eq,1,left,0,bed,nightstand", "bed", "nightstand", json!(["side_of"]), json!(["left"])),
                mapping("eq,1,left,0,bed,nightstand", "bed", "nightstand", json!(["side_of"]), json!(["right"])),
            ]})),
        ],
    );
    let session = Session::new(&vlm);
    let answers = pollster::block_on(session.ask(&relation_task())).unwrap();
    let on = answers.get(&"eq,1,on,0,desk,lamp".to_owned()).unwrap();
    assert!(
        matches!(on, Outcome::Answered { attempt: 1, answer } if answer.relations == Some(vec![Relation::OnTop]))
    );
    let face = answers.get(&"eq,1,face,0,tv,sofa".to_owned()).unwrap();
    assert!(matches!(face, Outcome::Answered { attempt: 2, .. }));
    let left = answers.get(&"eq,1,left,0,bed,nightstand".to_owned()).unwrap();
    let Outcome::Unanswered(why) = left else {
        panic!("{left:?}")
    };
    assert!(
        why.reason.contains("answered more than once") && why.reason.contains("no answer for"),
        "{}",
        why.reason
    );
    let second = &vlm.requests()[1].user_text;
    assert!(
        second.contains("- eq,1,face,0,tv,sofa: relationship type \"looking_at\""),
        "{second}"
    );
    assert!(
        second.contains("- eq,1,left,0,bed,nightstand: no answer for eq,1,left,0,bed,nightstand"),
        "{second}"
    );
    assert_eq!((session.usage().answered, session.usage().unanswered), (2, 1));
}

#[test]
fn backend_errors_propagate_and_are_counted() {
    let vlm = Scripted::queue("m", []);
    let session = Session::new(&vlm);
    let err = pollster::block_on(session.ask(&matching_task())).unwrap_err();
    assert!(matches!(err, VlmError::ScriptExhausted { .. }), "{err}");
    assert!(!err.is_permanent());
    assert_eq!(session.usage().failed_requests, 1);
}

#[test]
fn requests_carry_system_prompt_images_and_schema() {
    let vlm = Scripted::queue("m", []);
    let session = Session::new(&vlm);
    let task = AttributeTask::new(
        "chair",
        ["red"],
        vec![
            InstanceViews {
                front: test_image(),
                size: test_image(),
            },
            InstanceViews {
                front: test_image(),
                size: test_image(),
            },
        ],
    )
    .unwrap();
    let request = session.request(&task).unwrap();
    assert_eq!(request.task, "obj_attribute");
    assert!(
        request
            .system
            .starts_with("You are an expert in interior design.")
    );
    assert_eq!(request.images.len(), 4);
    assert!(
        request.user_text.ends_with(
            "Here are the renderings of 2 instances of object with category \"chair\" in the scene."
        )
    );
    assert!(
        request
            .user_text
            .contains("The attribute requirements are as follows:\n[\"red\"]")
    );
    assert_eq!(request.schema.name, "obj_attribute");
}

#[test]
fn overridden_prompts_are_used() {
    let prompts = Prompts::builtin()
        .with_override(
            Template::Task(TaskKind::ObjMatching),
            "Categories: <TARGET_CATEGORIES>",
        )
        .unwrap()
        .with_override(Template::System, "Be brief.")
        .unwrap();
    let vlm = Scripted::queue("m", [matching_answer("bed")]);
    let session = Session::new(&vlm).with_prompts(prompts);
    let answers = pollster::block_on(session.ask(&matching_task())).unwrap();
    assert!(answers.get(&Single).unwrap().is_answered());
    let r = &vlm.requests()[0];
    assert_eq!(
        (r.system.as_str(), r.user_text.as_str()),
        ("Be brief.", "Categories: [\"bed\",\"nightstand\"]")
    );
}

#[test]
fn functional_sides_end_to_end() {
    let task = FunctionalSidesTask::new(vec![
        ObjectToDescribe {
            id: "obj_1".into(),
            description: "double bed".into(),
        },
        ObjectToDescribe {
            id: "obj_2".into(),
            description: "mug".into(),
        },
    ])
    .unwrap();
    let vlm = Scripted::queue(
        "m",
        [json_answer(json!({"assessments": [
            {"obj_id": "obj_2", "obj_description": "mug", "functional_sides": [], "reason": "small"},
            {"obj_id": "obj_1", "obj_description": "double bed", "functional_sides": ["left", "right", "front"], "reason": "bed"},
        ]}))],
    );
    let session = Session::new(&vlm);
    let answers = pollster::block_on(session.ask(&task)).unwrap();
    let sides = |id: &str| {
        answers
            .get(&id.to_owned())
            .unwrap()
            .answer()
            .unwrap()
            .sides
            .clone()
    };
    assert_eq!(sides("obj_1"), [Side::Left, Side::Right, Side::Front]);
    assert!(sides("obj_2").is_empty());
    assert!(vlm.requests()[0].user_text.ends_with(
        "obj_id: \"obj_1\", obj_description: \"double bed\"\nobj_id: \"obj_2\", obj_description: \"mug\""
    ));
}
