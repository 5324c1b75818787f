//! The generated scenes load back through `sceneeval-io` with the fixture assets, their frames
//! are right, and every claim of `expected.json` holds when checked independently of the code
//! that wrote it (mesh queries, a fine navigability grid, surface quadrature).

// Test helpers outside `#[test]` functions may fail loudly too.
#![allow(clippy::unwrap_used, clippy::panic)]

use std::collections::{BTreeSet, VecDeque};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use sceneeval_annotation::{Annotations, Severity};
use sceneeval_fixtures::expected::{Expected, ExpectedScene};
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Obb, Point2, Point3, Polygon2, Real, Side, Vector2, Vector3};
use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state};
use sceneeval_scene::Category;
use sceneeval_scene::{OpeningKind, Scene, SceneObject, SupportType};

/// Tolerance on lengths: the assets store f32 coordinates (about 1e-7 m of rounding) and
/// `expected.json` rounds to 1e-6.
const TOL: Real = 2e-6;

struct Fixture {
    dir: PathBuf,
    expected: Expected,
    library: AssetLibrary,
    scenes: Vec<Scene>,
}

/// One generation per test binary, in the target's scratch folder.
fn fixture() -> &'static Fixture {
    static FIXTURE: OnceLock<Fixture> = OnceLock::new();
    FIXTURE.get_or_init(|| {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sceneeval-fixtures-scenes-test");
        if dir.exists() {
            std::fs::remove_dir_all(&dir).unwrap();
        }
        let generated = sceneeval_fixtures::generate(&dir).unwrap();
        // The CLI's `--assets fixture=fixtures/assets`.
        let spec = format!("fixture={}", dir.join("assets").display());
        let library = AssetLibrary::from_specs(&[spec]).unwrap();
        let scenes = generated
            .expected
            .scenes
            .iter()
            .map(|s| read_scene_state(&dir.join(&s.file), &library, &ReadOptions::default()).unwrap())
            .collect();
        Fixture {
            dir,
            expected: generated.expected,
            library,
            scenes,
        }
    })
}

fn scenes() -> impl Iterator<Item = (&'static ExpectedScene, &'static Scene)> {
    let f = fixture();
    f.expected.scenes.iter().zip(&f.scenes)
}

fn world_vertices(o: &SceneObject) -> impl Iterator<Item = Point3> + '_ {
    o.mesh().vertices().iter().map(|v| o.pose() * v)
}

fn object<'a>(scene: &'a Scene, id: &str) -> &'a SceneObject {
    scene.object(id).unwrap_or_else(|| panic!("no object {id}"))
}

#[test]
fn every_scene_loads_with_the_fixture_assets() {
    let f = fixture();
    assert!(f.expected.scenes.len() >= 12);
    assert!(
        f.scenes
            .iter()
            .any(|s| s.objects().len() >= 100 && s.rooms().len() >= 2)
    );
    for (e, scene) in scenes() {
        assert_eq!(scene.name(), Some(format!("scene_{}", e.id).as_str()));
        let ids: Vec<&str> = scene.objects().iter().map(|o| o.id().as_str()).collect();
        let expected_ids: Vec<&str> = e.objects.iter().map(|o| o.id.as_str()).collect();
        assert_eq!(ids, expected_ids, "scene {}", e.id);
        for (o, eo) in scene.objects().iter().zip(&e.objects) {
            // Asset categories come from the sidecar metadata, box categories from the file.
            assert_eq!(o.category(), Some(eo.category.as_str()), "{}", eo.id);
            assert_eq!(o.model_id(), eo.model_id.as_deref());
            let size = o.obb().extents();
            for k in 0..3 {
                assert!((size[k] - eo.size[k]).abs() < TOL, "{} size", eo.id);
            }
        }
        let rooms: Vec<&str> = scene.rooms().iter().map(|r| r.id().as_str()).collect();
        let expected_rooms: Vec<&str> = e.rooms.iter().map(|r| r.id.as_str()).collect();
        assert_eq!(rooms, expected_rooms);
        // Every room has a door and a window.
        assert!(
            e.rooms
                .iter()
                .all(|r| !r.doors.is_empty() && !r.windows.is_empty()),
            "scene {}",
            e.id
        );
    }
    // Each asset file was read once for all scenes.
    assert_eq!(f.library.files_read(), 18);
}

#[test]
fn the_required_room_shapes_are_present() {
    let f = fixture();
    let shapes: Vec<(usize, usize)> = f
        .scenes
        .iter()
        .map(|s| (s.rooms().len(), s.rooms()[0].walls().len()))
        .collect();
    // Rectangular, L-shaped (6 walls), diagonal (5 walls, one at 45 degrees), two rooms.
    assert_eq!(shapes[0], (1, 4));
    assert_eq!(shapes[2], (1, 6));
    assert_eq!(shapes[3], (1, 5));
    assert_eq!(shapes[4].0, 2);
    let diagonal = &f.scenes[3].rooms()[0].walls()[2];
    let expected = Vector2::new(-1.0, -1.0) / 2f64.sqrt();
    assert!((diagonal.inward_normal() - expected).norm() < 1e-12);
    // The apartment's rooms share the connecting door's position.
    let doors: Vec<_> = f.scenes[4]
        .openings()
        .filter(|(_, _, o)| o.kind == OpeningKind::Door)
        .collect();
    assert_eq!(doors.len(), 3);
}

#[test]
fn asset_fronts_survive_the_frame_conversion() {
    let lib = &fixture().library;
    let mesh = |id: &str| lib.asset(&format!("fixture.{id}")).unwrap().mesh.clone();
    // Object frame: front = -y, up = +z. The bed's headboard (the only part above the
    // 0.67 m pillows) is at its back, +y.
    let bed = mesh("bed");
    let high: Vec<_> = bed.vertices().iter().filter(|v| v.z > 0.7).collect();
    assert!(!high.is_empty());
    assert!(high.iter().all(|v| v.y > 0.96), "headboard at +y");
    assert!((bed.aabb().max.z - 1.1).abs() < 1e-6 && bed.aabb().min.z.abs() < 1e-9);
    // The chair's backrest (above the 0.46 m seat) is at its back.
    let chair = mesh("chair");
    assert!(chair.vertices().iter().filter(|v| v.z > 0.5).all(|v| v.y > 0.18));
    // The TV's screen is its front-most part: every vertex at y < -0.02 lies within the screen.
    let tv = mesh("tv");
    assert!((tv.aabb().min.y + 0.03).abs() < 1e-6);
    assert!(
        tv.vertices()
            .iter()
            .filter(|v| v.y < -0.021)
            .all(|v| v.x.abs() <= 0.58 + 1e-6)
    );
    assert!(tv.aabb().extents().y < 0.07, "thin along the front axis");
    // The painting's canvas faces front; the rug is 1 cm thick.
    let painting = mesh("painting");
    assert!(
        painting
            .vertices()
            .iter()
            .filter(|v| v.y < -0.011)
            .all(|v| v.x.abs() <= 0.36 + 1e-6)
    );
    assert!((mesh("rug").aabb().extents().z - 0.01).abs() < 1e-6);
    // The ceiling lamp's mounting canopy is its top: a narrow part above 0.7 m.
    let lamp = mesh("ceiling_lamp");
    assert!(
        lamp.vertices()
            .iter()
            .filter(|v| v.z > 0.69)
            .all(|v| v.x.abs() <= 0.06 + 1e-6)
    );
}

#[test]
fn placed_objects_face_the_intended_way() {
    let f = fixture();
    let front = |scene: usize, id: &str| object(&f.scenes[scene], id).obb().side_direction(Side::Front);
    let close = |a: Vector3, b: Vector3| (a - b).norm() < 1e-9;
    // Scene 0: the bed faces -y, its headboard against the north wall (y = 5).
    assert!(close(front(0, "idx0_fixture.bed"), -Vector3::y()));
    let bed = object(&f.scenes[0], "idx0_fixture.bed");
    let headboard_max_y = world_vertices(bed)
        .filter(|v| v.z > 0.7)
        .map(|v| v.y)
        .fold(Real::INFINITY, Real::min);
    assert!(headboard_max_y > 4.9, "headboard near the north wall");
    // Scene 1: the sofa faces +x toward the TV, the TV faces -x toward the sofa.
    assert!(close(front(1, "idx0_fixture.sofa"), Vector3::x()));
    assert!(close(front(1, "idx4_fixture.tv"), -Vector3::x()));
    // Scene 3: the bookshelf faces into the room from the diagonal wall.
    let d = Vector3::new(-1.0, -1.0, 0.0) / 2f64.sqrt();
    assert!(close(front(3, "idx3_fixture.bookshelf"), d));
    // Scene 4: the wide wardrobe is scaled 1.2 in width.
    let wardrobe = object(&f.scenes[4], "idx4_fixture.wardrobe");
    assert!((wardrobe.obb().extents() - Vector3::new(1.2, 0.6, 2.0)).norm() < 1e-6);
    assert!((wardrobe.scale() - Vector3::new(1.2, 1.0, 1.0)).norm() < 1e-12);
}

#[test]
fn yaws_include_quarter_turns_and_arbitrary_angles() {
    let yaws: BTreeSet<i64> = scenes()
        .flat_map(|(e, _)| e.objects.iter().map(|o| (o.yaw_deg * 1000.0).round() as i64))
        .collect();
    for required in [0, 90_000, 180_000, -90_000, 20_000, 30_000, -45_000] {
        assert!(
            yaws.contains(&required),
            "no object at yaw {}",
            required as f64 / 1000.0
        );
    }
}

#[test]
fn hand_computed_answers() {
    let e = &fixture().expected;
    // Scene 5: the nightstand's left side (1.625 - 0.225 = 1.4) is 1.5 - 1.4 = 0.10 m inside
    // the wardrobe (x 0.5..1.5); along y and z the overlaps are 0.42 and 0.55.
    let c = &e.scenes[5].collisions;
    assert_eq!(c.len(), 1);
    assert_eq!(
        (c[0].a.as_str(), c[0].b.as_str()),
        ("idx0_fixture.wardrobe", "idx1_fixture.nightstand")
    );
    assert_eq!(c[0].depth, Some(0.1));
    assert_eq!(c[0].axis.as_deref(), Some("x"));
    // Scene 6: the chair's feet at z = 0.25 over a floor at 0.
    assert_eq!(e.scenes[6].floating[0].gap, 0.25);
    assert_eq!(e.scenes[6].floating[0].object, "idx1_fixture.chair");
    // Scene 7: the sofa is its own mirror image in x and centred on the wall plane x = 4.
    assert_eq!(e.scenes[7].out_of_bounds[0].outside_share, 0.5);
    // Scene 8: the wardrobe covers along 0.95..1.95 (all of the door's 1.0..1.9) and height
    // 0..2.0 of the door's 0..2.1: 0.9 * 2.0 / (0.9 * 2.1) = 0.952381.
    let b = &e.scenes[8].blocked_doors[0];
    assert_eq!(b.occluded_fraction, 0.952381);
    assert_eq!(b.gap_to_wall, 0.02);
    assert_eq!(b.blocked_by, ["idx0_fixture.wardrobe"]);
    assert_eq!(e.scenes[8].navigable, Some(false));
    // Scene 9: the box's label face at y = 2.71 - 0.125 = 2.585, the carcass front at
    // 2.7 - 0.28 = 2.42: 0.165 m (x: 0.35, z: 0.9 are larger).
    assert_eq!(e.scenes[9].inside[0].clearance, 0.165);
    assert_eq!(e.scenes[9].collisions[0].kind, "containment");
    // Clean scenes have no flaws and are navigable.
    for s in e.scenes.iter().filter(|s| s.clean) {
        assert!(s.collisions.is_empty() && s.floating.is_empty() && s.out_of_bounds.is_empty());
        assert!(s.blocked_doors.is_empty() && s.inside.is_empty());
        assert_eq!(s.navigable, Some(true), "scene {}", s.id);
    }
}

/// The area-weighted surface centroid of the placed mesh (the reference's centre of mass).
fn surface_centroid(o: &SceneObject) -> Point3 {
    let mesh = o.mesh();
    let (mut sum, mut area) = (Vector3::zeros(), 0.0);
    for t in 0..mesh.triangles().len() {
        let [a, b, c] = mesh.triangle(t).map(|p| o.pose() * p);
        let w = (b - a).cross(&(c - a)).norm() * 0.5;
        sum += (a.coords + b.coords + c.coords) * (w / 3.0);
        area += w;
    }
    Point3::from(sum / area)
}

/// Convex hull (Andrew's monotone chain), counter-clockwise, without collinear points.
fn convex_hull(mut pts: Vec<Point2>) -> Vec<Point2> {
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: &Point2, a: &Point2, b: &Point2| (a - o).perp(&(b - o));
    let mut hull: Vec<Point2> = Vec::with_capacity(2 * pts.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Point2>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for p in iter {
            while hull.len() >= start + 2 && cross(&hull[hull.len() - 2], &hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(*p);
        }
        hull.pop();
    }
    hull
}

/// Whether `p` lies inside the counter-clockwise convex polygon `hull` (of positive area).
fn inside_convex(hull: &[Point2], p: &Point2) -> bool {
    hull.len() >= 3
        && (0..hull.len()).all(|i| (hull[(i + 1) % hull.len()] - hull[i]).perp(&(p - hull[i])) > 0.0)
}

/// Whether the object's centre of mass lies over the convex hull of its vertices that touch
/// the surface at height `z` within the plan region `over`.
fn held_by(o: &SceneObject, z: Real, over: &dyn Fn(&Point2) -> bool) -> bool {
    let contacts: Vec<Point2> = world_vertices(o)
        .filter(|p| (p.z - z).abs() < TOL)
        .map(|p| Point2::new(p.x, p.y))
        .filter(|p| over(p))
        .collect();
    assert!(!contacts.is_empty(), "{} touches nothing at z = {z}", o.id());
    let c = surface_centroid(o);
    inside_convex(&convex_hull(contacts), &Point2::new(c.x, c.y))
}

#[test]
fn support_claims_hold() {
    for (e, scene) in scenes() {
        for eo in &e.objects {
            let o = object(scene, &eo.id);
            let aabb = o.world_aabb();
            let room = eo
                .room
                .as_deref()
                .and_then(|r| scene.room(r))
                .expect("object in a room");
            let what = format!("scene {} {}", e.id, eo.id);
            // The scene file states the same type (`supportType`).
            assert_eq!(
                o.support_type(),
                Some(eo.support_type),
                "{what}: stated support type"
            );
            match (eo.support_type.name(), eo.supported_by.as_deref()) {
                ("ground", Some(floor)) => {
                    assert_eq!(floor, room.floor_id(), "{what}");
                    assert!((aabb.min.z - room.floor_z()).abs() < TOL, "{what} on the floor");
                    // Over a floor up to the f32 rounding of faces flush against walls.
                    let over = |p: &Point2| scene.rooms().iter().any(|r| r.floor().signed_distance(p) <= TOL);
                    let held = held_by(o, room.floor_z(), &over);
                    assert_eq!(held, eo.supported, "{what}: centre of mass over the contacts");
                }
                ("object", Some(below)) => {
                    let b = *object(scene, below).world_aabb();
                    assert!((aabb.min.z - b.max.z).abs() < TOL, "{what} on {below}");
                    let over = |p: &Point2| {
                        p.x > b.min.x - TOL
                            && p.x < b.max.x + TOL
                            && p.y > b.min.y - TOL
                            && p.y < b.max.y + TOL
                    };
                    assert_eq!(held_by(o, b.max.z, &over), eo.supported, "{what} on {below}");
                }
                ("wall", Some(wall)) => {
                    let (_, w) = scene.walls().find(|(_, w)| w.id() == wall).unwrap();
                    let back = o.obb().face_center(Side::Back);
                    assert!(
                        w.inner_plane().signed_distance(&back).abs() < TOL,
                        "{what} on {wall}"
                    );
                    assert!(o.obb().side_direction(Side::Back).dot(&-w.inward_normal_3d()) > 1.0 - 1e-9);
                    assert!(aabb.min.z > room.floor_z() + 0.5, "{what} hangs");
                    assert!(eo.supported);
                }
                ("ceiling", Some(_)) => {
                    assert!((aabb.max.z - room.ceiling_z().unwrap()).abs() < TOL, "{what}");
                    assert!(eo.supported);
                }
                (_, None) => {
                    assert!(!eo.supported, "{what}");
                    // Nothing within 1 cm below its lowest point.
                    assert!(aabb.min.z - room.floor_z() > 0.01, "{what}");
                    for other in scene.objects().iter().filter(|x| x.id() != o.id()) {
                        let b = other.world_aabb();
                        let overlaps_xy = b.min.x < aabb.max.x
                            && b.max.x > aabb.min.x
                            && b.min.y < aabb.max.y
                            && b.max.y > aabb.min.y;
                        let top_just_below = b.max.z <= aabb.min.z + TOL && b.max.z > aabb.min.z - 0.01;
                        assert!(!(overlaps_xy && top_just_below), "{what} rests on {}", other.id());
                    }
                }
                other => panic!("{what}: unexpected support {other:?}"),
            }
        }
    }
    // The sofa half outside the room touches the floor with its two west legs only.
    let sofa = &fixture().expected.scenes[7].objects[0];
    assert_eq!(
        (sofa.supported_by.as_deref(), sofa.supported),
        (Some("floor_living_room"), false)
    );
}

#[test]
fn convex_hull_and_containment() {
    let p = |x: Real, y: Real| Point2::new(x, y);
    // A unit square with an interior point and a point on an edge: the hull is the 4 corners.
    let hull = convex_hull(vec![
        p(0.0, 0.0),
        p(1.0, 0.0),
        p(0.5, 0.5),
        p(1.0, 1.0),
        p(0.0, 1.0),
        p(0.5, 0.0),
    ]);
    assert_eq!(hull.len(), 4);
    assert!(inside_convex(&hull, &p(0.5, 0.5)));
    assert!(!inside_convex(&hull, &p(1.5, 0.5)));
    assert!(!inside_convex(
        &convex_hull(vec![p(0.0, 0.0), p(1.0, 1.0)]),
        &p(0.5, 0.5)
    ));
}

/// Largest distance from a vertex of `b` that lies inside `a` to `a`'s surface.
fn vertex_depth(a: &SceneObject, b: &SceneObject) -> Real {
    world_vertices(b)
        .filter(|p| a.mesh().contains_point(a.pose(), p))
        .map(|p| a.mesh().distance_to_point(a.pose(), &p))
        .fold(0.0, Real::max)
}

#[test]
fn collision_lists_are_complete_and_depths_match() {
    for (e, scene) in scenes() {
        let objects = scene.objects();
        let supports: BTreeSet<(&str, &str)> = e
            .objects
            .iter()
            .filter(|o| o.support_type == SupportType::Object)
            .filter_map(|o| o.supported_by.as_deref().map(|b| (o.id.as_str(), b)))
            .collect();
        for i in 0..objects.len() {
            for j in i + 1..objects.len() {
                let (a, b) = (&objects[i], &objects[j]);
                if a.world_aabb().distance_to_aabb(b.world_aabb()) > 0.0 {
                    continue;
                }
                let (ia, ib) = (a.id().as_str(), b.id().as_str());
                let what = format!("scene {}: {ia} / {ib}", e.id);
                let listed = e
                    .collisions
                    .iter()
                    .find(|c| (c.a == ia && c.b == ib) || (c.a == ib && c.b == ia));
                match listed {
                    Some(c) if c.kind == "penetration" => {
                        let depth = vertex_depth(a, b).max(vertex_depth(b, a));
                        assert!((depth - c.depth.unwrap()).abs() < TOL, "{what}: depth {depth}");
                    }
                    Some(c) => {
                        let (outer, inner) = (object(scene, &c.a), object(scene, &c.b));
                        assert!(
                            !outer.mesh().intersects(outer.pose(), inner.mesh(), inner.pose()),
                            "{what}"
                        );
                        assert!(world_vertices(inner).all(|p| outer.mesh().contains_point(outer.pose(), &p)));
                    }
                    None if supports.contains(&(ia, ib)) || supports.contains(&(ib, ia)) => {
                        // Resting contact: the upper one's bottom on the lower one's top.
                        let (lo, hi) = if a.world_aabb().min.z < b.world_aabb().min.z {
                            (a, b)
                        } else {
                            (b, a)
                        };
                        assert!(hi.world_aabb().min.z >= lo.world_aabb().max.z - TOL, "{what}");
                    }
                    None => {
                        let d = a.mesh().distance(a.pose(), b.mesh(), b.pose());
                        assert!(d > 1e-3, "{what}: unlisted contact ({d} m apart)");
                        assert!(
                            world_vertices(b).all(|p| !a.mesh().contains_point(a.pose(), &p)),
                            "{what}"
                        );
                        assert!(
                            world_vertices(a).all(|p| !b.mesh().contains_point(b.pose(), &p)),
                            "{what}"
                        );
                    }
                }
            }
        }
    }
}

/// Share of the object's surface area outside every floor, by a fixed quadrature: each
/// triangle is split into `n * n` similar sub-triangles and each is tested at its centroid.
fn outside_share_by_quadrature(scene: &Scene, o: &SceneObject, n: usize) -> Real {
    let mesh = o.mesh();
    let (mut outside, mut total) = (0.0, 0.0);
    for t in 0..mesh.triangles().len() {
        let [a, b, c] = mesh.triangle(t).map(|p| o.pose() * p);
        let area = (b - a).cross(&(c - a)).norm() * 0.5;
        let sub = area / (n * n) as Real;
        for i in 0..n {
            for j in 0..n - i {
                // Upward sub-triangle (i, j) and, where it exists, the downward one.
                let mut centroids = vec![((i as Real + 1.0 / 3.0), (j as Real + 1.0 / 3.0))];
                if i + j + 1 < n {
                    centroids.push(((i as Real + 2.0 / 3.0), (j as Real + 2.0 / 3.0)));
                }
                for (u, v) in centroids {
                    let (u, v) = (u / n as Real, v / n as Real);
                    let p = a + (b - a) * u + (c - a) * v;
                    total += sub;
                    if !scene.is_over_floor(&Point2::new(p.x, p.y)) {
                        outside += sub;
                    }
                }
            }
        }
    }
    outside / total
}

#[test]
fn out_of_bounds_lists_are_complete_and_shares_match() {
    for (e, scene) in scenes() {
        for o in scene.objects() {
            let listed = e.out_of_bounds.iter().find(|x| x.object == o.id().as_str());
            match listed {
                Some(x) => {
                    let share = outside_share_by_quadrature(scene, o, 8);
                    assert!((share - x.outside_share).abs() < 0.01, "{}: {share}", o.id());
                }
                None => {
                    for p in world_vertices(o) {
                        let inside = scene
                            .rooms()
                            .iter()
                            .any(|r| r.floor().signed_distance(&Point2::new(p.x, p.y)) <= TOL);
                        assert!(inside, "scene {}: {} has vertex {p} outside", e.id, o.id());
                    }
                }
            }
        }
    }
}

/// The clearance box in front of a door on its room side: as deep as the door is wide, as
/// tall as the door (reference-notes 7.6).
fn door_clearance(wall: &sceneeval_scene::Wall, door: &sceneeval_scene::Opening) -> Obb {
    let depth = door.width();
    let mid = wall.point_on_inner_face(
        0.5 * (door.along[0] + door.along[1]),
        0.5 * (door.height[0] + door.height[1]),
    );
    Obb::new(
        mid + wall.inward_normal_3d() * (0.5 * depth),
        Vector3::new(0.5 * door.width(), 0.5 * depth, 0.5 * door.hole_height()),
        wall.rotation(),
    )
    .unwrap()
}

#[test]
fn blocked_door_lists_are_complete() {
    for (e, scene) in scenes() {
        for (room, wall, door) in scene.openings().filter(|(_, _, o)| o.kind == OpeningKind::Door) {
            let clearance = door_clearance(wall, door);
            let blockers: Vec<&str> = scene
                .objects()
                .iter()
                .filter(|o| o.obb().intersects(&clearance))
                .map(|o| o.id().as_str())
                .collect();
            match e.blocked_doors.iter().find(|b| b.door == door.id) {
                Some(b) => {
                    assert_eq!(b.room, room.id().as_str());
                    assert_eq!(blockers, b.blocked_by, "scene {} door {}", e.id, door.id);
                }
                None => assert!(
                    blockers.is_empty(),
                    "scene {} door {}: {blockers:?}",
                    e.id,
                    door.id
                ),
            }
        }
    }
}

#[test]
fn inside_claims_hold() {
    for (e, scene) in scenes() {
        for x in &e.inside {
            let (outer, inner) = (object(scene, &x.outer), object(scene, &x.inner));
            let clearance = world_vertices(inner)
                .inspect(|p| assert!(outer.mesh().contains_point(outer.pose(), p)))
                .map(|p| outer.mesh().distance_to_point(outer.pose(), &p))
                .fold(Real::INFINITY, Real::min);
            assert!(
                (clearance - x.clearance).abs() < TOL,
                "scene {}: {clearance}",
                e.id
            );
        }
    }
}

/// A navigability grid (cell `CELL`): a cell is free when it is over a floor, at least the
/// robot's half width from every wall's inner face outside the door openings, and from the
/// footprint of every object whose lowest point is under 2 m above the floor. Returns the
/// free cells' component labels (4-connected) and the grid geometry.
struct Grid {
    origin: Point2,
    nx: usize,
    ny: usize,
    label: Vec<Option<usize>>,
    components: usize,
}

const CELL: Real = 0.025;
const HALF_ROBOT: Real = 0.1;

impl Grid {
    fn new(scene: &Scene) -> Grid {
        let b = scene
            .rooms()
            .iter()
            .map(|r| r.floor_aabb())
            .reduce(|a, b| a.union(&b))
            .unwrap();
        let origin = Point2::new(b.min.x, b.min.y);
        let nx = ((b.max.x - b.min.x) / CELL).ceil() as usize;
        let ny = ((b.max.y - b.min.y) / CELL).ceil() as usize;
        let centre =
            |i: usize, j: usize| origin + Vector2::new((i as Real + 0.5) * CELL, (j as Real + 0.5) * CELL);
        let mut free: Vec<bool> = (0..nx * ny)
            .map(|k| scene.is_over_floor(&centre(k % nx, k / nx)))
            .collect();
        // Blocks every cell whose centre is within the robot's half width of `shape`, testing
        // only the cells around `lo..hi`.
        let mut block = |lo: Point2, hi: Point2, near: &dyn Fn(&Point2) -> bool| {
            let i0 = (((lo.x - HALF_ROBOT - origin.x) / CELL).floor().max(0.0)) as usize;
            let j0 = (((lo.y - HALF_ROBOT - origin.y) / CELL).floor().max(0.0)) as usize;
            let i1 = ((((hi.x + HALF_ROBOT - origin.x) / CELL).ceil()) as usize).min(nx);
            let j1 = ((((hi.y + HALF_ROBOT - origin.y) / CELL).ceil()) as usize).min(ny);
            for j in j0..j1 {
                for i in i0..i1 {
                    if near(&centre(i, j)) {
                        free[j * nx + i] = false;
                    }
                }
            }
        };
        for (room, wall) in scene.walls() {
            // The wall's inner face minus the door openings (windows start above the robot).
            let mut cuts: Vec<[Real; 2]> = wall
                .openings()
                .iter()
                .filter(|o| o.kind == OpeningKind::Door)
                .map(|o| o.along)
                .collect();
            cuts.sort_by(|a, b| a[0].total_cmp(&b[0]));
            let mut pieces = Vec::new();
            let mut at = 0.0;
            for c in cuts {
                if c[0] > at {
                    pieces.push([at, c[0]]);
                }
                at = at.max(c[1]);
            }
            if at < wall.length() {
                pieces.push([at, wall.length()]);
            }
            let _ = room;
            for [s, t] in pieces {
                let p = wall.start() + wall.direction() * s;
                let q = wall.start() + wall.direction() * t;
                let lo = Point2::new(p.x.min(q.x), p.y.min(q.y));
                let hi = Point2::new(p.x.max(q.x), p.y.max(q.y));
                block(lo, hi, &|c: &Point2| segment_distance(c, &p, &q) < HALF_ROBOT);
            }
        }
        for o in scene.objects() {
            let floor_z = scene
                .room_at(&Point2::new(o.pose().translation.x, o.pose().translation.y))
                .map_or(0.0, |r| r.floor_z());
            if o.world_aabb().min.z >= floor_z + 2.0 {
                continue;
            }
            let corners = o.obb().corners();
            let footprint = Polygon2::new(
                [0usize, 1, 3, 2]
                    .iter()
                    .map(|&k| Point2::new(corners[k].x, corners[k].y))
                    .collect(),
            )
            .unwrap();
            let a = o.world_aabb();
            block(
                Point2::new(a.min.x, a.min.y),
                Point2::new(a.max.x, a.max.y),
                &|c: &Point2| footprint.signed_distance(c) < HALF_ROBOT,
            );
        }
        // 4-connected components.
        let mut label = vec![None; nx * ny];
        let mut components = 0;
        for start in 0..nx * ny {
            if !free[start] || label[start].is_some() {
                continue;
            }
            let mut queue = VecDeque::from([start]);
            label[start] = Some(components);
            while let Some(k) = queue.pop_front() {
                let (i, j) = (k % nx, k / nx);
                let mut next = Vec::with_capacity(4);
                if i > 0 {
                    next.push(k - 1);
                }
                if i + 1 < nx {
                    next.push(k + 1);
                }
                if j > 0 {
                    next.push(k - nx);
                }
                if j + 1 < ny {
                    next.push(k + nx);
                }
                for n in next {
                    if free[n] && label[n].is_none() {
                        label[n] = Some(components);
                        queue.push_back(n);
                    }
                }
            }
            components += 1;
        }
        Grid {
            origin,
            nx,
            ny,
            label,
            components,
        }
    }

    fn label_at(&self, p: &Point2) -> Option<usize> {
        let i = ((p.x - self.origin.x) / CELL).floor();
        let j = ((p.y - self.origin.y) / CELL).floor();
        if i < 0.0 || j < 0.0 || i as usize >= self.nx || j as usize >= self.ny {
            return None;
        }
        self.label[j as usize * self.nx + i as usize]
    }
}

fn segment_distance(c: &Point2, p: &Point2, q: &Point2) -> Real {
    let d = q - p;
    let t = ((c - p).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (c - (p + d * t)).norm()
}

/// Whether the free floor is one region reaching every door (the cell 0.2 m in front of the
/// door's middle, on its room side, belongs to it).
fn navigable(scene: &Scene) -> bool {
    let grid = Grid::new(scene);
    grid.components == 1
        && scene
            .openings()
            .filter(|(_, _, o)| o.kind == OpeningKind::Door)
            .all(|(_, wall, door)| {
                let mid = wall.point_on_inner_face(0.5 * (door.along[0] + door.along[1]), 0.0);
                let probe = Point2::new(mid.x, mid.y) + wall.inward_normal() * 0.2;
                grid.label_at(&probe) == Some(0)
            })
}

#[test]
fn navigability_claims_hold() {
    for (e, scene) in scenes() {
        if let Some(claim) = e.navigable {
            assert_eq!(navigable(scene), claim, "scene {}", e.id);
        }
        // A blocked door leaves the floor itself in one piece: only the door is cut off.
        if !e.blocked_doors.is_empty() {
            assert_eq!(Grid::new(scene).components, 1, "scene {}", e.id);
        }
    }
}

#[test]
fn annotation_rows_match_the_scenes() {
    let f = fixture();
    let all = Annotations::read_csv(f.dir.join("annotations/fixture_scenes.csv")).unwrap();
    assert!(all.validate().iter().all(|x| x.severity != Severity::Error));
    for (e, scene) in scenes() {
        let row = all.get(&e.id.to_string()).unwrap();
        assert_eq!(row.description, e.description);
        // Every ObjCount entry holds: count objects per category (spaces as `_`).
        for c in row.obj_counts() {
            let n = scene
                .objects()
                .iter()
                .filter(|o| o.category().map(|x| x.replace(' ', "_")) == Some(c.category.clone()))
                .count();
            assert!(c.count.holds(n as u64), "scene {}: {} x {}", e.id, n, c.category);
        }
        // Every category of the scene is counted.
        let total: u64 = row.obj_counts().map(|c| c.count.quantity).sum();
        assert_eq!(total as usize, scene.objects().len());
    }
    for name in ["paper_examples.csv", "malformed.csv"] {
        assert!(f.dir.join("annotations").join(name).is_file(), "{name}");
    }
}

#[test]
fn the_navigability_check_sees_splits_narrow_gaps_and_blocked_doors() {
    use sceneeval_scene::RoomBuilder;
    let room = || {
        RoomBuilder::rectangle("r", Point2::new(0.0, 0.0), Point2::new(4.0, 4.0)).door(
            0,
            [0.5, 1.4],
            [0.0, 2.1],
        )
    };
    // A shelf along y = 2 from the west wall, `length` long, 0.3 deep, `z` its centre height.
    let with_shelf = |length: Real, z: Real| {
        Scene::builder()
            .room_builder(room())
            .add_box(
                "shelf",
                Category::new("bookshelf"),
                Vector3::new(length, 0.3, 0.2) * 0.5,
                pose_from_yaw(Point3::new(0.5 * length, 2.0, z), 0.0),
            )
            .build()
            .unwrap()
    };
    assert!(navigable(&Scene::builder().room_builder(room()).build().unwrap()));
    // Wall to wall: two regions.
    let split = with_shelf(4.0, 0.1);
    assert_eq!(Grid::new(&split).components, 2);
    assert!(!navigable(&split));
    // A 0.15 m gap is narrower than the 0.2 m robot; a 0.3 m gap leaves 0.1 m of free centres.
    assert!(!navigable(&with_shelf(3.85, 0.1)));
    assert!(navigable(&with_shelf(3.7, 0.1)));
    // The same wall-to-wall shelf hung with its bottom at 2.4 m is ignored.
    assert!(navigable(&with_shelf(4.0, 2.5)));
    // A box right in front of the door makes it unreachable although the floor stays connected.
    let blocked = Scene::builder()
        .room_builder(room())
        .add_box(
            "w",
            Category::new("wardrobe"),
            Vector3::new(0.5, 0.3, 1.0),
            pose_from_yaw(Point3::new(0.95, 0.3, 1.0), 0.0),
        )
        .build()
        .unwrap();
    assert_eq!(Grid::new(&blocked).components, 1);
    assert!(!navigable(&blocked));
}

#[test]
fn vertex_depth_of_two_boxes() {
    // Unit boxes whose centres are 0.9 m apart in x overlap by 0.1 m; the corners of each
    // inside the other are 0.1 m from the nearest face.
    let a = SceneObject::new_box(
        "a",
        Vector3::repeat(0.5),
        pose_from_yaw(Point3::new(0.0, 0.0, 0.5), 0.0),
    )
    .unwrap();
    let b = SceneObject::new_box(
        "b",
        Vector3::new(0.5, 0.25, 0.25),
        pose_from_yaw(Point3::new(0.9, 0.2, 0.6), 0.0),
    )
    .unwrap();
    assert!((vertex_depth(&a, &b) - 0.1).abs() < 1e-12);
    let far = SceneObject::new_box(
        "c",
        Vector3::repeat(0.5),
        pose_from_yaw(Point3::new(3.0, 0.0, 0.5), 0.0),
    )
    .unwrap();
    assert_eq!(vertex_depth(&a, &far), 0.0);
}
