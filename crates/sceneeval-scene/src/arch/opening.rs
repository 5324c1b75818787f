//! Doors and windows.

use sceneeval_geom::{Obb, Real};

/// Whether an opening is a door or a window: the two [`crate::ArchElement`] kinds an opening
/// can be ([`crate::ArchElement::opening`] and `From` convert).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum OpeningKind {
    /// A door.
    Door,
    /// A window.
    Window,
}

impl OpeningKind {
    /// `"door"` or `"window"`: the name of its [`crate::ArchElement`].
    pub const fn name(self) -> &'static str {
        match self {
            OpeningKind::Door => crate::ArchElement::Door.name(),
            OpeningKind::Window => crate::ArchElement::Window.name(),
        }
    }
}

/// A door or window: a rectangular hole through a wall, in wall coordinates.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Opening {
    /// The opening's id (unique within its wall).
    pub id: String,
    /// Door or window.
    pub kind: OpeningKind,
    /// Start and end along the wall, metres from the wall's start point.
    pub along: [Real; 2],
    /// Bottom and top, metres above the wall's base.
    pub height: [Real; 2],
}

impl Opening {
    /// A door or window spanning `along` and `height` (wall coordinates, metres).
    pub fn new(id: impl Into<String>, kind: OpeningKind, along: [Real; 2], height: [Real; 2]) -> Self {
        Opening {
            id: id.into(),
            kind,
            along,
            height,
        }
    }

    /// Width along the wall.
    #[inline]
    pub fn width(&self) -> Real {
        self.along[1] - self.along[0]
    }

    /// Height of the hole.
    #[inline]
    pub fn hole_height(&self) -> Real {
        self.height[1] - self.height[0]
    }
}

/// A door or window of a room, prepared once with the room: its wall, its position in that
/// wall's list, its kind and its box ([`crate::Wall::opening_obb`]). [`crate::Room::openings`]
/// lists them in wall order, so that queries over every door of a room read one slice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlacedOpening {
    /// Index of its wall in [`crate::Room::walls`].
    pub wall: usize,
    /// Index in that wall's [`crate::Wall::openings`].
    pub opening: usize,
    /// Door or window.
    pub kind: OpeningKind,
    /// The opening's box: its rectangle on the wall's inner face, through the wall's thickness
    /// (at least 1 mm deep), local -y into the room.
    pub obb: Obb,
}
