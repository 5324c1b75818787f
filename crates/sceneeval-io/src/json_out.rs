//! A tiny deterministic JSON printer: keys in the order given, two-space indentation, arrays
//! of scalars on one line, a trailing newline. Independent of serde_json's map ordering
//! features, so the output bytes depend only on the input.

use std::fmt::Write as _;

/// A JSON value to print.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Json {
    Str(String),
    Num(f64),
    Int(i64),
    Arr(Vec<Json>),
    Obj(Vec<(&'static str, Json)>),
}

impl Json {
    pub(crate) fn str(s: impl Into<String>) -> Json {
        Json::Str(s.into())
    }

    pub(crate) fn nums(values: &[f64]) -> Json {
        Json::Arr(values.iter().map(|&v| Json::Num(v)).collect())
    }

    fn is_scalar(&self) -> bool {
        matches!(self, Json::Str(_) | Json::Num(_) | Json::Int(_))
    }

    /// The first non-finite number, if any (JSON cannot represent NaN or infinity).
    pub(crate) fn find_non_finite(&self) -> Option<f64> {
        match self {
            Json::Num(v) if !v.is_finite() => Some(*v),
            Json::Arr(items) => items.iter().find_map(Json::find_non_finite),
            Json::Obj(fields) => fields.iter().find_map(|(_, v)| v.find_non_finite()),
            _ => None,
        }
    }

    /// Pretty-printed text with a trailing newline.
    pub(crate) fn to_pretty_string(&self) -> String {
        let mut out = String::new();
        self.write(&mut out, 0);
        out.push('\n');
        out
    }

    fn write(&self, out: &mut String, indent: usize) {
        match self {
            Json::Str(s) => out.push_str(&quote(s)),
            Json::Num(v) => out.push_str(&number(*v)),
            Json::Int(v) => {
                let _ = write!(out, "{v}");
            }
            Json::Arr(items) if items.is_empty() => out.push_str("[]"),
            Json::Arr(items) if items.iter().all(Json::is_scalar) => {
                out.push('[');
                for (i, item) in items.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    item.write(out, indent);
                }
                out.push(']');
            }
            Json::Arr(items) => {
                out.push_str("[\n");
                for (i, item) in items.iter().enumerate() {
                    pad(out, indent + 1);
                    item.write(out, indent + 1);
                    out.push_str(if i + 1 < items.len() { ",\n" } else { "\n" });
                }
                pad(out, indent);
                out.push(']');
            }
            Json::Obj(fields) if fields.is_empty() => out.push_str("{}"),
            Json::Obj(fields) => {
                out.push_str("{\n");
                for (i, (key, value)) in fields.iter().enumerate() {
                    pad(out, indent + 1);
                    out.push_str(&quote(key));
                    out.push_str(": ");
                    value.write(out, indent + 1);
                    out.push_str(if i + 1 < fields.len() { ",\n" } else { "\n" });
                }
                pad(out, indent);
                out.push('}');
            }
        }
    }
}

fn pad(out: &mut String, indent: usize) {
    for _ in 0..indent {
        out.push_str("  ");
    }
}

fn quote(s: &str) -> String {
    // Serialising a string cannot fail; fall back to a debug rendering just in case.
    serde_json::to_string(s).unwrap_or_else(|_| format!("{s:?}"))
}

/// The shortest text that parses back to the same `f64` (serde_json's ryu formatting), with
/// negative zero written as `0.0`.
fn number(v: f64) -> String {
    let v = if v == 0.0 { 0.0 } else { v };
    serde_json::to_string(&v).unwrap_or_else(|_| "null".to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prints_scalar_arrays_inline_and_keeps_key_order() {
        let doc = Json::Obj(vec![
            ("z", Json::Int(3)),
            ("a", Json::nums(&[1.0, -0.0, 1e-7, 0.1])),
            (
                "points",
                Json::Arr(vec![Json::nums(&[0.0, 1.0]), Json::nums(&[2.0, 3.5])]),
            ),
            ("s", Json::str("quote \" and \\")),
            ("empty", Json::Arr(vec![])),
        ]);
        let text = doc.to_pretty_string();
        let expected = "{\n  \"z\": 3,\n  \"a\": [1.0, 0.0, 1e-7, 0.1],\n  \"points\": [\n    [0.0, 1.0],\n    [2.0, 3.5]\n  ],\n  \"s\": \"quote \\\" and \\\\\",\n  \"empty\": []\n}\n";
        assert_eq!(text, expected);
        let parsed: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(parsed["a"][2].as_f64(), Some(1e-7));
        assert_eq!(doc.find_non_finite(), None);
        assert!(Json::nums(&[f64::NAN]).find_non_finite().unwrap().is_nan());
    }
}
