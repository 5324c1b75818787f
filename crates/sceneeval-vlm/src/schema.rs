//! JSON Schemas of the answers, generated from the Rust types and normalised for strict
//! structured output.
//!
//! OpenAI's strict mode (`response_format: {type: json_schema, strict: true}`) accepts a subset
//! of JSON Schema: every object lists all its properties as `required` and sets
//! `additionalProperties: false`, optional values are written as a union with `null`, and some
//! keywords (`format`, `minimum`, ...) are rejected or ignored. vLLM's and Ollama's guided
//! decoding accept the same subset. [`strict_schema_for`] generates a schema with schemars
//! (subschemas inlined, so there are no `$ref`s either), then:
//!
//! - sets `required` to every property and `additionalProperties: false` on every object;
//!   `required` lists the properties in declaration order (schemars lists required fields in
//!   that order but leaves `Option` fields out; write those
//!   `#[schemars(with = "Nullable<T>")]` to keep their place, otherwise they come last);
//! - keeps only the keywords `type`, `properties`, `required`, `additionalProperties`,
//!   `items`, `enum`, `anyOf` and `const`, dropping `format` (schemars writes `uint32`,
//!   `int64`, ...), numeric bounds, titles and descriptions (the prompts explain the fields;
//!   the reference's schemas had no descriptions either);
//! - fails on anything strict mode cannot express (`$ref`, `oneOf`, `allOf`, an object without
//!   `properties`, a root that is not an object).
//!
//! [`check_strict`] verifies these rules on any schema.
//!
//! # Property order
//! Models write an answer's fields in the order of the schema's `properties`, so the order is
//! part of the prompt (the reference's answers end with `reason`). A `serde_json::Value` keeps
//! object keys sorted, so [`ResponseSchema`] serialises itself with each `properties` object in
//! the order of its `required` list, and the keywords in a fixed order ([`ordered`]).

use std::borrow::Cow;
use std::marker::PhantomData;

use schemars::generate::SchemaSettings;
use schemars::{JsonSchema, Schema, SchemaGenerator};
use serde_json::{Map, Value};

use crate::{ResponseSchema, VlmError};

/// The keywords a normalised schema may contain.
const KEPT_KEYWORDS: [&str; 8] = [
    "type",
    "properties",
    "required",
    "additionalProperties",
    "items",
    "enum",
    "anyOf",
    "const",
];

/// The schema of `Option<T>` (a `T` or `null`) for a field that schemars should list as
/// required, in its declaration order: `#[schemars(with = "Nullable<T>")]` on an `Option<T>`
/// field. Used only for schemas; no value of this type exists.
#[derive(Debug)]
pub struct Nullable<T>(PhantomData<T>);

impl<T: JsonSchema> JsonSchema for Nullable<T> {
    fn schema_name() -> Cow<'static, str> {
        format!("Nullable_{}", T::schema_name()).into()
    }

    fn inline_schema() -> bool {
        true
    }

    fn json_schema(generator: &mut SchemaGenerator) -> Schema {
        <Option<T> as JsonSchema>::json_schema(generator)
    }
}

/// The strict-mode schema of `T`, named `name`.
///
/// ```
/// use sceneeval_vlm::schema::{check_strict, strict_schema_for};
/// use sceneeval_vlm::tasks::SupportTypeResponse;
///
/// let s = strict_schema_for::<SupportTypeResponse>("obj_support_type").unwrap();
/// assert_eq!(s.schema["required"], serde_json::json!(["support_type", "reason"]));
/// assert_eq!(s.schema["additionalProperties"], false);
/// check_strict(&s.schema).unwrap();
/// ```
///
/// # Errors
/// [`VlmError::Schema`] when the generated schema cannot be expressed in strict mode, or the
/// name is not 1 to 64 characters of `A-Z a-z 0-9 _ -`.
pub fn strict_schema_for<T: JsonSchema>(name: &str) -> Result<ResponseSchema, VlmError> {
    let err = |message: String| VlmError::Schema {
        name: name.to_owned(),
        message,
    };
    if name.is_empty()
        || name.len() > 64
        || !name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
    {
        return Err(err(
            "a schema name is 1 to 64 characters of A-Z a-z 0-9 _ -".into()
        ));
    }
    let generator = SchemaSettings::draft2020_12()
        .with(|s| {
            s.inline_subschemas = true;
            s.meta_schema = None;
        })
        .for_deserialize()
        .into_generator();
    let mut schema = generator.into_root_schema_for::<T>().to_value();
    normalise(&mut schema, "").map_err(err)?;
    check_strict(&schema).map_err(err)?;
    Ok(ResponseSchema {
        name: name.to_owned(),
        schema,
    })
}

/// Rewrites one schema node (and its children) in place; `at` is its JSON pointer.
fn normalise(node: &mut Value, at: &str) -> Result<(), String> {
    let Value::Object(map) = node else {
        return match node {
            Value::Bool(true) => Err(format!("{at}: an unconstrained value (`true`) is not allowed")),
            _ => Ok(()),
        };
    };
    for bad in ["$ref", "oneOf", "allOf", "not", "if", "patternProperties"] {
        if map.contains_key(bad) {
            return Err(format!("{at}: `{bad}` is not supported in strict mode"));
        }
    }
    map.retain(|k, _| KEPT_KEYWORDS.contains(&k.as_str()));
    let declared: Vec<Value> = match map.get("required") {
        Some(Value::Array(r)) => r.clone(),
        _ => Vec::new(),
    };
    if let Some(Value::Object(props)) = map.get_mut("properties") {
        for (name, child) in props.iter_mut() {
            normalise(child, &format!("{at}/properties/{name}"))?;
        }
        // Declaration order from schemars' `required`, then any property it left out.
        let mut required: Vec<Value> = declared
            .into_iter()
            .filter(|k| k.as_str().is_some_and(|k| props.contains_key(k)))
            .collect();
        for name in props.keys() {
            if !required.iter().any(|r| r == name.as_str()) {
                required.push(Value::String(name.clone()));
            }
        }
        map.insert("required".into(), Value::Array(required));
        map.insert("additionalProperties".into(), Value::Bool(false));
    } else if is_type(map, "object") {
        return Err(format!(
            "{at}: an object without `properties` (a map) is not allowed"
        ));
    }
    if let Some(items) = map.get_mut("items") {
        normalise(items, &format!("{at}/items"))?;
    }
    if let Some(Value::Array(alternatives)) = map.get_mut("anyOf") {
        for (i, alt) in alternatives.iter_mut().enumerate() {
            normalise(alt, &format!("{at}/anyOf/{i}"))?;
        }
    }
    Ok(())
}

fn is_type(map: &Map<String, Value>, ty: &str) -> bool {
    match map.get("type") {
        Some(Value::String(t)) => t == ty,
        Some(Value::Array(ts)) => ts.iter().any(|t| t == ty),
        _ => false,
    }
}

/// Checks the strict-mode rules listed in the [module docs](self) on a schema.
///
/// # Errors
/// A message naming the JSON pointer of the first violation.
pub fn check_strict(schema: &Value) -> Result<(), String> {
    match schema {
        Value::Object(map) if is_type(map, "object") => check_node(schema, ""),
        _ => Err("the root of the schema must be an object".into()),
    }
}

fn check_node(node: &Value, at: &str) -> Result<(), String> {
    let Value::Object(map) = node else {
        return Err(format!("{at}: a schema node must be an object"));
    };
    if let Some(k) = map.keys().find(|k| !KEPT_KEYWORDS.contains(&k.as_str())) {
        return Err(format!("{at}: keyword `{k}` is not allowed"));
    }
    if let Some(Value::Object(props)) = map.get("properties") {
        let required: Vec<&str> = match map.get("required") {
            Some(Value::Array(r)) => r.iter().filter_map(Value::as_str).collect(),
            _ => Vec::new(),
        };
        for name in props.keys() {
            if !required.contains(&name.as_str()) {
                return Err(format!("{at}: property `{name}` is not required"));
            }
        }
        if map.get("additionalProperties") != Some(&Value::Bool(false)) {
            return Err(format!("{at}: `additionalProperties` is not false"));
        }
        for (name, child) in props {
            check_node(child, &format!("{at}/properties/{name}"))?;
        }
    } else if is_type(map, "object") {
        return Err(format!("{at}: an object without `properties`"));
    }
    if let Some(items) = map.get("items") {
        check_node(items, &format!("{at}/items"))?;
    }
    if let Some(Value::Array(alternatives)) = map.get("anyOf") {
        for (i, alt) in alternatives.iter().enumerate() {
            check_node(alt, &format!("{at}/anyOf/{i}"))?;
        }
    }
    Ok(())
}

/// A schema node that serialises with its keywords in the order of the list in the module docs (others
/// after, sorted) and each `properties` object in the order of the sibling `required` list.
///
/// ```
/// use sceneeval_vlm::schema::{ordered, strict_schema_for};
/// use sceneeval_vlm::tasks::SupportTypeResponse;
/// let s = strict_schema_for::<SupportTypeResponse>("t").unwrap();
/// let text = serde_json::to_string(&ordered(&s.schema)).unwrap();
/// assert!(text.starts_with(r#"{"type":"object","properties":{"support_type":"#));
/// assert!(text.find("support_type") < text.find("reason"));
/// ```
pub fn ordered(schema: &Value) -> Ordered<'_> {
    Ordered(schema)
}

/// See [`ordered`].
#[derive(Debug, Clone, Copy)]
pub struct Ordered<'a>(&'a Value);

impl serde::Serialize for Ordered<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let Value::Object(map) = self.0 else {
            return self.0.serialize(serializer);
        };
        let mut keys: Vec<&String> = map.keys().collect();
        keys.sort_by_key(|k| {
            KEPT_KEYWORDS
                .iter()
                .position(|w| w == k)
                .unwrap_or(KEPT_KEYWORDS.len())
        });
        let order: Vec<&str> = match map.get("required") {
            Some(Value::Array(r)) => r.iter().filter_map(Value::as_str).collect(),
            _ => Vec::new(),
        };
        let mut out = serializer.serialize_map(Some(keys.len()))?;
        for key in keys {
            match (key.as_str(), &map[key]) {
                ("properties", Value::Object(props)) => {
                    let mut names: Vec<&String> = props.keys().collect();
                    names.sort_by_key(|n| order.iter().position(|o| o == n).unwrap_or(order.len()));
                    let ordered_props: Vec<(&String, Ordered<'_>)> =
                        names.into_iter().map(|n| (n, Ordered(&props[n]))).collect();
                    out.serialize_entry(key, &OrderedProps(&ordered_props))?;
                }
                (_, value) => out.serialize_entry(key, &Ordered(value))?,
            }
        }
        out.end()
    }
}

struct OrderedProps<'a, 'b>(&'b [(&'a String, Ordered<'a>)]);

impl serde::Serialize for OrderedProps<'_, '_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut out = serializer.serialize_map(Some(self.0.len()))?;
        for (k, v) in self.0 {
            out.serialize_entry(k, v)?;
        }
        out.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;
    use serde_json::json;

    #[allow(dead_code)]
    #[derive(Deserialize, JsonSchema)]
    struct Inner {
        #[schemars(with = "Nullable<String>")]
        note: Option<String>,
        /// A doc comment that must not reach the schema.
        count: u32,
    }

    #[allow(dead_code)]
    #[derive(Deserialize, JsonSchema)]
    struct Outer {
        items: Vec<Inner>,
        #[serde(default)]
        flag: bool,
    }

    #[test]
    fn keeps_declaration_order() {
        let s = strict_schema_for::<Outer>("outer").unwrap().schema;
        let text = serde_json::to_string(&ordered(&s)).unwrap();
        assert_eq!(
            text,
            concat!(
                r#"{"type":"object","properties":{"items":{"type":"array","items":{"type":"object","#,
                r#""properties":{"note":{"type":["string","null"]},"count":{"type":"integer"}},"#,
                r#""required":["note","count"],"additionalProperties":false}},"flag":{"type":"boolean"}},"#,
                r#""required":["items","flag"],"additionalProperties":false}"#
            )
        );
    }

    #[test]
    fn normalises_nested_objects() {
        let s = strict_schema_for::<Outer>("outer").unwrap().schema;
        assert_eq!(
            s,
            json!({
                "type": "object",
                "properties": {
                    "items": {
                        "type": "array",
                        "items": {
                            "type": "object",
                            "properties": {
                                "count": {"type": "integer"},
                                "note": {"type": ["string", "null"]}
                            },
                            "required": ["note", "count"],
                            "additionalProperties": false
                        }
                    },
                    "flag": {"type": "boolean"}
                },
                "required": ["items", "flag"],
                "additionalProperties": false
            })
        );
    }

    #[allow(dead_code)]
    #[derive(Deserialize, JsonSchema)]
    struct WithMap {
        m: std::collections::BTreeMap<String, u32>,
    }

    #[test]
    fn rejects_maps_and_bad_names() {
        let err = strict_schema_for::<WithMap>("m").unwrap_err().to_string();
        assert!(err.contains("/properties/m") && err.contains("map"), "{err}");
        assert!(strict_schema_for::<Outer>("has space").is_err());
        assert!(strict_schema_for::<Outer>(&"x".repeat(65)).is_err());
    }

    #[test]
    fn check_strict_names_the_violation() {
        let loose = json!({"type": "object", "properties": {"a": {"type": "string", "format": "date"}},
                           "required": ["a"], "additionalProperties": false});
        assert!(check_strict(&loose).unwrap_err().contains("/properties/a"));
        let optional = json!({"type": "object", "properties": {"a": {"type": "string"}},
                              "required": [], "additionalProperties": false});
        assert!(check_strict(&optional).unwrap_err().contains("not required"));
        assert!(check_strict(&json!({"type": "array", "items": {"type": "string"}})).is_err());
    }
}
