//! The layouts of generators that ship their own meshes with each scene, as the SceneSmith
//! fork of the reference lays them out after converting: IDesign and SceneAgent / SceneSmith.
//!
//! Both name an asset `scene_<ID>__<object id>` and keep it under `DIR/scene_<ID>/assets/`,
//! next to the scene file `DIR/scene_<ID>.json` (DIR is the folder `sceneeval convert` wrote).
//! The scene file's object entries (`"id"` = the object id) hold what the layout needs: the
//! description (IDesign) and the SDF path (SceneAgent).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};

use serde_json::Value;

use super::sources::{MetadataError, mesh_file, not_found, read_json};
use super::{AssetInfo, AssetLocation, AssetSource, Layout};
use crate::IoError;

/// The form of the asset ids of these layouts, for error messages.
const ASSET_ID_FORM: &str = "scene_<ID>__<object id>, as `sceneeval convert` writes it";

/// Splits an asset id `scene_<ID>__<object id>` into the scene id and the object id.
///
/// ```
/// use sceneeval_io::assets::split_scene_asset_id;
/// assert_eq!(split_scene_asset_id("scene_12__twin_bed_1"), Some(("12", "twin_bed_1")));
/// assert_eq!(split_scene_asset_id("twin_bed_1"), None);
/// ```
pub fn split_scene_asset_id(asset_id: &str) -> Option<(&str, &str)> {
    let (scene, object) = asset_id.strip_prefix("scene_")?.split_once("__")?;
    (!scene.is_empty() && !object.is_empty()).then_some((scene, object))
}

/// A readable name from an object id: a trailing `_<number>` dropped, underscores as spaces
/// (`twin_bed_1` -> `twin bed`), as the fork describes IDesign objects.
///
/// ```
/// assert_eq!(sceneeval_io::assets::humanize_object_id("bean_bag_chair_12"), "bean bag chair");
/// assert_eq!(sceneeval_io::assets::humanize_object_id("lamp"), "lamp");
/// ```
pub fn humanize_object_id(object_id: &str) -> String {
    let trimmed = match object_id.rsplit_once('_') {
        Some((head, tail))
            if !head.is_empty() && !tail.is_empty() && tail.bytes().all(|b| b.is_ascii_digit()) =>
        {
            head
        }
        _ => object_id,
    };
    trimmed.replace('_', " ")
}

/// What a scene file says about one object.
#[derive(Debug, Clone, Default)]
struct StateObject {
    /// The object entry's pointer, for error messages.
    pointer: String,
    description: Option<String>,
    sdf_path: Option<String>,
}

type StateCache = Mutex<HashMap<String, Result<Arc<HashMap<String, StateObject>>, MetadataError>>>;

/// The scene files of a converted folder, each read once.
#[derive(Debug, Default)]
struct SceneStates {
    cache: StateCache,
}

impl SceneStates {
    /// The scene file of scene `scene` in the converted folder `root`.
    fn path(root: &Path, scene: &str) -> PathBuf {
        root.join(format!("scene_{scene}.json"))
    }

    /// The objects of scene `scene` of the converted folder `root` by their `"id"`; `None`
    /// when its file does not exist.
    fn objects(
        &self,
        root: &Path,
        scene: &str,
    ) -> Result<Option<Arc<HashMap<String, StateObject>>>, IoError> {
        let mut cache = self.cache.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(entry) = cache.get(scene) {
            return entry.clone().map(Some).map_err(|e| e.to_io());
        }
        let path = Self::path(root, scene);
        let loaded = match read_json(&path) {
            Ok(None) => return Ok(None),
            Ok(Some(doc)) => state_objects(&path, &doc).map(Arc::new),
            Err(e) => Err(e),
        };
        cache.insert(scene.to_owned(), loaded.clone());
        loaded.map(Some).map_err(|e| e.to_io())
    }
}

fn state_objects(path: &Path, doc: &Value) -> Result<HashMap<String, StateObject>, MetadataError> {
    let Some(list) = doc.pointer("/scene/object") else {
        return Ok(HashMap::new());
    };
    let Some(list) = list.as_array() else {
        return Err(MetadataError::new(path, "/scene/object", "expected an array"));
    };
    let mut out: HashMap<String, StateObject> = HashMap::with_capacity(list.len());
    for (i, entry) in list.iter().enumerate() {
        let pointer = format!("/scene/object/{i}");
        let id = match entry.get("id") {
            Some(Value::String(s)) => s.clone(),
            Some(Value::Number(n)) => n.to_string(),
            _ => continue,
        };
        let text = |key: &str| -> Result<Option<String>, MetadataError> {
            match entry.get(key) {
                None | Some(Value::Null) => Ok(None),
                Some(Value::String(s)) => Ok(Some(s.clone()).filter(|s| !s.trim().is_empty())),
                Some(other) => Err(MetadataError::new(
                    path,
                    format!("{pointer}/{key}"),
                    format!("expected a string, found {other}"),
                )),
            }
        };
        let object = StateObject {
            description: text("description")?,
            sdf_path: text("sdfPath")?,
            pointer: pointer.clone(),
        };
        match out.get(&id) {
            // Entries of one asset (SceneSmith lists each member of a stack under its asset's
            // id): the same files, whichever entry is looked up.
            Some(first) if first.description == object.description && first.sdf_path == object.sdf_path => {}
            Some(first) => {
                return Err(MetadataError::new(
                    path,
                    pointer,
                    format!(
                        "object id {id:?} is also the id of {} with another {}: the model id \
                         names one asset, so one of the two objects would show the other's",
                        first.pointer,
                        if first.sdf_path == object.sdf_path {
                            "description"
                        } else {
                            "sdfPath"
                        }
                    ),
                ));
            }
            None => {
                out.insert(id, object);
            }
        }
    }
    Ok(out)
}

fn scene_asset_id<'a>(model_id: &str, asset_id: &'a str) -> Result<(&'a str, &'a str), IoError> {
    split_scene_asset_id(asset_id).ok_or_else(|| IoError::BadAssetId {
        model_id: model_id.to_owned(),
        expected: ASSET_ID_FORM,
    })
}

folder_source! {
    /// IDesign scenes as converted (by `sceneeval convert idesign` or the fork; the root is the
    /// folder it wrote): `DIR/scene_<ID>/assets/<object id>.glb` for asset id
    /// `scene_<ID>__<object id>`.
    ///
    /// Category = the object id made readable ([`humanize_object_id`]); description = the
    /// `description` of the object entry with that `"id"` in `DIR/scene_<ID>.json`, else the
    /// category.
    IDesignSource, Layout::IDesign, { states: SceneStates = SceneStates::default() }
}

impl IDesignSource {
    fn find(&self, model_id: &str, asset_id: &str) -> Result<AssetLocation, IoError> {
        let (scene, object) = scene_asset_id(model_id, asset_id)?;
        let root = &self.root;
        let path = mesh_file(
            model_id,
            vec![
                root.join(format!("scene_{scene}"))
                    .join("assets")
                    .join(format!("{object}.glb")),
            ],
        )?;
        let described = self
            .states
            .objects(root, scene)?
            .and_then(|objects| objects.get(object).and_then(|o| o.description.clone()));
        let category = humanize_object_id(object);
        Ok(AssetLocation {
            path,
            info: AssetInfo {
                description: Some(described.unwrap_or_else(|| category.clone())),
                category: Some(category),
            },
            alignment: None,
            metadata: vec![SceneStates::path(root, scene)],
        })
    }
}

folder_source! {
    /// SceneAgent / SceneSmith scenes as converted (by `sceneeval convert scene-agent` or the
    /// fork; the root is the folder it wrote): asset id `scene_<ID>__<object id>` names the
    /// object entry with that `"id"` in `DIR/scene_<ID>.json`; its `sdfPath` (relative to
    /// `DIR/scene_<ID>/assets/`) is the object's SDF model file, and the mesh is the glTF of the
    /// first `<visual>`'s `<geometry><mesh><uri>` in it (relative to the SDF's folder, which it
    /// may not leave), as the fork reads it.
    ///
    /// Category = the object id made readable ([`humanize_object_id`]); description = the
    /// object entry's `description`, else the category.
    SceneAgentSource, Layout::SceneAgent, { states: SceneStates = SceneStates::default() }
}

impl SceneAgentSource {
    fn find(&self, model_id: &str, asset_id: &str) -> Result<AssetLocation, IoError> {
        let (scene, object) = scene_asset_id(model_id, asset_id)?;
        let state_path = SceneStates::path(&self.root, scene);
        let Some(objects) = self.states.objects(&self.root, scene)? else {
            return Err(not_found(model_id, vec![state_path]));
        };
        let bad = |location: String, message: String| IoError::BadMetadata {
            path: state_path.clone(),
            location,
            message,
        };
        let Some(entry) = objects.get(object) else {
            return Err(bad(
                "/scene/object".into(),
                format!("no object entry with \"id\": {object:?} (named by {model_id:?})"),
            ));
        };
        let Some(sdf_uri) = &entry.sdf_path else {
            return Err(bad(
                format!("{}/sdfPath", entry.pointer),
                "missing: the object's SDF file is not named".into(),
            ));
        };
        let assets = self.root.join(format!("scene_{scene}")).join("assets");
        let sdf = mesh_file(
            model_id,
            vec![crate::uri::resolve_in_folder(&assets, &state_path, sdf_uri)?],
        )?;
        let path = mesh_file(model_id, vec![visual_mesh(&sdf)?])?;
        let category = humanize_object_id(object);
        Ok(AssetLocation {
            path,
            info: AssetInfo {
                description: Some(entry.description.clone().unwrap_or_else(|| category.clone())),
                category: Some(category),
            },
            alignment: None,
            metadata: vec![state_path, sdf],
        })
    }
}

/// The mesh file of an SDF model: the first `<visual>` with a `<geometry><mesh><uri>`,
/// resolved inside the SDF's folder.
fn visual_mesh(sdf: &Path) -> Result<PathBuf, IoError> {
    let bytes = crate::uri::read_file_limited(sdf, crate::Limits::default().max_file_bytes)?;
    let text = IoError::utf8(sdf, &bytes)?;
    let doc = roxmltree::Document::parse(text).map_err(|e| {
        let pos = e.pos();
        IoError::BadMetadata {
            path: sdf.to_owned(),
            location: format!("line {} column {}", pos.row, pos.col),
            message: format!("malformed XML: {e}"),
        }
    })?;
    let uri = doc
        .descendants()
        .filter(|n| n.is_element() && n.tag_name().name() == "visual")
        .find_map(|visual| {
            let uri = child(child(child(visual, "geometry")?, "mesh")?, "uri")?;
            Some(uri.text().unwrap_or_default().trim().to_owned())
        })
        .ok_or_else(|| IoError::BadMetadata {
            path: sdf.to_owned(),
            location: "<visual><geometry><mesh><uri>".into(),
            message: "no visual mesh: the SDF names no mesh file to show".into(),
        })?;
    let folder = sdf.parent().unwrap_or_else(|| Path::new("."));
    crate::uri::resolve_in_folder(folder, sdf, &uri)
}

/// The first element child of `node` named `name`.
fn child<'a, 'input>(node: roxmltree::Node<'a, 'input>, name: &str) -> Option<roxmltree::Node<'a, 'input>> {
    node.children()
        .find(|c| c.is_element() && c.tag_name().name() == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn asset_ids_split_on_the_first_double_underscore() {
        assert_eq!(split_scene_asset_id("scene_0__desk__0"), Some(("0", "desk__0")));
        assert_eq!(split_scene_asset_id("scene_a_b__c"), Some(("a_b", "c")));
        for bad in ["scene___x", "scene_1__", "scene1__x", "scene_1_x"] {
            assert_eq!(split_scene_asset_id(bad), None, "{bad}");
        }
    }

    #[test]
    fn object_ids_read_as_names() {
        assert_eq!(humanize_object_id("twin_bed_1"), "twin bed");
        assert_eq!(humanize_object_id("workstation_desk_0"), "workstation desk");
        assert_eq!(humanize_object_id("tv_stand"), "tv stand");
        assert_eq!(humanize_object_id("_3"), " 3");
        assert_eq!(humanize_object_id("chair_a1"), "chair a1");
    }
}
