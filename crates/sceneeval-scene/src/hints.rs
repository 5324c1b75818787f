//! What a scene's author states about an object's intended placement: its support type and its
//! functional sides.
//!
//! The plausibility metrics need both (support: what the object should rest on;
//! accessibility: which sides must stay free). The reference asks a VLM; a generator usually
//! knows them already (it hung the TV on the wall on purpose), so a [`SceneObject`] can carry
//! them, and `sceneeval-io` reads and writes them as the `supportType` and `functionalSides`
//! fields of a sceneState object. They are *stated intent*, never derived from the geometry
//! being checked.
//!
//! [`SceneObject`]: crate::SceneObject

use std::fmt;
use std::str::FromStr;

/// What an object should rest on (the paper's four support types).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum SupportType {
    /// Stands on the floor (gravity -z).
    Ground,
    /// Stands on another object (gravity -z).
    Object,
    /// Hangs on a wall (gravity along the object's back, local +y).
    Wall,
    /// Hangs from the ceiling (gravity +z).
    Ceiling,
}

impl SupportType {
    /// All four types.
    pub const ALL: [SupportType; 4] = [
        SupportType::Ground,
        SupportType::Object,
        SupportType::Wall,
        SupportType::Ceiling,
    ];

    /// `"ground"`, `"object"`, `"wall"` or `"ceiling"`.
    pub const fn name(self) -> &'static str {
        match self {
            SupportType::Ground => "ground",
            SupportType::Object => "object",
            SupportType::Wall => "wall",
            SupportType::Ceiling => "ceiling",
        }
    }
}

impl fmt::Display for SupportType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The error returned when a string is not one of the four support type names.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown support type {0:?}: expected one of ground, object, wall, ceiling")]
pub struct UnknownSupportType(pub String);

impl FromStr for SupportType {
    type Err = UnknownSupportType;

    /// Parses a support type name, ignoring ASCII case and surrounding whitespace.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim();
        SupportType::ALL
            .into_iter()
            .find(|ty| ty.name().eq_ignore_ascii_case(t))
            .ok_or_else(|| UnknownSupportType(s.to_owned()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for ty in SupportType::ALL {
            assert_eq!(ty.name().parse::<SupportType>(), Ok(ty));
            assert_eq!(ty.to_string(), ty.name());
        }
        assert_eq!(" Wall ".parse::<SupportType>(), Ok(SupportType::Wall));
        let err = "shelf".parse::<SupportType>().unwrap_err();
        assert!(err.to_string().contains("\"shelf\""), "{err}");
    }
}
