//! Shared code of the examples in this folder (run them with
//! `cargo run -p sceneeval-examples --example NAME`): the layout optimiser's model and annealer
//! live here so that the allocation-counting test (`sceneeval-alloc-check`) can run the very
//! loop the example runs.

pub mod layout;
