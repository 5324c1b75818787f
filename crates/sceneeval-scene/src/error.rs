use sceneeval_geom::GeomError;
use thiserror::Error;

/// What was wrong with the parts a [`crate::Scene`] was built from.
///
/// Variants name the object, room, wall or opening at fault so that a loader can add the file
/// and JSON pointer on top.
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
    #[error("wall id {id:?} is used twice")]
    DuplicateWallId {
        /// The repeated id.
        id: String,
    },
    /// An object's pose has a NaN or infinite component.
    #[error("object {object:?}: pose is not finite")]
    NonFinitePose {
        /// The object id.
        object: String,
    },
    /// Some geometry of an object, a floor or a wall was rejected.
    #[error("{what}: {source}")]
    Geometry {
        /// Which element, e.g. `object "bed"` or `room "r0" floor`.
        what: String,
        /// The geometric problem.
        #[source]
        source: GeomError,
    },
    /// A wall's two end points coincide.
    #[error("wall {wall:?} has zero length")]
    ZeroLengthWall {
        /// The wall id.
        wall: String,
    },
    /// A wall's height is zero, negative or not finite.
    #[error("wall {wall:?} height must be positive and finite, got {height}")]
    BadWallHeight {
        /// The wall id.
        wall: String,
        /// The height given.
        height: f64,
    },
    /// A wall's thickness is negative or not finite.
    #[error("wall {wall:?} thickness must be non-negative and finite, got {thickness}")]
    BadWallThickness {
        /// The wall id.
        wall: String,
        /// The thickness given.
        thickness: f64,
    },
    /// A wall end point or base height is not finite.
    #[error("wall {wall:?}: {what} is not finite")]
    NonFiniteWall {
        /// The wall id.
        wall: String,
        /// Which value.
        what: &'static str,
    },
    /// An opening is empty, inverted, not finite, or lies entirely outside its wall.
    #[error("wall {wall:?} opening {opening:?}: {reason}")]
    BadOpening {
        /// The wall id.
        wall: String,
        /// The opening id.
        opening: String,
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
    #[error("room {room:?}: {what} is not finite")]
    NonFiniteRoom {
        /// The room id.
        room: String,
        /// Which value.
        what: &'static str,
    },
    /// A lookup by object id found nothing.
    #[error("no object with id {id:?}")]
    UnknownObject {
        /// The id asked for.
        id: String,
    },
}

impl SceneError {
    pub(crate) fn geometry(what: impl Into<String>, source: GeomError) -> Self {
        SceneError::Geometry {
            what: what.into(),
            source,
        }
    }
}
