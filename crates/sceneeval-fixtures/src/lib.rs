//! Work in progress.

pub mod annotations;
