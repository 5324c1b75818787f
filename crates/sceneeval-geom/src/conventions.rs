//! The frame and unit conventions of the whole project, written once.
//!
//! | quantity | convention |
//! |---|---|
//! | world | right-handed, **z up**, metres, gravity `(0, 0, -1)` |
//! | object frame | **front = local -y**, right = +x, up = +z |
//! | yaw | radians about +z, counter-clockwise seen from above; yaw 0 means front = world -y |
//! | scores | in `[0, 1]`; a relation holds when its score is above 0.5 |
//!
//! Side names map to local half-axes exactly as the reference implementation does:
//!
//! | side | local axis |
//! |---|---|
//! | left | -x |
//! | right | +x |
//! | front | -y |
//! | back | +y |
//! | top | +z |
//! | bottom | -z |
//!
//! Because an object faces -y, "left" (-x) is the left of a viewer standing in front of the
//! object and looking at it, which is the object's own right. This is the reference's choice
//! (`spatial/spatial_relation.py`) and the front render camera's image-left.
//!
//! Asset files (glTF, 3D-FUTURE OBJ) are y-up with their front toward +z. Loading code maps
//! them into the object frame with [`object_from_asset`], a rotation of +90 degrees about x:
//! asset +y (up) becomes +z and asset +z (front) becomes -y. The sstk scene transform `T`
//! applies to asset coordinates, so the object's pose is `T * object_from_asset()^-1`; the
//! `sceneeval-io` crate is the only place that performs this conversion.

use std::fmt;
use std::str::FromStr;

use crate::na::{Translation3, UnitQuaternion};
use crate::{Isometry3, Point3, Real, Rotation3, Vector3};

/// World up direction, `+z`.
pub const UP: Vector3 = Vector3::new(0.0, 0.0, 1.0);
/// Direction of gravity in the world, `-z`.
pub const GRAVITY: Vector3 = Vector3::new(0.0, 0.0, -1.0);
/// An object's front in its own frame, `-y`.
pub const OBJECT_FRONT: Vector3 = Vector3::new(0.0, -1.0, 0.0);
/// An object's right (as seen by the object itself is left; see the module docs) in its own
/// frame: the `right` side, `+x`.
pub const OBJECT_RIGHT: Vector3 = Vector3::new(1.0, 0.0, 0.0);
/// An object's up in its own frame, `+z`.
pub const OBJECT_UP: Vector3 = Vector3::new(0.0, 0.0, 1.0);

/// The rotation that maps y-up, front-+z asset coordinates into the object frame
/// (z up, front -y): +90 degrees about x.
///
/// ```
/// use sceneeval_geom::{conventions::object_from_asset, Vector3};
/// let r = object_from_asset();
/// // Asset up (+y) becomes object up (+z); asset front (+z) becomes object front (-y).
/// assert!((r * Vector3::y() - Vector3::z()).norm() < 1e-15);
/// assert!((r * Vector3::z() + Vector3::y()).norm() < 1e-15);
/// ```
pub fn object_from_asset() -> Rotation3 {
    // Exact matrix rather than `from_axis_angle`, so that the conversion introduces no
    // rounding: (x, y, z) -> (x, -z, y).
    Rotation3::from_matrix_unchecked(crate::Matrix3::new(
        1.0, 0.0, 0.0, //
        0.0, 0.0, -1.0, //
        0.0, 1.0, 0.0,
    ))
}

/// A rotation about +z by `yaw` radians.
pub fn rotation_from_yaw(yaw: Real) -> Rotation3 {
    Rotation3::from_axis_angle(&Vector3::z_axis(), yaw)
}

/// The pose (`world_from_object`) of an upright object whose frame origin is at `origin`,
/// turned by `yaw` radians about +z: the rigid transform every API that places an object by
/// its yaw builds, so that an object created from a yaw and one moved to the same yaw have
/// bit-identical poses.
///
/// ```
/// use sceneeval_geom::{conventions::pose_from_yaw, Point3, Vector3};
/// let pose = pose_from_yaw(Point3::new(1.0, 2.0, 0.5), std::f64::consts::FRAC_PI_2);
/// // Yaw 90 degrees turns the object's front (-y) to world +x.
/// assert!((pose * -Vector3::y() - Vector3::x()).norm() < 1e-12);
/// assert_eq!(pose * Point3::origin(), Point3::new(1.0, 2.0, 0.5));
/// ```
pub fn pose_from_yaw(origin: Point3, yaw: Real) -> Isometry3 {
    Isometry3::from_parts(
        Translation3::from(origin.coords),
        UnitQuaternion::from_rotation_matrix(&rotation_from_yaw(yaw)),
    )
}

/// The yaw of a rotation: the z angle of its XYZ Euler decomposition,
/// `atan2(R[1,0], R[0,0])`, in `(-pi, pi]`. This is the reference's
/// `Scene.get_obj_z_rotation`; for a rotation about z only it is the rotation angle.
pub fn yaw_of(rotation: &Rotation3) -> Real {
    let m = rotation.matrix();
    m[(1, 0)].atan2(m[(0, 0)])
}

/// One of the six sides of an object, named in the object's own frame (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Side {
    /// Local -x.
    Left,
    /// Local +x.
    Right,
    /// Local -y, the object's front.
    Front,
    /// Local +y.
    Back,
    /// Local +z.
    Top,
    /// Local -z.
    Bottom,
}

impl Side {
    /// All six sides, in the order left, right, front, back, top, bottom.
    pub const ALL: [Side; 6] = [
        Side::Left,
        Side::Right,
        Side::Front,
        Side::Back,
        Side::Top,
        Side::Bottom,
    ];

    /// The four horizontal sides (left, right, front, back).
    pub const HORIZONTAL: [Side; 4] = [Side::Left, Side::Right, Side::Front, Side::Back];

    /// The local axis index (0 = x, 1 = y, 2 = z) and its sign (+1 or -1).
    #[inline]
    pub const fn axis_and_sign(self) -> (usize, Real) {
        match self {
            Side::Left => (0, -1.0),
            Side::Right => (0, 1.0),
            Side::Front => (1, -1.0),
            Side::Back => (1, 1.0),
            Side::Top => (2, 1.0),
            Side::Bottom => (2, -1.0),
        }
    }

    /// The unit direction of this side in the object frame.
    #[inline]
    pub fn local_direction(self) -> Vector3 {
        let (axis, sign) = self.axis_and_sign();
        let mut v = Vector3::zeros();
        v[axis] = sign;
        v
    }

    /// The opposite side (left <-> right, front <-> back, top <-> bottom).
    #[inline]
    pub const fn opposite(self) -> Side {
        match self {
            Side::Left => Side::Right,
            Side::Right => Side::Left,
            Side::Front => Side::Back,
            Side::Back => Side::Front,
            Side::Top => Side::Bottom,
            Side::Bottom => Side::Top,
        }
    }

    /// The snake-case name used in the paper, the annotations and the reference's prompts.
    pub const fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
            Side::Front => "front",
            Side::Back => "back",
            Side::Top => "top",
            Side::Bottom => "bottom",
        }
    }
}

impl fmt::Display for Side {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The error returned when a string is not one of the six side names.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown side {0:?}: expected one of left, right, front, back, top, bottom")]
pub struct UnknownSide(pub String);

impl FromStr for Side {
    type Err = UnknownSide;

    /// Parses a side name, ignoring ASCII case and surrounding whitespace.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim();
        Side::ALL
            .into_iter()
            .find(|side| side.name().eq_ignore_ascii_case(t))
            .ok_or_else(|| UnknownSide(s.to_owned()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn side_table_matches_reference() {
        assert_eq!(Side::Left.local_direction(), Vector3::new(-1.0, 0.0, 0.0));
        assert_eq!(Side::Right.local_direction(), Vector3::new(1.0, 0.0, 0.0));
        assert_eq!(Side::Front.local_direction(), Vector3::new(0.0, -1.0, 0.0));
        assert_eq!(Side::Back.local_direction(), Vector3::new(0.0, 1.0, 0.0));
        assert_eq!(Side::Top.local_direction(), Vector3::new(0.0, 0.0, 1.0));
        assert_eq!(Side::Bottom.local_direction(), Vector3::new(0.0, 0.0, -1.0));
        assert_eq!(Side::Front.local_direction(), OBJECT_FRONT);
    }

    #[test]
    fn sides_round_trip_through_names() {
        for side in Side::ALL {
            assert_eq!(side.name().parse::<Side>().unwrap(), side);
            assert_eq!(side.opposite().opposite(), side);
            assert_eq!(
                side.local_direction(),
                -side.opposite().local_direction(),
                "{side}"
            );
        }
        assert_eq!(" Left ".parse::<Side>().unwrap(), Side::Left);
        assert!("long".parse::<Side>().is_err());
    }

    #[test]
    fn asset_front_becomes_object_front() {
        let r = object_from_asset();
        assert_eq!(r * Vector3::z(), OBJECT_FRONT);
        assert_eq!(r * Vector3::y(), OBJECT_UP);
        assert_eq!(r * Vector3::x(), OBJECT_RIGHT);
        assert!((r.matrix().determinant() - 1.0).abs() < 1e-15);
        let expected = Rotation3::from_axis_angle(&Vector3::x_axis(), FRAC_PI_2);
        assert!((r.matrix() - expected.matrix()).norm() < 1e-15);
    }

    #[test]
    fn yaw_of_recovers_angle_and_front() {
        for &yaw in &[0.0, 0.3, -2.0, 3.0] {
            let r = rotation_from_yaw(yaw);
            assert!((yaw_of(&r) - yaw).abs() < 1e-12);
        }
        // Yaw 90 degrees turns the front (-y) to +x.
        let r = rotation_from_yaw(FRAC_PI_2);
        assert!((r * OBJECT_FRONT - Vector3::x()).norm() < 1e-12);
    }
}
