//! Structured references to the parts of a scene, for errors and warnings.

use std::fmt;

use crate::{ObjectId, RoomId};

/// One element of a scene: an object, a room or one of its parts. Errors carry it so that a
/// loader can point at the value in its own file (a JSON pointer) without reading the message,
/// and a user sees which element is at fault.
///
/// Walls and openings are identified by their position as given to the room (wall `i` of the
/// room's wall list, opening `k` of that wall's list) as well as by their ids, which a file may
/// repeat.
///
/// ```
/// use sceneeval_scene::Element;
/// let e = Element::Opening {
///     room: "r0".into(),
///     wall: 2,
///     wall_id: "w2".into(),
///     opening: 0,
///     id: "door_0".into(),
/// };
/// assert_eq!(e.to_string(), r#"opening "door_0" (0) of wall "w2" (2) of room "r0""#);
/// assert_eq!(e.room().map(|r| r.as_str()), Some("r0"));
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Element {
    /// An object.
    Object(ObjectId),
    /// A room as a whole.
    Room(RoomId),
    /// A room's floor.
    Floor {
        /// The room.
        room: RoomId,
    },
    /// A room's ceiling.
    Ceiling {
        /// The room.
        room: RoomId,
    },
    /// A wall of a room.
    Wall {
        /// The room.
        room: RoomId,
        /// Position in the room's list of walls.
        wall: usize,
        /// The wall's id.
        id: String,
    },
    /// A door or window of a wall.
    Opening {
        /// The room.
        room: RoomId,
        /// Position of its wall in the room's list of walls.
        wall: usize,
        /// The wall's id.
        wall_id: String,
        /// Position in the wall's list of openings.
        opening: usize,
        /// The opening's id.
        id: String,
    },
}

impl Element {
    /// The room the element belongs to (`None` for an object).
    pub fn room(&self) -> Option<&RoomId> {
        match self {
            Element::Object(_) => None,
            Element::Room(room)
            | Element::Floor { room }
            | Element::Ceiling { room }
            | Element::Wall { room, .. }
            | Element::Opening { room, .. } => Some(room),
        }
    }
}

impl fmt::Display for Element {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Element::Object(id) => write!(f, "object {:?}", id.as_str()),
            Element::Room(room) => write!(f, "room {:?}", room.as_str()),
            Element::Floor { room } => write!(f, "floor of room {:?}", room.as_str()),
            Element::Ceiling { room } => write!(f, "ceiling of room {:?}", room.as_str()),
            Element::Wall { room, wall, id } => {
                write!(f, "wall {id:?} ({wall}) of room {:?}", room.as_str())
            }
            Element::Opening {
                room,
                wall,
                wall_id,
                opening,
                id,
            } => write!(
                f,
                "opening {id:?} ({opening}) of wall {wall_id:?} ({wall}) of room {:?}",
                room.as_str()
            ),
        }
    }
}
