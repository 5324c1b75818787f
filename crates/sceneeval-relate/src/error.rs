use sceneeval_io::IoError;
use sceneeval_relations::RelationError;
use sceneeval_scene::RoomSpecError;
use thiserror::Error;

/// Why a [`super::Session`] could not answer a query or a declaration. Each message names the
/// operand (`target`, `anchor`, `targets[2]`, `room`) or the declared name at fault.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum RelateError {
    /// The relation, a box, or the operands of the relation's kind were wrong.
    #[error(transparent)]
    Relation(#[from] RelationError),
    /// A room written in place is not a room.
    #[error(transparent)]
    Room(#[from] RoomSpecError),
    /// A room written in place does not read as one.
    #[error("invalid room: {}{source}", prefix(path))]
    InvalidRoom {
        /// The path of the key at fault in the room (`floor[2]`, `openings[0].kind`), empty
        /// for the room as a whole.
        path: String,
        /// What serde_json found.
        #[source]
        source: serde_json::Error,
    },
    /// An asset object's asset could not be loaded.
    #[error("{what}: {}", sceneeval_files::ErrorChain::new(&**source))]
    Asset {
        /// The operand, e.g. `target`, or the declared name.
        what: String,
        /// What the asset library reported (boxed: errors stay small on the success path).
        #[source]
        source: Box<IoError>,
    },
    /// A name no declaration gave.
    #[error("{what}: no {kind} named {name:?} has been declared")]
    Undeclared {
        /// The operand, e.g. `anchor` or `room`.
        what: String,
        /// `object` or `room`.
        kind: &'static str,
        /// The name.
        name: String,
    },
    /// A name declared as the other kind (an object where a room is expected, or the reverse).
    #[error("{what}: {name:?} is {is}, not {expected}")]
    OtherKind {
        /// The operand.
        what: String,
        /// The name.
        name: String,
        /// What it was declared as: `a room` or `an object`.
        is: &'static str,
        /// What the operand needs.
        expected: &'static str,
    },
    /// A name whose latest declaration failed.
    #[error("{what}: {name:?} is unusable: its declaration on line {line} failed")]
    Unusable {
        /// The operand.
        what: String,
        /// The name.
        name: String,
        /// The line (the number the declaration was given) of the failed declaration.
        line: usize,
    },
    /// A declaration whose object or room is a name instead of being written in place.
    #[error("a declaration's \"{operand}\" must be {kind} written in place, not a name")]
    DeclaredByName {
        /// `object` or `room`.
        operand: &'static str,
        /// `an object` or `a room`.
        kind: &'static str,
    },
    /// A name declared again as the other kind.
    #[error("{name:?} is declared as {old}; a name cannot be declared again as {new}")]
    Redeclared {
        /// The name.
        name: String,
        /// Its kind: `an object` or `a room`.
        old: &'static str,
        /// The kind of the new declaration.
        new: &'static str,
    },
    /// A declaration failed; the name is unusable until declared again.
    #[error("declaration of {name:?}: {source}")]
    Declaration {
        /// The name.
        name: String,
        /// Why.
        #[source]
        source: Box<RelateError>,
    },
}

/// `path: ` when the path is known.
fn prefix(path: &str) -> String {
    if path.is_empty() {
        String::new()
    } else {
        format!("{path}: ")
    }
}
