//! Integration tests of sceneeval-render, one binary: camera and figure checks, the
//! reference's hiding rules, and reference images of the fixture scenes.
//!
//! They need a Vulkan driver; on a machine without a GPU install Mesa's software driver
//! (`apt-get install mesa-vulkan-drivers libvulkan1`), as CI does. Without one they are
//! skipped (saying so once), unless `SCENEEVAL_REQUIRE_GPU=1` (CI) makes that a failure. Re-bless the reference
//! images with `SCENEEVAL_BLESS=1 cargo test -p sceneeval-render --test render`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod cameras;
mod common;
mod materials;
mod reference;
mod selection;
