//! The asset-to-object frame conversion: the only place in the project where sstk transforms
//! and y-up asset coordinates meet the object frame (z up, front = local -y).
//!
//! # The rule
//! A sceneState `transform.data` holds 16 numbers in column-major order; the matrix `T` maps
//! asset coordinates (y up, front +z) to world coordinates. Its linear part `L` is decomposed
//! into a rotation `R` and a per-axis scale `S` (the column lengths of `L`):
//!
//! - the columns must be orthogonal within a relative `1e-6` (else "shear is not supported"),
//!   finite, non-zero (else "singular"), and the bottom row must be `0 0 0 1`;
//! - a negative determinant is a mirror, folded into a negative x scale;
//! - a column length within [`UNIT_SCALE_TOLERANCE`] (`1e-6`) of 1 counts as exactly 1;
//! - the object's rigid pose is `R * Rx(-90 deg)` with `T`'s translation;
//! - the object-frame mesh is `object_from_asset() * S * p` for asset vertices `p`, which is
//!   the mesh `object_from_asset() * p` scaled by `(sx, sz, sy)` in the object frame.
//!
//! Writing inverts this: `T = pose_rotation * Rx(+90 deg) * S_native` with
//! `S_native = (sx, sz, sy)` for an object-frame scale `(sx, sy, sz)`.
//!
//! Box objects (sceneState objects with a `box` entry) have no asset: their transform maps the
//! object frame to the world directly, so [`box_pose_from_sstk`] decomposes `T` the same way
//! but without the `Rx(-90 deg)`.
//!
//! # Example
//! ```
//! use sceneeval_io::frames::{asset_pose_from_sstk, sstk_from_asset_pose};
//! use sceneeval_geom::{Vector3, conventions::OBJECT_FRONT};
//!
//! // The usual generator transform Rx(+90 deg): asset y-up -> world z-up. Column-major, its
//! // columns are (1, 0, 0), (0, 0, 1), (0, -1, 0); translation (2, 1, 0).
//! let upright = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 2.0, 1.0, 0.0, 1.0];
//! let placed = asset_pose_from_sstk(&upright).unwrap();
//! // The asset's front (+z) is the object's front (-y), which T sends to world -y.
//! assert!((placed.pose.rotation * OBJECT_FRONT - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-15);
//! assert!((placed.pose.rotation * Vector3::z() - Vector3::z()).norm() < 1e-15);
//! // Writing inverts the conversion (to rounding: the pose is stored as a quaternion).
//! let back = sstk_from_asset_pose(&placed.pose, &placed.scale);
//! assert!(back.iter().zip(&upright).all(|(a, b)| (a - b).abs() < 1e-15));
//! ```

use sceneeval_geom::conventions::object_from_asset;
use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Matrix3, Real, Rotation3, Vector3};

/// Relative tolerance on the orthogonality of a transform's columns (cosine of the angle
/// between two columns).
pub const ORTHOGONALITY_TOLERANCE: Real = 1e-6;

/// A column length within this of 1 is taken as exactly 1 (no scale along that axis): float32
/// writers produce lengths like `1.0000001`, and treating them as scaled would give every
/// such object its own mesh. The geometry changes by at most this fraction.
pub const UNIT_SCALE_TOLERANCE: Real = 1e-6;

/// Absolute tolerance on the bottom row `0 0 0 1` of a transform.
pub const AFFINE_TOLERANCE: Real = 1e-9;

/// Why a transform cannot be turned into a pose.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FrameError {
    /// An element is NaN or infinite.
    #[error("element {index} is not finite ({value})")]
    NonFinite {
        /// Index into the 16 numbers.
        index: usize,
        /// The value.
        value: Real,
    },
    /// The bottom row is not `0 0 0 1`.
    #[error("the bottom row is {row:?}, not [0, 0, 0, 1] (projective transforms are not supported)")]
    NotAffine {
        /// The bottom row as read.
        row: [Real; 4],
    },
    /// A column of the linear part is zero, tiny, or overflows.
    #[error("the linear part is singular (column lengths {lengths:?})")]
    Singular {
        /// Lengths of the three columns.
        lengths: [Real; 3],
    },
    /// Two columns of the linear part are not orthogonal.
    #[error(
        "shear is not supported: columns {first} and {second} are not orthogonal \
         (cosine {cosine:.3e}, tolerance {ORTHOGONALITY_TOLERANCE:e})"
    )]
    Shear {
        /// First column.
        first: usize,
        /// Second column.
        second: usize,
        /// Cosine of the angle between them.
        cosine: Real,
    },
}

/// A transform split into rotation, scale and translation: `T = [R * diag(scale) | t]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decomposed {
    /// The rotation (determinant +1).
    pub rotation: Rotation3,
    /// Per-axis scale along the transform's own axes; a mirror shows as a negative x.
    pub scale: Vector3,
    /// The translation.
    pub translation: Vector3,
}

/// An object placed in the world: its rigid pose and the object-frame scale to apply to its
/// mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlacedObject {
    /// `world_from_object`, rigid.
    pub pose: Isometry3,
    /// Per-axis scale in the object frame (x width, y depth, z height), applied to the mesh.
    pub scale: Vector3,
}

/// Splits a column-major 4x4 transform into rotation, scale and translation (see the
/// [module docs](self) for the checks).
///
/// # Errors
/// [`FrameError`] when an element is not finite, the bottom row is not `0 0 0 1`, the linear
/// part is singular or has shear.
pub fn decompose_sstk(data: &[Real; 16]) -> Result<Decomposed, FrameError> {
    if let Some((index, &value)) = data.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(FrameError::NonFinite { index, value });
    }
    let row = [data[3], data[7], data[11], data[15]];
    if row[..3].iter().any(|v| v.abs() > AFFINE_TOLERANCE) || (row[3] - 1.0).abs() > AFFINE_TOLERANCE {
        return Err(FrameError::NotAffine { row });
    }
    let cols = [0, 1, 2].map(|j| Vector3::new(data[4 * j], data[4 * j + 1], data[4 * j + 2]));
    let lengths = cols.map(|c| c.norm());
    let longest = lengths.iter().copied().fold(0.0, Real::max);
    let shortest = lengths.iter().copied().fold(Real::INFINITY, Real::min);
    if !longest.is_finite() || shortest < Real::MIN_POSITIVE || shortest <= 1e-12 * longest {
        return Err(FrameError::Singular { lengths });
    }
    for (first, second) in [(0, 1), (0, 2), (1, 2)] {
        let cosine = cols[first].dot(&cols[second]) / (lengths[first] * lengths[second]);
        if cosine.abs() > ORTHOGONALITY_TOLERANCE {
            return Err(FrameError::Shear {
                first,
                second,
                cosine,
            });
        }
    }
    let linear = Matrix3::from_columns(&cols);
    let mirror = linear.determinant() < 0.0;
    let sign = if mirror { -1.0 } else { 1.0 };
    let unit = Matrix3::from_columns(&[
        cols[0] / (sign * lengths[0]),
        cols[1] / lengths[1],
        cols[2] / lengths[2],
    ]);
    // Lengths within UNIT_SCALE_TOLERANCE of 1 (float32 writers produce 1 +- 1e-7) are 1, so
    // that such objects share their asset's unscaled mesh.
    let snapped = lengths.map(|l| {
        if (l - 1.0).abs() <= UNIT_SCALE_TOLERANCE {
            1.0
        } else {
            l
        }
    });
    let scale = Vector3::new(sign * snapped[0], snapped[1], snapped[2]);
    // The columns are orthonormal to within the tolerance; take the nearest rotation, starting
    // from the quaternion read off the matrix.
    let guess = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(unit));
    let rotation = Rotation3::from_matrix_eps(&unit, Real::EPSILON, 16, guess.to_rotation_matrix());
    Ok(Decomposed {
        rotation,
        scale,
        translation: Vector3::new(data[12], data[13], data[14]),
    })
}

/// The column-major 4x4 transform `[rotation * diag(scale) | translation]`.
pub fn compose_sstk(rotation: &Rotation3, scale: &Vector3, translation: &Vector3) -> [Real; 16] {
    let m = rotation.matrix();
    let mut data = [0.0; 16];
    for j in 0..3 {
        for i in 0..3 {
            // `+ 0.0` turns a negative zero into a positive one.
            data[4 * j + i] = m[(i, j)] * scale[j] + 0.0;
        }
        data[12 + j] = translation[j] + 0.0;
    }
    data[15] = 1.0;
    data
}

/// The pose and object-frame scale of an asset object whose sceneState transform is `data`.
///
/// # Errors
/// As [`decompose_sstk`].
pub fn asset_pose_from_sstk(data: &[Real; 16]) -> Result<PlacedObject, FrameError> {
    let d = decompose_sstk(data)?;
    let rotation = d.rotation * object_from_asset().inverse();
    Ok(PlacedObject {
        pose: isometry(&rotation, &d.translation),
        scale: object_scale_from_native(&d.scale),
    })
}

/// The sceneState transform of an asset object with this pose and object-frame scale: the
/// inverse of [`asset_pose_from_sstk`].
pub fn sstk_from_asset_pose(pose: &Isometry3, scale: &Vector3) -> [Real; 16] {
    let rotation = pose.rotation.to_rotation_matrix() * object_from_asset();
    compose_sstk(
        &rotation,
        &native_scale_from_object(scale),
        &pose.translation.vector,
    )
}

/// The pose and scale of a box object (no asset: the transform maps the object frame to the
/// world directly).
///
/// # Errors
/// As [`decompose_sstk`].
pub fn box_pose_from_sstk(data: &[Real; 16]) -> Result<PlacedObject, FrameError> {
    let d = decompose_sstk(data)?;
    Ok(PlacedObject {
        pose: isometry(&d.rotation, &d.translation),
        scale: d.scale,
    })
}

/// The sceneState transform of a box object: the inverse of [`box_pose_from_sstk`].
pub fn sstk_from_box_pose(pose: &Isometry3, scale: &Vector3) -> [Real; 16] {
    compose_sstk(
        &pose.rotation.to_rotation_matrix(),
        scale,
        &pose.translation.vector,
    )
}

/// The object-frame scale `(sx, sz, sy)` for a scale `(sx, sy, sz)` along the asset's axes.
#[inline]
pub fn object_scale_from_native(native: &Vector3) -> Vector3 {
    Vector3::new(native.x, native.z, native.y)
}

/// The asset-axis scale for an object-frame scale (the inverse of
/// [`object_scale_from_native`]).
#[inline]
pub fn native_scale_from_object(object: &Vector3) -> Vector3 {
    Vector3::new(object.x, object.z, object.y)
}

/// The matrix mapping asset coordinates to the object frame for an asset placed with the
/// object-frame scale `scale`: `diag(scale) * object_from_asset()`
/// (= `object_from_asset() * diag(native scale)`).
pub fn object_from_asset_scaled(scale: &Vector3) -> Matrix3 {
    Matrix3::from_diagonal(scale) * object_from_asset().matrix()
}

/// The linear map from a mesh file's coordinates to the (unscaled) object frame:
/// `object_from_asset() * alignment`, where `alignment` is the asset source's rotation for
/// datasets not stored y-up with front +z (see `crate::assets::AssetLocation::alignment`).
/// Geometry and appearance loading both use this, so their meshes agree vertex for vertex.
pub fn object_from_file(alignment: Option<&Rotation3>) -> Matrix3 {
    match alignment {
        Some(e) => object_from_asset().matrix() * e.matrix(),
        None => *object_from_asset().matrix(),
    }
}

/// How an asset object's sceneState `transform.data` is to be read, chosen by its model id's
/// prefix as the SceneSmith fork of the reference chooses it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TransformFrame {
    /// The sstk convention: the transform maps the asset file's coordinates (y up, front +z)
    /// to the world, and the object frame is `T * Rx(-90 deg)`.
    Asset,
    /// The transform maps the object frame (z up: the mesh file's coordinates turned by
    /// `Rx(+90 deg)`, as a glTF importer into a z-up program turns them) to the world
    /// directly, as for box objects. Generators that export z-up scenes write this
    /// (IDesign, SceneAgent / SceneSmith: see [`Z_UP_PREFIXES`]).
    Object,
}

/// Model id prefixes whose transforms map the z-up object frame ([`TransformFrame::Object`]):
/// `idesign`, `scene-agent` and `scenesmith`. The fork loads these without its
/// `Rx(-90 deg)` correction; every other prefix uses [`TransformFrame::Asset`].
pub const Z_UP_PREFIXES: [&str; 3] = ["idesign", "scene-agent", "scenesmith"];

impl TransformFrame {
    /// The convention of an asset object's transform, from its model id (`PREFIX.ID`; the
    /// prefix is the part before the first dot).
    ///
    /// ```
    /// use sceneeval_io::frames::TransformFrame;
    /// assert_eq!(TransformFrame::for_model_id("scene-agent.scene_3__desk_0"), TransformFrame::Object);
    /// assert_eq!(TransformFrame::for_model_id("objaverse.0a1b"), TransformFrame::Asset);
    /// ```
    pub fn for_model_id(model_id: &str) -> TransformFrame {
        let prefix = model_id.split_once('.').map_or(model_id, |(p, _)| p);
        if Z_UP_PREFIXES.contains(&prefix) {
            TransformFrame::Object
        } else {
            TransformFrame::Asset
        }
    }

    /// Splits a transform read in this convention into the object's pose and object-frame
    /// scale.
    ///
    /// # Errors
    /// As [`decompose_sstk`].
    pub fn placed(self, data: &[Real; 16]) -> Result<PlacedObject, FrameError> {
        match self {
            TransformFrame::Asset => asset_pose_from_sstk(data),
            TransformFrame::Object => box_pose_from_sstk(data),
        }
    }

    /// The transform of an object with this pose and object-frame scale, in this convention
    /// (the inverse of [`TransformFrame::placed`]).
    pub fn sstk(self, pose: &Isometry3, scale: &Vector3) -> [Real; 16] {
        match self {
            TransformFrame::Asset => sstk_from_asset_pose(pose, scale),
            TransformFrame::Object => sstk_from_box_pose(pose, scale),
        }
    }
}

/// The front an object's asset faces in the object frame (z up) as a scene file declares it
/// (sceneState `objectFrontVector`): one of the four horizontal axis directions. The model's
/// convention is [`ObjectFront::MinusY`]; an object declared otherwise is turned when it is
/// read, so that local -y is its front again ([`ObjectFront::turn`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum ObjectFront {
    /// `[0, -1, 0]`: the model's convention (and the default).
    #[default]
    MinusY,
    /// `[0, 1, 0]` (IDesign, SceneAgent / SceneSmith).
    PlusY,
    /// `[1, 0, 0]`.
    PlusX,
    /// `[-1, 0, 0]`.
    MinusX,
}

impl ObjectFront {
    /// The declared front of a vector: it must be finite, horizontal (`z = 0`) and along x
    /// or y; its length does not matter.
    ///
    /// ```
    /// use sceneeval_io::frames::ObjectFront;
    /// assert_eq!(ObjectFront::from_vector([0.0, 2.0, 0.0]), Ok(ObjectFront::PlusY));
    /// assert!(ObjectFront::from_vector([0.6, 0.8, 0.0]).is_err());
    /// ```
    ///
    /// # Errors
    /// A message saying what is wrong with the vector.
    pub fn from_vector(v: [Real; 3]) -> Result<ObjectFront, String> {
        if !v.iter().all(|c| c.is_finite()) {
            return Err(format!("{v:?} is not finite"));
        }
        match v {
            [x, y, z] if z == 0.0 && x == 0.0 && y < 0.0 => Ok(ObjectFront::MinusY),
            [x, y, z] if z == 0.0 && x == 0.0 && y > 0.0 => Ok(ObjectFront::PlusY),
            [x, y, z] if z == 0.0 && y == 0.0 && x > 0.0 => Ok(ObjectFront::PlusX),
            [x, y, z] if z == 0.0 && y == 0.0 && x < 0.0 => Ok(ObjectFront::MinusX),
            _ => Err(format!(
                "{v:?} is not a horizontal axis direction: expected [0, -1, 0], [0, 1, 0], \
                 [1, 0, 0] or [-1, 0, 0]"
            )),
        }
    }

    /// The unit vector.
    pub fn vector(self) -> Vector3 {
        match self {
            ObjectFront::MinusY => Vector3::new(0.0, -1.0, 0.0),
            ObjectFront::PlusY => Vector3::new(0.0, 1.0, 0.0),
            ObjectFront::PlusX => Vector3::new(1.0, 0.0, 0.0),
            ObjectFront::MinusX => Vector3::new(-1.0, 0.0, 0.0),
        }
    }

    /// The turn `Q` about +z with `Q * front = -y`, with exact entries (0 and +-1). An
    /// object read with this front gets the mesh `Q * m` and the pose `pose * Q^-1`: the same
    /// world geometry, with local -y now its front.
    pub fn turn(self) -> Rotation3 {
        let m = match self {
            ObjectFront::MinusY => Matrix3::identity(),
            // Rz(180): (x, y) -> (-x, -y).
            ObjectFront::PlusY => Matrix3::new(-1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0),
            // Rz(-90): (x, y) -> (y, -x), so +x -> -y.
            ObjectFront::PlusX => Matrix3::new(0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0),
            // Rz(+90): (x, y) -> (-y, x), so -x -> -y.
            ObjectFront::MinusX => Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0),
        };
        Rotation3::from_matrix_unchecked(m)
    }

    /// An object-frame scale (or box size) after the turn: `Q * diag(s) * Q^-1`, which is
    /// diagonal because the turn only permutes axes (x and y swap for a quarter turn).
    pub fn turn_scale(self, s: &Vector3) -> Vector3 {
        match self {
            ObjectFront::MinusY | ObjectFront::PlusY => *s,
            ObjectFront::PlusX | ObjectFront::MinusX => Vector3::new(s.y, s.x, s.z),
        }
    }

    /// The turn `Q` as a unit quaternion: its components are 0, +-1 or +-sqrt(1/2), so a
    /// half turn composes with a pose without rounding.
    fn turn_quaternion(self) -> UnitQuaternion<Real> {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let (w, k) = match self {
            ObjectFront::MinusY => (1.0, 0.0),
            ObjectFront::PlusY => (0.0, 1.0),
            ObjectFront::PlusX => (h, -h),
            ObjectFront::MinusX => (h, h),
        };
        UnitQuaternion::new_unchecked(sceneeval_geom::na::Quaternion::new(w, 0.0, 0.0, k))
    }

    /// The pose the model uses for an object placed at `pose` (in the file's object frame)
    /// with this front: `pose * Q^-1`.
    pub fn model_pose(self, pose: &Isometry3) -> Isometry3 {
        if self == ObjectFront::MinusY {
            return *pose;
        }
        Isometry3::from_parts(pose.translation, pose.rotation * self.turn_quaternion().inverse())
    }

    /// The pose in the file's object frame of an object the model holds at `model_pose`:
    /// `model_pose * Q` (the inverse of [`ObjectFront::model_pose`]; exact for a half turn,
    /// to rounding for a quarter turn).
    pub fn file_pose(self, model_pose: &Isometry3) -> Isometry3 {
        if self == ObjectFront::MinusY {
            return *model_pose;
        }
        Isometry3::from_parts(
            model_pose.translation,
            model_pose.rotation * self.turn_quaternion(),
        )
    }
}

fn isometry(rotation: &Rotation3, translation: &Vector3) -> Isometry3 {
    Isometry3::from_parts(
        Translation3::from(*translation),
        UnitQuaternion::from_rotation_matrix(rotation),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::Point3;
    use sceneeval_geom::conventions::{OBJECT_FRONT, OBJECT_UP};
    use std::f64::consts::FRAC_PI_2;

    fn column_major(m: &sceneeval_geom::na::Matrix4<Real>) -> [Real; 16] {
        let mut d = [0.0; 16];
        d.copy_from_slice(m.as_slice());
        d
    }

    #[test]
    fn identity_turns_asset_front_to_world_minus_y() {
        let placed = asset_pose_from_sstk(&column_major(&sceneeval_geom::na::Matrix4::identity())).unwrap();
        // T = I leaves the asset y-up: the object frame is Rx(-90), which maps (x, y, z) to
        // (x, z, -y), so the object front (0, -1, 0) -> (0, 0, 1) = the asset front +z.
        let front = placed.pose.rotation * OBJECT_FRONT;
        assert!((front - Vector3::z()).norm() < 1e-15, "{front}");
        // Object up (+z) -> (0, 1, 0): the asset's up stays world +y under T = I.
        assert!((placed.pose.rotation * OBJECT_UP - Vector3::y()).norm() < 1e-15);
        assert_eq!(placed.scale, Vector3::repeat(1.0));
    }

    #[test]
    fn y_up_to_z_up_transform_gives_upright_object() {
        // The usual generator transform: Rx(+90) (asset y-up -> world z-up), at (1, 2, 0).
        // Column-major: columns (1,0,0), (0,0,1), (0,-1,0), translation (1,2,0).
        let data = [
            1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 2.0, 0.0, 1.0,
        ];
        let placed = asset_pose_from_sstk(&data).unwrap();
        // Pose = Rx(+90) * Rx(-90) = identity: front = world -y, up = world +z.
        assert!((placed.pose.rotation.to_rotation_matrix().matrix() - Matrix3::identity()).norm() < 1e-15);
        assert_eq!(placed.pose.translation.vector, Vector3::new(1.0, 2.0, 0.0));
        let back = sstk_from_asset_pose(&placed.pose, &placed.scale);
        assert!(
            back.iter().zip(&data).all(|(a, b)| (a - b).abs() < 1e-15),
            "{back:?}"
        );
    }

    #[test]
    fn scale_mirror_and_round_trip() {
        // T = Rz(90) * Rx(90) * diag(-2, 3, 0.5): native scale (-2, 3, 0.5), a mirror in x.
        let rot = Rotation3::from_axis_angle(&Vector3::z_axis(), FRAC_PI_2)
            * Rotation3::from_axis_angle(&Vector3::x_axis(), FRAC_PI_2);
        let data = compose_sstk(&rot, &Vector3::new(-2.0, 3.0, 0.5), &Vector3::new(4.0, 5.0, 6.0));
        let d = decompose_sstk(&data).unwrap();
        assert!((d.scale - Vector3::new(-2.0, 3.0, 0.5)).norm() < 1e-14);
        assert!((d.rotation.matrix() - rot.matrix()).norm() < 1e-14);
        let placed = asset_pose_from_sstk(&data).unwrap();
        // Object-frame scale is (sx, sz, sy).
        assert!((placed.scale - Vector3::new(-2.0, 0.5, 3.0)).norm() < 1e-14);
        // The pose is Rz(90): the object's front (-y) points to world +x.
        assert!((placed.pose.rotation * OBJECT_FRONT - Vector3::x()).norm() < 1e-14);
        let back = sstk_from_asset_pose(&placed.pose, &placed.scale);
        for (a, b) in back.iter().zip(&data) {
            assert!((a - b).abs() < 1e-14);
        }
        // World position of an asset vertex: T * p equals pose * (object-frame mesh vertex).
        let p = Vector3::new(0.3, -0.7, 1.1);
        let t = sceneeval_geom::na::Matrix4::from_column_slice(&data);
        let world = t.transform_point(&Point3::from(p));
        let object_vertex = object_from_asset_scaled(&placed.scale) * p;
        let via_pose = placed.pose * Point3::from(object_vertex);
        assert!((world - via_pose).norm() < 1e-14);
    }

    #[test]
    fn lengths_near_one_are_unit_scale() {
        // Column lengths 1 + 5e-7 (within the tolerance) and 1 + 2e-6 (outside it).
        let data = [
            1.0 + 5e-7,
            0.0,
            0.0,
            0.0,
            0.0,
            1.0 + 2e-6,
            0.0,
            0.0,
            0.0,
            0.0,
            -(1.0 - 5e-7),
            0.0,
            0.0,
            0.0,
            0.0,
            1.0,
        ];
        let d = decompose_sstk(&data).unwrap();
        // Determinant < 0: a mirror, folded into x.
        assert_eq!(d.scale, Vector3::new(-1.0, 1.0 + 2e-6, 1.0));
        assert!(
            (d.rotation.matrix() - Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, -1.0))).norm() < 1e-15
        );
    }

    #[test]
    fn fronts_turn_to_minus_y_exactly() {
        for front in [
            ObjectFront::MinusY,
            ObjectFront::PlusY,
            ObjectFront::PlusX,
            ObjectFront::MinusX,
        ] {
            let q = front.turn();
            // Q * front = -y, exactly (entries are 0 and +-1), and Q is a rotation about +z.
            assert_eq!(q * front.vector(), OBJECT_FRONT, "{front:?}");
            assert_eq!(q * Vector3::z(), Vector3::z());
            assert_eq!(q.matrix().determinant(), 1.0);
            // The quaternion is the same rotation.
            assert!((front.turn_quaternion().to_rotation_matrix().matrix() - q.matrix()).norm() < 1e-15);
            // Scale: Q diag(s) Q^-1 = diag(turn_scale(s)).
            let s = Vector3::new(1.0, 2.0, 3.0);
            let turned = q.matrix() * Matrix3::from_diagonal(&s) * q.inverse().matrix();
            assert_eq!(turned, Matrix3::from_diagonal(&front.turn_scale(&s)));
            assert_eq!(ObjectFront::from_vector(front.vector().into()), Ok(front));
        }
        // Model pose = pose * Q^-1: the world front of the turned object is pose * front.
        let pose = Isometry3::new(Vector3::new(1.0, 2.0, 0.0), Vector3::z() * 0.3);
        for front in [ObjectFront::PlusY, ObjectFront::PlusX, ObjectFront::MinusX] {
            let model = front.model_pose(&pose);
            assert!((model.rotation * OBJECT_FRONT - pose.rotation * front.vector()).norm() < 1e-15);
            let back = front.file_pose(&model);
            assert!(back.rotation.angle_to(&pose.rotation) < 1e-15);
        }
        // A half turn composes without rounding.
        assert_eq!(
            ObjectFront::PlusY.file_pose(&ObjectFront::PlusY.model_pose(&pose)),
            pose
        );
        for bad in [
            [0.0, 0.0, 1.0],
            [0.6, 0.8, 0.0],
            [0.0, 1.0, 0.1],
            [0.0, 0.0, 0.0],
            [Real::NAN, 1.0, 0.0],
        ] {
            assert!(ObjectFront::from_vector(bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn z_up_prefixes_read_transforms_in_the_object_frame() {
        // Rz(90) at (1, 2, 3) with object-frame scale (2, 1, 1): as an object-frame transform
        // the pose is Rz(90) and the scale (2, 1, 1) as given.
        let rot = Rotation3::from_axis_angle(&Vector3::z_axis(), FRAC_PI_2);
        let data = compose_sstk(&rot, &Vector3::new(2.0, 1.0, 1.0), &Vector3::new(1.0, 2.0, 3.0));
        let frame = TransformFrame::for_model_id("idesign.scene_0__bed_1");
        assert_eq!(frame, TransformFrame::Object);
        let placed = frame.placed(&data).unwrap();
        assert!((placed.pose.rotation.to_rotation_matrix().matrix() - rot.matrix()).norm() < 1e-15);
        assert_eq!(placed.scale, Vector3::new(2.0, 1.0, 1.0));
        let back = frame.sstk(&placed.pose, &placed.scale);
        assert!(back.iter().zip(&data).all(|(a, b)| (a - b).abs() < 1e-15));
        for (id, expected) in [
            ("scenesmith.desk_0", TransformFrame::Object),
            ("scene-agent.scene_0__desk_0", TransformFrame::Object),
            ("objaverse.abc", TransformFrame::Asset),
            ("idesignx.a", TransformFrame::Asset),
            ("idesign", TransformFrame::Object),
        ] {
            assert_eq!(TransformFrame::for_model_id(id), expected, "{id}");
        }
    }

    #[test]
    fn bad_transforms_are_rejected() {
        let mut data = column_major(&sceneeval_geom::na::Matrix4::identity());
        data[13] = Real::NAN;
        assert!(matches!(
            decompose_sstk(&data),
            Err(FrameError::NonFinite { index: 13, .. })
        ));
        let mut data = column_major(&sceneeval_geom::na::Matrix4::identity());
        data[3] = 0.5;
        assert!(matches!(decompose_sstk(&data), Err(FrameError::NotAffine { .. })));
        let mut data = column_major(&sceneeval_geom::na::Matrix4::identity());
        data[5] = 0.0;
        assert!(matches!(decompose_sstk(&data), Err(FrameError::Singular { .. })));
        let mut data = column_major(&sceneeval_geom::na::Matrix4::identity());
        data[4] = 0.1; // column 1 = (0.1, 1, 0): cosine with column 0 is 0.0995
        match decompose_sstk(&data) {
            Err(FrameError::Shear {
                first: 0,
                second: 1,
                cosine,
            }) => assert!((cosine - 0.1 / (1.01f64).sqrt()).abs() < 1e-12),
            other => panic!("{other:?}"),
        }
        // Overflowing columns count as singular, not as a finite pose.
        let mut data = column_major(&sceneeval_geom::na::Matrix4::identity());
        data[0] = 1e300;
        data[1] = 1e300;
        data[5] = 0.0;
        data[4] = 0.0;
        assert!(decompose_sstk(&data).is_err());
    }
}
