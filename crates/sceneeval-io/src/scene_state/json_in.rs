//! Walking a parsed JSON document with JSON pointers, turning every type problem into an
//! [`IoError`] that names the file and the pointer. The sceneState reader uses it, and so do
//! the converters of generators' own files (`sceneeval-convert`), so that a bad input names
//! its file and JSON pointer the same way everywhere.
//!
//! ```
//! use std::path::Path;
//! use sceneeval_io::scene_state::json_in::{Doc, parse, ptr_index, ptr_key};
//!
//! let path = Path::new("layout.json");
//! let root = parse(r#"{"bed-0": {"position": [1, 2, "x"]}}"#, path).unwrap();
//! let doc = Doc { path };
//! let bed = doc.object(doc.required(doc.object(&root, "").unwrap(), "", "bed-0").unwrap(), "/bed-0").unwrap();
//! let err = doc
//!     .numbers::<3>(&bed["position"], &ptr_key("/bed-0", "position"), "an array of 3 numbers")
//!     .unwrap_err();
//! assert_eq!(err.to_string(), "layout.json: /bed-0/position/2: expected a number, found the string \"x\"");
//! assert_eq!(ptr_index("/a", 2), "/a/2");
//! ```

use std::path::{Path, PathBuf};

use serde_json::{Map, Value};

use crate::IoError;

/// An RFC 6901 pointer to `key` inside the value at `base` (`~` and `/` escaped).
pub fn ptr_key(base: &str, key: &str) -> String {
    format!("{base}/{}", key.replace('~', "~0").replace('/', "~1"))
}

/// An RFC 6901 pointer to element `i` of the array at `base`.
pub fn ptr_index(base: &str, i: usize) -> String {
    format!("{base}/{i}")
}

/// A short description of a JSON value's type, for error messages.
pub fn describe(v: &Value) -> String {
    match v {
        Value::Null => "null".into(),
        Value::Bool(_) => "a boolean".into(),
        Value::Number(n) if n.is_i64() || n.is_u64() => "an integer".into(),
        Value::Number(_) => "a number".into(),
        Value::String(s) => format!("the string {s:?}"),
        Value::Array(a) => format!("an array of {} elements", a.len()),
        Value::Object(_) => "an object".into(),
    }
}

/// The file being read: its typed accessors name it and the value's pointer in every error.
#[derive(Debug, Clone, Copy)]
pub struct Doc<'a> {
    /// The file, for error messages.
    pub path: &'a Path,
}

impl<'a> Doc<'a> {
    /// The file as an owned path.
    pub fn path_buf(&self) -> PathBuf {
        self.path.to_owned()
    }

    /// [`IoError::WrongType`]: the value at `ptr` is not `expected`.
    pub fn wrong(&self, ptr: &str, expected: &'static str, found: &Value) -> IoError {
        IoError::WrongType {
            path: self.path_buf(),
            pointer: ptr.to_owned(),
            expected,
            found: describe(found),
        }
    }

    /// [`IoError::InvalidValue`]: the value at `ptr` has the right type but is not acceptable.
    pub fn invalid(&self, ptr: &str, reason: impl Into<String>) -> IoError {
        IoError::InvalidValue {
            path: self.path_buf(),
            pointer: ptr.to_owned(),
            reason: reason.into(),
        }
    }

    /// The value at `ptr` as a JSON object.
    ///
    /// # Errors
    /// [`IoError::WrongType`].
    pub fn object<'v>(&self, v: &'v Value, ptr: &str) -> Result<&'v Map<String, Value>, IoError> {
        v.as_object().ok_or_else(|| self.wrong(ptr, "an object", v))
    }

    /// The value at `ptr` as a JSON array.
    ///
    /// # Errors
    /// [`IoError::WrongType`].
    pub fn array<'v>(&self, v: &'v Value, ptr: &str) -> Result<&'v Vec<Value>, IoError> {
        v.as_array().ok_or_else(|| self.wrong(ptr, "an array", v))
    }

    /// A field that must be present and not null.
    ///
    /// # Errors
    /// [`IoError::MissingField`] naming `ptr` (the object) and the field.
    pub fn required<'v>(
        &self,
        o: &'v Map<String, Value>,
        ptr: &str,
        key: &'static str,
    ) -> Result<&'v Value, IoError> {
        optional(o, key).ok_or_else(|| IoError::MissingField {
            path: self.path_buf(),
            pointer: ptr.to_owned(),
            field: key,
        })
    }

    /// A finite number. (JSON has no NaN or infinity and serde_json rejects numbers out of the
    /// f64 range while parsing, so the finiteness check is a safeguard.)
    ///
    /// # Errors
    /// [`IoError::WrongType`], or [`IoError::InvalidValue`] for a non-finite number.
    pub fn number(&self, v: &Value, ptr: &str) -> Result<f64, IoError> {
        let x = v.as_f64().ok_or_else(|| self.wrong(ptr, "a number", v))?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.invalid(ptr, format!("{x} is not finite")))
        }
    }

    /// An integer.
    ///
    /// # Errors
    /// [`IoError::WrongType`].
    pub fn integer(&self, v: &Value, ptr: &str) -> Result<i64, IoError> {
        v.as_i64().ok_or_else(|| self.wrong(ptr, "an integer", v))
    }

    /// A string.
    ///
    /// # Errors
    /// [`IoError::WrongType`].
    pub fn string<'v>(&self, v: &'v Value, ptr: &str) -> Result<&'v str, IoError> {
        v.as_str().ok_or_else(|| self.wrong(ptr, "a string", v))
    }

    /// An id: a string, or an integer written as its decimal text.
    ///
    /// # Errors
    /// [`IoError::WrongType`].
    pub fn id(&self, v: &Value, ptr: &str) -> Result<String, IoError> {
        match v {
            Value::String(s) => Ok(s.clone()),
            Value::Number(n) if n.is_i64() || n.is_u64() => Ok(n.to_string()),
            _ => Err(self.wrong(ptr, "a string or an integer", v)),
        }
    }

    /// An array of exactly `N` finite numbers.
    ///
    /// # Errors
    /// [`IoError::WrongType`] naming `expected`, or the element's error.
    pub fn numbers<const N: usize>(
        &self,
        v: &Value,
        ptr: &str,
        expected: &'static str,
    ) -> Result<[f64; N], IoError> {
        let a = match v.as_array() {
            Some(a) if a.len() == N => a,
            _ => return Err(self.wrong(ptr, expected, v)),
        };
        let mut out = [0.0; N];
        for (i, (slot, item)) in out.iter_mut().zip(a).enumerate() {
            *slot = self.number(item, &ptr_index(ptr, i))?;
        }
        Ok(out)
    }
}

/// A field that is present and not null.
pub fn optional<'v>(o: &'v Map<String, Value>, key: &str) -> Option<&'v Value> {
    o.get(key).filter(|v| !v.is_null())
}

/// Reads the JSON file at `path`: at most `max_bytes` long, UTF-8, well-formed.
///
/// # Errors
/// [`IoError::File`], [`IoError::TooLarge`], [`IoError::InvalidUtf8`] or
/// [`IoError::MalformedJson`], each naming the file.
pub fn read_json_file(path: &Path, max_bytes: u64) -> Result<Value, IoError> {
    let bytes = crate::uri::read_file_limited(path, max_bytes)?;
    parse(IoError::utf8(path, &bytes)?, path)
}

/// Parses JSON text, reporting line and column (and a hint for NaN/Infinity, which some
/// Python writers emit) on failure.
///
/// # Errors
/// [`IoError::MalformedJson`] naming `path`.
pub fn parse(text: &str, path: &Path) -> Result<Value, IoError> {
    serde_json::from_str(text).map_err(|e| {
        let (line, column) = (e.line(), e.column());
        let full = e.to_string();
        let suffix = format!(" at line {line} column {column}");
        let mut message = full.strip_suffix(&suffix).unwrap_or(&full).to_owned();
        let rest = text
            .lines()
            .nth(line.saturating_sub(1))
            .and_then(|l| l.get(column.saturating_sub(1)..))
            .unwrap_or("");
        if ["NaN", "Infinity", "-Infinity", "inf", "-inf"]
            .iter()
            .any(|w| rest.starts_with(w))
        {
            message.push_str(" (NaN and Infinity are not valid JSON numbers)");
        }
        IoError::MalformedJson {
            path: path.to_owned(),
            line,
            column,
            message,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pointers_escape_keys() {
        assert_eq!(ptr_key("", "scene"), "/scene");
        assert_eq!(ptr_key("/a", "b/c~d"), "/a/b~1c~0d");
        assert_eq!(ptr_index("/scene/object", 3), "/scene/object/3");
    }

    #[test]
    fn parse_errors_have_position_and_hints() {
        let p = Path::new("s.json");
        match parse("{\n  \"a\": NaN\n}", p) {
            Err(IoError::MalformedJson {
                line,
                column,
                message,
                ..
            }) => {
                assert_eq!(line, 2);
                assert!(column >= 8, "{column}");
                assert!(message.contains("NaN and Infinity"), "{message}");
            }
            other => panic!("{other:?}"),
        }
        match parse("{\"a\": 1e999}", p) {
            Err(IoError::MalformedJson { line: 1, message, .. }) => {
                assert!(message.contains("out of range"), "{message}")
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(parse("[1, 2", p), Err(IoError::MalformedJson { .. })));
    }

    #[test]
    fn typed_accessors_report_pointer_and_found_type() {
        let doc = Doc {
            path: Path::new("s.json"),
        };
        let v: Value = serde_json::json!({"n": "x", "arr": [1, 2], "i": 1.5, "id": 7});
        let o = doc.object(&v, "").unwrap();
        match doc.number(&o["n"], "/n") {
            Err(IoError::WrongType {
                pointer,
                expected,
                found,
                ..
            }) => {
                assert_eq!((pointer.as_str(), expected), ("/n", "a number"));
                assert_eq!(found, "the string \"x\"");
            }
            other => panic!("{other:?}"),
        }
        assert!(doc.numbers::<3>(&o["arr"], "/arr", "3 numbers").is_err());
        assert!(doc.integer(&o["i"], "/i").is_err());
        assert_eq!(doc.id(&o["id"], "/id").unwrap(), "7");
        assert!(matches!(
            doc.required(o, "", "missing"),
            Err(IoError::MissingField { field: "missing", .. })
        ));
    }
}
