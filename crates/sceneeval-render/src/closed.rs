//! Which meshes may be drawn with back-face culling without changing the image.
//!
//! The renderer draws both sides of every triangle (assets often have flipped triangles). On
//! a CPU rasteriser most of the time goes to triangles, and for a closed mesh seen from
//! outside, the triangles facing away from the camera are always hidden behind the mesh's own
//! front faces. [`closed_outward`] recognises the meshes for which that holds: every
//! edge-connected component is a closed surface whose triangles all wind the same way and
//! whose signed volume is positive (counter-clockwise seen from outside). A flipped triangle,
//! a hole, a T-junction, a duplicated or degenerate triangle, or an inside-out component
//! makes the whole mesh fail, and it is drawn two-sided as before.

use std::cmp::Ordering;

/// A component whose signed volume is below this fraction of the cube of its bounding-box
/// diagonal counts as flat (e.g. a double-sided sheet) rather than outward.
const MIN_RELATIVE_VOLUME: f64 = 1e-6;

/// Whether the triangles `indices` (three per triangle) over `positions` form closed,
/// consistently and outwardly wound surfaces: after merging vertices with bit-identical
/// positions, every directed edge occurs once and its reverse once, no triangle repeats a
/// vertex, and every edge-connected component encloses a positive volume (counter-clockwise
/// triangles seen from outside, the renderer's front faces).
///
/// An empty mesh, or indices out of range, give `false`.
pub(crate) fn closed_outward(positions: &[[f32; 3]], indices: &[u32]) -> bool {
    if indices.is_empty() || !indices.len().is_multiple_of(3) {
        return false;
    }
    if indices.iter().any(|&i| i as usize >= positions.len()) {
        return false;
    }
    let ids = weld(positions);
    let triangles: Vec<[u32; 3]> = indices
        .chunks_exact(3)
        .map(|t| [ids[t[0] as usize], ids[t[1] as usize], ids[t[2] as usize]])
        .collect();
    if triangles.iter().any(|&[a, b, c]| a == b || b == c || a == c) {
        return false;
    }
    // Directed edges with their triangle, sorted by edge.
    let mut edges: Vec<(u64, u32)> = Vec::with_capacity(3 * triangles.len());
    for (t, &[a, b, c]) in triangles.iter().enumerate() {
        for (p, q) in [(a, b), (b, c), (c, a)] {
            edges.push((edge_key(p, q), t as u32));
        }
    }
    edges.sort_unstable();
    if edges.windows(2).any(|w| w[0].0 == w[1].0) {
        // The same directed edge twice: inconsistent winding or more than two triangles.
        return false;
    }
    // Every edge's reverse must exist; join the two triangles.
    let mut parent: Vec<u32> = (0..triangles.len() as u32).collect();
    for &(key, t) in &edges {
        let reverse = key.rotate_right(32);
        let Ok(k) = edges.binary_search_by(|e| e.0.cmp(&reverse)) else {
            return false;
        };
        union(&mut parent, t, edges[k].1);
    }
    // Signed volume and bounds per component (relative to one vertex, for precision).
    let origin = positions[indices[0] as usize].map(f64::from);
    let mut volume = vec![0.0f64; triangles.len()];
    let mut lo = vec![[f64::INFINITY; 3]; triangles.len()];
    let mut hi = vec![[f64::NEG_INFINITY; 3]; triangles.len()];
    for (t, tri) in indices.chunks_exact(3).enumerate() {
        let root = find(&mut parent, t as u32) as usize;
        let [a, b, c] = [0, 1, 2].map(|k| {
            let p = positions[tri[k] as usize];
            [0, 1, 2].map(|j| f64::from(p[j]) - origin[j])
        });
        volume[root] += dot(a, cross(b, c)) / 6.0;
        for p in [a, b, c] {
            for j in 0..3 {
                lo[root][j] = lo[root][j].min(p[j]);
                hi[root][j] = hi[root][j].max(p[j]);
            }
        }
    }
    (0..triangles.len()).all(|t| {
        if find(&mut parent, t as u32) as usize != t {
            return true;
        }
        let d = [0, 1, 2].map(|j| hi[t][j] - lo[t][j]);
        let diagonal = dot(d, d).sqrt();
        volume[t].partial_cmp(&(MIN_RELATIVE_VOLUME * diagonal.powi(3))) == Some(Ordering::Greater)
    })
}

/// One id per distinct position (bit-identical coordinates, `-0.0` taken as `0.0`).
fn weld(positions: &[[f32; 3]]) -> Vec<u32> {
    let bits = |p: &[f32; 3]| p.map(|v| if v == 0.0 { 0 } else { v.to_bits() });
    let mut order: Vec<u32> = (0..positions.len() as u32).collect();
    order.sort_unstable_by_key(|&i| bits(&positions[i as usize]));
    let mut ids = vec![0u32; positions.len()];
    let mut next = 0u32;
    for (k, &i) in order.iter().enumerate() {
        if k > 0 && bits(&positions[order[k - 1] as usize]) != bits(&positions[i as usize]) {
            next += 1;
        }
        ids[i as usize] = next;
    }
    ids
}

fn edge_key(from: u32, to: u32) -> u64 {
    (u64::from(from) << 32) | u64::from(to)
}

fn find(parent: &mut [u32], mut t: u32) -> u32 {
    while parent[t as usize] != t {
        let up = parent[parent[t as usize] as usize];
        parent[t as usize] = up;
        t = up;
    }
    t
}

fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube's 8 corners (index = x + 2y + 4z) and its 12 triangles, counter-clockwise
    /// seen from outside.
    fn cube() -> (Vec<[f32; 3]>, Vec<u32>) {
        let positions = (0..8)
            .map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32])
            .collect();
        #[rustfmt::skip]
        let indices = vec![
            0, 2, 3, 0, 3, 1, // z = 0, normal -z
            4, 5, 7, 4, 7, 6, // z = 1, normal +z
            0, 1, 5, 0, 5, 4, // y = 0, normal -y
            2, 6, 7, 2, 7, 3, // y = 1, normal +y
            0, 4, 6, 0, 6, 2, // x = 0, normal -x
            1, 3, 7, 1, 7, 5, // x = 1, normal +x
        ];
        (positions, indices)
    }

    #[test]
    fn an_outward_cube_is_closed() {
        let (p, i) = cube();
        // Its signed volume is +1 (the faces are counter-clockwise from outside).
        assert!(closed_outward(&p, &i));
    }

    #[test]
    fn an_inside_out_cube_is_not() {
        let (p, mut i) = cube();
        for t in i.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
        // Volume -1.
        assert!(!closed_outward(&p, &i));
    }

    #[test]
    fn one_flipped_triangle_or_a_hole_fails() {
        let (p, i) = cube();
        let mut flipped = i.clone();
        flipped.swap(1, 2);
        assert!(!closed_outward(&p, &flipped));
        // Without the last triangle the +x face has a hole.
        assert!(!closed_outward(&p, &i[..33]));
    }

    #[test]
    fn split_vertices_are_welded_by_position() {
        // Each triangle gets its own three vertices (as a file with per-face normals has them).
        let (p, i) = cube();
        let split: Vec<[f32; 3]> = i.iter().map(|&k| p[k as usize]).collect();
        let indices: Vec<u32> = (0..36).collect();
        assert!(closed_outward(&split, &indices));
    }

    #[test]
    fn two_cubes_are_two_components_and_each_must_be_outward() {
        let (p, i) = cube();
        let mut positions = p.clone();
        positions.extend(p.iter().map(|v| [v[0] + 3.0, v[1], v[2]]));
        let mut both = i.clone();
        both.extend(i.iter().map(|k| k + 8));
        assert!(closed_outward(&positions, &both));
        // The second cube inside out: total volume 0, and its own volume is -1.
        let mut inverted = i.clone();
        let mut second: Vec<u32> = i.iter().map(|k| k + 8).collect();
        for t in second.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
        inverted.extend(second);
        assert!(!closed_outward(&positions, &inverted));
    }

    #[test]
    fn a_double_sided_sheet_has_no_volume() {
        // A square as two triangles and the same two wound the other way: every edge has its
        // reverse, but the enclosed volume is 0.
        let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        let i = vec![0, 1, 2, 0, 2, 3, 0, 2, 1, 0, 3, 2];
        assert!(!closed_outward(&p, &i));
    }

    #[test]
    fn degenerate_or_repeated_triangles_fail() {
        let (p, mut i) = cube();
        i.extend_from_slice(&[0, 0, 1]);
        assert!(!closed_outward(&p, &i));
        let (p, mut i) = cube();
        i.extend_from_slice(&[0, 2, 3]);
        assert!(!closed_outward(&p, &i));
        assert!(!closed_outward(&p, &[]));
        assert!(!closed_outward(&p, &[0, 1, 8]));
    }
}
