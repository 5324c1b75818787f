//! Distance between a solid box and a triangle.

use super::{ClosestPoints, gjk_from_box, parry_triangle};
use crate::{Obb, Point3, Real};

/// Distance between a solid box and a world triangle.
pub(crate) fn box_triangle(b: &Obb, tri: &[Point3; 3]) -> Real {
    box_triangle_closest(b, tri).distance
}

/// [`box_triangle`] with a pair of closest points (the box's first).
pub(crate) fn box_triangle_closest(b: &Obb, tri: &[Point3; 3]) -> ClosestPoints {
    let (pb, _) = b.to_parry();
    // The triangle is in world coordinates: its pose relative to the cuboid is pb^-1.
    gjk_from_box(b, &pb.inverse(), &parry_triangle(tri))
}

#[cfg(test)]
mod tests {
    use crate::{Obb, Point3, Real, Vector3};

    fn cube(c: [Real; 3], h: Real, yaw: Real) -> Obb {
        Obb::from_yaw(Point3::new(c[0], c[1], c[2]), Vector3::repeat(h), yaw).unwrap()
    }

    #[test]
    fn box_triangle_distance() {
        let a = cube([0.0, 0.0, 1.0], 0.5, 0.3);
        let tri = [
            Point3::new(-5.0, -5.0, 2.8),
            Point3::new(5.0, -5.0, 2.8),
            Point3::new(0.0, 5.0, 2.8),
        ];
        assert!((a.distance_to_triangle(&tri) - 1.3).abs() < 1e-9);
        assert_eq!(cube([0.0, 0.0, 2.3], 0.5, 0.3).distance_to_triangle(&tri), 0.0);
    }
}
