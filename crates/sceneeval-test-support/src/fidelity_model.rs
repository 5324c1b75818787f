//! A scripted model of the VLM for fixture scenes 2 and 8 (`fixtures/scenes/`), and the
//! annotation rows its tests check: what a model answers to each task, shared by the facade's
//! pipeline tests (a `Scripted` model) and the command line's tests (a mock server on
//! 127.0.0.1), so that both routes check the same expected numbers.
//!
//! The answers: the nightstand of scene 8 is not recognised; the wardrobe is tall; five of the
//! six chairs are wooden; "in_harmony_with" maps to no predicate; every object's functional
//! side is its front (the fixture scenes state every support type, so none is asked).

use std::collections::HashMap;
use std::sync::{Mutex, PoisonError};

use serde_json::{Value, json};

/// The annotation rows of scenes 8 and 2: a spec that fails, an absent object with `eq,0`, a
/// `surround` group and an unmappable phrase. The fixture geometry behind each relation is
/// described in `crates/sceneeval-fixtures/src/scene_annotations.rs`.
pub const CSV: &str = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
8,easy,A small bedroom.,\"eq,1,wardrobe; eq,1,bed; eq,1,nightstand; eq,1,ceiling_lamp; eq,0,tv; eq,2,chair\",\
\"eq,1,wardrobe,tall\",\"eq,1,next_to,0,bed,nightstand; eq,1,in_harmony_with,0,bed,wardrobe\",\
\"eq,1,against,bed,wall; eq,1,next_to,wardrobe,door\"\n\
2,hard,A dining room.,\"eq,1,dining_table; eq,6,chair; eq,1,ceiling_lamp; eq,1,bookshelf; eq,1,plant; eq,1,floor_lamp; eq,1,painting\",\
\"eq,6,chair,wooden\",\"eq,1,surround,0,dining_table,chair:0,chair:1,chair:2,chair:3,chair:4,chair:5; eq,6,next_to,0,dining_table,chair\",\
\"eq,1,corner,plant,room; eq,1,hang,ceiling_lamp,ceiling\"\n";

/// Scene 8's objects in scene order (the order of its matching requests).
pub const SCENE_8: [&str; 4] = ["wardrobe", "bed", "nightstand", "ceiling_lamp"];

/// Scene 2's objects in scene order.
pub const SCENE_2: [&str; 12] = [
    "dining_table",
    "chair",
    "chair",
    "chair",
    "chair",
    "chair",
    "chair",
    "ceiling_lamp",
    "bookshelf",
    "plant",
    "floor_lamp",
    "painting",
];

/// What the model answers to `task` (the schema name) given the prompt's `user_text`;
/// `nth_matching` is the object's position in its scene (see [`Nth`]).
///
/// # Panics
/// On a task the fixtures never ask (the test is then wrong).
#[allow(clippy::panic)] // Test scaffolding: an unexpected task is a broken test.
pub fn answer(task: &str, user_text: &str, nth_matching: usize) -> Value {
    match task {
        "obj_matching" => {
            let scene8 = user_text.contains("\"wardrobe\"");
            let category = if scene8 {
                SCENE_8[nth_matching]
            } else {
                SCENE_2[nth_matching]
            };
            let matched = category != "nightstand";
            json!({"provided_categories": [], "matched": matched,
                   "matched_category": if matched { category } else { "" },
                   "actual_category": category, "reason": format!("looks like a {category}")})
        }
        "obj_attribute" if user_text.contains("\"wardrobe\"") => json!({
            "category": "wardrobe", "num_instances": 1,
            "assessments": [{"instance": 0, "attribute": "tall", "satisfied": true, "reason": "2 m"}]}),
        "obj_attribute" => json!({
            "category": "chair", "num_instances": 6,
            "assessments": (0..6).map(|i| json!({"instance": i, "attribute": "wooden", "satisfied": i != 5,
                                                  "reason": format!("chair {i}")})).collect::<Vec<_>>()}),
        // Every object described in the prompt (`obj_id: "<id>", ...`) is used from the front.
        "obj_functional_sides" => json!({"assessments": user_text
            .split("obj_id: \"")
            .skip(1)
            .filter_map(|rest| rest.split('"').next())
            .map(|id| json!({"obj_id": id, "obj_description": "", "functional_sides": ["front"], "reason": "used from the front"}))
            .collect::<Vec<_>>()}),
        "obj_support_type" => json!({"support_type": "ground", "reason": "on the floor"}),
        "obj_relationship_mapping" => json!({"assessments": [{
            "key": "1", "relationship": "in_harmony_with", "anchor_object": "bed",
            "other_objects": ["wardrobe"], "other_object_counts": [1],
            "relationship_types": null, "sides": [], "reason": "not spatial"}]}),
        other => panic!("unexpected task {other}"),
    }
}

/// Counts matching requests per category list (one list per scene), so that the n-th request
/// of a scene is its n-th object whatever the order scenes run in.
#[derive(Debug, Default)]
pub struct Nth(Mutex<HashMap<String, usize>>);

impl Nth {
    /// The position of this matching request in its scene (0 for other tasks).
    pub fn next(&self, task: &str, user_text: &str) -> usize {
        if task != "obj_matching" {
            return 0;
        }
        let mut m = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        let n = m.entry(user_text.to_owned()).or_default();
        *n += 1;
        *n - 1
    }
}
