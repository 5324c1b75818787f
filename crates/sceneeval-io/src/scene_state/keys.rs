//! The keys of the sceneState format, place by place, and the keys of a file that are none of
//! them ([`unknown_keys`]).
//!
//! A misspelt key is read as absent, which can change a scene without a word (an object whose
//! `"transfrom"` is misspelt stands at the origin), so the reader reports every key it does
//! not know: a warning per key and place, or with [`crate::ReadOptions::strict`] an error. The
//! known keys are those the reader reads and those the sstk format and the generators' own
//! exports carry that the reader ignores on purpose (`up`, `unit`, arch `defaults`, object
//! `parentId`, ...: the reference, its SceneSmith fork, SceneSmith's exporter and the fork's
//! converters write them), so that real files read without a warning. The contents of the
//! ignored values (`defaults`, `materials`, `regions`, ...) are not checked.

use std::fmt;

use serde::Serialize;
use serde_json::{Map, Value};

use super::json_in::{ptr_index, ptr_key};

/// A place of the format: its pointer pattern (`*` for any array position) and its keys.
struct Place {
    pattern: &'static str,
    keys: &'static [&'static str],
}

/// The top level.
const ROOT: Place = Place {
    pattern: "",
    keys: &["format", "scene", "selected"],
};
/// `scene`.
const SCENE: Place = Place {
    pattern: "/scene",
    keys: &[
        "version",
        "id",
        "up",
        "front",
        "unit",
        "assetSource",
        "arch",
        "object",
        "objectFrontVector",
        "modifications",
    ],
};
/// `scene.arch`.
const ARCH: Place = Place {
    pattern: "/scene/arch",
    keys: &[
        "version",
        "id",
        "up",
        "front",
        "coords2d",
        "scaleToMeters",
        "defaults",
        "elements",
        "regions",
        "holes",
        "images",
        "materials",
        "textures",
        "open_room_pairs",
    ],
};
/// An architecture element (Floor, Ceiling, Wall).
const ELEMENT: Place = Place {
    pattern: "/scene/arch/elements/*",
    keys: &[
        "id",
        "type",
        "roomId",
        "roomType",
        "points",
        "height",
        "depth",
        "holes",
        "materials",
    ],
};
/// A wall's hole (Door, Window).
const HOLE: Place = Place {
    pattern: "/scene/arch/elements/*/holes/*",
    keys: &["id", "type", "box"],
};
/// A hole's box.
const HOLE_BOX: Place = Place {
    pattern: "/scene/arch/elements/*/holes/*/box",
    keys: &["min", "max"],
};
/// An object entry.
const OBJECT: Place = Place {
    pattern: "/scene/object/*",
    keys: &[
        "index",
        "id",
        "objectId",
        "modelId",
        "parentId",
        "parentIndex",
        "transform",
        "objectPose",
        "objectFrontVector",
        "isArchitecture",
        "category",
        "description",
        "box",
        "supportType",
        "functionalSides",
        "sdfPath",
    ],
};
/// An object's transform (the sstk writers add the matrix's parts).
const TRANSFORM: Place = Place {
    pattern: "/scene/object/*/transform",
    keys: &["rows", "cols", "data", "rotation", "scale", "translation"],
};
/// A box object's box.
const BOX: Place = Place {
    pattern: "/scene/object/*/box",
    keys: &["size"],
};
/// An object's exact pose, as this crate writes it.
const OBJECT_POSE: Place = Place {
    pattern: "/scene/object/*/objectPose",
    keys: &["rotation", "scale"],
};

/// The known keys of an object entry (`/scene/object/*`).
pub(crate) const OBJECT_KEYS: &[&str] = OBJECT.keys;

/// A key of a sceneState file that the format does not have at its place, reported once per
/// place of the format (all objects are one place) with the first object that has it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct UnknownKey {
    /// The key as written.
    pub key: String,
    /// Pointer to the first JSON object that has it, e.g. `/scene/object/3`.
    pub pointer: String,
    /// The place in the format, `*` standing for any array position, e.g. `/scene/object/*`.
    pub place: &'static str,
    /// How many JSON objects at that place have it.
    pub occurrences: usize,
    /// The key of that place it most resembles, when one is close (a likely misspelling).
    pub similar: Option<&'static str>,
}

impl fmt::Display for UnknownKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let at = if self.pointer.is_empty() {
            "/"
        } else {
            &self.pointer
        };
        write!(f, "{at}: unknown key {:?}", self.key)?;
        if self.occurrences > 1 {
            write!(f, " (and in {} more like it)", self.occurrences - 1)?;
        }
        if let Some(s) = self.similar {
            write!(f, "; did you mean {s:?}?")?;
        }
        Ok(())
    }
}

/// The key of `known` that `key` most resembles, if one is at most two edits away (a swap of
/// two neighbouring letters is one edit) or differs only in case.
pub(crate) fn similar(key: &str, known: &[&'static str]) -> Option<&'static str> {
    known
        .iter()
        .map(|k| {
            let d = if k.eq_ignore_ascii_case(key) {
                0
            } else {
                strsim::osa_distance(k, key)
            };
            (d, *k)
        })
        .filter(|(d, _)| *d <= 2.min(key.len().saturating_sub(1)))
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// Every key of the document `root` that the format does not have at its place, each once per
/// place (in the order first met), with the number of JSON objects at that place that have it.
/// Values of the wrong type are not looked into (the reader reports them).
pub fn unknown_keys(root: &Value) -> Vec<UnknownKey> {
    let mut out = Vec::new();
    let Some(root) = root.as_object() else {
        return out;
    };
    check(root, "", &ROOT, &mut out);
    let Some(scene) = root.get("scene").and_then(Value::as_object) else {
        return out;
    };
    check(scene, "/scene", &SCENE, &mut out);
    if let Some(arch) = scene.get("arch").and_then(Value::as_object) {
        check(arch, "/scene/arch", &ARCH, &mut out);
        for (e, ptr) in objects_of(arch, "/scene/arch", "elements") {
            check(e, &ptr, &ELEMENT, &mut out);
            for (h, hptr) in objects_of(e, &ptr, "holes") {
                check(h, &hptr, &HOLE, &mut out);
                if let Some(b) = h.get("box").and_then(Value::as_object) {
                    check(b, &ptr_key(&hptr, "box"), &HOLE_BOX, &mut out);
                }
            }
        }
    }
    for (o, ptr) in objects_of(scene, "/scene", "object") {
        check(o, &ptr, &OBJECT, &mut out);
        for (key, place) in [
            ("transform", &TRANSFORM),
            ("box", &BOX),
            ("objectPose", &OBJECT_POSE),
        ] {
            if let Some(v) = o.get(key).and_then(Value::as_object) {
                check(v, &ptr_key(&ptr, key), place, &mut out);
            }
        }
    }
    out
}

/// The JSON objects of the array `parent[key]` with their pointers.
fn objects_of<'v>(
    parent: &'v Map<String, Value>,
    parent_ptr: &str,
    key: &str,
) -> Vec<(&'v Map<String, Value>, String)> {
    let Some(list) = parent.get(key).and_then(Value::as_array) else {
        return Vec::new();
    };
    let base = ptr_key(parent_ptr, key);
    list.iter()
        .enumerate()
        .filter_map(|(i, v)| Some((v.as_object()?, ptr_index(&base, i))))
        .collect()
}

fn check(o: &Map<String, Value>, ptr: &str, place: &Place, out: &mut Vec<UnknownKey>) {
    for key in o.keys() {
        if place.keys.contains(&key.as_str()) {
            continue;
        }
        match out.iter_mut().find(|u| u.place == place.pattern && u.key == *key) {
            Some(u) => u.occurrences += 1,
            None => out.push(UnknownKey {
                key: key.clone(),
                pointer: ptr.to_owned(),
                place: place.pattern,
                occurrences: 1,
                similar: similar(key, place.keys),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn misspellings_are_found_once_per_place_with_a_suggestion() {
        let doc = json!({
            "format": "sceneState", "selected": [],
            "scene": {
                "version": "scene@1.0.2", "up": [0, 0, 1], "unit": 1, "assetSource": ["x"],
                "arch": {"elements": [
                    {"id": "f", "type": "Floor", "roomId": "r", "points": [], "materials": []},
                    {"id": "w", "type": "Wall", "roomId": "r", "points": [], "hieght": 2,
                     "holes": [{"type": "Door", "box": {"min": [0, 0], "mx": [1, 2]}}]}
                ], "defaults": {"Wall": {"anything": 1}}},
                "object": [
                    {"index": 0, "modelId": "a.b", "transfrom": {"data": []}},
                    {"index": 1, "modelId": "a.b", "transform": {"data": [], "rows": 4, "colz": 4}},
                    {"index": 2, "modelId": "a.b", "transfrom": {"data": []}, "parentId": "", "sdfPath": "x"},
                    "not an object"
                ]
            }
        });
        let found = unknown_keys(&doc);
        let brief: Vec<(&str, &str, usize, Option<&str>)> = found
            .iter()
            .map(|u| (u.key.as_str(), u.pointer.as_str(), u.occurrences, u.similar))
            .collect();
        assert_eq!(
            brief,
            [
                ("hieght", "/scene/arch/elements/1", 1, Some("height")),
                ("mx", "/scene/arch/elements/1/holes/0/box", 1, Some("max")),
                ("transfrom", "/scene/object/0", 2, Some("transform")),
                ("colz", "/scene/object/1/transform", 1, Some("cols")),
            ]
        );
        assert_eq!(
            found[2].to_string(),
            "/scene/object/0: unknown key \"transfrom\" (and in 1 more like it); did you mean \"transform\"?"
        );
        assert_eq!(found[2].place, "/scene/object/*");
    }

    #[test]
    fn suggestions_need_a_close_key() {
        assert_eq!(similar("ModelId", OBJECT.keys), Some("modelId"));
        assert_eq!(similar("colour", OBJECT.keys), None);
        assert_eq!(similar("x", &["y"]), None, "one letter is no evidence");
        assert!(unknown_keys(&json!([1, 2])).is_empty());
        assert!(unknown_keys(&json!({"format": "sceneState", "scene": 3})).is_empty());
    }
}
