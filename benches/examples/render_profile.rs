//! Renders the benchmark's 100,000-triangle top view (`render/top_512_100k_triangles`: 50
//! cylinders of 2,000 triangles on a grid in a 15 x 10 m room) a given number of times, for
//! instruction counts that do not depend on the machine's load:
//!
//! ```text
//! cargo build --profile bench -p sceneeval-benches --example render-profile
//! LP_NUM_THREADS=0 valgrind --tool=callgrind --callgrind-out-file=cg.%p \
//!     target/release/examples/render-profile --samples 4 --renders 5
//! ```
//!
//! `LP_NUM_THREADS=0` makes Mesa's software driver rasterise on its queue thread instead of
//! worker threads. Running with `--renders 1` and `--renders 5` and taking a quarter of the
//! difference gives the cost of one render without the device set-up and the shader
//! compilation; `benches/render_stages.py` does that (with 1 and 3 renders) and splits the
//! count by stage (docs/performance.md, Rendering). `--out FILE.png` writes the last image; `--scene tubes` renders 50 open
//! tubes of 2,000 triangles instead of the closed cylinders (`render/top_512_100k_triangles_open`:
//! nothing can be culled), `--scene fixtures` the top view of the 50 fixture-furniture
//! objects; `--size N` renders N x N images instead of 512 x 512.

// A measuring tool: it stops on a set-up failure and prints what it did.
#![allow(clippy::expect_used, clippy::print_stdout, clippy::print_stderr)]

#[path = "../benches/common/mod.rs"]
mod common;

use std::path::PathBuf;

use sceneeval_io::AssetLibrary;
use sceneeval_io::assets::PlainFolderSource;
use sceneeval_render::{RenderSettings, Renderer, View};

fn main() {
    let mut samples = RenderSettings::DEFAULT_SAMPLES;
    let mut renders = 1usize;
    let mut size = RenderSettings::DEFAULT_SIZE;
    let mut out: Option<PathBuf> = None;
    let mut scene_name = String::from("cylinders");
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let mut value = || args.next().expect("a value after the option");
        match arg.as_str() {
            "--samples" => samples = value().parse().expect("--samples N"),
            "--renders" => renders = value().parse().expect("--renders N"),
            "--size" => size = value().parse().expect("--size N"),
            "--out" => out = Some(PathBuf::from(value())),
            "--scene" => scene_name = value(),
            other => {
                eprintln!(
                    "unknown option {other:?}; usage: render-profile [--samples 1|4] [--renders N] [--size N] [--scene cylinders|tubes|fixtures] [--out FILE.png]"
                );
                std::process::exit(2);
            }
        }
    }

    let renderer = Renderer::new().expect("a renderer (install mesa-vulkan-drivers libvulkan1)");
    let dir = tempfile::tempdir().expect("temp dir");
    let (library, scene) = if scene_name == "fixtures" {
        let root = common::fixture_assets();
        let library = AssetLibrary::new().with_source("fixture", PlainFolderSource::new(root));
        let scene = common::grid_scene(&library, "fixture", &common::FIXTURE_IDS);
        (library, scene)
    } else {
        let ids = common::heavy_assets(dir.path(), scene_name == "tubes");
        let library = AssetLibrary::new().with_source("bench", PlainFolderSource::new(dir.path()));
        let refs: Vec<&str> = ids.iter().map(String::as_str).collect();
        let scene = common::grid_scene(&library, "bench", &refs);
        (library, scene)
    };
    let prepared = renderer.prepare(&scene, &library).expect("prepared");
    let settings = RenderSettings {
        samples,
        ..RenderSettings::square(size)
    };
    let mut last = None;
    for _ in 0..renders {
        last = Some(prepared.render(&View::Top, &settings).expect("rendered"));
    }
    if let (Some(image), Some(path)) = (last, out) {
        sceneeval_render::write_png(&image, &path).expect("png written");
        println!("wrote {}", path.display());
    }
    println!(
        "{renders} top views of {size} x {size}, {samples} sample(s) per pixel, on {}",
        renderer.gpu().adapter().name
    );
}
