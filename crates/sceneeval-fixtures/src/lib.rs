//! The program that writes `fixtures/`: procedural furniture assets, scenes with known
//! answers, the expected answers themselves and annotation rows, all byte-identical on every
//! run.
//!
//! Run it as `cargo run -p sceneeval-fixtures` (writes `<workspace>/fixtures`) or
//! `cargo run -p sceneeval-fixtures -- --out DIR`. Tests call [`generate`] directly.
//!
//! | output | written by |
//! |---|---|
//! | `assets/<id>.glb`, `assets/<id>.json` | [`assets`] (meshes from [`primitives`]), via `sceneeval_io::write_glb` |
//! | `scenes/scene_<N>.json` | [`scenes`] (data) -> [`build`] -> `sceneeval_io::write_scene_state` |
//! | `expected.json` | [`expected`], measured on each scene as read back from its file |
//! | `README.md` | [`readme`] |
//! | `annotations/*.csv` | [`annotations`] (paper examples, malformed rows) and [`scene_annotations`] (one row per scene) |
//! | `native/<format>/` | [`native`]: scenes in Holodeck's, LayoutVLM's, IDesign's and SceneAgent's own formats, with their assets, for `sceneeval convert` |
//!
//! # Frames
//! Assets are written in the asset frame (y up, front +z, origin at the bottom centre). Scenes
//! place them through `sceneeval_io::AssetLibrary`, which reads the GLB files just written and
//! converts them into the object frame (z up, front -y), so the conversion is `sceneeval-io`'s
//! and nobody else's. Placements are object-frame poses: a yaw about +z and the world position
//! of the bottom centre (see [`spec`]).
//!
//! # Determinism
//! Every file is a pure function of the code: no clocks, no randomness, no hash-map iteration
//! in any output, floats formatted by `serde_json`/`sceneeval-io`. The `regenerate` test
//! compares a fresh generation with the committed `fixtures/` byte for byte.
//!
//! # Example
//! ```
//! let dir = tempfile::tempdir()?;
//! let generated = sceneeval_fixtures::generate(dir.path())?;
//! assert!(generated.files.iter().any(|f| f == std::path::Path::new("scenes/scene_0.json")));
//! assert!(dir.path().join("assets/bed.glb").is_file());
//! let expected: sceneeval_fixtures::expected::Expected =
//!     serde_json::from_str(&std::fs::read_to_string(dir.path().join("expected.json"))?)?;
//! assert!(expected.scenes.len() >= 12);
//! // Scene 5: the nightstand is pushed 0.10 m into the wardrobe (1.5 - 1.4).
//! assert_eq!(expected.scenes[5].collisions[0].depth, Some(0.1));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::path::{Path, PathBuf};

use sceneeval_io::assets::PlainFolderSource;
use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state, write_glb, write_scene_state};
use serde::{Deserialize, Serialize};

pub mod annotations;
pub mod assets;
pub mod build;
mod error;
pub mod expected;
pub mod native;
pub mod primitives;
pub mod readme;
pub mod scene_annotations;
pub mod scenes;
pub mod spec;

pub use error::FixtureError;

/// The model-id prefix of the fixture assets (`fixture.<id>`).
pub const ASSET_PREFIX: &str = "fixture";
/// The asset folder inside the fixtures folder.
pub const ASSET_DIR: &str = "assets";
/// The scene folder inside the fixtures folder.
pub const SCENE_DIR: &str = "scenes";
/// The annotation folder inside the fixtures folder.
pub const ANNOTATION_DIR: &str = "annotations";

/// The sidecar metadata of an asset, `assets/<id>.json`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct AssetMetadata {
    /// The asset's category.
    pub category: String,
    /// A one-sentence description.
    pub description: String,
}

/// What [`generate`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct Generated {
    /// Every file written, relative to the output folder, sorted.
    pub files: Vec<PathBuf>,
    /// The expected answers (also written to `expected.json`).
    pub expected: expected::Expected,
}

/// The default output folder: `fixtures/` at the workspace root.
pub fn default_output_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// Writes `value` as pretty JSON with a trailing newline.
pub(crate) fn write_json<T: Serialize>(path: &Path, value: &T) -> Result<(), FixtureError> {
    let mut text = serde_json::to_string_pretty(value).map_err(|source| FixtureError::Json {
        path: path.to_owned(),
        source,
    })?;
    text.push('\n');
    std::fs::write(path, text).map_err(|e| FixtureError::file(path, e))
}

fn create_dir(path: &Path) -> Result<(), FixtureError> {
    std::fs::create_dir_all(path).map_err(|e| FixtureError::file(path, e))
}

/// Writes every asset of the catalog into `dir` as `<id>.glb` and `<id>.json`; returns the
/// file names written.
///
/// # Errors
/// [`FixtureError::Io`] or [`FixtureError::File`] when a file cannot be written.
pub fn write_assets(dir: &Path, catalog: &[assets::AssetDef]) -> Result<Vec<PathBuf>, FixtureError> {
    let mut written = Vec::with_capacity(2 * catalog.len());
    for a in catalog {
        let glb = PathBuf::from(format!("{}.glb", a.id));
        let path = dir.join(&glb);
        write_glb(&path, &a.glb_meshes()).map_err(|e| FixtureError::io(path.display().to_string(), e))?;
        let json = PathBuf::from(format!("{}.json", a.id));
        let meta = AssetMetadata {
            category: a.category.to_owned(),
            description: a.description.to_owned(),
        };
        write_json(&dir.join(&json), &meta)?;
        written.extend([glb, json]);
    }
    Ok(written)
}

/// Writes the whole fixtures folder into `dir` (created if needed): assets, scenes,
/// `expected.json`, `README.md` and the annotation files. Files already in `dir` that this
/// generator does not write are left alone.
///
/// Each scene is written, read back through `sceneeval-io` with the fixture assets, and its
/// expected answers are measured on the scene as read.
///
/// # Errors
/// The first [`FixtureError`] met; files written before it stay.
pub fn generate(dir: &Path) -> Result<Generated, FixtureError> {
    let asset_dir = dir.join(ASSET_DIR);
    let scene_dir = dir.join(SCENE_DIR);
    let annotation_dir = dir.join(ANNOTATION_DIR);
    for d in [&asset_dir, &scene_dir, &annotation_dir] {
        create_dir(d)?;
    }
    let mut files = Vec::new();

    let catalog = assets::catalog();
    files.extend(
        write_assets(&asset_dir, &catalog)?
            .into_iter()
            .map(|f| Path::new(ASSET_DIR).join(f)),
    );
    tracing::info!(count = catalog.len(), dir = %asset_dir.display(), "assets written");

    let library = AssetLibrary::new().with_source(ASSET_PREFIX, PlainFolderSource::new(&asset_dir));
    let specs = scenes::all();
    let mut expected_scenes = Vec::with_capacity(specs.len());
    for spec in &specs {
        let built = build::build_scene(spec, |asset, scale| {
            let model_id = format!("{ASSET_PREFIX}.{asset}");
            library
                .mesh(&model_id, scale)
                .map_err(|e| FixtureError::io(model_id, e))
        })?;
        let file = Path::new(SCENE_DIR).join(format!("{}.json", spec.name()));
        let path = dir.join(&file);
        let io_err = |e| FixtureError::io(path.display().to_string(), e);
        write_scene_state(&built, &path).map_err(io_err)?;
        let read = read_scene_state(&path, &library, &ReadOptions::default()).map_err(io_err)?;
        check_read_back(spec, &built, &read)?;
        expected_scenes.push(expected::expected_scene(spec, &read)?);
        files.push(file);
        tracing::info!(scene = %spec.name(), objects = read.objects().len(), "scene written");
    }

    let expected = expected::Expected {
        format: expected::FORMAT.to_owned(),
        version: expected::VERSION,
        rounding: expected::ROUNDING,
        asset_prefix: ASSET_PREFIX.to_owned(),
        asset_dir: ASSET_DIR.to_owned(),
        scenes: expected_scenes,
    };
    write_json(&dir.join("expected.json"), &expected)?;
    files.push(PathBuf::from("expected.json"));
    std::fs::write(dir.join("README.md"), readme::readme(&catalog, &expected))
        .map_err(|e| FixtureError::file(dir.join("README.md"), e))?;
    files.push(PathBuf::from("README.md"));

    files.extend(
        scene_annotations::write(&annotation_dir, &specs)?
            .into_iter()
            .map(|f| Path::new(ANNOTATION_DIR).join(f)),
    );
    files.extend(native::write(dir)?);
    files.sort();
    Ok(Generated { files, expected })
}

/// Checks that the scene read back from its file has the objects, ids and poses it was
/// written with (the reader and writer are another crate's; a fixture must not silently
/// differ from its spec).
fn check_read_back(
    spec: &spec::SceneSpec,
    built: &sceneeval_scene::Scene,
    read: &sceneeval_scene::Scene,
) -> Result<(), FixtureError> {
    let name = spec.name();
    if built.objects().len() != read.objects().len() || built.rooms().len() != read.rooms().len() {
        return Err(FixtureError::spec(
            &name,
            format!(
                "read back {} objects in {} rooms, wrote {} in {}",
                read.objects().len(),
                read.rooms().len(),
                built.objects().len(),
                built.rooms().len()
            ),
        ));
    }
    for (b, r) in built.objects().iter().zip(read.objects()) {
        let moved = (b.pose().translation.vector - r.pose().translation.vector).norm()
            + b.pose().rotation.angle_to(&r.pose().rotation);
        let resized = (b.obb().extents() - r.obb().extents()).norm();
        if b.id() != r.id() || moved > 1e-9 || resized > 1e-9 {
            return Err(FixtureError::spec(
                &name,
                format!(
                    "object {} read back as {} moved by {moved:e}, resized by {resized:e}",
                    b.id(),
                    r.id()
                ),
            ));
        }
    }
    Ok(())
}
