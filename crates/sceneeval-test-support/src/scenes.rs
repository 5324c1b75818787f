//! Procedural scenes for the plausibility benchmarks (`benches/benches/plausibility.rs`): rooms furnished with `n` objects whose
//! meshes have about 5,000 triangles each (tables, cabinets, lamps, paintings), placed on a
//! deterministic jittered grid with a few deliberate collisions, lamps on tables, paintings on
//! walls and lamps on the ceiling, so that every metric does real work.

use crate::Lcg;
use std::sync::Arc;

use sceneeval_geom::{Isometry3, Matrix3, Mesh, Point2, Point3, Vector3};

use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_scene::{Category, RoomBuilder, Scene, SceneObject};

/// The four meshes the benchmark scenes are made of.
#[derive(Debug, Clone)]
pub struct BenchMeshes {
    /// A table: top and four legs (boxes subdivided 9 x 9 per face), 4,860 triangles,
    /// 1.2 x 0.8 x 0.75 m, origin at the floor.
    pub table: Arc<Mesh>,
    /// A cabinet: a box subdivided 20 x 20 per face, 4,800 triangles, 0.8 x 0.5 x 1.2 m,
    /// origin at the floor.
    pub cabinet: Arc<Mesh>,
    /// A lamp shade: a UV sphere of radius 0.15 m (72 segments, 36 rings), 5,040 triangles,
    /// origin at its centre.
    pub lamp: Arc<Mesh>,
    /// A painting: a 0.8 x 0.04 x 0.6 m box subdivided 20 x 20 per face, origin at its centre.
    pub painting: Arc<Mesh>,
}

/// Builds the meshes (a few milliseconds) from `sceneeval_geom`'s procedural meshes.
///
/// # Panics
/// Never for these fixed shapes (the constructors only reject degenerate input).
#[allow(clippy::expect_used)]
pub fn meshes() -> BenchMeshes {
    let [table, cabinet, painting, lamp] = furniture(9, 20, 72, 36);
    BenchMeshes {
        table: Arc::new(table),
        cabinet: Arc::new(cabinet),
        lamp: Arc::new(lamp),
        painting: Arc::new(painting),
    }
}

const CELL: f64 = 1.6;
const WALL_HEIGHT: f64 = 2.8;

/// A square room furnished with exactly `n` objects of about 5k triangles each.
///
/// Objects cycle through: table, cabinet, lamp on the last table, cabinet, table, painting on
/// a wall, cabinet, table, lamp touching the ceiling, cabinet. Ground objects fill a grid of
/// 1.6 m cells with up to 0.2 m of jitter and random yaw; every sixth one is pushed 0.9 m
/// into its neighbour's cell (a collision). The room grows with `n` (about 2.6 m^2 per
/// object) and has a door and a window.
///
/// # Panics
/// Never: every placement is finite and the ids are unique.
#[allow(clippy::expect_used)]
pub fn scene(n: usize, meshes: &BenchMeshes) -> Scene {
    // Cells for every object that may stand on the floor: paintings that find no wall slot
    // become cabinets, so they get a cell too (the room then never runs out of cells).
    let ground = (0..n).filter(|i| !matches!(i % 10, 2 | 8)).count();
    let cols = ((ground as f64).sqrt().ceil() as usize).max(2);
    let side = cols as f64 * CELL + 0.4;
    let room = RoomBuilder::rectangle("bench", Point2::new(0.0, 0.0), Point2::new(side, side))
        .wall_height(WALL_HEIGHT)
        .door(0, [0.4, 1.3], [0.0, 2.1])
        .window(1, [1.0, 2.2], [0.9, 2.0]);
    let mut b = Scene::builder().name(format!("bench_{n}")).room_builder(room);
    let mut rng = Lcg(0x5eed ^ n as u64);
    let (mut cell, mut paintings) = (0usize, 0usize);
    let mut last_table: Option<(f64, f64)> = None;
    for i in 0..n {
        let id = format!("obj{i}");
        let kind = i % 10;
        match kind {
            2 | 8 => {
                // A lamp on the last table, or hanging from the ceiling above a cell.
                let (x, y, z, cat) = match (kind, last_table) {
                    (2, Some((x, y))) => (x, y, 0.75 + 0.15, "table_lamp"),
                    _ => {
                        let (x, y) = cell_centre(cell % (cols * cols), cols);
                        (x, y, WALL_HEIGHT - 0.15, "ceiling_lamp")
                    }
                };
                b = b.add_mesh(
                    &id,
                    Category::new(cat),
                    meshes.lamp.clone(),
                    Isometry3::translation(x, y, z),
                );
            }
            5 => {
                // Paintings along the far wall (y = side), then the west wall (x = 0).
                let along = 0.6 + 1.0 * paintings as f64;
                let slots = (side / 1.0) as usize - 1;
                let pose = if paintings < slots {
                    Isometry3::translation(along.min(side - 0.6), side - 0.02, 1.5)
                } else {
                    let along = 0.6 + 1.0 * (paintings - slots) as f64;
                    Isometry3::new(
                        Vector3::new(0.02, along.min(side - 0.6), 1.5),
                        Vector3::z() * std::f64::consts::FRAC_PI_2,
                    )
                };
                paintings += 1;
                b = b.add_mesh(&id, Category::new("painting"), meshes.painting.clone(), pose);
            }
            _ => {
                let (mut x, y) = cell_centre(cell, cols);
                let (jx, jy, yaw) = (
                    rng.next() - 0.5,
                    rng.next() - 0.5,
                    rng.next() * std::f64::consts::TAU,
                );
                x += 0.4 * jx;
                let y = y + 0.4 * jy;
                if cell % 6 == 5 {
                    x -= 0.9;
                }
                cell += 1;
                let (mesh, cat) = if matches!(kind, 0 | 4 | 7) {
                    last_table = Some((x, y));
                    (meshes.table.clone(), "table")
                } else {
                    (meshes.cabinet.clone(), "cabinet")
                };
                let yaw = if matches!(kind, 0 | 4 | 7) { 0.0 } else { yaw };
                let pose = Isometry3::new(Vector3::new(x, y, 0.0), Vector3::z() * yaw);
                b = b.add_mesh(&id, Category::new(cat), mesh, pose);
            }
        }
    }
    b.build().expect("bench scene")
}

fn cell_centre(cell: usize, cols: usize) -> (f64, f64) {
    (
        0.2 + CELL * ((cell % cols) as f64 + 0.5),
        0.2 + CELL * ((cell / cols) as f64 + 0.5),
    )
}

/// A scene the size of the fixture scenes: a 4 x 5 m bedroom with eight box objects (bed,
/// nightstands, wardrobe, desk, chair, lamp, painting), one door and one window.
///
/// # Panics
/// Never: the boxes are valid.
#[allow(clippy::expect_used)]
pub fn fixture_scene() -> Scene {
    let p = Point3::new;
    let s = Vector3::new;
    Scene::builder()
        .name("fixture_size")
        .room_builder(crate::bedroom("bedroom").window(2, [1.0, 2.5], [0.9, 2.0]))
        .add_box(
            "bed",
            Category::new("bed"),
            s(0.8, 1.0, 0.3),
            pose_from_yaw(p(2.0, 3.95, 0.3), 0.0),
        )
        .add_box(
            "nightstand_l",
            Category::new("nightstand"),
            s(0.25, 0.2, 0.3),
            pose_from_yaw(p(0.9, 4.75, 0.3), 0.0),
        )
        .add_box(
            "nightstand_r",
            Category::new("nightstand"),
            s(0.25, 0.2, 0.3),
            pose_from_yaw(p(3.1, 4.75, 0.3), 0.0),
        )
        .add_box(
            "lamp",
            Category::new("table_lamp"),
            s(0.1, 0.1, 0.2),
            pose_from_yaw(p(0.9, 4.75, 0.8), 0.0),
        )
        .add_box(
            "wardrobe",
            Category::new("wardrobe"),
            s(0.3, 0.6, 1.0),
            pose_from_yaw(p(3.7, 1.5, 1.0), std::f64::consts::FRAC_PI_2),
        )
        .add_box(
            "desk",
            Category::new("desk"),
            s(0.6, 0.3, 0.375),
            pose_from_yaw(p(0.4, 1.5, 0.375), -std::f64::consts::FRAC_PI_2),
        )
        .add_box(
            "chair",
            Category::new("chair"),
            s(0.225, 0.225, 0.45),
            pose_from_yaw(p(0.95, 1.5, 0.45), std::f64::consts::FRAC_PI_2),
        )
        .add_box(
            "painting",
            Category::new("painting"),
            s(0.3, 0.02, 0.25),
            pose_from_yaw(p(0.6, 4.98, 1.6), 0.0),
        )
        .build()
        .expect("fixture-size scene")
}

/// The four kinds of object of a scaling scene, each a named mesh (the name is the asset id
/// in a sceneState file).
#[derive(Debug, Clone)]
pub struct AssetSet {
    /// What the set is made of (`boxes`, `fixtures`, `mesh8k`).
    pub kind: String,
    /// The model-id prefix scene files use for the set (`bench` or `fixture`).
    pub prefix: String,
    /// A table (ground object whose top carries lamps).
    pub table: (String, Arc<Mesh>),
    /// A cabinet (ground object).
    pub cabinet: (String, Arc<Mesh>),
    /// A lamp (stands on tables or hangs at the ceiling).
    pub lamp: (String, Arc<Mesh>),
    /// A painting (hangs on a wall, its back at the mesh's `+y` bound).
    pub painting: (String, Arc<Mesh>),
}

/// Closed meshes of about 8,000 triangles: a table (five boxes split 11 x 11 per face, 7,260
/// triangles), a cabinet (a box split 26 x 26 per face, 8,112), a lamp (a UV sphere of 90
/// segments and 46 rings, 8,100) and a painting (a box split 26 x 26, 8,112); origins at the
/// bottom centre (the lamp and painting at their centre).
///
/// # Panics
/// Never for these fixed shapes.
#[allow(clippy::expect_used)]
pub fn mesh8k_set() -> AssetSet {
    let [table, cabinet, painting, lamp] = furniture(11, 26, 90, 46);
    AssetSet {
        kind: "mesh8k".into(),
        prefix: "bench".into(),
        table: ("table8k".into(), Arc::new(table)),
        cabinet: ("cabinet8k".into(), Arc::new(cabinet)),
        lamp: ("lamp8k".into(), Arc::new(lamp)),
        painting: ("painting8k".into(), Arc::new(painting)),
    }
}

/// The bounding boxes of [`mesh8k_set`] as 12-triangle box meshes.
///
/// # Panics
/// Never for these fixed shapes.
#[allow(clippy::expect_used)]
pub fn box_set() -> AssetSet {
    let m = mesh8k_set();
    let boxed = |name: &str, mesh: &Mesh| {
        let b = mesh.aabb();
        let cube = Mesh::cuboid(&b.half_extents())
            .and_then(|c| c.transformed(&Matrix3::identity(), &b.center().coords))
            .expect("box mesh");
        (name.to_owned(), Arc::new(cube))
    };
    AssetSet {
        kind: "boxes".into(),
        prefix: "bench".into(),
        table: boxed("table_box", &m.table.1),
        cabinet: boxed("cabinet_box", &m.cabinet.1),
        lamp: boxed("lamp_box", &m.lamp.1),
        painting: boxed("painting_box", &m.painting.1),
    }
}

/// A square room furnished with exactly `n` objects of `set`, laid out like [`scene`]: ground
/// objects on a grid of 1.6 m cells with up to 0.2 m of jitter and random yaw (tables
/// unturned), every sixth pushed 0.9 m into its neighbour's cell (a collision), a lamp on
/// every third table, lamps under the ceiling, paintings on the two far walls while they have
/// room (then cabinets instead, so no two paintings share a spot), and objects carrying model
/// ids `<prefix>.<name>` so that the scene can be written as a sceneState file. Every object
/// stands on its mesh's lowest point (or hangs by its highest / its back).
///
/// # Panics
/// Never: every placement is finite and the ids are unique.
#[allow(clippy::expect_used)]
pub fn scaling_scene(n: usize, set: &AssetSet) -> Scene {
    // Cells for every object that may stand on the floor: paintings that find no wall slot
    // become cabinets, so they get a cell too (the room then never runs out of cells).
    let ground = (0..n).filter(|i| !matches!(i % 10, 2 | 8)).count();
    let cols = ((ground as f64).sqrt().ceil() as usize).max(2);
    let side = cols as f64 * CELL + 0.4;
    let room = RoomBuilder::rectangle("hall", Point2::new(0.0, 0.0), Point2::new(side, side))
        .wall_height(WALL_HEIGHT)
        .door(0, [0.4, 1.3], [0.0, 2.1])
        .window(1, [1.0, 2.2], [0.9, 2.0]);
    let mut b = Scene::builder()
        .name(format!("{}_{n}", set.kind))
        .room_builder(room);
    let mut rng = Lcg(0x5eed ^ n as u64);
    let (mut cell, mut paintings) = (0usize, 0usize);
    let slots = ((side - 1.2) / 1.0).floor().max(0.0) as usize + 1;
    let mut last_table: Option<(f64, f64)> = None;
    let object = |id: &str, (name, mesh): &(String, Arc<Mesh>), pose: Isometry3, category: &str| {
        SceneObject::from_mesh(id, mesh.clone(), pose)
            .expect("finite pose")
            .with_model_id(format!("{}.{name}", set.prefix))
            .with_category(category)
    };
    for i in 0..n {
        let id = format!("obj{i}");
        let kind = i % 10;
        let painting_slot = kind == 5 && paintings < 2 * slots;
        if matches!(kind, 2 | 8) {
            let lamp = &set.lamp.1;
            let (x, y, z, cat) = match (kind, last_table) {
                (2, Some((x, y))) => (x, y, set.table.1.aabb().max.z - lamp.aabb().min.z, "table_lamp"),
                _ => {
                    let (x, y) = cell_centre(cell % (cols * cols), cols);
                    (x, y, WALL_HEIGHT - lamp.aabb().max.z, "ceiling_lamp")
                }
            };
            b = b.object(object(&id, &set.lamp, Isometry3::translation(x, y, z), cat));
        } else if painting_slot {
            let p = &set.painting.1;
            let back = p.aabb().max.y;
            let (k, wall) = (paintings % slots, paintings / slots);
            let along = 0.6 + k as f64;
            let pose = if wall == 0 {
                // The far wall (y = side), facing -y.
                Isometry3::translation(along, side - back, 1.5)
            } else {
                // The west wall (x = 0), facing +x: yaw 90 degrees maps +y (back) to -x.
                Isometry3::new(
                    Vector3::new(back, along, 1.5),
                    Vector3::z() * std::f64::consts::FRAC_PI_2,
                )
            };
            paintings += 1;
            b = b.object(object(&id, &set.painting, pose, "painting"));
        } else {
            let (mut x, y) = cell_centre(cell, cols);
            let (jx, jy, yaw) = (
                rng.next() - 0.5,
                rng.next() - 0.5,
                rng.next() * std::f64::consts::TAU,
            );
            x += 0.4 * jx;
            let y = y + 0.4 * jy;
            if cell % 6 == 5 {
                x -= 0.9;
            }
            cell += 1;
            let table = matches!(kind, 0 | 4 | 7);
            let (entry, cat, yaw) = if table {
                last_table = (cell % 3 == 1).then_some((x, y));
                (&set.table, "table", 0.0)
            } else {
                (&set.cabinet, "cabinet", yaw)
            };
            let z = -entry.1.aabb().min.z;
            let pose = Isometry3::new(Vector3::new(x, y, z), Vector3::z() * yaw);
            b = b.object(object(&id, entry, pose, cat));
        }
    }
    b.build().expect("scaling scene")
}

/// One mesh of several parts, each moved by its offset (`p + offset`), their triangles kept in
/// order: furniture made of boxes and ellipsoids for tests and benchmarks.
///
/// # Errors
/// What [`Mesh::new`] rejects (no part, or non-finite offsets).
pub fn joined(parts: impl IntoIterator<Item = (Mesh, Vector3)>) -> Result<Mesh, sceneeval_geom::GeomError> {
    let (mut vertices, mut triangles): (Vec<Point3>, Vec<[u32; 3]>) = (Vec::new(), Vec::new());
    for (part, offset) in parts {
        let base = vertices.len() as u32;
        vertices.extend(part.vertices().iter().map(|p| p + offset));
        triangles.extend(part.triangles().iter().map(|t| t.map(|i| i + base)));
    }
    Mesh::new(vertices, triangles)
}

/// The benchmark furniture at a given detail: a table (a top and four legs, each a box split
/// `table_split` times per edge), a cabinet and a painting (boxes split `box_split` times),
/// a lamp (a UV sphere of `segments` x `rings`); origins at the bottom centre (the lamp and
/// painting at their centre).
#[allow(clippy::expect_used)]
fn furniture(table_split: u32, box_split: u32, segments: u32, rings: u32) -> [Mesh; 4] {
    let table_parts = [
        (Vector3::new(0.6, 0.4, 0.025), Vector3::new(0.0, 0.0, 0.725)),
        (Vector3::new(0.03, 0.03, 0.35), Vector3::new(-0.55, -0.35, 0.35)),
        (Vector3::new(0.03, 0.03, 0.35), Vector3::new(0.55, -0.35, 0.35)),
        (Vector3::new(0.03, 0.03, 0.35), Vector3::new(-0.55, 0.35, 0.35)),
        (Vector3::new(0.03, 0.03, 0.35), Vector3::new(0.55, 0.35, 0.35)),
    ];
    let table =
        joined(table_parts.map(|(h, c)| (Mesh::subdivided_box(&h, table_split).expect("table part"), c)))
            .expect("table mesh");
    let cabinet = Mesh::subdivided_box(&Vector3::new(0.4, 0.25, 0.6), box_split)
        .and_then(|m| m.transformed(&Matrix3::identity(), &Vector3::new(0.0, 0.0, 0.6)))
        .expect("cabinet mesh");
    let painting = Mesh::subdivided_box(&Vector3::new(0.4, 0.02, 0.3), box_split).expect("painting mesh");
    let lamp = Mesh::uv_ellipsoid(&Vector3::repeat(0.15), segments, rings).expect("lamp mesh");
    [table, cabinet, painting, lamp]
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_plausibility::{PlausibilityParams, Sources, evaluate};

    #[test]
    fn scaling_scenes_keep_every_object_in_the_room() {
        // Paintings without a wall slot become cabinets; they must still find a cell.
        for n in [10usize, 700, 3000] {
            let s = scaling_scene(n, &box_set());
            assert_eq!(s.objects().len(), n);
            let floor = s.rooms()[0].floor_mesh().aabb();
            for o in s.objects() {
                let b = o.world_aabb();
                assert!(
                    b.min.x >= floor.min.x - 1.0 && b.max.x <= floor.max.x + 1e-6,
                    "{n}: {} at {b:?}",
                    o.id()
                );
                assert!(
                    b.min.y >= floor.min.y - 1e-6 && b.max.y <= floor.max.y + 1e-6,
                    "{n}: {}",
                    o.id()
                );
            }
        }
    }

    #[test]
    fn bench_scenes_have_the_advertised_shape() {
        let m = meshes();
        for mesh in [&m.table, &m.cabinet, &m.lamp, &m.painting] {
            let t = mesh.triangles().len();
            assert!((4500..=5100).contains(&t), "{t} triangles");
            assert!(mesh.is_closed());
        }
        for n in [5, 20, 50] {
            let s = scene(n, &m);
            assert_eq!(s.objects().len(), n);
            let r = evaluate(&s, &PlausibilityParams::default(), &Sources::default()).unwrap();
            println!("{n}: {:?}", r.summary);
            // Lamps, paintings and furniture are placed to be supported; only a pushed object
            // can end up unsupported (if it leaves the floor), so most are.
            assert!(r.summary.sup.unwrap() > 0.8, "{:?}", r.summary);
            if n >= 20 {
                assert_eq!(r.summary.col_sc, Some(true), "pushed objects collide");
            }
        }
        let f = fixture_scene();
        let r = evaluate(&f, &PlausibilityParams::default(), &Sources::default()).unwrap();
        assert_eq!(r.summary.sup, Some(1.0));
        assert_eq!(r.summary.col_sc, Some(false));
    }
}
