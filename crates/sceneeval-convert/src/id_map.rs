//! `--id-map`: which SceneEval-500 id each converted scene gets.

use std::collections::BTreeMap;

use std::path::Path;

use sceneeval_io::IoError;
use sceneeval_io::scene_state::json_in;
use serde_json::Value;

use crate::ConvertError;

/// A map from scene keys (the `NNN` of `scene_NNN`, or a Holodeck scene's position) to the
/// SceneEval-500 ids the converted files are named after (`scene_<ID>.json`), as the fork's
/// `--mapping` gives it: a JSON object such as `{"0": 106, "1": 56}`. With a map, scenes whose
/// key it does not list are skipped.
///
/// ```
/// use sceneeval_convert::IdMap;
/// let map = IdMap::parse(r#"{"0": 106, "007": 56}"#).unwrap();
/// assert_eq!(map.get(0), Some(106));
/// assert_eq!(map.get(7), Some(56));
/// assert_eq!(map.get(1), None);
/// assert!(IdMap::parse(r#"{"0": 1, "1": 1}"#).is_err(), "two scenes, one id");
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct IdMap {
    ids: BTreeMap<u64, u64>,
}

impl IdMap {
    /// Parses the JSON text of a map. Keys are decimal scene keys (leading zeros allowed);
    /// values are non-negative integer ids (or strings of digits).
    ///
    /// # Errors
    /// [`ConvertError::IdMap`] for malformed JSON, a key or value that is not a
    /// non-negative integer, a key given twice (`"7"` and `"007"`), or two keys mapped to one id.
    pub fn parse(text: &str) -> Result<IdMap, ConvertError> {
        let bad = |reason: String| ConvertError::IdMap { reason };
        let value: Value = json_in::parse(text, Path::new("")).map_err(|e| {
            bad(match e {
                IoError::DuplicateKey { key, .. } => format!("scene {key:?} is given twice"),
                IoError::MalformedJson {
                    line,
                    column,
                    message,
                    ..
                } => format!("not valid JSON: {message} at line {line} column {column}"),
                other => other.to_string(),
            })
        })?;
        let Some(object) = value.as_object() else {
            return Err(bad(format!(
                "expected a JSON object of scene keys to ids, such as {{\"0\": 106}}, found {value}"
            )));
        };
        let mut ids = BTreeMap::new();
        let mut targets: BTreeMap<u64, &str> = BTreeMap::new();
        for (key, v) in object {
            let k = number(key).ok_or_else(|| bad(format!("key {key:?} is not a scene number")))?;
            let id = match v {
                Value::Number(n) => n.as_u64(),
                Value::String(s) => number(s),
                _ => None,
            }
            .ok_or_else(|| bad(format!("{key:?}: {v} is not a non-negative integer id")))?;
            if ids.insert(k, id).is_some() {
                return Err(bad(format!("scene {k} is given twice (key {key:?})")));
            }
            if let Some(first) = targets.insert(id, key) {
                return Err(bad(format!("keys {first:?} and {key:?} both map to id {id}")));
            }
        }
        Ok(IdMap { ids })
    }

    /// The id of scene `key`, if the map lists it.
    pub fn get(&self, key: u64) -> Option<u64> {
        self.ids.get(&key).copied()
    }

    /// The scene keys the map lists, in order.
    pub fn keys(&self) -> impl Iterator<Item = u64> + '_ {
        self.ids.keys().copied()
    }
}

/// A decimal number of at most 19 digits, leading zeros allowed.
pub(crate) fn number(s: &str) -> Option<u64> {
    (!s.is_empty() && s.len() <= 19 && s.bytes().all(|b| b.is_ascii_digit()))
        .then(|| s.parse().ok())
        .flatten()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_parse_and_refuse_ambiguity() {
        let m = IdMap::parse(r#"{"2": "31", "10": 0}"#).unwrap();
        assert_eq!(m.keys().collect::<Vec<_>>(), [2, 10]);
        assert_eq!((m.get(2), m.get(10)), (Some(31), Some(0)));
        for bad in [
            "[1, 2]",
            r#"{"a": 1}"#,
            r#"{"1": -3}"#,
            r#"{"1": 2.5}"#,
            r#"{"1": "x"}"#,
            r#"{"7": 1, "007": 2}"#,
            r#"{"7": 1, "7": 2}"#,
            r#"{"1": 5, "2": 5}"#,
            "{",
        ] {
            assert!(
                matches!(IdMap::parse(bad), Err(ConvertError::IdMap { .. })),
                "{bad}"
            );
        }
        assert_eq!(number("007"), Some(7));
        assert_eq!(number("+7"), None);
        assert_eq!(number(""), None);
    }
}
