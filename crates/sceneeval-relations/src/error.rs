use sceneeval_geom::GeomError;
use thiserror::Error;

/// What was wrong with a relation name, a query or the geometry it was asked about.
///
/// Variants name the offending input: the relation (in its printed form), the argument, the
/// object or floor id, or the position in a batch.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RelationError {
    /// The name is none of the 23 relation names (or their aliases).
    #[error(
        "unknown relation {name:?}: expected one of {}",
        crate::relation::expected_names()
    )]
    UnknownRelation {
        /// The name given.
        name: String,
    },
    /// The relationship mapping said "None": no predefined relation applies.
    #[error("relation {name:?} means that no predefined relation applies")]
    NoRelation {
        /// The name given (`None` in any case).
        name: String,
    },
    /// A relation that needs an argument (a side, `long`/`short`, or an element type) got none.
    #[error("relation {relation} needs {expected}")]
    MissingArgument {
        /// The relation's base name, e.g. `side_of`.
        relation: &'static str,
        /// What it needs, e.g. `a side (left, right, front, back, top, bottom)`.
        expected: &'static str,
    },
    /// The argument is not valid for this relation.
    #[error("relation {relation}: {value:?} is not {expected}")]
    BadArgument {
        /// The relation's base name.
        relation: &'static str,
        /// The argument given.
        value: String,
        /// What it needs.
        expected: &'static str,
    },
    /// A relation that takes no argument was given one.
    #[error("relation {relation} takes no argument, got {value:?}")]
    UnexpectedArgument {
        /// The relation's base name.
        relation: &'static str,
        /// The argument given.
        value: String,
    },
    /// The relation is of another kind than the call expects (for example an
    /// object-architecture relation passed to an object-object kernel).
    #[error("relation {relation} is {actual}, but {expected} was expected here")]
    WrongKind {
        /// The relation in its printed form.
        relation: String,
        /// Its kind, e.g. `an object-architecture relation`.
        actual: &'static str,
        /// What the call accepts.
        expected: &'static str,
    },
    /// A relation got fewer target objects than it needs.
    #[error("relation {relation} needs at least {needed} target object(s), got {got}")]
    NotEnoughTargets {
        /// The relation in its printed form.
        relation: String,
        /// How many it needs.
        needed: usize,
        /// How many it got.
        got: usize,
    },
    /// No object of the scene has this id.
    #[error("no object with id {id:?} in the scene")]
    UnknownObject {
        /// The id asked for.
        id: String,
    },
    /// No room of the scene has a floor with this id (floor ids are `floor_<room>` by default;
    /// room ids are accepted too).
    #[error("no floor or room with id {id:?} in the scene")]
    UnknownFloor {
        /// The id asked for.
        id: String,
    },
    /// An object-architecture relation was asked about a scene without rooms.
    #[error("relation {relation} needs architecture, but the scene has no rooms")]
    NoArchitecture {
        /// The relation in its printed form.
        relation: String,
    },
    /// The slices of a batch call have different lengths.
    #[error("batch: {what} has {got} entries, expected {expected}")]
    LengthMismatch {
        /// Which slice.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The length it should have.
        expected: usize,
    },
    /// No object of the scene is at this index.
    #[error("no object at index {index}: the scene has {count}")]
    NoSuchObject {
        /// The index asked for.
        index: usize,
        /// Number of objects in the scene.
        count: usize,
    },
    /// A relation got more target objects than it accepts (its cost grows faster than the
    /// number of targets).
    #[error("relation {relation} accepts at most {limit} target objects, got {got}")]
    TooManyTargets {
        /// The relation in its printed form.
        relation: String,
        /// How many it got.
        got: usize,
        /// The most it accepts.
        limit: usize,
    },
    /// A parameter is out of its domain (for example a negative standard deviation).
    #[error("parameter {name} = {value} is invalid: {reason}")]
    BadParameter {
        /// The parameter's field name in [`crate::RelationParams`].
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must satisfy.
        reason: &'static str,
    },
    /// A number of an object given as plain data is NaN or infinite.
    #[error("{field} is not finite")]
    NotFinite {
        /// The field, e.g. `target.center` or `anchor.yaw`.
        field: String,
    },
    /// Two inputs that exclude each other were both given.
    #[error("{what}: give either {first} or {second}, not both")]
    Conflict {
        /// Where, e.g. `target` or `relation "side_of(left)"`.
        what: String,
        /// The first input.
        first: &'static str,
        /// The second input.
        second: &'static str,
    },
    /// A scale of an object given as plain data is not finite or not positive.
    #[error("{what}.scale {scale:?} must be finite and positive")]
    BadScale {
        /// The object, e.g. `target`.
        what: String,
        /// The scale along x, y, z.
        scale: [f64; 3],
    },
    /// A relation was not given an operand its kind needs.
    #[error("relation {relation} needs \"{operand}\"")]
    MissingOperand {
        /// The relation in its printed form.
        relation: String,
        /// The operand: `target`, `anchor`, `targets` or `room`.
        operand: &'static str,
    },
    /// A relation was given an operand its kind does not use.
    #[error("relation {relation} does not use \"{operand}\"")]
    UnexpectedOperand {
        /// The relation in its printed form.
        relation: String,
        /// The operand.
        operand: &'static str,
    },
    /// Plain geometry given to a constructor was rejected.
    #[error("{what}: {source}")]
    Geometry {
        /// Which input, e.g. `room floor`.
        what: String,
        /// The geometric problem.
        #[source]
        source: GeomError,
    },
}
