use crate::{Point3, Real, Vector3};

/// An axis-aligned box, `min <= max` component-wise.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Aabb {
    /// Lowest corner.
    pub min: Point3,
    /// Highest corner.
    pub max: Point3,
}

impl Aabb {
    /// A box from two corners; the corners are sorted per axis, so any two opposite corners work.
    pub fn new(a: Point3, b: Point3) -> Self {
        Aabb {
            min: a.inf(&b),
            max: a.sup(&b),
        }
    }

    /// The smallest box containing all `points`, or `None` for an empty iterator.
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a Point3>) -> Option<Self> {
        let mut it = points.into_iter();
        let first = *it.next()?;
        Some(it.fold(Aabb::new(first, first), |acc, p| acc.including(p)))
    }

    /// A box from its centre and half extents.
    pub fn from_center_half_extents(center: Point3, half_extents: Vector3) -> Self {
        Aabb {
            min: center - half_extents,
            max: center + half_extents,
        }
    }

    /// This box grown to contain `p`.
    #[inline]
    pub fn including(&self, p: &Point3) -> Self {
        Aabb {
            min: self.min.inf(p),
            max: self.max.sup(p),
        }
    }

    /// The smallest box containing both boxes.
    #[inline]
    pub fn union(&self, other: &Aabb) -> Self {
        Aabb {
            min: self.min.inf(&other.min),
            max: self.max.sup(&other.max),
        }
    }

    /// The overlap of both boxes, or `None` if they are disjoint (touching boxes give a flat box).
    pub fn intersection(&self, other: &Aabb) -> Option<Aabb> {
        let min = self.min.sup(&other.min);
        let max = self.max.inf(&other.max);
        (min.x <= max.x && min.y <= max.y && min.z <= max.z).then_some(Aabb { min, max })
    }

    /// The box grown by `margin` on every side (shrunk for a negative margin, never inverted).
    pub fn loosened(&self, margin: Real) -> Self {
        let m = Vector3::repeat(margin);
        let min = self.min - m;
        let max = self.max + m;
        let center = self.center();
        Aabb {
            min: min.inf(&center),
            max: max.sup(&center),
        }
    }

    /// Centre point.
    #[inline]
    pub fn center(&self) -> Point3 {
        na_center(&self.min, &self.max)
    }

    /// Full size along each axis.
    #[inline]
    pub fn extents(&self) -> Vector3 {
        self.max - self.min
    }

    /// Half the size along each axis.
    #[inline]
    pub fn half_extents(&self) -> Vector3 {
        self.extents() * 0.5
    }

    /// Volume in cubic metres.
    #[inline]
    pub fn volume(&self) -> Real {
        let e = self.extents();
        e.x * e.y * e.z
    }

    /// Whether `p` lies in the closed box.
    #[inline]
    pub fn contains_point(&self, p: &Point3) -> bool {
        (0..3).all(|i| p[i] >= self.min[i] && p[i] <= self.max[i])
    }

    /// Whether `other` lies entirely in this box.
    #[inline]
    pub fn contains_aabb(&self, other: &Aabb) -> bool {
        self.contains_point(&other.min) && self.contains_point(&other.max)
    }

    /// Whether the two closed boxes share at least one point.
    #[inline]
    pub fn intersects(&self, other: &Aabb) -> bool {
        (0..3).all(|i| self.min[i] <= other.max[i] && other.min[i] <= self.max[i])
    }

    /// Euclidean distance between the two boxes (0 when they touch or overlap).
    pub fn distance_to_aabb(&self, other: &Aabb) -> Real {
        let mut d2 = 0.0;
        for i in 0..3 {
            let gap = (other.min[i] - self.max[i]).max(self.min[i] - other.max[i]);
            if gap > 0.0 {
                d2 += gap * gap;
            }
        }
        d2.sqrt()
    }

    /// The eight corners; bit `i` of the corner index selects `max` on axis `i`.
    pub fn corners(&self) -> [Point3; 8] {
        std::array::from_fn(|k| {
            Point3::new(
                if k & 1 == 0 { self.min.x } else { self.max.x },
                if k & 2 == 0 { self.min.y } else { self.max.y },
                if k & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }
}

#[inline]
fn na_center(a: &Point3, b: &Point3) -> Point3 {
    Point3::from((a.coords + b.coords) * 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Aabb {
        Aabb::new(Point3::origin(), Point3::new(1.0, 2.0, 3.0))
    }

    #[test]
    fn basic_measures() {
        let b = unit();
        assert_eq!(b.volume(), 6.0);
        assert_eq!(b.center(), Point3::new(0.5, 1.0, 1.5));
        assert_eq!(b.half_extents(), Vector3::new(0.5, 1.0, 1.5));
        assert_eq!(
            Aabb::new(Point3::new(1.0, 2.0, 3.0), Point3::origin()),
            b,
            "corners are sorted"
        );
    }

    #[test]
    fn distance_and_overlap() {
        let a = unit();
        let b = Aabb::new(Point3::new(4.0, 6.0, 0.0), Point3::new(5.0, 7.0, 1.0));
        // Gaps 3 along x and 4 along y: distance 5.
        assert!((a.distance_to_aabb(&b) - 5.0).abs() < 1e-12);
        assert!(!a.intersects(&b));
        let c = Aabb::new(Point3::new(1.0, 0.0, 0.0), Point3::new(2.0, 1.0, 1.0));
        assert!(a.intersects(&c), "touching boxes intersect");
        assert_eq!(a.distance_to_aabb(&c), 0.0);
        assert_eq!(a.intersection(&c).unwrap().volume(), 0.0);
        assert!(a.intersection(&b).is_none());
    }

    #[test]
    fn from_points_and_corners() {
        let b = unit();
        let corners = b.corners();
        assert_eq!(Aabb::from_points(corners.iter()), Some(b));
        assert!(corners.iter().all(|p| b.contains_point(p)));
        assert_eq!(Aabb::from_points(std::iter::empty()), None);
        assert!(b.loosened(0.5).contains_aabb(&b));
        assert_eq!(b.loosened(-10.0).volume(), 0.0);
    }
}
