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
/// Python writers emit) on failure. A key given twice in one object is an error: JSON readers
/// silently keep one of the two (serde_json and Python's `json` the last), so the file does not
/// say which value it means.
///
/// ```
/// use std::path::Path;
/// use sceneeval_io::IoError;
/// use sceneeval_io::scene_state::json_in::parse;
/// let err = parse(r#"{"a": [{"k": 1, "k": 2}]}"#, Path::new("s.json")).unwrap_err();
/// assert!(matches!(&err, IoError::DuplicateKey { pointer, key, .. } if pointer == "/a/0" && key == "k"));
/// assert_eq!(parse(r#"{"a": {"k": 1}, "b": {"k": 2}}"#, Path::new("s.json")).unwrap()["b"]["k"], 2);
/// ```
///
/// # Errors
/// [`IoError::MalformedJson`] or [`IoError::DuplicateKey`] naming `path`.
pub fn parse(text: &str, path: &Path) -> Result<Value, IoError> {
    let duplicate = std::cell::RefCell::new(None);
    let mut de = serde_json::Deserializer::from_str(text);
    let parsed = serde::de::DeserializeSeed::deserialize(
        strict::Node {
            at: &strict::Place::Root,
            duplicate: &duplicate,
        },
        &mut de,
    )
    .and_then(|v| de.end().map(|()| v));
    parsed.map_err(|e| {
        let (line, column) = (e.line(), e.column());
        if let Some((pointer, key)) = duplicate.into_inner() {
            return IoError::DuplicateKey {
                path: path.to_owned(),
                pointer,
                key,
                line,
                column,
            };
        }
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

/// A [`Value`] deserializer that refuses a key given twice in one object, remembering where.
mod strict {
    use std::cell::RefCell;
    use std::fmt;

    use serde::de::{self, DeserializeSeed, MapAccess, SeqAccess, Visitor};
    use serde_json::{Map, Number, Value};

    /// Where a value is, as a chain to the root (the pointer is written only for an error).
    pub(super) enum Place<'a> {
        Root,
        Key(&'a Place<'a>, &'a str),
        Index(&'a Place<'a>, usize),
    }

    impl Place<'_> {
        fn pointer(&self) -> String {
            match self {
                Place::Root => String::new(),
                Place::Key(parent, key) => super::ptr_key(&parent.pointer(), key),
                Place::Index(parent, i) => super::ptr_index(&parent.pointer(), *i),
            }
        }
    }

    /// The first repeated key met: the pointer of its object and the key.
    type Duplicate = RefCell<Option<(String, String)>>;

    /// The value at `at`.
    pub(super) struct Node<'a> {
        pub(super) at: &'a Place<'a>,
        pub(super) duplicate: &'a Duplicate,
    }

    impl<'de> DeserializeSeed<'de> for Node<'_> {
        type Value = Value;

        fn deserialize<D: de::Deserializer<'de>>(self, deserializer: D) -> Result<Value, D::Error> {
            deserializer.deserialize_any(self)
        }
    }

    impl<'de> Visitor<'de> for Node<'_> {
        type Value = Value;

        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("any JSON value")
        }

        fn visit_bool<E>(self, v: bool) -> Result<Value, E> {
            Ok(Value::Bool(v))
        }

        fn visit_i64<E>(self, v: i64) -> Result<Value, E> {
            Ok(Value::Number(v.into()))
        }

        fn visit_u64<E>(self, v: u64) -> Result<Value, E> {
            Ok(Value::Number(v.into()))
        }

        fn visit_f64<E>(self, v: f64) -> Result<Value, E> {
            // The parser gives only finite numbers.
            Ok(Number::from_f64(v).map_or(Value::Null, Value::Number))
        }

        fn visit_str<E>(self, v: &str) -> Result<Value, E> {
            Ok(Value::String(v.to_owned()))
        }

        fn visit_string<E>(self, v: String) -> Result<Value, E> {
            Ok(Value::String(v))
        }

        fn visit_unit<E>(self) -> Result<Value, E> {
            Ok(Value::Null)
        }

        fn visit_none<E>(self) -> Result<Value, E> {
            Ok(Value::Null)
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
            let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(4096));
            loop {
                let at = Place::Index(self.at, out.len());
                let node = Node {
                    at: &at,
                    duplicate: self.duplicate,
                };
                match seq.next_element_seed(node)? {
                    Some(v) => out.push(v),
                    None => return Ok(Value::Array(out)),
                }
            }
        }

        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
            let mut out = Map::new();
            while let Some(key) = map.next_key::<String>()? {
                if out.contains_key(&key) {
                    let message = format!("key {key:?} appears twice in one object");
                    *self.duplicate.borrow_mut() = Some((self.at.pointer(), key));
                    return Err(de::Error::custom(message));
                }
                let at = Place::Key(self.at, &key);
                let value = map.next_value_seed(Node {
                    at: &at,
                    duplicate: self.duplicate,
                })?;
                out.insert(key, value);
            }
            Ok(Value::Object(out))
        }
    }
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
