//! What a scene contains, as plain serializable values: its objects (id, model, category, box,
//! yaw, stated support type and functional sides) and its rooms with their walls and openings.
//! `sceneeval inspect --format json` prints these, `sceneeval report` draws its top views from
//! them, and the Python package returns them as dicts. With the feature `serde` they serialize.
//!
//! Lengths are metres, angles radians, coordinates world (z up; see `docs/conventions.md`).
//!
//! ```
//! use sceneeval_scene::inspect::SceneInfo;
//! use sceneeval_scene::{Category, RoomBuilder, Scene};
//! use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
//!
//! let scene = Scene::builder()
//!     .name("scene_0")
//!     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
//!         .door(0, [1.0, 1.9], [0.0, 2.1]))
//!     .add_box("bed", Category::new("bed"), Vector3::new(0.8, 1.0, 0.25),
//!              pose_from_yaw(Point3::new(2.0, 3.9, 0.25), 0.0))
//!     .build()
//!     .unwrap();
//! let info = SceneInfo::new(&scene);
//! assert_eq!(info.objects[0].id, "bed");
//! // Full size = twice the half extents.
//! assert_eq!(info.objects[0].size, [1.6, 2.0, 0.5]);
//! // Yaw 0: the bed's front faces world -y.
//! assert_eq!(info.objects[0].front, [0.0, -1.0, 0.0]);
//! assert_eq!(info.rooms[0].walls.len(), 4);
//! assert_eq!(info.rooms[0].walls[0].openings[0].kind, "door");
//! // A 4 x 5 m floor.
//! assert!((info.rooms[0].floor_area - 20.0).abs() < 1e-9);
//! ```

use sceneeval_geom::{Real, Side};

use crate::{Room, Scene, SceneObject, SupportType, Wall};

/// A scene's objects and rooms.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct SceneInfo<'a> {
    /// The scene's name, if it has one.
    pub scene: Option<&'a str>,
    /// Every object, in scene order.
    pub objects: Vec<ObjectInfo<'a>>,
    /// Every room.
    pub rooms: Vec<RoomInfo<'a>>,
}

/// One object.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ObjectInfo<'a> {
    /// The object's id.
    pub id: &'a str,
    /// The object's index in its scene file, if it has one.
    pub index: Option<i64>,
    /// The asset's model id (`PREFIX.ID`), if it has one.
    pub model_id: Option<&'a str>,
    /// The category, if known.
    pub category: Option<&'a str>,
    /// The description, if any.
    pub description: Option<&'a str>,
    /// Whether the object is a plain box (no asset mesh).
    pub is_box: bool,
    /// OBB centre, world coordinates.
    pub center: [Real; 3],
    /// OBB full size: width (x), depth (y), height (z) in the object frame.
    pub size: [Real; 3],
    /// Rotation about +z; 0 means the front faces world -y.
    pub yaw: Real,
    /// The direction the object's front faces, world coordinates (unit): its local -y.
    pub front: [Real; 3],
    /// The front the scene file declared for the object's asset in its own z-up frame
    /// (sceneState `objectFrontVector`) when it is not the model's `[0, -1, 0]`; the object
    /// was turned on reading so that `front` is right.
    pub asset_front: Option<[Real; 3]>,
    /// Object-frame scale baked into the mesh.
    pub scale: [Real; 3],
    /// The support type the scene states (`supportType`), if any.
    pub support_type: Option<SupportType>,
    /// The functional sides the scene states (`functionalSides`), if any.
    pub functional_sides: Option<&'a [Side]>,
}

/// One room.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct RoomInfo<'a> {
    /// The room's id.
    pub id: &'a str,
    /// The room type, if known.
    pub kind: Option<&'a str>,
    /// The floor's id.
    pub floor_id: &'a str,
    /// Height of the floor.
    pub floor_z: Real,
    /// Height of the ceiling, if the room has one.
    pub ceiling_z: Option<Real>,
    /// Floor area, square metres.
    pub floor_area: Real,
    /// The floor outline in the xy plane.
    pub floor: Vec<[Real; 2]>,
    /// The walls, in outline order.
    pub walls: Vec<WallInfo<'a>>,
}

/// One wall.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct WallInfo<'a> {
    /// The wall's id.
    pub id: &'a str,
    /// Start of the inner face, xy.
    pub start: [Real; 2],
    /// End of the inner face, xy.
    pub end: [Real; 2],
    /// Height of the wall's base.
    pub base_z: Real,
    /// Height above the base.
    pub height: Real,
    /// Thickness (the solid stands outside the room).
    pub thickness: Real,
    /// Length of the inner face.
    pub length: Real,
    /// Unit normal of the inner face, pointing into the room.
    pub inward_normal: [Real; 2],
    /// The wall's doors and windows.
    pub openings: Vec<OpeningInfo<'a>>,
}

/// One door or window.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct OpeningInfo<'a> {
    /// The opening's id.
    pub id: &'a str,
    /// `door` or `window`.
    pub kind: &'static str,
    /// Start and end along the wall, from its start point.
    pub along: [Real; 2],
    /// Bottom and top above the wall's base.
    pub height: [Real; 2],
}

impl<'a> SceneInfo<'a> {
    /// The objects and rooms of `scene`.
    pub fn new(scene: &'a Scene) -> Self {
        SceneInfo {
            scene: scene.name(),
            objects: scene.objects().iter().map(ObjectInfo::new).collect(),
            rooms: scene.rooms().iter().map(RoomInfo::new).collect(),
        }
    }
}

impl<'a> ObjectInfo<'a> {
    /// What `o` is and where.
    pub fn new(o: &'a SceneObject) -> Self {
        let obb = o.obb();
        let size = obb.extents();
        ObjectInfo {
            id: o.id().as_str(),
            index: o.index(),
            model_id: o.model_id(),
            category: o.category(),
            description: o.description(),
            is_box: o.box_half_extents().is_some(),
            center: [obb.center.x, obb.center.y, obb.center.z],
            size: [size.x, size.y, size.z],
            yaw: o.yaw(),
            front: {
                let f = obb.side_direction(Side::Front);
                [f.x, f.y, f.z]
            },
            asset_front: o.asset_front().map(|f| [f.x, f.y, f.z]),
            scale: [o.scale().x, o.scale().y, o.scale().z],
            support_type: o.support_type(),
            functional_sides: o.functional_sides(),
        }
    }
}

impl<'a> RoomInfo<'a> {
    /// The room `r` with its walls.
    pub fn new(r: &'a Room) -> Self {
        RoomInfo {
            id: r.id().as_str(),
            kind: r.kind(),
            floor_id: r.floor_id(),
            floor_z: r.floor_z(),
            ceiling_z: r.ceiling_z(),
            floor_area: r.floor().area(),
            floor: r.floor().points().iter().map(|p| [p.x, p.y]).collect(),
            walls: r.walls().iter().map(WallInfo::new).collect(),
        }
    }
}

impl<'a> WallInfo<'a> {
    /// The wall `w` with its openings.
    pub fn new(w: &'a Wall) -> Self {
        let n = w.inward_normal();
        WallInfo {
            id: w.id(),
            start: [w.start().x, w.start().y],
            end: [w.end().x, w.end().y],
            base_z: w.base_z(),
            height: w.height(),
            thickness: w.thickness(),
            length: w.length(),
            inward_normal: [n.x, n.y],
            openings: w
                .openings()
                .iter()
                .map(|o| OpeningInfo {
                    id: &o.id,
                    kind: o.kind.name(),
                    along: o.along,
                    height: o.height,
                })
                .collect(),
        }
    }
}
