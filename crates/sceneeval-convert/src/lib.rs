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
//! **Nothing half-written.** The output is built in a temporary folder beside `DIR` and
//! renamed to `DIR` in one step once every scene is written and has been read back; a
//! conversion that fails leaves nothing. `DIR` must not exist or be empty.
//!
//! **Errors** name the generator's file and the JSON pointer of the value at fault (a missing
//! file, malformed JSON, `NaN`, an unknown asset, a bad id map). Objects and scenes left out on
//! purpose (AI2-THOR assets, assets LayoutVLM did not place, scenes not in the id map) are
//! listed in the [`Report`] with the reason.
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
use std::str::FromStr;

use sceneeval_io::assets::{AssetSpec, Layout};
use sceneeval_io::{AssetLibrary, ReadOptions};

pub use error::ConvertError;
pub use holodeck::unity_euler;
pub use id_map::IdMap;
pub use report::{ConvertedScene, Report, SkippedObject, SkippedScene};

/// A generator whose output [`convert`] reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Format {
    /// Holodeck (AI2-THOR house JSON, Unity's y-up left-handed frame).
    Holodeck,
    /// LayoutVLM (`scene.json` with the room and the assets, `layout.json` with placements).
    #[serde(rename = "layoutvlm")]
    LayoutVlm,
    /// IDesign (`scene_graph.json` and the retrieved GLB files).
    #[serde(rename = "idesign")]
    IDesign,
    /// SceneAgent / SceneSmith (its own sceneState export, SDF + glTF assets per room).
    SceneAgent,
}

impl Format {
    /// Every format.
    pub const ALL: [Format; 4] = [
        Format::Holodeck,
        Format::LayoutVlm,
        Format::IDesign,
        Format::SceneAgent,
    ];

    /// The name used on the command line: `holodeck`, `layoutvlm`, `idesign`, `scene-agent`.
    pub const fn name(self) -> &'static str {
        match self {
            Format::Holodeck => "holodeck",
            Format::LayoutVlm => "layoutvlm",
            Format::IDesign => "idesign",
            Format::SceneAgent => "scene-agent",
        }
    }

    /// The model id prefix of the converted scenes' objects.
    pub const fn asset_prefix(self) -> &'static str {
        match self {
            Format::Holodeck => "objaverse",
            Format::LayoutVlm => "layoutvlm-objaverse",
            Format::IDesign => "idesign",
            Format::SceneAgent => "scene-agent",
        }
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Format {
    type Err = String;

    /// Parses a format name (`scenesmith` is `scene-agent`), ignoring ASCII case.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("scenesmith") {
            return Ok(Format::SceneAgent);
        }
        Format::ALL
            .into_iter()
            .find(|f| f.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| {
                format!(
                    "unknown format {s:?} (expected one of {})",
                    Format::ALL.map(Format::name).join(", ")
                )
            })
    }
}

/// How to convert.
#[derive(Debug, Clone, Default)]
pub struct ConvertOptions {
    /// Scene keys to SceneEval-500 ids; without it every scene is written under its key.
    pub id_map: Option<IdMap>,
    /// Asset folders, as `--assets` gives them. Holodeck needs the Objathor folder
    /// (`objaverse=DIR`) and LayoutVLM its asset folder (`layoutvlm-objaverse=DIR`): their
    /// positions are box centres, and only the mesh tells where an asset's box centre is. The
    /// `idesign` and `scene-agent` prefixes are served from the output itself.
    pub assets: Vec<AssetSpec>,
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
/// folder renamed to `out`.
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
    let needs = match format {
        Format::Holodeck | Format::LayoutVlm => Some(format.asset_prefix()),
        Format::IDesign | Format::SceneAgent => None,
    };
    if let Some(prefix) = needs
        && !options.assets.iter().any(|a| a.prefix == prefix)
    {
        return Err(ConvertError::input(
            input,
            format!(
                "{format} gives box centres, and only the meshes say where an asset's box centre is: \
                 pass --assets {prefix}=DIR, the folder the evaluation will read the assets from"
            ),
        ));
    }
    let native = match format {
        Format::Holodeck => holodeck::scenes(input)?,
        _ => numbered_scenes(input)?,
    };
    if native.is_empty() {
        let expected = match format {
            Format::Holodeck => "a folder per scene holding its house JSON",
            _ => "scene_NNN folders",
        };
        return Err(ConvertError::input(
            input,
            format!("no scenes: expected {expected}"),
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
                        reason: "not in --id-map".into(),
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
        tracing::info!(key = k, "--id-map names scene {k}, which the input does not have");
    }

    let staging = output::Staging::new(out)?;
    let library = library(format, &options.assets, staging.path())?;
    let mut scenes = Vec::with_capacity(todo.len());
    for (scene, id) in todo {
        let file = PathBuf::from(format!("scene_{id}.json"));
        let path = staging.path().join(&file);
        let written = match format {
            Format::Holodeck => holodeck::convert(&scene, &path, &library)?,
            Format::LayoutVlm => layoutvlm::convert(&scene, &path, &library)?,
            Format::IDesign => idesign::convert(&scene, id, staging.path(), &library)?,
            Format::SceneAgent => scene_agent::convert(&scene, id, staging.path(), &library)?,
        };
        let read = sceneeval_io::read_scene_state(&path, &library, &ReadOptions::default()).map_err(|e| {
            ConvertError::Verify {
                path: path.clone(),
                source: Box::new(e),
            }
        })?;
        tracing::info!(key = scene.key, id, objects = read.objects().len(), source = %scene.dir.display(), "scene converted");
        let mut files = vec![file];
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
    let own: &[(&str, Layout)] = match format {
        Format::IDesign => &[("idesign", Layout::IDesign)],
        Format::SceneAgent => &[
            ("scene-agent", Layout::SceneAgent),
            ("scenesmith", Layout::SceneAgent),
        ],
        _ => &[],
    };
    let mut library = AssetLibrary::new();
    for spec in specs {
        if own.iter().any(|(prefix, _)| *prefix == spec.prefix) {
            tracing::warn!(prefix = %spec.prefix, "--assets {}=... ignored: {format} assets are read from the scenes being converted", spec.prefix);
            continue;
        }
        if !spec.dir.is_dir() {
            return Err(ConvertError::input(
                &spec.dir,
                format!("--assets {}: not a folder", spec.prefix),
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
fn numbered_scenes(input: &Path) -> Result<Vec<NativeScene>, ConvertError> {
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
    fn format_names_round_trip() {
        for f in Format::ALL {
            assert_eq!(f.name().parse::<Format>().unwrap(), f);
            assert_eq!(
                Layout::for_prefix(f.asset_prefix()).name(),
                match f {
                    Format::Holodeck => "objathor",
                    Format::LayoutVlm => "layoutvlm",
                    Format::IDesign => "idesign",
                    Format::SceneAgent => "scene-agent",
                }
            );
        }
        assert_eq!("SceneSmith".parse::<Format>().unwrap(), Format::SceneAgent);
        assert!("sceneweaver".parse::<Format>().is_err());
    }

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
