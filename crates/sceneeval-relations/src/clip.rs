//! Exact clipping on the stack: the volume of a box inside up to six half-spaces, and convex
//! polygons clipped by half-planes. Nothing here allocates (the polyhedron is a per-thread
//! scratch value, reused from call to call).
//!
//! The box is clipped as a polyhedron whose faces are kept as unordered sets of directed
//! edges, wound counter-clockwise seen from outside. Clipping a convex face by a plane keeps
//! the inside parts of its edges and closes it with one new edge from where the boundary
//! leaves the half-space to where it comes back; the reversed new edges form the cap face.
//! The volume follows from the divergence theorem, `V = 1/6 sum_f p_f . sum_e (a x b)`, which
//! needs no vertex order. An edge shared by two faces is cut at bit-identical points because
//! the cut is always computed from the inside end.
//!
//! For gradients ([`box_volume_moments`]) each face remembers where it lies (a face of the box
//! or the cap of one half-space), and the same clip also gives each face's area and first
//! moment: the volume's derivative with respect to a plane's offset is the area of the face on
//! it, with respect to its normal minus the face's first moment, and with respect to a half
//! extent of the box the area of the two faces on that axis (the boundary moves, the interior
//! does not: Reynolds' transport theorem).

use std::cell::RefCell;

use sceneeval_geom::{Point2, Real, Vector3};

/// At most this many half-spaces cut one box.
pub(crate) const MAX_PLANES: usize = 6;
/// Faces: the box's six plus one cap per plane.
const MAX_FACES: usize = 6 + MAX_PLANES;
/// Edges of one face: a box face gains at most one per plane (4 + 6); a cap face starts with
/// at most one per existing face (at most 11) and gains one per later plane (at most 11).
const MAX_EDGES: usize = 12;

/// The half-space `{x : normal . x <= offset}` (the normal need not be unit length).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HalfSpace {
    pub normal: Vector3,
    pub offset: Real,
}

impl HalfSpace {
    const NONE: HalfSpace = HalfSpace {
        normal: Vector3::new(0.0, 0.0, 0.0),
        offset: 0.0,
    };

    #[inline]
    pub(crate) fn new(normal: Vector3, offset: Real) -> Self {
        HalfSpace { normal, offset }
    }

    #[inline]
    fn excess(&self, p: &Vector3) -> Real {
        self.normal.dot(p) - self.offset
    }

    /// How far the box `[-h, h]` reaches along the normal (times its length).
    #[inline]
    fn reach(&self, h: &Vector3) -> Real {
        self.normal.x.abs() * h.x + self.normal.y.abs() * h.y + self.normal.z.abs() * h.z
    }
}

#[derive(Clone, Copy)]
struct Face {
    len: usize,
    /// Where the face lies: `0..6` a face of the box (in [`Polyhedron::set_cuboid`]'s order),
    /// `6 + k` the cap of the `k`-th plane clipped.
    label: usize,
    edges: [[Vector3; 2]; MAX_EDGES],
}

impl Face {
    const EMPTY: Face = Face {
        len: 0,
        label: 0,
        edges: [[Vector3::new(0.0, 0.0, 0.0); 2]; MAX_EDGES],
    };

    #[inline]
    fn push(&mut self, a: Vector3, b: Vector3) {
        if self.len < MAX_EDGES {
            self.edges[self.len] = [a, b];
            self.len += 1;
        }
    }
}

struct Polyhedron {
    len: usize,
    faces: [Face; MAX_FACES],
}

thread_local! {
    /// The polyhedron [`box_volume_inside`] clips, kept per thread: it is about 7 KiB, and
    /// filling a fresh one with zeros took a good part of a volume fraction's time. Only the
    /// faces and edges below their lengths are ever read, so what a previous call left beyond
    /// them does not matter.
    static SCRATCH: RefCell<Polyhedron> = const { RefCell::new(Polyhedron::EMPTY) };
}

impl Polyhedron {
    const EMPTY: Polyhedron = Polyhedron {
        len: 0,
        faces: [Face::EMPTY; MAX_FACES],
    };

    /// Makes this the box `[-h, h]` with counter-clockwise (outward) faces.
    fn set_cuboid(&mut self, h: &Vector3) {
        let v = |k: usize| {
            Vector3::new(
                if k & 1 == 0 { -h.x } else { h.x },
                if k & 2 == 0 { -h.y } else { h.y },
                if k & 4 == 0 { -h.z } else { h.z },
            )
        };
        const QUADS: [[usize; 4]; 6] = [
            [0, 2, 3, 1], // -z
            [4, 5, 7, 6], // +z
            [0, 1, 5, 4], // -y
            [2, 6, 7, 3], // +y
            [0, 4, 6, 2], // -x
            [1, 3, 7, 5], // +x
        ];
        for (label, (face, q)) in self.faces.iter_mut().zip(QUADS).enumerate() {
            face.len = 0;
            face.label = label;
            for i in 0..4 {
                face.push(v(q[i]), v(q[(i + 1) % 4]));
            }
        }
        self.len = 6;
    }

    /// Keeps the part inside `plane`; returns whether anything is left. The cap face is built
    /// in the first unused face (when there is one) and labelled `label`.
    fn clip(&mut self, plane: &HalfSpace, label: usize) -> bool {
        #[inline]
        fn cut(inside: &Vector3, d_in: Real, outside: &Vector3, d_out: Real) -> Vector3 {
            inside + (outside - inside) * (d_in / (d_in - d_out))
        }
        let len = self.len;
        let (faces, spare) = self.faces.split_at_mut(len);
        // With every face in use there is no room for a cap (never for at most MAX_PLANES
        // planes): it is then not built.
        let mut cap = spare.first_mut();
        if let Some(cap) = cap.as_deref_mut() {
            cap.len = 0;
            cap.label = label;
        }
        let mut kept = 0;
        for fi in 0..len {
            let face = &mut faces[fi];
            let mut w = 0;
            let mut exit = None;
            let mut entry = None;
            for r in 0..face.len {
                let [a, b] = face.edges[r];
                let (da, db) = (plane.excess(&a), plane.excess(&b));
                match (da <= 0.0, db <= 0.0) {
                    (true, true) => {
                        face.edges[w] = [a, b];
                        w += 1;
                    }
                    (true, false) => {
                        let p = cut(&a, da, &b, db);
                        face.edges[w] = [a, p];
                        w += 1;
                        exit = Some(p);
                    }
                    (false, true) => {
                        let p = cut(&b, db, &a, da);
                        face.edges[w] = [p, b];
                        w += 1;
                        entry = Some(p);
                    }
                    (false, false) => {}
                }
            }
            face.len = w;
            if let (Some(x), Some(e)) = (exit, entry)
                && x != e
            {
                face.push(x, e);
                if let Some(cap) = cap.as_deref_mut() {
                    cap.push(e, x);
                }
            }
            if face.len > 0 {
                if kept != fi {
                    faces[kept] = faces[fi];
                }
                kept += 1;
            }
        }
        let has_cap = cap.is_some_and(|cap| cap.len >= 3);
        if has_cap && kept != len {
            // Move the cap down next to the faces kept.
            self.faces[kept] = self.faces[len];
        }
        self.len = kept + usize::from(has_cap);
        self.len > 0
    }

    /// Enclosed volume (divergence theorem with one vertex of each face as its point).
    fn volume(&self) -> Real {
        let mut six_v = 0.0;
        for face in &self.faces[..self.len] {
            let p = face.edges[0][0];
            let mut area2 = Vector3::zeros();
            for [a, b] in &face.edges[..face.len] {
                area2 += a.cross(b);
            }
            six_v += p.dot(&area2);
        }
        (six_v / 6.0).abs()
    }

    /// Adds each face's area and first moment to `out`: box faces to
    /// [`VolumeMoments::box_area`], caps to the entry of the plane they lie on (`planes[k]` is
    /// the `k`-th plane clipped, `from[k]` its index in the caller's list), divided by the
    /// length of its normal.
    fn moments(&self, planes: &[HalfSpace], from: &[usize], out: &mut VolumeMoments) {
        for face in &self.faces[..self.len] {
            if face.len == 0 {
                continue;
            }
            // Outward unit normal: the box's axes, or the plane's normal (its outside).
            let (normal, scale) = if face.label < 6 {
                let axis = 2 - face.label / 2;
                let sign = if face.label % 2 == 0 { -1.0 } else { 1.0 };
                (Vector3::ith(axis, sign), 1.0)
            } else {
                let n = planes[face.label - 6].normal;
                let len = n.norm();
                (n / len, 1.0 / len)
            };
            // Fan from the face's first vertex: signed triangle areas along the normal and
            // their centroids (valid for any closed set of directed edges in the plane).
            let p = face.edges[0][0];
            let mut area = 0.0;
            let mut moment = Vector3::zeros();
            for [a, b] in &face.edges[..face.len] {
                let w = 0.5 * (a - p).cross(&(b - p)).dot(&normal);
                area += w;
                moment += (p + a + b) * (w / 3.0);
            }
            if face.label < 6 {
                out.box_area[2 - face.label / 2] += area;
            } else {
                let i = from[face.label - 6];
                out.plane_area[i] += area * scale;
                out.plane_moment[i] += moment * scale;
            }
        }
    }
}

/// The derivatives of [`box_volume_inside`] with respect to its inputs (see the module docs),
/// from the faces of the clipped box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct VolumeMoments {
    /// Per plane of the caller's list: the area of the clipped box's face on it over the length
    /// of its normal, `dV / d offset`.
    pub plane_area: [Real; MAX_PLANES],
    /// Per plane: the first moment `integral of x dA` of that face (box frame) over the length of
    /// the normal, `-dV / d normal`.
    pub plane_moment: [Vector3; MAX_PLANES],
    /// Per box axis: the area of the clipped box's faces on `+h` and `-h`, `dV / dh`.
    pub box_area: Vector3,
}

impl VolumeMoments {
    pub(crate) const ZERO: VolumeMoments = VolumeMoments {
        plane_area: [0.0; MAX_PLANES],
        plane_moment: [Vector3::new(0.0, 0.0, 0.0); MAX_PLANES],
        box_area: Vector3::new(0.0, 0.0, 0.0),
    };
}

/// What clipping a box by half-spaces left: all of it, nothing, or a polyhedron measured by
/// the caller.
enum Clipped<R> {
    Whole,
    Empty,
    Cut(R),
}

/// Clips the box `[-h, h]` by `planes` and measures what is left with `measure` (given the
/// polyhedron, the planes that cut and their indices in `planes`), unless no plane cuts the
/// box or one excludes it. Allocation free: the polyhedron is the per-thread scratch value.
fn clip_box<R>(
    h: &Vector3,
    planes: &[HalfSpace],
    measure: impl Fn(&Polyhedron, &[HalfSpace], &[usize]) -> R,
) -> Clipped<R> {
    let mut cutting = [HalfSpace::NONE; MAX_PLANES];
    let mut from = [0usize; MAX_PLANES];
    let mut k = 0;
    for (i, p) in planes.iter().enumerate() {
        let reach = p.reach(h);
        if reach <= p.offset {
            continue;
        }
        if -reach >= p.offset {
            return Clipped::Empty;
        }
        if k < MAX_PLANES {
            cutting[k] = *p;
            from[k] = i;
            k += 1;
        }
    }
    if k == 0 {
        return Clipped::Whole;
    }
    let clip_all = |poly: &mut Polyhedron| {
        poly.set_cuboid(h);
        for (label, p) in cutting[..k].iter().enumerate() {
            if !poly.clip(p, 6 + label) {
                return Clipped::Empty;
            }
        }
        Clipped::Cut(measure(poly, &cutting[..k], &from[..k]))
    };
    let kept = SCRATCH.try_with(|scratch| scratch.try_borrow_mut().ok().map(|mut poly| clip_all(&mut poly)));
    match kept {
        Ok(Some(clipped)) => clipped,
        // Not reached (nothing here calls back into this function, and threads are not torn
        // down while they compute); a fresh polyhedron gives the same result.
        _ => {
            let mut fresh = Polyhedron::EMPTY;
            clip_all(&mut fresh)
        }
    }
}

/// The volume of the axis-aligned box `[-h, h]` (centred at the origin) that lies inside every
/// half-space of `planes` (the box's own frame). At most [`MAX_PLANES`] half-spaces may cut
/// the box; callers never pass more than that many.
///
/// Half-spaces that do not cut the box are skipped, and one that excludes it returns 0 at
/// once, so the common cases cost a few dot products.
pub(crate) fn box_volume_inside(h: &Vector3, planes: &[HalfSpace]) -> Real {
    let full = 8.0 * h.x * h.y * h.z;
    match clip_box(h, planes, |poly, _, _| poly.volume()) {
        Clipped::Whole => full,
        Clipped::Empty => 0.0,
        Clipped::Cut(volume) => volume.min(full),
    }
}

/// The volume of the box `[-h, h]` inside `planes` when no plane cuts it: the whole box's,
/// or 0 when one excludes it (bit for bit [`box_volume_inside`]'s); `None` when one cuts it.
/// A few dot products, no clipping.
pub(crate) fn uncut_volume(h: &Vector3, planes: &[HalfSpace]) -> Option<Real> {
    let mut cut = false;
    for p in planes {
        let reach = p.reach(h);
        if reach <= p.offset {
            continue;
        }
        if -reach >= p.offset {
            return Some(0.0);
        }
        cut = true;
    }
    (!cut).then(|| 8.0 * h.x * h.y * h.z)
}

/// How [`box_volume_moments`] found the box: inside every half-space, outside one, or cut.
// Returned by value once per clip, on the stack: boxing the large variant would allocate.
#[allow(clippy::large_enum_variant)]
pub(crate) enum Moments {
    /// No half-space cuts it: `dV/dh` is the area of the box's own faces, nothing else moves
    /// the volume.
    Whole,
    /// A half-space excludes it: every derivative is 0.
    Empty,
    /// Cut: the derivatives from the clipped faces.
    Cut(VolumeMoments),
}

/// [`box_volume_inside`] (the same value, bit for bit) and its derivatives, from the same
/// clip. Where a plane only touches the box (or a face degenerates) the derivatives are
/// one-sided: those of the side the clip's comparisons put the input on.
pub(crate) fn box_volume_moments(h: &Vector3, planes: &[HalfSpace]) -> (Real, Moments) {
    let full = 8.0 * h.x * h.y * h.z;
    match clip_box(h, planes, |poly, cutting, from| {
        let mut m = VolumeMoments::ZERO;
        poly.moments(cutting, from, &mut m);
        (poly.volume(), m)
    }) {
        Clipped::Whole => (full, Moments::Whole),
        Clipped::Empty => (0.0, Moments::Empty),
        Clipped::Cut((volume, m)) => (volume.min(full), Moments::Cut(m)),
    }
}

/// Capacity of a clipped polygon: a quadrilateral clipped by up to twelve half-planes.
const MAX_POLY: usize = 16;

/// A convex polygon in the plane on the stack. Each edge (from vertex `k` to `k + 1`) carries
/// the label of the line it lies on, for gradients: the caller's labels for the polygon's own
/// edges and for each half-plane it is clipped by.
#[derive(Clone, Copy)]
pub(crate) struct Poly2 {
    len: usize,
    pts: [Point2; MAX_POLY],
    labels: [u8; MAX_POLY],
}

impl Poly2 {
    /// The empty polygon.
    pub(crate) const EMPTY: Poly2 = Poly2 {
        len: 0,
        pts: [Point2::new(0.0, 0.0); MAX_POLY],
        labels: [0; MAX_POLY],
    };

    /// A polygon from four corners in order (either winding), its edges labelled `labels`
    /// (edge `k` from corner `k` to `k + 1`).
    pub(crate) fn quad(corners: [Point2; 4], labels: [u8; 4]) -> Self {
        let mut pts = [Point2::origin(); MAX_POLY];
        pts[..4].copy_from_slice(&corners);
        let mut all = [0; MAX_POLY];
        all[..4].copy_from_slice(&labels);
        Poly2 {
            len: 4,
            pts,
            labels: all,
        }
    }

    /// The axis-aligned rectangle `[-hx, hx] x [-hy, hy]` (counter-clockwise from
    /// `(-hx, -hy)`), its edges labelled `labels` (bottom, right, top, left).
    pub(crate) fn rectangle(hx: Real, hy: Real, labels: [u8; 4]) -> Self {
        Poly2::quad(
            [
                Point2::new(-hx, -hy),
                Point2::new(hx, -hy),
                Point2::new(hx, hy),
                Point2::new(-hx, hy),
            ],
            labels,
        )
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.len < 3
    }

    /// The vertices.
    pub(crate) fn points(&self) -> &[Point2] {
        &self.pts[..self.len]
    }

    /// The edges' labels (edge `k` from vertex `k` to `k + 1`, the last back to the first).
    pub(crate) fn labels(&self) -> &[u8] {
        &self.labels[..self.len]
    }

    /// Keeps the part with `a x + b y <= c` (Sutherland-Hodgman for one half-plane); the new
    /// edge along the line is labelled `label`.
    ///
    /// Each vertex's side is computed once; a polygon wholly inside is left as it is and one
    /// wholly outside emptied without walking its edges (what the walk would give, exactly).
    pub(crate) fn clip(&mut self, a: Real, b: Real, c: Real, label: u8) {
        let len = self.len;
        if len == 0 {
            return;
        }
        let mut d = [0.0; MAX_POLY];
        let mut inside = 0;
        for (di, p) in d.iter_mut().zip(&self.pts[..len]) {
            *di = a * p.x + b * p.y - c;
            inside += usize::from(*di <= 0.0);
        }
        if inside == len {
            return;
        }
        if inside == 0 {
            self.len = 0;
            return;
        }
        let (src, src_labels) = (self.pts, self.labels);
        let mut n = 0;
        for i in 0..len {
            let j = if i + 1 == len { 0 } else { i + 1 };
            let (p, q, dp, dq) = (src[i], src[j], d[i], d[j]);
            if dp <= 0.0 && n < MAX_POLY {
                self.pts[n] = p;
                self.labels[n] = src_labels[i];
                n += 1;
            }
            if (dp <= 0.0) != (dq <= 0.0) && n < MAX_POLY {
                // Cut from the inside end so that neighbouring pieces agree exactly.
                let (i_pt, di, o_pt, d_o) = if dp <= 0.0 { (p, dp, q, dq) } else { (q, dq, p, dp) };
                self.pts[n] = i_pt + (o_pt - i_pt) * (di / (di - d_o));
                // Leaving the half-plane, the boundary follows the line; entering it, edge i.
                self.labels[n] = if dp <= 0.0 { label } else { src_labels[i] };
                n += 1;
            }
        }
        self.len = n;
    }

    /// Keeps the part inside the convex polygon `other` (either winding); the new edges carry
    /// `other`'s edge labels. The half-plane of `other`'s edge from `p` to `q` is
    /// [`Poly2::edge_half_plane`].
    pub(crate) fn clip_by_convex(&mut self, other: &Poly2) {
        let s = other.signed_area();
        if s == 0.0 {
            self.len = 0;
            return;
        }
        let sign = if s > 0.0 { 1.0 } else { -1.0 };
        for i in 0..other.len {
            let p = other.pts[i];
            let q = other.pts[(i + 1) % other.len];
            let (a, b, c) = Poly2::edge_half_plane(&p, &q, sign);
            self.clip(a, b, c, other.labels[i]);
            if self.is_empty() {
                return;
            }
        }
    }

    /// The half-plane `a x + b y <= c` inside a convex polygon's edge from `p` to `q`, for a
    /// polygon of winding `sign` (`1` counter-clockwise, `-1` clockwise): its left for a
    /// counter-clockwise polygon.
    #[inline]
    pub(crate) fn edge_half_plane(p: &Point2, q: &Point2, sign: Real) -> (Real, Real, Real) {
        // For a counter-clockwise polygon the inside of edge p -> q is to its left:
        // dx (y - p.y) - dy (x - p.x) >= 0  <=>  dy x - dx y <= dy p.x - dx p.y.
        let (dx, dy) = ((q.x - p.x) * sign, (q.y - p.y) * sign);
        (dy, -dx, dy * p.x - dx * p.y)
    }

    /// Signed area (positive counter-clockwise).
    pub(crate) fn signed_area(&self) -> Real {
        if self.len < 3 {
            return 0.0;
        }
        let o = self.pts[0];
        let mut twice = 0.0;
        for i in 1..self.len - 1 {
            twice += (self.pts[i] - o).perp(&(self.pts[i + 1] - o));
        }
        twice * 0.5
    }

    /// Unsigned area and area centroid (the first vertex for a degenerate polygon).
    pub(crate) fn area_centroid(&self) -> (Real, Point2) {
        if self.len < 3 {
            return (0.0, self.pts[0]);
        }
        let o = self.pts[0];
        let mut twice = 0.0;
        let mut acc = sceneeval_geom::Vector2::zeros();
        for i in 1..self.len - 1 {
            let (a, b) = (self.pts[i] - o, self.pts[i + 1] - o);
            let cross = a.perp(&b);
            twice += cross;
            acc += (a + b) * cross;
        }
        if twice == 0.0 {
            return (0.0, o);
        }
        (0.5 * twice.abs(), o + acc / (3.0 * twice))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hs(n: [Real; 3], o: Real) -> HalfSpace {
        HalfSpace::new(Vector3::new(n[0], n[1], n[2]), o)
    }

    #[test]
    fn axis_planes_give_box_volumes() {
        let h = Vector3::new(1.0, 2.0, 3.0);
        // Whole box: 2 * 4 * 6 = 48.
        assert_eq!(box_volume_inside(&h, &[]), 48.0);
        // x <= 0.5 keeps x in [-1, 0.5]: 1.5 * 4 * 6 = 36.
        let v = box_volume_inside(&h, &[hs([1.0, 0.0, 0.0], 0.5)]);
        assert!((v - 36.0).abs() < 1e-12, "{v}");
        // Also y >= 1 (-y <= -1): y in [1, 2]: 1.5 * 1 * 6 = 9.
        let v = box_volume_inside(&h, &[hs([1.0, 0.0, 0.0], 0.5), hs([0.0, -1.0, 0.0], -1.0)]);
        assert!((v - 9.0).abs() < 1e-12, "{v}");
        // Excluding plane: x <= -1 touches only the face.
        assert_eq!(box_volume_inside(&h, &[hs([1.0, 0.0, 0.0], -1.0)]), 0.0);
    }

    #[test]
    fn diagonal_plane_cuts_a_corner_tetrahedron() {
        // Unit cube [-0.5, 0.5]^3; x + y + z >= 1.5 - t cuts off a corner tetrahedron with legs t:
        // volume t^3 / 6. With t = 0.6: 0.036.
        let h = Vector3::repeat(0.5);
        let t: Real = 0.6;
        let v = box_volume_inside(&h, &[hs([-1.0, -1.0, -1.0], -(1.5 - t))]);
        assert!((v - t.powi(3) / 6.0).abs() < 1e-12, "{v}");
        // The complement has the rest of the unit volume.
        let rest = box_volume_inside(&h, &[hs([1.0, 1.0, 1.0], 1.5 - t)]);
        assert!((v + rest - 1.0).abs() < 1e-12);
        // The mid plane x + y + z <= 0 halves the cube by symmetry.
        let half = box_volume_inside(&h, &[hs([1.0, 1.0, 1.0], 0.0)]);
        assert!((half - 0.5).abs() < 1e-12, "{half}");
    }

    #[test]
    fn six_planes_make_an_inner_rotated_box() {
        // A cube of half size 0.3 turned 45 degrees about z, inside the unit cube [-1, 1]^3:
        // its corners reach 0.3 * sqrt(2) = 0.424 < 1, so the clip keeps it whole: 0.6^3 = 0.216.
        let h = Vector3::repeat(1.0);
        let (c, s) = (std::f64::consts::FRAC_1_SQRT_2, std::f64::consts::FRAC_1_SQRT_2);
        let planes = [
            hs([c, s, 0.0], 0.3),
            hs([-c, -s, 0.0], 0.3),
            hs([-s, c, 0.0], 0.3),
            hs([s, -c, 0.0], 0.3),
            hs([0.0, 0.0, 1.0], 0.3),
            hs([0.0, 0.0, -1.0], 0.3),
        ];
        let v = box_volume_inside(&h, &planes);
        assert!((v - 0.216).abs() < 1e-12, "{v}");
        // Shifted by 0.9 along x it pokes out of the cube: the part beyond x = 1 is cut.
        // The rotated square (diamond in x) spans x in [0.9 - 0.424, 0.9 + 0.424]; the tip beyond
        // x = 1 is a triangle with height 0.324 and base 2 * 0.324: area 0.324^2, times 0.6 high.
        let shifted = planes.map(|p| HalfSpace::new(p.normal, p.offset + p.normal.x * 0.9));
        let v = box_volume_inside(&h, &shifted);
        let tip = 0.3 * 2f64.sqrt() - 0.1;
        assert!((v - (0.216 - tip * tip * 0.6)).abs() < 1e-12, "{v}");
    }

    #[test]
    fn polygons_clip_and_measure() {
        let mut p = Poly2::rectangle(1.0, 0.5, [0, 1, 2, 3]);
        assert!((p.signed_area() - 2.0).abs() < 1e-15);
        // Keep x <= 0.5: area 1.5 * 1 = 1.5, centroid x = (-1 + 0.5) / 2 = -0.25.
        p.clip(1.0, 0.0, 0.5, 9);
        // The right edge now lies on the clip line; bottom, top and left keep theirs.
        assert_eq!(p.labels(), &[0, 9, 2, 3]);
        let (a, c) = p.area_centroid();
        assert!((a - 1.5).abs() < 1e-15);
        assert!((c - Point2::new(-0.25, 0.0)).norm() < 1e-15);
        // Clip by a clockwise triangle covering x + y <= 0 within the rectangle's reach.
        let tri = Poly2::quad(
            [
                Point2::new(-5.0, -5.0),
                Point2::new(-5.0, 5.0),
                Point2::new(5.0, -5.0),
                Point2::new(-5.0, -5.0),
            ],
            [4, 5, 6, 7],
        );
        let mut r = Poly2::rectangle(1.0, 1.0, [0, 1, 2, 3]);
        r.clip_by_convex(&tri);
        let (a, _) = r.area_centroid();
        assert!((a - 2.0).abs() < 1e-12, "{a}");
    }

    #[test]
    fn the_reused_polyhedron_keeps_no_trace_of_earlier_clips() {
        // A six-plane clip leaves twelve faces behind in the per-thread polyhedron; the volumes
        // after it are those of a fresh one (the 36 and 9 of axis_planes_give_box_volumes).
        let h = Vector3::new(1.0, 2.0, 3.0);
        let six = [
            hs([1.0, 0.2, 0.1], 0.5),
            hs([-0.3, 1.0, 0.2], 1.0),
            hs([0.1, -0.2, 1.0], 2.0),
            hs([-1.0, 0.1, -0.3], 0.7),
            hs([0.2, -1.0, 0.1], 1.5),
            hs([-0.1, 0.3, -1.0], 2.5),
        ];
        let first = box_volume_inside(&h, &six);
        assert!(first > 0.0 && first < 48.0, "{first}");
        let one = box_volume_inside(&h, &[hs([1.0, 0.0, 0.0], 0.5)]);
        assert!((one - 36.0).abs() < 1e-12, "{one}");
        let two = box_volume_inside(&h, &[hs([1.0, 0.0, 0.0], 0.5), hs([0.0, -1.0, 0.0], -1.0)]);
        assert!((two - 9.0).abs() < 1e-12, "{two}");
        assert_eq!(box_volume_inside(&h, &six).to_bits(), first.to_bits());
        // Another thread (its own polyhedron) gets the same bits.
        let other = std::thread::spawn(move || box_volume_inside(&h, &six))
            .join()
            .unwrap();
        assert_eq!(other.to_bits(), first.to_bits());
    }

    #[test]
    fn polygons_wholly_inside_or_outside_a_half_plane() {
        let mut p = Poly2::rectangle(1.0, 0.5, [0, 1, 2, 3]);
        let before = p;
        // x <= 1 keeps the whole rectangle (its right edge lies on the line): unchanged.
        p.clip(1.0, 0.0, 1.0, 9);
        assert_eq!((p.len, &p.pts[..4]), (4, &before.pts[..4]));
        // x <= -1.5 keeps nothing.
        p.clip(1.0, 0.0, -1.5, 9);
        assert!(p.is_empty());
        assert_eq!(p.area_centroid().0, 0.0);
        // The diagonal y = x / 2 through two corners keeps the lower-right triangle, area 1.
        let mut q = Poly2::rectangle(1.0, 0.5, [0, 1, 2, 3]);
        q.clip(-0.5, 1.0, 0.0, 9);
        let (a, c) = q.area_centroid();
        assert!((a - 1.0).abs() < 1e-15, "{a}");
        // Centroid of the triangle (-1, -0.5), (1, -0.5), (1, 0.5): (1/3, -1/6).
        assert!((c - Point2::new(1.0 / 3.0, -1.0 / 6.0)).norm() < 1e-15, "{c}");
    }
}
