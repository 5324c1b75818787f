//! Opening clearance (reference v1.1): objects blocking the space in front of doors and
//! windows.

use rayon::prelude::*;
use sceneeval_geom::{Aabb, Point2, Point3, Real, Vector2};
use sceneeval_scene::{ObjectId, OpeningKind, Room, Scene, Wall};
use serde::{Deserialize, Serialize};

use crate::error::{check_non_negative, check_range};
use crate::index::{BoxIndex, IndexWork, WorkCounter};
use crate::objects::{DEFAULT_WALKABLE_HEIGHT, ObjectInfo};
use crate::plane::{area3, clip_half_space};
use crate::raster::{Storage, check_raster, chord};
use crate::{Deadline, PlausibilityError};

/// Parameters of the opening-clearance metric (reference yaml `OpeningClearanceMetric`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct OpeningClearanceParams {
    /// Check doors (reference `door_check`, true).
    pub check_doors: bool,
    /// Check windows (reference `window_check`, true).
    pub check_windows: bool,
    /// Clearance depth of a door equals its width (reference `door_use_width_as_extrude`,
    /// true); otherwise [`OpeningClearanceParams::door_depth_m`].
    pub door_depth_from_width: bool,
    /// Clearance depth of a door in metres when not taken from its width (reference
    /// `door_extrude_distance`, 1.0). Range: finite, `>= 0`.
    pub door_depth_m: Real,
    /// Clearance depth of a window in metres (reference `window_front_extrude_distance`, 0.5).
    /// Range: finite, `>= 0`.
    pub window_depth_m: Real,
    /// Also check the far side of an opening when a floor lies there (a door between two
    /// rooms), probed [`OpeningClearanceParams::probe_offset_m`] beyond the wall's outer face
    /// (reference `*_room_side_only`: every side over a floor is checked). Default true.
    pub far_side_when_over_floor: bool,
    /// Distance of the floor probe beyond the wall, metres (reference
    /// `within_room_point_offset`, 0.1). Range: finite, `>= 0`.
    pub probe_offset_m: Real,
    /// Resolution of the occlusion map over the opening, pixels per metre (reference
    /// `map_pixel_per_meter`, 100). Range: `> 0` and at most
    /// [`OpeningClearanceParams::MAX_PIXELS_PER_METRE`] (1 mm pixels); an opening whose map
    /// would exceed the raster budget (16,777,216 pixels: a 4 x 4 m opening at 1 mm) fails its
    /// scene with [`PlausibilityError::RasterTooLarge`] before the map is allocated.
    pub pixels_per_m: Real,
    /// The clearance box is shrunk by this on every face before testing, metres (default
    /// 0.001), so that an object standing flush beside the opening or against the wall does
    /// not count as blocking. Range: finite, `>= 0`.
    pub touch_tolerance_m: Real,
    /// Objects whose top is at most this above their floor (rugs, doormats) do not block,
    /// metres. Default [`DEFAULT_WALKABLE_HEIGHT`] (5 cm); the reference lets every object
    /// block (0). Range: finite, `>= 0`.
    pub walkable_height_m: Real,
}

impl Default for OpeningClearanceParams {
    fn default() -> Self {
        OpeningClearanceParams {
            check_doors: true,
            check_windows: true,
            door_depth_from_width: true,
            door_depth_m: 1.0,
            window_depth_m: 0.5,
            far_side_when_over_floor: true,
            probe_offset_m: 0.1,
            pixels_per_m: 100.0,
            touch_tolerance_m: 0.001,
            walkable_height_m: DEFAULT_WALKABLE_HEIGHT,
        }
    }
}

impl OpeningClearanceParams {
    /// The largest `pixels_per_m`: 1000, millimetre pixels (the reference uses 100).
    pub const MAX_PIXELS_PER_METRE: Real = 1000.0;

    pub(crate) fn validate(&self) -> Result<(), PlausibilityError> {
        let m = "opening_clearance";
        check_non_negative(m, "door_depth_m", self.door_depth_m, false)?;
        check_non_negative(m, "window_depth_m", self.window_depth_m, false)?;
        check_non_negative(m, "probe_offset_m", self.probe_offset_m, false)?;
        check_non_negative(m, "pixels_per_m", self.pixels_per_m, true)?;
        check_range(
            m,
            "pixels_per_m",
            self.pixels_per_m,
            [0.0, Self::MAX_PIXELS_PER_METRE],
            "must be at most 1000 (millimetre pixels)",
        )?;
        check_non_negative(m, "touch_tolerance_m", self.touch_tolerance_m, false)?;
        check_non_negative(m, "walkable_height_m", self.walkable_height_m, false)
    }
}

/// Which side of its wall an opening is checked on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OpeningSide {
    /// The side of the wall's own room.
    Room,
    /// The other side (checked when a floor lies there).
    Far,
}

/// An object intruding into a clearance box.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BlockingObject {
    /// The object.
    pub id: ObjectId,
    /// Share of the opening's area its intruding part covers, seen along the wall normal.
    pub occluded_fraction: Real,
}

/// The clearance of one side of an opening.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SideClearance {
    /// The side.
    pub side: OpeningSide,
    /// Depth of the clearance box beyond the wall, metres.
    pub depth: Real,
    /// Objects whose geometry enters the box, in scene order.
    pub blocking: Vec<BlockingObject>,
    /// Share of the opening covered by any of them (union).
    pub occluded_fraction: Real,
    /// Whether any object enters the box.
    pub blocked: bool,
}

/// The clearance of one door or window.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OpeningClearance {
    /// The opening's id.
    pub opening: String,
    /// Door or window.
    pub kind: OpeningKind,
    /// Its wall.
    pub wall: String,
    /// The wall's room.
    pub room: String,
    /// Width along the wall, metres.
    pub width: Real,
    /// Height of the hole, metres.
    pub height: Real,
    /// The sides checked.
    pub sides: Vec<SideClearance>,
    /// Whether any side is blocked.
    pub blocked: bool,
}

/// The opening-clearance metric of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OpeningClearanceReport {
    /// One entry per checked opening, in scene order (rooms, walls, openings).
    pub openings: Vec<OpeningClearance>,
    /// Doors checked.
    pub num_doors: usize,
    /// Doors with a blocked side.
    pub doors_blocked: usize,
    /// Windows checked.
    pub num_windows: usize,
    /// Windows with a blocked side.
    pub windows_blocked: usize,
}

/// Computes the opening-clearance metric.
///
/// For each door and window, on its room's side (and on the far side when a floor lies there),
/// the clearance box spans the opening's width and height band and extends from the far face
/// of the hole through the wall to the clearance depth beyond the wall's face (doors: their
/// width; windows: 0.5 m; reference notes 7.6). Each object's triangles are clipped exactly
/// against the box (shrunk by [`OpeningClearanceParams::touch_tolerance_m`]); an object with any
/// clipped area blocks. The clipped parts are projected along the wall normal onto a raster of
/// the opening ([`OpeningClearanceParams::pixels_per_m`], sampled at pixel centres, pixels
/// tiling the opening exactly) for the occluded fractions per object and in union. The
/// reference keeps whole triangles that reach the box's depth even outside the opening's
/// rectangle; we clip them.
///
/// # Errors
/// [`PlausibilityError::InvalidParameter`] for bad parameters,
/// [`PlausibilityError::RasterTooLarge`] for an opening whose occlusion map would exceed the
/// raster budget.
pub fn opening_clearance(
    scene: &Scene,
    params: &OpeningClearanceParams,
) -> Result<OpeningClearanceReport, PlausibilityError> {
    let infos = crate::objects::object_infos(scene);
    opening_clearance_with(scene, params, &infos, &Deadline::none())
}

pub(crate) fn opening_clearance_with(
    scene: &Scene,
    params: &OpeningClearanceParams,
    infos: &[ObjectInfo],
    deadline: &Deadline,
) -> Result<OpeningClearanceReport, PlausibilityError> {
    opening_clearance_counted(scene, params, infos, deadline).map(|(report, _)| report)
}

/// [`opening_clearance_with`] and the work of its spatial-index queries.
fn opening_clearance_counted(
    scene: &Scene,
    params: &OpeningClearanceParams,
    infos: &[ObjectInfo],
    deadline: &Deadline,
) -> Result<(OpeningClearanceReport, IndexWork), PlausibilityError> {
    params.validate()?;
    let candidates = Candidates::new(scene, infos, params);
    let list: Vec<(&Room, &Wall, &sceneeval_scene::Opening)> = scene
        .openings()
        .filter(|(_, _, o)| match o.kind {
            OpeningKind::Door => params.check_doors,
            OpeningKind::Window => params.check_windows,
        })
        .collect();
    let openings: Vec<OpeningClearance> = list
        .par_iter()
        .map(|(room, wall, o)| {
            deadline.check("opening_clearance")?;
            let (depth, sides) = checked_sides(wall, o, params, |p| scene.is_over_floor(p));
            let sides: Vec<SideClearance> = sides
                .into_iter()
                .flatten()
                .map(|side| {
                    let frame = OpeningFrame::new(wall, o, side, depth, params.touch_tolerance_m);
                    side_clearance(scene, &candidates, &frame, side, depth, params, deadline)
                })
                .collect::<Result<_, _>>()?;
            Ok(OpeningClearance {
                opening: o.id.clone(),
                kind: o.kind,
                wall: wall.id().to_owned(),
                room: room.id().to_string(),
                width: o.width(),
                height: o.hole_height(),
                blocked: sides.iter().any(|s| s.blocked),
                sides,
            })
        })
        .collect::<Result<_, PlausibilityError>>()?;
    let count = |kind: OpeningKind, blocked: bool| {
        openings
            .iter()
            .filter(|o| o.kind == kind && (!blocked || o.blocked))
            .count()
    };
    let report = OpeningClearanceReport {
        num_doors: count(OpeningKind::Door, false),
        doors_blocked: count(OpeningKind::Door, true),
        num_windows: count(OpeningKind::Window, false),
        windows_blocked: count(OpeningKind::Window, true),
        openings,
    };
    Ok((report, candidates.work.total()))
}

/// The clearance depth of opening `o` of `wall` and the sides the metric checks: its room's,
/// and the far one when `over_floor` says a floor lies there.
pub(crate) fn checked_sides(
    wall: &Wall,
    o: &sceneeval_scene::Opening,
    params: &OpeningClearanceParams,
    over_floor: impl Fn(&Point2) -> bool,
) -> (Real, [Option<OpeningSide>; 2]) {
    let depth = match o.kind {
        OpeningKind::Door if params.door_depth_from_width => o.width(),
        OpeningKind::Door => params.door_depth_m,
        OpeningKind::Window => params.window_depth_m,
    };
    let mut far = None;
    if params.far_side_when_over_floor {
        let mid = wall.start() + wall.direction() * (0.5 * (o.along[0] + o.along[1]));
        let probe = mid - wall.inward_normal() * (wall.thickness() + params.probe_offset_m);
        if over_floor(&probe) {
            far = Some(OpeningSide::Far);
        }
    }
    (depth, [Some(OpeningSide::Room), far])
}

/// Coordinates of an opening's side: `u` along the wall from its start, `v` away from the
/// wall's inner face toward the checked side, `w` above the wall's base; and the box.
pub(crate) struct OpeningFrame {
    start: Point2,
    dir: Vector2,
    normal: Vector2,
    base_z: Real,
    /// Box `[u0, u1] x [v0, v1] x [w0, w1]` before shrinking.
    pub lo: [Real; 3],
    /// Upper corner of the box.
    pub hi: [Real; 3],
    shrink: Real,
}

impl OpeningFrame {
    pub(crate) fn new(
        wall: &Wall,
        o: &sceneeval_scene::Opening,
        side: OpeningSide,
        depth: Real,
        shrink: Real,
    ) -> Self {
        let t = wall.thickness();
        let (normal, v) = match side {
            OpeningSide::Room => (wall.inward_normal(), [-t, depth]),
            OpeningSide::Far => (-wall.inward_normal(), [0.0, t + depth]),
        };
        OpeningFrame {
            start: wall.start(),
            dir: wall.direction(),
            normal,
            base_z: wall.base_z(),
            lo: [o.along[0], v[0], o.height[0]],
            hi: [o.along[1], v[1], o.height[1]],
            shrink,
        }
    }

    /// The box the metric tests (shrunk by the touch tolerance on every face) as a world
    /// oriented box, or `None` when shrinking leaves nothing.
    pub(crate) fn shrunk_obb(&self) -> Option<sceneeval_geom::Obb> {
        let half = |k: usize| 0.5 * (self.hi[k] - self.lo[k]) - self.shrink;
        let mid = |k: usize| 0.5 * (self.lo[k] + self.hi[k]);
        let h = sceneeval_geom::Vector3::new(half(0), half(1), half(2));
        if h.iter().any(|&v| v <= 0.0) {
            return None;
        }
        let p = self.start + self.dir * mid(0) + self.normal * mid(1);
        let (u, v) = (
            sceneeval_geom::Vector3::new(self.dir.x, self.dir.y, 0.0),
            sceneeval_geom::Vector3::new(self.normal.x, self.normal.y, 0.0),
        );
        // The third axis is up or down, whichever makes a proper rotation (a box is symmetric).
        let basis = sceneeval_geom::Matrix3::from_columns(&[u, v, u.cross(&v)]);
        sceneeval_geom::Obb::new(
            Point3::new(p.x, p.y, self.base_z + mid(2)),
            h,
            sceneeval_geom::Rotation3::from_matrix_unchecked(basis),
        )
        .ok()
    }

    fn to_frame(&self, p: &Point3) -> Point3 {
        let d = Point2::new(p.x, p.y) - self.start;
        Point3::new(d.dot(&self.dir), d.dot(&self.normal), p.z - self.base_z)
    }

    fn world_aabb(&self) -> Aabb {
        let corner = |u: Real, v: Real, w: Real| {
            let p = self.start + self.dir * u + self.normal * v;
            Point3::new(p.x, p.y, self.base_z + w)
        };
        let pts: Vec<Point3> = (0..8)
            .map(|k| {
                corner(
                    if k & 1 == 0 { self.lo[0] } else { self.hi[0] },
                    if k & 2 == 0 { self.lo[1] } else { self.hi[1] },
                    if k & 4 == 0 { self.lo[2] } else { self.hi[2] },
                )
            })
            .collect();
        Aabb::from_points(pts.iter()).unwrap_or(Aabb::new(Point3::origin(), Point3::origin()))
    }

    /// The part of a world triangle inside the shrunk box, in frame coordinates.
    pub(crate) fn clip(&self, tri: &[Point3; 3]) -> Vec<Point3> {
        let mut poly: Vec<Point3> = tri.iter().map(|p| self.to_frame(p)).collect();
        for axis in 0..3 {
            let (lo, hi) = (self.lo[axis] + self.shrink, self.hi[axis] - self.shrink);
            if poly.iter().all(|p| p[axis] < lo) || poly.iter().all(|p| p[axis] > hi) {
                return Vec::new();
            }
            poly = clip_half_space(&poly, |p| p[axis] - lo);
            poly = clip_half_space(&poly, |p| hi - p[axis]);
            if poly.len() < 3 {
                return Vec::new();
            }
        }
        poly
    }
}

/// The occlusion raster over an opening: `nu x nw` pixels tiling `[u0, u1] x [w0, w1]`, one
/// value per pixel, so within the dense raster budget ([`check_raster`]).
pub(crate) struct OcclusionMap {
    pub nu: usize,
    pub nw: usize,
    u0: Real,
    w0: Real,
    pu: Real,
    pw: Real,
}

impl OcclusionMap {
    /// The map of `frame`'s opening at `ppm` pixels per metre.
    ///
    /// # Errors
    /// [`PlausibilityError::RasterTooLarge`] when it exceeds the raster budget.
    pub(crate) fn new(frame: &OpeningFrame, ppm: Real) -> Result<Self, PlausibilityError> {
        let (w, h) = (frame.hi[0] - frame.lo[0], frame.hi[2] - frame.lo[2]);
        // Float-to-int casts saturate: an absurd size stays above the budget.
        let nu = ((w * ppm).ceil() as usize).max(1);
        let nw = ((h * ppm).ceil() as usize).max(1);
        check_raster("opening_clearance", nu, nw, Storage::Dense)?;
        Ok(OcclusionMap {
            nu,
            nw,
            u0: frame.lo[0],
            w0: frame.lo[2],
            pu: w / nu as Real,
            pw: h / nw as Real,
        })
    }

    /// Marks the pixels (row-major from the bottom) whose centre lies in the convex polygon's
    /// projection onto the `(u, w)` plane.
    pub(crate) fn fill(&self, poly: &[Point3], mut f: impl FnMut(usize)) {
        let pts: Vec<Point2> = poly.iter().map(|p| Point2::new(p.x, p.z)).collect();
        let (lo_w, hi_w) = pts
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(a, b), p| {
                (a.min(p.y), b.max(p.y))
            });
        let j0 = (((lo_w - self.w0) / self.pw - 0.5).ceil().max(0.0)) as usize;
        let j1 = ((hi_w - self.w0) / self.pw - 0.5).floor();
        if j1 < 0.0 {
            return;
        }
        let j1 = (j1 as usize).min(self.nw - 1);
        for j in j0..=j1 {
            let w = self.w0 + (j as Real + 0.5) * self.pw;
            let Some((lo, hi)) = chord(&pts, w) else {
                continue;
            };
            let i0 = (((lo - self.u0) / self.pu - 0.5).ceil().max(0.0)) as usize;
            let i1 = ((hi - self.u0) / self.pu - 0.5).floor();
            if i1 < 0.0 {
                continue;
            }
            for i in i0..=(i1 as usize).min(self.nu - 1) {
                f(j * self.nu + i);
            }
        }
    }
}

/// The objects an opening's clearance box can meet: their world boxes indexed, walkable
/// objects left out as the parameters say.
pub(crate) struct Candidates {
    members: Vec<usize>,
    index: BoxIndex,
    /// The work of the queries made through it.
    work: WorkCounter,
}

impl Candidates {
    pub(crate) fn new(scene: &Scene, infos: &[ObjectInfo], params: &OpeningClearanceParams) -> Self {
        let members: Vec<usize> = (0..scene.objects().len())
            .filter(|&k| infos[k].max_z - infos[k].floor_z > params.walkable_height_m)
            .collect();
        let boxes: Vec<Aabb> = members
            .iter()
            .map(|&k| *scene.objects()[k].world_aabb())
            .collect();
        Candidates {
            index: BoxIndex::new(&boxes),
            members,
            work: WorkCounter::default(),
        }
    }
}

/// Per object in the box: its clipped polygons; then rasterised.
pub(crate) fn intruding_parts(
    scene: &Scene,
    candidates: &Candidates,
    frame: &OpeningFrame,
) -> Vec<(usize, Vec<Vec<Point3>>)> {
    let box_aabb = frame.world_aabb();
    let mut out = Vec::new();
    for m in candidates.index.query(&box_aabb, &candidates.work) {
        let k = candidates.members[m];
        let o = &scene.objects()[k];
        if !o.world_aabb().intersects(&box_aabb) {
            continue;
        }
        let world: Vec<Point3> = o.mesh().vertices().iter().map(|v| o.pose() * v).collect();
        let parts: Vec<Vec<Point3>> = o
            .mesh()
            .triangles()
            .iter()
            .map(|t| [world[t[0] as usize], world[t[1] as usize], world[t[2] as usize]])
            .filter(|t| Aabb::from_points(t.iter()).is_some_and(|b| b.intersects(&box_aabb)))
            .map(|t| frame.clip(&t))
            .filter(|p| area3(p) > 1e-12)
            .collect();
        if !parts.is_empty() {
            out.push((k, parts));
        }
    }
    out
}

fn side_clearance(
    scene: &Scene,
    candidates: &Candidates,
    frame: &OpeningFrame,
    side: OpeningSide,
    depth: Real,
    params: &OpeningClearanceParams,
    deadline: &Deadline,
) -> Result<SideClearance, PlausibilityError> {
    let map = OcclusionMap::new(frame, params.pixels_per_m)?;
    let total = (map.nu * map.nw) as Real;
    let mut union = vec![false; map.nu * map.nw];
    let mut blocking = Vec::new();
    for (k, parts) in intruding_parts(scene, candidates, frame) {
        let mut mine = vec![false; union.len()];
        for p in &parts {
            // Filling one polygon costs up to the map's size: the budget is polled per polygon.
            deadline.check("opening_clearance")?;
            map.fill(p, |i| mine[i] = true);
        }
        let count = mine.iter().filter(|&&m| m).count();
        for (u, m) in union.iter_mut().zip(&mine) {
            *u |= *m;
        }
        blocking.push(BlockingObject {
            id: scene.objects()[k].id().clone(),
            occluded_fraction: count as Real / total,
        });
    }
    Ok(SideClearance {
        side,
        depth,
        occluded_fraction: union.iter().filter(|&&u| u).count() as Real / total,
        blocked: !blocking.is_empty(),
        blocking,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::Vector3;
    use sceneeval_geom::conventions::pose_from_yaw;
    use sceneeval_scene::{Category, RoomBuilder};

    /// A square hall with `n` cabinets on a 1.5 m grid and four doors along its south wall,
    /// one cabinet standing in front of the first door.
    fn hall(n: usize) -> Scene {
        let cols = (n as f64).sqrt().ceil() as usize;
        let side = cols as f64 * 1.5 + 3.0;
        let mut room = RoomBuilder::rectangle("hall", Point2::new(0.0, 0.0), Point2::new(side, side));
        for k in 0..4 {
            let x = 1.0 + 2.0 * f64::from(k);
            room = room.door(0, [x, x + 0.9], [0.0, 2.1]);
        }
        let mut b = Scene::builder().room_builder(room);
        for k in 0..n {
            let (x, y) = (2.0 + (k % cols) as f64 * 1.5, 3.0 + (k / cols) as f64 * 1.5);
            b = b.add_box(
                format!("o{k}"),
                Category::new("cabinet"),
                Vector3::new(0.3, 0.2, 0.4),
                pose_from_yaw(Point3::new(x, y, 0.4), 0.3),
            );
        }
        // In front of the first door (x in [1.0, 1.9]), 0.4 m into the room.
        b = b.add_box(
            "blocker",
            Category::new("cabinet"),
            Vector3::new(0.3, 0.2, 0.4),
            pose_from_yaw(Point3::new(1.45, 0.4, 0.4), 0.0),
        );
        b.build().unwrap()
    }

    #[test]
    fn openings_find_their_blockers_through_the_index() {
        // Sixteen times the objects: the four doors' clearance boxes cost about log n box
        // tests each, where a scan would test every object (16 times as many).
        let mut tests = Vec::new();
        for n in [256usize, 4096] {
            let s = hall(n);
            let infos = crate::objects::object_infos(&s);
            let (r, work) =
                opening_clearance_counted(&s, &OpeningClearanceParams::default(), &infos, &Deadline::none())
                    .unwrap();
            assert_eq!((r.num_doors, r.doors_blocked), (4, 1));
            assert!(work.box_tests < n as u64, "{work:?}");
            tests.push(work.box_tests as f64);
        }
        assert!(tests[1] <= 2.0 * tests[0], "{tests:?}");
    }
}
