//! Scaffolding shared by the workspace's tests, examples and benchmarks, so that each is
//! written once: the standard 4 x 5 m bedroom, box meshes in the `f32` form asset writers
//! take, the procedural scenes of the plausibility benchmarks ([`scenes`]), a scripted VLM for
//! fixture scenes 2 and 8 with the annotation rows its tests check ([`fidelity_model`]), a mock
//! OpenAI-compatible endpoint on 127.0.0.1 with a fixed latency that counts the requests in
//! flight at the server ([`mock_endpoint`]), a log writer tests read back ([`logs`]), and the one decision whether a test that needs a system package (a GPU driver) runs, skips with
//! the reason or fails ([`system`]). Not published; crates use it only as a dev-dependency
//! (tier `dev`).
//!
//! It depends on `sceneeval-geom` and `sceneeval-scene` only, so the unit tests of every crate
//! above them can use it (a crate's own unit tests cannot use a helper crate that depends on
//! that crate: they would see two copies of its types).
//!
//! # Example
//! ```
//! use sceneeval_test_support::bedroom;
//!
//! let room = bedroom("r0").window(2, [1.0, 2.5], [0.9, 2.0]).build().unwrap();
//! assert_eq!(room.walls().len(), 4);
//! assert_eq!(room.openings().len(), 2);
//! assert!((room.floor().area() - 20.0).abs() < 1e-12);
//! ```

pub mod fidelity_model;
pub mod logs;
pub mod mock_endpoint;
pub mod scenes;
pub mod system;

use sceneeval_geom::{CUBOID_TRIANGLES, Point2, cuboid_corner};
use sceneeval_scene::RoomBuilder;

/// The names of the entries of folder `dir`, sorted: what a test checks a command left
/// behind (no temporary file, exactly the outputs it names).
///
/// # Panics
/// When the folder cannot be read (a test's own temporary folder).
#[allow(clippy::unwrap_used)]
pub fn file_names(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Every file below folder `dir` (in its subfolders too), sorted: what a test checks about all
/// that a command wrote (permissions, content).
///
/// # Panics
/// When a folder cannot be read (a test's own temporary folder).
#[allow(clippy::unwrap_used)]
pub fn files_below(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(files_below(&path));
        } else {
            out.push(path);
        }
    }
    out.sort();
    out
}

/// A deterministic sequence of numbers in `[0, 1)` (a 64-bit linear congruential generator
/// with Knuth's constants, the top 53 bits of each state), for tests and benchmarks that need
/// the same "random" inputs on every run.
///
/// ```
/// use sceneeval_test_support::Lcg;
/// let (mut a, mut b) = (Lcg(7), Lcg(7));
/// let x = a.next();
/// assert!((0.0..1.0).contains(&x));
/// assert_eq!(x, b.next());
/// ```
#[derive(Debug, Clone)]
pub struct Lcg(pub u64);

impl Lcg {
    /// The next number, in `[0, 1)`.
    #[allow(clippy::should_implement_trait)] // Not an iterator: it never ends.
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The standard test bedroom: floor x in [0, 4], y in [0, 5] at z = 0, walls 2.8 m high and
/// 0.1 m thick (wall 0 along y = 0, wall 1 along x = 4, wall 2 along y = 5, wall 3 along
/// x = 0), and a door in wall 0 spanning x in [1.0, 1.9], 2.1 m high. Tests add their windows
/// (`.window(wall, along, height)`) and objects.
pub fn bedroom(id: &str) -> RoomBuilder {
    RoomBuilder::rectangle(id, Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
        .wall_height(2.8)
        .wall_thickness(0.1)
        .door(0, [1.0, 1.9], [0.0, 2.1])
}

/// A large, slightly concave floor outline for tests of cost: `n` points counter-clockwise
/// around the origin at radius `10 (1 + 0.05 sin 7a)` metres (a = the point's angle), every
/// other point pushed out by 1 mm so that the outline is not convex at any scale. Simple for
/// any `n` of at least 3.
///
/// ```
/// let outline = sceneeval_test_support::wobbly_outline(1000);
/// let floor = sceneeval_geom::Polygon2::new(outline).unwrap();
/// assert!(floor.is_ccw() && (floor.area() - 314.5).abs() < 1.0);
/// ```
pub fn wobbly_outline(n: u32) -> Vec<Point2> {
    (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * f64::from(i) / f64::from(n);
            let r = 10.0 * (1.0 + 0.05 * (7.0 * a).sin()) + if i % 2 == 0 { 0.0 } else { 0.001 };
            Point2::new(r * a.cos(), r * a.sin())
        })
        .collect()
}

/// Appends the 8 corners and 12 outward triangles of the axis-aligned box `[min, max]` to a
/// mesh given as `f32` positions and flat triangle indices (the form of
/// `sceneeval_io::GlbMesh`).
///
/// ```
/// let (mut p, mut i) = (Vec::new(), Vec::new());
/// sceneeval_test_support::push_cuboid(&mut p, &mut i, [0.0; 3], [1.0, 2.0, 3.0]);
/// assert_eq!((p.len(), i.len()), (8, 36));
/// assert_eq!(p[7], [1.0, 2.0, 3.0]);
/// ```
pub fn push_cuboid(positions: &mut Vec<[f32; 3]>, indices: &mut Vec<u32>, min: [f32; 3], max: [f32; 3]) {
    let base = positions.len() as u32;
    positions.extend((0..8).map(|k| cuboid_corner(k, min, max)));
    indices.extend(CUBOID_TRIANGLES.iter().flatten().map(|i| base + i));
}
