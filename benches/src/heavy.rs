//! Furniture-like non-convex meshes of realistic size, and the fixture rooms furnished with
//! them.
//!
//! Real furniture meshes (Objaverse, HSSD) are not reachable from the measurement machine, and
//! the fixture furniture (`fixtures/assets`, 24 to 168 triangles) is far lighter than what a
//! generator places. These meshes are the honest substitute for the stability measurement: a
//! chair with four legs and a back (9,600 triangles), a table with four legs and two aprons
//! (16,464), a sofa with feet, arms, a back and two cushions (38,880), an open shelf with five
//! boards and a back (13,824) and a floor lamp with a base, a pole and a wide shade (40,048),
//! each made of closed parts (finely split boxes, a fine UV ellipsoid) that touch without being
//! merged, as many real assets are. They are generated here, deterministically, never stored.
//!
//! [`heavy_rooms`] puts them in place of the fixture meshes of the same kind in five of the
//! twelve fixture rooms ([`HEAVY_ROOMS`]), each fitted to the bounds of the mesh it replaces so
//! that every object keeps its place, its support and its contacts.

use std::sync::Arc;

use sceneeval_geom::{Mesh, Vector3};
use sceneeval_scene::{Scene, SceneError, SceneObject};

/// The fixture rooms (`fixtures/scenes/scene_N.json`) whose chairs, tables, desks, sofas,
/// bookshelves and lamps [`heavy_rooms`] replaces: the living rooms 1 and 7, the dining room 2
/// and the studies 3 and 6.
pub const HEAVY_ROOMS: [usize; 5] = [1, 2, 3, 6, 7];

/// The kinds of generated furniture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HeavyKind {
    /// Four legs, a seat, two back posts and a back panel.
    Chair,
    /// A top, four legs and two aprons.
    Table,
    /// Four feet, a base, a back, two arms and two seat cushions.
    Sofa,
    /// Two sides, a back and five boards (open to the front).
    Shelf,
    /// A flat base, a thin pole and a wide ellipsoidal shade.
    Lamp,
}

impl HeavyKind {
    /// The kind that replaces a fixture asset, from the last segment of its model id
    /// (`fixture.coffee_table` gives [`HeavyKind::Table`]); `None` for the other assets.
    pub fn of_asset(model_id: &str) -> Option<HeavyKind> {
        match model_id.rsplit('.').next()? {
            "chair" => Some(HeavyKind::Chair),
            "dining_table" | "coffee_table" | "desk" => Some(HeavyKind::Table),
            "sofa" => Some(HeavyKind::Sofa),
            "bookshelf" => Some(HeavyKind::Shelf),
            "floor_lamp" | "table_lamp" => Some(HeavyKind::Lamp),
            _ => None,
        }
    }
}

/// One closed part, in the unit frame of [`heavy_mesh`].
enum Part {
    /// An axis-aligned box from `min` to `max`, each face split `n` x `n` (`12 n^2` triangles).
    Box([f64; 3], [f64; 3], u32),
    /// An ellipsoid: centre, half extents, segments, rings (`2 s (r - 1)` triangles).
    Ellipsoid([f64; 3], [f64; 3], u32, u32),
}

fn parts(kind: HeavyKind) -> Vec<Part> {
    use Part::{Box as B, Ellipsoid as E};
    // Unit frame: x across, y from front (-0.5) to back (+0.5), z up from 0 to 1.
    let legs = |w: f64, h: f64, n: u32| {
        [(-0.5, -0.5), (0.5 - w, -0.5), (-0.5, 0.5 - w), (0.5 - w, 0.5 - w)]
            .map(|(x, y)| B([x, y, 0.0], [x + w, y + w, h], n))
    };
    match kind {
        HeavyKind::Chair => {
            let mut p: Vec<Part> = legs(0.1, 0.45, 10).into();
            p.extend([
                B([-0.5, -0.5, 0.45], [0.5, 0.5, 0.52], 10),
                B([-0.5, 0.4, 0.52], [-0.4, 0.5, 1.0], 10),
                B([0.4, 0.4, 0.52], [0.5, 0.5, 1.0], 10),
                B([-0.4, 0.42, 0.65], [0.4, 0.48, 0.95], 10),
            ]);
            p
        }
        HeavyKind::Table => {
            let mut p: Vec<Part> = legs(0.08, 0.94, 14).into();
            p.extend([
                B([-0.5, -0.5, 0.94], [0.5, 0.5, 1.0], 14),
                B([-0.42, -0.46, 0.86], [0.42, -0.42, 0.94], 14),
                B([-0.42, 0.42, 0.86], [0.42, 0.46, 0.94], 14),
            ]);
            p
        }
        HeavyKind::Sofa => {
            let mut p: Vec<Part> = legs(0.06, 0.1, 18).into();
            p.extend([
                B([-0.5, -0.5, 0.1], [0.5, 0.5, 0.42], 18),
                B([-0.5, 0.3, 0.42], [0.5, 0.5, 1.0], 18),
                B([-0.5, -0.5, 0.42], [-0.38, 0.3, 0.7], 18),
                B([0.38, -0.5, 0.42], [0.5, 0.3, 0.7], 18),
                B([-0.38, -0.48, 0.42], [0.0, 0.3, 0.55], 18),
                B([0.0, -0.48, 0.42], [0.38, 0.3, 0.55], 18),
            ]);
            p
        }
        HeavyKind::Shelf => {
            let mut p = vec![
                B([-0.5, -0.5, 0.0], [-0.46, 0.5, 1.0], 12),
                B([0.46, -0.5, 0.0], [0.5, 0.5, 1.0], 12),
                B([-0.46, 0.46, 0.0], [0.46, 0.5, 1.0], 12),
            ];
            p.extend([0.0, 0.24, 0.48, 0.72, 0.97].map(|z| B([-0.46, -0.5, z], [0.46, 0.46, z + 0.03], 12)));
            p
        }
        HeavyKind::Lamp => vec![
            B([-0.3, -0.3, 0.0], [0.3, 0.3, 0.05], 10),
            B([-0.03, -0.03, 0.05], [0.03, 0.03, 0.7], 8),
            E([0.0, 0.0, 0.85], [0.5, 0.5, 0.15], 160, 120),
        ],
    }
}

/// The mesh of one kind in its unit frame: x and y from -0.5 to 0.5 (front at -y), z from 0
/// to 1, every part a closed surface.
///
/// # Panics
/// Never: the parts are fixed, finite and non-degenerate.
#[allow(clippy::expect_used)]
pub fn heavy_mesh(kind: HeavyKind) -> Mesh {
    let parts = parts(kind).into_iter().map(|part| match part {
        Part::Box(min, max, n) => {
            let (min, max) = (Vector3::from(min), Vector3::from(max));
            let mesh = Mesh::subdivided_box(&((max - min) / 2.0), n).expect("box part");
            (mesh, (min + max) / 2.0)
        }
        Part::Ellipsoid(c, h, s, r) => {
            let mesh = Mesh::uv_ellipsoid(&Vector3::from(h), s, r).expect("ellipsoid part");
            (mesh, Vector3::from(c))
        }
    });
    sceneeval_test_support::scenes::joined(parts).expect("heavy furniture mesh")
}

/// `mesh` stretched along each axis to span exactly `target`'s bounds; `None` when either mesh
/// is flat along an axis.
fn fitted(mesh: &Mesh, target: &Mesh) -> Option<Mesh> {
    let (s, t) = (mesh.aabb(), target.aabb());
    let (se, te) = (s.max - s.min, t.max - t.min);
    if (0..3).any(|k| se[k] <= 0.0 || te[k] <= 0.0) {
        return None;
    }
    let vertices = mesh
        .vertices()
        .iter()
        .map(|p| t.min + (p - s.min).component_mul(&te).component_div(&se))
        .collect();
    Mesh::new(vertices, mesh.triangles().to_vec()).ok()
}

/// `scene` with the mesh of every object whose asset has a [`HeavyKind`] replaced by that
/// kind's [`heavy_mesh`], fitted to the bounds of the mesh it replaces (same pose, same
/// metadata). Returns the scene and the number of objects replaced.
///
/// # Errors
/// What [`Scene::new`] or [`SceneObject::from_mesh`] reject (never for a scene that was
/// already valid).
pub fn refurnished(scene: &Scene) -> Result<(Scene, usize), SceneError> {
    let kinds = [
        HeavyKind::Chair,
        HeavyKind::Table,
        HeavyKind::Sofa,
        HeavyKind::Shelf,
        HeavyKind::Lamp,
    ];
    let unit: Vec<(HeavyKind, Mesh)> = kinds.iter().map(|&k| (k, heavy_mesh(k))).collect();
    let mut replaced = 0;
    let mut objects = Vec::with_capacity(scene.objects().len());
    for o in scene.objects() {
        let mesh = o
            .model_id()
            .and_then(HeavyKind::of_asset)
            .and_then(|k| unit.iter().find(|(u, _)| *u == k))
            .and_then(|(_, m)| fitted(m, o.mesh()));
        let Some(mesh) = mesh else {
            objects.push(o.clone());
            continue;
        };
        replaced += 1;
        let mut n = SceneObject::from_mesh(o.id().clone(), Arc::new(mesh), *o.pose())?.with_scale(o.scale());
        if let Some(v) = o.model_id() {
            n = n.with_model_id(v);
        }
        if let Some(v) = o.index() {
            n = n.with_index(v);
        }
        if let Some(v) = o.category() {
            n = n.with_category(v);
        }
        if let Some(v) = o.description() {
            n = n.with_description(v);
        }
        if let Some(v) = o.support_type() {
            n = n.with_support_type(v);
        }
        if let Some(v) = o.functional_sides() {
            n = n.with_functional_sides(v.iter().copied());
        }
        if let Some(v) = o.asset_front() {
            n = n.with_asset_front(v);
        }
        objects.push(n);
    }
    let scene = Scene::new(scene.name().map(str::to_owned), objects, scene.rooms().to_vec())?;
    Ok((scene, replaced))
}

/// The twelve fixture rooms with [`HEAVY_ROOMS`] refurnished by [`refurnished`] (the others
/// unchanged), and the number of objects replaced.
///
/// # Errors
/// As [`refurnished`].
pub fn heavy_rooms(rooms: &[Scene]) -> Result<(Vec<Scene>, usize), SceneError> {
    let mut total = 0;
    let mut out = Vec::with_capacity(rooms.len());
    for (i, s) in rooms.iter().enumerate() {
        if HEAVY_ROOMS.contains(&i) {
            let (s, n) = refurnished(s)?;
            total += n;
            out.push(s);
        } else {
            out.push(s.clone());
        }
    }
    Ok((out, total))
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::Point3;

    #[test]
    fn meshes_have_the_documented_sizes_and_span_the_unit_frame() {
        // Chair: 8 boxes split 10 (12 * 100 = 1,200 each) = 9,600. Table: 7 boxes split 14
        // (2,352) = 16,464. Sofa: 10 boxes split 18 (3,888) = 38,880. Shelf: 8 boxes split 12
        // (1,728) = 13,824. Lamp: base 1,200 + pole 12 * 8^2 = 768 + shade 2 * 160 * 119 =
        // 38,080: 40,048.
        for (kind, tris) in [
            (HeavyKind::Chair, 9_600),
            (HeavyKind::Table, 16_464),
            (HeavyKind::Sofa, 38_880),
            (HeavyKind::Shelf, 13_824),
            (HeavyKind::Lamp, 40_048),
        ] {
            let m = heavy_mesh(kind);
            assert_eq!(m.triangles().len(), tris, "{kind:?}");
            let b = m.aabb();
            assert!(
                (b.min - Point3::new(-0.5, -0.5, 0.0)).norm() < 1e-9,
                "{kind:?} {b:?}"
            );
            assert!(
                (b.max - Point3::new(0.5, 0.5, 1.0)).norm() < 1e-9,
                "{kind:?} {b:?}"
            );
        }
    }

    #[test]
    fn fitting_keeps_the_target_bounds() {
        let target = Mesh::cuboid(&Vector3::new(0.3, 0.2, 0.4)).unwrap();
        let f = fitted(&heavy_mesh(HeavyKind::Chair), &target).unwrap();
        assert!((f.aabb().min - target.aabb().min).norm() < 1e-9);
        assert!((f.aabb().max - target.aabb().max).norm() < 1e-9);
    }
}
