//! CNT, ATR, OOR and OAR on a small scene, with every expected value worked out by hand:
//! a failing spec, an absent object with `eq,0`, a `surround` group, an unmappable phrase,
//! the reference switches, and a VLM whose answers are all invalid.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use sceneeval_annotation::{AnnotationRow, Annotations};
use sceneeval_fidelity::{
    FidelityEvaluator, FidelityMetric, FidelityParams, MappingStatus, MatchingMethod, MemoViews,
    RelationMapping, Resources,
};
use sceneeval_geom::{Point2, Point3, Vector3, conventions::pose_from_yaw};
use sceneeval_relations::RelationParams;
use sceneeval_scene::{Category, RoomBuilder, Scene, SceneBuilder};
use sceneeval_vlm::{AnswerContent, Scripted, Session, check::test_image};
use serde_json::json;

/// A 4 x 4 m room; a 1 x 1 x 0.8 m table in its centre; four 0.4 x 0.4 x 0.9 m chairs, one on
/// each side, 0.1 m from the table's edges (chair centres 0.8 m from the table's centre);
/// a 0.2 m lamp standing on the table (its bottom at the table top, z = 0.8).
fn scene() -> Scene {
    let chair = |id: &str, x: f64, y: f64| {
        (
            id.to_owned(),
            Vector3::new(0.2, 0.2, 0.45),
            pose_from_yaw(Point3::new(x, y, 0.45), 0.0),
        )
    };
    let mut b = room()
        .add_box(
            "t",
            Category::new("table"),
            Vector3::new(0.5, 0.5, 0.4),
            pose_from_yaw(Point3::new(2.0, 2.0, 0.4), 0.0),
        )
        .add_box(
            "l",
            Category::new("Lamp"),
            Vector3::new(0.1, 0.1, 0.1),
            pose_from_yaw(Point3::new(2.0, 2.0, 0.9), 0.0),
        );
    for (id, h, pose) in [
        chair("c1", 1.2, 2.0),
        chair("c2", 2.8, 2.0),
        chair("c3", 2.0, 1.2),
        chair("c4", 2.0, 2.8),
    ] {
        b = b.add_box(&id, Category::new("chairs"), h, pose);
    }
    b.build().unwrap()
}

fn row() -> AnnotationRow {
    let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
        7,medium,A table with four chairs and a lamp,\
        \"eq,1,table; eq,4,chair; eq,1,lamp; eq,0,tv; eq,2,sofa\",\
        \"eq,1,table,wooden; eq,4,chair,red; lt,1,tv,black\",\
        \"eq,1,surround,0,table,chair:0,chair:1,chair:2,chair:3; eq,4,next_to,0,table,chair; \
        eq,1,on,0,table,lamp; eq,1,left,0,table,lamp; eq,1,in_harmony_with,0,table,chair; \
        eq,0,next_to,0,table,tv\",\
        \"eq,1,middle,table,room; eq,1,against,table,wall\"\n";
    Annotations::from_csv_str(csv).unwrap().rows.remove(0)
}

/// A 4 x 4 m room to add objects to.
fn room() -> SceneBuilder {
    Scene::builder().room_builder(RoomBuilder::rectangle(
        "r0",
        Point2::new(0.0, 0.0),
        Point2::new(4.0, 4.0),
    ))
}

/// Neither a VLM nor views: labels and the lexicon only.
fn offline() -> Resources<'static, Scripted> {
    Resources {
        session: None,
        views: None,
        scene_name: "scene_7",
    }
}

fn params() -> FidelityParams {
    FidelityParams::default()
}

/// Answers ATR and relation-mapping requests: the table is wooden, chairs 0-2 are red and
/// chair 3 is not, and "in_harmony_with" maps to no predicate.
fn scripted() -> Scripted {
    Scripted::from_fn("scripted", |req| {
        let value = match req.task.as_str() {
            "obj_attribute" if req.user_text.contains("\"table\"") => json!({
                "category": "table", "num_instances": 1,
                "assessments": [{"instance": 0, "attribute": "wooden", "satisfied": true, "reason": "oak"}]
            }),
            "obj_attribute" => json!({
                "category": "chair", "num_instances": 4,
                "assessments": (0..4).map(|i| json!({
                    "instance": i, "attribute": "red", "satisfied": i < 3, "reason": format!("chair {i}")
                })).collect::<Vec<_>>()
            }),
            "obj_relationship_mapping" => json!({"assessments": [{
                "key": "4", "relationship": "in_harmony_with", "anchor_object": "table",
                "other_objects": ["chair"], "other_object_counts": [1],
                "relationship_types": null, "sides": [], "reason": "no spatial meaning"
            }]}),
            other => panic!("unexpected task {other}"),
        };
        Ok(AnswerContent::Json { value })
    })
}

#[test]
fn labels_and_lexicon_without_vlm() {
    let (scene, row) = (scene(), row());
    let ev = FidelityEvaluator::new(params(), RelationParams::default()).unwrap();
    let res = offline();
    let out = ev.evaluate(&scene, &row, &FidelityMetric::ALL, &res).unwrap();
    let r = &out.report;
    // CNT: table 1 (eq,1 yes), chairs 4 (labelled "chairs": plural), lamp 1 ("Lamp"),
    // tv 0 (eq,0 yes), sofa 0 (eq,2 no) -> 4/5.
    let cnt = r.cnt.as_ref().unwrap();
    let verdicts: Vec<Option<bool>> = cnt.specs.iter().map(|s| s.satisfied).collect();
    assert_eq!(
        verdicts,
        [Some(true), Some(true), Some(true), Some(true), Some(false)]
    );
    assert_eq!(cnt.unanswered, 0);
    assert_eq!(r.summary.cnt, Some(0.8));
    assert_eq!(cnt.message, "4/5 requirements are satisfied.");
    // ATR: not judged without a VLM. The table and the chairs are present, so their specs
    // have no verdict (not "false"); the absent tv is decided by its quantifier (lt,1 holds
    // on a count of 0) without asking.
    assert_eq!(r.summary.atr, None);
    let atr = r.atr.as_ref().unwrap();
    assert!(atr.not_judged.is_some());
    let verdicts: Vec<Option<bool>> = atr.specs.iter().map(|s| s.satisfied).collect();
    assert_eq!(verdicts, [None, None, Some(true)]);
    assert_eq!((atr.satisfied, atr.score), (None, None));
    let json = serde_json::to_value(atr).unwrap();
    assert!(json["satisfied"].is_null() && json["score"].is_null(), "{json}");
    assert!(
        json["specs"][0]["satisfied"].is_null() && json["specs"][0]["count_satisfied"].is_null(),
        "{json}"
    );
    // OOR: surround: 1 anchor x C(4,4) = 1 group, four chairs evenly around: 1 satisfied (yes);
    // next_to: 1 x C(4,1) = 4 groups, each gap 0.1 m: 4 (eq,4 yes); on: the lamp rests on the
    // table: 1 (yes); left: the lamp is over the table, not beyond its -x face: 0 (no);
    // in_harmony_with: not in the lexicon, no VLM: unmapped (no); eq,0 next_to tv: the tv is
    // absent, the quantifier allows 0 (yes) -> 4/6.
    let oor = r.oor.as_ref().unwrap();
    let counts: Vec<(u64, u64, Option<bool>)> = oor
        .specs
        .iter()
        .map(|s| (s.num_candidate_groups, s.count_satisfied, s.satisfied))
        .collect();
    assert_eq!(
        counts,
        [
            (1, 1, Some(true)),
            (4, 4, Some(true)),
            (1, 1, Some(true)),
            (1, 0, Some(false)),
            (0, 0, Some(false)),
            (0, 0, Some(true))
        ]
    );
    assert_eq!(oor.specs[0].groups[0].others, ["c1", "c2", "c3", "c4"]);
    assert_eq!(oor.specs[0].mapping.relations, ["surround"]);
    assert_eq!(oor.specs[3].mapping.relations, ["side_of(left)"]);
    assert_eq!(oor.specs[4].mapping.status, MappingStatus::Unmapped);
    assert!(!oor.specs[5].all_objects_present);
    assert_eq!(r.summary.oor, Some(4.0 / 6.0));
    // OAR: the table is in the middle of the room (yes) and 1.5 m from every wall (no) -> 1/2.
    let oar = r.oar.as_ref().unwrap();
    assert_eq!(oar.specs[0].mapping.relations, ["middle_of_room"]);
    assert_eq!(oar.specs[1].mapping.relations, ["against_wall"]);
    assert_eq!(r.summary.oar, Some(0.5));
    // The matching: 6 of 6 objects, 3 of 5 categories.
    assert_eq!(
        r.matching.as_ref().unwrap().message,
        "Matched 3/5 categories. Matched 6/6 objects."
    );
}

#[test]
fn scripted_vlm_judges_attributes_and_maps_unknown_words() {
    let (scene, row) = (scene(), row());
    let ev = FidelityEvaluator::new(params(), RelationParams::default()).unwrap();
    let vlm = scripted();
    let session = Session::new(&vlm);
    let views = MemoViews::new(|_, _| Ok(test_image()));
    let res = Resources {
        session: Some(&session),
        views: Some(&views),
        scene_name: "scene_7",
    };
    let out = ev.evaluate(&scene, &row, &FidelityMetric::ALL, &res).unwrap();
    let r = &out.report;
    // ATR: wooden table 1 of 1 (eq,1 yes); red chairs 3 of 4 (eq,4 no); tv absent and lt,1
    // allows 0 (yes, not asked) -> 2/3.
    let atr = r.atr.as_ref().unwrap();
    let got: Vec<(Option<u64>, Option<bool>)> = atr
        .specs
        .iter()
        .map(|s| (s.count_satisfied, s.satisfied))
        .collect();
    assert_eq!(
        got,
        [
            (Some(1), Some(true)),
            (Some(3), Some(false)),
            (Some(0), Some(true))
        ]
    );
    assert_eq!(atr.satisfied, Some(2));
    assert_eq!(r.summary.atr, Some(2.0 / 3.0));
    assert_eq!(atr.specs[1].assessments[3].reason, "chair 3");
    // OOR: the unknown word went to the VLM, which found no predicate: unmapped, unsatisfied.
    let oor = r.oor.as_ref().unwrap();
    assert_eq!(oor.specs[4].mapping.status, MappingStatus::Unmapped);
    assert_eq!(oor.specs[4].mapping.reason, "no spatial meaning");
    assert_eq!(r.summary.oor, Some(4.0 / 6.0));
    // Requests: two attribute specs with objects, one mapping: 3; views: front + size of the
    // table and the four chairs, each made once.
    assert_eq!(vlm.requests().len(), 3);
    assert_eq!(r.vlm_usage.unwrap().requests, 3);
    assert_eq!(r.views_rendered, 10);
}

#[test]
fn reference_switches() {
    let (scene, row) = (scene(), row());
    let p = FidelityParams {
        matching: MatchingMethod::Labels,
        relation_mapping: RelationMapping::Lexicon,
        ..FidelityParams::reference()
    };
    let ev = FidelityEvaluator::new(p, RelationParams::default()).unwrap();
    let vlm = scripted();
    let session = Session::new(&vlm);
    let views = MemoViews::new(|_, _| Ok(test_image()));
    let res = Resources {
        session: Some(&session),
        views: Some(&views),
        scene_name: "scene_7",
    };
    let r = ev
        .evaluate(&scene, &row, &FidelityMetric::ALL, &res)
        .unwrap()
        .report;
    // Q5: the absent tv fails its specs (ATR lt,1 and OOR eq,0). Q4: the unmapped relation
    // counts as satisfied. ATR 1/3; OOR: surround, next_to, on, unmapped = 4/6.
    assert_eq!(r.summary.atr, Some(1.0 / 3.0));
    let v: Vec<Option<bool>> = r
        .oor
        .as_ref()
        .unwrap()
        .specs
        .iter()
        .map(|s| s.satisfied)
        .collect();
    let (t, f) = (Some(true), Some(false));
    assert_eq!(v, [t, t, t, f, t, f]);
    // Q22: with the anchor allowed as target nothing changes here (different categories).
    assert_eq!(r.summary.oor, Some(4.0 / 6.0));
}

#[test]
fn unanswered_questions_are_never_scored_as_unsatisfied() {
    let (scene, row) = (scene(), row());
    let vlm = Scripted::from_fn("broken", |_| {
        Ok(AnswerContent::Json {
            value: json!({"nonsense": true}),
        })
    });
    let session = Session::new(&vlm);
    let views = MemoViews::new(|_, _| Ok(test_image()));
    let res = Resources {
        session: Some(&session),
        views: Some(&views),
        scene_name: "scene_7",
    };
    // Labels matching: every ATR question and the mapping question go unanswered.
    let ev = FidelityEvaluator::new(params(), RelationParams::default()).unwrap();
    let r = ev
        .evaluate(&scene, &row, &FidelityMetric::ALL, &res)
        .unwrap()
        .report;
    // ATR: the table (eq,1) could have 0 or 1 wooden instance, the chairs (eq,4) 0 to 4 red
    // ones: no verdict, left out of the score; the absent tv (lt,1) is decided without asking
    // -> 1/1, 2 unanswered.
    let atr = r.atr.as_ref().unwrap();
    for s in &atr.specs[..2] {
        assert!(s.unanswered.is_some() && s.satisfied.is_none(), "{s:?}");
        assert!(s.assessments.iter().all(|a| a.satisfied.is_none()));
        assert_eq!(s.count_satisfied, Some(0));
    }
    assert_eq!(
        (atr.satisfied, atr.unanswered, atr.total, atr.score),
        (Some(1), 2, 3, Some(1.0))
    );
    assert_eq!(
        atr.message,
        "1/1 requirements are satisfied; 2 of 3 not decided (an answer they need is missing)."
    );
    // OOR: in_harmony_with has no valid mapping: no verdict (before: unsatisfied); the other
    // five are the lexicon's: 4 of 5.
    let oor = r.oor.as_ref().unwrap();
    let unmapped = &oor.specs[4];
    assert_eq!(unmapped.mapping.status, MappingStatus::Unanswered);
    assert_eq!(unmapped.satisfied, None);
    assert!(
        unmapped
            .unanswered
            .as_deref()
            .unwrap()
            .starts_with("the VLM gave no valid mapping"),
        "{unmapped:?}"
    );
    assert_eq!((oor.unanswered, r.summary.oor), (1, Some(0.8)));
    let json = serde_json::to_value(oor).unwrap();
    assert!(
        json["specs"][4]["satisfied"].is_null() && json["unanswered"] == 1,
        "{json}"
    );

    // VLM matching: no object has a valid answer, any could be of any category: no CNT spec
    // has a verdict (before: every object unmatched, CNT 1/5).
    let ev = FidelityEvaluator::new(
        FidelityParams {
            matching: MatchingMethod::Vlm,
            ..params()
        },
        RelationParams::default(),
    )
    .unwrap();
    let out = ev.evaluate(&scene, &row, &FidelityMetric::ALL, &res).unwrap();
    assert_eq!(out.matching.as_ref().unwrap().unanswered.len(), 6);
    assert_eq!(out.report.matching.as_ref().unwrap().unanswered, 6);
    let cnt = out.report.cnt.as_ref().unwrap();
    assert_eq!((cnt.unanswered, out.report.summary.cnt), (5, None));
    assert!(
        cnt.specs[0]
            .unanswered
            .as_deref()
            .unwrap()
            .contains("6 object(s) without a matching answer")
    );
}

/// Matched 1 table of eq,1 and one object unanswered: eq,1 could become 2 (no verdict);
/// ge,1 holds whatever the unknown object is.
#[test]
fn an_unanswered_object_leaves_only_the_specs_it_could_change_undecided() {
    let scene = room()
        .add_box(
            "t",
            Category::new("table"),
            Vector3::new(0.5, 0.5, 0.4),
            pose_from_yaw(Point3::new(2.0, 2.0, 0.4), 0.0),
        )
        .add_box(
            "x",
            Category::new("thing"),
            Vector3::new(0.2, 0.2, 0.2),
            pose_from_yaw(Point3::new(1.0, 1.0, 0.2), 0.0),
        )
        .build()
        .unwrap();
    let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
        7,easy,A table,\"eq,1,table; ge,1,table; lt,1,sofa; ge,3,chair\",,,\n";
    let row = Annotations::from_csv_str(csv).unwrap().rows.remove(0);
    // The table is recognised; the other object's answers are refusals.
    let vlm = Scripted::from_fn("m", |req| {
        Ok(if req.images[0].blake3_hex() == test_image().blake3_hex() {
            AnswerContent::Json {
                value: json!({"provided_categories": [], "matched": true, "matched_category": "table",
                              "actual_category": "table", "reason": "a table"}),
            }
        } else {
            AnswerContent::Refusal { text: "no".into() }
        })
    });
    let session = Session::new(&vlm);
    let views = MemoViews::new(|id, _| {
        Ok(if id == "t" {
            test_image()
        } else {
            sceneeval_vlm::encode_rgb_png(1, 1, &[0, 0, 0]).unwrap()
        })
    });
    let res = Resources {
        session: Some(&session),
        views: Some(&views),
        scene_name: "scene_7",
    };
    let ev = FidelityEvaluator::new(
        FidelityParams {
            matching: MatchingMethod::Vlm,
            ..params()
        },
        RelationParams::default(),
    )
    .unwrap();
    let r = ev
        .evaluate(&scene, &row, &[FidelityMetric::Cnt], &res)
        .unwrap()
        .report;
    let cnt = r.cnt.unwrap();
    // eq,1 table: 1 or 2 -> none; ge,1 table: yes either way; lt,1 sofa: 0 or 1 -> none;
    // ge,3 chair: at most 1 -> no either way. 1/2 decided, 2 unanswered.
    let v: Vec<Option<bool>> = cnt.specs.iter().map(|s| s.satisfied).collect();
    assert_eq!(v, [None, Some(true), None, Some(false)]);
    assert_eq!((cnt.unanswered, cnt.score), (2, Some(0.5)));
}

/// The relation-mapping answers of a model that keeps the prompt's order but leaves every key
/// empty, or copies them: the mapping prompt lists the specs `- key "<k>": ...`.
fn mapping_model(copy_keys: bool) -> Scripted {
    Scripted::from_fn("m", move |req| {
        let keys: Vec<String> = req
            .user_text
            .split("- key \"")
            .skip(1)
            .filter_map(|rest| rest.split('"').next().map(str::to_owned))
            .collect();
        let key = |k: &str| if copy_keys { k.to_owned() } else { String::new() };
        let value = match req.task.as_str() {
            // OOR specs 0-5 of `row()`, in order.
            "obj_relationship_mapping" => {
                let items = [
                    ("table", vec![("chair", 4)], json!(["surround"]), json!([null])),
                    ("table", vec![("chair", 1)], json!(["next_to"]), json!([null])),
                    ("table", vec![("lamp", 1)], json!(["on_top"]), json!([null])),
                    ("table", vec![("lamp", 1)], json!(["side_of"]), json!(["left"])),
                    ("table", vec![("chair", 1)], json!(null), json!([])),
                    ("table", vec![("tv", 1)], json!(["next_to"]), json!([null])),
                ];
                let assessments: Vec<_> = items
                    .iter()
                    .zip(&keys)
                    .map(|((anchor, others, types, sides), k)| {
                        json!({"key": key(k), "relationship": "", "anchor_object": anchor,
                               "other_objects": others.iter().map(|(c, _)| *c).collect::<Vec<_>>(),
                               "other_object_counts": others.iter().map(|(_, n)| *n).collect::<Vec<_>>(),
                               "relationship_types": types, "sides": sides, "reason": "r"})
                    })
                    .collect();
                json!({ "assessments": assessments })
            }
            "arch_relationship_mapping" => json!({"assessments": [
                {"key": key(&keys[0]), "relationship": "", "target_object": "table",
                 "architectural_element_type": "room", "relationship_type": "middle_of_room",
                 "specific_floors": [], "reason": "r"},
                {"key": key(&keys[1]), "relationship": "", "target_object": "table",
                 "architectural_element_type": "wall", "relationship_type": "against_wall",
                 "specific_floors": [], "reason": "r"},
            ]}),
            other => panic!("unexpected task {other}"),
        };
        Ok(AnswerContent::Json { value })
    })
}

#[test]
fn a_model_that_leaves_every_key_empty_scores_as_one_that_copies_them() {
    let (scene, row) = (scene(), row());
    let ev = FidelityEvaluator::new(
        FidelityParams {
            relation_mapping: RelationMapping::Vlm,
            ..params()
        },
        RelationParams::default(),
    )
    .unwrap();
    let run = |vlm: &Scripted| {
        let session = Session::new(vlm);
        let res = Resources {
            session: Some(&session),
            views: None,
            scene_name: "scene_7",
        };
        let metrics = [FidelityMetric::Oor, FidelityMetric::Oar];
        ev.evaluate(&scene, &row, &metrics, &res).unwrap().report
    };
    let copied = run(&mapping_model(true));
    let blank = run(&mapping_model(false));
    // As the lexicon run: OOR 4/6 (the sixth, eq,0 next_to tv, holds: the tv is absent), OAR
    // 1/2. Before, blank keys gave OOR = OAR = 0 with no warning.
    assert_eq!(copied.summary.oor, Some(4.0 / 6.0));
    assert_eq!(copied.summary.oar, Some(0.5));
    assert_eq!(blank.summary, copied.summary);
    let verdicts = |r: &sceneeval_fidelity::FidelityReport| {
        let oor = r.oor.as_ref().unwrap().specs.iter().map(|s| s.satisfied);
        let oar = r.oar.as_ref().unwrap().specs.iter().map(|s| s.satisfied);
        oor.chain(oar).collect::<Vec<_>>()
    };
    assert_eq!(verdicts(&blank), verdicts(&copied));
    // The recovery is counted and noted in the evidence.
    let (b, c) = (blank.vlm_usage.unwrap(), copied.vlm_usage.unwrap());
    assert_eq!((b.paired_by_position, c.paired_by_position), (8, 0));
    assert_eq!((b.requests, c.requests), (2, 2));
    let reason = &blank.oor.as_ref().unwrap().specs[0].mapping.reason;
    assert_eq!(reason, "r (paired by position: item 0 of the answer had no key)");
}

#[test]
fn candidate_group_cap_warns() {
    let (scene, row) = (scene(), row());
    let ev = FidelityEvaluator::new(
        FidelityParams {
            max_candidate_groups: 2,
            ..params()
        },
        RelationParams::default(),
    )
    .unwrap();
    let res = offline();
    let r = ev
        .evaluate(&scene, &row, &[FidelityMetric::Oor], &res)
        .unwrap()
        .report;
    let next_to = &r.oor.as_ref().unwrap().specs[1];
    // 4 groups, 2 evaluated (both satisfied): 2 of eq,4 -> no.
    assert_eq!((next_to.num_candidate_groups, next_to.groups_evaluated), (4, 2));
    assert_eq!(next_to.satisfied, Some(false));
    assert!(
        r.warnings.iter().any(|w| w.contains("max_candidate_groups")),
        "{:?}",
        r.warnings
    );
    assert!(r.cnt.is_none());
}

#[test]
fn matching_from_a_reference_file() {
    let (scene, row) = (scene(), row());
    let dir = tempfile::tempdir().unwrap();
    // The reference's obj_matching_result.json shape: the lamp is called a chair here, so
    // CNT sees 5 chairs (eq,4 no) and no lamp (eq,1 no): table, tv eq,0 -> 2/5.
    let file = dir.path().join("scene_7").join("obj_matching_result.json");
    std::fs::create_dir_all(file.parent().unwrap()).unwrap();
    std::fs::write(
        &file,
        serde_json::to_string(&json!({
            "per_category": {
                "table": {"t": "a table"},
                "chair": {"c1": "", "c2": "", "c3": "", "c4": "", "l": "looks like a chair"},
                "lamp": {}, "tv": {}, "sofa": {}
            },
            "not_matched_objs": {},
            "actual_categories": {"l": "chair"}
        }))
        .unwrap(),
    )
    .unwrap();
    let ev = FidelityEvaluator::new(
        FidelityParams {
            matching: MatchingMethod::File(dir.path().to_owned()),
            ..params()
        },
        RelationParams::default(),
    )
    .unwrap();
    let res = offline();
    let out = ev.evaluate(&scene, &row, &[FidelityMetric::Cnt], &res).unwrap();
    assert_eq!(out.report.summary.cnt, Some(0.4));
    assert_eq!(
        out.matching.as_ref().unwrap().file.as_deref(),
        Some(file.as_path())
    );
    // An object the scene does not have is an error naming it.
    std::fs::write(
        &file,
        r#"{"per_category": {"table": {"ghost": ""}}, "not_matched_objs": {}}"#,
    )
    .unwrap();
    let err = ev
        .evaluate(&scene, &row, &[FidelityMetric::Cnt], &res)
        .unwrap_err();
    assert!(err.to_string().contains("ghost"), "{err}");
    // A category the annotation does not have is an error too.
    std::fs::write(&file, r#"{"per_category": {"bed": {}}, "not_matched_objs": {}}"#).unwrap();
    let err = ev
        .evaluate(&scene, &row, &[FidelityMetric::Cnt], &res)
        .unwrap_err();
    assert!(
        err.to_string().contains("\"bed\" is not an annotated category"),
        "{err}"
    );
}

#[test]
fn malformed_entries_are_errors_and_several_attributes_are_one_spec() {
    let scene = scene();
    let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
        7,easy,x,\"eq,1,table\",\"eq,1,table,wooden,round\",,\n";
    let row = Annotations::from_csv_str(csv).unwrap().rows.remove(0);
    let ev = FidelityEvaluator::new(params(), RelationParams::default()).unwrap();
    let vlm = Scripted::from_fn("m", |req| {
        assert!(
            req.user_text.contains("[\"wooden\",\"round\"]"),
            "{}",
            req.user_text
        );
        Ok(AnswerContent::Json {
            value: json!({"category": "table", "num_instances": 1, "assessments": [
                {"instance": 0, "attribute": "wooden", "satisfied": true, "reason": ""},
                {"instance": 0, "attribute": "round", "satisfied": false, "reason": "square"}]}),
        })
    });
    let session = Session::new(&vlm);
    let views = MemoViews::new(|_, _| Ok(test_image()));
    let res = Resources {
        session: Some(&session),
        views: Some(&views),
        scene_name: "scene_7",
    };
    // Q6: both attributes are required of the one table: wooden but not round -> 0 of eq,1.
    let r = ev
        .evaluate(&scene, &row, &[FidelityMetric::Atr], &res)
        .unwrap()
        .report;
    let spec = &r.atr.as_ref().unwrap().specs[0];
    assert_eq!(spec.attributes, ["wooden", "round"]);
    assert_eq!((spec.count_satisfied, spec.satisfied), (Some(0), Some(false)));
    // Q18: an unknown quantifier is an error naming the row, column and entry.
    let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n7,easy,x,\"about,1,table\",,,\n";
    let row = Annotations::from_csv_str(csv).unwrap().rows.remove(0);
    let err = ev
        .evaluate(&scene, &row, &[FidelityMetric::Cnt], &res)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("row \"7\", ObjCount") && err.contains("about,1,table"),
        "{err}"
    );
}

/// Objects of HSSD assets state their WordNet synset as category (`bed.n.01`, `chair.n.01`):
/// matching by labels reads them as `bed` and `chair`, as the plausibility tables do (before,
/// no synset matched any annotated category and both specs failed).
#[test]
fn labels_read_synset_categories() {
    let scene = room()
        .add_box(
            "b",
            Category::new("bed.n.01"),
            Vector3::new(1.0, 0.8, 0.3),
            pose_from_yaw(Point3::new(2.0, 2.0, 0.3), 0.0),
        )
        .add_box(
            "c",
            Category::new("Chair.n.01"),
            Vector3::new(0.2, 0.2, 0.45),
            pose_from_yaw(Point3::new(0.5, 0.5, 0.45), 0.0),
        )
        .build()
        .unwrap();
    let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
        7,easy,A bed and a chair,\"eq,1,bed; eq,1,chair\",,,\n";
    let row = Annotations::from_csv_str(csv).unwrap().rows.remove(0);
    let ev = FidelityEvaluator::new(params(), RelationParams::default()).unwrap();
    let res = offline();
    let out = ev.evaluate(&scene, &row, &[FidelityMetric::Cnt], &res).unwrap();
    // CNT: one bed (bed.n.01) and one chair (Chair.n.01): 2/2.
    let cnt = out.report.cnt.unwrap();
    let found: Vec<(&str, &[String])> = cnt
        .specs
        .iter()
        .map(|s| (s.category.as_str(), s.objects.as_slice()))
        .collect();
    assert_eq!(
        found,
        [("bed", &["b".to_owned()][..]), ("chair", &["c".to_owned()][..])]
    );
    assert_eq!(out.report.summary.cnt, Some(1.0));
}

/// The endpoint fails the relation-mapping request (503 on every attempt, say) and the OARel
/// column has a malformed entry: OOR and OAR are listed as failed with the reason; CNT and ATR
/// are computed as without the failures.
#[test]
fn a_failed_metric_never_erases_another() {
    let scene = scene();
    let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
        7,medium,x,\"eq,1,table; eq,4,chair\",\"eq,1,table,wooden\",\
        \"eq,1,in_harmony_with,0,table,chair\",\"about,1,middle,table,room\"\n";
    let row = Annotations::from_csv_str(csv).unwrap().rows.remove(0);
    let inner = scripted();
    let vlm = Scripted::from_fn("scripted", move |req| {
        if req.task == "obj_relationship_mapping" {
            return Err(sceneeval_vlm::VlmError::Backend {
                task: req.task.clone(),
                model: "scripted".into(),
                permanent: false,
                source: "503 Service Unavailable".into(),
            });
        }
        pollster::block_on(sceneeval_vlm::Vlm::answer(&inner, req)).map(|a| a.content)
    });
    let session = Session::new(&vlm);
    let views = MemoViews::new(|_, _| Ok(test_image()));
    let res = Resources {
        session: Some(&session),
        views: Some(&views),
        scene_name: "scene_7",
    };
    let ev = FidelityEvaluator::new(params(), RelationParams::default()).unwrap();
    let out = pollster::block_on(ev.evaluate_async(&scene, &row, &FidelityMetric::ALL, &res));
    let failed: Vec<(FidelityMetric, bool)> = out.failures.iter().map(|f| (f.metric, f.is_vlm())).collect();
    assert_eq!(
        failed,
        [(FidelityMetric::Oor, true), (FidelityMetric::Oar, false)]
    );
    assert!(
        out.failures[1]
            .error
            .to_string()
            .contains("about,1,middle,table,room"),
        "{}",
        out.failures[1].error
    );
    // CNT 2/2 and ATR 1/1 (the wooden table) as ever; OOR and OAR absent.
    let r = &out.report;
    assert_eq!((r.summary.cnt, r.summary.atr), (Some(1.0), Some(1.0)));
    assert!(r.oor.is_none() && r.oar.is_none());
    assert_eq!((r.summary.oor, r.summary.oar), (None, None));
    // The all-or-nothing call reports the first failure.
    let err = ev.evaluate(&scene, &row, &FidelityMetric::ALL, &res).unwrap_err();
    assert!(
        matches!(err, sceneeval_fidelity::FidelityError::Vlm { .. }),
        "{err}"
    );
}

/// A model whose answers arrive in another order than the questions were asked: each request
/// waits a number of polls that depends on its text and images.
struct OutOfOrder<'a>(&'a Scripted);

/// Ready after `n` more polls (waking itself each time).
struct Polls(u32);

impl std::future::Future for Polls {
    type Output = ();

    fn poll(mut self: std::pin::Pin<&mut Self>, cx: &mut std::task::Context<'_>) -> std::task::Poll<()> {
        if self.0 == 0 {
            return std::task::Poll::Ready(());
        }
        self.0 -= 1;
        cx.waker().wake_by_ref();
        std::task::Poll::Pending
    }
}

impl sceneeval_vlm::Vlm for OutOfOrder<'_> {
    fn model(&self) -> &str {
        self.0.model()
    }

    async fn answer(
        &self,
        request: &sceneeval_vlm::VlmRequest,
    ) -> Result<sceneeval_vlm::Answer, sceneeval_vlm::VlmError> {
        let mut h = request.user_text.len() as u32;
        for i in &request.images {
            h = h
                .wrapping_mul(31)
                .wrapping_add(u32::from(i.bytes()[i.bytes().len() / 2]));
        }
        Polls(h % 7 * 3).await;
        self.0.answer(request).await
    }
}

#[test]
fn the_report_does_not_depend_on_the_order_answers_arrive_in() {
    let (scene, row) = (scene(), row());
    // Each object's front view is its own image; the model tells them apart by it.
    let grey = |id: &str| match id {
        "t" => 10,
        "l" => 20,
        _ => 30 + id.as_bytes()[1],
    };
    let views = MemoViews::new(move |id, kind| {
        let k = if kind == sceneeval_fidelity::ViewKind::Front {
            0
        } else {
            100
        };
        Ok(sceneeval_vlm::encode_rgb_png(1, 1, &[grey(id) + k, 0, 0]).unwrap())
    });
    let model = || {
        let attributes = scripted();
        Scripted::from_fn("m", move |req| {
            if req.task != "obj_matching" {
                return pollster::block_on(sceneeval_vlm::Vlm::answer(&attributes, req)).map(|a| a.content);
            }
            let g = req.images[0].bytes();
            let is = |n: u8| sceneeval_vlm::encode_rgb_png(1, 1, &[n, 0, 0]).unwrap().bytes() == g;
            let category = if is(10) {
                "table"
            } else if is(20) {
                "lamp"
            } else {
                "chair"
            };
            Ok(AnswerContent::Json {
                value: json!({"provided_categories": [], "matched": true, "matched_category": category,
                              "actual_category": category, "reason": category}),
            })
        })
    };
    let ev = FidelityEvaluator::new(
        FidelityParams {
            matching: MatchingMethod::Vlm,
            ..params()
        },
        RelationParams::default(),
    )
    .unwrap();
    let in_order = model();
    let session = Session::new(&in_order);
    let res = Resources {
        session: Some(&session),
        views: Some(&views),
        scene_name: "scene_7",
    };
    let a = ev.evaluate(&scene, &row, &FidelityMetric::ALL, &res).unwrap();
    let shuffled = model();
    let session = Session::new(OutOfOrder(&shuffled));
    let res = Resources {
        session: Some(&session),
        views: Some(&views),
        scene_name: "scene_7",
    };
    let b = ev.evaluate(&scene, &row, &FidelityMetric::ALL, &res).unwrap();
    // The answers arrived in another order...
    let tasks = |v: &Scripted| {
        v.requests()
            .iter()
            .map(|r| (r.task.clone(), r.images.len()))
            .collect::<Vec<_>>()
    };
    let order = |v: &Scripted| {
        v.requests()
            .iter()
            .map(|r| r.user_text.len() + r.images.len())
            .collect::<Vec<_>>()
    };
    assert_eq!(tasks(&in_order).len(), tasks(&shuffled).len());
    assert_ne!(order(&in_order), order(&shuffled));
    // ... and the report and the matching are the same, byte for byte.
    assert_eq!(
        serde_json::to_string(&a.report).unwrap(),
        serde_json::to_string(&b.report).unwrap()
    );
    assert_eq!(a.matching, b.matching);
    // As with labels: 6 objects matched, CNT 4/5.
    assert_eq!(a.report.summary.cnt, Some(0.8));
}
