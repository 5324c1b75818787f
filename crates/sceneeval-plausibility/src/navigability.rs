//! Navigability (NAV): how much of the free floor is one connected region.

use sceneeval_geom::{Point2, Real};
use sceneeval_scene::{ObjectId, OpeningKind, Scene, Wall};
use serde::{Deserialize, Serialize};

use crate::error::check_non_negative;
use crate::{Deadline, PlausibilityError};

/// The metric's name in errors and deadline checks.
const STAGE: &str = "navigability";
use crate::objects::{DEFAULT_WALKABLE_HEIGHT, Footprint, ObjectInfo, object_infos};
use crate::plane::{ccw, exposed_boundary};
use crate::raster::{Grid, Resolution, RowRuns, Storage, check_raster, merge, par_rows, subtract};

/// Parameters of the navigability metric (reference yaml `NavigabilityMetric`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct NavigabilityParams {
    /// Raster resolution (reference `image_resolution`: 256 pixels over the floors' extent).
    /// Range: 1 to 65,536 pixels per side; a metres-per-pixel size finite and `> 0`, and the
    /// raster it gives for a scene's floors at most 65,536 pixels per side (checked per
    /// scene; the margins alone are checked with the parameters).
    pub resolution: Resolution,
    /// Margin in metres around the floors' extent (reference `scale_margin`, 0.2). Range:
    /// finite, `>= 0`.
    pub margin_m: Real,
    /// Width of the robot in metres (reference `robot_width`, 0.2): free space is every point
    /// at least half of it away from any obstacle and from the edge of the floor. Range:
    /// finite, `>= 0`.
    pub robot_width_m: Real,
    /// Objects with any part lower than this above their floor obstruct, in metres (reference
    /// `obj_height_threshold`, 2.0, applied there to the OBB centre). Range: finite, `>= 0`.
    pub height_cutoff_m: Real,
    /// Objects whose top is at most this above their floor are walked over (rugs), in metres.
    /// Default [`DEFAULT_WALKABLE_HEIGHT`] (5 cm); the reference lets every object obstruct
    /// (0). Range: finite, `>= 0`.
    pub walkable_height_m: Real,
    /// A door whose bottom is at most this above its wall's base is passable, in metres
    /// (default 0.05). Windows never are. Range: finite, `>= 0`.
    pub door_max_sill_m: Real,
    /// Depth in metres of the strip in front of a door, on its room's side, from which a room
    /// counts as reachable (default 0.5). Range: finite, `> 0`.
    pub door_strip_depth_m: Real,
    /// Obstacle footprints: convex hulls of the projected meshes (default) or, as the
    /// reference, the projected bounding boxes ([`Footprint::BoundingBox`]).
    pub footprint: Footprint,
}

impl Default for NavigabilityParams {
    fn default() -> Self {
        NavigabilityParams {
            resolution: Resolution::Pixels(256),
            margin_m: 0.2,
            robot_width_m: 0.2,
            height_cutoff_m: 2.0,
            walkable_height_m: DEFAULT_WALKABLE_HEIGHT,
            door_max_sill_m: 0.05,
            door_strip_depth_m: 0.5,
            footprint: Footprint::ConvexHull,
        }
    }
}

impl NavigabilityParams {
    fn validate(&self) -> Result<(), PlausibilityError> {
        let m = STAGE;
        check_non_negative(m, "margin_m", self.margin_m, false)?;
        check_non_negative(m, "robot_width_m", self.robot_width_m, false)?;
        check_non_negative(m, "height_cutoff_m", self.height_cutoff_m, false)?;
        check_non_negative(m, "walkable_height_m", self.walkable_height_m, false)?;
        check_non_negative(m, "door_max_sill_m", self.door_max_sill_m, false)?;
        check_non_negative(m, "door_strip_depth_m", self.door_strip_depth_m, true)?;
        match self.resolution {
            Resolution::Pixels(0) => Err(PlausibilityError::InvalidParameter {
                metric: m,
                name: "resolution",
                value: 0.0,
                reason: "a raster needs at least one pixel",
            }),
            Resolution::Pixels(n) => check_raster(m, n as usize, n as usize, Storage::Runs),
            Resolution::MetresPerPixel(p) => {
                check_non_negative(m, "resolution", p, true)?;
                // The margins alone span `2 margin / p` pixels, whatever the floors.
                let side = (2.0 * self.margin_m / p).ceil() as usize;
                check_raster(m, side, side, Storage::Runs)
            }
        }
    }
}

/// Reachability of one room.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RoomNavigability {
    /// The room.
    pub room: String,
    /// Free pixels whose centre lies on this room's floor.
    pub free_pixels: usize,
    /// Passable doors in this room's walls.
    pub num_doors: usize,
    /// Whether the room can be entered: some free pixel lies in the strip in front of one of
    /// its doors on the room's side. `None` for a room without a passable door.
    pub reachable: Option<bool>,
    /// Share of the room's free pixels connected to the strip in front of one of its doors.
    /// `None` without a passable door or without free pixels.
    pub reachable_fraction: Option<Real>,
}

/// The navigability metric of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NavigabilityReport {
    /// The raster used.
    pub grid: Grid,
    /// Pixels whose centre lies on a floor.
    pub floor_pixels: usize,
    /// Free pixels (on the floor, at least half the robot width from every obstacle).
    pub free_pixels: usize,
    /// Free area in square metres (free pixels times pixel area).
    pub free_area: Real,
    /// Number of 8-connected free regions.
    pub num_components: usize,
    /// Pixels of the largest region.
    pub largest_component_pixels: usize,
    /// **NAV**: largest region over all free pixels, in [0, 1]; 0 without free pixels (as the
    /// reference).
    pub nav: Real,
    /// Objects drawn as obstacles, in scene order.
    pub obstacles: Vec<ObjectId>,
    /// Objects ignored (entirely above the height cut-off, or walkable).
    pub ignored: Vec<ObjectId>,
    /// Per room, in scene order.
    pub rooms: Vec<RoomNavigability>,
    /// Whether every room with a passable door is reachable; `None` when no room has one.
    pub all_rooms_reachable: Option<bool>,
}

/// The floor-plan raster behind the navigability metric: which pixels are floor and which are
/// free for the robot, as runs of pixels per row (memory grows with rows and runs, not
/// pixels).
#[derive(Debug, Clone, PartialEq)]
pub struct OccupancyMap {
    /// The raster.
    pub grid: Grid,
    /// Pixels whose centre lies on a floor, row by row from the lowest y.
    pub floor: RowRuns,
    /// Pixels free for the robot.
    pub free: RowRuns,
}

impl OccupancyMap {
    /// Labels of the 8-connected free regions, one per run of [`OccupancyMap::free`]
    /// (numbered in scan order of each region's first pixel), and their sizes in pixels.
    pub fn components(&self) -> (Vec<u32>, Vec<usize>) {
        self.free.components8()
    }
}

/// Builds the occupancy map of [`navigability`].
///
/// # Errors
/// As [`navigability`].
pub fn occupancy_map(scene: &Scene, params: &NavigabilityParams) -> Result<OccupancyMap, PlausibilityError> {
    params.validate()?;
    let infos = object_infos(scene);
    Ok(build_map(scene, params, &infos, &Deadline::none())?.0)
}

/// Computes the navigability metric.
///
/// The floor plan is rasterised over the union of the floors ([`NavigabilityParams::
/// resolution`]); every pixel is sampled at its centre. A pixel is **free** when its centre is
/// on a floor and at least `r = robot_width_m / 2` from every obstacle, in exact Euclidean
/// distance (the reference approximates this with square-kernel erosion and thick outlines).
/// Obstacles are: the edges of the floors that border no other floor; the walls (their
/// footprint, from the inner face outward by their thickness) except where a passable door
/// cuts through them, through any wall lying on the door's wall line, so that rooms connect
/// through doors (the reference draws no walls, quirk Q16); and the footprints (convex hull of
/// the mesh projected on the floor) of objects with any part lower than
/// [`NavigabilityParams::height_cutoff_m`] above their floor (the reference tests the OBB centre,
/// which ignores a pendant lamp reaching down to head height) and a top above
/// [`NavigabilityParams::walkable_height_m`].
///
/// NAV is the size of the largest 8-connected free region over all free pixels. Per room,
/// a room is reachable when the strip of depth [`NavigabilityParams::door_strip_depth_m`] in
/// front of one of its passable doors, on the room's side, holds a free pixel.
///
/// # Errors
/// [`PlausibilityError::InvalidParameter`] for bad parameters,
/// [`PlausibilityError::RasterTooLarge`] for a too fine resolution.
pub fn navigability(
    scene: &Scene,
    params: &NavigabilityParams,
) -> Result<NavigabilityReport, PlausibilityError> {
    params.validate()?;
    let infos = object_infos(scene);
    navigability_with(scene, params, &infos, &Deadline::none())
}

/// [`navigability`] with the objects' footprints given, under `deadline` (polled per chunk of
/// raster rows and per room).
pub(crate) fn navigability_with(
    scene: &Scene,
    params: &NavigabilityParams,
    infos: &[ObjectInfo],
    deadline: &Deadline,
) -> Result<NavigabilityReport, PlausibilityError> {
    let (map, obstacle_flags) = build_map(scene, params, infos, deadline)?;
    deadline.check(STAGE)?;
    let (labels, sizes) = map.components();
    let free_pixels: usize = sizes.iter().sum();
    let largest_size = sizes.iter().copied().max().unwrap_or(0);
    let grid = map.grid;
    let rooms = room_reachability(scene, params, &map, &labels, sizes.len(), deadline)?;
    let with_doors: Vec<bool> = rooms.iter().filter_map(|r| r.reachable).collect();
    let (mut obstacles, mut ignored) = (Vec::new(), Vec::new());
    for (o, &obstructs) in scene.objects().iter().zip(&obstacle_flags) {
        if obstructs {
            obstacles.push(o.id().clone());
        } else {
            ignored.push(o.id().clone());
        }
    }
    Ok(NavigabilityReport {
        grid,
        floor_pixels: map.floor.count(),
        free_pixels,
        free_area: free_pixels as Real * grid.pixel_area(),
        num_components: sizes.len(),
        largest_component_pixels: largest_size,
        nav: if free_pixels == 0 {
            0.0
        } else {
            largest_size as Real / free_pixels as Real
        },
        obstacles,
        ignored,
        all_rooms_reachable: (!with_doors.is_empty()).then(|| with_doors.iter().all(|&r| r)),
        rooms,
    })
}

/// Something that blocks pixels within half the robot width of it, with the rows it reaches.
enum Blocker<'a> {
    Segment(Point2, Point2),
    Convex(Vec<Point2>),
    Footprint(&'a [Point2]),
}

/// The map and, per object, whether it was drawn as an obstacle. Row by row (in parallel):
/// the floor's intervals minus the intervals within the robot's half width of a blocker,
/// each computed in closed form; blockers are bucketed by their first row and swept.
pub(crate) fn build_map(
    scene: &Scene,
    params: &NavigabilityParams,
    infos: &[ObjectInfo],
    deadline: &Deadline,
) -> Result<(OccupancyMap, Vec<bool>), PlausibilityError> {
    let floors: Vec<_> = scene.rooms().iter().map(|r| r.floor()).collect();
    let (min, max) = floors
        .iter()
        .map(|f| f.bounds())
        .reduce(|a, b| (a.0.inf(&b.0), a.1.sup(&b.1)))
        .unwrap_or((Point2::origin(), Point2::new(1.0, 1.0)));
    let grid = Grid::covering(STAGE, min, max, params.margin_m, params.resolution)?;
    let r = 0.5 * params.robot_width_m;
    let mut blockers: Vec<Blocker<'_>> = Vec::new();
    for (a, b) in exposed_boundary(&floors) {
        blockers.push(Blocker::Segment(a, b));
    }
    let doors = passable_doors(scene, params.door_max_sill_m);
    for (_, wall) in scene.walls() {
        for piece in wall_pieces(wall, &doors) {
            if piece.len() == 2 {
                blockers.push(Blocker::Segment(piece[0], piece[1]));
            } else {
                blockers.push(Blocker::Convex(piece));
            }
        }
    }
    let flags: Vec<bool> = infos
        .iter()
        .map(|i| i.obstructs(params.height_cutoff_m, params.walkable_height_m))
        .collect();
    for (info, _) in infos.iter().zip(&flags).filter(|(_, f)| **f) {
        blockers.push(Blocker::Footprint(info.footprint_of(params.footprint).0));
    }
    // The rows each blocker reaches, sorted by first row, and each floor's rows.
    let mut spans: Vec<(usize, usize, usize)> = blockers
        .iter()
        .enumerate()
        .filter_map(|(k, b)| {
            let (lo, hi) = match b {
                Blocker::Segment(a, b) => (a.y.min(b.y), a.y.max(b.y)),
                Blocker::Convex(p) => y_range(p),
                Blocker::Footprint(p) => y_range(p),
            };
            grid.rows(lo, hi, r).map(|(j0, j1)| (j0, j1, k))
        })
        .collect();
    spans.sort_unstable();
    let floor_rows: Vec<Option<(usize, usize)>> = floors
        .iter()
        .map(|f| {
            let (a, b) = f.bounds();
            grid.rows(a.y, b.y, 0.0)
        })
        .collect();
    // Chunks of rows look up their blockers among those starting before the chunk ends.
    const CHUNK: usize = 64;
    let chunks = grid.height.div_ceil(CHUNK);
    type Chunk = (Vec<Intervals>, Vec<Intervals>);
    let per_chunk: Vec<Result<Chunk, PlausibilityError>> = par_rows(chunks, |c| {
        deadline.check(STAGE)?;
        let (ja, jb) = (c * CHUNK, ((c + 1) * CHUNK).min(grid.height));
        let started = spans.partition_point(|s| s.0 < jb);
        let active: Vec<&(usize, usize, usize)> = spans[..started].iter().filter(|s| s.1 >= ja).collect();
        let mut floor_out = Vec::with_capacity(jb - ja);
        let mut free_out = Vec::with_capacity(jb - ja);
        for j in ja..jb {
            let y = grid.row_y(j);
            let mut floor = Vec::new();
            for (f, rows) in floors.iter().zip(&floor_rows) {
                if rows.is_some_and(|(j0, j1)| j0 <= j && j <= j1) {
                    grid.polygon_row(f.points(), y, &mut floor);
                }
            }
            let floor = merge(floor);
            let mut cut = Vec::new();
            for &&(j0, j1, k) in &active {
                if j < j0 || j > j1 {
                    continue;
                }
                let span = match &blockers[k] {
                    Blocker::Segment(a, b) => grid.segment_row(a, b, r, y),
                    Blocker::Convex(p) => grid.convex_row(p, r, y),
                    Blocker::Footprint(p) => grid.convex_row(p, r, y),
                };
                cut.extend(span);
            }
            let free = subtract(&floor, &merge(cut));
            floor_out.push(floor);
            free_out.push(free);
        }
        Ok((floor_out, free_out))
    });
    let (mut floor_rows_all, mut free_rows_all) =
        (Vec::with_capacity(grid.height), Vec::with_capacity(grid.height));
    for chunk in per_chunk {
        let (f, fr) = chunk?;
        floor_rows_all.extend(f);
        free_rows_all.extend(fr);
    }
    let map = OccupancyMap {
        grid,
        floor: RowRuns::from_rows(floor_rows_all),
        free: RowRuns::from_rows(free_rows_all),
    };
    Ok((map, flags))
}

/// Column intervals `[start, end)` of one row.
type Intervals = Vec<(usize, usize)>;

fn y_range(poly: &[Point2]) -> (Real, Real) {
    poly.iter()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.y), hi.max(p.y))
        })
}

/// A passable door: its wall's inner-face line and its interval along it.
pub(crate) struct DoorGap {
    start: Point2,
    dir: sceneeval_geom::Vector2,
    thickness: Real,
    along: [Real; 2],
}

pub(crate) fn passable_doors(scene: &Scene, max_sill: Real) -> Vec<DoorGap> {
    scene
        .openings()
        .filter(|(_, _, o)| o.kind == OpeningKind::Door && o.height[0] <= max_sill)
        .map(|(_, w, o)| DoorGap {
            start: w.start(),
            dir: w.direction(),
            thickness: w.thickness(),
            along: o.along,
        })
        .collect()
}

/// A wall's footprint minus the passable door gaps lying on its line, as convex pieces
/// (four corners) or, for a zero-thickness wall, segments (two points).
pub(crate) fn wall_pieces(wall: &Wall, doors: &[DoorGap]) -> Vec<Vec<Point2>> {
    let (s, d, len, t) = (wall.start(), wall.direction(), wall.length(), wall.thickness());
    let mut gaps: Vec<[Real; 2]> = Vec::new();
    for door in doors {
        if d.perp(&door.dir).abs() > 1e-6 {
            continue;
        }
        let p0 = door.start + door.dir * door.along[0];
        let p1 = door.start + door.dir * door.along[1];
        let offset = d.perp(&(p0 - s)).abs();
        if offset > t + door.thickness + 1e-6 {
            continue;
        }
        let (u0, u1) = ((p0 - s).dot(&d), (p1 - s).dot(&d));
        let (lo, hi) = (u0.min(u1).max(0.0), u0.max(u1).min(len));
        if hi > lo {
            gaps.push([lo, hi]);
        }
    }
    gaps.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let mut solid: Vec<[Real; 2]> = Vec::new();
    let mut cursor = 0.0;
    for g in &gaps {
        if g[0] > cursor {
            solid.push([cursor, g[0]]);
        }
        cursor = Real::max(cursor, g[1]);
    }
    if cursor < len {
        solid.push([cursor, len]);
    }
    let out = -wall.inward_normal();
    solid
        .into_iter()
        .filter(|[a, b]| b - a > 1e-12)
        .map(|[a, b]| {
            let (p, q) = (s + d * a, s + d * b);
            if t > 0.0 {
                ccw(vec![p, q, q + out * t, p + out * t])
            } else {
                vec![p, q]
            }
        })
        .collect()
}

fn room_reachability(
    scene: &Scene,
    params: &NavigabilityParams,
    map: &OccupancyMap,
    labels: &[u32],
    num_labels: usize,
    deadline: &Deadline,
) -> Result<Vec<RoomNavigability>, PlausibilityError> {
    let grid = &map.grid;
    // Free runs of row `j` meeting the columns `[a, b)`: (run index, overlap length).
    let overlaps = |j: usize, a: usize, b: usize, f: &mut dyn FnMut(usize, usize)| {
        let base = map.free.row_offset(j);
        for (k, run) in map.free.row(j).iter().enumerate() {
            let (s, e) = (run[0] as usize, run[1] as usize);
            if e <= a {
                continue;
            }
            if s >= b {
                break;
            }
            f(base + k, e.min(b) - s.max(a));
        }
    };
    scene
        .rooms()
        .iter()
        .map(|room| {
            deadline.check(STAGE)?;
            let mut reached = vec![false; num_labels];
            let mut num_doors = 0;
            let mut strip_free = false;
            for wall in room.walls() {
                for o in wall.openings() {
                    if o.kind != OpeningKind::Door || o.height[0] > params.door_max_sill_m {
                        continue;
                    }
                    num_doors += 1;
                    let (s, d, n) = (wall.start(), wall.direction(), wall.inward_normal());
                    let (p, q) = (s + d * o.along[0], s + d * o.along[1]);
                    let depth = n * params.door_strip_depth_m;
                    let strip = ccw(vec![p, q, q + depth, p + depth]);
                    let (lo, hi) = y_range(&strip);
                    if let Some((j0, j1)) = grid.rows(lo, hi, 0.0) {
                        for j in j0..=j1 {
                            if let Some((a, b)) = grid.convex_row(&strip, 0.0, grid.row_y(j)) {
                                overlaps(j, a, b, &mut |run, _| {
                                    strip_free = true;
                                    reached[labels[run] as usize] = true;
                                });
                            }
                        }
                    }
                }
            }
            let (mut free_pixels, mut connected) = (0usize, 0usize);
            let (lo, hi) = room.floor().bounds();
            if let Some((j0, j1)) = grid.rows(lo.y, hi.y, 0.0) {
                let mut row = Vec::new();
                for j in j0..=j1 {
                    row.clear();
                    grid.polygon_row(room.floor().points(), grid.row_y(j), &mut row);
                    for &(a, b) in &row {
                        overlaps(j, a, b, &mut |run, len| {
                            free_pixels += len;
                            if reached[labels[run] as usize] {
                                connected += len;
                            }
                        });
                    }
                }
            }
            let has_door = num_doors > 0;
            Ok(RoomNavigability {
                room: room.id().to_string(),
                free_pixels,
                num_doors,
                reachable: has_door.then_some(strip_free),
                reachable_fraction: (has_door && free_pixels > 0)
                    .then(|| connected as Real / free_pixels as Real),
            })
        })
        .collect()
}

pub(crate) fn validate(params: &NavigabilityParams) -> Result<(), PlausibilityError> {
    params.validate()
}
