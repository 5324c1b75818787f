//! IDesign: `scene_NNN/scene_graph.json` (a flat array of room elements and objects, z up,
//! metres, origin at the room's south-west corner), `scene_NNN/Assets/<object id>.glb` (the
//! retrieved Objaverse meshes, glTF y up) and optionally `scene_NNN/scene.blend`.
//!
//! - Room `0`: the floor element (`"middle of the room"` / `itemType: floor`), a
//!   `length` x `width` rectangle centred on its `position`; four walls along its edges
//!   (`south_wall`, `east_wall`, `north_wall`, `west_wall`), 0.1 m thick, as high as the
//!   ceiling element is above the floor (else the tallest wall element).
//! - Objects (every other element): the GLB is copied to `scene_<ID>/assets/<id>.glb` and
//!   named `idesign.scene_<ID>__<id>`; the transform (z-up, the `idesign` prefix's convention)
//!   scales the mesh's bounds to `size_in_meters` (length along x, width along y, height along
//!   z), turns it by `z_angle + 180` degrees about z (IDesign's `place_in_blender.py`), and puts
//!   its box centre at `position`; `objectFrontVector` `[0, 1, 0]` (IDesign's assets face +y).
//!   The description is `style material name`, as the fork writes it.

use std::path::{Path, PathBuf};

use sceneeval_geom::{Point2, Point3, Polygon2, Real, Rotation3, Vector3};
use sceneeval_io::assets::humanize_object_id;
use sceneeval_io::frames::ObjectFront;
use sceneeval_io::scene_state::derived_object_id;
use sceneeval_io::scene_state::json_in::{Doc, optional, ptr_index, ptr_key};
use sceneeval_io::{AssetLibrary, IoError};
use sceneeval_scene::{Floor, Room, WallSpec};
use serde_json::{Map, Value};

use crate::format::Converter;
use crate::native::{Ids, read_json, text, xyz};
use crate::output::{Output, files_under};
use crate::place::{Target, place};
use crate::{ConvertError, NativeScene, Written};

/// The ids of IDesign's room elements.
const ROOM_ELEMENTS: [&str; 6] = [
    "south_wall",
    "north_wall",
    "east_wall",
    "west_wall",
    "middle of the room",
    "ceiling",
];
/// Wall thickness written for IDesign rooms (the fork's 0.1 m).
const WALL_DEPTH: Real = 0.1;
/// A mesh extent below this cannot be scaled to a size (the fork's threshold); it keeps its
/// own size along that axis.
const MIN_EXTENT: Real = 1e-6;

/// The IDesign conversion.
pub(crate) struct IDesign;

impl Converter for IDesign {
    /// Converts one IDesign scene into `scene_<id>.json` of `out` and its assets.
    fn convert(
        &self,
        scene: &NativeScene,
        id: u64,
        out: Output<'_>,
        library: &AssetLibrary,
    ) -> Result<Written, ConvertError> {
        let file = scene.dir.join("scene_graph.json");
        let root = read_json(&file, library)?;
        let doc = Doc { path: &file };
        let items = doc.array(&root, "")?;
        let mut room_items = Vec::new();
        let mut object_items = Vec::new();
        // An object's id names its GLB and its model id: two objects with one id would share one.
        let mut ids = Ids::new(&doc);
        for (i, item) in items.iter().enumerate() {
            let ptr = ptr_index("", i);
            let o = doc.object(item, &ptr)?;
            let name = doc.string(
                doc.required(o, &ptr, "new_object_id")?,
                &ptr_key(&ptr, "new_object_id"),
            )?;
            ids.add(name, &ptr)?;
            let kind = text(&doc, o, &ptr, "itemType")?;
            if ROOM_ELEMENTS.contains(&name) || matches!(kind, Some("wall" | "floor" | "ceiling")) {
                room_items.push((ptr, name, kind, o));
            } else {
                object_items.push((ptr, name, o));
            }
        }
        let room = read_room(&doc, &room_items)?;

        let assets_rel = PathBuf::from(format!("scene_{id}")).join("assets");
        let mut files = Vec::new();
        let mut objects = Vec::new();
        for (ptr, name, o) in object_items {
            if name.is_empty() || name.contains(['/', '\\']) || name == "." || name == ".." {
                return Err(doc
                    .invalid(&ptr_key(&ptr, "new_object_id"), "not usable as a file name")
                    .into());
            }
            let glb = find_glb(&scene.dir.join("Assets"), name)?.ok_or_else(|| IoError::File {
                path: scene.dir.join("Assets").join(format!("{name}.glb")),
                source: std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    format!("no GLB for the object at {ptr} of {}", file.display()),
                ),
            })?;
            let rel = assets_rel.join(format!("{name}.glb"));
            out.copy_file(&glb, &rel)?;
            files.push(rel);
            let model_id = format!("idesign.scene_{id}__{name}");
            // The mesh's bounds in the z-up frame the transform maps.
            let asset = library
                .asset(&model_id)
                .map_err(|e| ConvertError::asset(&file, &ptr, &model_id, e))?;
            let mesh = *asset.mesh.aabb();
            let size_ptr = ptr_key(&ptr, "size_in_meters");
            let size = doc.object(doc.required(o, &ptr, "size_in_meters")?, &size_ptr)?;
            let dim = |key: &'static str| -> Result<Real, ConvertError> {
                Ok(doc.number(doc.required(size, &size_ptr, key)?, &ptr_key(&size_ptr, key))?)
            };
            let wanted = Vector3::new(dim("length")?, dim("width")?, dim("height")?);
            let extents = mesh.extents();
            let scale = Vector3::from_fn(|k, _| {
                if extents[k] > MIN_EXTENT && wanted[k] > 0.0 {
                    wanted[k] / extents[k]
                } else {
                    tracing::warn!(file = %file.display(), object = name, axis = k, "the mesh or the wanted size is flat along this axis; not scaled along it");
                    1.0
                }
            });
            let z_angle = match optional(o, "rotation") {
                Some(r) => {
                    let rptr = ptr_key(&ptr, "rotation");
                    match optional(doc.object(r, &rptr)?, "z_angle") {
                        Some(v) => doc.number(v, &ptr_key(&rptr, "z_angle"))?,
                        None => 0.0,
                    }
                }
                None => 0.0,
            };
            let position = xyz(
                &doc,
                doc.required(o, &ptr, "position")?,
                &ptr_key(&ptr, "position"),
                None,
            )?;
            let turn = Rotation3::from_axis_angle(&Vector3::z_axis(), (z_angle + 180.0).to_radians());
            let object_id = derived_object_id(objects.len() as i64, Some(&model_id));
            let style = text(&doc, o, &ptr, "style")?;
            let material = text(&doc, o, &ptr, "material")?;
            let description = [style, material, Some(humanize_object_id(name).as_str())]
                .into_iter()
                .flatten()
                .filter(|s| !s.trim().is_empty())
                .collect::<Vec<_>>()
                .join(" ");
            let object = place(
                library,
                &object_id,
                &model_id,
                &turn,
                &scale,
                ObjectFront::PlusY,
                Target::Centre(Point3::from(position)),
                (&file, &ptr),
            )?
            .with_index(objects.len() as i64)
            .with_description(description);
            objects.push(object);
        }
        let blend = scene.dir.join("scene.blend");
        if blend.is_file() {
            let rel = assets_rel.join("original_idesign.blend");
            out.copy_file(&blend, &rel)?;
            files.push(rel);
        }
        out.write_scene(objects, vec![room], &file, id)?;
        Ok(Written {
            files,
            skipped_objects: Vec::new(),
        })
    }
}

/// `Assets/<name>.glb`, else the first file under `Assets/` (in name order) whose name up to
/// its first dot is `name`, as IDesign's `place_in_blender.py` finds them.
fn find_glb(assets: &Path, name: &str) -> Result<Option<PathBuf>, ConvertError> {
    let direct = assets.join(format!("{name}.glb"));
    if direct.is_file() {
        return Ok(Some(direct));
    }
    if !assets.is_dir() {
        return Ok(None);
    }
    Ok(files_under(assets)?.into_iter().find_map(|rel| {
        let file = rel.file_name()?.to_str()?;
        (file.ends_with(".glb") && file.split('.').next() == Some(name)).then(|| assets.join(&rel))
    }))
}

type Item<'a> = (String, &'a str, Option<&'a str>, &'a Map<String, Value>);

fn read_room(doc: &Doc<'_>, items: &[Item<'_>]) -> Result<Room, ConvertError> {
    let is_floor = |(_, name, kind, _): &&Item<'_>| *kind == Some("floor") || *name == "middle of the room";
    let Some((fptr, _, _, floor)) = items.iter().find(is_floor) else {
        return Err(doc
            .invalid(
                "",
                "no floor element (\"middle of the room\" or itemType \"floor\")",
            )
            .into());
    };
    let centre = xyz(
        doc,
        doc.required(floor, fptr, "position")?,
        &ptr_key(fptr, "position"),
        None,
    )?;
    let size_ptr = ptr_key(fptr, "size_in_meters");
    let size = doc.object(doc.required(floor, fptr, "size_in_meters")?, &size_ptr)?;
    let length = doc.number(
        doc.required(size, &size_ptr, "length")?,
        &ptr_key(&size_ptr, "length"),
    )?;
    let width = doc.number(
        doc.required(size, &size_ptr, "width")?,
        &ptr_key(&size_ptr, "width"),
    )?;
    let z = centre[2];
    let ceiling = items
        .iter()
        .find(|(_, name, kind, _)| *kind == Some("ceiling") || *name == "ceiling")
        .map(|(p, _, _, o)| {
            xyz(
                doc,
                doc.required(o, p, "position")?,
                &ptr_key(p, "position"),
                None,
            )
            .map(|c| c[2] - z)
        })
        .transpose()?;
    let tallest_wall = items
        .iter()
        .filter(|(_, name, kind, _)| *kind == Some("wall") || name.ends_with("_wall"))
        .map(|(p, _, _, o)| {
            let sp = ptr_key(p, "size_in_meters");
            let s = doc.object(doc.required(o, p, "size_in_meters")?, &sp)?;
            doc.number(doc.required(s, &sp, "height")?, &ptr_key(&sp, "height"))
        })
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .reduce(Real::max);
    let Some(height) = ceiling.or(tallest_wall) else {
        return Err(doc
            .invalid("", "no ceiling or wall element gives the room's height")
            .into());
    };
    let (x0, x1) = (centre[0] - length / 2.0, centre[0] + length / 2.0);
    let (y0, y1) = (centre[1] - width / 2.0, centre[1] + width / 2.0);
    let corners = [
        Point2::new(x0, y0),
        Point2::new(x1, y0),
        Point2::new(x1, y1),
        Point2::new(x0, y1),
    ];
    let polygon =
        Polygon2::new(corners.to_vec()).map_err(|e| doc.invalid(&size_ptr, format!("floor: {e}")))?;
    let walls = ["south_wall", "east_wall", "north_wall", "west_wall"]
        .iter()
        .enumerate()
        .map(|(i, id)| WallSpec::new(*id, corners[i], corners[(i + 1) % 4], z, height, WALL_DEPTH))
        .collect();
    let floor = Floor {
        id: "floor_0".into(),
        polygon,
        z,
    };
    Room::new("0", floor, walls, None).map_err(|e| ConvertError::scene(doc.path, fptr.as_str(), e))
}
