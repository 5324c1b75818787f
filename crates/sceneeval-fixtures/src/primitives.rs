//! Closed, outward-wound primitive meshes in the **asset frame** (y up, front toward +z,
//! metres), from which the fixture furniture is assembled.
//!
//! Every primitive is a closed triangle surface whose triangles run counter-clockwise seen from
//! outside (the glTF convention), so its signed volume is positive. Points on the unit circle at
//! multiples of 90 degrees are snapped to exact values, so a cylinder of radius `r` spans exactly
//! `[-r, r]` along x and z and the stored files contain no `6.1e-17`-style noise.

use std::f64::consts::PI;

use sceneeval_geom::{CUBOID_TRIANGLES, cuboid_corner};

/// One named part of an asset: a closed triangle mesh in the asset frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// Part name (becomes the glTF node and mesh name).
    pub name: String,
    /// Vertex positions `[x, y, z]` in the asset frame (y up, front +z), metres.
    pub positions: Vec<[f64; 3]>,
    /// Triangles as vertex index triples, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// `(cos, sin)` of `2 pi k / n`, exact at multiples of a quarter turn.
fn unit_circle(k: usize, n: usize) -> (f64, f64) {
    let k = k % n;
    if (4 * k).is_multiple_of(n) {
        match 4 * k / n {
            0 => return (1.0, 0.0),
            1 => return (0.0, 1.0),
            2 => return (-1.0, 0.0),
            _ => return (0.0, -1.0),
        }
    }
    let a = 2.0 * PI * k as f64 / n as f64;
    (a.cos(), a.sin())
}

impl Part {
    /// An axis-aligned box spanning `min` to `max` (8 vertices, 12 triangles).
    pub fn cuboid(name: &str, min: [f64; 3], max: [f64; 3]) -> Part {
        Part {
            name: name.to_owned(),
            positions: (0..8).map(|k| cuboid_corner(k, min, max)).collect(),
            triangles: CUBOID_TRIANGLES.to_vec(),
        }
    }

    /// A vertical frustum (a cylinder when `r_bottom == r_top`) with `segments` sides: its
    /// bottom face is centred at `bottom_center`, it rises `height` along +y, and its radius
    /// goes from `r_bottom` to `r_top`. `2 + 2 segments` vertices, `4 segments` triangles.
    pub fn frustum(
        name: &str,
        bottom_center: [f64; 3],
        height: f64,
        r_bottom: f64,
        r_top: f64,
        segments: usize,
    ) -> Part {
        let n = segments.max(3);
        let [cx, y0, cz] = bottom_center;
        let y1 = y0 + height;
        let mut positions = vec![[cx, y0, cz], [cx, y1, cz]];
        for (r, y) in [(r_bottom, y0), (r_top, y1)] {
            for k in 0..n {
                let (c, s) = unit_circle(k, n);
                positions.push([cx + r * c, y, cz + s * r]);
            }
        }
        let b = |k: usize| (2 + k % n) as u32;
        let t = |k: usize| (2 + n + k % n) as u32;
        let mut triangles = Vec::with_capacity(4 * n);
        for k in 0..n {
            // Angle grows from +x toward +z, so (centre, k, k+1) faces -y.
            triangles.push([0, b(k), b(k + 1)]);
            triangles.push([1, t(k + 1), t(k)]);
            triangles.push([b(k), t(k), b(k + 1)]);
            triangles.push([b(k + 1), t(k), t(k + 1)]);
        }
        Part {
            name: name.to_owned(),
            positions,
            triangles,
        }
    }

    /// A UV sphere of `radius` about `center` with `segments` meridians and `rings` bands
    /// (poles on the y axis). With an even number of rings and a multiple of 4 segments, it
    /// spans exactly `center +- radius` along every axis.
    pub fn sphere(name: &str, center: [f64; 3], radius: f64, segments: usize, rings: usize) -> Part {
        let n = segments.max(3);
        let m = rings.max(2);
        let [cx, cy, cz] = center;
        let mut positions = vec![[cx, cy + radius, cz], [cx, cy - radius, cz]];
        for i in 1..m {
            // Polar angle i * pi / m from +y; (cos, sin) of it via the unit circle of 2m steps.
            let (cp, sp) = unit_circle(i, 2 * m);
            for k in 0..n {
                let (c, s) = unit_circle(k, n);
                positions.push([cx + radius * sp * c, cy + radius * cp, cz + radius * sp * s]);
            }
        }
        let ring = |i: usize, k: usize| (2 + (i - 1) * n + k % n) as u32;
        let mut triangles = Vec::new();
        for k in 0..n {
            triangles.push([0, ring(1, k + 1), ring(1, k)]);
            triangles.push([1, ring(m - 1, k), ring(m - 1, k + 1)]);
        }
        for i in 1..m - 1 {
            // Ring i is above ring i + 1.
            for k in 0..n {
                let (t0, t1, b0, b1) = (ring(i, k), ring(i, k + 1), ring(i + 1, k), ring(i + 1, k + 1));
                triangles.push([b0, t0, b1]);
                triangles.push([b1, t0, t1]);
            }
        }
        Part {
            name: name.to_owned(),
            positions,
            triangles,
        }
    }

    /// The part's bounds `(min, max)` in the asset frame.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut min = [f64::INFINITY; 3];
        let mut max = [f64::NEG_INFINITY; 3];
        for p in &self.positions {
            for i in 0..3 {
                min[i] = min[i].min(p[i]);
                max[i] = max[i].max(p[i]);
            }
        }
        (min, max)
    }

    /// Signed enclosed volume (divergence theorem); positive for an outward closed surface.
    pub fn signed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                let cross = [
                    b[1] * c[2] - b[2] * c[1],
                    b[2] * c[0] - b[0] * c[2],
                    b[0] * c[1] - b[1] * c[0],
                ];
                (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0
            })
            .sum()
    }
}

/// The union of the bounds of several parts, `(min, max)`.
pub fn bounds_of(parts: &[Part]) -> ([f64; 3], [f64; 3]) {
    let mut min = [f64::INFINITY; 3];
    let mut max = [f64::NEG_INFINITY; 3];
    for p in parts {
        let (lo, hi) = p.bounds();
        for i in 0..3 {
            min[i] = min[i].min(lo[i]);
            max[i] = max[i].max(hi[i]);
        }
    }
    (min, max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Every edge of a closed, consistently wound surface is used once in each direction.
    fn is_closed_and_consistent(part: &Part) -> bool {
        let mut edges = std::collections::BTreeMap::new();
        for t in &part.triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *edges.entry((a, b)).or_insert(0) += 1;
            }
        }
        edges
            .iter()
            .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
    }

    #[test]
    fn cuboid_volume_and_bounds() {
        let p = Part::cuboid("c", [-0.5, 0.0, -0.25], [0.5, 2.0, 0.25]);
        // 1.0 x 2.0 x 0.5 = 1.0 m^3.
        assert!((p.signed_volume() - 1.0).abs() < 1e-12);
        assert_eq!(p.bounds(), ([-0.5, 0.0, -0.25], [0.5, 2.0, 0.25]));
        assert!(is_closed_and_consistent(&p));
        assert_eq!(p.triangles.len(), 12);
    }

    #[test]
    fn frustum_of_four_segments_is_a_square_prism() {
        // Four segments at radius 1: a square with corners on the axes, side sqrt(2), area 2;
        // height 3 gives volume 6 exactly.
        let p = Part::frustum("f", [0.0, 0.0, 0.0], 3.0, 1.0, 1.0, 4);
        assert!((p.signed_volume() - 6.0).abs() < 1e-12);
        assert_eq!(p.bounds(), ([-1.0, 0.0, -1.0], [1.0, 3.0, 1.0]));
        assert!(is_closed_and_consistent(&p));
    }

    #[test]
    fn sphere_bounds_are_exact() {
        let p = Part::sphere("s", [1.0, 2.0, 3.0], 0.5, 8, 4);
        assert_eq!(p.bounds(), ([0.5, 1.5, 2.5], [1.5, 2.5, 3.5]));
        assert!(is_closed_and_consistent(&p));
        // Inscribed polyhedron: smaller than the ball (4/3 pi 0.5^3 = 0.5236), but most of it.
        let ball = 4.0 / 3.0 * PI * 0.125;
        let v = p.signed_volume();
        assert!(v > 0.6 * ball && v < ball, "{v}");
    }

    #[test]
    fn unit_circle_is_exact_at_quarter_turns() {
        assert_eq!(unit_circle(0, 12), (1.0, 0.0));
        assert_eq!(unit_circle(3, 12), (0.0, 1.0));
        assert_eq!(unit_circle(6, 12), (-1.0, 0.0));
        assert_eq!(unit_circle(9, 12), (0.0, -1.0));
        let (c, s) = unit_circle(1, 12);
        assert!((c - 3f64.sqrt() / 2.0).abs() < 1e-15 && (s - 0.5).abs() < 1e-15);
    }

    proptest! {
        /// Law: every frustum is a closed, consistently wound surface with positive volume, and
        /// with a multiple of four segments it spans exactly the larger radius along x and z.
        #[test]
        fn frustums_are_closed_and_outward(
            rb in 0.01f64..1.0, rt in 0.01f64..1.0, h in 0.01f64..2.0, quarter in 1usize..6,
            x in -1.0f64..1.0, z in -1.0f64..1.0,
        ) {
            let p = Part::frustum("f", [x, 0.5, z], h, rb, rt, 4 * quarter);
            prop_assert!(is_closed_and_consistent(&p));
            prop_assert!(p.signed_volume() > 0.0);
            let r = rb.max(rt);
            let (lo, hi) = p.bounds();
            prop_assert!((hi[0] - lo[0] - 2.0 * r).abs() < 1e-12);
            prop_assert!((hi[2] - lo[2] - 2.0 * r).abs() < 1e-12);
            prop_assert!((lo[1] - 0.5).abs() < 1e-15 && (hi[1] - 0.5 - h).abs() < 1e-12);
        }

        /// Law: every box is closed and outward with volume equal to the product of its sides.
        #[test]
        fn cuboids_are_closed_and_outward(
            a in prop::array::uniform3(-2.0f64..2.0), d in prop::array::uniform3(0.001f64..2.0),
        ) {
            let b = [a[0] + d[0], a[1] + d[1], a[2] + d[2]];
            let p = Part::cuboid("c", a, b);
            prop_assert!(is_closed_and_consistent(&p));
            let v = d[0] * d[1] * d[2];
            prop_assert!((p.signed_volume() - v).abs() <= 1e-9 * v.max(1.0));
        }

        /// Law: spheres are closed and outward for any resolution.
        #[test]
        fn spheres_are_closed_and_outward(n in 3usize..16, m in 2usize..10, r in 0.01f64..2.0) {
            let p = Part::sphere("s", [0.0, 0.0, 0.0], r, n, m);
            prop_assert!(is_closed_and_consistent(&p));
            prop_assert!(p.signed_volume() > 0.0);
        }
    }
}
