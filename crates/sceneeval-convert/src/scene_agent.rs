//! SceneAgent / SceneSmith: each scene folder holds the generator's own sceneState export,
//! `combined_house/sceneeval_state.json` (or, in older runs,
//! `scene_states/final_scene/sceneeval_state.json`), the assets of each room under
//! `room_<name>/generated_assets/` (older runs: `generated_assets/` at the top), the floor plan
//! `floor_plans/floor_plan.sdf` (older: `floor_plan.sdf`) and a Blender file.
//!
//! The state file is copied with, for each object whose model id is `scene-agent.<id>` or
//! `scenesmith.<id>`, the model id rewritten to `scene-agent.scene_<ID>__<id>` and its
//! `sdfPath` made relative to `scene_<ID>/assets/`; the scene's `objectFrontVector` is set to
//! `[0, 1, 0]` when the file has none (SceneSmith's assets face +y). Transforms stay as they are
//! (z-up, the `scene-agent` prefix's convention). The SDF folder of every object is copied
//! from the room that holds it to `scene_<ID>/assets/<path after generated_assets/>`, so the
//! assets of every room are kept; two rooms holding different files at one such path are an
//! error rather than one silently replacing the other.

use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

use sceneeval_io::AssetLibrary;
use sceneeval_io::scene_state::json_in::{Doc, optional, ptr_index, ptr_key};
use serde_json::Value;

use crate::format::Converter;
use crate::native::{duplicate, read_json, subfolders};
use crate::output::{Output, files_under};
use crate::{ConvertError, NativeScene, SkippedObject, Written};

/// Where a scene's state file is, newest layout first.
const STATE_FILES: [&str; 2] = [
    "combined_house/sceneeval_state.json",
    "scene_states/final_scene/sceneeval_state.json",
];
/// Where its floor plan is.
const FLOOR_PLANS: [&str; 2] = ["floor_plans/floor_plan.sdf", "floor_plan.sdf"];
/// Where its Blender file is.
const BLEND_FILES: [&str; 2] = [
    "combined_house/house.blend",
    "scene_states/final_scene/scene.blend",
];
/// The folder of generated assets inside a room (or scene) folder.
const GENERATED: &str = "generated_assets";

/// The SceneAgent / SceneSmith conversion.
pub(crate) struct SceneAgent;

impl Converter for SceneAgent {
    /// Converts one SceneAgent scene into `scene_<id>.json` of `out` and its assets.
    fn convert(
        &self,
        scene: &NativeScene,
        id: u64,
        out: Output<'_>,
        library: &AssetLibrary,
    ) -> Result<Written, ConvertError> {
        let Some(state_path) = first_file(&scene.dir, &STATE_FILES) else {
            return Err(ConvertError::input(
                &scene.dir,
                format!(
                    "no sceneeval_state.json (looked for {})",
                    STATE_FILES.join(" and ")
                ),
            ));
        };
        let mut root = read_json(&state_path, library)?;
        let doc = Doc { path: &state_path };
        let scene_dir = PathBuf::from(format!("scene_{id}"));
        let mut assets = Assets {
            out,
            rel: scene_dir.join("assets"),
            roots: asset_roots(&scene.dir)?,
            copied: BTreeMap::new(),
            files: Vec::new(),
        };
        let mut skipped = Vec::new();
        let edits = object_edits(&doc, &root, id, &mut assets, &mut skipped)?;
        // Apply the edits to the document.
        if let Some(Value::Array(list)) = root.pointer_mut("/scene/object") {
            for (i, edit) in edits {
                if let Some(Value::Object(o)) = list.get_mut(i) {
                    o.insert("modelId".into(), Value::String(edit.model_id));
                    o.entry("id").or_insert(Value::String(edit.object_id));
                    o.insert("sdfPath".into(), Value::String(edit.sdf_path));
                }
            }
        }
        if let Some(Value::Object(scene_obj)) = root.pointer_mut("/scene")
            && !scene_obj.contains_key("objectFrontVector")
        {
            scene_obj.insert("objectFrontVector".into(), serde_json::json!([0, 1, 0]));
        }
        let mut text = serde_json::to_string_pretty(&root).map_err(|e| {
            ConvertError::output(
                &state_path,
                std::io::Error::new(std::io::ErrorKind::InvalidData, e),
            )
        })?;
        text.push('\n');
        out.write_text(Path::new(&format!("scene_{id}.json")), &text)?;
        let mut files = assets.files;
        if let Some(plan) = first_file(&scene.dir, &FLOOR_PLANS) {
            let rel = scene_dir.join("floor_plan.sdf");
            out.copy_file(&plan, &rel)?;
            files.push(rel);
        }
        if let Some(blend) = first_file(&scene.dir, &BLEND_FILES) {
            let rel = assets.rel.join("original_scene_agent.blend");
            out.copy_file(&blend, &rel)?;
            files.push(rel);
        }
        files.sort();
        Ok(Written {
            files,
            skipped_objects: skipped,
        })
    }
}

/// What becomes of an object entry of the state file.
struct Edit {
    model_id: String,
    object_id: String,
    /// Its `sdfPath`, relative to `scene_<ID>/assets/`.
    sdf_path: String,
}

/// The SDF folders copied into the output.
struct Assets<'a> {
    out: Output<'a>,
    /// `scene_<ID>/assets`, relative to the output.
    rel: PathBuf,
    /// The scene's `generated_assets` folders.
    roots: Vec<PathBuf>,
    /// Relative SDF folder -> the room asset root it was copied from.
    copied: BTreeMap<PathBuf, PathBuf>,
    /// The files copied, relative to the output.
    files: Vec<PathBuf>,
}

impl Assets<'_> {
    /// Copies the folder of the SDF `rel` (inside the asset root `from`) unless it was copied
    /// already; the same folder of another room must hold the same files.
    fn copy_folder_of(&mut self, rel: &Path, from: PathBuf) -> Result<(), ConvertError> {
        let folder = rel.parent().map(Path::to_path_buf).unwrap_or_default();
        match self.copied.get(&folder) {
            Some(first) if first == &from => Ok(()),
            Some(first) => same_files(&first.join(&folder), &from.join(&folder), &self.rel.join(&folder)),
            None => {
                for f in files_under(&from.join(&folder))? {
                    let target = self.rel.join(&folder).join(&f);
                    self.out.copy_file(&from.join(&folder).join(&f), &target)?;
                    self.files.push(target);
                }
                self.copied.insert(folder, from);
                Ok(())
            }
        }
    }
}

/// The edits of the state file's object entries (by position), copying each object's SDF
/// folder; entries marked `isArchitecture` go to `skipped`. Two entries with one object id
/// are an error unless they name the same SDF (one asset listed twice, as SceneSmith lists
/// the members of a stack): the converted model id names one asset.
fn object_edits(
    doc: &Doc<'_>,
    root: &Value,
    id: u64,
    assets: &mut Assets<'_>,
    skipped: &mut Vec<SkippedObject>,
) -> Result<Vec<(usize, Edit)>, ConvertError> {
    let top = doc.object(root, "")?;
    let scene_obj = doc.object(doc.required(top, "", "scene")?, "/scene")?;
    let Some(list) = optional(scene_obj, "object") else {
        return Ok(Vec::new());
    };
    let list_ptr = "/scene/object";
    let list = doc.array(list, list_ptr)?;
    let mut edits = Vec::new();
    // Object id -> the pointer of its first entry and its SDF file.
    let mut seen: BTreeMap<String, (String, PathBuf)> = BTreeMap::new();
    for (i, entry) in list.iter().enumerate() {
        let ptr = ptr_index(list_ptr, i);
        let o = doc.object(entry, &ptr)?;
        if optional(o, "isArchitecture").and_then(Value::as_bool) == Some(true) {
            let name = optional(o, "id")
                .or_else(|| optional(o, "modelId"))
                .map_or_else(String::new, |v| {
                    v.as_str().map_or_else(|| v.to_string(), str::to_owned)
                });
            skipped.push(SkippedObject {
                file: doc.path_buf(),
                pointer: ptr,
                name,
                reason: "marked isArchitecture (part of the building): copied, left out when read".into(),
            });
            continue;
        }
        let Some(model) = optional(o, "modelId") else {
            continue;
        };
        let model = doc.string(model, &ptr_key(&ptr, "modelId"))?;
        let Some(object_id) = model
            .strip_prefix("scene-agent.")
            .or_else(|| model.strip_prefix("scenesmith."))
        else {
            continue;
        };
        match optional(o, "id")
            .map(|v| doc.id(v, &ptr_key(&ptr, "id")))
            .transpose()?
        {
            Some(own) if own != object_id => {
                return Err(doc
                    .invalid(
                        &ptr_key(&ptr, "id"),
                        format!("{own:?} is not the object id {object_id:?} of its modelId {model:?}"),
                    )
                    .into());
            }
            _ => {}
        }
        let sdf_ptr = ptr_key(&ptr, "sdfPath");
        let sdf = match optional(o, "sdfPath") {
            Some(v) => doc.string(v, &sdf_ptr)?,
            None => "",
        };
        if sdf.trim().is_empty() {
            return Err(doc
                .invalid(&sdf_ptr, "missing or empty: the object's SDF file is not named")
                .into());
        }
        let (rel, from) = locate_sdf(doc, &sdf_ptr, sdf, &assets.roots)?;
        // The second object of an id takes the first one's asset: right only when it is.
        let file = from.join(&rel);
        match seen.get(object_id) {
            Some((first, first_file)) if *first_file != file => {
                return Err(duplicate(doc, object_id, first, &ptr));
            }
            Some(_) => {}
            None => {
                seen.insert(object_id.to_owned(), (ptr.clone(), file));
            }
        }
        assets.copy_folder_of(&rel, from)?;
        let edit = Edit {
            model_id: format!("scene-agent.scene_{id}__{object_id}"),
            object_id: object_id.to_owned(),
            sdf_path: slashed(&rel),
        };
        edits.push((i, edit));
    }
    Ok(edits)
}

fn first_file(dir: &Path, candidates: &[&str]) -> Option<PathBuf> {
    candidates.iter().map(|c| dir.join(c)).find(|p| p.is_file())
}

/// The scene's asset roots: `generated_assets/` at the top, then each `room_*/generated_assets/`
/// in name order.
fn asset_roots(dir: &Path) -> Result<Vec<PathBuf>, ConvertError> {
    let mut roots = Vec::new();
    if dir.join(GENERATED).is_dir() {
        roots.push(dir.join(GENERATED));
    }
    for (name, room) in subfolders(dir)? {
        if name.starts_with("room_") && room.join(GENERATED).is_dir() {
            roots.push(room.join(GENERATED));
        }
    }
    Ok(roots)
}

/// The SDF an object's `sdfPath` names: its path after `generated_assets/` and the asset root
/// that holds it. A path naming its room folder (`room_x/generated_assets/...`) is looked for
/// there; otherwise in every root, and it must be found in exactly one (or in several with
/// the same files).
fn locate_sdf(
    doc: &Doc<'_>,
    ptr: &str,
    sdf: &str,
    roots: &[PathBuf],
) -> Result<(PathBuf, PathBuf), ConvertError> {
    let sdf = sdf.replace('\\', "/");
    let (room, rel) = match sdf.rfind("generated_assets/") {
        Some(at) => {
            let before = sdf[..at].trim_end_matches('/');
            let room = before.rsplit('/').next().filter(|r| r.starts_with("room_"));
            (room, &sdf[at + "generated_assets/".len()..])
        }
        None => (None, sdf.as_str()),
    };
    let rel = PathBuf::from(rel);
    if rel.as_os_str().is_empty() || !rel.components().all(|c| matches!(c, Component::Normal(_))) {
        return Err(doc
            .invalid(
                ptr,
                format!("{sdf:?} is not a relative path inside generated_assets/"),
            )
            .into());
    }
    let mut found: Vec<&PathBuf> = roots
        .iter()
        .filter(|r| room.is_none_or(|name| r.parent().and_then(Path::file_name).is_some_and(|n| n == name)))
        .filter(|r| r.join(&rel).is_file())
        .collect();
    match found.len() {
        0 => Err(sceneeval_io::IoError::File {
            path: roots.first().map_or_else(|| rel.clone(), |r| r.join(&rel)),
            source: std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!(
                    "the SDF named at {ptr} of {} is in none of the scene's generated_assets folders ({})",
                    doc.path.display(),
                    roots
                        .iter()
                        .map(|r| r.display().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ),
        }
        .into()),
        _ => {
            let first = found.remove(0);
            let folder = rel.parent().map(Path::to_path_buf).unwrap_or_default();
            for other in found {
                same_files(&first.join(&folder), &other.join(&folder), &folder)?;
            }
            Ok((rel, first.clone()))
        }
    }
}

/// Checks that two folders hold the same files with the same bytes.
fn same_files(a: &Path, b: &Path, target: &Path) -> Result<(), ConvertError> {
    let (fa, fb) = (files_under(a)?, files_under(b)?);
    if fa != fb {
        return Err(ConvertError::Conflict {
            first: a.to_owned(),
            second: b.to_owned(),
            target: target.to_owned(),
            reason: "two rooms hold different files under this path; the scene file cannot say which an object uses".into(),
        });
    }
    for f in fa {
        let read = |p: PathBuf| std::fs::read(&p).map_err(|e| ConvertError::output(p, e));
        if read(a.join(&f))? != read(b.join(&f))? {
            return Err(ConvertError::Conflict {
                first: a.join(&f),
                second: b.join(&f),
                target: target.join(&f),
                reason: "two rooms hold different files under this path; the scene file cannot say which an object uses".into(),
            });
        }
    }
    Ok(())
}

/// A relative path with `/` separators.
fn slashed(p: &Path) -> String {
    p.components()
        .map(|c| c.as_os_str().to_string_lossy())
        .collect::<Vec<_>>()
        .join("/")
}
