//! Plausibility checks of one object or one pair at a time, for loops that move objects
//! (layout optimisers): the architecture is prepared once, each check borrows it and the
//! objects.

use sceneeval_geom::{Obb, Point2, Polygon2, Real};
use sceneeval_scene::{OpeningKind, Room, SceneObject};

use crate::clearance::{OpeningFrame, checked_sides};
use crate::contact::{Contact, contact, enters};
use crate::oob::{ClipScratch, OutOfBoundsParams, area_over_floor, in_bounds_ratio};
use crate::plane::{FloorPiece, floor_pieces};
use crate::{CollisionParams, OpeningClearanceParams, PlausibilityError};

/// The rooms of a scene prepared once for per-object and pairwise plausibility checks: the
/// floors as disjoint convex pieces (what the out-of-bounds metric clips against) and the
/// doors' clearance boxes. Objects are passed to each check, so a loop can move them
/// (`Scene::set_pose`) and ask again; nothing is prepared again, and with a reused
/// [`LayoutScratch`] nothing is allocated.
///
/// - **Is an object inside its room?** [`LayoutChecks::in_bounds_ratio`] and
///   [`LayoutChecks::is_out_of_bounds`]: exactly the out-of-bounds metric's numbers for the
///   object ([`crate::out_of_bounds`] shares their code).
/// - **Do two objects collide?** [`LayoutChecks::contact`]: for two box objects exactly (the
///   separating-axis theorem), with the penetration depth and its gradient with respect to
///   both boxes (`sceneeval_relations::grad::box_penetration`), colliding beyond the collision
///   metric's contact tolerance; with a mesh involved, whether the solids meet (the exact
///   mesh distance is 0, or one is inside the other), which is stricter than the collision
///   metric's verdict (it forgives contacts up to the tolerance deep, with a depth search that
///   allocates).
/// - **Does an object block a door?** [`LayoutChecks::blocks_door`]: whether its surface
///   enters the clearance box of a door (either side checked by the opening-clearance metric,
///   with its parameters), as that metric decides it for the object.
///
/// ```
/// use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
/// use sceneeval_plausibility::{LayoutChecks, OutOfBoundsParams};
/// use sceneeval_scene::{Category, RoomBuilder, Scene};
///
/// let mut scene = Scene::builder()
///     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0)))
///     .add_box("box", Category::new("box"), Vector3::repeat(0.5), pose_from_yaw(Point3::new(2.0, 2.0, 0.5), 0.0))
///     .build()
///     .unwrap();
/// let checks = LayoutChecks::new(scene.rooms(), &OutOfBoundsParams::default()).unwrap();
/// let mut scratch = checks.scratch();
/// let b = scene.object_index("box").unwrap();
/// assert_eq!(checks.in_bounds_ratio(&scene.objects()[b], &mut scratch), 1.0);
/// // Centred on the wall x = 4: the half beyond it, and half of the top and bottom, are out:
/// // (1 + 4 x 0.5) of 6 faces of 1 m^2 are over the floor.
/// scene.set_pose(b, pose_from_yaw(Point3::new(4.0, 2.0, 0.5), 0.0)).unwrap();
/// let r = checks.in_bounds_ratio(&scene.objects()[b], &mut scratch);
/// assert!((r - 3.0 / 6.0).abs() < 1e-3, "{r}");
/// assert!(checks.is_out_of_bounds(&scene.objects()[b], &mut scratch));
/// ```
#[derive(Debug, Clone)]
pub struct LayoutChecks {
    pieces: Vec<FloorPiece>,
    out_of_bounds: OutOfBoundsParams,
    /// The floors (outline and height) in room order, for the floor under an object.
    floors: Vec<(Polygon2, Real)>,
    /// The doors' clearance boxes (both sides where the metric checks both).
    doors: Vec<Obb>,
    clearance: OpeningClearanceParams,
    /// Penetration depth beyond which two box objects collide.
    contact_tolerance_m: Real,
}

/// Buffers a [`LayoutChecks`] check clips polygons in; keep one across calls. One made by
/// [`LayoutChecks::scratch`] is large enough for any clip, so checks never allocate; a default
/// one grows on the first calls.
#[derive(Debug, Default)]
pub struct LayoutScratch {
    clip: ClipScratch,
}

impl LayoutChecks {
    /// Prepares `rooms` for the checks, with the out-of-bounds metric's parameters.
    ///
    /// # Errors
    /// [`PlausibilityError::InvalidParameter`] for parameters the metric rejects.
    /// The collision and opening-clearance parameters are the metrics' defaults
    /// ([`LayoutChecks::with_collision`] and [`LayoutChecks::with_clearance`] change them).
    pub fn new(rooms: &[Room], out_of_bounds: &OutOfBoundsParams) -> Result<Self, PlausibilityError> {
        out_of_bounds.validate()?;
        let floors: Vec<_> = rooms.iter().map(|r| (r.floor(), r.floor_z())).collect();
        let clearance = OpeningClearanceParams::default();
        Ok(LayoutChecks {
            pieces: floor_pieces(&floors),
            out_of_bounds: out_of_bounds.clone(),
            floors: rooms.iter().map(|r| (r.floor().clone(), r.floor_z())).collect(),
            doors: door_boxes(rooms, &clearance),
            clearance,
            contact_tolerance_m: CollisionParams::default().contact_tolerance_m,
        })
    }

    /// These checks with the collision metric's `params` (its contact tolerance).
    ///
    /// # Errors
    /// [`PlausibilityError::InvalidParameter`] for parameters the metric rejects.
    pub fn with_collision(mut self, params: &CollisionParams) -> Result<Self, PlausibilityError> {
        params.validate()?;
        self.contact_tolerance_m = params.contact_tolerance_m;
        Ok(self)
    }

    /// These checks with the opening-clearance metric's `params` (depths, sides, touch
    /// tolerance, walkable height), given the same `rooms` as [`LayoutChecks::new`].
    ///
    /// # Errors
    /// [`PlausibilityError::InvalidParameter`] for parameters the metric rejects.
    pub fn with_clearance(
        mut self,
        rooms: &[Room],
        params: &OpeningClearanceParams,
    ) -> Result<Self, PlausibilityError> {
        params.validate()?;
        self.doors = door_boxes(rooms, params);
        self.clearance = params.clone();
        Ok(self)
    }

    /// A scratch buffer large enough for every clip these checks make (a triangle clipped by a
    /// floor plane and a floor piece's edges), so that no check allocates.
    pub fn scratch(&self) -> LayoutScratch {
        let most = 4 + self.pieces.iter().map(|p| p.poly.len()).max().unwrap_or(0);
        LayoutScratch {
            clip: ClipScratch::with_capacity(most),
        }
    }

    /// The out-of-bounds metric's in-bounds ratio of `object`: the share of its surface area
    /// over a floor and not below it, in [0, 1] (see [`crate::out_of_bounds`]).
    pub fn in_bounds_ratio(&self, object: &SceneObject, scratch: &mut LayoutScratch) -> Real {
        let over = area_over_floor(object, self.pieces.iter(), &self.out_of_bounds, &mut scratch.clip);
        in_bounds_ratio(object.mesh().surface_area(), over)
    }

    /// Whether the out-of-bounds metric counts `object` as out of bounds (its in-bounds ratio
    /// below [`OutOfBoundsParams::threshold`]).
    pub fn is_out_of_bounds(&self, object: &SceneObject, scratch: &mut LayoutScratch) -> bool {
        self.in_bounds_ratio(object, scratch) < self.out_of_bounds.threshold
    }

    /// Whether `a` and `b` collide, with the penetration depth and its gradient for two box
    /// objects (see [`Contact`] and the type's docs). Allocation free. Which pairs to check is
    /// the caller's choice (the collision metric leaves floor coverings out by default).
    ///
    /// ```
    /// use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
    /// use sceneeval_plausibility::{LayoutChecks, OutOfBoundsParams};
    /// use sceneeval_scene::{Category, RoomBuilder, Scene};
    ///
    /// let scene = Scene::builder()
    ///     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0)))
    ///     .add_box("bed", Category::new("bed"), Vector3::new(0.8, 1.0, 0.3), pose_from_yaw(Point3::new(2.0, 4.0, 0.3), 0.0))
    ///     // 2 cm into the bed's -x side.
    ///     .add_box("stand", Category::new("nightstand"), Vector3::new(0.25, 0.2, 0.3), pose_from_yaw(Point3::new(0.97, 4.0, 0.3), 0.0))
    ///     .build()
    ///     .unwrap();
    /// let checks = LayoutChecks::new(scene.rooms(), &OutOfBoundsParams::default()).unwrap();
    /// let c = checks.contact(&scene.objects()[1], &scene.objects()[0]);
    /// assert!(c.colliding);
    /// assert!((c.depth.unwrap() - 0.02).abs() < 1e-12);
    /// // Moving the stand by dx along -x reduces the depth by dx.
    /// let (d_stand, _) = c.gradient.unwrap();
    /// assert!((d_stand.center.x - 1.0).abs() < 1e-12);
    /// ```
    pub fn contact(&self, a: &SceneObject, b: &SceneObject) -> Contact {
        contact(a, b, self.contact_tolerance_m)
    }

    /// Whether `object` blocks a door: it rises above the walkable height over the floor under
    /// it and its surface enters a door's clearance box (the box of the opening-clearance
    /// metric, on each side the metric checks), as that metric decides it for the object.
    /// Allocation free.
    pub fn blocks_door(&self, object: &SceneObject) -> bool {
        if !self.clearance.check_doors {
            return false;
        }
        let aabb = object.world_aabb();
        let c = aabb.center();
        let centre = Point2::new(c.x, c.y);
        let lowest = self.floors.iter().map(|f| f.1).reduce(Real::min).unwrap_or(0.0);
        let floor_z = self
            .floors
            .iter()
            .find(|(outline, _)| outline.contains_point(&centre))
            .map_or(lowest, |f| f.1);
        if aabb.max.z - floor_z <= self.clearance.walkable_height_m {
            return false;
        }
        self.doors.iter().any(|door| enters(object, door))
    }
}

/// The clearance boxes of every door of `rooms` the opening-clearance metric checks with
/// `params`: the room side, and the far side when a floor lies there.
fn door_boxes(rooms: &[Room], params: &OpeningClearanceParams) -> Vec<Obb> {
    let over_floor = |p: &Point2| rooms.iter().any(|r| r.floor().contains_point(p));
    let mut out = Vec::new();
    for room in rooms {
        for wall in room.walls() {
            for o in wall.openings().iter().filter(|o| o.kind == OpeningKind::Door) {
                let (depth, sides) = checked_sides(wall, o, params, over_floor);
                for side in sides.into_iter().flatten() {
                    let frame = OpeningFrame::new(wall, o, side, depth, params.touch_tolerance_m);
                    out.extend(frame.shrunk_obb());
                }
            }
        }
    }
    out
}
