//! Writing a [`Scene`] as a sceneState JSON file.

use std::path::Path;

use sceneeval_geom::{Real, Vector3};
use sceneeval_scene::{OpeningKind, Room, Scene, SceneObject, Wall};

use super::{ARCH_VERSION, FORMAT, SCENE_VERSION, derived_object_id};
use crate::IoError;
use crate::frames::{ObjectFront, TransformFrame};
use crate::json_out::Json;

/// Writes `scene` as a sceneState JSON file at `path` (see [`scene_state_to_string`]),
/// atomically: through a unique temporary file in the same folder and a rename
/// ([`sceneeval_files::write_atomic`]), so a reader never sees a part of it; the folder is
/// created if missing.
///
/// # Errors
/// As [`scene_state_to_string`], plus [`IoError::File`] when the file cannot be written.
pub fn write_scene_state(scene: &Scene, path: &Path) -> Result<(), IoError> {
    let text = scene_state_to_string(scene)?;
    sceneeval_files::write_atomic(path, text.as_bytes()).map_err(|e| IoError::file(path, e))
}

/// The sceneState JSON text of `scene`: deterministic, pretty-printed (two spaces, arrays of
/// numbers on one line), keys in a fixed order, with a trailing newline.
///
/// Every room is written as its `Floor` element, its explicit `Ceiling` (if any) and its
/// `Wall`s; every object as an entry with `index`, `modelId` (asset objects) or `box` (box
/// objects), `category`/`description` when known, `transform.data` (column-major, asset
/// frame for asset objects) and `objectPose`, the exact rotation and scale, so that reading
/// the file back gives the same poses bit for bit. A scene without rooms gets an empty `arch`
/// (so that reading it back does not build the simple architecture). The scene's name is
/// not written: a scene read from a file is named after the file's stem. The format is
/// described in `docs/formats.md`.
///
/// ```
/// use sceneeval_scene::{Category, RoomBuilder, Scene};
/// use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
/// use sceneeval_io::scene_state_to_string;
///
/// let scene = Scene::builder()
///     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 3.0)))
///     // A 1.2 x 0.6 x 0.75 m desk (half extents); the file states its full size.
///     .add_box("desk", Category::new("desk"), Vector3::new(0.6, 0.3, 0.375),
///              pose_from_yaw(Point3::new(2.0, 2.7, 0.375), 0.0))
///     .build()
///     .unwrap();
/// let text = scene_state_to_string(&scene).unwrap();
/// assert!(text.starts_with("{\n  \"format\": \"sceneState\""));
/// assert!(text.contains("\"size\": [1.2, 0.6, 0.75]"));
/// assert_eq!(text, scene_state_to_string(&scene).unwrap(), "deterministic");
/// ```
///
/// # Errors
/// [`IoError::Unwritable`] for an object that is neither a box nor has a model id (its mesh
/// cannot be referenced from a sceneState file), or for a non-finite number.
pub fn scene_state_to_string(scene: &Scene) -> Result<String, IoError> {
    let mut elements = Vec::new();
    for room in scene.rooms() {
        room_elements(room, &mut elements);
    }
    let fronts = scene
        .objects()
        .iter()
        .map(object_front)
        .collect::<Result<Vec<_>, _>>()?;
    // One front shared by every object (and not the default) is written once for the scene,
    // as the SceneSmith fork writes it; otherwise each object that differs says so.
    let shared = match fronts.split_first() {
        Some((&first, rest)) if first != ObjectFront::MinusY && rest.iter().all(|&f| f == first) => {
            Some(first)
        }
        _ => None,
    };
    let objects = scene
        .objects()
        .iter()
        .zip(&fronts)
        .enumerate()
        .map(|(position, (object, &front))| object_entry(object, position, front, shared.is_none()))
        .collect::<Result<Vec<_>, _>>()?;
    let mut scene_fields = vec![
        ("version", Json::str(SCENE_VERSION)),
        ("up", Json::nums(&[0.0, 0.0, 1.0])),
        ("unit", Json::Num(1.0)),
    ];
    if let Some(front) = shared {
        scene_fields.push(("objectFrontVector", Json::nums(front.vector().as_slice())));
    }
    scene_fields.push((
        "arch",
        Json::Obj(vec![
            ("version", Json::str(ARCH_VERSION)),
            ("elements", Json::Arr(elements)),
        ]),
    ));
    scene_fields.push(("object", Json::Arr(objects)));
    let doc = Json::Obj(vec![
        ("format", Json::str(FORMAT)),
        ("scene", Json::Obj(scene_fields)),
    ]);
    if let Some(v) = doc.find_non_finite() {
        return Err(IoError::Unwritable {
            object: scene.name().unwrap_or("scene").to_owned(),
            reason: format!("the scene holds a non-finite number ({v})"),
        });
    }
    Ok(doc.to_pretty_string())
}

fn points(points: impl Iterator<Item = [Real; 3]>) -> Json {
    Json::Arr(points.map(|p| Json::nums(&p)).collect())
}

fn room_elements(room: &Room, out: &mut Vec<Json>) {
    let room_id = room.id().as_str();
    let z = room.floor_z();
    let mut floor = vec![
        ("id", Json::str(room.floor_id())),
        ("roomId", Json::str(room_id)),
        ("type", Json::str("Floor")),
    ];
    if let Some(kind) = room.kind() {
        floor.push(("roomType", Json::str(kind)));
    }
    floor.push((
        "points",
        points(room.floor().points().iter().map(|p| [p.x, p.y, z])),
    ));
    out.push(Json::Obj(floor));
    if let Some(c) = room.explicit_ceiling() {
        out.push(Json::Obj(vec![
            ("id", Json::str(&c.id)),
            ("roomId", Json::str(room_id)),
            ("type", Json::str("Ceiling")),
            (
                "points",
                points(c.polygon.points().iter().map(|p| [p.x, p.y, c.z])),
            ),
        ]));
    }
    for wall in room.walls() {
        out.push(wall_element(room_id, wall));
    }
}

fn wall_element(room_id: &str, wall: &Wall) -> Json {
    let (a, b, z) = (wall.start(), wall.end(), wall.base_z());
    let holes = wall
        .openings()
        .iter()
        .map(|o| {
            Json::Obj(vec![
                ("id", Json::str(&o.id)),
                (
                    "type",
                    Json::str(match o.kind {
                        OpeningKind::Door => "Door",
                        OpeningKind::Window => "Window",
                    }),
                ),
                (
                    "box",
                    Json::Obj(vec![
                        ("min", Json::nums(&[o.along[0], o.height[0]])),
                        ("max", Json::nums(&[o.along[1], o.height[1]])),
                    ]),
                ),
            ])
        })
        .collect();
    Json::Obj(vec![
        ("id", Json::str(wall.id())),
        ("roomId", Json::str(room_id)),
        ("type", Json::str("Wall")),
        ("points", points([[a.x, a.y, z], [b.x, b.y, z]].into_iter())),
        ("height", Json::Num(wall.height())),
        ("depth", Json::Num(wall.thickness())),
        ("holes", Json::Arr(holes)),
    ])
}

/// The front an object's file declares for it (see [`SceneObject::asset_front`]).
fn object_front(object: &SceneObject) -> Result<ObjectFront, IoError> {
    match object.asset_front() {
        None => Ok(ObjectFront::MinusY),
        Some(v) => ObjectFront::from_vector([v.x, v.y, v.z]).map_err(|reason| IoError::Unwritable {
            object: object.id().to_string(),
            reason: format!("its asset front {reason}"),
        }),
    }
}

/// The entry of `object`; `front` is the front its file declares, written on the entry when
/// `own_front` and it is not the default.
fn object_entry(
    object: &SceneObject,
    position: usize,
    front: ObjectFront,
    own_front: bool,
) -> Result<Json, IoError> {
    let index = object.index().unwrap_or(position as i64);
    let model_id = object.model_id();
    let is_box = object.box_half_extents();
    if is_box.is_none() && model_id.is_none() {
        return Err(IoError::Unwritable {
            object: object.id().to_string(),
            reason: "it is neither a box nor an asset (no model id), so its mesh cannot be \
                     referenced from a sceneState file"
                .into(),
        });
    }
    let pose = *object.pose();
    let mut fields = vec![("index", Json::Int(index))];
    if object.id().as_str() != derived_object_id(index, model_id) {
        fields.push(("objectId", Json::str(object.id().as_str())));
    }
    if let Some(m) = model_id {
        fields.push(("modelId", Json::str(m)));
    }
    if let Some(c) = object.category() {
        fields.push(("category", Json::str(c)));
    }
    if let Some(d) = object.description() {
        fields.push(("description", Json::str(d)));
    }
    if let Some(t) = object.support_type() {
        fields.push(("supportType", Json::str(t.name())));
    }
    if let Some(sides) = object.functional_sides() {
        fields.push((
            "functionalSides",
            Json::Arr(sides.iter().map(|s| Json::str(s.name())).collect()),
        ));
    }
    if own_front && front != ObjectFront::MinusY {
        fields.push(("objectFrontVector", Json::nums(front.vector().as_slice())));
    }
    let scale = object.scale();
    // The file holds the object in its declared frame: the pose turned back by the front,
    // sizes and scales in that frame.
    let file_pose = front.file_pose(&pose);
    let data = match is_box {
        Some(half) => {
            // A box's scale is already in its size: the transform is the rigid pose, and
            // `objectPose.scale` only records the scale that was baked in.
            let size = front.turn_scale(&(half * 2.0));
            fields.push(("box", Json::Obj(vec![("size", Json::nums(size.as_slice()))])));
            TransformFrame::Object.sstk(&file_pose, &Vector3::repeat(1.0))
        }
        None => {
            let frame = TransformFrame::for_model_id(model_id.unwrap_or_default());
            frame.sstk(&file_pose, &front.turn_scale(&scale))
        }
    };
    let scale = (scale != Vector3::repeat(1.0)).then_some(scale);
    fields.push((
        "transform",
        Json::Obj(vec![
            ("rows", Json::Int(4)),
            ("cols", Json::Int(4)),
            ("data", Json::nums(&data)),
        ]),
    ));
    let q = pose.rotation.coords; // [x, y, z, w]
    let mut object_pose = vec![("rotation", Json::nums(&[q.x, q.y, q.z, q.w]))];
    if let Some(s) = scale {
        object_pose.push(("scale", Json::nums(s.as_slice())));
    }
    fields.push(("objectPose", Json::Obj(object_pose)));
    Ok(Json::Obj(fields))
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::conventions::pose_from_yaw;
    use sceneeval_geom::{Isometry3, Mesh, Point2, Point3};
    use sceneeval_scene::Category;
    use sceneeval_scene::RoomBuilder;
    use std::sync::Arc;

    fn scene() -> Scene {
        Scene::builder()
            .room_builder(
                RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 3.0))
                    .kind("bedroom")
                    .wall_thickness(0.1)
                    .with_ceiling()
                    .door(0, [1.0, 1.9], [0.0, 2.1])
                    .window(2, [0.5, 1.5], [0.9, 2.0]),
            )
            .add_box(
                "desk",
                Category::new("desk"),
                Vector3::new(0.6, 0.3, 0.375),
                pose_from_yaw(Point3::new(2.0, 2.7, 0.375), 0.0),
            )
            .object(
                SceneObject::from_mesh(
                    "idx7_fixture.lamp",
                    Arc::new(Mesh::cuboid(&Vector3::repeat(0.1)).unwrap()),
                    Isometry3::translation(1.0, 1.0, 0.1),
                )
                .unwrap()
                .with_index(7)
                .with_model_id("fixture.lamp")
                .with_scale(Vector3::new(1.0, 2.0, 1.0)),
            )
            .build()
            .unwrap()
    }

    #[test]
    fn writes_every_part_in_a_fixed_layout() {
        let text = scene_state_to_string(&scene()).unwrap();
        assert!(text.ends_with("}\n"));
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["format"], "sceneState");
        let elements = v["scene"]["arch"]["elements"].as_array().unwrap();
        let types: Vec<&str> = elements.iter().map(|e| e["type"].as_str().unwrap()).collect();
        assert_eq!(types, ["Floor", "Ceiling", "Wall", "Wall", "Wall", "Wall"]);
        assert_eq!(elements[0]["id"], "floor_r0");
        assert_eq!(elements[0]["roomType"], "bedroom");
        assert_eq!(elements[1]["points"][2], serde_json::json!([4.0, 3.0, 2.8]));
        let wall0 = &elements[2];
        assert_eq!(wall0["id"], "r0_wall_0");
        assert_eq!(
            wall0["points"],
            serde_json::json!([[0.0, 0.0, 0.0], [4.0, 0.0, 0.0]])
        );
        assert_eq!(wall0["depth"], 0.1);
        assert_eq!(wall0["holes"][0]["type"], "Door");
        assert_eq!(wall0["holes"][0]["box"]["max"], serde_json::json!([1.9, 2.1]));
        assert_eq!(elements[4]["holes"][0]["type"], "Window");

        let objects = v["scene"]["object"].as_array().unwrap();
        // The desk was built in code: its id differs from idx0_box, so it is kept explicitly.
        assert_eq!(objects[0]["index"], 0);
        assert_eq!(objects[0]["objectId"], "desk");
        assert_eq!(objects[0]["category"], "desk");
        assert!(objects[0].get("modelId").is_none());
        assert_eq!(objects[0]["box"]["size"], serde_json::json!([1.2, 0.6, 0.75]));
        // Box transform = the object pose: yaw 0, translation at the centre.
        let data: Vec<f64> = serde_json::from_value(objects[0]["transform"]["data"].clone()).unwrap();
        assert_eq!(&data[12..16], &[2.0, 2.7, 0.375, 1.0]);
        // The lamp's id is the derived one, so no objectId; its transform is in the asset frame:
        // pose identity, so T = Rx(+90) * diag(native scale (1, 1, 2)) [object (1, 2, 1)]:
        // columns (1,0,0), (0,0,1)*1, (0,-1,0)*2.
        assert!(objects[1].get("objectId").is_none());
        assert_eq!(objects[1]["modelId"], "fixture.lamp");
        let data: Vec<f64> = serde_json::from_value(objects[1]["transform"]["data"].clone()).unwrap();
        let expected = [
            1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -2.0, 0.0, 0.0, 1.0, 1.0, 0.1, 1.0,
        ];
        assert_eq!(data, expected);
        assert_eq!(
            objects[1]["objectPose"]["scale"],
            serde_json::json!([1.0, 2.0, 1.0])
        );
    }

    #[test]
    fn output_is_deterministic_and_files_match_strings() {
        let s = scene();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("scene_0.json");
        write_scene_state(&s, &path).unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            scene_state_to_string(&s).unwrap()
        );
        assert_eq!(
            scene_state_to_string(&s).unwrap(),
            scene_state_to_string(&s.clone()).unwrap()
        );
    }

    #[test]
    fn mesh_objects_without_model_id_are_unwritable() {
        let s = Scene::builder()
            .add_mesh(
                "blob",
                Category::new("thing"),
                Arc::new(Mesh::cuboid(&Vector3::repeat(0.5)).unwrap()),
                Isometry3::identity(),
            )
            .build()
            .unwrap();
        match scene_state_to_string(&s) {
            Err(IoError::Unwritable { object, .. }) => assert_eq!(object, "blob"),
            other => panic!("{other:?}"),
        }
    }
}
