//! The asset folders a run read, recovered from the files its records name, so that a report
//! can draw a scene's objects without the `--assets` options the run was given.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use sceneeval_io::AssetLibrary;
use sceneeval_io::assets::{Layout, split_model_id};
use sceneeval_results::SceneRecord;

/// An [`AssetLibrary`] with, for each model-id prefix of the records, the folder and layout
/// the run read its assets from.
///
/// Every record's fingerprint lists, per model id, the files read for it, the mesh first. For
/// each prefix the folder is recovered from one asset's files under each layout in turn (the
/// prefix's default layout first: `PLAIN/ID.glb`, `3D-FUTURE/ID/raw_model.obj`,
/// `OBJATHOR/ID/ID.glb`, `HSSD/glb/<c>/ID.glb`, `IDESIGN/scene_<S>/assets/<O>.glb`; for
/// SceneAgent, the folder of the scene file `scene_<S>.json` read for the asset) and kept only
/// when that folder and layout resolve every model id of the prefix to the mesh file the
/// records name. A prefix whose folder cannot be recovered (files moved, paths relative to
/// another working folder) is left out: reading a scene that uses it then fails naming the
/// prefix.
///
/// Only folders inside one of `within` (after following symbolic links; canonical paths) are
/// registered: a record can name any file, and the report reads only inside the folders it is
/// given (the run folder, the scene folder). A prefix whose folder lies elsewhere is left out
/// as above.
pub fn recorded_assets(records: &[SceneRecord], within: &[&Path]) -> AssetLibrary {
    // Per prefix, per model id: the mesh file and the first metadata file.
    let mut meshes: BTreeMap<String, BTreeMap<String, (PathBuf, Option<PathBuf>)>> = BTreeMap::new();
    for record in records {
        for asset in record.fingerprint.iter().flat_map(|f| &f.assets) {
            let (Ok((prefix, _)), Some(mesh)) = (split_model_id(&asset.model_id), asset.files.first()) else {
                continue;
            };
            let metadata = asset.files.get(1).map(|f| PathBuf::from(&f.path));
            meshes
                .entry(prefix.to_owned())
                .or_default()
                .insert(asset.model_id.clone(), (PathBuf::from(&mesh.path), metadata));
        }
    }
    let mut library = AssetLibrary::new();
    for (prefix, assets) in meshes {
        let Some((first_id, (first_mesh, first_metadata))) = assets.iter().next() else {
            continue;
        };
        let Ok((_, asset_id)) = split_model_id(first_id) else {
            continue;
        };
        let default = Layout::for_prefix(&prefix);
        let layouts = std::iter::once(default).chain(Layout::ALL.into_iter().filter(|l| *l != default));
        // A folder outside the folders given is not looked into at all (locating an asset
        // reads metadata files).
        let allowed = |root: &Path| {
            root.canonicalize()
                .is_ok_and(|r| within.iter().any(|w| r.starts_with(w)))
        };
        let found = layouts
            .filter_map(|layout| {
                let root = root(layout, first_mesh, first_metadata.as_deref(), asset_id)?;
                if !allowed(&root) {
                    tracing::info!(%prefix, %layout, "a recorded asset folder lies outside the folders given: not read");
                    return None;
                }
                Some((layout, root))
            })
            .find(|(layout, root)| {
                let source = layout.source(root.clone());
                assets.iter().all(|(model_id, (mesh, _))| {
                    split_model_id(model_id)
                        .ok()
                        .and_then(|(_, id)| source.locate(model_id, id).ok())
                        .is_some_and(|l| l.path == *mesh)
                })
            });
        match found {
            Some((layout, root)) => {
                tracing::debug!(%prefix, %layout, root = %root.display(), "asset folder recovered from the records");
                if let Err(e) = library.add_source(prefix.clone(), layout.source(root)) {
                    tracing::warn!(%prefix, error = %e, "asset folder not registered");
                }
            }
            None => {
                tracing::info!(%prefix, mesh = %first_mesh.display(), "asset folder not recovered from the records")
            }
        }
    }
    library
}

/// The folder of `layout` holding `mesh`, the mesh file of asset `id` (`metadata`: the first
/// metadata file read for it), when the paths have that layout's shape.
fn root(layout: Layout, mesh: &Path, metadata: Option<&Path>, id: &str) -> Option<PathBuf> {
    let name = |p: &Path| p.file_name().map(|n| n.to_string_lossy().into_owned());
    let stem = mesh.file_stem()?.to_string_lossy().into_owned();
    let parent = mesh.parent()?;
    let up = |p: &Path, n: usize| -> Option<PathBuf> { p.ancestors().nth(n).map(Path::to_path_buf) };
    match layout {
        Layout::Plain => (stem == id).then(|| parent.to_path_buf()),
        Layout::ThreeDFuture => (name(mesh)? == "raw_model.obj" && name(parent)? == id)
            .then(|| up(parent, 1))
            .flatten(),
        Layout::Objathor | Layout::LayoutVlm => (stem == id && name(parent)? == id)
            .then(|| up(parent, 1))
            .flatten(),
        Layout::Hssd => {
            let kind = name(parent.parent()?)?;
            (stem == id && (kind == "glb" || kind == "decomposed"))
                .then(|| up(parent, 2))
                .flatten()
        }
        // `DIR/scene_<S>/assets/<O>.glb` for the id `scene_<S>__<O>`.
        Layout::IDesign => {
            let (scene, object) = id.split_once("__")?;
            (stem == object && name(parent)? == "assets" && name(parent.parent()?)? == scene)
                .then(|| up(parent, 2))
                .flatten()
        }
        // The mesh is the glTF an SDF names, anywhere below the scene's assets; the first
        // metadata file is the scene file `DIR/scene_<S>.json` that names it.
        Layout::SceneAgent => {
            let (scene, _) = id.split_once("__")?;
            let metadata = metadata?;
            (name(metadata)? == format!("{scene}.json"))
                .then(|| metadata.parent().map(Path::to_path_buf))
                .flatten()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_layout_s_folder_from_a_mesh_path() {
        let p = Path::new;
        let r = |layout, mesh, id| root(layout, p(mesh), None, id);
        assert_eq!(
            r(Layout::Plain, "a/assets/bed.glb", "bed"),
            Some(PathBuf::from("a/assets"))
        );
        assert_eq!(r(Layout::Plain, "a/assets/bed.glb", "chair"), None);
        assert_eq!(
            r(Layout::ThreeDFuture, "/d/3df/abc/raw_model.obj", "abc"),
            Some(PathBuf::from("/d/3df"))
        );
        assert_eq!(
            r(Layout::Objathor, "/d/o/abc/abc.glb", "abc"),
            Some(PathBuf::from("/d/o"))
        );
        assert_eq!(
            r(Layout::Hssd, "/d/h/glb/a/abc.glb", "abc"),
            Some(PathBuf::from("/d/h"))
        );
        assert_eq!(
            r(Layout::Hssd, "/d/h/decomposed/abc/abc_part1.glb", "abc_part1"),
            Some(PathBuf::from("/d/h"))
        );
        assert_eq!(r(Layout::Hssd, "/d/h/x/a/abc.glb", "abc"), None);
        assert_eq!(
            r(Layout::IDesign, "/c/scene_3/assets/bed_0.glb", "scene_3__bed_0"),
            Some(PathBuf::from("/c"))
        );
        assert_eq!(
            r(Layout::IDesign, "/c/scene_4/assets/bed_0.glb", "scene_3__bed_0"),
            None
        );
        // SceneAgent: the mesh's path says nothing; the scene file read for it does.
        let mesh = p("/c/scene_3/sdf/bed/bed.gltf");
        assert_eq!(root(Layout::SceneAgent, mesh, None, "scene_3__bed"), None);
        assert_eq!(
            root(
                Layout::SceneAgent,
                mesh,
                Some(p("/c/scene_3.json")),
                "scene_3__bed"
            ),
            Some(PathBuf::from("/c"))
        );
        assert_eq!(
            root(
                Layout::SceneAgent,
                mesh,
                Some(p("/c/scene_4.json")),
                "scene_3__bed"
            ),
            None
        );
    }
}
