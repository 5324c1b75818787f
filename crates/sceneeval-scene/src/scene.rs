use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use sceneeval_geom::{Aabb, Isometry3, Mesh, Point2, Vector3};

use crate::{Category, ObjectId, Opening, Room, RoomBuilder, SceneError, SceneObject, Wall};

/// A scene: objects and the rooms they stand in.
///
/// Object ids, room ids and wall ids are unique (checked on construction); objects keep the
/// order they were given in, which is the order every per-object result reports them.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    name: Option<String>,
    objects: Vec<SceneObject>,
    rooms: Vec<Room>,
    lookup: HashMap<ObjectId, usize>,
}

impl Scene {
    /// A scene from its parts.
    ///
    /// # Errors
    /// [`SceneError::DuplicateObjectId`], [`SceneError::DuplicateRoomId`] or
    /// [`SceneError::DuplicateWallId`].
    pub fn new(
        name: Option<String>,
        objects: Vec<SceneObject>,
        rooms: Vec<Room>,
    ) -> Result<Self, SceneError> {
        let mut lookup = HashMap::with_capacity(objects.len());
        for (i, o) in objects.iter().enumerate() {
            if lookup.insert(o.id().clone(), i).is_some() {
                return Err(SceneError::DuplicateObjectId {
                    id: o.id().to_string(),
                });
            }
        }
        let mut room_ids = HashSet::new();
        let mut wall_ids: HashMap<&str, &Wall> = HashMap::new();
        for r in &rooms {
            if !room_ids.insert(r.id().as_str()) {
                return Err(SceneError::DuplicateRoomId {
                    id: r.id().to_string(),
                });
            }
            for w in r.walls() {
                if let Some(first) = wall_ids.insert(w.id(), w) {
                    return Err(SceneError::DuplicateWallId {
                        id: w.id().to_owned(),
                        first: Box::new(first.element().clone()),
                        second: Box::new(w.element().clone()),
                    });
                }
            }
        }
        Ok(Scene {
            name,
            objects,
            rooms,
            lookup,
        })
    }

    /// A builder for assembling a scene in code.
    pub fn builder() -> SceneBuilder {
        SceneBuilder::default()
    }

    /// The scene's name (for files read from disk, the file stem, e.g. `scene_12`; the
    /// benchmark id, `12`, is derived from it by `sceneeval_results::SceneName`).
    #[inline]
    pub fn name(&self) -> Option<&str> {
        self.name.as_deref()
    }

    /// The scene's name: [`Scene::name`], its name now (`scene_id` means the benchmark id
    /// everywhere else).
    #[deprecated(
        note = "renamed `Scene::name`: `scene_id` means the benchmark id (`12`), the name is the file stem (`scene_12`)"
    )]
    #[inline]
    pub fn id(&self) -> Option<&str> {
        self.name()
    }

    /// The objects, in order.
    #[inline]
    pub fn objects(&self) -> &[SceneObject] {
        &self.objects
    }

    /// The object with this id.
    #[inline]
    pub fn object(&self, id: &str) -> Option<&SceneObject> {
        self.lookup.get(id).map(|&i| &self.objects[i])
    }

    /// The position of the object with this id in [`Scene::objects`].
    #[inline]
    pub fn object_index(&self, id: &str) -> Option<usize> {
        self.lookup.get(id).copied()
    }

    /// The object at position `index` of [`Scene::objects`].
    #[inline]
    pub fn object_at(&self, index: usize) -> Option<&SceneObject> {
        self.objects.get(index)
    }

    /// Moves an object, found by id (a hash lookup; no allocation).
    ///
    /// # Errors
    /// [`SceneError::UnknownObject`], [`SceneError::NonFinitePose`].
    pub fn set_object_pose(&mut self, id: &str, pose: Isometry3) -> Result<(), SceneError> {
        let i = self
            .object_index(id)
            .ok_or_else(|| SceneError::UnknownObject { id: id.to_owned() })?;
        self.objects[i].set_pose(pose)
    }

    /// Moves the object at position `index` (see [`Scene::object_index`]): the loop of a layout
    /// optimiser. Only the object's pose and cached boxes change; the rooms, prepared when they
    /// were built, are untouched, and nothing is allocated.
    ///
    /// ```
    /// use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
    /// use sceneeval_scene::{Category, RoomBuilder, Scene};
    ///
    /// let mut scene = Scene::builder()
    ///     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0)))
    ///     .add_box("desk", Category::new("desk"), Vector3::new(0.6, 0.3, 0.375), pose_from_yaw(Point3::new(2.0, 4.7, 0.375), 0.0))
    ///     .build()
    ///     .unwrap();
    /// let desk = scene.object_index("desk").unwrap();
    /// scene.set_pose(desk, pose_from_yaw(Point3::new(1.0, 4.7, 0.375), 0.0)).unwrap();
    /// assert_eq!(scene.object_at(desk).unwrap().obb().center, Point3::new(1.0, 4.7, 0.375));
    /// ```
    ///
    /// # Errors
    /// [`SceneError::NoSuchObject`], [`SceneError::NonFinitePose`].
    pub fn set_pose(&mut self, index: usize, pose: Isometry3) -> Result<(), SceneError> {
        let count = self.objects.len();
        self.objects
            .get_mut(index)
            .ok_or(SceneError::NoSuchObject { index, count })?
            .set_pose(pose)
    }

    /// The rooms, in order.
    #[inline]
    pub fn rooms(&self) -> &[Room] {
        &self.rooms
    }

    /// The room with this id.
    pub fn room(&self, id: &str) -> Option<&Room> {
        self.rooms.iter().find(|r| r.id().as_str() == id)
    }

    /// Every wall with its room.
    pub fn walls(&self) -> impl Iterator<Item = (&Room, &Wall)> + '_ {
        self.rooms
            .iter()
            .flat_map(|r| r.walls().iter().map(move |w| (r, w)))
    }

    /// Every door and window with its wall and room.
    pub fn openings(&self) -> impl Iterator<Item = (&Room, &Wall, &Opening)> + '_ {
        self.walls()
            .flat_map(|(r, w)| w.openings().iter().map(move |o| (r, w, o)))
    }

    /// The first room whose floor outline contains the plan point `p`.
    pub fn room_at(&self, p: &Point2) -> Option<&Room> {
        self.rooms.iter().find(|r| r.floor().contains_point(p))
    }

    /// Whether the plan point `p` lies over any room's floor.
    pub fn is_over_floor(&self, p: &Point2) -> bool {
        self.room_at(p).is_some()
    }

    /// The bounds of every object and every floor, or `None` for an empty scene.
    pub fn bounds(&self) -> Option<Aabb> {
        let objects = self.objects.iter().map(|o| *o.world_aabb());
        let floors = self.rooms.iter().map(Room::floor_aabb);
        objects.chain(floors).reduce(|a, b| a.union(&b))
    }
}

/// Assembles a [`Scene`] in code. Fallible steps are deferred: the first error is returned by
/// [`SceneBuilder::build`].
///
/// ```
/// use sceneeval_scene::{Category, RoomBuilder, Scene};
/// use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
///
/// let scene = Scene::builder()
///     .name("bedroom")
///     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
///         .door(0, [1.0, 1.9], [0.0, 2.1]))
///     // Half extents: a 1.6 x 2.0 x 0.6 m bed and a 0.5 x 0.4 x 0.6 m nightstand.
///     .add_box("bed", Category::new("bed"), Vector3::new(0.8, 1.0, 0.3),
///              pose_from_yaw(Point3::new(2.0, 3.9, 0.3), std::f64::consts::PI))
///     .add_box("nightstand", Category::new("nightstand"), Vector3::new(0.25, 0.2, 0.3),
///              pose_from_yaw(Point3::new(0.6, 4.7, 0.3), 0.0))
///     .build()
///     .unwrap();
/// assert_eq!(scene.objects().len(), 2);
/// assert_eq!(scene.object("bed").unwrap().category(), Some("bed"));
/// ```
#[derive(Debug, Default)]
pub struct SceneBuilder {
    name: Option<String>,
    objects: Vec<SceneObject>,
    rooms: Vec<Room>,
    error: Option<SceneError>,
}

impl SceneBuilder {
    /// Sets the scene's name.
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.name = Some(name.into());
        self
    }

    /// Sets the scene's name: [`SceneBuilder::name`], its name now.
    #[deprecated(
        note = "renamed `SceneBuilder::name`: `scene_id` means the benchmark id, the name is the file stem"
    )]
    pub fn id(self, name: impl Into<String>) -> Self {
        self.name(name)
    }

    /// Adds an object.
    pub fn object(mut self, object: SceneObject) -> Self {
        self.objects.push(object);
        self
    }

    /// Adds a room.
    pub fn room(mut self, room: Room) -> Self {
        self.rooms.push(room);
        self
    }

    /// Builds and adds a room.
    pub fn room_builder(self, room: RoomBuilder) -> Self {
        let r = room.build();
        self.push(r, SceneBuilder::room)
    }

    /// Adds a solid box object with a category: half extents and pose as for
    /// [`SceneObject::new_box`].
    pub fn add_box(
        self,
        id: impl Into<ObjectId>,
        category: Category,
        half_extents: Vector3,
        pose: Isometry3,
    ) -> Self {
        let o = SceneObject::new_box(id, half_extents, pose).map(|o| o.with_category(category));
        self.push(o, SceneBuilder::object)
    }

    /// Adds a mesh object with a category (see [`SceneObject::from_mesh`]).
    pub fn add_mesh(
        self,
        id: impl Into<ObjectId>,
        category: Category,
        mesh: Arc<Mesh>,
        pose: Isometry3,
    ) -> Self {
        let o = SceneObject::from_mesh(id, mesh, pose).map(|o| o.with_category(category));
        self.push(o, SceneBuilder::object)
    }

    fn push<T>(mut self, item: Result<T, SceneError>, add: fn(Self, T) -> Self) -> Self {
        match item {
            Ok(item) => add(self, item),
            Err(e) => {
                self.error.get_or_insert(e);
                self
            }
        }
    }

    /// The scene, or the first error met while building it.
    pub fn build(self) -> Result<Scene, SceneError> {
        if let Some(e) = self.error {
            return Err(e);
        }
        Scene::new(self.name, self.objects, self.rooms)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::Point3;
    use sceneeval_geom::conventions::pose_from_yaw;

    fn two_rooms() -> SceneBuilder {
        Scene::builder()
            .room_builder(RoomBuilder::rectangle(
                "a",
                Point2::new(0.0, 0.0),
                Point2::new(4.0, 4.0),
            ))
            .room_builder(RoomBuilder::rectangle(
                "b",
                Point2::new(4.0, 0.0),
                Point2::new(7.0, 4.0),
            ))
    }

    #[test]
    fn shared_boundary_walls_face_their_own_rooms() {
        let scene = two_rooms().build().unwrap();
        // Room a's wall 1 lies on x = 4 and faces -x; room b's wall 3 lies on x = 4 and faces +x.
        let a1 = &scene.room("a").unwrap().walls()[1];
        let b3 = &scene.room("b").unwrap().walls()[3];
        assert_eq!(a1.inward_normal(), sceneeval_geom::Vector2::new(-1.0, 0.0));
        assert_eq!(b3.inward_normal(), sceneeval_geom::Vector2::new(1.0, 0.0));
        assert_eq!(scene.walls().count(), 8);
        assert_eq!(scene.room_at(&Point2::new(5.0, 1.0)).unwrap().id().as_str(), "b");
        assert!(!scene.is_over_floor(&Point2::new(8.0, 1.0)));
    }

    #[test]
    fn duplicate_ids_are_rejected() {
        let dup = two_rooms()
            .add_box(
                "x",
                Category::new("box"),
                Vector3::repeat(0.5),
                pose_from_yaw(Point3::origin(), 0.0),
            )
            .add_box(
                "x",
                Category::new("box"),
                Vector3::repeat(0.5),
                pose_from_yaw(Point3::origin(), 0.0),
            )
            .build();
        assert_eq!(dup.unwrap_err(), SceneError::DuplicateObjectId { id: "x".into() });
        let dup_room = two_rooms()
            .room_builder(RoomBuilder::rectangle(
                "a",
                Point2::new(9.0, 0.0),
                Point2::new(10.0, 1.0),
            ))
            .build();
        assert!(matches!(dup_room, Err(SceneError::DuplicateRoomId { .. })));
    }

    #[test]
    fn builder_reports_first_error_and_lookups_work() {
        let err = Scene::builder()
            .add_box(
                "bad",
                Category::new("box"),
                Vector3::new(0.5, -0.5, 0.5),
                pose_from_yaw(Point3::origin(), 0.0),
            )
            .add_box(
                "ok",
                Category::new("box"),
                Vector3::repeat(0.5),
                pose_from_yaw(Point3::origin(), f64::NAN),
            )
            .build()
            .unwrap_err();
        assert!(matches!(err, SceneError::Geometry { .. }), "{err}");
        let mut scene = two_rooms()
            .add_box(
                "t",
                Category::new("table"),
                Vector3::new(0.5, 0.5, 0.4),
                pose_from_yaw(Point3::new(1.0, 1.0, 0.4), 0.0),
            )
            .build()
            .unwrap();
        assert_eq!(scene.object_index("t"), Some(0));
        scene
            .set_object_pose("t", Isometry3::translation(2.0, 2.0, 0.4))
            .unwrap();
        assert!((scene.object("t").unwrap().obb().center - Point3::new(2.0, 2.0, 0.4)).norm() < 1e-12);
        assert!(matches!(
            scene.set_object_pose("nope", Isometry3::identity()),
            Err(SceneError::UnknownObject { .. })
        ));
        let b = scene.bounds().unwrap();
        assert_eq!(b.min, Point3::new(0.0, 0.0, 0.0));
        assert_eq!(b.max.x, 7.0);
    }
}
