//! `fixtures/native/<format>/`: small scenes in the native formats of the generators that
//! `sceneeval convert` reads, with the assets each needs, written from the catalog's furniture.
//! The tests of `sceneeval-convert` convert them and compare the objects' boxes and fronts and
//! the architecture with values computed by hand from the numbers below.
//!
//! | folder | what | assets |
//! |---|---|---|
//! | `holodeck/scenes/` | two AI2-THOR house JSONs (Unity frame): `bedroom-2024-05-01/bedroom.json` (one room, an exterior door given on the exterior wall face, a window, exterior wall twins, floor, wall, small, ceiling and tilted objects, one AI2-THOR asset) and `two_rooms/two_rooms.json` (a door between two rooms) | `holodeck/objathor/<uid>/<uid>.glb` + `annotations.json` (Objathor layout: y up, front +z, origin at the bottom centre) |
//! | `layoutvlm/scenes/` | `scene_000` (four assets, the second not placed) and `scene_001` (one asset, an older task file without `uid`) | `layoutvlm/assets/<uid>/<uid>.glb` + `data.json` |
//! | `idesign/scenes/` | `scene_000`: `scene_graph.json`, `Assets/<id>.glb`, `scene.blend` | the GLBs face +y once turned z up (IDesign's convention), half size and off-centre, so that conversion must recentre and scale them |
//! | `scene-agent/scenes/` | `scene_000`: two rooms (`combined_house/sceneeval_state.json`, `room_bedroom/`, `room_office/`), both prefixes (`scenesmith.`, `scene-agent.`), an `isArchitecture` entry | each object's `generated_assets/<category>/sdf/<name>/` with its SDF and a glTF + `.bin` facing +y once turned z up |
//!
//! The `.blend` files are placeholders (the converters only copy them).

use std::path::{Path, PathBuf};

use sceneeval_io::{GlbMesh, write_glb, write_glb_to_vec};
use serde_json::{Value, json};

use crate::assets::{AssetDef, asset};
use crate::{FixtureError, write_json};

/// The folder inside the fixtures folder.
pub const NATIVE_DIR: &str = "native";

/// The Objaverse uid the fixtures give a catalog asset: 32 hex digits.
pub fn uid(asset_id: &str) -> String {
    // A fixed, readable uid per asset: its position in the catalog, padded.
    let index = crate::assets::catalog()
        .iter()
        .position(|a| a.id == asset_id)
        .unwrap_or(99);
    format!("f1c7{index:028x}")
}

fn catalog_asset(id: &str) -> Result<AssetDef, FixtureError> {
    asset(id).ok_or_else(|| FixtureError::spec("native", format!("no catalog asset {id:?}")))
}

/// The catalog asset's meshes with every position mapped by `f`.
fn mapped(def: &AssetDef, f: impl Fn([f32; 3]) -> [f32; 3]) -> Vec<GlbMesh> {
    def.glb_meshes()
        .into_iter()
        .map(|mut m| {
            m.positions = m.positions.into_iter().map(&f).collect();
            m
        })
        .collect()
}

/// Turned by pi about the asset's up axis: the front moves from +z to -z, which is +y once the
/// file is turned z up (the convention of IDesign's and SceneSmith's assets).
fn facing_plus_y(p: [f32; 3]) -> [f32; 3] {
    [-p[0], p[1], -p[2]]
}

struct Out<'a> {
    root: &'a Path,
    files: Vec<PathBuf>,
}

impl Out<'_> {
    fn path(&self, rel: &str) -> Result<PathBuf, FixtureError> {
        let path = self.root.join(rel);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|e| FixtureError::file(parent, e))?;
        }
        Ok(path)
    }

    fn json(&mut self, rel: &str, value: &Value) -> Result<(), FixtureError> {
        write_json(&self.path(rel)?, value)?;
        self.files.push(rel.into());
        Ok(())
    }

    fn bytes(&mut self, rel: &str, bytes: &[u8]) -> Result<(), FixtureError> {
        let path = self.path(rel)?;
        std::fs::write(&path, bytes).map_err(|e| FixtureError::file(path, e))?;
        self.files.push(rel.into());
        Ok(())
    }

    fn glb(&mut self, rel: &str, meshes: &[GlbMesh]) -> Result<(), FixtureError> {
        let path = self.path(rel)?;
        write_glb(&path, meshes).map_err(|e| FixtureError::io(rel, e))?;
        self.files.push(rel.into());
        Ok(())
    }

    /// A glTF (`<stem>.gltf`, JSON) with its binary buffer beside it (`<stem>.bin`), as
    /// SceneSmith writes its visual meshes.
    fn gltf(&mut self, rel_stem: &str, meshes: &[GlbMesh]) -> Result<(), FixtureError> {
        let glb = write_glb_to_vec(meshes).map_err(|e| FixtureError::io(rel_stem, e))?;
        let bad = |reason: &str| FixtureError::spec("native", format!("{rel_stem}: {reason}"));
        let word = |at: usize| -> Result<usize, FixtureError> {
            let b: [u8; 4] = glb
                .get(at..at + 4)
                .and_then(|s| s.try_into().ok())
                .ok_or_else(|| bad("short GLB"))?;
            Ok(u32::from_le_bytes(b) as usize)
        };
        let json_len = word(12)?;
        let json_bytes = glb
            .get(20..20 + json_len)
            .ok_or_else(|| bad("short JSON chunk"))?;
        let bin_at = 20 + json_len;
        let bin_len = word(bin_at)?;
        let bin = glb
            .get(bin_at + 8..bin_at + 8 + bin_len)
            .ok_or_else(|| bad("short BIN chunk"))?;
        let mut doc: Value = serde_json::from_slice(json_bytes).map_err(|e| FixtureError::Json {
            path: rel_stem.into(),
            source: e,
        })?;
        let name = Path::new(rel_stem)
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let length = doc["buffers"][0]["byteLength"]
            .as_u64()
            .ok_or_else(|| bad("no buffer"))? as usize;
        doc["buffers"][0]["uri"] = Value::String(format!("{name}.bin"));
        self.json(&format!("{rel_stem}.gltf"), &doc)?;
        self.bytes(
            &format!("{rel_stem}.bin"),
            bin.get(..length).ok_or_else(|| bad("short buffer"))?,
        )
    }
}

/// Writes `native/` into the fixtures folder `dir`; returns the files written, relative to
/// `dir`.
///
/// # Errors
/// [`FixtureError`] when a file cannot be written.
pub fn write(dir: &Path) -> Result<Vec<PathBuf>, FixtureError> {
    let root = dir.join(NATIVE_DIR);
    let mut out = Out {
        root: &root,
        files: Vec::new(),
    };
    holodeck(&mut out)?;
    layoutvlm(&mut out)?;
    idesign(&mut out)?;
    scene_agent(&mut out)?;
    let mut files: Vec<PathBuf> = out
        .files
        .into_iter()
        .map(|f| Path::new(NATIVE_DIR).join(f))
        .collect();
    files.sort();
    Ok(files)
}

/// A Unity `{x, y, z}`.
fn v3(x: f64, y: f64, z: f64) -> Value {
    json!({"x": x, "y": y, "z": z})
}

/// A Holodeck wall along `[a, b]` (Unity x-z) and its exterior twin.
fn holo_walls(room: &str, side: &str, a: [f64; 2], b: [f64; 2], height: f64, exterior: bool) -> Vec<Value> {
    let width = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
    let id = format!("wall|{room}|{side}|0");
    let mut out = vec![
        json!({"id": id, "roomId": room, "segment": [a, b], "height": height, "width": width,
                              "material": {"name": "PureWhite"}}),
    ];
    if exterior {
        out.push(
            json!({"id": format!("{id}|exterior"), "roomId": room, "segment": [b, a], "height": height,
                        "width": width, "material": {"name": "Walldrywall4Tiled"}}),
        );
    }
    out
}

fn holo_object(id: &str, asset: &str, position: Value, rotation: Value) -> Value {
    json!({"id": id, "assetId": asset, "position": position, "rotation": rotation, "kinematic": false})
}

fn holodeck(out: &mut Out<'_>) -> Result<(), FixtureError> {
    let used = [
        "bed",
        "nightstand",
        "painting",
        "table_lamp",
        "ceiling_lamp",
        "storage_box",
        "sofa",
        "dining_table",
    ];
    let mut annotations = serde_json::Map::new();
    for id in used {
        let def = catalog_asset(id)?;
        let uid = uid(id);
        out.glb(&format!("holodeck/objathor/{uid}/{uid}.glb"), &def.glb_meshes())?;
        annotations.insert(
            uid,
            json!({"category": def.category, "ref_category": def.category, "description": def.description,
                   "description_auto": ""}),
        );
    }
    out.json("holodeck/objathor/annotations.json", &Value::Object(annotations))?;

    // Scene 0: a 4 x 5 m bedroom (Unity x 0..4, z 0..5), walls 2.7 m high.
    let mut walls = Vec::new();
    for (side, a, b) in [
        ("south", [0.0, 0.0], [4.0, 0.0]),
        ("east", [4.0, 0.0], [4.0, 5.0]),
        ("north", [4.0, 5.0], [0.0, 5.0]),
        ("west", [0.0, 5.0], [0.0, 0.0]),
    ] {
        walls.extend(holo_walls("bedroom", side, a, b, 2.7, true));
    }
    let objects = vec![
        // Floor objects (the box centre is half their height up, as Holodeck writes it).
        holo_object(
            "bed (bedroom)",
            &uid("bed"),
            v3(2.0, 0.55, 3.95),
            v3(0.0, 180.0, 0.0),
        ),
        holo_object(
            "nightstand (bedroom)",
            &uid("nightstand"),
            v3(3.3, 0.275, 4.7),
            v3(0.0, 180.0, 0.0),
        ),
        // A box tipped over onto its back, turned a quarter: Unity Euler (90, 90, 0).
        holo_object(
            "storage box (bedroom)",
            &uid("storage_box"),
            v3(1.0, 0.15, 1.0),
            v3(90.0, 90.0, 0.0),
        ),
        // On the west wall, facing the room (+x).
        holo_object(
            "painting (bedroom)",
            &uid("painting"),
            v3(0.02, 1.5, 2.5),
            v3(0.0, 90.0, 0.0),
        ),
        // On the nightstand (0.55 m high): its box centre half its 0.45 m height above it.
        holo_object(
            "table lamp (bedroom)",
            &uid("table_lamp"),
            v3(3.3, 0.775, 4.7),
            v3(0.0, 195.0, 0.0),
        ),
        // Hanging from the 2.7 m ceiling (0.73 m tall).
        holo_object(
            "ceiling (bedroom)",
            &uid("ceiling_lamp"),
            v3(2.0, 2.335, 2.5),
            v3(0.0, 0.0, 0.0),
        ),
        // An AI2-THOR asset: skipped.
        holo_object(
            "Chair (bedroom)",
            "Chair_204_1",
            v3(1.0, 0.45, 4.0),
            v3(0.0, 0.0, 0.0),
        ),
    ];
    let house = json!({
        "rooms": [{"id": "bedroom", "roomType": "Bedroom",
                   "floorPolygon": [v3(0.0, 0.0, 0.0), v3(0.0, 0.0, 5.0), v3(4.0, 0.0, 5.0), v3(4.0, 0.0, 0.0)]}],
        "walls": walls,
        // The exterior door is given on the exterior face (x from that face's first point,
        // Unity (4, 0)), as Holodeck writes exterior doors; the window on the interior face.
        "doors": [{"id": "door|0|exterior|bedroom", "assetId": "Doorway_1", "room0": "bedroom", "room1": "bedroom",
                   "wall0": "wall|bedroom|south|0|exterior", "wall1": "wall|bedroom|south|0",
                   "holePolygon": [v3(1.0, 0.0, 0.0), v3(1.9, 2.1, 0.0)]}],
        "windows": [{"id": "window|wall|bedroom|east|0|0", "assetId": "Window_Slider_36x36", "roomId": "bedroom",
                     "wall0": "wall|bedroom|east|0", "wall1": "wall|bedroom|east|0|exterior",
                     "holePolygon": [v3(1.5, 0.9, 0.0), v3(2.5, 2.0, 0.0)]}],
        "objects": objects,
        "floor_objects": [{"id": "bed (bedroom)"}, {"id": "nightstand (bedroom)"}, {"id": "storage box (bedroom)"}],
        "wall_objects": [{"id": "painting (bedroom)"}],
        "small_objects": [{"id": "table lamp (bedroom)"}],
        "ceiling_objects": [{"id": "ceiling (bedroom)"}],
        "wall_height": 2.7,
    });
    out.json("holodeck/scenes/bedroom-2024-05-01/bedroom.json", &house)?;

    // Scene 1: a kitchen (x 0..3) and a living room (x 3..7), z 0..4, a door in the wall
    // between them given on the kitchen's face (x from (3, 0)).
    let mut walls = Vec::new();
    for (room, side, a, b) in [
        ("kitchen", "south", [0.0, 0.0], [3.0, 0.0]),
        ("kitchen", "east", [3.0, 0.0], [3.0, 4.0]),
        ("kitchen", "north", [3.0, 4.0], [0.0, 4.0]),
        ("kitchen", "west", [0.0, 4.0], [0.0, 0.0]),
        ("living room", "south", [3.0, 0.0], [7.0, 0.0]),
        ("living room", "east", [7.0, 0.0], [7.0, 4.0]),
        ("living room", "north", [7.0, 4.0], [3.0, 4.0]),
        ("living room", "west", [3.0, 4.0], [3.0, 0.0]),
    ] {
        walls.extend(holo_walls(room, side, a, b, 2.5, false));
    }
    let house = json!({
        "rooms": [
            {"id": "kitchen", "roomType": "Kitchen",
             "floorPolygon": [v3(0.0, 0.0, 0.0), v3(0.0, 0.0, 4.0), v3(3.0, 0.0, 4.0), v3(3.0, 0.0, 0.0)]},
            {"id": "living room", "roomType": "LivingRoom",
             "floorPolygon": [v3(3.0, 0.0, 0.0), v3(3.0, 0.0, 4.0), v3(7.0, 0.0, 4.0), v3(7.0, 0.0, 0.0)]},
        ],
        "walls": walls,
        "doors": [{"id": "door|1|kitchen|living room", "assetId": "Doorway_2", "room0": "kitchen", "room1": "living room",
                   "wall0": "wall|kitchen|east|0", "wall1": "wall|living room|west|0",
                   "holePolygon": [v3(1.0, 0.0, 0.0), v3(2.0, 2.0, 0.0)]}],
        "windows": [],
        "objects": [
            holo_object("dining table (kitchen)", &uid("dining_table"), v3(1.5, 0.38, 2.0), v3(0.0, 90.0, 0.0)),
            holo_object("sofa (living room)", &uid("sofa"), v3(5.0, 0.425, 3.5), v3(0.0, 180.0, 0.0)),
        ],
        "floor_objects": [{"id": "dining table (kitchen)"}, {"id": "sofa (living room)"}],
        "wall_height": 2.5,
    });
    out.json("holodeck/scenes/two_rooms/two_rooms.json", &house)
}

fn layoutvlm(out: &mut Out<'_>) -> Result<(), FixtureError> {
    for id in ["bed", "chair", "bookshelf", "desk"] {
        let def = catalog_asset(id)?;
        let uid = uid(id);
        out.glb(&format!("layoutvlm/assets/{uid}/{uid}.glb"), &def.glb_meshes())?;
        let [w, h, d] = def.asset_size();
        out.json(
            &format!("layoutvlm/assets/{uid}/data.json"),
            &json!({"annotations": {"category": def.category, "description": def.description, "materials": "",
                                    "onFloor": true, "onWall": false, "onCeiling": false, "onObject": false,
                                    "frontView": 0},
                    "assetMetadata": {"boundingBox": {"x": w, "y": d, "z": h}}}),
        )?;
    }
    // Scene 0: a 4 x 5 m room, 2.6 m walls. LayoutVLM did not place the bookshelf, whose key
    // sorts second: pairing the placements with the assets by position (as the fork does)
    // would give the bookshelf the first chair's placement; pairing by key does not.
    out.json(
        "layoutvlm/scenes/scene_000/scene.json",
        &json!({
            "task_description": "a bedroom with a desk and two chairs, 4m x 5m",
            "boundary": {"floor_vertices": [[0, 0, 0], [4, 0, 0], [4, 5, 0], [0, 5, 0]], "wall_height": 2.6},
            "assets": {
                "bed-0": {"uid": uid("bed"), "category": "bed"},
                "chair-0": {"uid": uid("chair"), "category": "chair"},
                "chair-1": {"uid": uid("chair"), "category": "chair"},
                "bookshelf-0": {"uid": uid("bookshelf"), "category": "bookshelf"},
            },
        }),
    )?;
    out.json(
        "layoutvlm/scenes/scene_000/layout.json",
        &json!({
            "chair-0": {"position": [1.0, 1.0, 0.45], "rotation": [0, 0, 90]},
            "chair-1": {"position": [1.0, 2.0, 0.45], "rotation": [0, 0, 90]},
            "bed-0": {"position": [2.5, 3.95, 0.55], "rotation": [0, 0, 0]},
        }),
    )?;
    // Scene 1: one desk in a 3 x 3 m room (older task files: no `uid`, the key says it).
    out.json(
        "layoutvlm/scenes/scene_001/scene.json",
        &json!({
            "boundary": {"floor_vertices": [[0, 0, 0], [3, 0, 0], [3, 3, 0], [0, 3, 0]], "wall_height": 2.4},
            "assets": {format!("{}-0", uid("desk")): {}},
        }),
    )?;
    out.json(
        "layoutvlm/scenes/scene_001/layout.json",
        &json!({format!("{}-0", uid("desk")): {"position": [1.5, 2.65, 0.375], "rotation": [0, 0, 180]}}),
    )
}

fn idesign(out: &mut Out<'_>) -> Result<(), FixtureError> {
    // IDesign's GLBs face +y once turned z up; these are also half size and off-centre
    // (x + 0.3, y + 0.1, z - 0.2 in the file), so that conversion has to recentre and scale.
    let shrunk = |p: [f32; 3]| {
        let q = facing_plus_y(p);
        [0.5 * q[0] + 0.3, 0.5 * q[1] + 0.1, 0.5 * q[2] - 0.2]
    };
    for id in ["bed", "nightstand", "wardrobe"] {
        let def = catalog_asset(id)?;
        out.glb(
            &format!("idesign/scenes/scene_000/Assets/{id}_1.glb"),
            &mapped(&def, shrunk),
        )?;
    }
    let room = |id: &str, kind: &str, pos: [f64; 3], size: [f64; 3], angle: f64| {
        json!({"new_object_id": id, "itemType": kind, "position": {"x": pos[0], "y": pos[1], "z": pos[2]},
               "size_in_meters": {"length": size[0], "width": size[1], "height": size[2]},
               "rotation": {"z_angle": angle}})
    };
    let object = |id: &str, pos: [f64; 3], size: [f64; 3], angle: f64, facing: &str| {
        json!({"new_object_id": id, "style": "Modern", "material": "Wood",
               "size_in_meters": {"length": size[0], "width": size[1], "height": size[2]},
               "is_on_the_floor": true, "facing": facing,
               "placement": {"room_layout_elements": [], "objects_in_room": []},
               "rotation": {"z_angle": angle}, "position": {"x": pos[0], "y": pos[1], "z": pos[2]}})
    };
    out.json(
        "idesign/scenes/scene_000/scene_graph.json",
        &json!([
            room("south_wall", "wall", [2.0, 0.0, 1.25], [4.0, 0.0, 2.5], 0.0),
            room("north_wall", "wall", [2.0, 5.0, 1.25], [4.0, 0.0, 2.5], 180.0),
            room("east_wall", "wall", [4.0, 2.5, 1.25], [5.0, 0.0, 2.5], 270.0),
            room("west_wall", "wall", [0.0, 2.5, 1.25], [5.0, 0.0, 2.5], 90.0),
            room(
                "middle of the room",
                "floor",
                [2.0, 2.5, 0.0],
                [4.0, 5.0, 0.0],
                0.0
            ),
            room("ceiling", "ceiling", [2.0, 2.5, 2.5], [4.0, 5.0, 0.0], 0.0),
            // Against the north wall, facing south (-y).
            object("bed_1", [2.0, 3.95, 0.55], [1.6, 2.1, 1.1], 0.0, "south_wall"),
            // Against the west wall, facing east (+x): z_angle 90.
            // Its size is given with length and width swapped from the mesh's (0.42 x 0.45):
            // the scale is not uniform.
            object(
                "nightstand_1",
                [0.225, 4.6, 0.275],
                [0.42, 0.45, 0.55],
                90.0,
                "east_wall"
            ),
            // Against the south wall, facing north (+y): z_angle 180.
            object(
                "wardrobe_1",
                [3.2, 0.3, 1.0],
                [1.0, 0.6, 2.0],
                180.0,
                "north_wall"
            ),
        ]),
    )?;
    out.bytes(
        "idesign/scenes/scene_000/scene.blend",
        b"BLENDER-v402 placeholder written by sceneeval-fixtures: sceneeval convert copies it as is\n",
    )
}

/// An SDF model whose visual is `<name>.gltf` (and whose collision mesh, listed first, is not).
fn sdf(name: &str) -> String {
    format!(
        "<?xml version=\"1.0\"?>\n<sdf version=\"1.7\">\n  <model name=\"{name}\">\n    <link name=\"base_link\">\n      \
         <collision name=\"collision_0\">\n        <geometry><mesh><uri>{name}_collision_0.obj</uri></mesh></geometry>\n      \
         </collision>\n      <visual name=\"visual\">\n        <geometry><mesh><uri>{name}.gltf</uri></mesh></geometry>\n      \
         </visual>\n    </link>\n  </model>\n</sdf>\n"
    )
}

/// A column-major transform: a turn by `yaw_deg` about z, then a translation.
fn z_up_transform(yaw_deg: f64, t: [f64; 3]) -> Value {
    let (s, c) = yaw_deg.to_radians().sin_cos();
    // Exact at quarter turns (sin 180 deg is 1.2e-16 in floating point).
    let exact = |v: f64| {
        if (v - v.round()).abs() < 1e-12 {
            v.round() + 0.0
        } else {
            v
        }
    };
    let (s, c) = (exact(s), exact(c));
    json!([
        c, s, 0.0, 0.0, -s, c, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, t[0], t[1], t[2], 1.0
    ])
}

fn scene_agent(out: &mut Out<'_>) -> Result<(), FixtureError> {
    let base = "scene-agent/scenes/scene_000";
    // (room, category, folder, asset, object id)
    let assets = [
        ("room_bedroom", "furniture", "bed_1717171717", "bed", "bed_0"),
        ("room_office", "furniture", "desk_1717171718", "desk", "desk_0"),
        (
            "room_office",
            "manipuland",
            "table_lamp_1717171719",
            "table_lamp",
            "table_lamp_0",
        ),
    ];
    for (room, category, folder, id, _) in assets {
        let def = catalog_asset(id)?;
        let dir = format!("{base}/{room}/generated_assets/{category}/sdf/{folder}");
        out.bytes(&format!("{dir}/{id}.sdf"), sdf(id).as_bytes())?;
        out.gltf(&format!("{dir}/{id}"), &mapped(&def, facing_plus_y))?;
        out.bytes(
            &format!("{dir}/{id}_collision_0.obj"),
            b"# collision mesh placeholder (not read by SceneEval)\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        )?;
    }
    // Files every room has that no object needs (and that differ between rooms).
    for (room, n) in [("room_bedroom", 1), ("room_office", 2)] {
        out.json(
            &format!("{base}/{room}/generated_assets/furniture/asset_registry.json"),
            &json!({"assets": n}),
        )?;
    }
    let sdf_path = |k: usize| {
        let (_, category, folder, id, _) = assets[k];
        format!("generated_assets/{category}/sdf/{folder}/{id}.sdf")
    };
    let wall = |room: &str, k: usize, a: [f64; 2], b: [f64; 2], holes: Value| {
        json!({"id": format!("wall|{room}|{k}"), "roomId": room, "type": "Wall", "height": 2.5, "depth": 0.05,
               "points": [[a[0], a[1], 0.0], [b[0], b[1], 0.0]], "holes": holes})
    };
    let door =
        json!([{"id": "door_bedroom_office", "type": "Door", "box": {"min": [2.0, 0.0], "max": [3.0, 2.1]}}]);
    let office_door =
        json!([{"id": "door_bedroom_office", "type": "Door", "box": {"min": [2.0, 0.0], "max": [3.0, 2.1]}}]);
    let state = json!({
        "format": "sceneState",
        "scene": {
            "version": "scene@1.0.2", "id": "scenesmith-combined_house", "unit": 1.0, "up": [0, 0, 1],
            "front": [0, 1, 0], "assetSource": ["scenesmith"],
            "arch": {
                "version": "arch@1.0.2", "id": "arch",
                "elements": [
                    {"id": "floor|bedroom", "roomId": "bedroom", "type": "Floor", "depth": 0.1,
                     "points": [[0, 0, 0], [4, 0, 0], [4, 5, 0], [0, 5, 0]]},
                    wall("bedroom", 1, [0.0, 0.0], [4.0, 0.0], json!([])),
                    wall("bedroom", 2, [4.0, 0.0], [4.0, 5.0], door),
                    wall("bedroom", 3, [4.0, 5.0], [0.0, 5.0], json!([])),
                    wall("bedroom", 4, [0.0, 5.0], [0.0, 0.0], json!([])),
                    {"id": "floor|office", "roomId": "office", "type": "Floor", "depth": 0.1,
                     "points": [[4, 0, 0], [8, 0, 0], [8, 5, 0], [4, 5, 0]]},
                    wall("office", 6, [4.0, 0.0], [8.0, 0.0], json!([])),
                    wall("office", 7, [8.0, 0.0], [8.0, 5.0], json!([])),
                    wall("office", 8, [8.0, 5.0], [4.0, 5.0], json!([])),
                    wall("office", 9, [4.0, 5.0], [4.0, 0.0], office_door),
                ],
                "regions": [{"id": "bedroom", "type": "Other", "walls": [1, 2, 3, 4]},
                            {"id": "office", "type": "Other", "walls": [6, 7, 8, 9]}],
            },
            "object": [
                // The bed against the bedroom's north wall facing south: its front (+y) turned
                // by 180 degrees.
                {"index": 0, "id": "bed_0", "modelId": "scenesmith.bed_0", "parentId": "", "parentIndex": -1,
                 "transform": {"data": z_up_transform(180.0, [2.0, 3.95, 0.0])}, "sdfPath": sdf_path(0)},
                // The desk against the office's east wall facing west (-x): +y turned by 90.
                {"index": 1, "id": "desk_0", "modelId": "scene-agent.desk_0", "parentId": "", "parentIndex": -1,
                 "transform": {"data": z_up_transform(90.0, [7.65, 2.5, 0.0])}, "sdfPath": sdf_path(1)},
                // The lamp on the desk (0.75 m high).
                {"index": 2, "id": "table_lamp_0", "modelId": "scenesmith.table_lamp_0", "parentId": "",
                 "parentIndex": -1, "transform": {"data": z_up_transform(90.0, [7.65, 3.0, 0.75])},
                 "sdfPath": format!("/home/user/outputs/scene_000/room_office/{}", sdf_path(2))},
                // Part of the building, not furniture: left out when read.
                {"index": 3, "id": "floor_bedroom", "modelId": "scenesmith.floor_bedroom", "isArchitecture": true,
                 "transform": {"data": z_up_transform(0.0, [0.0, 0.0, 0.0])}},
            ],
        },
    });
    out.json(&format!("{base}/combined_house/sceneeval_state.json"), &state)?;
    out.bytes(
        &format!("{base}/combined_house/house.blend"),
        b"BLENDER-v402 placeholder written by sceneeval-fixtures: sceneeval convert copies it as is\n",
    )?;
    out.bytes(
        &format!("{base}/floor_plans/floor_plan.sdf"),
        b"<?xml version=\"1.0\"?>\n<sdf version=\"1.7\">\n  <model name=\"floor_plan\"><static>true</static></model>\n</sdf>\n",
    )
}
