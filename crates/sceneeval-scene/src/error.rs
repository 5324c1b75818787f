use sceneeval_geom::GeomError;
use thiserror::Error;

use crate::{Element, RoomId};

/// What was wrong with the parts a [`crate::Scene`] was built from. (Elements are boxed to
/// keep the error small on the success path.)
///
/// Every variant names the element at fault ([`SceneError::element`]), structurally, so that
/// a loader can add the file and JSON pointer on top without reading the message; geometric
/// causes are kept as the [`std::error::Error::source`].
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SceneError {
    /// Two objects share an id.
    #[error("object id {id:?} is used twice")]
    DuplicateObjectId {
        /// The repeated id.
        id: String,
    },
    /// Two rooms share an id.
    #[error("room id {id:?} is used twice")]
    DuplicateRoomId {
        /// The repeated id.
        id: String,
    },
    /// Two walls share an id.
    #[error("wall id {id:?} is used twice: {first} and {second}")]
    DuplicateWallId {
        /// The repeated id.
        id: String,
        /// The first wall with it.
        first: Box<Element>,
        /// The second.
        second: Box<Element>,
    },
    /// Two doors or windows of one wall share an id.
    #[error("opening id {id:?} is used twice in one wall: {first} and {second}")]
    DuplicateOpeningId {
        /// The repeated id.
        id: String,
        /// The first opening with it.
        first: Box<Element>,
        /// The second.
        second: Box<Element>,
    },
    /// An object's pose has a NaN or infinite component.
    #[error("object {object:?}: pose is not finite")]
    NonFinitePose {
        /// The object id.
        object: String,
    },
    /// Some geometry of an object, a floor, a ceiling or a wall was rejected.
    #[error("{element}: {source}")]
    Geometry {
        /// The element whose geometry was rejected.
        element: Box<Element>,
        /// The geometric problem.
        #[source]
        source: GeomError,
    },
    /// A wall's two end points coincide.
    #[error("{wall} has zero length")]
    ZeroLengthWall {
        /// The wall.
        wall: Box<Element>,
    },
    /// A wall's height is zero, negative or not finite.
    #[error("{wall}: height must be positive and finite, got {height}")]
    BadWallHeight {
        /// The wall.
        wall: Box<Element>,
        /// The height given.
        height: f64,
    },
    /// A wall's thickness is negative or not finite.
    #[error("{wall}: thickness must be non-negative and finite, got {thickness}")]
    BadWallThickness {
        /// The wall.
        wall: Box<Element>,
        /// The thickness given.
        thickness: f64,
    },
    /// A wall end point or base height is not finite.
    #[error("{wall}: {what} is not finite")]
    NonFiniteWall {
        /// The wall.
        wall: Box<Element>,
        /// Which value.
        what: &'static str,
    },
    /// An opening is empty, inverted, not finite, or lies entirely outside its wall.
    #[error("{opening}: {reason}")]
    BadOpening {
        /// The opening.
        opening: Box<Element>,
        /// What is wrong.
        reason: String,
    },
    /// A room-building call referred to a wall index the room does not have.
    #[error("room {room:?} has {count} walls, there is no wall {index}")]
    NoSuchWall {
        /// The room id.
        room: String,
        /// The index asked for.
        index: usize,
        /// Number of walls.
        count: usize,
    },
    /// A floor or ceiling height is not finite.
    #[error("{element}: {what} is not finite")]
    NonFiniteRoom {
        /// The floor or the ceiling.
        element: Box<Element>,
        /// Which value.
        what: &'static str,
    },
    /// An explicit ceiling is at or below its room's floor.
    #[error("room {:?}: the ceiling (z = {ceiling_z}) is not above the floor (z = {floor_z})", room.as_str())]
    CeilingBelowFloor {
        /// The room.
        room: RoomId,
        /// World z of the floor.
        floor_z: f64,
        /// World z of the ceiling.
        ceiling_z: f64,
    },
    /// A lookup by object id found nothing.
    #[error("no object with id {id:?}")]
    UnknownObject {
        /// The id asked for.
        id: String,
    },
    /// A lookup by object index found nothing.
    #[error("no object at index {index}: the scene has {count}")]
    NoSuchObject {
        /// The index asked for.
        index: usize,
        /// Number of objects.
        count: usize,
    },
}

impl SceneError {
    /// The element at fault, when the error is about one (for a duplicate, the second
    /// occurrence).
    pub fn element(&self) -> Option<Element> {
        match self {
            SceneError::DuplicateObjectId { id }
            | SceneError::NonFinitePose { object: id }
            | SceneError::UnknownObject { id } => Some(Element::Object(id.as_str().into())),
            SceneError::DuplicateRoomId { id } => Some(Element::Room(id.as_str().into())),
            SceneError::NoSuchWall { room, .. } => Some(Element::Room(room.as_str().into())),
            SceneError::CeilingBelowFloor { room, .. } => Some(Element::Ceiling { room: room.clone() }),
            SceneError::DuplicateWallId { second, .. } | SceneError::DuplicateOpeningId { second, .. } => {
                Some((**second).clone())
            }
            SceneError::Geometry { element, .. } | SceneError::NonFiniteRoom { element, .. } => {
                Some((**element).clone())
            }
            SceneError::ZeroLengthWall { wall }
            | SceneError::BadWallHeight { wall, .. }
            | SceneError::BadWallThickness { wall, .. }
            | SceneError::NonFiniteWall { wall, .. } => Some((**wall).clone()),
            SceneError::BadOpening { opening, .. } => Some((**opening).clone()),
            SceneError::NoSuchObject { .. } => None,
        }
    }
}
