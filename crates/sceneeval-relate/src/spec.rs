//! Objects as plain data: boxes and placed mesh assets the way a client outside Rust writes
//! them (the JSON of `sceneeval relate`, the dicts and rows of the Python package), checked
//! here so that every front end accepts the same inputs and gives the same errors. Rooms as
//! plain data are `sceneeval_scene::RoomSpec`, beside the room builder.
//!
//! - [`BoxSpec`]: a solid box from its centre, half extents and a yaw (radians about +z) or a
//!   3x3 row-major rotation matrix. [`BoxSpec::to_obb`] checks every number is finite and the
//!   rotation proper.
//! - [`AssetObjectSpec`]: a mesh asset by model id with a position, rotation and scale (the
//!   session loads the asset through its `sceneeval_io::AssetLibrary`).
//! - [`ObjectSpec`]: either, told apart by the `asset` key.
//!
//! They deserialize from the documented schema (`docs/formats.md`, "`sceneeval relate` JSON
//! lines"): unknown fields are errors.

use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Matrix3, Obb, Point3, Real, Rotation3, Vector3};
use sceneeval_relations::RelationError;

/// A solid box: centre, half extents, and either a yaw (radians about +z, counter-clockwise
/// seen from above) or a 3x3 row-major rotation matrix. Neither means axis-aligned.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    /// Centre in world coordinates, metres.
    pub center: [Real; 3],
    /// Half extents along the box's local x, y, z, metres.
    pub half_size: [Real; 3],
    /// Rotation about +z, radians.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yaw: Option<Real>,
    /// Full rotation (local axes as columns), row-major.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<RotationSpec>,
}

/// A 3x3 rotation matrix, row-major: as nested rows or as nine numbers.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
pub enum RotationSpec {
    /// `[[r00, r01, r02], [r10, r11, r12], [r20, r21, r22]]`.
    Rows([[Real; 3]; 3]),
    /// `[r00, r01, r02, r10, ..., r22]`.
    Flat([Real; 9]),
}

impl RotationSpec {
    /// The rows of the matrix.
    pub fn rows(&self) -> [[Real; 3]; 3] {
        match self {
            RotationSpec::Rows(rows) => *rows,
            RotationSpec::Flat(f) => [[f[0], f[1], f[2]], [f[3], f[4], f[5]], [f[6], f[7], f[8]]],
        }
    }
}

impl BoxSpec {
    /// A box rotated by `yaw` radians about +z.
    pub fn from_yaw(center: [Real; 3], half_size: [Real; 3], yaw: Real) -> Self {
        BoxSpec {
            center,
            half_size,
            yaw: Some(yaw),
            rotation: None,
        }
    }

    /// The oriented box. `what` names the box in errors (for example `target` or
    /// `targets[2]`).
    ///
    /// # Errors
    /// [`RelationError::NotFinite`] for a NaN or infinite number, [`RelationError::Conflict`]
    /// when both a yaw and a rotation are given, [`RelationError::Geometry`] for negative half
    /// extents or a matrix that is not a proper rotation.
    pub fn to_obb(&self, what: &str) -> Result<Obb, RelationError> {
        if let (Some(yaw), None) = (self.yaw, &self.rotation)
            && let Some(obb) = yaw_box(self.center, self.half_size, yaw)
        {
            return Ok(obb);
        }
        self.checked_obb(what)
    }

    /// The oriented box of a centre, half extents and yaw: exactly
    /// `BoxSpec::from_yaw(center, half_size, yaw).to_obb(&what())`, without building the spec;
    /// `what` is called only for an error, so a valid box allocates nothing. This is how the
    /// Python package's batch forms read their `(N, 7)` rows.
    ///
    /// ```
    /// use sceneeval_relate::BoxSpec;
    /// let obb = BoxSpec::yaw_obb([1.0, 2.0, 0.5], [0.5, 0.25, 0.5], 0.3, || "targets[4]".into()).unwrap();
    /// assert_eq!(Some(obb), BoxSpec::from_yaw([1.0, 2.0, 0.5], [0.5, 0.25, 0.5], 0.3).to_obb("t").ok());
    /// let err = BoxSpec::yaw_obb([1.0, 2.0, 0.5], [0.5, f64::NAN, 0.5], 0.3, || "targets[4]".into());
    /// assert_eq!(err.unwrap_err().to_string(), "targets[4].half_size is not finite");
    /// ```
    ///
    /// # Errors
    /// As [`BoxSpec::to_obb`].
    #[inline]
    pub fn yaw_obb(
        center: [Real; 3],
        half_size: [Real; 3],
        yaw: Real,
        what: impl FnOnce() -> String,
    ) -> Result<Obb, RelationError> {
        match yaw_box(center, half_size, yaw) {
            Some(obb) => Ok(obb),
            None => BoxSpec::from_yaw(center, half_size, yaw).checked_obb(&what()),
        }
    }

    /// [`BoxSpec::to_obb`] checking every number and the rotation through [`Obb::new`].
    fn checked_obb(&self, what: &str) -> Result<Obb, RelationError> {
        finite(&self.center, || format!("{what}.center"))?;
        finite(&self.half_size, || format!("{what}.half_size"))?;
        let rotation = rotation_of(self.yaw, self.rotation.as_ref(), what)?;
        Obb::new(Point3::from(self.center), Vector3::from(self.half_size), rotation).map_err(|source| {
            RelationError::Geometry {
                what: format!("{what} is not a valid box"),
                source,
            }
        })
    }
}

/// An object showing a mesh asset: the asset's model id (`PREFIX.ID`, resolved by the caller,
/// for example through `sceneeval_io::AssetLibrary`), where its object frame stands, its
/// rotation (a yaw about +z or a row-major matrix; neither means none) and its scale along
/// the object frame's axes (default 1).
///
/// The object frame is the asset's (z up, front -y; `docs/conventions.md`): `position` is
/// where the asset's origin goes, not the centre of its bounds.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AssetObjectSpec {
    /// The model id, `PREFIX.ID`.
    pub asset: String,
    /// World position of the object frame's origin, metres.
    pub position: [Real; 3],
    /// Rotation about +z, radians.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yaw: Option<Real>,
    /// Full rotation (object axes as columns), row-major.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<RotationSpec>,
    /// Scale along the object frame's x, y, z (one number for all three); default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<ScaleSpec>,
}

/// A scale: one factor for all three axes, or one per axis.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
pub enum ScaleSpec {
    /// The same factor along x, y and z.
    Uniform(Real),
    /// Factors along x, y, z.
    PerAxis([Real; 3]),
}

impl AssetObjectSpec {
    /// The pose placing the object frame in the world (`world_from_object`). `what` names
    /// the object in errors.
    ///
    /// # Errors
    /// [`RelationError::NotFinite`], [`RelationError::Conflict`] for both a yaw and a
    /// rotation, [`RelationError::Geometry`] for a matrix that is not a proper rotation.
    pub fn pose(&self, what: &str) -> Result<Isometry3, RelationError> {
        finite(&self.position, || format!("{what}.position"))?;
        let rotation = rotation_of(self.yaw, self.rotation.as_ref(), what)?;
        // A zero-size box at the origin checks the rotation exactly as a box's is checked.
        Obb::new(Point3::from(self.position), Vector3::zeros(), rotation).map_err(|source| {
            RelationError::Geometry {
                what: format!("{what}.rotation is not a valid rotation"),
                source,
            }
        })?;
        Ok(Isometry3::from_parts(
            Translation3::from(Vector3::from(self.position)),
            UnitQuaternion::from_rotation_matrix(&rotation),
        ))
    }

    /// The scale along the object frame's x, y, z.
    ///
    /// # Errors
    /// [`RelationError::BadScale`] when a factor is not finite or not positive.
    pub fn scale(&self, what: &str) -> Result<Vector3, RelationError> {
        let scale = match self.scale {
            None => Vector3::repeat(1.0),
            Some(ScaleSpec::Uniform(s)) => Vector3::repeat(s),
            Some(ScaleSpec::PerAxis(s)) => Vector3::from(s),
        };
        if scale.iter().all(|s| s.is_finite() && *s > 0.0) {
            Ok(scale)
        } else {
            Err(RelationError::BadScale {
                what: what.to_owned(),
                scale: [scale.x, scale.y, scale.z],
            })
        }
    }
}

/// An object given as plain data: a solid box ([`BoxSpec`]) or a mesh asset
/// ([`AssetObjectSpec`]). In JSON the two are told apart by the `asset` key: an object with
/// `asset` is an asset object, any other a box.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(untagged)]
pub enum ObjectSpec {
    /// A solid box.
    Box(BoxSpec),
    /// A mesh asset placed in the world.
    Asset(AssetObjectSpec),
}

impl<'de> serde::Deserialize<'de> for ObjectSpec {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        // Every key of both forms, read in one pass (no buffering), then sorted out.
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Fields {
            #[serde(default)]
            center: Option<[Real; 3]>,
            #[serde(default)]
            half_size: Option<[Real; 3]>,
            #[serde(default)]
            yaw: Option<Real>,
            #[serde(default)]
            rotation: Option<RotationSpec>,
            #[serde(default)]
            asset: Option<String>,
            #[serde(default)]
            position: Option<[Real; 3]>,
            #[serde(default)]
            scale: Option<ScaleSpec>,
        }
        let f = Fields::deserialize(deserializer)?;
        match f.asset {
            Some(asset) => {
                if f.center.is_some() || f.half_size.is_some() {
                    return Err(D::Error::custom(
                        "an asset object is placed by \"position\" (its origin); \"center\" and \"half_size\" belong to boxes",
                    ));
                }
                let position = f.position.ok_or_else(|| D::Error::missing_field("position"))?;
                Ok(ObjectSpec::Asset(AssetObjectSpec {
                    asset,
                    position,
                    yaw: f.yaw,
                    rotation: f.rotation,
                    scale: f.scale,
                }))
            }
            None => {
                if f.position.is_some() || f.scale.is_some() {
                    return Err(D::Error::custom(
                        "\"position\" and \"scale\" belong to asset objects (with \"asset\"); a box has \"center\" and \"half_size\"",
                    ));
                }
                Ok(ObjectSpec::Box(BoxSpec {
                    center: f.center.ok_or_else(|| D::Error::missing_field("center"))?,
                    half_size: f.half_size.ok_or_else(|| D::Error::missing_field("half_size"))?,
                    yaw: f.yaw,
                    rotation: f.rotation,
                }))
            }
        }
    }
}

/// The box turned by `yaw` when every number is finite and no half extent is negative, else
/// `None`. It is the box [`Obb::new`] validates in [`BoxSpec::checked_obb`], with the same
/// rotation (`rotation_of`), built without `Obb::new`'s check that the matrix is a rotation:
/// a turn about +z made by `Rotation3::from_axis_angle` from a finite angle is one (its
/// columns are `(c, s, 0)`, `(-s, c, 0)`, `(0, 0, 1)` with `c^2 + s^2` one within rounding).
#[inline]
fn yaw_box(center: [Real; 3], half_size: [Real; 3], yaw: Real) -> Option<Obb> {
    let finite = center.iter().chain(&half_size).all(|v| v.is_finite()) && yaw.is_finite();
    if !finite || half_size.iter().any(|&h| h < 0.0) {
        return None;
    }
    Some(Obb {
        center: Point3::from(center),
        half_extents: Vector3::from(half_size),
        rotation: Rotation3::from_axis_angle(&Vector3::z_axis(), yaw),
    })
}

/// The rotation given by a `yaw` or a row-major `rotation` (neither: identity), unchecked
/// beyond finiteness (callers validate it as part of a box).
fn rotation_of(
    yaw: Option<Real>,
    rotation: Option<&RotationSpec>,
    what: &str,
) -> Result<Rotation3, RelationError> {
    match (yaw, rotation) {
        (Some(_), Some(_)) => Err(RelationError::Conflict {
            what: what.to_owned(),
            first: "\"yaw\"",
            second: "\"rotation\"",
        }),
        (Some(yaw), None) => {
            finite(&[yaw], || format!("{what}.yaw"))?;
            Ok(Rotation3::from_axis_angle(&Vector3::z_axis(), yaw))
        }
        (None, None) => Ok(Rotation3::identity()),
        (None, Some(r)) => {
            let rows = r.rows();
            finite(rows.as_flattened(), || format!("{what}.rotation"))?;
            Ok(Rotation3::from_matrix_unchecked(Matrix3::from_fn(|i, j| {
                rows[i][j]
            })))
        }
    }
}

/// `Ok` when every value is finite, else [`RelationError::NotFinite`] naming `field()`.
fn finite(values: &[Real], field: impl FnOnce() -> String) -> Result<(), RelationError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(RelationError::NotFinite { field: field() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_cube(x: Real) -> BoxSpec {
        BoxSpec::from_yaw([x, 0.0, 0.5], [0.5, 0.5, 0.5], 0.0)
    }

    #[test]
    fn boxes_reject_non_finite_numbers_and_both_rotations() {
        let mut b = unit_cube(0.0);
        b.center[1] = Real::NAN;
        assert_eq!(
            b.to_obb("target"),
            Err(RelationError::NotFinite {
                field: "target.center".into()
            })
        );
        let mut b = unit_cube(0.0);
        b.rotation = Some(RotationSpec::Flat([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]));
        assert!(matches!(b.to_obb("anchor"), Err(RelationError::Conflict { .. })));
        let mut b = unit_cube(0.0);
        b.half_size[0] = -1.0;
        assert!(matches!(b.to_obb("anchor"), Err(RelationError::Geometry { .. })));
    }

    #[test]
    fn yaw_boxes_are_the_boxes_the_checked_path_makes() {
        // The shortcut for a yaw builds the same box, bit for bit, as the path through
        // Obb::new; and every invalid box gets the checked path's error.
        let mut rng = sceneeval_test_support::Lcg(0x9e37_79b9_7f4a_7c15);
        let mut next = || rng.next();
        for i in 0..2000 {
            let c = [next() * 10.0 - 5.0, next() * 10.0 - 5.0, next() * 2.0];
            let h = [next(), next() * 0.5, next() * 2.0];
            let yaw = match i % 4 {
                0 => next() * 7.0 - 3.5,
                1 => (next() * 1e6).round() * 1e-3,
                2 => [0.0, std::f64::consts::PI, -std::f64::consts::FRAC_PI_2, 1e12][i % 8 / 2],
                _ => next() * 200.0 - 100.0,
            };
            let spec = BoxSpec::from_yaw(c, h, yaw);
            let checked = spec.checked_obb("b").unwrap();
            assert_eq!(spec.to_obb("b").unwrap(), checked, "{c:?} {h:?} {yaw}");
            assert_eq!(BoxSpec::yaw_obb(c, h, yaw, || "b".into()).unwrap(), checked);
        }
        let good = ([0.0, 0.0, 0.5], [0.5, 0.5, 0.5], 0.2);
        let bad_rows = [
            ([Real::NAN, 0.0, 0.5], good.1, good.2),
            (good.0, [0.5, Real::INFINITY, 0.5], good.2),
            (good.0, [0.5, -0.1, 0.5], good.2),
            (good.0, good.1, Real::NEG_INFINITY),
        ];
        for (c, h, yaw) in bad_rows {
            let expected = BoxSpec::from_yaw(c, h, yaw).checked_obb("rows[3]").unwrap_err();
            assert_eq!(
                BoxSpec::yaw_obb(c, h, yaw, || "rows[3]".into()).unwrap_err(),
                expected
            );
            assert_eq!(
                BoxSpec::from_yaw(c, h, yaw).to_obb("rows[3]").unwrap_err(),
                expected
            );
        }
    }

    #[test]
    fn a_yaw_and_the_equivalent_matrix_give_the_same_box() {
        let yaw: Real = 0.3;
        let (s, c) = yaw.sin_cos();
        let by_yaw = BoxSpec::from_yaw([1.0, 2.0, 0.5], [0.4, 0.2, 0.5], yaw)
            .to_obb("b")
            .unwrap();
        let by_matrix = BoxSpec {
            center: [1.0, 2.0, 0.5],
            half_size: [0.4, 0.2, 0.5],
            yaw: None,
            rotation: Some(RotationSpec::Rows([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])),
        }
        .to_obb("b")
        .unwrap();
        assert!((by_yaw.rotation.matrix() - by_matrix.rotation.matrix()).norm() < 1e-15);
    }

    #[test]
    fn asset_objects_are_placed_and_checked() {
        let spec = AssetObjectSpec {
            asset: "fixture.chair".into(),
            position: [1.0, 2.0, 0.0],
            yaw: Some(std::f64::consts::FRAC_PI_2),
            rotation: None,
            scale: Some(ScaleSpec::Uniform(2.0)),
        };
        let pose = spec.pose("target").unwrap();
        // Turned 90 degrees counter-clockwise: local +x points along world +y.
        let x = pose * Point3::new(1.0, 0.0, 0.0);
        assert!((x - Point3::new(1.0, 3.0, 0.0)).norm() < 1e-12, "{x}");
        assert_eq!(spec.scale("target").unwrap(), Vector3::repeat(2.0));
        let mut bad = spec.clone();
        bad.scale = Some(ScaleSpec::PerAxis([1.0, 0.0, 1.0]));
        assert!(matches!(bad.scale("t"), Err(RelationError::BadScale { .. })));
        let mut bad = spec.clone();
        bad.rotation = Some(RotationSpec::Flat([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]));
        assert!(matches!(bad.pose("t"), Err(RelationError::Conflict { .. })));
        bad.yaw = None;
        bad.rotation = Some(RotationSpec::Flat([1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]));
        assert!(matches!(bad.pose("t"), Err(RelationError::Geometry { .. })));
        bad.rotation = None;
        bad.position[2] = Real::NAN;
        assert_eq!(
            bad.pose("t").unwrap_err(),
            RelationError::NotFinite {
                field: "t.position".into()
            }
        );
    }

    #[test]
    fn objects_are_boxes_or_assets_by_their_keys() {
        let b: ObjectSpec = serde_json::from_str(r#"{"center":[0,0,1],"half_size":[1,1,1]}"#).unwrap();
        assert_eq!(
            b,
            ObjectSpec::Box(BoxSpec {
                center: [0.0, 0.0, 1.0],
                half_size: [1.0; 3],
                yaw: None,
                rotation: None
            })
        );
        let a: ObjectSpec =
            serde_json::from_str(r#"{"asset":"fixture.bed","position":[1,2,0],"yaw":0.5,"scale":[1,1,2]}"#)
                .unwrap();
        assert!(
            matches!(&a, ObjectSpec::Asset(s) if s.asset == "fixture.bed" && s.scale == Some(ScaleSpec::PerAxis([1.0, 1.0, 2.0])))
        );
        for (text, expect) in [
            (r#"{"asset":"x.y","center":[0,0,0]}"#, "belong to boxes"),
            (r#"{"asset":"x.y"}"#, "missing field `position`"),
            (
                r#"{"center":[0,0,0],"position":[0,0,0]}"#,
                "belong to asset objects",
            ),
            (r#"{"center":[0,0,0]}"#, "missing field `half_size`"),
            (
                r#"{"center":[0,0,0],"half_size":[1,1,1],"colour":1}"#,
                "unknown field `colour`",
            ),
        ] {
            let e = serde_json::from_str::<ObjectSpec>(text).unwrap_err().to_string();
            assert!(e.contains(expect), "{text}: {e}");
        }
    }
}
