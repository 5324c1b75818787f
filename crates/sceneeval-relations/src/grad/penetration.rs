//! The penetration depth of two boxes and its gradient, for collision penalties.

use sceneeval_geom::{Obb, Real, Vector3};

use super::BoxGrad;

/// How deep two solid boxes interpenetrate: the length of the shortest translation that
/// separates them, and its derivatives.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Penetration {
    /// The depth (metres, at least 0; 0 when the boxes only touch).
    pub depth: Real,
    /// The unit direction in which moving the second box by `depth` separates them (the
    /// first box's way out is its opposite).
    pub normal: Vector3,
    /// The depth's derivatives with respect to the first box's parameters.
    pub a: BoxGrad,
    /// With respect to the second box's.
    pub b: BoxGrad,
}

/// The penetration depth of two solid boxes and its gradient, or `None` when they are apart.
///
/// Exact: by the separating-axis theorem the depth is the smallest overlap of the two boxes'
/// projections over the 15 candidate axes (each box's three face normals and the nine cross
/// products of their edges), which include every face normal of their Minkowski difference.
/// At every pose the depth is the least of the 15 overlaps, each a smooth function of the
/// poses (its axis turning with the box or boxes it comes from), so its derivative is that of
/// the least overlap: with `n` the axis oriented from the first box toward the second,
/// `d/dc_a = n`, `d/dc_b = -n`, `d/dh_i = |n . axis_i|`, and for a yaw the turn of the box's
/// axes and of `n`. Where two axes give the same depth (a kink) the first in the order above
/// counts. Yaw is about each box's centre.
///
/// ```
/// use sceneeval_relations::grad::box_penetration;
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// let a = Obb::from_yaw(Point3::new(0.0, 0.0, 0.5), Vector3::repeat(0.5), 0.0).unwrap();
/// // Overlapping by 0.2 m along x.
/// let b = Obb::from_yaw(Point3::new(0.8, 0.1, 0.5), Vector3::repeat(0.5), 0.0).unwrap();
/// let p = box_penetration(&a, &b).unwrap();
/// assert!((p.depth - 0.2).abs() < 1e-12);
/// assert!((p.normal - Vector3::x()).norm() < 1e-12);
/// // Moving b away along x by dx reduces the depth by dx; growing a's half width adds to it.
/// assert!((p.b.center.x + 1.0).abs() < 1e-12 && (p.a.half_extents.x - 1.0).abs() < 1e-12);
/// // Apart: no penetration.
/// let c = Obb::from_yaw(Point3::new(1.2, 0.0, 0.5), Vector3::repeat(0.5), 0.0).unwrap();
/// assert!(box_penetration(&a, &c).is_none());
/// ```
pub fn box_penetration(a: &Obb, b: &Obb) -> Option<Penetration> {
    let d = b.center - a.center;
    let (ax, bx) = (axes(a), axes(b));
    let reach = |o: &Obb, axes: &[Vector3; 3], l: &Vector3| -> Real {
        (0..3).map(|i| o.half_extents[i] * l.dot(&axes[i]).abs()).sum()
    };
    let mut best: Option<(Real, Vector3, Axis)> = None;
    let mut consider = |l: Vector3, kind: Axis| -> bool {
        let overlap = reach(a, &ax, &l) + reach(b, &bx, &l) - l.dot(&d).abs();
        if overlap < 0.0 {
            return false;
        }
        if best.is_none_or(|(depth, _, _)| overlap < depth) {
            best = Some((overlap, l, kind));
        }
        true
    };
    for (i, l) in ax.iter().enumerate() {
        if !consider(*l, Axis::OfA(i)) {
            return None;
        }
    }
    for (j, l) in bx.iter().enumerate() {
        if !consider(*l, Axis::OfB(j)) {
            return None;
        }
    }
    for (i, u) in ax.iter().enumerate() {
        for (j, v) in bx.iter().enumerate() {
            // Nearly parallel edges give no axis of their own (the face axes cover them).
            if let Some(l) = u.cross(v).try_normalize(1e-9)
                && !consider(l, Axis::Cross(i, j))
            {
                return None;
            }
        }
    }
    let (depth, l, kind) = best?;
    let normal = if l.dot(&d) >= 0.0 { l } else { -l };
    // The axis turns with the boxes: its derivative with respect to each box's yaw.
    let z = Vector3::z();
    let (turn_a, turn_b) = match kind {
        // n is the axis or its opposite; it turns as it does.
        Axis::OfA(i) => (z.cross(&ax[i]) * normal.dot(&ax[i]).signum(), Vector3::zeros()),
        Axis::OfB(j) => (Vector3::zeros(), z.cross(&bx[j]) * normal.dot(&bx[j]).signum()),
        Axis::Cross(i, j) => {
            let u = ax[i].cross(&bx[j]);
            let len = u.norm();
            let unit_rate = |du: Vector3| {
                let du = if u.dot(&normal) >= 0.0 { du } else { -du };
                (du - normal * normal.dot(&du)) / len
            };
            (
                unit_rate(z.cross(&ax[i]).cross(&bx[j])),
                unit_rate(ax[i].cross(&z.cross(&bx[j]))),
            )
        }
    };
    // d/dyaw of sum_k h_k |n . axis_k| for a box whose axes turn by `own` (z x axis_k, or 0)
    // while the normal turns by `dn`.
    let reach_rate = |o: &Obb, axes: &[Vector3; 3], dn: &Vector3, own: bool| -> Real {
        (0..3)
            .map(|k| {
                let along = normal.dot(&axes[k]);
                let turn = if own { normal.dot(&z.cross(&axes[k])) } else { 0.0 };
                o.half_extents[k] * along.signum() * (dn.dot(&axes[k]) + turn)
            })
            .sum()
    };
    let yaw =
        |dn: &Vector3, of_a: bool| reach_rate(a, &ax, dn, of_a) + reach_rate(b, &bx, dn, !of_a) - dn.dot(&d);
    let half = |axes: &[Vector3; 3]| Vector3::from_fn(|k, _| normal.dot(&axes[k]).abs());
    Some(Penetration {
        depth,
        normal,
        a: BoxGrad {
            center: normal,
            half_extents: half(&ax),
            yaw: yaw(&turn_a, true),
        },
        b: BoxGrad {
            center: -normal,
            half_extents: half(&bx),
            yaw: yaw(&turn_b, false),
        },
    })
}

/// Which candidate axis gives the depth: a face normal of either box, or the cross product of
/// an edge of each.
#[derive(Debug, Clone, Copy)]
enum Axis {
    OfA(usize),
    OfB(usize),
    Cross(usize, usize),
}

fn axes(o: &Obb) -> [Vector3; 3] {
    [o.axis(0), o.axis(1), o.axis(2)]
}
