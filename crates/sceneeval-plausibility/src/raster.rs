//! Rasters over the floor plan: the pixel grid, polygon filling, distance marking and
//! connected components.

use sceneeval_geom::{Point2, Real};
use serde::{Deserialize, Serialize};

use crate::PlausibilityError;
use crate::plane::{convex_distance, point_segment_distance};

/// How finely a floor-plan raster samples the floor.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Resolution {
    /// A square image of this many pixels per side over the floors' extent plus the margin,
    /// like the reference (`image_resolution: 256`); pixel size then depends on the room size.
    Pixels(u32),
    /// Square pixels of this size in metres, so that large and small rooms are treated alike.
    MetresPerPixel(Real),
}

/// Largest raster the metrics build (64 M pixels, 64 MB per mask).
pub(crate) const MAX_PIXELS: usize = 1 << 26;

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
                Grid {
                    x0: min.x - margin,
                    y0: min.y - margin,
                    pixel: p,
                    width: ((w / p).ceil() as usize).max(1),
                    height: ((h / p).ceil() as usize).max(1),
                }
            }
        };
        if grid.width.saturating_mul(grid.height) > MAX_PIXELS {
            return Err(PlausibilityError::RasterTooLarge {
                metric,
                width: grid.width,
                height: grid.height,
                max: MAX_PIXELS,
            });
        }
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

    /// The pixel index ranges whose centres can lie in `min..max` grown by `pad`.
    pub(crate) fn span(&self, min: Point2, max: Point2, pad: Real) -> Option<(usize, usize, usize, usize)> {
        let lo = |v: Real, o: Real| ((v - pad - o) / self.pixel - 0.5).ceil();
        let hi = |v: Real, o: Real| ((v + pad - o) / self.pixel - 0.5).floor();
        let (i0, i1) = (lo(min.x, self.x0).max(0.0), hi(max.x, self.x0));
        let (j0, j1) = (lo(min.y, self.y0).max(0.0), hi(max.y, self.y0));
        if !(i0.is_finite() && i1.is_finite() && j0.is_finite() && j1.is_finite()) || i1 < i0 || j1 < j0 {
            return None;
        }
        let i1 = (i1 as usize).min(self.width.checked_sub(1)?);
        let j1 = (j1 as usize).min(self.height.checked_sub(1)?);
        let (i0, j0) = (i0 as usize, j0 as usize);
        (i0 <= i1 && j0 <= j1).then_some((i0, i1, j0, j1))
    }

    /// Calls `f(index)` for every pixel whose centre lies within distance `< r` of the convex
    /// counter-clockwise polygon `poly` (inside when `r` is 0: distance 0 counts).
    pub(crate) fn for_convex_within(&self, poly: &[Point2], r: Real, mut f: impl FnMut(usize)) {
        if poly.is_empty() {
            return;
        }
        let (min, max) = crate::plane::bounds(poly);
        let Some((i0, i1, j0, j1)) = self.span(min, max, r) else {
            return;
        };
        for j in j0..=j1 {
            for i in i0..=i1 {
                let d = convex_distance(poly, &self.center(i, j));
                if d < r || (r == 0.0 && d == 0.0) {
                    f(self.index(i, j));
                }
            }
        }
    }

    /// Calls `f(index)` for every pixel whose centre lies within distance `< r` of the segment.
    pub(crate) fn for_segment_within(&self, a: &Point2, b: &Point2, r: Real, mut f: impl FnMut(usize)) {
        let (min, max) = (a.inf(b), a.sup(b));
        let Some((i0, i1, j0, j1)) = self.span(min, max, r) else {
            return;
        };
        for j in j0..=j1 {
            for i in i0..=i1 {
                if point_segment_distance(&self.center(i, j), a, b) < r {
                    f(self.index(i, j));
                }
            }
        }
    }

    /// Calls `f(index)` for every pixel whose centre lies inside the simple polygon (even-odd
    /// scanline fill; centres on an edge may fall either way).
    pub(crate) fn for_polygon(&self, poly: &[Point2], mut f: impl FnMut(usize)) {
        let n = poly.len();
        if n < 3 {
            return;
        }
        let (min, max) = crate::plane::bounds(poly);
        let Some((i0, i1, j0, j1)) = self.span(min, max, 0.0) else {
            return;
        };
        let mut xs: Vec<Real> = Vec::with_capacity(8);
        for j in j0..=j1 {
            let y = self.y0 + (j as Real + 0.5) * self.pixel;
            xs.clear();
            for k in 0..n {
                let (a, b) = (poly[k], poly[(k + 1) % n]);
                if (a.y > y) != (b.y > y) {
                    xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
                }
            }
            xs.sort_by(|p, q| p.total_cmp(q));
            for pair in xs.chunks_exact(2) {
                for i in i0..=i1 {
                    let x = self.x0 + (i as Real + 0.5) * self.pixel;
                    if x >= pair[0] && x < pair[1] {
                        f(self.index(i, j));
                    }
                }
            }
        }
    }
}

/// Labels the 8-connected components of the `true` pixels in scan order (row by row from the
/// lowest y). Returns the label of every pixel (`u32::MAX` for `false` pixels) and the size of
/// every component.
pub(crate) fn components8(grid: &Grid, mask: &[bool]) -> (Vec<u32>, Vec<usize>) {
    let (w, h) = (grid.width, grid.height);
    let mut labels = vec![u32::MAX; mask.len()];
    let mut sizes = Vec::new();
    let mut stack = Vec::new();
    for start in 0..mask.len() {
        if !mask[start] || labels[start] != u32::MAX {
            continue;
        }
        let label = sizes.len() as u32;
        labels[start] = label;
        stack.push(start);
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
                    if mask[q] && labels[q] == u32::MAX {
                        labels[q] = label;
                        stack.push(q);
                    }
                }
            }
        }
        sizes.push(size);
    }
    (labels, sizes)
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let mut n = 0;
        // [0.2, 0.6] x [0.0, 0.3]: centres 0.25..0.55 (4) x 0.05..0.25 (3).
        let rect = [
            Point2::new(0.2, 0.0),
            Point2::new(0.6, 0.0),
            Point2::new(0.6, 0.3),
            Point2::new(0.2, 0.3),
        ];
        g.for_polygon(&rect, |_| n += 1);
        assert_eq!(n, 12);
        let mut m = 0;
        g.for_convex_within(&rect, 0.0, |_| m += 1);
        assert_eq!(m, 12);
        let mut s = 0;
        // Centres within 0.1 of the segment x = 0.5 (strictly): x = 0.45, 0.55 -> 2 columns.
        g.for_segment_within(&Point2::new(0.5, -1.0), &Point2::new(0.5, 2.0), 0.1, |_| s += 1);
        assert_eq!(s, 20);
    }

    #[test]
    fn components_are_eight_connected() {
        let g = grid10();
        let mut mask = vec![false; g.len()];
        // Two diagonal neighbours (connected) and one separate pixel.
        mask[g.index(0, 0)] = true;
        mask[g.index(1, 1)] = true;
        mask[g.index(5, 5)] = true;
        let (labels, sizes) = components8(&g, &mask);
        assert_eq!(sizes, vec![2, 1]);
        assert_eq!(labels[g.index(1, 1)], 0);
        assert_eq!(labels[g.index(5, 5)], 1);
        assert_eq!(labels[g.index(3, 3)], u32::MAX);
    }
}
