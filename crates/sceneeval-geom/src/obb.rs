use crate::conventions::{Side, rotation_from_yaw, yaw_of};
use crate::parry_adapter::{to_parry_pose, to_parry_vec};
use crate::{Aabb, ClosestPoints, GeomError, Isometry3, Point3, Real, Rotation3, Vector3, parry};

/// An oriented box: a centre, half extents along the box's own axes, and the rotation that
/// takes box-local directions to world directions.
///
/// The box's local frame follows the object convention (front = local -y, up = +z), so for an
/// object's OBB, [`Obb::side_direction`] gives the world direction of each named side.
/// The fields are public for speed in predicate kernels; [`Obb::new`] validates them
/// (finite, half extents `>= 0`, rotation orthonormal with determinant +1).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Obb {
    /// Centre in world coordinates (metres).
    pub center: Point3,
    /// Half the box size along its local x, y, z axes (metres, non-negative).
    pub half_extents: Vector3,
    /// `world_from_box` rotation; its columns are the box axes in world coordinates.
    pub rotation: Rotation3,
}

impl Obb {
    /// A validated box.
    pub fn new(center: Point3, half_extents: Vector3, rotation: Rotation3) -> Result<Self, GeomError> {
        if !center.iter().all(|v| v.is_finite()) {
            return Err(GeomError::NonFinite { what: "box centre" });
        }
        if !half_extents.iter().all(|v| v.is_finite()) {
            return Err(GeomError::NonFinite {
                what: "box half extents",
            });
        }
        if half_extents.iter().any(|&v| v < 0.0) {
            return Err(GeomError::NegativeExtent(half_extents.into()));
        }
        check_rotation(rotation.matrix())?;
        Ok(Obb {
            center,
            half_extents,
            rotation,
        })
    }

    /// A validated box turned by `yaw` radians about +z (yaw 0: front = world -y).
    pub fn from_yaw(center: Point3, half_extents: Vector3, yaw: Real) -> Result<Self, GeomError> {
        if !yaw.is_finite() {
            return Err(GeomError::NonFinite { what: "yaw" });
        }
        Obb::new(center, half_extents, rotation_from_yaw(yaw))
    }

    /// The box spanned by `local` (an axis-aligned box in some local frame) once that frame is
    /// placed in the world by `world_from_local`. This is how an object's OBB is made from the
    /// bounds of its mesh in the object frame.
    pub fn from_local_aabb(local: &Aabb, world_from_local: &Isometry3) -> Self {
        Obb {
            center: world_from_local * local.center(),
            half_extents: local.half_extents(),
            rotation: world_from_local.rotation.to_rotation_matrix(),
        }
    }

    /// Full size along the local axes (width x, depth y, height z).
    #[inline]
    pub fn extents(&self) -> Vector3 {
        self.half_extents * 2.0
    }

    /// Volume in cubic metres.
    #[inline]
    pub fn volume(&self) -> Real {
        let e = self.extents();
        e.x * e.y * e.z
    }

    /// The local axis `i` (0 = x, 1 = y, 2 = z) in world coordinates.
    #[inline]
    pub fn axis(&self, i: usize) -> Vector3 {
        self.rotation.matrix().column(i).into_owned()
    }

    /// The world direction of a named side (see [`crate::conventions`]).
    #[inline]
    pub fn side_direction(&self, side: Side) -> Vector3 {
        let (axis, sign) = side.axis_and_sign();
        self.axis(axis) * sign
    }

    /// The centre of the face on `side`, in world coordinates.
    pub fn face_center(&self, side: Side) -> Point3 {
        let (axis, _) = side.axis_and_sign();
        self.center + self.side_direction(side) * self.half_extents[axis]
    }

    /// The yaw of the box's rotation (see [`crate::conventions::yaw_of`]).
    #[inline]
    pub fn yaw(&self) -> Real {
        yaw_of(&self.rotation)
    }

    /// `world_from_box`: the rigid transform placing the box's local frame (origin at its centre).
    pub fn pose(&self) -> Isometry3 {
        Isometry3::from_parts(
            self.center.coords.into(),
            crate::na::UnitQuaternion::from_rotation_matrix(&self.rotation),
        )
    }

    /// Coordinates of a world point in the box frame (origin at the centre).
    #[inline]
    pub fn to_local(&self, p: &Point3) -> Vector3 {
        self.rotation.inverse_transform_vector(&(p - self.center))
    }

    /// The world point with box-frame coordinates `local`.
    #[inline]
    pub fn to_world(&self, local: &Vector3) -> Point3 {
        self.center + self.rotation * local
    }

    /// Whether `p` lies in the closed box.
    #[inline]
    pub fn contains_point(&self, p: &Point3) -> bool {
        let l = self.to_local(p);
        (0..3).all(|i| l[i].abs() <= self.half_extents[i])
    }

    /// The point of the solid box closest to `p` (`p` itself when inside).
    pub fn closest_point(&self, p: &Point3) -> Point3 {
        let l = self.to_local(p);
        let clamped = Vector3::from_fn(|i, _| l[i].clamp(-self.half_extents[i], self.half_extents[i]));
        self.to_world(&clamped)
    }

    /// Distance from `p` to the solid box (0 inside).
    #[inline]
    pub fn distance_to_point(&self, p: &Point3) -> Real {
        self.distance_to_point_squared(p).sqrt()
    }

    /// Squared distance from `p` to the solid box (0 inside).
    #[inline]
    pub fn distance_to_point_squared(&self, p: &Point3) -> Real {
        let l = self.to_local(p);
        let mut d2 = 0.0;
        for i in 0..3 {
            let excess = l[i].abs() - self.half_extents[i];
            if excess > 0.0 {
                d2 += excess * excess;
            }
        }
        d2
    }

    /// The eight corners; bit `i` of the corner index selects the + side of local axis `i`.
    pub fn corners(&self) -> [Point3; 8] {
        std::array::from_fn(|k| {
            let l = Vector3::new(
                if k & 1 == 0 { -1.0 } else { 1.0 } * self.half_extents.x,
                if k & 2 == 0 { -1.0 } else { 1.0 } * self.half_extents.y,
                if k & 4 == 0 { -1.0 } else { 1.0 } * self.half_extents.z,
            );
            self.to_world(&l)
        })
    }

    /// The world axis-aligned box enclosing this box (exact: `|R| h` about the centre).
    pub fn aabb(&self) -> Aabb {
        let r = self.rotation.matrix();
        let h = r.abs() * self.half_extents;
        Aabb::from_center_half_extents(self.center, h)
    }

    /// This box moved by `motion` (applied in the world frame).
    pub fn transformed(&self, motion: &Isometry3) -> Obb {
        Obb {
            center: motion * self.center,
            half_extents: self.half_extents,
            rotation: motion.rotation.to_rotation_matrix() * self.rotation,
        }
    }

    /// Whether the two closed boxes share a point (separating-axis test, exact up to rounding).
    pub fn intersects(&self, other: &Obb) -> bool {
        let (p1, c1) = self.to_parry();
        let (p2, c2) = other.to_parry();
        parry::query::intersection_test(&p1, &c1, &p2, &c2).is_ok_and(|r| r.intersecting)
    }

    /// Euclidean distance between the two solid boxes (0 when they touch or overlap), exact up
    /// to rounding.
    ///
    /// # Performance
    /// No allocation. Cheap bounds settle most pairs (a corner of one box closest to the other
    /// box: tens of nanoseconds); edge-against-edge pairs fall back to GJK. parry's dedicated
    /// cuboid-cuboid distance is not used: it can overestimate by millimetres when two edges
    /// are closest.
    #[inline]
    pub fn distance_to_obb(&self, other: &Obb) -> Real {
        crate::distance::box_box(self, other)
    }

    /// [`Obb::distance_to_obb`] (the same value, same cost) with a pair of closest points,
    /// this box's first (none when the boxes touch or overlap).
    #[inline]
    pub fn closest_points_to_obb(&self, other: &Obb) -> ClosestPoints {
        crate::distance::box_box_closest(self, other)
    }

    /// A lower bound on the distance between the two solid boxes: the larger of the gaps
    /// between each box and the other's bounding box in its frame. Equal to the distance when
    /// the boxes are aligned; 0 when they overlap. Cheaper than [`Obb::distance_to_obb`], for
    /// pruning.
    #[inline]
    pub fn distance_lower_bound(&self, other: &Obb) -> Real {
        crate::distance::frame_gap(self, other).max(crate::distance::frame_gap(other, self))
    }

    /// Distance between the solid box and the world triangle `tri` (0 when they meet).
    pub fn distance_to_triangle(&self, tri: &[Point3; 3]) -> Real {
        crate::distance::box_triangle(self, tri)
    }

    /// [`Obb::distance_to_triangle`] (the same value) with a pair of closest points, the
    /// box's first (none when they meet).
    pub fn closest_points_to_triangle(&self, tri: &[Point3; 3]) -> ClosestPoints {
        crate::distance::box_triangle_closest(self, tri)
    }

    /// The box as a parry cuboid and its pose, for queries this crate does not wrap.
    pub fn to_parry(&self) -> (parry::math::Pose, parry::shape::Cuboid) {
        (
            to_parry_pose(&self.pose()),
            parry::shape::Cuboid::new(to_parry_vec(&self.half_extents)),
        )
    }
}

/// Checks that `m` is a rotation: orthonormal within 1e-6 and determinant +1.
pub(crate) fn check_rotation(m: &crate::Matrix3) -> Result<(), GeomError> {
    if !m.iter().all(|v| v.is_finite()) {
        return Err(GeomError::NonFinite { what: "rotation" });
    }
    let err = (m.transpose() * m - crate::Matrix3::identity()).abs().max();
    let det = m.determinant();
    if err > 1e-6 || det <= 0.0 {
        return Err(GeomError::NotARotation { error: err, det });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    fn bed() -> Obb {
        Obb::from_yaw(
            Point3::new(1.0, 2.0, 0.25),
            Vector3::new(1.0, 0.5, 0.25),
            FRAC_PI_2,
        )
        .unwrap()
    }

    #[test]
    fn validation() {
        let r = Rotation3::identity();
        assert!(Obb::new(Point3::origin(), Vector3::new(-1.0, 1.0, 1.0), r).is_err());
        assert!(Obb::new(Point3::new(f64::NAN, 0.0, 0.0), Vector3::repeat(1.0), r).is_err());
        let mirror =
            Rotation3::from_matrix_unchecked(crate::Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0)));
        assert!(matches!(
            Obb::new(Point3::origin(), Vector3::repeat(1.0), mirror),
            Err(GeomError::NotARotation { .. })
        ));
        assert!(Obb::from_yaw(Point3::origin(), Vector3::repeat(1.0), f64::INFINITY).is_err());
    }

    #[test]
    fn yawed_box_axes_and_aabb() {
        let b = bed();
        // Yaw 90 degrees: local x -> world y, local y -> world -x; front (-y local) -> world +x.
        assert!((b.side_direction(Side::Front) - Vector3::x()).norm() < 1e-12);
        assert!((b.side_direction(Side::Right) - Vector3::y()).norm() < 1e-12);
        let aabb = b.aabb();
        assert!((aabb.half_extents() - Vector3::new(0.5, 1.0, 0.25)).norm() < 1e-12);
        assert!((b.face_center(Side::Front) - Point3::new(1.5, 2.0, 0.25)).norm() < 1e-12);
        assert!((b.yaw() - FRAC_PI_2).abs() < 1e-12);
        assert_eq!(b.volume(), 1.0);
    }

    #[test]
    fn containment_and_distance() {
        let b = bed();
        assert!(b.contains_point(&Point3::new(1.4, 2.9, 0.4)));
        assert!(!b.contains_point(&Point3::new(1.6, 2.0, 0.25)));
        // 0.5 m beyond the front face (world +x), 0.2 m beyond the top: distance sqrt(0.29).
        let p = Point3::new(2.0, 2.0, 0.7);
        assert!((b.distance_to_point(&p) - 0.29f64.sqrt()).abs() < 1e-12);
        assert!((b.closest_point(&p) - Point3::new(1.5, 2.0, 0.5)).norm() < 1e-12);
        assert_eq!(b.distance_to_point(&b.center), 0.0);
    }

    #[test]
    fn box_box_queries() {
        let a = Obb::from_yaw(Point3::origin(), Vector3::repeat(0.5), 0.0).unwrap();
        let b = Obb::from_yaw(Point3::new(2.0, 0.0, 0.0), Vector3::repeat(0.5), 0.0).unwrap();
        assert!((a.distance_to_obb(&b) - 1.0).abs() < 1e-9);
        assert!(!a.intersects(&b));
        // Turned 45 degrees, the second box's corner reaches 0.5*sqrt(2) toward the first.
        let c = Obb::from_yaw(
            Point3::new(1.2, 0.0, 0.0),
            Vector3::repeat(0.5),
            std::f64::consts::FRAC_PI_4,
        )
        .unwrap();
        assert!(a.intersects(&c));
        let d = Obb::from_yaw(
            Point3::new(1.3, 0.0, 0.0),
            Vector3::repeat(0.5),
            std::f64::consts::FRAC_PI_4,
        )
        .unwrap();
        let expected = 1.3 - 0.5 * 2f64.sqrt() - 0.5;
        assert!(
            (a.distance_to_obb(&d) - expected).abs() < 1e-9,
            "{}",
            a.distance_to_obb(&d)
        );
    }

    #[test]
    fn from_local_aabb_places_centre() {
        let local = Aabb::new(Point3::new(-1.0, -0.5, 0.0), Point3::new(1.0, 0.5, 0.5));
        let pose = Isometry3::new(Vector3::new(3.0, 0.0, 0.0), Vector3::z() * FRAC_PI_2);
        let obb = Obb::from_local_aabb(&local, &pose);
        assert!((obb.center - Point3::new(3.0, 0.0, 0.25)).norm() < 1e-12);
        assert_eq!(obb.half_extents, Vector3::new(1.0, 0.5, 0.25));
        let corners = obb.corners();
        for c in &corners {
            let l = obb.to_local(c);
            assert!((l.abs() - obb.half_extents).norm() < 1e-12);
        }
    }
}
