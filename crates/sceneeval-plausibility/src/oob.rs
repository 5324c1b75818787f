//! Out-of-bounds (OOB): how much of each object lies over a floor.

use rayon::prelude::*;
use sceneeval_geom::{Point2, Point3, Real};
use sceneeval_scene::{ObjectId, Scene, SceneObject};
use serde::{Deserialize, Serialize};

use crate::accessibility::scene_floor_pieces;
use crate::error::{check_non_negative, check_range};
use crate::index::{BoxIndex, WorkCounter, flat, grown};
use crate::plane::{FloorPiece, area3, boxes_overlap, clip_half_space_into};
use crate::{Deadline, PlausibilityError};

/// Parameters of the out-of-bounds metric (reference yaml `OutOfBoundMetric`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct OutOfBoundsParams {
    /// An object is out of bounds when less than this share of its surface lies over a floor
    /// (reference `threshold`, 0.99). Range: `[0, 1]`.
    pub threshold: Real,
    /// Surface lower than this below a floor still counts as over it, metres (default 0.005,
    /// the collision contact tolerance; the reference's floor slab is 1 mm thick). Range:
    /// finite, `>= 0`.
    pub below_floor_tolerance_m: Real,
    /// Surface at most this far outside the outline of the floors, horizontally, still counts as
    /// over them, metres (default 0.001). Without it an object standing flush against a wall
    /// loses its whole back face: float32 asset coordinates and rotations put that face a few
    /// 1e-8 m beyond the floor's edge. Edges between two floors never move. Not in the
    /// reference, whose random rays decide such faces by chance. Range: finite, `>= 0`.
    pub boundary_tolerance_m: Real,
}

impl Default for OutOfBoundsParams {
    fn default() -> Self {
        OutOfBoundsParams {
            threshold: 0.99,
            below_floor_tolerance_m: 0.005,
            boundary_tolerance_m: 0.001,
        }
    }
}

impl OutOfBoundsParams {
    pub(crate) fn validate(&self) -> Result<(), PlausibilityError> {
        check_non_negative(
            "out_of_bounds",
            "below_floor_tolerance_m",
            self.below_floor_tolerance_m,
            false,
        )?;
        check_non_negative(
            "out_of_bounds",
            "boundary_tolerance_m",
            self.boundary_tolerance_m,
            false,
        )?;
        check_range(
            "out_of_bounds",
            "threshold",
            self.threshold,
            [0.0, 1.0],
            "must lie in [0, 1]",
        )
    }
}

/// Out-of-bounds evidence of one object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectBounds {
    /// The object.
    pub id: ObjectId,
    /// Surface area of its mesh, square metres.
    pub surface_area: Real,
    /// Surface area lying over a floor (and not below it), square metres.
    pub area_over_floor: Real,
    /// `area_over_floor / surface_area`, in [0, 1].
    pub ratio_in_bounds: Real,
    /// Whether the ratio is below the threshold.
    pub out_of_bounds: bool,
}

/// The out-of-bounds metric of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OutOfBoundsReport {
    /// One entry per object, in scene order.
    pub objects: Vec<ObjectBounds>,
    /// Objects out of bounds.
    pub num_out: usize,
    /// **OOB**: share of objects out of bounds; `None` for a scene without objects.
    pub oob: Option<Real>,
}

/// Computes the out-of-bounds metric.
///
/// The reference casts rays straight down from random surface samples and counts those that
/// hit a floor; we compute that ratio's expectation exactly. Each triangle of the world mesh
/// is clipped against the vertical prism over each convex piece of the union of floors and
/// against the half-space above that floor (less [`OutOfBoundsParams::below_floor_tolerance_m`]),
/// the prism's outer walls moved out by [`OutOfBoundsParams::boundary_tolerance_m`];
/// the clipped areas (in 3-D, so vertical faces count by how much of them stands over a floor)
/// summed over the mesh, divided by its surface area, give the in-bounds ratio. Floors that
/// overlap in plan are counted once (the earlier room's floor height applies where they
/// overlap); surface below the floor it stands over is out of bounds, as in the reference.
///
/// # Errors
/// [`PlausibilityError::InvalidParameter`] for a threshold outside [0, 1] or a negative
/// tolerance.
pub fn out_of_bounds(
    scene: &Scene,
    params: &OutOfBoundsParams,
) -> Result<OutOfBoundsReport, PlausibilityError> {
    let pieces = scene_floor_pieces(scene);
    out_of_bounds_with(scene, params, &pieces, &Deadline::none())
}

pub(crate) fn out_of_bounds_with(
    scene: &Scene,
    params: &OutOfBoundsParams,
    pieces: &[FloorPiece],
    deadline: &Deadline,
) -> Result<OutOfBoundsReport, PlausibilityError> {
    let work = WorkCounter::default();
    out_of_bounds_counted(scene, params, pieces, deadline, &work)
}

/// [`out_of_bounds_with`], counting the work of its spatial-index queries into `work`.
fn out_of_bounds_counted(
    scene: &Scene,
    params: &OutOfBoundsParams,
    pieces: &[FloorPiece],
    deadline: &Deadline,
    work: &WorkCounter,
) -> Result<OutOfBoundsReport, PlausibilityError> {
    params.validate()?;
    // The floor pieces near an object come from an index over their boxes (grown by the
    // boundary tolerance), so large, finely triangulated floors cost `log` per object.
    let margin = params.boundary_tolerance_m;
    let index = BoxIndex::new(
        &pieces
            .iter()
            .map(|p| flat(&grown(&p.bounds, margin)))
            .collect::<Vec<_>>(),
    );
    let objects: Vec<ObjectBounds> = scene
        .objects()
        .par_iter()
        .map_init(ClipScratch::default, |scratch, o| {
            deadline.check("out_of_bounds")?;
            let surface_area = o.mesh().surface_area();
            let b = o.world_aabb();
            let near = index.query_flat(
                &(Point2::new(b.min.x, b.min.y), Point2::new(b.max.x, b.max.y)),
                work,
            );
            let over = area_over_floor(o, near.iter().map(|&k| &pieces[k]), params, scratch);
            let ratio = in_bounds_ratio(surface_area, over);
            Ok(ObjectBounds {
                id: o.id().clone(),
                surface_area,
                area_over_floor: over,
                ratio_in_bounds: ratio,
                out_of_bounds: ratio < params.threshold,
            })
        })
        .collect::<Result<_, PlausibilityError>>()?;
    let num_out = objects.iter().filter(|o| o.out_of_bounds).count();
    Ok(OutOfBoundsReport {
        oob: (!objects.is_empty()).then(|| num_out as Real / objects.len() as Real),
        objects,
        num_out,
    })
}

/// The share of a surface of area `surface_area` that `over` covers, in [0, 1] (0 for an
/// object without surface).
pub(crate) fn in_bounds_ratio(surface_area: Real, over: Real) -> Real {
    if surface_area > 0.0 {
        (over / surface_area).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Two polygon buffers reused across clips: after they have grown to the largest polygon met,
/// [`area_over_floor`] allocates nothing.
#[derive(Debug, Default)]
pub(crate) struct ClipScratch {
    a: Vec<Point3>,
    b: Vec<Point3>,
}

impl ClipScratch {
    /// Buffers that hold `n` points without growing.
    pub(crate) fn with_capacity(n: usize) -> Self {
        ClipScratch {
            a: Vec::with_capacity(n),
            b: Vec::with_capacity(n),
        }
    }
}

/// The surface area of `o`'s world mesh lying over a floor piece and above its floor (less
/// `tol`), the pieces' outer edges moved out by `margin` (see [`out_of_bounds`]). `pieces`
/// may be all floor pieces or only those an index found near the object.
pub(crate) fn area_over_floor<'p>(
    o: &SceneObject,
    pieces: impl Iterator<Item = &'p FloorPiece> + Clone,
    params: &OutOfBoundsParams,
    scratch: &mut ClipScratch,
) -> Real {
    let (tol, margin) = (params.below_floor_tolerance_m, params.boundary_tolerance_m);
    let aabb = o.world_aabb();
    let ob = (
        Point2::new(aabb.min.x, aabb.min.y),
        Point2::new(aabb.max.x, aabb.max.y),
    );
    let grow = |b: &(Point2, Point2)| grown(b, margin);
    let near = || pieces.clone().filter(|p| boxes_overlap(&grow(&p.bounds), &ob));
    if near().next().is_none() {
        return 0.0;
    }
    // Whole object over one piece and above its floor.
    let corners = [
        ob.0,
        Point2::new(ob.1.x, ob.0.y),
        ob.1,
        Point2::new(ob.0.x, ob.1.y),
    ];
    if near().any(|p| aabb.min.z >= p.floor_z - tol && corners.iter().all(|c| p.contains(c, margin))) {
        return o.mesh().surface_area();
    }
    let (mesh, pose) = (o.mesh(), o.pose());
    let vertices = mesh.vertices();
    let mut total = 0.0;
    for t in mesh.triangles() {
        let tri = t.map(|i| pose * vertices[i as usize]);
        let full = area3(&tri);
        let xy = tri.map(|p| Point2::new(p.x, p.y));
        let tb = (xy[0].inf(&xy[1]).inf(&xy[2]), xy[0].sup(&xy[1]).sup(&xy[2]));
        let mut covered = 0.0;
        for p in near().filter(|p| boxes_overlap(&grow(&p.bounds), &tb)) {
            let low = p.floor_z - tol;
            if tri.iter().all(|v| v.z >= low) && xy.iter().all(|c| p.contains(c, margin)) {
                covered += full;
                continue;
            }
            let ClipScratch { a, b } = scratch;
            clip_half_space_into(&tri, |v| v.z - low, a);
            for k in 0..p.poly.len() {
                if a.len() < 3 {
                    break;
                }
                clip_half_space_into(a, |v| p.inside_edge(k, &Point2::new(v.x, v.y), margin), b);
                std::mem::swap(a, b);
            }
            covered += area3(a);
        }
        total += covered.min(full);
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::conventions::pose_from_yaw;
    use sceneeval_geom::{Vector3, na::Point2 as P2};
    use sceneeval_scene::Category;
    use sceneeval_scene::RoomBuilder;

    fn ratio(scene: &Scene, params: &OutOfBoundsParams) -> Real {
        out_of_bounds(scene, params).unwrap().objects[0].ratio_in_bounds
    }

    fn room() -> RoomBuilder {
        RoomBuilder::rectangle("r", P2::new(0.0, 0.0), P2::new(4.0, 4.0))
    }

    #[test]
    fn floor_pieces_are_found_through_the_index() {
        // A k x k grid of 3 m rooms, a box in the middle of each: sixteen times the rooms
        // (and floor pieces) cost about log n box tests per object, where a scan would test
        // every piece.
        let mut per_object = Vec::new();
        for k in [8u32, 32] {
            let mut b = Scene::builder();
            for r in 0..k * k {
                let (x, y) = (3.0 * f64::from(r % k), 3.0 * f64::from(r / k));
                b = b
                    .room_builder(RoomBuilder::rectangle(
                        format!("r{r}"),
                        P2::new(x, y),
                        P2::new(x + 3.0, y + 3.0),
                    ))
                    .add_box(
                        format!("o{r}"),
                        Category::new("cabinet"),
                        Vector3::new(0.4, 0.3, 0.5),
                        pose_from_yaw(Point3::new(x + 1.5, y + 1.5, 0.5), 0.2),
                    );
            }
            let s = b.build().unwrap();
            let pieces = scene_floor_pieces(&s);
            let work = WorkCounter::default();
            let params = OutOfBoundsParams::default();
            let r = out_of_bounds_counted(&s, &params, &pieces, &Deadline::none(), &work).unwrap();
            assert_eq!(r.num_out, 0);
            let n = f64::from(k * k);
            let tests = work.total().box_tests as f64 / n;
            assert!(
                tests < pieces.len() as f64,
                "{tests} tests per object, {} pieces",
                pieces.len()
            );
            per_object.push(tests);
        }
        assert!(per_object[1] <= 2.0 * per_object[0], "{per_object:?}");
    }

    #[test]
    fn flush_against_a_wall_is_in_bounds() {
        // A unit cube whose back face lies 1e-8 m beyond the wall line x = 0, as float32 asset
        // coordinates put it: in bounds with the default 1 mm tolerance, out without it.
        let scene = Scene::builder()
            .room_builder(room())
            .add_box(
                "w",
                Category::new("wardrobe"),
                Vector3::repeat(0.5),
                pose_from_yaw(Point3::new(0.5 - 1e-8, 2.0, 0.5), 0.0),
            )
            .build()
            .unwrap();
        assert_eq!(ratio(&scene, &OutOfBoundsParams::default()), 1.0);
        let strict = OutOfBoundsParams {
            boundary_tolerance_m: 0.0,
            ..OutOfBoundsParams::default()
        };
        // The back face (1 of 6 square metres) and slivers of 1e-8 m on four faces are out.
        let r = ratio(&scene, &strict);
        assert!((r - (5.0 - 4e-8) / 6.0).abs() < 1e-9, "{r}");
    }

    #[test]
    fn protrusion_beyond_the_tolerance_counts() {
        // A unit cube reaching 5 cm through the wall at x = 0 (x in [-0.05, 0.95]). Outside the
        // 1 mm band: the back face (1 m^2) and a 0.049 m strip of the top, bottom and the two
        // y faces (4 x 0.049 m^2): ratio = (6 - 1 - 0.196) / 6.
        let scene = Scene::builder()
            .room_builder(room())
            .add_box(
                "w",
                Category::new("wardrobe"),
                Vector3::repeat(0.5),
                pose_from_yaw(Point3::new(0.45, 2.0, 0.5), 0.0),
            )
            .build()
            .unwrap();
        let r = ratio(&scene, &OutOfBoundsParams::default());
        assert!((r - 4.804 / 6.0).abs() < 1e-9, "{r}");
    }

    #[test]
    fn edges_between_floors_do_not_move() {
        // Two rooms sharing the line x = 4. A cube straddling it is over a floor everywhere,
        // counted once; with a large margin it still cannot exceed its own area, and one
        // reaching 0.5 m beyond the outer wall x = 7 loses exactly what lies beyond the margin.
        let two = || {
            Scene::builder()
                .room_builder(room())
                .room_builder(RoomBuilder::rectangle("s", P2::new(4.0, 0.0), P2::new(7.0, 4.0)))
        };
        let straddling = two()
            .add_box(
                "t",
                Category::new("table"),
                Vector3::repeat(0.5),
                pose_from_yaw(Point3::new(4.0, 2.0, 0.5), 0.0),
            )
            .build()
            .unwrap();
        let wide = OutOfBoundsParams {
            boundary_tolerance_m: 0.1,
            ..OutOfBoundsParams::default()
        };
        let report = out_of_bounds(&straddling, &wide).unwrap();
        assert!((report.objects[0].area_over_floor - 6.0).abs() < 1e-9);
        let poking = two()
            .add_box(
                "t",
                Category::new("table"),
                Vector3::repeat(0.5),
                pose_from_yaw(Point3::new(7.0, 2.0, 0.5), 0.0),
            )
            .build()
            .unwrap();
        // x in [6.5, 7.5]; with a 0.1 m margin, x in [7.1, 7.5] is out: the +x face (1) and a
        // 0.4 m strip of four faces (1.6): ratio = (6 - 2.6) / 6.
        let r = ratio(&poking, &wide);
        assert!((r - 3.4 / 6.0).abs() < 1e-9, "{r}");
    }
}
