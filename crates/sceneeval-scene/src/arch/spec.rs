//! Rooms described as plain data: the room of `sceneeval relate`'s JSON lines and of the
//! Python package's dicts, built by [`RoomBuilder`].

use sceneeval_geom::{Point2, Real};
use thiserror::Error;

use super::{Room, RoomBuilder};
use crate::SceneError;

/// A room as plain data: a floor outline (either winding) with floor height, wall height and
/// thickness, and doors and windows on walls (wall `i` runs from outline point `i` to point
/// `i + 1`, the last wall closing the loop). [`RoomSpec::build`] prepares the [`Room`]
/// through [`RoomBuilder`]; build it once and ask many queries in it.
///
/// With the `serde` feature it reads the documented schema (`docs/formats.md`, the room of
/// "`sceneeval relate` JSON lines"); unknown fields are errors.
///
/// ```
/// use sceneeval_scene::{OpeningSpec, RoomSpec};
/// let mut spec = RoomSpec::new(vec![[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]]);
/// spec.openings.push(OpeningSpec { kind: "door".into(), wall: 0, along: [1.0, 1.9], height: [0.0, 2.1] });
/// let room = spec.build().unwrap();
/// assert_eq!((room.walls().len(), room.openings().len()), (4, 1));
/// // 4 x 5 m: 20 m^2 of floor.
/// assert!((room.floor().area() - 20.0).abs() < 1e-12);
/// spec.height = f64::NAN;
/// assert_eq!(spec.build().unwrap_err().to_string(), "room.height is not finite");
/// ```
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

/// Why a [`RoomSpec`] is not a room. Fields are named as in the room's JSON, under `room`
/// (`room.floor[3]`, `room.openings[1].kind`).
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RoomSpecError {
    /// A number is NaN or infinite.
    #[error("{field} is not finite")]
    NotFinite {
        /// The field, e.g. `room.floor[3]` or `room.height`.
        field: String,
    },
    /// An opening is neither a door nor a window.
    #[error("room.openings[{index}].kind {kind:?} is not \"door\" or \"window\"")]
    UnknownOpeningKind {
        /// Position of the opening in the room's list.
        index: usize,
        /// The kind given.
        kind: String,
    },
    /// The room builder rejected the outline, a wall or an opening.
    #[error("room: {source}")]
    Room {
        /// What the room builder rejected.
        #[source]
        source: SceneError,
    },
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
    /// [`RoomSpecError::NotFinite`], [`RoomSpecError::UnknownOpeningKind`], and
    /// [`RoomSpecError::Room`] for an outline or opening the room builder rejects.
    pub fn build(&self) -> Result<Room, RoomSpecError> {
        self.build_with_id("room")
    }

    /// [`RoomSpec::build`] with the room's id `id` (several rooms of one scene need distinct
    /// ids; its walls are `<id>_wall_<i>`, its floor `floor_<id>`).
    ///
    /// # Errors
    /// As [`RoomSpec::build`].
    pub fn build_with_id(&self, id: &str) -> Result<Room, RoomSpecError> {
        self.builder(id)?
            .build()
            .map_err(|source| RoomSpecError::Room { source })
    }

    /// The [`RoomBuilder`] of this room with the id `id`, every number checked finite and
    /// every opening's kind read (the builder checks the rest when it builds).
    ///
    /// # Errors
    /// [`RoomSpecError::NotFinite`], [`RoomSpecError::UnknownOpeningKind`].
    pub fn builder(&self, id: &str) -> Result<RoomBuilder, RoomSpecError> {
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
                    return Err(RoomSpecError::UnknownOpeningKind {
                        index: i,
                        kind: o.kind.clone(),
                    });
                }
            };
        }
        Ok(room)
    }
}

/// `Ok` when every value is finite, else [`RoomSpecError::NotFinite`] naming `field()`.
fn finite(values: &[Real], field: impl FnOnce() -> String) -> Result<(), RoomSpecError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(RoomSpecError::NotFinite { field: field() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_room() -> RoomSpec {
        RoomSpec::new(vec![[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]])
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
        assert_eq!(room.id().as_str(), "room");
        assert_eq!(spec.build_with_id("r7").unwrap().floor_id(), "floor_r7");
        spec.openings[0].kind = "hatch".into();
        assert_eq!(
            spec.build().unwrap_err(),
            RoomSpecError::UnknownOpeningKind {
                index: 0,
                kind: "hatch".into()
            }
        );
        assert_eq!(
            spec.build().unwrap_err().to_string(),
            r#"room.openings[0].kind "hatch" is not "door" or "window""#
        );
        spec.openings[0].kind = "window".into();
        spec.openings[0].along[1] = Real::NEG_INFINITY;
        assert_eq!(
            spec.build().unwrap_err().to_string(),
            "room.openings[0].along is not finite"
        );
        let mut spec = square_room();
        spec.height = Real::INFINITY;
        assert_eq!(
            spec.build().unwrap_err(),
            RoomSpecError::NotFinite {
                field: "room.height".into()
            }
        );
        spec.height = 2.8;
        spec.floor[2][1] = Real::NAN;
        assert_eq!(
            spec.build().unwrap_err().to_string(),
            "room.floor[2] is not finite"
        );
        // Two points are no floor: the builder's error, under "room: ".
        let spec = RoomSpec::new(vec![[0.0, 0.0], [1.0, 0.0]]);
        let err = spec.build().unwrap_err();
        assert!(matches!(err, RoomSpecError::Room { .. }));
        assert!(err.to_string().starts_with("room: "), "{err}");
        // A door in a wall the room does not have.
        let mut spec = square_room();
        spec.openings.push(OpeningSpec {
            kind: "door".into(),
            wall: 4,
            along: [1.0, 2.0],
            height: [0.0, 2.0],
        });
        assert_eq!(
            spec.build().unwrap_err().to_string(),
            r#"room: room "room" has 4 walls, there is no wall 4"#
        );
    }

    #[cfg(feature = "serde")]
    #[test]
    fn the_json_form_has_defaults_and_refuses_unknown_fields() {
        let spec: RoomSpec = serde_json::from_str(r#"{"floor":[[0,0],[4,0],[4,3],[0,3]]}"#).unwrap();
        assert_eq!(spec, square_room());
        let spec: RoomSpec = serde_json::from_str(
            r#"{"floor":[[0,0],[4,0],[4,3],[0,3]],"floor_z":1,"height":2.5,"wall_thickness":0.2,
                "openings":[{"kind":"window","wall":2,"along":[1,2],"height":[1,2]}]}"#,
        )
        .unwrap();
        assert_eq!((spec.floor_z, spec.height, spec.wall_thickness), (1.0, 2.5, 0.2));
        assert_eq!(spec.openings[0].wall, 2);
        let err = serde_json::from_str::<RoomSpec>(r#"{"floor":[],"colour":1}"#).unwrap_err();
        assert!(err.to_string().contains("unknown field `colour`"), "{err}");
    }
}
