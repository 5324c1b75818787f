//! Rasters over the floor plan: the pixel grid, free space as runs of pixels per row, exact
//! distance marking row by row, and connected components by a two-pass labelling of runs.
//!
//! Nothing here stores a value per pixel: a row's floor, obstacles and free space are
//! intervals of pixel columns computed in closed form (the set of pixel centres within a
//! distance of a convex polygon meets a row in one interval), so memory grows with the number
//! of rows and runs, not pixels, and any resolution up to [`MAX_SIDE`] pixels per side works.

use rayon::prelude::*;
use sceneeval_geom::{Point2, Real};
use serde::{Deserialize, Serialize};

use crate::PlausibilityError;

/// How finely a floor-plan raster samples the floor.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Resolution {
    /// A square image of this many pixels per side over the floors' extent plus the margin,
    /// like the reference (`image_resolution: 256`); pixel size then depends on the room size.
    Pixels(u32),
    /// Square pixels of this size in metres, so that large and small rooms are treated alike.
    /// Written `{"m_per_pixel": 0.02}` in a plan (the inverse of opening clearance's
    /// `pixels_per_m`).
    #[serde(rename = "m_per_pixel")]
    MetresPerPixel(Real),
}

/// Most pixels per side of any raster (2^16 = 65,536: a centimetre grid over 650 m). The
/// navigability raster stores runs per row, so its memory grows with rows and runs, not
/// pixels, and this bounds only the time of absurd requests (a 100,000-pixel side is refused
/// before any scene is read).
pub(crate) const MAX_SIDE: usize = 1 << 16;

/// Most pixels of a raster that stores a value per pixel (2^24 = 16,777,216, 4096 x 4096: a
/// few bytes each): the opening-clearance occlusion maps and the diagnostic images.
pub(crate) const MAX_DENSE_PIXELS: usize = 1 << 24;

/// How a raster stores its pixels, which decides its budget ([`check_raster`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Storage {
    /// Runs of pixels per row: at most [`MAX_SIDE`] pixels per side.
    Runs,
    /// A value per pixel: also at most [`MAX_DENSE_PIXELS`] pixels in all.
    Dense,
}

/// The one budget of every raster the metrics build, checked before anything is allocated
/// for it: at most [`MAX_SIDE`] pixels per side, and [`MAX_DENSE_PIXELS`] pixels in all for
/// [`Storage::Dense`] rasters. Sizes come from float-to-int casts, which saturate, so an absurd
/// request stays above the limits instead of wrapping.
///
/// # Errors
/// [`PlausibilityError::RasterTooLarge`] naming `metric`.
pub(crate) fn check_raster(
    metric: &'static str,
    width: usize,
    height: usize,
    storage: Storage,
) -> Result<(), PlausibilityError> {
    let max_pixels = (storage == Storage::Dense).then_some(MAX_DENSE_PIXELS);
    let over_total = max_pixels.is_some_and(|m| width.checked_mul(height).is_none_or(|n| n > m));
    if width > MAX_SIDE || height > MAX_SIDE || over_total {
        return Err(PlausibilityError::RasterTooLarge {
            metric,
            width,
            height,
            max: MAX_SIDE,
            max_pixels,
        });
    }
    Ok(())
}

/// A pixel grid over the floor plan. Pixel `(i, j)` covers `[x0 + i p, x0 + (i+1) p] x
/// [y0 + j p, y0 + (j+1) p]` and is sampled at its centre; row `j = 0` is the lowest y.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Grid {
    /// World x of the grid's lower-left corner.
    pub x0: Real,
    /// World y of the grid's lower-left corner.
    pub y0: Real,
    /// Pixel size in metres.
    pub pixel: Real,
    /// Pixels along x.
    pub width: usize,
    /// Pixels along y.
    pub height: usize,
}

impl Grid {
    /// A grid covering the rectangle `min..max` grown by `margin` metres on every side.
    pub(crate) fn covering(
        metric: &'static str,
        min: Point2,
        max: Point2,
        margin: Real,
        resolution: Resolution,
    ) -> Result<Grid, PlausibilityError> {
        let (w, h) = (max.x - min.x + 2.0 * margin, max.y - min.y + 2.0 * margin);
        let grid = match resolution {
            Resolution::Pixels(n) => {
                if n == 0 {
                    return Err(PlausibilityError::InvalidParameter {
                        metric,
                        name: "resolution",
                        value: 0.0,
                        reason: "a raster needs at least one pixel",
                    });
                }
                check_raster(metric, n as usize, n as usize, Storage::Runs)?;
                let side = w.max(h).max(1e-6);
                let c = Point2::new(0.5 * (min.x + max.x), 0.5 * (min.y + max.y));
                Grid {
                    x0: c.x - 0.5 * side,
                    y0: c.y - 0.5 * side,
                    pixel: side / Real::from(n),
                    width: n as usize,
                    height: n as usize,
                }
            }
            Resolution::MetresPerPixel(p) => {
                crate::error::check_non_negative(metric, "resolution", p, true)?;
                // Float-to-int casts saturate, so an absurd ratio stays above the limit.
                Grid {
                    x0: min.x - margin,
                    y0: min.y - margin,
                    pixel: p,
                    width: ((w / p).ceil() as usize).max(1),
                    height: ((h / p).ceil() as usize).max(1),
                }
            }
        };
        check_raster(metric, grid.width, grid.height, Storage::Runs)?;
        Ok(grid)
    }

    /// Number of pixels.
    #[inline]
    pub fn len(&self) -> usize {
        self.width * self.height
    }

    /// Whether the grid has no pixel.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Area of one pixel in square metres.
    #[inline]
    pub fn pixel_area(&self) -> Real {
        self.pixel * self.pixel
    }

    /// World centre of pixel `(i, j)`.
    #[inline]
    pub fn center(&self, i: usize, j: usize) -> Point2 {
        Point2::new(
            self.x0 + (i as Real + 0.5) * self.pixel,
            self.y0 + (j as Real + 0.5) * self.pixel,
        )
    }

    /// Index of pixel `(i, j)` in row-major order.
    #[inline]
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.width + i
    }

    /// The rows whose pixel centres can lie within `pad` of `min.y..max.y`, as `j0..=j1`.
    pub(crate) fn rows(&self, min_y: Real, max_y: Real, pad: Real) -> Option<(usize, usize)> {
        let lo = ((min_y - pad - self.y0) / self.pixel - 0.5).ceil().max(0.0);
        let hi = ((max_y + pad - self.y0) / self.pixel - 0.5).floor();
        if !(lo.is_finite() && hi.is_finite()) || hi < lo {
            return None;
        }
        let j1 = (hi as usize).min(self.height.checked_sub(1)?);
        let j0 = lo as usize;
        (j0 <= j1).then_some((j0, j1))
    }

    /// World y of row `j`'s pixel centres.
    #[inline]
    pub(crate) fn row_y(&self, j: usize) -> Real {
        self.y0 + (j as Real + 0.5) * self.pixel
    }

    /// World x of column `i`'s pixel centres.
    #[inline]
    fn col_x(&self, i: usize) -> Real {
        self.x0 + (i as Real + 0.5) * self.pixel
    }

    /// The first column whose centre satisfies `after(x)`, for a predicate that is false then
    /// true along the row; starts from the closed-form guess `guess` and corrects rounding.
    fn first_column(&self, guess: Real, after: impl Fn(Real) -> bool) -> usize {
        let mut i = if guess.is_nan() {
            0
        } else {
            guess.clamp(0.0, self.width as Real) as usize
        };
        while i > 0 && after(self.col_x(i - 1)) {
            i -= 1;
        }
        while i < self.width && !after(self.col_x(i)) {
            i += 1;
        }
        i
    }

    /// The columns `[i0, i1)` whose centres lie in `lo < x < hi` (open) or, when `closed`,
    /// `lo <= x <= hi`.
    pub(crate) fn columns(&self, lo: Real, hi: Real, closed: bool) -> Option<(usize, usize)> {
        if lo
            .partial_cmp(&hi)
            .is_none_or(|o| o == std::cmp::Ordering::Greater)
        {
            return None;
        }
        let g = |x: Real| (x - self.x0) / self.pixel - 0.5;
        let i0 = if closed {
            self.first_column(g(lo).ceil(), |x| x >= lo)
        } else {
            self.first_column(g(lo).floor() + 1.0, |x| x > lo)
        };
        let i1 = if closed {
            self.first_column(g(hi).floor() + 1.0, |x| x > hi)
        } else {
            self.first_column(g(hi).ceil(), |x| x >= hi)
        };
        (i0 < i1).then_some((i0, i1))
    }

    /// The columns of row `y` whose centres lie within distance `< r` of the convex
    /// counter-clockwise polygon `poly` (one or two points: a point or a segment), or inside
    /// or on it when `r` is 0. One interval: that set is convex.
    pub(crate) fn convex_row(&self, poly: &[Point2], r: Real, y: Real) -> Option<(usize, usize)> {
        let n = poly.len();
        let (mut lo, mut hi) = (Real::INFINITY, Real::NEG_INFINITY);
        let mut take = |a: Real, b: Real| {
            lo = lo.min(a);
            hi = hi.max(b);
        };
        if n >= 3
            && let Some((a, b)) = chord(poly, y)
        {
            take(a, b);
        }
        if r > 0.0 {
            match n {
                0 => return None,
                1 => {
                    if let Some((a, b)) = capsule_row(&poly[0], &poly[0], r, y) {
                        take(a, b);
                    }
                }
                _ => {
                    for k in 0..n {
                        if let Some((a, b)) = capsule_row(&poly[k], &poly[(k + 1) % n], r, y) {
                            take(a, b);
                        }
                    }
                }
            }
            self.columns(lo, hi, false)
        } else {
            self.columns(lo, hi, true)
        }
    }

    /// The columns of row `y` whose centres lie within distance `< r` of the segment `a b`.
    pub(crate) fn segment_row(&self, a: &Point2, b: &Point2, r: Real, y: Real) -> Option<(usize, usize)> {
        let (lo, hi) = capsule_row(a, b, r, y)?;
        self.columns(lo, hi, false)
    }

    /// The column intervals of row `y` whose centres lie inside the simple polygon (even-odd
    /// rule; a centre exactly on a left edge counts, on a right edge does not), appended to
    /// `out`.
    pub(crate) fn polygon_row(&self, poly: &[Point2], y: Real, out: &mut Vec<(usize, usize)>) {
        let n = poly.len();
        if n < 3 {
            return;
        }
        let mut xs: Vec<Real> = Vec::with_capacity(8);
        for k in 0..n {
            let (a, b) = (poly[k], poly[(k + 1) % n]);
            if (a.y > y) != (b.y > y) {
                xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
            }
        }
        xs.sort_by(|p, q| p.total_cmp(q));
        for pair in xs.chunks_exact(2) {
            let g = |x: Real| (x - self.x0) / self.pixel - 0.5;
            let i0 = self.first_column(g(pair[0]).ceil(), |x| x >= pair[0]);
            let i1 = self.first_column(g(pair[1]).ceil(), |x| x >= pair[1]);
            if i0 < i1 {
                out.push((i0, i1));
            }
        }
    }

    /// Calls `f(index)` for every pixel whose centre lies within distance `< r` of the convex
    /// counter-clockwise polygon `poly` (inside or on it when `r` is 0).
    #[cfg_attr(not(feature = "images"), allow(dead_code))]
    pub(crate) fn for_convex_within(&self, poly: &[Point2], r: Real, mut f: impl FnMut(usize)) {
        if poly.is_empty() {
            return;
        }
        let (min, max) = crate::plane::bounds(poly);
        let Some((j0, j1)) = self.rows(min.y, max.y, r) else {
            return;
        };
        for j in j0..=j1 {
            if let Some((i0, i1)) = self.convex_row(poly, r, self.row_y(j)) {
                for i in i0..i1 {
                    f(self.index(i, j));
                }
            }
        }
    }
}

/// Where the horizontal line at `y` crosses the closed convex polygon: `[x0, x1]` (`None`
/// when it misses it). The rasters of this module and the openings' clearance pixels
/// (`clearance`) fill rows with it.
pub(crate) fn chord(poly: &[Point2], y: Real) -> Option<(Real, Real)> {
    let n = poly.len();
    let (mut lo, mut hi) = (Real::INFINITY, Real::NEG_INFINITY);
    for k in 0..n {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        // Compared, not multiplied: a product of two tiny differences could round to 0.
        if y < a.y.min(b.y) || y > a.y.max(b.y) {
            continue;
        }
        if a.y == b.y {
            lo = lo.min(a.x.min(b.x));
            hi = hi.max(a.x.max(b.x));
        } else {
            let x = a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x);
            lo = lo.min(x);
            hi = hi.max(x);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// The open interval of x where the horizontal line at `y` lies within distance `< r` of the
/// segment `a b` (a capsule: two discs and a strip).
fn capsule_row(a: &Point2, b: &Point2, r: Real, y: Real) -> Option<(Real, Real)> {
    if r <= 0.0 {
        return None;
    }
    let (mut lo, mut hi) = (Real::INFINITY, Real::NEG_INFINITY);
    for c in [a, b] {
        let dy = y - c.y;
        if dy.abs() < r {
            let half = (r * r - dy * dy).sqrt();
            lo = lo.min(c.x - half);
            hi = hi.max(c.x + half);
        }
    }
    let d = b - a;
    let len = d.norm();
    if len > 0.0 {
        let u = d / len;
        let n = sceneeval_geom::Vector2::new(-u.y, u.x);
        // Along the segment: u.x (x - a.x) + u.y (y - a.y) in [0, len]; across it:
        // |n.x (x - a.x) + n.y (y - a.y)| < r.
        let along = affine_range(u.x, u.y * (y - a.y) - u.x * a.x, 0.0, len);
        let across = affine_range(n.x, n.y * (y - a.y) - n.x * a.x, -r, r);
        if let (Some((a0, a1)), Some((c0, c1))) = (along, across) {
            let (s0, s1) = (a0.max(c0), a1.min(c1));
            if s0 <= s1 {
                lo = lo.min(s0);
                hi = hi.max(s1);
            }
        }
    }
    (lo < hi).then_some((lo, hi))
}

/// The x with `lo <= k x + c <= hi` (all x when `k` is 0 and `c` fits).
fn affine_range(k: Real, c: Real, lo: Real, hi: Real) -> Option<(Real, Real)> {
    if k == 0.0 {
        return (lo <= c && c <= hi).then_some((Real::NEG_INFINITY, Real::INFINITY));
    }
    let (p, q) = ((lo - c) / k, (hi - c) / k);
    Some((p.min(q), p.max(q)))
}

/// Sorted, disjoint, non-adjacent column intervals `[start, end)` per row: the free space (or
/// the floor) of an [`crate::OccupancyMap`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RowRuns {
    /// Row `j`'s runs are `runs[row_start[j]..row_start[j + 1]]`.
    row_start: Vec<usize>,
    runs: Vec<[u32; 2]>,
}

impl RowRuns {
    /// Runs from one sorted, merged interval list per row.
    pub(crate) fn from_rows(rows: Vec<Vec<(usize, usize)>>) -> Self {
        let mut row_start = Vec::with_capacity(rows.len() + 1);
        let mut runs = Vec::with_capacity(rows.iter().map(Vec::len).sum());
        row_start.push(0);
        for row in rows {
            runs.extend(row.into_iter().map(|(a, b)| [a as u32, b as u32]));
            row_start.push(runs.len());
        }
        RowRuns { row_start, runs }
    }

    /// Number of rows.
    pub fn height(&self) -> usize {
        self.row_start.len().saturating_sub(1)
    }

    /// The runs of row `j`, each `[start, end)` in pixel columns, left to right.
    pub fn row(&self, j: usize) -> &[[u32; 2]] {
        match (self.row_start.get(j), self.row_start.get(j + 1)) {
            (Some(&a), Some(&b)) => &self.runs[a..b],
            _ => &[],
        }
    }

    /// All runs, row by row (index them with [`RowRuns::run_at`] or the labels of
    /// [`crate::OccupancyMap::components`]).
    pub fn runs(&self) -> &[[u32; 2]] {
        &self.runs
    }

    /// Index (into [`RowRuns::runs`]) of the first run of row `j`.
    pub fn row_offset(&self, j: usize) -> usize {
        self.row_start.get(j).copied().unwrap_or(self.runs.len())
    }

    /// The index of the run holding pixel `(i, j)`, if any.
    pub fn run_at(&self, i: usize, j: usize) -> Option<usize> {
        let row = self.row(j);
        let k = row.partition_point(|r| (r[1] as usize) <= i);
        row.get(k)
            .filter(|r| r[0] as usize <= i)
            .map(|_| self.row_offset(j) + k)
    }

    /// Whether pixel `(i, j)` is in a run.
    pub fn contains(&self, i: usize, j: usize) -> bool {
        self.run_at(i, j).is_some()
    }

    /// Number of pixels in runs.
    pub fn count(&self) -> usize {
        self.runs.iter().map(|r| (r[1] - r[0]) as usize).sum()
    }

    /// Labels of the 8-connected components of the runs (two passes: union-find over runs
    /// of adjacent rows that touch, then numbering in scan order of each component's first
    /// pixel) and the size of every component in pixels.
    pub(crate) fn components8(&self) -> (Vec<u32>, Vec<usize>) {
        let n = self.runs.len();
        let mut parent: Vec<u32> = (0..n as u32).collect();
        fn find(parent: &mut [u32], mut x: u32) -> u32 {
            while parent[x as usize] != x {
                let up = parent[parent[x as usize] as usize];
                parent[x as usize] = up;
                x = up;
            }
            x
        }
        for j in 1..self.height() {
            let (prev, cur) = (self.row_offset(j - 1), self.row_offset(j));
            let (prow, crow) = (self.row(j - 1), self.row(j));
            let mut p = 0;
            for (c, run) in crow.iter().enumerate() {
                // 8-connected: runs touch when they overlap after growing one by a pixel.
                while p < prow.len() && prow[p][1] < run[0] {
                    p += 1;
                }
                let mut q = p;
                while q < prow.len() && prow[q][0] <= run[1] {
                    let (x, y) = (
                        find(&mut parent, (prev + q) as u32),
                        find(&mut parent, (cur + c) as u32),
                    );
                    if x != y {
                        parent[x.max(y) as usize] = x.min(y);
                    }
                    q += 1;
                }
            }
        }
        let mut label_of_root: Vec<u32> = vec![u32::MAX; n];
        let mut labels = vec![0u32; n];
        let mut sizes: Vec<usize> = Vec::new();
        for (k, (label, run)) in labels.iter_mut().zip(&self.runs).enumerate() {
            let root = find(&mut parent, k as u32) as usize;
            if label_of_root[root] == u32::MAX {
                label_of_root[root] = sizes.len() as u32;
                sizes.push(0);
            }
            *label = label_of_root[root];
            sizes[*label as usize] += (run[1] - run[0]) as usize;
        }
        (labels, sizes)
    }
}

/// Merges sorted-by-start intervals `[a, b)` that overlap or touch.
pub(crate) fn merge(mut v: Vec<(usize, usize)>) -> Vec<(usize, usize)> {
    v.sort_unstable();
    let mut out: Vec<(usize, usize)> = Vec::with_capacity(v.len());
    for (a, b) in v {
        match out.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => out.push((a, b)),
        }
    }
    out
}

/// `keep` minus `cut`, both merged.
pub(crate) fn subtract(keep: &[(usize, usize)], cut: &[(usize, usize)]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut c = 0;
    for &(mut a, b) in keep {
        while c < cut.len() && cut[c].1 <= a {
            c += 1;
        }
        let mut k = c;
        while k < cut.len() && cut[k].0 < b {
            if cut[k].0 > a {
                out.push((a, cut[k].0));
            }
            a = a.max(cut[k].1);
            k += 1;
        }
        if a < b {
            out.push((a, b));
        }
    }
    out
}

/// `f(0..count)` computed in parallel, collected in order.
pub(crate) fn par_rows<T: Send>(height: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
    (0..height).into_par_iter().map(f).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::planar::{convex_distance, point_segment_distance};

    fn grid10() -> Grid {
        Grid::covering(
            "test",
            Point2::new(0.0, 0.0),
            Point2::new(1.0, 1.0),
            0.0,
            Resolution::MetresPerPixel(0.1),
        )
        .unwrap()
    }

    #[test]
    fn grid_geometry() {
        let g = grid10();
        assert_eq!((g.width, g.height), (10, 10));
        assert!((g.center(0, 0) - Point2::new(0.05, 0.05)).norm() < 1e-12);
        let p = Grid::covering(
            "test",
            Point2::new(0.0, 0.0),
            Point2::new(4.0, 2.0),
            0.2,
            Resolution::Pixels(256),
        )
        .unwrap();
        // Side = max(4.4, 2.4) = 4.4 m over 256 pixels, centred on (2, 1).
        assert!((p.pixel - 4.4 / 256.0).abs() < 1e-15);
        assert!((p.x0 + 0.2).abs() < 1e-12 && (p.y0 - (1.0 - 2.2)).abs() < 1e-12);
        // 1e4 m at 1 mm: 10 million pixels per side, over the limit of 2^20.
        assert!(matches!(
            Grid::covering(
                "t",
                Point2::origin(),
                Point2::new(1e4, 1e4),
                0.0,
                Resolution::MetresPerPixel(1e-3)
            ),
            Err(PlausibilityError::RasterTooLarge { .. })
        ));
        assert!(
            Grid::covering(
                "t",
                Point2::origin(),
                Point2::new(1.0, 1.0),
                0.0,
                Resolution::Pixels(0)
            )
            .is_err()
        );
    }

    #[test]
    fn fills_count_pixel_centres() {
        let g = grid10();
        // [0.2, 0.6] x [0.0, 0.3]: centres 0.25..0.55 (4) x 0.05..0.25 (3).
        let rect = [
            Point2::new(0.2, 0.0),
            Point2::new(0.6, 0.0),
            Point2::new(0.6, 0.3),
            Point2::new(0.2, 0.3),
        ];
        let mut n = 0;
        for j in 0..g.height {
            let mut row = Vec::new();
            g.polygon_row(&rect, g.row_y(j), &mut row);
            n += row.iter().map(|(a, b)| b - a).sum::<usize>();
        }
        assert_eq!(n, 12);
        let mut m = 0;
        g.for_convex_within(&rect, 0.0, |_| m += 1);
        assert_eq!(m, 12);
        // Centres within 0.1 of the segment x = 0.5 (strictly): x = 0.45, 0.55 -> 2 columns.
        let s = (0..g.height)
            .filter_map(|j| g.segment_row(&Point2::new(0.5, -1.0), &Point2::new(0.5, 2.0), 0.1, g.row_y(j)))
            .map(|(a, b)| b - a)
            .sum::<usize>();
        assert_eq!(s, 20);
    }

    #[test]
    fn row_intervals_match_pixel_by_pixel_distances() {
        // A fine grid and a few convex shapes at odd angles: the closed-form row intervals
        // mark exactly the centres whose exact distance is below r.
        let g = Grid::covering(
            "t",
            Point2::new(0.0, 0.0),
            Point2::new(3.0, 2.0),
            0.3,
            Resolution::MetresPerPixel(0.013),
        )
        .unwrap();
        let shapes: Vec<Vec<Point2>> = vec![
            crate::plane::ccw(vec![
                Point2::new(0.3, 0.2),
                Point2::new(1.7, 0.5),
                Point2::new(1.2, 1.6),
                Point2::new(0.4, 1.1),
            ]),
            vec![Point2::new(2.0, 0.4)],
            vec![Point2::new(2.1, 0.3), Point2::new(2.9, 1.8)],
            crate::plane::ccw(vec![
                Point2::new(2.2, 1.0),
                Point2::new(2.6, 1.0),
                Point2::new(2.6, 1.0001),
            ]),
        ];
        for poly in &shapes {
            for r in [0.0, 0.07, 0.25] {
                let mut by_rows = vec![false; g.len()];
                for j in 0..g.height {
                    if let Some((a, b)) = g.convex_row(poly, r, g.row_y(j)) {
                        for i in a..b {
                            by_rows[g.index(i, j)] = true;
                        }
                    }
                }
                for j in 0..g.height {
                    for i in 0..g.width {
                        let c = g.center(i, j);
                        let d = if poly.len() == 2 {
                            point_segment_distance(&c, &poly[0], &poly[1])
                        } else {
                            convex_distance(poly, &c)
                        };
                        // Centres within 1e-9 of the boundary may fall either way.
                        if (d - r).abs() > 1e-9 && !(r == 0.0 && d < 1e-9) {
                            let want = if r > 0.0 { d < r } else { d == 0.0 };
                            assert_eq!(by_rows[g.index(i, j)], want, "{poly:?} r {r} at {c}: d {d}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn components_are_eight_connected() {
        // Row 0: pixel 0; row 1: pixel 1 (diagonal neighbour); row 5: pixel 5.
        let mut rows = vec![Vec::new(); 10];
        rows[0] = vec![(0, 1)];
        rows[1] = vec![(1, 2)];
        rows[5] = vec![(5, 6)];
        let runs = RowRuns::from_rows(rows);
        let (labels, sizes) = runs.components8();
        assert_eq!(sizes, vec![2, 1]);
        assert_eq!(labels, vec![0, 0, 1]);
        assert_eq!(runs.run_at(1, 1), Some(1));
        assert_eq!(runs.run_at(3, 3), None);
        assert_eq!(runs.count(), 3);
    }

    proptest::proptest! {
        /// Labelling runs gives the same components as a flood fill over pixels.
        #[test]
        fn run_labels_match_a_pixel_flood_fill(bits in proptest::collection::vec(proptest::bool::weighted(0.6), 12 * 9)) {
            let (w, h) = (12usize, 9usize);
            let rows: Vec<Vec<(usize, usize)>> = (0..h)
                .map(|j| {
                    let mut row = Vec::new();
                    let mut i = 0;
                    while i < w {
                        if bits[j * w + i] {
                            let s = i;
                            while i < w && bits[j * w + i] {
                                i += 1;
                            }
                            row.push((s, i));
                        } else {
                            i += 1;
                        }
                    }
                    row
                })
                .collect();
            let runs = RowRuns::from_rows(rows);
            let (labels, sizes) = runs.components8();
            // Flood fill, components numbered in scan order.
            let mut flood = vec![u32::MAX; w * h];
            let mut flood_sizes = Vec::new();
            for start in 0..w * h {
                if !bits[start] || flood[start] != u32::MAX {
                    continue;
                }
                let label = flood_sizes.len() as u32;
                let mut stack = vec![start];
                flood[start] = label;
                let mut size = 0;
                while let Some(p) = stack.pop() {
                    size += 1;
                    let (i, j) = ((p % w) as isize, (p / w) as isize);
                    for dj in -1..=1isize {
                        for di in -1..=1isize {
                            let (ni, nj) = (i + di, j + dj);
                            if ni < 0 || nj < 0 || ni >= w as isize || nj >= h as isize {
                                continue;
                            }
                            let q = nj as usize * w + ni as usize;
                            if bits[q] && flood[q] == u32::MAX {
                                flood[q] = label;
                                stack.push(q);
                            }
                        }
                    }
                }
                flood_sizes.push(size);
            }
            proptest::prop_assert_eq!(&sizes, &flood_sizes);
            for j in 0..h {
                for i in 0..w {
                    let by_runs = runs.run_at(i, j).map_or(u32::MAX, |k| labels[k]);
                    proptest::prop_assert_eq!(by_runs, flood[j * w + i]);
                }
            }
        }
    }

    #[test]
    fn interval_algebra() {
        assert_eq!(merge(vec![(5, 7), (0, 2), (2, 3), (6, 9)]), vec![(0, 3), (5, 9)]);
        assert_eq!(
            subtract(&[(0, 10), (20, 30)], &[(2, 4), (8, 22), (25, 26)]),
            vec![(0, 2), (4, 8), (22, 25), (26, 30)]
        );
        assert_eq!(subtract(&[(0, 10)], &[]), vec![(0, 10)]);
    }
}
