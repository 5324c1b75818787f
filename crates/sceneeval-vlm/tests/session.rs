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
fn a_category_not_offered_is_asked_again_once_then_recorded_as_unmatched() {
    let vlm = Scripted::queue("m", [matching_answer("sofa"), matching_answer("armchair")]);
    let session = Session::new(&vlm);
    let answers = pollster::block_on(session.ask(&matching_task())).unwrap();
    assert_eq!(answers.requests, 2);
    let Some(Outcome::Answered {
        answer,
        attempt: 2,
        note: Some(note),
    }) = answers.get(&Single)
    else {
        panic!("expected an unmatched answer with a note: {answers:?}")
    };
    assert_eq!(answer.category, None, "none of the offered categories");
    assert_eq!(
        answer.actual_category, "armchair",
        "the second answer's own words"
    );
    assert!(
        note.contains("after asking twice") && note.contains("\"armchair\" is not one of the offered"),
        "{note}"
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
        (
            usage.requests,
            usage.re_asks,
            usage.answered,
            usage.unanswered,
            usage.unmatched_not_offered
        ),
        (2, 1, 1, 0, 1)
    );
}

#[test]
fn a_category_not_offered_then_a_refusal_is_unmatched_too() {
    let refusal = AnswerContent::Refusal { text: "no".into() };
    let vlm = Scripted::queue("m", [matching_answer("sofa"), refusal]);
    let session = Session::new(&vlm);
    let outcome = pollster::block_on(session.ask(&matching_task()))
        .unwrap()
        .into_single()
        .unwrap();
    let Outcome::Answered {
        answer,
        note: Some(note),
        ..
    } = outcome
    else {
        panic!("{outcome:?}")
    };
    assert_eq!((answer.category, answer.actual_category.as_str()), (None, "sofa"));
    assert!(note.contains("\"sofa\""), "{note}");
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
            attempt: 2,
            note: None,
        }
    );
    assert_eq!(session.usage().unmatched_not_offered, 0);
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
        matches!(on, Outcome::Answered { attempt: 1, answer, .. } if answer.relations == Some(vec![Relation::OnTop]))
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
    // Only the two questions without a valid answer are asked again: the relation already
    // mapped is not in the second prompt's list (its answer there is ignored).
    let listed = |text: &str, key: &str| text.contains(&format!("- key \"{key}\":"));
    assert!(listed(&vlm.requests()[0].user_text, "eq,1,on,0,desk,lamp"));
    assert!(!listed(second, "eq,1,on,0,desk,lamp"), "{second}");
    assert!(listed(second, "eq,1,face,0,tv,sofa") && listed(second, "eq,1,left,0,bed,nightstand"));
    let usage = session.usage();
    assert_eq!(
        (
            usage.answered,
            usage.unanswered,
            usage.re_asks,
            usage.re_asked_questions
        ),
        (2, 1, 1, 2)
    );
}

/// The relation-mapping answer of a model that follows the prompt's order but leaves every
/// `key` empty (weak local models do), or copies the keys.
fn in_order(keys: bool) -> AnswerContent {
    let key = |k: &'static str| if keys { k } else { "" };
    json_answer(json!({"assessments": [
        mapping(key("eq,1,left,0,bed,nightstand"), "bed", "nightstand", json!(["side_of"]), json!(["left"])),
        mapping(key("eq,1,on,0,desk,lamp"), "desk", "lamp", json!(["on_top"]), json!([null])),
        mapping(key("eq,1,face,0,tv,sofa"), "tv", "sofa", json!(["face_to"]), json!([null])),
    ]}))
}

#[test]
fn blank_keys_in_prompt_order_are_paired_by_position() {
    let copied = Scripted::queue("m", [in_order(true)]);
    let blank = Scripted::queue("m", [in_order(false)]);
    let (s1, s2) = (Session::new(&copied), Session::new(&blank));
    let a = pollster::block_on(s1.ask(&relation_task())).unwrap();
    let b = pollster::block_on(s2.ask(&relation_task())).unwrap();
    // The same mappings, asked once; the positional pairing is noted and counted.
    let mappings = |x: &sceneeval_vlm::Answers<String, ObjectRelationMapping>| {
        x.answered()
            .map(|(k, m)| (k.clone(), m.clone()))
            .collect::<Vec<_>>()
    };
    assert_eq!(mappings(&a), mappings(&b));
    assert_eq!(mappings(&b).len(), 3);
    assert_eq!(b.requests, 1);
    let Some(Outcome::Answered { note: Some(note), .. }) = b.get(&"eq,1,face,0,tv,sofa".to_owned()) else {
        panic!("{b:?}")
    };
    assert_eq!(note, "paired by position: item 2 of the answer had no key");
    assert_eq!(
        (s1.usage().paired_by_position, s2.usage().paired_by_position),
        (0, 3)
    );

    // A missing key is a blank one.
    let mut missing = in_order(false);
    if let AnswerContent::Json { value } = &mut missing {
        for m in value["assessments"].as_array_mut().unwrap() {
            m.as_object_mut().unwrap().remove("key");
        }
    }
    let vlm = Scripted::queue("m", [missing]);
    let c = pollster::block_on(Session::new(&vlm).ask(&relation_task())).unwrap();
    assert_eq!(mappings(&c), mappings(&a));
}

#[test]
fn a_key_naming_no_relation_stays_an_error_and_blank_keys_need_one_item_per_question() {
    // Three items, one with a key that is no relation's: that item is not used (and the
    // others are still paired by position, the count matching the prompt).
    let mut wrong = in_order(false);
    if let AnswerContent::Json { value } = &mut wrong {
        value["assessments"][1]["key"] = json!("eq,1,under,0,desk,lamp");
    }
    // Two items without keys for three questions: nothing can be paired by position.
    let short = json_answer(json!({"assessments": [
        mapping("", "bed", "nightstand", json!(["side_of"]), json!(["left"])),
        mapping("", "desk", "lamp", json!(["on_top"]), json!([null])),
    ]}));
    let vlm = Scripted::queue("m", [wrong, short]);
    let session = Session::new(&vlm);
    let answers = pollster::block_on(session.ask(&relation_task())).unwrap();
    let answered: Vec<&str> = answers.answered().map(|(k, _)| k.as_str()).collect();
    assert_eq!(answered, ["eq,1,left,0,bed,nightstand", "eq,1,face,0,tv,sofa"]);
    let second = &vlm.requests()[1].user_text;
    assert!(
        second.contains("key \"eq,1,under,0,desk,lamp\", which is not one of the keys"),
        "{second}"
    );
    let Some(Outcome::Unanswered(why)) = answers.get(&"eq,1,on,0,desk,lamp".to_owned()) else {
        panic!("{answers:?}")
    };
    assert!(
        why.reason.contains("cannot be paired by position"),
        "{}",
        why.reason
    );
}

#[test]
fn blank_ids_and_attributes_are_paired_by_position_too() {
    // Functional sides without obj_id.
    let task = FunctionalSidesTask::new(vec![
        ObjectToDescribe {
            id: "bed_0".into(),
            description: "a bed".into(),
        },
        ObjectToDescribe {
            id: "desk_1".into(),
            description: "a desk".into(),
        },
    ])
    .unwrap();
    let vlm = Scripted::queue(
        "m",
        [json_answer(json!({"assessments": [
            {"obj_id": "", "obj_description": "", "functional_sides": ["left", "right"], "reason": "bed"},
            {"obj_id": "", "obj_description": "", "functional_sides": ["front"], "reason": "desk"},
        ]}))],
    );
    let answers = pollster::block_on(Session::new(&vlm).ask(&task)).unwrap();
    let sides = |id: &str| {
        answers
            .get(&id.to_owned())
            .unwrap()
            .answer()
            .unwrap()
            .sides
            .clone()
    };
    assert_eq!(
        (sides("bed_0"), sides("desk_1")),
        (vec![Side::Left, Side::Right], vec![Side::Front])
    );

    // Attributes without the attribute's name, in prompt order (instance 0: red, wooden;
    // instance 1: red, wooden); an instance that contradicts its position is not paired.
    let views = || InstanceViews {
        front: test_image(),
        size: test_image(),
    };
    let task = AttributeTask::new("chair", ["red", "wooden"], vec![views(), views()]).unwrap();
    let item = |i: i64, sat: bool| json!({"instance": i, "attribute": "", "satisfied": sat, "reason": ""});
    let vlm = Scripted::queue(
        "m",
        [
            json_answer(json!({"category": "chair", "num_instances": 2,
                "assessments": [item(0, true), item(0, false), item(0, true), item(1, true)]})),
            json_answer(json!({"category": "chair", "num_instances": 1,
                "assessments": [{"instance": 0, "attribute": "red", "satisfied": false, "reason": ""}]})),
        ],
    );
    let session = Session::new(&vlm);
    let answers = pollster::block_on(session.ask(&task)).unwrap();
    let verdict = |i: usize, a: &str| {
        answers
            .get(&AttributeKey {
                instance: i,
                attribute: a.into(),
            })
            .and_then(|o| o.answer())
            .map(|v| v.satisfied)
    };
    assert_eq!(
        [
            verdict(0, "red"),
            verdict(0, "wooden"),
            verdict(1, "wooden"),
            verdict(1, "red")
        ],
        [Some(true), Some(false), Some(true), Some(false)]
    );
    // The third item (instance 0 at instance 1's place) was not used; only instance 1's red
    // was asked again, with instance 1's views alone, numbered 0 in the second prompt.
    let second = &vlm.requests()[1];
    assert_eq!(second.images.len(), 2);
    assert!(second.user_text.contains("[\"red\"]"), "{}", second.user_text);
    assert_eq!(session.usage().paired_by_position, 3);
}

#[test]
fn a_reference_category_not_offered_is_unmatched_after_the_re_ask() {
    let task = CategoryMatchingTask::new(["chair", "table"], ["armchair", "desk"]).unwrap();
    let answer = |desk: &str| {
        json_answer(json!({"assessments": [
            {"input_category": "armchair", "matched": true, "matched_reference_category": "chair", "reason": ""},
            {"input_category": "desk", "matched": true, "matched_reference_category": desk, "reason": "a desk"},
        ]}))
    };
    let vlm = Scripted::queue("m", [answer("bench"), answer("bench")]);
    let session = Session::new(&vlm);
    let answers = pollster::block_on(session.ask(&task)).unwrap();
    let desk = answers.get(&"desk".to_owned()).unwrap();
    assert!(
        matches!(desk, Outcome::Answered { answer, note: Some(_), .. } if answer.reference_category.is_none()),
        "{desk:?}"
    );
    // The re-ask listed only the desk.
    assert!(vlm.requests()[1].user_text.contains("[\"desk\"]"));
    assert_eq!(session.usage().unmatched_not_offered, 1);
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
