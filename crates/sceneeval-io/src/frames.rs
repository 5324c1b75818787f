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
