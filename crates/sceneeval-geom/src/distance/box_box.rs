//! Distance between two solid boxes: exact bounds first, GJK when they do not meet.

use super::{ClosestPoints, gjk_from_box};
use crate::{Obb, Point3, Real};

/// The gap between box `b` and the bounding box of `a` in `b`'s frame: a lower bound on the
/// distance between the solids.
#[inline]
pub(crate) fn frame_gap(b: &Obb, a: &Obb) -> Real {
    let rt = b.rotation.inverse();
    let m = (rt * a.rotation).into_inner();
    let t = rt * (a.center - b.center);
    let mut g2 = 0.0;
    for i in 0..3 {
        let reach = m[(i, 0)].abs() * a.half_extents.x
            + m[(i, 1)].abs() * a.half_extents.y
            + m[(i, 2)].abs() * a.half_extents.z;
        let gap = t[i].abs() - reach - b.half_extents[i];
        if gap > 0.0 {
            g2 += gap * gap;
        }
    }
    g2.sqrt()
}

/// The box-box distance when cheap bounds pin it down, else `None`.
///
/// Lower bound: the larger of the two frame gaps ([`frame_gap`] both ways). Upper bound: the
/// smallest distance from a corner of either box to the other box (a distance between two
/// points of the solids). When they agree to `1e-12` relative, the distance is the upper
/// bound: the closest points are a corner and a point of the other box, as for an object whose
/// nearest corner faces a wall. Otherwise (edge against edge, or overlapping boxes with no
/// corner inside the other) the caller runs GJK.
#[inline]
fn bracketed(a: &Obb, b: &Obb) -> Option<Bracketed> {
    let lower = frame_gap(b, a).max(frame_gap(a, b));
    let mut upper2 = Real::INFINITY;
    // The corner reaching the upper bound, and whether it is `b`'s.
    let mut at = (false, a.center);
    for (of_b, (x, y)) in [(false, (a, b)), (true, (b, a))] {
        for c in x.corners() {
            let d2 = y.distance_to_point_squared(&c);
            if d2 < upper2 {
                at = (of_b, c);
            }
            upper2 = upper2.min(d2);
        }
    }
    let upper = upper2.sqrt();
    (upper - lower <= 1e-12 * (1.0 + upper)).then_some(Bracketed { distance: upper, at })
}

/// The distance [`bracketed`] found and the corner that reaches it (whether it is the second
/// box's, and the corner).
struct Bracketed {
    distance: Real,
    at: (bool, Point3),
}

/// Distance between two solid boxes (0 when they touch or overlap): [`bracketed`] when its
/// bounds agree, else GJK on the two cuboids' support maps.
///
/// parry's dedicated `distance_cuboid_cuboid` (which `parry::query::distance` dispatches to)
/// is not used: its separating-axis shortcut can overestimate the distance by millimetres when
/// an edge of one box is closest to an edge of the other.
#[inline]
pub(crate) fn box_box(a: &Obb, b: &Obb) -> Real {
    match bracketed(a, b) {
        Some(br) => br.distance,
        None => gjk_boxes(a, b).distance,
    }
}

/// [`box_box`] with a pair of closest points (`a`'s first): for a bracketed distance the
/// corner and its closest point on the other box.
#[inline]
pub(crate) fn box_box_closest(a: &Obb, b: &Obb) -> ClosestPoints {
    let Some(Bracketed {
        distance,
        at: (of_b, c),
    }) = bracketed(a, b)
    else {
        return gjk_boxes(a, b);
    };
    let points = (distance > 0.0).then(|| {
        if of_b {
            (a.closest_point(&c), c)
        } else {
            (c, b.closest_point(&c))
        }
    });
    ClosestPoints { distance, points }
}

/// GJK between the two cuboids.
fn gjk_boxes(a: &Obb, b: &Obb) -> ClosestPoints {
    let (pa, _) = a.to_parry();
    let (pb, cb) = b.to_parry();
    gjk_from_box(a, &pa.inv_mul(&pb), &cb)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parry::query::details;
    use crate::{Point3, Rotation3, Vector3};
    use std::f64::consts::FRAC_PI_4;

    fn cube(c: [Real; 3], h: Real, yaw: Real) -> Obb {
        Obb::from_yaw(Point3::new(c[0], c[1], c[2]), Vector3::repeat(h), yaw).unwrap()
    }

    #[test]
    fn box_distances_are_exact() {
        let a = cube([0.0, 0.0, 0.0], 0.5, 0.0);
        // Face to face, 1 m gap.
        assert!((box_box(&a, &cube([2.0, 0.0, 0.0], 0.5, 0.0)) - 1.0).abs() < 1e-12);
        // Diagonal offset: gap 0.5 in x and 0.5 in y -> sqrt(0.5).
        let d = box_box(&a, &cube([1.5, 1.5, 0.0], 0.5, 0.0));
        assert!((d - 0.5f64.sqrt()).abs() < 1e-12, "{d}");
        // Corner of a 45-degree box toward a face: 1.3 - 0.5 sqrt(2) - 0.5.
        let d = box_box(&a, &cube([1.3, 0.0, 0.0], 0.5, FRAC_PI_4));
        assert!((d - (0.8 - 0.5 * 2f64.sqrt())).abs() < 1e-12, "{d}");
        // Overlapping and nested boxes are 0 apart.
        assert_eq!(box_box(&a, &cube([0.7, 0.0, 0.0], 0.5, 0.3)), 0.0);
        assert_eq!(box_box(&a, &cube([0.1, 0.0, 0.0], 0.1, 0.3)), 0.0);
    }

    #[test]
    fn box_distance_agrees_with_brute_force() {
        // Dense sampling of the second box's surface gives an upper bound that converges to
        // the exact distance; a coarse grid bounds the error by the grid spacing.
        let a = Obb::new(
            Point3::new(0.1, -0.2, 0.3),
            Vector3::new(0.6, 0.3, 0.2),
            Rotation3::from_euler_angles(0.3, -0.2, 0.7),
        )
        .unwrap();
        for (i, yaw) in [0.0, 0.4, 1.1, 2.5].into_iter().enumerate() {
            let b = Obb::new(
                Point3::new(1.4, 0.5 + 0.1 * i as Real, 0.6),
                Vector3::new(0.3, 0.5, 0.4),
                Rotation3::from_euler_angles(0.1 * i as Real, 0.5, yaw),
            )
            .unwrap();
            let exact = box_box(&a, &b);
            let n = 40;
            let mut best = Real::INFINITY;
            for ix in 0..=n {
                for iy in 0..=n {
                    for iz in 0..=n {
                        let l = Vector3::new(
                            (2.0 * ix as Real / n as Real - 1.0) * b.half_extents.x,
                            (2.0 * iy as Real / n as Real - 1.0) * b.half_extents.y,
                            (2.0 * iz as Real / n as Real - 1.0) * b.half_extents.z,
                        );
                        best = best.min(a.distance_to_point(&b.to_world(&l)));
                    }
                }
            }
            // Never above the sampled minimum, and within the grid's reach of it.
            assert!(exact <= best + 1e-12, "{exact} > {best}");
            assert!(best - exact < 0.03, "{exact} vs {best}");
        }
    }

    #[test]
    fn bracketing_agrees_with_gjk() {
        // Over a sweep of yaws and offsets, the shortcut (when it applies) equals GJK.
        let a = cube([0.0, 0.0, 0.5], 0.5, 0.0);
        let (pa, ca) = a.to_parry();
        let mut shortcuts = 0;
        for i in 0..60 {
            let yaw = 0.1 * i as Real;
            for dx in [0.9, 1.3, 2.0] {
                let b = Obb::from_yaw(
                    Point3::new(dx, 0.3 * (i % 7) as Real - 0.9, 0.4 + 0.05 * (i % 3) as Real),
                    Vector3::new(0.3, 0.2, 0.35),
                    yaw,
                )
                .unwrap();
                let (pb, cb) = b.to_parry();
                let gjk = details::distance_support_map_support_map(&pa.inv_mul(&pb), &ca, &cb);
                if let Some(d) = bracketed(&a, &b).map(|c| c.distance) {
                    shortcuts += 1;
                    assert!((d - gjk).abs() < 1e-9, "yaw {yaw} dx {dx}: {d} vs {gjk}");
                }
                assert!((box_box(&a, &b) - gjk).abs() < 1e-9);
            }
        }
        assert!(
            shortcuts > 60,
            "the shortcut should apply in most of these: {shortcuts}"
        );
    }

    #[test]
    fn box_distance_is_mirror_symmetric() {
        // Found by a mirror-symmetry law in the relations crate: parry's cuboid-cuboid
        // shortcut gives 1.781161 for the mirrored pair but 1.780385 for the original; both are
        // 1.780385 (a 60^3 grid on the second box's surface gives 1.780394).
        let r = |m: [Real; 4]| {
            Rotation3::from_matrix_unchecked(crate::Matrix3::new(
                m[0], m[1], 0.0, m[2], m[3], 0.0, 0.0, 0.0, 1.0,
            ))
        };
        let b = Obb {
            center: Point3::new(0.0, -2.375793039456613, 0.0),
            half_extents: Vector3::new(0.05, 0.4070422242028465, 0.05),
            rotation: r([
                -0.9925879607510085,
                -0.12152835131011316,
                0.12152835131011316,
                -0.9925879607510085,
            ]),
        };
        let a = Obb {
            center: Point3::new(-1.833736971811297, -1.8769287386567672, 0.0),
            half_extents: Vector3::repeat(0.05),
            rotation: r([
                0.11382045802485088,
                -0.9935013353463664,
                0.9935013353463664,
                0.11382045802485088,
            ]),
        };
        let rb = b.rotation.matrix();
        let flip = crate::Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0));
        let m = rb * flip * rb.transpose();
        let mirrored = Obb {
            center: b.center + m * (a.center - b.center),
            half_extents: a.half_extents,
            rotation: Rotation3::from_matrix_unchecked(m * a.rotation.matrix() * flip),
        };
        let (d, dm) = (a.distance_to_obb(&b), mirrored.distance_to_obb(&b));
        assert!((d - 1.780_384_815).abs() < 1e-8, "{d}");
        assert!((d - dm).abs() < 1e-9, "{d} vs {dm}");
    }
}
