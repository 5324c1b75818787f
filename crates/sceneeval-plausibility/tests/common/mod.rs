//! Shared scene builders and report invariants for the integration tests. The invariant
//! checks take any scene, so they run unchanged on the fixture scenes of `fixtures/`.

#![allow(dead_code, clippy::unwrap_used)]

use std::sync::Arc;

use sceneeval_geom::{Isometry3, Mesh, Vector3};
use sceneeval_plausibility::{Metric, PlausibilityReport};
use sceneeval_scene::{RoomBuilder, SceneBuilder};

/// A 4 m x 5 m room (x in [0, 4], y in [0, 5]), 2.8 m walls 0.1 m thick, a door in wall 0
/// (y = 0) spanning x in [1.0, 1.9] and height [0, 2.1], a window in wall 2 (y = 5).
pub fn room() -> RoomBuilder {
    sceneeval_test_support::bedroom("r0").window(2, [1.0, 2.5], [0.9, 2.0])
}

/// A scene builder with [`room`].
pub fn scene() -> SceneBuilder {
    sceneeval_scene::Scene::builder().room_builder(room())
}

/// A closed UV sphere of radius `r` with `n` rings and `2n` segments (`4n^2 - 4n` triangles).
pub fn sphere(r: f64, n: u32) -> Arc<Mesh> {
    Arc::new(Mesh::uv_ellipsoid(&Vector3::repeat(r), 2 * n, n).unwrap())
}

/// Placement of a mesh at a point, upright, turned by `yaw`.
pub fn at(x: f64, y: f64, z: f64, yaw: f64) -> Isometry3 {
    Isometry3::new(Vector3::new(x, y, z), Vector3::z() * yaw)
}

/// Checks what must hold for any scene: shares and scores in [0, 1], per-object lists in
/// scene order, counts consistent with flags.
pub fn check_invariants(r: &PlausibilityReport) {
    let unit = |x: f64| (0.0..=1.0).contains(&x);
    let n = r.object_ids.len();
    assert_eq!(r.metrics, Metric::ALL.to_vec(), "every metric ran");
    let (collision, support, accessibility, out_of_bounds, nav, clearance) = (
        r.collision.as_ref().unwrap(),
        r.support.as_ref().unwrap(),
        r.accessibility.as_ref().unwrap(),
        r.out_of_bounds.as_ref().unwrap(),
        r.navigability.as_ref().unwrap(),
        r.opening_clearance.as_ref().unwrap(),
    );
    assert_eq!(collision.objects.len(), n);
    assert_eq!(support.objects.len(), n);
    assert_eq!(accessibility.objects.len(), n);
    assert_eq!(out_of_bounds.objects.len(), n);
    for share in [r.summary.col_ob, r.summary.sup, r.summary.acc, r.summary.oob]
        .into_iter()
        .flatten()
    {
        assert!(unit(share), "{share}");
    }
    assert!(unit(r.summary.nav.unwrap()));
    assert_eq!(
        collision.num_in_collision,
        collision.objects.iter().filter(|o| o.in_collision).count()
    );
    assert_eq!(
        r.summary.col_sc,
        Some(collision.contacts.iter().any(|c| c.colliding))
    );
    for c in &collision.contacts {
        assert!(c.depth >= 0.0 && c.depth.is_finite());
    }
    for o in &support.objects {
        assert!((o.gravity.norm() - 1.0).abs() < 1e-12);
        assert!(o.num_contacts <= o.num_ray_origins);
    }
    for o in &accessibility.objects {
        for s in &o.sides {
            assert!(unit(s.score));
            assert!(s.free_area <= s.on_floor_area + 1e-9 && s.on_floor_area <= s.strip_area + 1e-9);
        }
    }
    for o in &out_of_bounds.objects {
        assert!(unit(o.ratio_in_bounds));
    }
    assert!(nav.largest_component_pixels <= nav.free_pixels && nav.free_pixels <= nav.floor_pixels);
    for o in &clearance.openings {
        for s in &o.sides {
            assert!(unit(s.occluded_fraction));
            assert_eq!(s.blocked, !s.blocking.is_empty());
        }
    }
}
