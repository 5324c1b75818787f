//! Where in a query's JSON a value was wrong: the path of the key at fault
//! (`target.half_size`, `targets[2].center`, `openings[0].kind`), so that an error names the
//! key and the object, not only what serde expected.
//!
//! Paths are found by reading again, through `serde_path_to_error`, only when a first reading
//! failed: the readings that succeed pay nothing.

use serde::de::{Deserialize, DeserializeOwned};
use serde_path_to_error::{Path, Segment};

/// The path of the key at which reading a `T` from `text` fails, as `a.b[2].c` (empty when
/// the error is about the value as a whole); `None` when `text` reads as a `T`.
///
/// An unknown key's path is that of the object holding it: the error already names the key.
///
/// ```
/// use sceneeval_relate::{ObjectSpec, error_path};
/// let text = r#"{"center":[0,0,0],"half_size":[1,1]}"#;
/// assert_eq!(error_path::<ObjectSpec>(text).as_deref(), Some("half_size"));
/// assert_eq!(error_path::<ObjectSpec>(r#"{"center":[0,0,0],"colour":1}"#).as_deref(), Some(""));
/// assert_eq!(error_path::<ObjectSpec>(r#"{"center":[0,0,0],"half_size":[1,1,1]}"#), None);
/// ```
pub fn error_path<'de, T: Deserialize<'de>>(text: &'de str) -> Option<String> {
    let mut deserializer = serde_json::Deserializer::from_str(text);
    match serde_path_to_error::deserialize::<_, T>(&mut deserializer) {
        Ok(_) => None,
        Err(e) => Some(path_text(e.path(), is_unknown_field(e.inner()))),
    }
}

/// Reads a `T` from `value`; the error gives the path of the key at fault as
/// [`error_path`] does, with the error.
///
/// # Errors
/// The path (empty for the value as a whole) and serde_json's error.
pub fn from_value<T: DeserializeOwned>(value: serde_json::Value) -> Result<T, (String, serde_json::Error)> {
    serde_path_to_error::deserialize::<_, T>(value).map_err(|e| {
        let path = path_text(e.path(), is_unknown_field(e.inner()));
        (path, e.into_inner())
    })
}

/// `what` followed by `path` as one path: `target` and `half_size` give `target.half_size`,
/// `targets` and `[2]` give `targets[2]`; an empty `path` leaves `what`.
///
/// ```
/// use sceneeval_relate::under;
/// assert_eq!(under("target", "half_size"), "target.half_size");
/// assert_eq!(under("rooms", "[2].floor"), "rooms[2].floor");
/// assert_eq!(under("room", ""), "room");
/// ```
pub fn under(what: &str, path: &str) -> String {
    if path.is_empty() || path.starts_with('[') || what.is_empty() {
        format!("{what}{path}")
    } else {
        format!("{what}.{path}")
    }
}

/// Whether serde's error is about a key the type does not have (its message names the key).
fn is_unknown_field(e: &serde_json::Error) -> bool {
    e.to_string().starts_with("unknown field `")
}

/// The path as `a.b[2].c`; without its last key when `drop_last` (an unknown key's own name).
fn path_text(path: &Path, drop_last: bool) -> String {
    let segments: Vec<&Segment> = path.iter().collect();
    let keep = if drop_last {
        segments.len().saturating_sub(1)
    } else {
        segments.len()
    };
    let mut text = String::new();
    for segment in &segments[..keep] {
        match segment {
            Segment::Seq { index } => text.push_str(&format!("[{index}]")),
            Segment::Map { key } | Segment::Enum { variant: key } => {
                if !text.is_empty() {
                    text.push('.');
                }
                text.push_str(key);
            }
            Segment::Unknown => {
                if !text.is_empty() {
                    text.push('.');
                }
                text.push('?');
            }
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ObjectSpec, Operand};
    use sceneeval_scene::RoomSpec;

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Line<'a> {
        #[serde(borrow, default)]
        target: Option<Operand<'a>>,
        #[serde(borrow, default)]
        targets: Option<Vec<Operand<'a>>>,
    }

    #[test]
    fn paths_name_the_key_and_the_object() {
        for (text, path) in [
            (
                r#"{"target":{"center":[0,0,0],"half_size":[1,1]}}"#,
                "target.half_size",
            ),
            (
                r#"{"targets":["a",{"center":[0,0,0],"half_size":[1,1]}]}"#,
                "targets[1].half_size",
            ),
            (
                r#"{"target":{"center":[0,0,0],"half_size":[1,1,1,1]}}"#,
                "target.half_size",
            ),
            (
                r#"{"target":{"center":[0,0,"x"],"half_size":[1,1,1]}}"#,
                "target.center[2]",
            ),
            // An unknown key: the object holding it (the message names the key).
            (r#"{"target":{"colour":1}}"#, "target"),
            (r#"{"colour":1}"#, ""),
            (r#"{"target":3}"#, "target"),
        ] {
            assert_eq!(error_path::<Line<'_>>(text).as_deref(), Some(path), "{text}");
        }
        assert_eq!(error_path::<Line<'_>>(r#"{"target":"bed"}"#), None);
    }

    #[test]
    fn values_read_with_their_paths() {
        let room = serde_json::json!({"floor": [[0, 0], [1, 0, 2]], "height": 2.5});
        let (path, e) = from_value::<RoomSpec>(room).unwrap_err();
        assert_eq!(path, "floor[1]");
        assert_eq!(under("room", &path), "room.floor[1]");
        assert!(e.to_string().contains("length"), "{e}");
        let spec: ObjectSpec =
            from_value(serde_json::json!({"center": [0, 0, 0], "half_size": [1, 1, 1]})).unwrap();
        assert!(matches!(spec, ObjectSpec::Box(_)));
    }
}
