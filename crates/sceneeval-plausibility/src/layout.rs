//! Plausibility checks of one object at a time, for loops that move objects (layout
//! optimisers): the architecture is prepared once, each check borrows it and the object.

use sceneeval_geom::Real;
use sceneeval_scene::{Room, SceneObject};

use crate::PlausibilityError;
use crate::oob::{ClipScratch, OutOfBoundsParams, area_over_floor, in_bounds_ratio};
use crate::plane::{FloorPiece, floor_pieces};

/// The rooms of a scene prepared once for per-object plausibility checks: the floors as
/// disjoint convex pieces (what the out-of-bounds metric clips against). Objects are passed to
/// each check, so a loop can move them (`Scene::set_pose`) and ask again; nothing is prepared
/// again, and with a reused [`LayoutScratch`] nothing is allocated.
///
/// The checks give exactly the numbers the metrics give for the same object
/// ([`crate::out_of_bounds`] shares their code).
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
    pub fn new(rooms: &[Room], out_of_bounds: &OutOfBoundsParams) -> Result<Self, PlausibilityError> {
        out_of_bounds.validate()?;
        let floors: Vec<_> = rooms.iter().map(|r| (r.floor(), r.floor_z())).collect();
        Ok(LayoutChecks {
            pieces: floor_pieces(&floors),
            out_of_bounds: out_of_bounds.clone(),
        })
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
}
