//! Relation queries as plain data: boxes, rooms and relation names the way a client outside
//! Rust writes them (the JSON lines of `sceneeval relate`, the dicts and tuples of the Python
//! package), validated and scored here so that every front end accepts exactly the same
//! inputs and gives exactly the same errors.
//!
//! - [`BoxSpec`]: a solid box from its centre, half extents and a yaw (radians about +z) or a
//!   3x3 row-major rotation matrix. [`BoxSpec::to_obb`] checks every number is finite and the
//!   rotation proper.
//! - [`RoomSpec`]: a floor outline (either winding) with floor height, wall height and
//!   thickness, and doors and windows on walls (`wall` i runs from outline point i to i + 1).
//!   [`RoomSpec::build`] prepares a `sceneeval_scene::Room`; build it once and score many
//!   queries against it.
//! - [`relation_from_spec`]: a relation from its name plus a `side` (sides, `long`/`short`) or
//!   an `arch` element (`wall`, `door`, `window`); a name may carry its argument itself
//!   (`side_of(left)`).
//! - [`score_operands`]: one score from a relation and its [`Operands`], checking that exactly
//!   the operands the relation's kind uses are given.
//! - [`QuerySpec`]: all of the above in one value (the fields of a `relate` line).
//! - [`AssetObjectSpec`]: a mesh asset by model id with a position, rotation and scale (the
//!   caller loads the asset); [`ObjectSpec`] is a box or an asset object, told apart by the
//!   `asset` key. [`score_geoms`] scores [`GeomOperands`], objects that may carry meshes.
//!
//! - [`RoomCache`]: prepared rooms kept by their text (or any key), least recently used
//!   dropped, so that a room handed over again and again is prepared once.
//!
//! With the `serde` feature (on by default) the spec types deserialize from the documented
//! schema (`docs/formats.md`, "`sceneeval relate` JSON lines"): unknown fields are errors.
//!
//! ```
//! use sceneeval_relations::spec::{BoxSpec, QuerySpec};
//! use sceneeval_relations::RelationParams;
//!
//! let lamp = BoxSpec::from_yaw([0.0, 0.0, 1.1], [0.1, 0.1, 0.1], 0.0);
//! let table = BoxSpec::from_yaw([0.0, 0.0, 0.5], [0.5, 0.5, 0.5], 0.0);
//! let query = QuerySpec::pair("on_top", lamp, table);
//! // The lamp rests on the table's top face (z = 1.0): all of it is above, score 1.
//! assert_eq!(query.score(&RelationParams::default()).unwrap(), 1.0);
//! ```

use std::borrow::Borrow;
use std::cell::Cell;
use std::collections::HashMap;
use std::hash::Hash;
use std::sync::Arc;

use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Matrix3, Obb, Point2, Point3, Real, Rotation3, Vector3};
use sceneeval_scene::{Room, RoomBuilder};

use crate::scene_eval::SURROUND_REFERENCE_MAX_TARGETS;
use crate::{
    ObjectGeom, Relation, RelationError, RelationKind, RelationParams, SurroundVariant, arch, batch, surround,
};

/// A solid box: centre, half extents, and either a yaw (radians about +z, counter-clockwise
/// seen from above) or a 3x3 row-major rotation matrix. Neither means axis-aligned.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct BoxSpec {
    /// Centre in world coordinates, metres.
    pub center: [Real; 3],
    /// Half extents along the box's local x, y, z, metres.
    pub half_size: [Real; 3],
    /// Rotation about +z, radians.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Option::is_none"))]
    pub yaw: Option<Real>,
    /// Full rotation (local axes as columns), row-major.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Option::is_none"))]
    pub rotation: Option<RotationSpec>,
}

/// A 3x3 rotation matrix, row-major: as nested rows or as nine numbers.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(untagged))]
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
    /// use sceneeval_relations::spec::BoxSpec;
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
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct AssetObjectSpec {
    /// The model id, `PREFIX.ID`.
    pub asset: String,
    /// World position of the object frame's origin, metres.
    pub position: [Real; 3],
    /// Rotation about +z, radians.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Option::is_none"))]
    pub yaw: Option<Real>,
    /// Full rotation (object axes as columns), row-major.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Option::is_none"))]
    pub rotation: Option<RotationSpec>,
    /// Scale along the object frame's x, y, z (one number for all three); default 1.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Option::is_none"))]
    pub scale: Option<ScaleSpec>,
}

/// A scale: one factor for all three axes, or one per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(untagged))]
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
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(untagged))]
pub enum ObjectSpec {
    /// A solid box.
    Box(BoxSpec),
    /// A mesh asset placed in the world.
    Asset(AssetObjectSpec),
}

#[cfg(feature = "serde")]
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

/// A room from its floor outline: floor height, wall height and thickness, and openings.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct RoomSpec {
    /// Floor outline in the xy plane, metres, either winding; wall i runs from point i to
    /// point i + 1 (the last wall closes the loop).
    pub floor: Vec<[Real; 2]>,
    /// Height of the floor, metres (default 0).
    #[cfg_attr(feature = "serde", serde(default))]
    pub floor_z: Real,
    /// Wall height above the floor, metres (default 2.8).
    #[cfg_attr(feature = "serde", serde(default = "default_height"))]
    pub height: Real,
    /// Wall thickness, metres (default 0.1); walls stand outside the outline.
    #[cfg_attr(feature = "serde", serde(default = "default_thickness"))]
    pub wall_thickness: Real,
    /// Doors and windows.
    #[cfg_attr(feature = "serde", serde(default))]
    pub openings: Vec<OpeningSpec>,
}

#[cfg(feature = "serde")]
fn default_height() -> Real {
    RoomSpec::DEFAULT_HEIGHT
}

#[cfg(feature = "serde")]
fn default_thickness() -> Real {
    RoomSpec::DEFAULT_WALL_THICKNESS
}

/// A door or window in one wall of a [`RoomSpec`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct OpeningSpec {
    /// `door` or `window` (any case).
    pub kind: String,
    /// Index of the wall (wall i runs from outline point i to point i + 1).
    pub wall: usize,
    /// Start and end along the wall from its first point, metres.
    pub along: [Real; 2],
    /// Bottom and top above the floor, metres.
    pub height: [Real; 2],
}

impl RoomSpec {
    /// Default wall height, metres.
    pub const DEFAULT_HEIGHT: Real = 2.8;
    /// Default wall thickness, metres.
    pub const DEFAULT_WALL_THICKNESS: Real = 0.1;

    /// A room with this outline and the default floor height (0), wall height and thickness,
    /// and no openings.
    pub fn new(floor: Vec<[Real; 2]>) -> Self {
        RoomSpec {
            floor,
            floor_z: 0.0,
            height: Self::DEFAULT_HEIGHT,
            wall_thickness: Self::DEFAULT_WALL_THICKNESS,
            openings: Vec::new(),
        }
    }

    /// Prepares the room (walls with their openings cut out, floor triangles); the id of the
    /// room is `room`.
    ///
    /// # Errors
    /// [`RelationError::NotFinite`], [`RelationError::UnknownOpeningKind`], and
    /// [`RelationError::Room`] for an outline or opening the room builder rejects.
    pub fn build(&self) -> Result<Room, RelationError> {
        self.build_with_id("room")
    }

    /// [`RoomSpec::build`] with the room's id `id` (several rooms of one scene need distinct
    /// ids; its walls are `<id>_wall_<i>`, its floor `floor_<id>`).
    ///
    /// # Errors
    /// As [`RoomSpec::build`].
    pub fn build_with_id(&self, id: &str) -> Result<Room, RelationError> {
        for (i, p) in self.floor.iter().enumerate() {
            finite(p, || format!("room.floor[{i}]"))?;
        }
        finite(&[self.floor_z], || "room.floor_z".to_owned())?;
        finite(&[self.height], || "room.height".to_owned())?;
        finite(&[self.wall_thickness], || "room.wall_thickness".to_owned())?;
        let outline = self.floor.iter().map(|p| Point2::new(p[0], p[1])).collect();
        let mut room = RoomBuilder::polygon(id, outline)
            .floor_z(self.floor_z)
            .wall_height(self.height)
            .wall_thickness(self.wall_thickness);
        for (i, o) in self.openings.iter().enumerate() {
            finite(&o.along, || format!("room.openings[{i}].along"))?;
            finite(&o.height, || format!("room.openings[{i}].height"))?;
            room = match o.kind.to_ascii_lowercase().as_str() {
                "door" => room.door(o.wall, o.along, o.height),
                "window" => room.window(o.wall, o.along, o.height),
                _ => {
                    return Err(RelationError::UnknownOpeningKind {
                        index: i,
                        kind: o.kind.clone(),
                    });
                }
            };
        }
        room.build().map_err(|source| RelationError::Room { source })
    }
}

/// The relation named by `name` plus a `side` (`left`, ..., `long`, `short`) or an
/// architecture element (`wall`, `door`, `window`). `name` may carry its argument itself, as
/// in `side_of(left)` or `next_to:wall`; then `side` and `arch` must be absent.
///
/// # Errors
/// [`RelationError::UnknownRelation`] and the argument errors of
/// [`Relation::from_parts`]; [`RelationError::Conflict`] when both `side` and `arch` are
/// given or the name already carries an argument; [`RelationError::BadArgument`] for a side
/// on a distance relation (`next_to`, `near`, `across_from`, `far`), whose argument is an
/// architecture element.
pub fn relation_from_spec(
    name: &str,
    side: Option<&str>,
    arch: Option<&str>,
) -> Result<Relation, RelationError> {
    let name = name.trim();
    if name.contains('(') || name.contains(':') {
        if side.is_some() || arch.is_some() {
            return Err(RelationError::Conflict {
                what: format!("relation {name:?}"),
                first: "an argument in the name",
                second: "\"side\"/\"arch\"",
            });
        }
        return name.parse::<Relation>();
    }
    match (side, arch) {
        (Some(_), Some(_)) => Err(RelationError::Conflict {
            what: format!("relation {name:?}"),
            first: "\"side\"",
            second: "\"arch\"",
        }),
        (Some(side), None) if is_distance_name(name) => Err(RelationError::BadArgument {
            relation: "a distance relation",
            value: side.to_owned(),
            expected: "a side: its argument is an architecture element (wall, door, window) given as \"arch\"",
        }),
        (Some(side), None) => Relation::from_parts(name, Some(side)),
        (None, Some(element)) => Relation::from_arch_mapping(name, Some(element)),
        (None, None) => Relation::from_parts(name, None),
    }
}

/// Whether `name` is one of the distance relations, which relate two objects without an
/// argument and an object to walls, doors or windows with one.
fn is_distance_name(name: &str) -> bool {
    matches!(
        name.to_ascii_lowercase().as_str(),
        "next_to" | "near" | "across_from" | "across" | "far" | "far_from"
    )
}

/// What one relation is scored on: a target and an anchor (object-object), several targets
/// and an anchor (`surround`), or a target and a room (object-architecture).
#[derive(Debug, Clone, Copy, Default)]
pub struct Operands<'a> {
    /// The object being located.
    pub target: Option<&'a Obb>,
    /// The reference object.
    pub anchor: Option<&'a Obb>,
    /// The objects around the anchor (`surround` only).
    pub targets: Option<&'a [Obb]>,
    /// The room (object-architecture relations only).
    pub room: Option<&'a Room>,
}

/// The score of `relation` on `operands`.
///
/// # Errors
/// [`RelationError::MissingOperand`] and [`RelationError::UnexpectedOperand`] when the
/// operands do not match the relation's kind (a distance relation given a room but no anchor
/// is told to name an architecture element), [`RelationError::TooManyTargets`] for the
/// reference `surround` beyond [`SURROUND_REFERENCE_MAX_TARGETS`] targets.
pub fn score_operands(
    relation: Relation,
    operands: &Operands<'_>,
    params: &RelationParams,
) -> Result<Real, RelationError> {
    let views: Option<Vec<ObjectGeom<'_>>> = operands
        .targets
        .map(|targets| targets.iter().map(ObjectGeom::from_box).collect());
    score_geoms(
        relation,
        &GeomOperands {
            target: operands.target.map(ObjectGeom::from_box),
            anchor: operands.anchor.map(ObjectGeom::from_box),
            targets: views.as_deref(),
            room: operands.room,
        },
        params,
    )
}

/// [`Operands`] as predicate views: objects that may carry a mesh (see [`ObjectGeom`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct GeomOperands<'a> {
    /// The object being located.
    pub target: Option<ObjectGeom<'a>>,
    /// The reference object.
    pub anchor: Option<ObjectGeom<'a>>,
    /// The objects around the anchor (`surround` only).
    pub targets: Option<&'a [ObjectGeom<'a>]>,
    /// The room (object-architecture relations only).
    pub room: Option<&'a Room>,
}

/// The score of `relation` on `operands` whose objects may carry meshes (the distance
/// relations and `face_to` use them; see [`ObjectGeom`]). [`score_operands`] is this for
/// boxes.
///
/// # Errors
/// As [`score_operands`].
pub fn score_geoms(
    relation: Relation,
    operands: &GeomOperands<'_>,
    params: &RelationParams,
) -> Result<Real, RelationError> {
    let missing = |operand: &'static str| RelationError::MissingOperand {
        relation: relation.to_string(),
        operand,
    };
    let unexpected = |present: bool, operand: &'static str| {
        if present {
            Err(RelationError::UnexpectedOperand {
                relation: relation.to_string(),
                operand,
            })
        } else {
            Ok(())
        }
    };
    match relation.kind() {
        RelationKind::ObjectObject => {
            unexpected(operands.targets.is_some(), "targets")?;
            if operands.room.is_some()
                && operands.anchor.is_none()
                && matches!(
                    relation,
                    Relation::NextTo | Relation::Near | Relation::AcrossFrom | Relation::Far
                )
            {
                return Err(RelationError::MissingArgument {
                    relation: relation.name(),
                    expected: "\"arch\" (wall, door or window) to relate an object to a room",
                });
            }
            unexpected(operands.room.is_some(), "room")?;
            let target = operands.target.ok_or_else(|| missing("target"))?;
            let anchor = operands.anchor.ok_or_else(|| missing("anchor"))?;
            batch::score_pair(relation, &target, &anchor, params)
        }
        RelationKind::MultiTarget => {
            unexpected(operands.target.is_some(), "target (surround takes targets)")?;
            unexpected(operands.room.is_some(), "room")?;
            let anchor = operands.anchor.ok_or_else(|| missing("anchor"))?;
            let targets = operands.targets.ok_or_else(|| missing("targets"))?;
            if params.surround_variant == SurroundVariant::Reference
                && targets.len() > SURROUND_REFERENCE_MAX_TARGETS
            {
                return Err(RelationError::TooManyTargets {
                    relation: relation.to_string(),
                    got: targets.len(),
                    limit: SURROUND_REFERENCE_MAX_TARGETS,
                });
            }
            Ok(surround(targets, &anchor, params))
        }
        RelationKind::ObjectArchitecture => {
            unexpected(operands.anchor.is_some(), "anchor")?;
            unexpected(operands.targets.is_some(), "targets")?;
            let target = operands.target.ok_or_else(|| missing("target"))?;
            let room = operands.room.ok_or_else(|| missing("room"))?;
            arch::score_rooms(relation, &target, std::slice::from_ref(room), params)
        }
    }
}

/// One relation query as plain data: the relation's name with its `side` or `arch` argument,
/// and the operands its kind uses (see [`Operands`]).
#[derive(Debug, Clone, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct QuerySpec {
    /// The relation's name (see [`relation_from_spec`]).
    pub relation: String,
    /// A side (`left`, `right`, `front`, `back`, `top`, `bottom`) or `long`/`short`.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Option::is_none"))]
    pub side: Option<String>,
    /// An architecture element: `wall`, `door` or `window`.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Option::is_none"))]
    pub arch: Option<String>,
    /// The object being located.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Option::is_none"))]
    pub target: Option<BoxSpec>,
    /// The reference object.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Option::is_none"))]
    pub anchor: Option<BoxSpec>,
    /// The objects around the anchor (`surround`).
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Option::is_none"))]
    pub targets: Option<Vec<BoxSpec>>,
    /// The room (object-architecture relations).
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Option::is_none"))]
    pub room: Option<RoomSpec>,
}

impl QuerySpec {
    /// An object-object query: `target` relative to `anchor`.
    pub fn pair(relation: impl Into<String>, target: BoxSpec, anchor: BoxSpec) -> Self {
        QuerySpec {
            relation: relation.into(),
            target: Some(target),
            anchor: Some(anchor),
            ..QuerySpec::default()
        }
    }

    /// The relation (see [`relation_from_spec`]).
    ///
    /// # Errors
    /// As [`relation_from_spec`].
    pub fn parse_relation(&self) -> Result<Relation, RelationError> {
        relation_from_spec(&self.relation, self.side.as_deref(), self.arch.as_deref())
    }

    /// Builds the boxes and the room and scores the relation.
    ///
    /// # Errors
    /// Any error of [`QuerySpec::parse_relation`], [`BoxSpec::to_obb`], [`RoomSpec::build`]
    /// and [`score_operands`].
    pub fn score(&self, params: &RelationParams) -> Result<Real, RelationError> {
        let relation = self.parse_relation()?;
        let target = self.target.as_ref().map(|b| b.to_obb("target")).transpose()?;
        let anchor = self.anchor.as_ref().map(|b| b.to_obb("anchor")).transpose()?;
        let targets = self
            .targets
            .as_ref()
            .map(|ts| {
                ts.iter()
                    .enumerate()
                    .map(|(i, b)| b.to_obb(&format!("targets[{i}]")))
                    .collect::<Result<Vec<Obb>, _>>()
            })
            .transpose()?;
        let room = self.room.as_ref().map(RoomSpec::build).transpose()?;
        score_operands(
            relation,
            &Operands {
                target: target.as_ref(),
                anchor: anchor.as_ref(),
                targets: targets.as_deref(),
                room: room.as_ref(),
            },
            params,
        )
    }
}

/// Prepared rooms kept by a key, at most a fixed number, the least recently used dropped
/// beyond that: preparing a [`Room`] from a [`RoomSpec`] (walls cut into solids around their
/// openings, the floor triangulated) costs far more than scoring a relation in it, so a front
/// end that is handed the same room again and again (`sceneeval relate`'s rooms written in
/// place, the Python package's `room=` dicts) prepares it once.
///
/// The key is whatever identifies a room's content to the caller: `relate` keys by the room's
/// JSON text as written, the Python package by the JSON text of the dict it was given. Two
/// spellings of one room are two entries (both correct); one key is never two rooms.
/// The room asked for last is compared before the map is hashed, so a stream repeating one
/// room costs one comparison per query.
///
/// ```
/// use std::sync::Arc;
/// use sceneeval_relations::spec::{RoomCache, RoomSpec};
/// let mut cache: RoomCache = RoomCache::new(8);
/// let text = r#"{"floor": [[0, 0], [4, 0], [4, 3], [0, 3]]}"#;
/// let build = || RoomSpec::new(vec![[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]]).build();
/// let first = cache.get_or_build(text, build).unwrap();
/// let again = cache.get_or_build(text, build).unwrap();
/// assert!(Arc::ptr_eq(&first, &again));
/// assert_eq!(cache.built(), 1);
/// ```
#[derive(Debug)]
pub struct RoomCache<K = Arc<str>> {
    capacity: usize,
    clock: u64,
    rooms: HashMap<K, (Arc<Room>, Cell<u64>)>,
    /// The room asked for last, with its key. Its map entry's use stamp stays the newest
    /// while it is last, so it is never the one evicted.
    last: Option<(K, Arc<Room>)>,
    /// Rooms added so far.
    built: usize,
}

impl<K: Hash + Eq + Clone> RoomCache<K> {
    /// An empty cache holding at most `capacity` rooms (at least one).
    pub fn new(capacity: usize) -> Self {
        RoomCache {
            capacity: capacity.max(1),
            clock: 0,
            rooms: HashMap::new(),
            last: None,
            built: 0,
        }
    }

    /// The most rooms the cache holds.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// How many rooms the cache holds.
    pub fn len(&self) -> usize {
        self.rooms.len()
    }

    /// Whether the cache holds no room.
    pub fn is_empty(&self) -> bool {
        self.rooms.is_empty()
    }

    /// How many rooms have been added ([`RoomCache::insert`], or built by
    /// [`RoomCache::get_or_build`]) since the cache was made: the misses.
    pub fn built(&self) -> usize {
        self.built
    }

    /// The room kept under `key`, marked as used now.
    pub fn get<Q>(&mut self, key: &Q) -> Option<Arc<Room>>
    where
        K: Borrow<Q>,
        Q: Hash + Eq + ?Sized,
    {
        if let Some((last_key, room)) = &self.last
            && last_key.borrow() == key
        {
            return Some(Arc::clone(room));
        }
        self.clock += 1;
        let (key, (room, used)) = self.rooms.get_key_value(key)?;
        used.set(self.clock);
        let room = Arc::clone(room);
        self.last = Some((key.clone(), Arc::clone(&room)));
        Some(room)
    }

    /// Keeps `room` under `key` (replacing a room kept under it), dropping the least recently
    /// used room when the cache is full.
    pub fn insert(&mut self, key: K, room: Arc<Room>) {
        self.clock += 1;
        if self.rooms.len() >= self.capacity
            && !self.rooms.contains_key(&key)
            && let Some(oldest) = self
                .rooms
                .iter()
                .min_by_key(|(_, (_, used))| used.get())
                .map(|(k, _)| k.clone())
        {
            self.rooms.remove(&oldest);
        }
        self.built += 1;
        self.rooms
            .insert(key.clone(), (Arc::clone(&room), Cell::new(self.clock)));
        self.last = Some((key, room));
    }

    /// The room kept under `key`, else the room `build` makes, kept under `key` (a failure is
    /// not kept).
    ///
    /// # Errors
    /// The error of `build`.
    pub fn get_or_build<Q, E>(
        &mut self,
        key: &Q,
        build: impl FnOnce() -> Result<Room, E>,
    ) -> Result<Arc<Room>, E>
    where
        K: Borrow<Q> + for<'q> From<&'q Q>,
        Q: Hash + Eq + ?Sized,
    {
        if let Some(room) = self.get(key) {
            return Ok(room);
        }
        let room = Arc::new(build()?);
        self.insert(K::from(key), Arc::clone(&room));
        Ok(room)
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

    fn square_room() -> RoomSpec {
        RoomSpec::new(vec![[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]])
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
    fn relation_names_take_their_argument_one_way_only() {
        assert_eq!(
            relation_from_spec("side_of", Some("left"), None)
                .unwrap()
                .to_string(),
            "side_of(left)"
        );
        assert_eq!(
            relation_from_spec("side_of(left)", None, None).unwrap(),
            relation_from_spec("side_of", Some("left"), None).unwrap()
        );
        assert!(matches!(
            relation_from_spec("side_of(left)", Some("left"), None),
            Err(RelationError::Conflict { .. })
        ));
        assert!(matches!(
            relation_from_spec("next_to", Some("wall"), Some("wall")),
            Err(RelationError::Conflict { .. })
        ));
        assert!(matches!(
            relation_from_spec("near", Some("left"), None),
            Err(RelationError::BadArgument { .. })
        ));
        assert_eq!(
            relation_from_spec("near", None, Some("wall")).unwrap().kind(),
            RelationKind::ObjectArchitecture
        );
        assert!(matches!(
            relation_from_spec("beside", None, None),
            Err(RelationError::UnknownRelation { .. })
        ));
    }

    #[test]
    fn operands_must_match_the_relations_kind() {
        let params = RelationParams::default();
        let a = unit_cube(0.0).to_obb("a").unwrap();
        let b = unit_cube(1.3).to_obb("b").unwrap();
        let room = square_room().build().unwrap();
        let next_to = Relation::from_parts("next_to", None).unwrap();
        // Only a target: the anchor is missing.
        let only_target = Operands {
            target: Some(&a),
            ..Operands::default()
        };
        assert!(matches!(
            score_operands(next_to, &only_target, &params),
            Err(RelationError::MissingOperand {
                operand: "anchor",
                ..
            })
        ));
        // A room without an anchor on a distance relation: the caller meant the architecture.
        let with_room = Operands {
            target: Some(&a),
            room: Some(&room),
            ..Operands::default()
        };
        assert!(matches!(
            score_operands(next_to, &with_room, &params),
            Err(RelationError::MissingArgument { .. })
        ));
        let pair_and_room = Operands {
            target: Some(&a),
            anchor: Some(&b),
            room: Some(&room),
            ..Operands::default()
        };
        assert!(matches!(
            score_operands(next_to, &pair_and_room, &params),
            Err(RelationError::UnexpectedOperand { operand: "room", .. })
        ));
        // Unit cubes 1.3 m apart centre to centre: a 0.3 m gap, inside next_to's [0, 0.5] m.
        let pair = Operands {
            target: Some(&a),
            anchor: Some(&b),
            ..Operands::default()
        };
        assert_eq!(score_operands(next_to, &pair, &params).unwrap(), 1.0);
    }

    #[test]
    fn the_reference_surround_refuses_more_targets_than_its_limit() {
        let anchor = unit_cube(0.0).to_obb("a").unwrap();
        let targets = vec![unit_cube(3.0).to_obb("t").unwrap(); SURROUND_REFERENCE_MAX_TARGETS + 1];
        let operands = Operands {
            anchor: Some(&anchor),
            targets: Some(&targets),
            ..Operands::default()
        };
        let surround = Relation::from_parts("surround", None).unwrap();
        assert!(matches!(
            score_operands(surround, &operands, &RelationParams::reference()),
            Err(RelationError::TooManyTargets { .. })
        ));
        // The paper's variant is linear in the targets and takes any number. All targets at one
        // place: every distance equals the mean (distance term 1, weight 0.5) but no angle is
        // the ideal 360/n degrees (angle term 0, weight 0.5), so the score is 0.5.
        assert_eq!(
            score_operands(surround, &operands, &RelationParams::default()).unwrap(),
            0.5
        );
    }

    #[test]
    fn rooms_are_built_with_their_openings_and_checked() {
        let mut spec = square_room();
        spec.openings.push(OpeningSpec {
            kind: "Door".into(),
            wall: 0,
            along: [1.0, 2.0],
            height: [0.0, 2.0],
        });
        let room = spec.build().unwrap();
        assert_eq!(room.openings().len(), 1);
        spec.openings[0].kind = "hatch".into();
        assert_eq!(
            spec.build().unwrap_err(),
            RelationError::UnknownOpeningKind {
                index: 0,
                kind: "hatch".into()
            }
        );
        let mut spec = square_room();
        spec.height = Real::INFINITY;
        assert_eq!(
            spec.build().unwrap_err(),
            RelationError::NotFinite {
                field: "room.height".into()
            }
        );
        let spec = RoomSpec::new(vec![[0.0, 0.0], [1.0, 0.0]]);
        assert!(matches!(spec.build(), Err(RelationError::Room { .. })));
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

    #[cfg(feature = "serde")]
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

    #[test]
    fn geometry_operands_score_as_box_operands_for_boxes() {
        let params = RelationParams::default();
        let a = unit_cube(0.0).to_obb("a").unwrap();
        let b = unit_cube(1.3).to_obb("b").unwrap();
        let room = square_room().build().unwrap();
        for name in ["next_to", "side_of(left)", "on_top", "far"] {
            let r: Relation = name.parse().unwrap();
            let by_box = score_operands(
                r,
                &Operands {
                    target: Some(&a),
                    anchor: Some(&b),
                    ..Operands::default()
                },
                &params,
            )
            .unwrap();
            let by_geom = score_geoms(
                r,
                &GeomOperands {
                    target: Some(ObjectGeom::from_box(&a)),
                    anchor: Some(ObjectGeom::from_box(&b)),
                    ..GeomOperands::default()
                },
                &params,
            )
            .unwrap();
            assert_eq!(by_box.to_bits(), by_geom.to_bits(), "{name}");
        }
        let views = [ObjectGeom::from_box(&a)];
        let surround_with_room = GeomOperands {
            anchor: Some(ObjectGeom::from_box(&b)),
            targets: Some(&views),
            room: Some(&room),
            ..GeomOperands::default()
        };
        assert!(matches!(
            score_geoms(Relation::Surround, &surround_with_room, &params),
            Err(RelationError::UnexpectedOperand { operand: "room", .. })
        ));
    }

    #[test]
    fn the_room_cache_builds_each_key_once_and_evicts_the_least_recently_used() {
        const ROOM: &str = r#"{"floor":[[0,0],[4,0],[4,3],[0,3]]}"#;
        let other = r#"{"floor":[[0,0],[5,0],[5,3],[0,3]]}"#;
        let third = r#"{"floor":[[0,0],[6,0],[6,3],[0,3]]}"#;
        let build = |x: Real| move || RoomSpec::new(vec![[0.0, 0.0], [x, 0.0], [x, 3.0], [0.0, 3.0]]).build();
        let mut cache: RoomCache = RoomCache::new(2);
        assert!(cache.is_empty());
        let a = cache.get_or_build(ROOM, build(4.0)).unwrap();
        let again = cache.get_or_build(ROOM, build(4.0)).unwrap();
        assert!(Arc::ptr_eq(&a, &again));
        assert_eq!(cache.built(), 1);
        cache.get_or_build(other, build(5.0)).unwrap();
        // ROOM was used before `other`: adding a third evicts ROOM, keeps `other`.
        cache.get_or_build(third, build(6.0)).unwrap();
        assert_eq!((cache.len(), cache.built(), cache.capacity()), (2, 3, 2));
        let kept = cache.get_or_build(other, build(5.0)).unwrap();
        assert_eq!(cache.built(), 3, "other stayed cached");
        // The 5 m room's floor: 15 m^2.
        assert!((kept.floor().area() - 15.0).abs() < 1e-12);
        cache.get_or_build(ROOM, build(4.0)).unwrap();
        assert_eq!(cache.built(), 4, "ROOM was evicted and built again");
        // `third` was used before `other`'s last use: it went, `other` stays.
        assert!(cache.get(other).is_some());
        assert!(cache.get(third).is_none());
        let bad = cache.get_or_build("bad", || RoomSpec::new(vec![[0.0, 0.0], [1.0, 0.0]]).build());
        assert!(matches!(bad, Err(RelationError::Room { .. })));
        assert_eq!(cache.len(), 2, "failures are not kept");
        assert!(cache.get("bad").is_none());
        // A capacity of 0 still keeps the room in use.
        let mut tiny: RoomCache<String> = RoomCache::new(0);
        tiny.insert("a".into(), Arc::clone(&a));
        assert!(tiny.get("a").is_some());
        assert_eq!(tiny.capacity(), 1);
    }

    #[test]
    fn a_query_inside_its_room_scores_one() {
        let q = QuerySpec {
            relation: "inside_room".into(),
            target: Some(BoxSpec::from_yaw([2.0, 1.5, 0.4], [0.3, 0.3, 0.4], 0.0)),
            room: Some(square_room()),
            ..QuerySpec::default()
        };
        assert_eq!(q.score(&RelationParams::default()).unwrap(), 1.0);
    }
}
