//! Converts what scene generators write into sceneState files that SceneEval evaluates: the
//! answer to "how do I evaluate my method?" for Holodeck, LayoutVLM, IDesign and SceneAgent /
//! SceneSmith. `sceneeval convert FORMAT INPUT --out DIR` is [`convert`].
//!
//! | format | input (the generator's batch folder) | output in `DIR` |
//! |---|---|---|
//! | [`Format::Holodeck`] | `<name>/<name>.json` (AI2-THOR house JSON), scenes keyed by sorted position | `scene_<ID>.json`, objects `objaverse.<assetId>` |
//! | [`Format::LayoutVlm`] | `scene_NNN/{scene.json, layout.json}` | `scene_<ID>.json`, objects `layoutvlm-objaverse.<uid>` |
//! | [`Format::IDesign`] | `scene_NNN/{scene_graph.json, Assets/*.glb, scene.blend}` | `scene_<ID>.json`, `scene_<ID>/assets/<obj>.glb`, `scene_<ID>/assets/original_idesign.blend`; objects `idesign.scene_<ID>__<obj>` |
//! | [`Format::SceneAgent`] | `scene_NNN/` with `combined_house/sceneeval_state.json` (or `scene_states/final_scene/sceneeval_state.json`), the rooms' `generated_assets/`, the floor plan | `scene_<ID>.json`, `scene_<ID>/assets/<category>/...` of every room, `scene_<ID>/floor_plan.sdf`, `scene_<ID>/assets/original_scene_agent.blend`; objects `scene-agent.scene_<ID>__<id>` |
//!
//! A scene's key is the `NNN` of its folder (Holodeck: its position in name order); it is
//! written as `scene_<key>.json` unless an [`IdMap`] gives it a SceneEval-500 id. The SceneSmith
//! fork of the reference is the reference for each conversion; where it is wrong this crate
//! does it right and `docs/formats.md` ("Converting generators' output") lists each
//! difference. The conversions' frame arithmetic stays in `sceneeval-io`: a converter states
//! the generator's placement as a sceneState transform in the convention of its model id
//! ([`sceneeval_io::frames::TransformFrame`]) and lets the asset library build the object.
//!
//! **The formats** are one table ([`Format`]): each row names the format, its objects' model
//! id prefix, whether it needs an asset folder and which assets it writes into the output, and
//! holds the format's converter (one implementation per format, in its module). [`convert`]
//! is the same for every format.
//!
//! **Nothing half-written.** The output is built in a temporary folder beside `DIR` and
//! renamed to `DIR` in one step once every scene is written and has been read back; a
//! conversion that fails, or is interrupted ([`ConvertOptions::with_interrupt`]), leaves
//! nothing. The temporary folder is locked while its conversion runs, and a conversion first
//! removes the temporary folders of `DIR` that no running conversion holds (those of killed
//! ones). Folders get the permissions the umask gives. `DIR` must not exist or be empty.
//!
//! **Errors** name the generator's file and the JSON pointer of the value at fault (a missing
//! file, malformed JSON, `NaN`, a key given twice, two objects with one id, an unknown asset, a
//! bad id map), and never a command-line flag: they say what is missing
//! ([`ConvertError::AssetsNeeded`] names the prefix whose folder is needed). Objects and scenes
//! left out on purpose (AI2-THOR assets, assets LayoutVLM did not place, scenes not in the id
//! map) are listed in the [`Report`] with the reason.
//!
//! # Example
//! ```
//! use sceneeval_convert::{ConvertOptions, Format, convert};
//! use serde_json::json;
//!
//! // A LayoutVLM batch folder with one scene: a 4 x 3 m room and a box-shaped asset.
//! let dir = tempfile::tempdir()?;
//! let scene = dir.path().join("results/scene_000");
//! std::fs::create_dir_all(&scene)?;
//! let uid = "0123456789abcdef0123456789abcdef";
//! std::fs::write(scene.join("scene.json"), json!({
//!     "boundary": {"floor_vertices": [[0, 0, 0], [4, 0, 0], [4, 3, 0], [0, 3, 0]], "wall_height": 2.5},
//!     "assets": {"crate-0": {"uid": uid}},
//! }).to_string())?;
//! // LayoutVLM places the crate's box centre at (2, 1.5, 0.25), turned 90 degrees.
//! std::fs::write(scene.join("layout.json"), json!({
//!     "crate-0": {"position": [2.0, 1.5, 0.25], "rotation": [0, 0, 90]},
//! }).to_string())?;
//! // Its asset: LayoutVLM's layout, `ID/ID.glb` (y up, front +z), a 1 x 0.5 x 0.6 m box.
//! let assets = dir.path().join("layoutvlm-assets");
//! std::fs::create_dir_all(assets.join(uid))?;
//! let (mut p, mut i) = (Vec::new(), Vec::new());
//! for k in 0..8u32 {
//!     p.push([if k & 1 == 0 { -0.5 } else { 0.5 }, if k & 2 == 0 { 0.0 } else { 0.5 },
//!             if k & 4 == 0 { -0.3 } else { 0.3 }]);
//! }
//! for t in [[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
//!           [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]] {
//!     i.extend(t);
//! }
//! sceneeval_io::write_glb(&assets.join(uid).join(format!("{uid}.glb")),
//!                         &[sceneeval_io::GlbMesh::new("crate", p, i)])?;
//!
//! let options = ConvertOptions::default()
//!     .with_assets(vec![format!("layoutvlm-objaverse={}", assets.display()).parse()?]);
//! let out = dir.path().join("converted");
//! let report = convert(Format::LayoutVlm, &dir.path().join("results"), &out, &options)?;
//! assert_eq!(report.scenes[0].id, 0);
//! assert_eq!(report.scenes[0].objects, 1);
//!
//! // The converted scene reads back with the crate's box centre where LayoutVLM put it.
//! let library = sceneeval_io::AssetLibrary::from_specs(&[format!("layoutvlm-objaverse={}", assets.display())])?;
//! let read = sceneeval_io::read_scene_state(&out.join("scene_0.json"), &library, &Default::default())?;
//! let c = read.objects()[0].obb().center;
//! assert!((c - sceneeval_geom::Point3::new(2.0, 1.5, 0.25)).norm() < 1e-6);
//! assert_eq!(read.rooms()[0].walls().len(), 4);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod error;
mod format;
mod holodeck;
mod id_map;
mod idesign;
mod layoutvlm;
mod native;
mod output;
mod place;
mod report;
mod scene_agent;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use sceneeval_io::assets::AssetSpec;
use sceneeval_io::{AssetLibrary, ReadOptions};

pub use error::ConvertError;
pub use format::Format;
pub use holodeck::unity_euler;
pub use id_map::IdMap;
pub use report::{ConvertedScene, Report, SkippedObject, SkippedScene};

/// How to convert.
#[derive(Debug, Clone, Default)]
pub struct ConvertOptions {
    /// Scene keys to SceneEval-500 ids; without it every scene is written under its key.
    pub id_map: Option<IdMap>,
    /// Asset folders, as the evaluation reads them. Holodeck needs the Objathor folder
    /// (`objaverse=DIR`) and LayoutVLM its asset folder (`layoutvlm-objaverse=DIR`): their
    /// positions are box centres, and only the mesh tells where an asset's box centre is
    /// ([`Format::needs_assets`]). The `idesign` and `scene-agent` prefixes are served from the
    /// output itself.
    pub assets: Vec<AssetSpec>,
    /// Read the converted scenes back strictly ([`ReadOptions::strict`]): a key the sceneState
    /// format does not have (in a SceneAgent state file, which is copied) fails the conversion
    /// instead of being a warning.
    pub strict: bool,
    /// Once set, the conversion stops at its next file with [`ConvertError::Interrupted`] and
    /// removes its temporary folder (the command line sets it on SIGINT and SIGTERM).
    pub interrupt: Option<Arc<AtomicBool>>,
}

impl ConvertOptions {
    /// These options with the id map `map`.
    pub fn with_id_map(mut self, map: IdMap) -> Self {
        self.id_map = Some(map);
        self
    }

    /// These options with the asset folders `assets`.
    pub fn with_assets(mut self, assets: Vec<AssetSpec>) -> Self {
        self.assets = assets;
        self
    }

    /// These options reading the converted scenes back strictly or not.
    pub fn with_strict(mut self, strict: bool) -> Self {
        self.strict = strict;
        self
    }

    /// These options with the flag that interrupts the conversion.
    pub fn with_interrupt(mut self, flag: Arc<AtomicBool>) -> Self {
        self.interrupt = Some(flag);
        self
    }
}

/// One scene of the input: its folder and key.
#[derive(Debug, Clone)]
pub(crate) struct NativeScene {
    pub(crate) key: u64,
    pub(crate) dir: PathBuf,
}

/// What converting one scene wrote.
#[derive(Debug, Default)]
pub(crate) struct Written {
    /// Files written besides the scene file, relative to the output folder.
    pub(crate) files: Vec<PathBuf>,
    pub(crate) skipped_objects: Vec<SkippedObject>,
}

/// Converts the scenes of the generator's batch folder `input` into `out`.
///
/// Every scene is converted, written to a temporary folder beside `out`, and read back through
/// `sceneeval-io` with the conversion's asset library; only when all of them succeed is the
/// folder renamed to `out`. Temporary folders that earlier conversions into `out` left behind
/// (killed before they could remove them) are removed first, unless a running conversion
/// still holds them.
///
/// # Errors
/// The first [`ConvertError`] met (see its variants); `out` is then not created.
pub fn convert(
    format: Format,
    input: &Path,
    out: &Path,
    options: &ConvertOptions,
) -> Result<Report, ConvertError> {
    if !input.is_dir() {
        return Err(ConvertError::input(input, "not a folder"));
    }
    if let Some(prefix) = format.needs_assets()
        && !options.assets.iter().any(|a| a.prefix == prefix)
    {
        return Err(ConvertError::AssetsNeeded { format, prefix });
    }
    let converter = format.converter();
    let native = converter.scenes(input)?;
    if native.is_empty() {
        return Err(ConvertError::input(
            input,
            format!("no scenes: expected {}", converter.expected_scenes()),
        ));
    }
    let mut skipped = Vec::new();
    let mut todo = Vec::new();
    for scene in native {
        let id = match &options.id_map {
            None => scene.key,
            Some(map) => match map.get(scene.key) {
                Some(id) => id,
                None => {
                    skipped.push(SkippedScene {
                        source: scene.dir.clone(),
                        key: scene.key,
                        reason: "not in the id map".into(),
                    });
                    continue;
                }
            },
        };
        todo.push((scene, id));
    }
    let unused_id_map_keys = options.id_map.as_ref().map_or_else(Vec::new, |map| {
        map.keys()
            .filter(|k| !todo.iter().any(|(s, _)| s.key == *k) && !skipped.iter().any(|s| s.key == *k))
            .collect()
    });
    for k in &unused_id_map_keys {
        tracing::info!(
            key = k,
            "the id map names scene {k}, which the input does not have"
        );
    }

    let staging = output::Staging::new(out)?;
    let output = output::Output::new(staging.path(), options.interrupt.as_deref());
    let library = library(format, &options.assets, staging.path())?;
    let read_options = ReadOptions::default().with_strict(options.strict);
    let mut scenes = Vec::with_capacity(todo.len());
    for (scene, id) in todo {
        output.check()?;
        let written = converter.convert(&scene, id, output, &library)?;
        let path = output.scene_file(id);
        output.check()?;
        let read = sceneeval_io::read_scene_state(&path, &library, &read_options).map_err(|e| {
            ConvertError::Verify {
                path: path.clone(),
                source: Box::new(e),
            }
        })?;
        tracing::info!(key = scene.key, id, objects = read.objects().len(), source = %scene.dir.display(), "scene converted");
        let mut files = vec![PathBuf::from(format!("scene_{id}.json"))];
        files.extend(written.files);
        scenes.push(ConvertedScene {
            key: scene.key,
            id,
            source: scene.dir,
            files,
            objects: read.objects().len(),
            rooms: read.rooms().len(),
            skipped_objects: written.skipped_objects,
        });
    }
    output.check()?;
    let out = staging.commit()?;
    Ok(Report {
        format,
        input: input.to_owned(),
        out,
        scenes,
        skipped,
        unused_id_map_keys,
    })
}

/// The asset library of a conversion: the given folders, and the output itself for the
/// formats whose assets travel with their scenes.
fn library(format: Format, specs: &[AssetSpec], staging: &Path) -> Result<AssetLibrary, ConvertError> {
    let own = format.output_sources();
    let mut library = AssetLibrary::new();
    for spec in specs {
        if own.iter().any(|(prefix, _)| *prefix == spec.prefix) {
            tracing::warn!(prefix = %spec.prefix, "the asset folder given for prefix {:?} is ignored: {format} assets are read from the scenes being converted", spec.prefix);
            continue;
        }
        if !spec.dir.is_dir() {
            return Err(ConvertError::input(
                &spec.dir,
                format!("the asset folder of prefix {:?} is not a folder", spec.prefix),
            ));
        }
        library.add_source(spec.prefix.clone(), spec.layout.source(spec.dir.clone()))?;
    }
    for (prefix, layout) in own {
        library.add_source(*prefix, layout.source(staging))?;
    }
    Ok(library)
}

/// The `scene_NNN` folders of `input`, keyed by `NNN`, in key order; other entries are
/// ignored.
pub(crate) fn numbered_scenes(input: &Path) -> Result<Vec<NativeScene>, ConvertError> {
    let mut scenes: Vec<NativeScene> = Vec::new();
    for (name, dir) in native::subfolders(input)? {
        let Some(key) = name.strip_prefix("scene_").and_then(id_map::number) else {
            tracing::debug!(folder = %dir.display(), "not a scene_NNN folder; ignored");
            continue;
        };
        if let Some(other) = scenes.iter().find(|s| s.key == key) {
            return Err(ConvertError::input(
                &dir,
                format!("scene key {key} is also the key of {}", other.dir.display()),
            ));
        }
        scenes.push(NativeScene { key, dir });
    }
    scenes.sort_by_key(|s| s.key);
    Ok(scenes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_folders_are_keyed_by_number() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["scene_010", "scene_2", "notes", "scene_x"] {
            std::fs::create_dir(dir.path().join(name)).unwrap();
        }
        std::fs::write(dir.path().join("scene_5"), "a file").unwrap();
        let scenes = numbered_scenes(dir.path()).unwrap();
        assert_eq!(scenes.iter().map(|s| s.key).collect::<Vec<_>>(), [2, 10]);
        std::fs::create_dir(dir.path().join("scene_0002")).unwrap();
        assert!(matches!(
            numbered_scenes(dir.path()),
            Err(ConvertError::Input { .. })
        ));
    }
}
