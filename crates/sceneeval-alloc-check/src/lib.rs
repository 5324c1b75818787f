//! Test-only package: `tests/no_allocation.rs` installs a counting global allocator and checks
//! that the kernels documented as allocation-free (`sceneeval-relations`' predicates on plain
//! geometry and their batch forms, `sceneeval-geom`'s exact box and mesh distances) allocate
//! nothing per call. It lives in its own package because a global allocator needs `unsafe`,
//! which the rest of the workspace forbids. Run with
//! `cargo test -p sceneeval-alloc-check`.
