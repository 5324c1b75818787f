//! Conversions between this crate's nalgebra values and parry 0.31's glam values, for callers
//! that run parry queries this crate does not wrap. Every conversion in the workspace goes
//! through here.

use crate::parry::math::{Pose, Rot3, Vector};
use crate::{Isometry3, Point3, Vector3};

#[inline]
/// A vector as parry's.
pub fn to_parry_vec(v: &Vector3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

#[inline]
/// A point as parry's vector.
pub fn point_to_parry(p: &Point3) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

#[inline]
/// A parry vector as a nalgebra vector.
pub fn vec_from_parry(v: Vector) -> Vector3 {
    Vector3::new(v.x, v.y, v.z)
}

#[inline]
/// A parry vector as a nalgebra point.
pub fn point_from_parry(v: Vector) -> Point3 {
    Point3::new(v.x, v.y, v.z)
}

#[inline]
/// A rigid transform as a parry pose.
pub fn to_parry_pose(iso: &Isometry3) -> Pose {
    let q = iso.rotation.quaternion();
    Pose::from_parts(
        to_parry_vec(&iso.translation.vector),
        Rot3::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

#[inline]
/// A parry pose as a rigid transform (the inverse of [`to_parry_pose`]).
pub fn pose_from_parry(pose: &Pose) -> Isometry3 {
    let t = pose.translation;
    let q = pose.rotation;
    Isometry3::from_parts(
        crate::na::Translation3::new(t.x, t.y, t.z),
        crate::na::UnitQuaternion::new_unchecked(crate::na::Quaternion::new(q.w, q.x, q.y, q.z)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pose_conversion_maps_points_identically() {
        let iso = Isometry3::new(Vector3::new(1.0, -2.0, 0.5), Vector3::new(0.3, -0.2, 1.1));
        let pose = to_parry_pose(&iso);
        let p = Point3::new(0.7, 0.1, -0.4);
        let a = iso * p;
        let b = point_from_parry(pose.transform_point(point_to_parry(&p)));
        assert!((a - b).norm() < 1e-14);
        // And back, bit for bit.
        assert_eq!(pose_from_parry(&pose), iso);
        assert_eq!(
            vec_from_parry(to_parry_vec(&Vector3::new(1.0, 2.0, 3.0))),
            Vector3::new(1.0, 2.0, 3.0)
        );
    }
}
