//! [`SceneName`]: a scene's identity, made once where scene files are found (the file stem and
//! the benchmark id in it, which finds the scene's annotation row).

use std::fmt;

use sceneeval_annotation::{AnnotationRow, Annotations};
use serde::{Deserialize, Serialize};

/// A scene's name and benchmark id: the one rule from a scene to its annotation row.
///
/// The name is the scene file's stem (`scene_007`), also the name of its output folder. The
/// benchmark id is the digits after the name's last `_`, as written (`007`); the reference
/// numbers scenes this way. Serialized as the two fields `scene` and `scene_id` of
/// `eval.json`.
///
/// ```
/// use sceneeval_results::SceneName;
/// let name = SceneName::new("scene_007");
/// assert_eq!((name.as_str(), name.id(), name.number()), ("scene_007", Some("007"), Some(7)));
/// assert_eq!(SceneName::new("kitchen").id(), None);
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct SceneName {
    /// The name.
    #[serde(rename = "scene")]
    name: String,
    /// The benchmark id, if the name has one.
    #[serde(rename = "scene_id")]
    id: Option<String>,
}

impl SceneName {
    /// The name `name` with its benchmark id (the digits after its last `_`, if any).
    pub fn new(name: impl Into<String>) -> Self {
        let name = name.into();
        let id = name
            .rsplit_once('_')
            .map(|(_, id)| id)
            .filter(|id| !id.is_empty() && id.bytes().all(|b| b.is_ascii_digit()))
            .map(str::to_owned);
        SceneName { name, id }
    }

    /// The name (`scene_007`).
    #[inline]
    pub fn as_str(&self) -> &str {
        &self.name
    }

    /// The benchmark id as written (`007`), if the name has one.
    #[inline]
    pub fn id(&self) -> Option<&str> {
        self.id.as_deref()
    }

    /// The benchmark id as a number (`7`), if the name has one that fits a `u64`.
    pub fn number(&self) -> Option<u64> {
        self.id()?.parse().ok()
    }

    /// The scene's annotation row: the row whose ID is the benchmark id as written (`007`),
    /// else the row of its number (`7`; an id of zeros is row `0`). Scene files are often
    /// numbered with leading zeros; annotation files usually are not.
    ///
    /// ```
    /// use sceneeval_results::SceneName;
    /// use sceneeval_annotation::Annotations;
    /// let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n0,hard,A kitchen.,,,,\n12,easy,A bedroom.,,,,\n";
    /// let annotations = Annotations::from_csv_str(csv).unwrap();
    /// let difficulty = |name| SceneName::new(name).annotation_row(&annotations).map(|r| r.difficulty.as_str());
    /// assert_eq!(difficulty("scene_012"), Some("easy"));
    /// assert_eq!(difficulty("scene_000"), Some("hard"));
    /// assert_eq!(difficulty("scene_13"), None);
    /// ```
    pub fn annotation_row<'a>(&self, annotations: &'a Annotations) -> Option<&'a AnnotationRow> {
        let id = self.id()?;
        annotations.get(id).or_else(|| {
            let number = id.trim_start_matches('0');
            // All zeros is the number 0, not an empty id.
            annotations.get(if number.is_empty() { "0" } else { number })
        })
    }
}

impl fmt::Display for SceneName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_ids() {
        let cases = [
            ("scene_12", Some("12")),
            ("my_scene_007", Some("007")),
            ("scene", None),
            ("scene_x1", None),
            ("scene_", None),
        ];
        for (name, id) in cases {
            assert_eq!(SceneName::new(name).id(), id, "{name}");
        }
        let json = serde_json::to_string(&SceneName::new("scene_007")).unwrap();
        assert_eq!(json, r#"{"scene":"scene_007","scene_id":"007"}"#);
    }

    #[test]
    fn scenes_numbered_with_leading_zeros_read_their_row() {
        let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
                   12,easy,A bedroom.,,,,\n\
                   0,hard,A kitchen.,,,,\n\
                   007,medium,A study.,,,,\n";
        let annotations = Annotations::from_csv_reader(csv.as_bytes()).unwrap();
        let difficulty = |id: &str| {
            SceneName::new(format!("scene_{id}"))
                .annotation_row(&annotations)
                .map(|r| r.difficulty.as_str())
        };
        assert_eq!(difficulty("12"), Some("easy"));
        assert_eq!(difficulty("012"), Some("easy"));
        assert_eq!(difficulty("0"), Some("hard"));
        assert_eq!(difficulty("000"), Some("hard"));
        // An id written with zeros in the annotations is found as written.
        assert_eq!(difficulty("007"), Some("medium"));
        assert_eq!(difficulty("7"), None);
        assert_eq!(difficulty("13"), None);
        assert_eq!(SceneName::new("scene").annotation_row(&annotations), None);
    }
}
