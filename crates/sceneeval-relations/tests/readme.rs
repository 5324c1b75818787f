//! The README's "Use from Rust" program is `examples/use_from_rust.rs` (which `cargo test`
//! compiles, against this crate and its dependencies): the first `rust` code block after that
//! heading must be the example's text, and it may name no crate but `sceneeval_relations`.

#![allow(clippy::expect_used)]

use std::path::Path;

/// The first code block tagged `rust` after the line `## Use from Rust`.
fn readme_block(readme: &str) -> Option<String> {
    let after = &readme[readme.find("\n## Use from Rust\n")?..];
    let start = after.find("\n```rust\n")? + "\n```rust\n".len();
    let body = &after[start..];
    Some(body[..body.find("\n```\n")? + 1].to_owned())
}

#[test]
fn the_readme_program_is_the_compiled_example() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    // In the repository the README is at the root; in the published package, beside this
    // crate's manifest.
    let readme = [dir.join("../../README.md"), dir.join("README.md")]
        .iter()
        .find_map(|p| std::fs::read_to_string(p).ok())
        .expect("README.md in the repository or the package");
    let block = readme_block(&readme).expect("a ```rust block after \"## Use from Rust\"");
    let example = std::fs::read_to_string(dir.join("examples/use_from_rust.rs")).expect("the example");
    assert_eq!(block, example, "README.md and examples/use_from_rust.rs differ");
    for other in [
        "sceneeval_geom",
        "sceneeval_scene",
        "sceneeval_plausibility",
        "sceneeval::",
    ] {
        assert!(!block.contains(other), "the README program names {other}");
    }
}
