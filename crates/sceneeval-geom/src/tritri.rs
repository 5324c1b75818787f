//! Whether two placed surfaces touch or cross: a simultaneous descent of both meshes'
//! triangle hierarchies ([`crate::solid::TriangleTree`]) that stops at the first pair of
//! triangles meeting (Moeller's interval test, coplanar pairs by their overlap in the plane).

use crate::solid::SolidTables;
use crate::{Isometry3, Mesh, Point3, Real, Vector3};

/// A vertex distance to the other triangle's plane below this (relative to the triangles'
/// size) counts as on the plane.
const PLANE_EPS: Real = 1e-12;

/// Whether the surfaces of `a` and `b` touch or cross; `t` maps `b`'s frame into `a`'s.
pub(crate) fn surfaces_meet(a: &Mesh, ta: &SolidTables, b: &Mesh, tb: &SolidTables, t: &Isometry3) -> bool {
    let (na, nb) = (&ta.tree.nodes, &tb.tree.nodes);
    if na.is_empty() || nb.is_empty() {
        return false;
    }
    let r = t.rotation.to_rotation_matrix();
    let r_abs = r.matrix().abs();
    let inv = t.inverse();
    let rt_abs = r.matrix().transpose().abs();
    // A node of `b` as a box in `a`'s frame, and a node of `a` in `b`'s frame.
    let overlap = |ia: usize, ib: usize| {
        let (x, y) = (&na[ia], &nb[ib]);
        let (ca, ha) = (nalgebra::center(&x.lo, &x.hi), (x.hi - x.lo) * 0.5);
        let (cb, hb) = (nalgebra::center(&y.lo, &y.hi), (y.hi - y.lo) * 0.5);
        let cb_in_a = t * cb;
        let hb_in_a = r_abs * hb;
        if (0..3).any(|k| (cb_in_a[k] - ca[k]).abs() > ha[k] + hb_in_a[k]) {
            return false;
        }
        let ca_in_b = inv * ca;
        let ha_in_b = rt_abs * ha;
        (0..3).all(|k| (ca_in_b[k] - cb[k]).abs() <= hb[k] + ha_in_b[k])
    };
    // Squared distance between two nodes' centres (in `a`'s frame): closer pairs first.
    let gap = |ia: usize, ib: usize| {
        let (x, y) = (&na[ia], &nb[ib]);
        (nalgebra::center(&x.lo, &x.hi) - t * nalgebra::center(&y.lo, &y.hi)).norm_squared()
    };
    let mut stack: Vec<(usize, usize)> = vec![(0, 0)];
    let mut moved: Vec<([Point3; 3], Point3, Point3)> = Vec::with_capacity(8);
    while let Some((ia, ib)) = stack.pop() {
        if !overlap(ia, ib) {
            continue;
        }
        let (x, y) = (&na[ia], &nb[ib]);
        match (x.is_leaf(), y.is_leaf()) {
            (true, true) => {
                // Each triangle against the other leaf's box first, then pairs whose boxes meet.
                let (alo, ahi) = (x.lo, x.hi);
                moved.clear();
                for &k in tb.tree.leaf(ib) {
                    let v = b.triangle(k as usize).map(|p| t * p);
                    let (lo, hi) = tri_box(&v);
                    if boxes_meet(&lo, &hi, &alo, &ahi) {
                        moved.push((v, lo, hi));
                    }
                }
                if moved.is_empty() {
                    continue;
                }
                for &k in ta.tree.leaf(ia) {
                    let u = a.triangle(k as usize);
                    let (lo, hi) = tri_box(&u);
                    if moved
                        .iter()
                        .any(|(v, vlo, vhi)| boxes_meet(&lo, &hi, vlo, vhi) && triangles_meet(&u, v))
                    {
                        return true;
                    }
                }
            }
            (false, true) => {
                let [l, rr] = ta.tree.children(ia);
                push_nearer_last(&mut stack, (l, ib), (rr, ib), &gap);
            }
            (true, false) => {
                let [l, rr] = tb.tree.children(ib);
                push_nearer_last(&mut stack, (ia, l), (ia, rr), &gap);
            }
            (false, false) => {
                // Open the larger node.
                if (x.hi - x.lo).norm_squared() >= (y.hi - y.lo).norm_squared() {
                    let [l, rr] = ta.tree.children(ia);
                    push_nearer_last(&mut stack, (l, ib), (rr, ib), &gap);
                } else {
                    let [l, rr] = tb.tree.children(ib);
                    push_nearer_last(&mut stack, (ia, l), (ia, rr), &gap);
                }
            }
        }
    }
    false
}

fn tri_box(t: &[Point3; 3]) -> (Point3, Point3) {
    (t[0].inf(&t[1]).inf(&t[2]), t[0].sup(&t[1]).sup(&t[2]))
}

fn boxes_meet(alo: &Point3, ahi: &Point3, blo: &Point3, bhi: &Point3) -> bool {
    (0..3).all(|k| alo[k] <= bhi[k] && blo[k] <= ahi[k])
}

/// Pushes two node pairs so that the one whose centres lie nearer is popped first.
fn push_nearer_last(
    stack: &mut Vec<(usize, usize)>,
    p: (usize, usize),
    q: (usize, usize),
    gap: &impl Fn(usize, usize) -> Real,
) {
    if gap(p.0, p.1) <= gap(q.0, q.1) {
        stack.push(q);
        stack.push(p);
    } else {
        stack.push(p);
        stack.push(q);
    }
}

/// Signed distances of `p`'s corners to the plane `n . x + d = 0`, those within `eps` set to 0.
fn plane_distances(p: &[Point3; 3], n: &Vector3, d: Real, eps: Real) -> [Real; 3] {
    p.map(|q| {
        let s = n.dot(&q.coords) + d;
        if s.abs() <= eps { 0.0 } else { s }
    })
}

/// Whether two triangles touch or cross (Moeller 1997; coplanar triangles by edge crossings
/// and containment in their common plane).
pub(crate) fn triangles_meet(v: &[Point3; 3], u: &[Point3; 3]) -> bool {
    let scale = v
        .iter()
        .chain(u.iter())
        .map(|p| p.coords.amax())
        .fold(1.0, Real::max);
    let n1 = (v[1] - v[0]).cross(&(v[2] - v[0]));
    let d1 = -n1.dot(&v[0].coords);
    let du = plane_distances(u, &n1, d1, PLANE_EPS * scale * n1.norm());
    if (du[0] > 0.0 && du[1] > 0.0 && du[2] > 0.0) || (du[0] < 0.0 && du[1] < 0.0 && du[2] < 0.0) {
        return false;
    }
    let n2 = (u[1] - u[0]).cross(&(u[2] - u[0]));
    let d2 = -n2.dot(&u[0].coords);
    let dv = plane_distances(v, &n2, d2, PLANE_EPS * scale * n2.norm());
    if (dv[0] > 0.0 && dv[1] > 0.0 && dv[2] > 0.0) || (dv[0] < 0.0 && dv[1] < 0.0 && dv[2] < 0.0) {
        return false;
    }
    if du == [0.0; 3] {
        return coplanar_meet(&n1, v, u);
    }
    let dir = n1.cross(&n2);
    let axis = dir.iamax();
    let (Some(a), Some(b)) = (interval(v, &dv, axis), interval(u, &du, axis)) else {
        return coplanar_meet(&n1, v, u);
    };
    a.0 <= b.1 && b.0 <= a.1
}

/// The interval the triangle's crossing of the other plane covers, projected on `axis`.
fn interval(p: &[Point3; 3], d: &[Real; 3], axis: usize) -> Option<(Real, Real)> {
    let mut ts: Vec<Real> = Vec::with_capacity(3);
    for i in 0..3 {
        let j = (i + 1) % 3;
        if d[i] == 0.0 {
            ts.push(p[i][axis]);
        }
        if (d[i] > 0.0 && d[j] < 0.0) || (d[i] < 0.0 && d[j] > 0.0) {
            let s = d[i] / (d[i] - d[j]);
            ts.push(p[i][axis] + (p[j][axis] - p[i][axis]) * s);
        }
    }
    let lo = ts.iter().copied().fold(Real::INFINITY, Real::min);
    let hi = ts.iter().copied().fold(Real::NEG_INFINITY, Real::max);
    (lo <= hi).then_some((lo, hi))
}

/// Coplanar triangles: whether their projections on the plane meet.
fn coplanar_meet(n: &Vector3, v: &[Point3; 3], u: &[Point3; 3]) -> bool {
    let drop = n.iamax();
    let (i, j) = match drop {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    let flat = |p: &Point3| (p[i], p[j]);
    let a = v.map(|p| flat(&p));
    let b = u.map(|p| flat(&p));
    for k in 0..3 {
        for l in 0..3 {
            if segments_meet(a[k], a[(k + 1) % 3], b[l], b[(l + 1) % 3]) {
                return true;
            }
        }
    }
    inside(&a, b[0]) || inside(&b, a[0])
}

fn orient(a: (Real, Real), b: (Real, Real), c: (Real, Real)) -> Real {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

fn segments_meet(p: (Real, Real), q: (Real, Real), r: (Real, Real), s: (Real, Real)) -> bool {
    let (o1, o2) = (orient(p, q, r), orient(p, q, s));
    let (o3, o4) = (orient(r, s, p), orient(r, s, q));
    if ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0))
        && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0))
    {
        return true;
    }
    let on = |a: (Real, Real), b: (Real, Real), c: (Real, Real), o: Real| {
        o == 0.0 && c.0 >= a.0.min(b.0) && c.0 <= a.0.max(b.0) && c.1 >= a.1.min(b.1) && c.1 <= a.1.max(b.1)
    };
    on(p, q, r, o1) || on(p, q, s, o2) || on(r, s, p, o3) || on(r, s, q, o4)
}

fn inside(t: &[(Real, Real); 3], p: (Real, Real)) -> bool {
    let (a, b, c) = (
        orient(t[0], t[1], p),
        orient(t[1], t[2], p),
        orient(t[2], t[0], p),
    );
    (a >= 0.0 && b >= 0.0 && c >= 0.0) || (a <= 0.0 && b <= 0.0 && c <= 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: Real, y: Real, z: Real) -> Point3 {
        Point3::new(x, y, z)
    }

    #[test]
    fn crossing_touching_and_apart_triangles() {
        let t = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
        // Pierces the first through its interior.
        assert!(triangles_meet(
            &t,
            &[p(0.2, 0.2, -1.0), p(0.3, 0.2, 1.0), p(0.2, 0.3, 1.0)]
        ));
        // Above it.
        assert!(!triangles_meet(
            &t,
            &[p(0.2, 0.2, 0.1), p(0.3, 0.2, 1.0), p(0.2, 0.3, 1.0)]
        ));
        // Touches it with a vertex.
        assert!(triangles_meet(
            &t,
            &[p(0.2, 0.2, 0.0), p(0.3, 0.2, 1.0), p(0.2, 0.3, 1.0)]
        ));
        // Crosses its plane beside it.
        assert!(!triangles_meet(
            &t,
            &[p(2.0, 2.0, -1.0), p(3.0, 2.0, 1.0), p(2.0, 3.0, 1.0)]
        ));
        // Coplanar, overlapping and disjoint; one inside the other.
        assert!(triangles_meet(
            &t,
            &[p(0.5, 0.5, 0.0), p(-0.5, 0.2, 0.0), p(0.1, -0.3, 0.0)]
        ));
        assert!(!triangles_meet(
            &t,
            &[p(2.0, 2.0, 0.0), p(3.0, 2.0, 0.0), p(2.0, 3.0, 0.0)]
        ));
        assert!(triangles_meet(
            &t,
            &[p(0.1, 0.1, 0.0), p(0.2, 0.1, 0.0), p(0.1, 0.2, 0.0)]
        ));
    }

    #[test]
    fn mesh_surfaces_agree_with_parry() {
        let a = Mesh::cuboid(&Vector3::new(0.5, 0.4, 0.3)).unwrap();
        let b = Mesh::subdivided_box(&Vector3::repeat(0.5), 5).unwrap();
        for k in 0..300 {
            let f = Real::from(k);
            let pb = Isometry3::new(
                Vector3::new(
                    1.3 * (f * 0.37).sin(),
                    1.1 * (f * 0.71).cos(),
                    0.9 * (f * 0.53).sin(),
                ),
                Vector3::new((f * 0.3).sin(), (f * 0.9).cos(), (f * 1.7).sin()),
            );
            let pa = Isometry3::identity();
            let ours = surfaces_meet(&a, a.solid(), &b, b.solid(), &(pa.inverse() * pb));
            assert_eq!(ours, a.intersects(&pa, &b, &pb), "pose {k}");
        }
    }
}
