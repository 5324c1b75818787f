//! Relation queries as plain data, answered in one place: the [`Session`] that
//! `sceneeval relate` and the Python package (`relation`, `relation_batch`) go through, and the
//! relate JSON-line format, read in one place ([`answer_line`]).
//!
//! A query's path: the input is read into plain data (a relate line by [`answer_line`],
//! through a scanner of its own for a flat line of names or serde_json into the types of
//! [`Query`]; Python's arguments and dicts into [`BoxSpec`]s and `sceneeval_scene::RoomSpec`s);
//! the [`Session`] holds the declared names,
//! the prepared rooms ([`RoomCache`]) and the asset library, resolves the operands and
//! parses the relation name ([`sceneeval_relations::Relation::from_fields`]); the one
//! dispatcher, [`sceneeval_relations::score`], checks the operands against the relation's
//! kind and calls the kernel.
//!
//! - [`BoxSpec`], [`AssetObjectSpec`], [`ObjectSpec`]: objects as plain data, checked into
//!   oriented boxes and placed assets (rooms as plain data are `sceneeval_scene::RoomSpec`,
//!   beside the room builder).
//! - [`Operand`], [`RoomOperand`], [`Query`]: a query's operands, each a declared name or
//!   written in place, as read from JSON.
//! - [`Session`]: declarations, prepared rooms and answers; errors are [`RelateError`]s.
//! - [`answer_line`], [`Answer`], [`write_answer`]: one relate line parsed, answered and
//!   written back (the command only frames the stream).
//! - [`error_path`], [`from_value`], [`under`]: the path of the key at fault when JSON does not
//!   read as a query type (`target.half_size`), for front ends' error messages.
//!
//! The JSON schema (`sceneeval relate`'s lines, version 1) is in `docs/formats.md`.

mod answer;
mod cache;
mod error;
mod flat;
mod json;
mod line;
mod query;
mod session;
mod spec;

pub use answer::{Answer, SCHEMA_VERSION, answer_line, write_answer};
pub use line::RawText;

pub use cache::RoomCache;
pub use error::RelateError;
pub use json::{error_path, from_value, under};
pub use query::{Operand, Query, RoomOperand};
pub use session::Session;
pub use spec::{AssetObjectSpec, BoxSpec, ObjectSpec, RotationSpec, ScaleSpec};
