//! The kinds of architectural element: the one vocabulary of walls, floors, ceilings, windows,
//! doors and rooms.

use std::fmt;

use crate::OpeningKind;

/// A kind of architectural element: the one list every crate names architecture by (the
/// annotation schema's element types, the VLM's `architectural_element_type`, the elements the
/// object-architecture relations measure against, sceneState's element types).
///
/// Crates that accept only some kinds say which: an opening is a door or a window
/// ([`OpeningKind`], [`ArchElement::opening`]); the distance relations measure walls, doors and
/// windows; sceneState elements are floors, ceilings and walls.
///
/// ```
/// use sceneeval_scene::{ArchElement, OpeningKind};
/// assert_eq!(ArchElement::from_name("window"), Some(ArchElement::Window));
/// assert_eq!(ArchElement::Window.opening(), Some(OpeningKind::Window));
/// assert_eq!(ArchElement::Room.to_string(), "room");
/// assert_eq!(ArchElement::NAMES, ["wall", "floor", "ceiling", "window", "door", "room"]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum ArchElement {
    /// `wall`: a wall (its solid slab with doors and windows cut out).
    Wall,
    /// `floor`: a room's floor.
    Floor,
    /// `ceiling`: a room's ceiling.
    Ceiling,
    /// `window`: a window opening.
    Window,
    /// `door`: a door opening.
    Door,
    /// `room`: the room as a whole.
    Room,
}

impl ArchElement {
    /// All six, in the paper's order.
    pub const ALL: [ArchElement; 6] = [
        ArchElement::Wall,
        ArchElement::Floor,
        ArchElement::Ceiling,
        ArchElement::Window,
        ArchElement::Door,
        ArchElement::Room,
    ];

    /// The names of [`ArchElement::ALL`], in that order.
    pub const NAMES: [&'static str; 6] = {
        let mut names = [""; 6];
        let mut i = 0;
        while i < names.len() {
            names[i] = ArchElement::ALL[i].name();
            i += 1;
        }
        names
    };

    /// The name: `wall`, `floor`, `ceiling`, `window`, `door` or `room`.
    pub const fn name(self) -> &'static str {
        match self {
            ArchElement::Wall => "wall",
            ArchElement::Floor => "floor",
            ArchElement::Ceiling => "ceiling",
            ArchElement::Window => "window",
            ArchElement::Door => "door",
            ArchElement::Room => "room",
        }
    }

    /// The kind with this exact name (lower case, no surrounding whitespace), if any.
    pub fn from_name(name: &str) -> Option<ArchElement> {
        ArchElement::ALL.into_iter().find(|e| e.name() == name)
    }

    /// The opening kind, for doors and windows.
    pub const fn opening(self) -> Option<OpeningKind> {
        match self {
            ArchElement::Door => Some(OpeningKind::Door),
            ArchElement::Window => Some(OpeningKind::Window),
            _ => None,
        }
    }
}

impl From<OpeningKind> for ArchElement {
    fn from(kind: OpeningKind) -> Self {
        match kind {
            OpeningKind::Door => ArchElement::Door,
            OpeningKind::Window => ArchElement::Window,
        }
    }
}

impl fmt::Display for ArchElement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_openings_agree() {
        for e in ArchElement::ALL {
            assert_eq!(ArchElement::from_name(e.name()), Some(e));
            if let Some(kind) = e.opening() {
                assert_eq!(ArchElement::from(kind), e);
                assert_eq!(kind.name(), e.name());
            }
        }
        assert_eq!(ArchElement::from_name("Wall"), None, "exact names only");
        assert_eq!(ArchElement::from_name("walls"), None);
    }
}
