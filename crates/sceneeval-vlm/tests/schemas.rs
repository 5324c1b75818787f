//! The response schemas: strict mode, the reference's field names, field order, and the name
//! lists the schemas offer against the relation vocabulary.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use sceneeval_relations::{OBJECT_ARCH_NAMES, OBJECT_OBJECT_NAMES};
use sceneeval_vlm::check::EndpointCheckResponse;
use sceneeval_vlm::schema::{check_strict, ordered, strict_schema_for};
use sceneeval_vlm::tasks::*;
use sceneeval_vlm::{ResponseSchema, TaskKind};
use serde_json::{Value, json};

fn all() -> Vec<(TaskKind, ResponseSchema)> {
    vec![
        (
            TaskKind::ObjMatching,
            strict_schema_for::<ObjMatchingResponse>("obj_matching").unwrap(),
        ),
        (
            TaskKind::ObjAttribute,
            strict_schema_for::<ObjAttributeResponse>("obj_attribute").unwrap(),
        ),
        (
            TaskKind::ObjSupportType,
            strict_schema_for::<SupportTypeResponse>("obj_support_type").unwrap(),
        ),
        (
            TaskKind::ObjFunctionalSides,
            strict_schema_for::<FunctionalSidesResponse>("obj_functional_sides").unwrap(),
        ),
        (
            TaskKind::ObjRelationshipMapping,
            strict_schema_for::<ObjRelationshipMappingResponse>("obj_relationship_mapping").unwrap(),
        ),
        (
            TaskKind::ArchRelationshipMapping,
            strict_schema_for::<ArchRelationshipMappingResponse>("arch_relationship_mapping").unwrap(),
        ),
        (
            TaskKind::CategoryMatchingForSemanticColor,
            strict_schema_for::<CategoryMatchingResponse>("category_matching_for_semantic_color").unwrap(),
        ),
        (
            TaskKind::EndpointCheck,
            strict_schema_for::<EndpointCheckResponse>("endpoint_check").unwrap(),
        ),
    ]
}

/// Every schema node, with its JSON pointer.
fn nodes<'a>(v: &'a Value, at: String, out: &mut Vec<(String, &'a Value)>) {
    out.push((at.clone(), v));
    if let Some(props) = v.get("properties").and_then(Value::as_object) {
        for (k, child) in props {
            nodes(child, format!("{at}/properties/{k}"), out);
        }
    }
    if let Some(items) = v.get("items") {
        nodes(items, format!("{at}/items"), out);
    }
}

#[test]
fn every_schema_is_strict() {
    for (kind, s) in all() {
        assert_eq!(s.name, kind.name());
        check_strict(&s.schema).unwrap_or_else(|e| panic!("{kind}: {e}"));
        let mut all_nodes = Vec::new();
        nodes(&s.schema, String::new(), &mut all_nodes);
        for (at, node) in all_nodes {
            let map = node.as_object().unwrap();
            assert!(!map.contains_key("format"), "{kind}{at}: format");
            assert!(
                !map.contains_key("$ref") && !map.contains_key("description"),
                "{kind}{at}"
            );
            if let Some(props) = map.get("properties").and_then(Value::as_object) {
                assert_eq!(map["additionalProperties"], false, "{kind}{at}");
                let required: Vec<&str> = map["required"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_str().unwrap())
                    .collect();
                assert_eq!(required.len(), props.len(), "{kind}{at}: every field required");
            }
        }
    }
}

/// Field names of every object in the schema, in declaration order, by pointer.
fn fields(s: &ResponseSchema) -> Vec<(String, Vec<String>)> {
    let mut all_nodes = Vec::new();
    nodes(&s.schema, String::new(), &mut all_nodes);
    all_nodes
        .into_iter()
        .filter(|(_, n)| n.get("properties").is_some())
        .map(|(at, n)| {
            let req = n["required"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_str().unwrap().to_owned())
                .collect();
            (at, req)
        })
        .collect()
}

#[test]
fn field_names_are_the_reference_ones_plus_key() {
    // Reference pydantic models (metrics/*.py), in their declaration order; `key` is ours.
    type Objects<'a> = Vec<(&'a str, Vec<&'a str>)>;
    let expected: Vec<(TaskKind, Objects<'_>)> = vec![
        (
            TaskKind::ObjMatching,
            vec![(
                "",
                vec![
                    "provided_categories",
                    "matched",
                    "matched_category",
                    "actual_category",
                    "reason",
                ],
            )],
        ),
        (
            TaskKind::ObjAttribute,
            vec![
                ("", vec!["category", "num_instances", "assessments"]),
                (
                    "/properties/assessments/items",
                    vec!["instance", "attribute", "satisfied", "reason"],
                ),
            ],
        ),
        (
            TaskKind::ObjSupportType,
            vec![("", vec!["support_type", "reason"])],
        ),
        (
            TaskKind::ObjFunctionalSides,
            vec![
                ("", vec!["assessments"]),
                (
                    "/properties/assessments/items",
                    vec!["obj_id", "obj_description", "functional_sides", "reason"],
                ),
            ],
        ),
        (
            TaskKind::ObjRelationshipMapping,
            vec![
                ("", vec!["assessments"]),
                (
                    "/properties/assessments/items",
                    vec![
                        "key",
                        "relationship",
                        "anchor_object",
                        "other_objects",
                        "other_object_counts",
                        "relationship_types",
                        "sides",
                        "reason",
                    ],
                ),
            ],
        ),
        (
            TaskKind::ArchRelationshipMapping,
            vec![
                ("", vec!["assessments"]),
                (
                    "/properties/assessments/items",
                    vec![
                        "key",
                        "relationship",
                        "target_object",
                        "architectural_element_type",
                        "relationship_type",
                        "specific_floors",
                        "reason",
                    ],
                ),
            ],
        ),
        (
            TaskKind::CategoryMatchingForSemanticColor,
            vec![
                ("", vec!["assessments"]),
                (
                    "/properties/assessments/items",
                    vec![
                        "input_category",
                        "matched",
                        "matched_reference_category",
                        "reason",
                    ],
                ),
            ],
        ),
        (TaskKind::EndpointCheck, vec![("", vec!["colour", "reason"])]),
    ];
    let schemas = all();
    for (kind, want) in expected {
        let (_, s) = schemas.iter().find(|(k, _)| *k == kind).unwrap();
        let got = fields(s);
        let want: Vec<(String, Vec<String>)> = want
            .into_iter()
            .map(|(at, f)| (at.to_owned(), f.into_iter().map(str::to_owned).collect()))
            .collect();
        assert_eq!(got, want, "{kind}");
        // Serialised in that order too (the order a model writes the fields in).
        let text = serde_json::to_string(s).unwrap();
        let positions: Vec<usize> = want
            .last()
            .unwrap()
            .1
            .iter()
            .map(|f| text.find(&format!("\"{f}\":{{")).unwrap())
            .collect();
        assert!(positions.windows(2).all(|w| w[0] < w[1]), "{kind}: {text}");
    }
}

fn enum_at<'a>(s: &'a ResponseSchema, pointer: &str) -> Vec<&'a str> {
    s.schema
        .pointer(pointer)
        .and_then(Value::as_array)
        .unwrap_or_else(|| panic!("{pointer}"))
        .iter()
        .filter_map(Value::as_str)
        .collect()
}

#[test]
fn name_lists_match_the_relation_vocabulary() {
    let oo = strict_schema_for::<ObjRelationshipMappingResponse>("x").unwrap();
    let item = "/properties/assessments/items/properties";
    assert_eq!(
        enum_at(&oo, &format!("{item}/relationship_types/items/enum")),
        OBJECT_OBJECT_NAMES
    );
    assert_eq!(
        oo.schema.pointer(&format!("{item}/relationship_types/type")),
        Some(&json!(["array", "null"]))
    );
    assert_eq!(
        enum_at(&oo, &format!("{item}/sides/items/enum")),
        ["left", "right", "front", "back", "top", "bottom", "long", "short"]
    );
    assert!(
        oo.schema
            .pointer(&format!("{item}/sides/items/enum"))
            .unwrap()
            .as_array()
            .unwrap()
            .contains(&Value::Null)
    );

    let oa = strict_schema_for::<ArchRelationshipMappingResponse>("x").unwrap();
    assert_eq!(
        enum_at(&oa, &format!("{item}/relationship_type/enum")),
        OBJECT_ARCH_NAMES
    );
    assert_eq!(
        enum_at(&oa, &format!("{item}/architectural_element_type/enum")),
        ["wall", "floor", "ceiling", "room", "window", "door"]
    );

    let st = strict_schema_for::<SupportTypeResponse>("x").unwrap();
    assert_eq!(
        enum_at(&st, "/properties/support_type/enum"),
        ["ground", "object", "wall", "ceiling"]
    );
    let fs = strict_schema_for::<FunctionalSidesResponse>("x").unwrap();
    assert_eq!(
        enum_at(&fs, &format!("{item}/functional_sides/items/enum")),
        ["left", "right", "front", "back"]
    );
}

#[test]
fn support_type_schema_in_full() {
    let s = strict_schema_for::<SupportTypeResponse>("obj_support_type").unwrap();
    assert_eq!(
        serde_json::to_string(&ordered(&s.schema)).unwrap(),
        concat!(
            r#"{"type":"object","properties":{"support_type":{"type":"string","enum":["ground","object","wall","ceiling"]},"#,
            r#""reason":{"type":"string"}},"required":["support_type","reason"],"additionalProperties":false}"#
        )
    );
}
