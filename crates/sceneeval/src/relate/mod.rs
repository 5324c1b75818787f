//! Relation queries as plain data, answered in one place: the [`Session`] that
//! `sceneeval relate` and the Python package (`relation`, `relation_batch`) go through.
//!
//! A query's path: a front end reads its input (`relate`: a JSON line, by its own scanner or
//! by serde_json into the types of [`query`](Query); Python: arguments and dicts into
//! [`BoxSpec`]s and `sceneeval_scene::RoomSpec`s); the [`Session`] holds the declared names,
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
//! - [`error_path`], [`from_value`], [`under`]: the path of the key at fault when JSON does not
//!   read as a query type (`target.half_size`), for front ends' error messages.
//!
//! The JSON schema (`sceneeval relate`'s lines, version 1) is in `docs/formats.md`.

mod cache;
mod error;
mod json;
mod query;
mod session;
mod spec;

pub use cache::RoomCache;
pub use error::RelateError;
pub use json::{error_path, from_value, under};
pub use query::{Operand, Query, RoomOperand};
pub use session::Session;
pub use spec::{AssetObjectSpec, BoxSpec, ObjectSpec, RotationSpec, ScaleSpec};
