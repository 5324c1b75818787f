//! Every parameter of the 23 predicates, with the reference's values as defaults.

use sceneeval_geom::Real;

use crate::RelationError;

/// A distance range with a Gaussian fall-off outside it, in metres: the score is 1 for
/// `min_m <= d <= max_m` and `exp(-delta^2 / (2 sigma_m^2))` otherwise, where `delta` is the distance
/// from `d` to the nearer end of the range.
///
/// Closed or open ends make no difference: at `d == min` the Gaussian is `exp(0) = 1`, so the
/// score is continuous in `d` and equals the reference's strict `min < d < max` test
/// everywhere. A relation holds (score above 0.5) when `delta < sigma * sqrt(2 ln 2)`, about
/// `1.1774 sigma`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct DistanceBand {
    /// Lower end of the range (metres). Range: finite, at most `max_m`.
    pub min_m: Real,
    /// Upper end of the range (metres; `f64::INFINITY` for "and beyond", written as `null`
    /// in JSON). Range: at least `min_m`, not NaN.
    #[cfg_attr(feature = "serde", serde(with = "infinite_as_null"))]
    pub max_m: Real,
    /// Standard deviation of the fall-off outside the range (metres). Range: finite, `> 0`.
    pub sigma_m: Real,
}

impl DistanceBand {
    /// A band from its range and fall-off (metres).
    pub const fn new(min_m: Real, max_m: Real, sigma_m: Real) -> Self {
        DistanceBand {
            min_m,
            max_m,
            sigma_m,
        }
    }

    /// The score of a distance `d` (metres) in `[0, 1]`.
    ///
    /// ```
    /// use sceneeval_relations::DistanceBand;
    /// let near = DistanceBand::new(0.5, 1.5, 0.25);
    /// assert_eq!(near.score(1.0), 1.0);
    /// // 0.25 m short of the range: exp(-0.25^2 / (2 * 0.25^2)) = exp(-0.5).
    /// assert!((near.score(0.25) - (-0.5f64).exp()).abs() < 1e-15);
    /// ```
    #[inline]
    pub fn score(&self, d: Real) -> Real {
        let delta = if d < self.min_m {
            self.min_m - d
        } else if d > self.max_m {
            d - self.max_m
        } else {
            return 1.0;
        };
        (-(delta * delta) / (2.0 * self.sigma_m * self.sigma_m)).exp()
    }

    fn check(&self, name: &'static str) -> Result<(), RelationError> {
        if !(self.sigma_m.is_finite() && self.sigma_m > 0.0) {
            return Err(RelationError::BadParameter {
                name,
                value: self.sigma_m,
                reason: "sigma_m must be positive and finite",
            });
        }
        if !(self.min_m.is_finite() && self.min_m <= self.max_m) || self.max_m.is_nan() {
            return Err(RelationError::BadParameter {
                name,
                value: self.min_m,
                reason: "min_m must be finite and not above max_m",
            });
        }
        Ok(())
    }
}

/// JSON has no infinity: an unbounded band end is written and read as `null`.
#[cfg(feature = "serde")]
mod infinite_as_null {
    use sceneeval_geom::Real;
    use serde::{Deserialize, Deserializer, Serializer};

    pub(super) fn serialize<S: Serializer>(v: &Real, s: S) -> Result<S::Ok, S::Error> {
        if v.is_infinite() && *v > 0.0 {
            s.serialize_none()
        } else {
            s.serialize_f64(*v)
        }
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Real, D::Error> {
        Ok(Option::<Real>::deserialize(d)?.unwrap_or(Real::INFINITY))
    }
}

/// Which plane `on_top` measures "above" from (reference quirk Q1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum OnTopPlane {
    /// The anchor's top face: the part of the target above the anchor's box, within its
    /// footprint. The paper's definition ("`side_of` with the top side, no extension"), the
    /// reference's dataclass default and the mapping prompt ("at its top-most surface and not
    /// inside it").
    #[default]
    TopFace,
    /// The anchor's horizontal centre plane: anything above the anchor's mid-height within its
    /// footprint counts, so a target sunk into the anchor still scores. What the reference's
    /// YAML configuration actually runs (`no_contain: False`), and so what produced the
    /// published numbers.
    CentrePlane,
}

/// How `surround` measures the spread of its targets (reference quirk Q2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum SurroundVariant {
    /// The paper: the ideal distance is the **mean** centroid distance; each target's angle is
    /// its counter-clockwise gap (about the vertical axis, plan view) to the next target.
    #[default]
    Paper,
    /// The reference: the **median** centroid distance; angles between 3-D directions, signed
    /// by the vertical, with the smallest positive angle as the neighbour angle (a target
    /// with no counter-clockwise neighbour within 180 degrees gets the full penalty).
    Reference,
}

/// At which heights `face_to` lets its rays find the anchor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum FaceToHeights {
    /// At any height: the first hits are taken in plan view, as if the anchor's footprint
    /// were a vertical prism, so that a sofa faces a TV hung above its backrest and a bed a
    /// painting on the wall. The reference's angle is a plan-view angle too; only its rays are
    /// bounded by the target's height. Applies to upright objects (rotated about the vertical
    /// only), which is every object a scene generator places upright; a tilted target, or a
    /// tilted box anchor, is scored as with [`FaceToHeights::TargetSpan`].
    #[default]
    Any,
    /// The reference: rays leave the target horizontally at the heights it spans, so an
    /// anchor wholly above or below the target is never hit (score 0).
    TargetSpan,
}

/// Which point of a floor `middle_of_room` measures from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum RoomCentre {
    /// The floor polygon's area centroid (the paper's "room's centroid").
    #[default]
    AreaCentroid,
    /// The centre of the floor's bounding rectangle (the reference: the floor OBB's centre).
    /// Equal to the centroid for rectangular rooms.
    BoundsCentre,
}

/// How `corner_of_room` decides that two walls are perpendicular (reference quirk Q17).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum CornerWalls {
    /// The paper: from the walls' front (inward normal) vectors, independent of the object.
    #[default]
    WallNormals,
    /// The reference: from the mean directions from the object's box to each wall's closest
    /// points (a fixed 4 x 4 x 4 midpoint quadrature over the box here).
    MeanDirections,
}

/// What the distance relations measure from (reference quirk Q3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum DistanceFrom {
    /// The paper: the distance between the closest points of the two objects as solids (their
    /// meshes when given, else their boxes); 0 when they touch, overlap or nest.
    #[default]
    Geometry,
    /// Closer to the reference: object-object relations measure from the box of the object
    /// with the smaller box volume (ties: the anchor) to the other object's geometry;
    /// object-architecture relations measure from the object's box.
    SmallerBox,
}

/// Every parameter of the predicates. [`RelationParams::default`] gives the reference's
/// values (`configs/metrics.yaml`) with this crate's deliberate choices for the reference's
/// quirks; [`RelationParams::reference`] switches those choices to the reference's behaviour.
/// Lengths are metres, angles degrees (as in the reference's configuration).
///
/// Each field's docs end with its range, which [`RelationParams::validate`] checks: scores
/// and shares in `[0, 1]`; lengths, margins and weights finite and `>= 0`; standard
/// deviations finite and `> 0`; bands as [`DistanceBand`] says.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct RelationParams {
    /// A relation holds when its score is strictly above this (0.5). Range: `[0, 1]`.
    pub threshold: Real,
    /// Tolerance of the box-membership tests (metres, `1e-6`): box faces are moved outward by
    /// this much, as the reference's `contains` and face tests do. Range: finite, `>= 0`.
    pub tolerance_m: Real,
    /// Smallest half extent a box is given for volume fractions (metres, `5e-7`): flat boxes
    /// (a rug of height 0) get this thickness, as the reference clamps full sizes to `1e-6`.
    /// Range: finite, `>= 0`.
    pub min_half_extent_m: Real,
    /// `side_of`: how much the anchor's face is enlarged sideways (0.25 = 25 % of each lateral
    /// half extent; the region is unbounded away from the face, as in the reference). Range:
    /// finite, `>= 0`.
    pub side_of_margin: Real,
    /// `side_region`, `long_short_side_of`, `on_top`, `on_wall`, `against_wall`: relative
    /// enlargement of the lateral extents (the reference's `1e-9`). Range: finite, `>= 0`.
    pub region_margin: Real,
    /// `face_to`: deviation angle at which the score reaches 0 (degrees, 30; holds below 15).
    /// Range: `(0, 180]`.
    pub face_to_max_deviation_deg: Real,
    /// `face_to` against a mesh: rays per side of the square grid over the target's
    /// cross-section (8, so 64 rays). Boxes are handled exactly without rays. Range: 1 to
    /// [`RelationParams::MAX_FACE_TO_MESH_RAYS`] (the rays per pair grow as its square).
    pub face_to_mesh_rays: u32,
    /// `face_to`: the anchor counts at any height (plan view) or only at the target's.
    pub face_to_heights: FaceToHeights,
    /// `middle_of`: standard deviation of the plan-view centre distance (metres, 0.25; holds
    /// below 0.294 m). Range: finite, `> 0`.
    pub middle_of_sigma_m: Real,
    /// `surround`: weight of the distance term (0.5). Range: finite, `>= 0`.
    pub surround_distance_weight: Real,
    /// `surround`: weight of the angle term (0.5). Range: finite, `>= 0`.
    pub surround_angle_weight: Real,
    /// `surround`: mean distances and plan-view gaps, or the reference's median and 3-D angles.
    pub surround_variant: SurroundVariant,
    /// `on_top`: the anchor's top face or its centre plane.
    pub on_top_plane: OnTopPlane,
    /// Object-object `next_to`: [0, 0.5] m, sigma 0.25 m.
    pub next_to: DistanceBand,
    /// Object-object `near`: [0.5, 1.5] m, sigma 0.25 m.
    pub near: DistanceBand,
    /// Object-object `across_from`: [1.5, 4] m, sigma 0.25 m.
    pub across_from: DistanceBand,
    /// Object-object `far`: [4, inf) m, sigma 0.25 m.
    pub far: DistanceBand,
    /// Object-architecture `next_to`: [0, 0.5] m, sigma 0.25 m.
    pub arch_next_to: DistanceBand,
    /// Object-architecture `near`: [0.5, 1.5] m, sigma 0.25 m.
    pub arch_near: DistanceBand,
    /// Object-architecture `across_from`: [1.5, 4] m, sigma 0.25 m.
    pub arch_across_from: DistanceBand,
    /// Object-architecture `far`: [4, inf) m, sigma 0.25 m.
    pub arch_far: DistanceBand,
    /// What distances are measured from.
    pub distance_from: DistanceFrom,
    /// `middle_of_room`: base standard deviation (metres, 1.0). Range: finite, `> 0`.
    pub middle_of_room_base_sigma_m: Real,
    /// `middle_of_room`: weight of the object's longer plan side in the standard deviation
    /// (0.5, the paper's `o/2`). Range: finite, `>= 0`.
    pub middle_of_room_size_weight: Real,
    /// `middle_of_room`: weight of the `(1 - o/r)` term (1.0). Range: finite, `>= 0`.
    pub middle_of_room_ratio_weight: Real,
    /// `middle_of_room`: which point of the floor is the room's centre.
    pub room_centre: RoomCentre,
    /// `corner_of_room`: per-wall distance band ([0, 0.8] m, sigma 0.25 m).
    pub corner_wall: DistanceBand,
    /// `corner_of_room`: two walls are perpendicular when the absolute dot product of their
    /// directions is below this (0.15). Range: `[0, 1]`.
    pub corner_perpendicular_threshold: Real,
    /// `corner_of_room`: a room counts only if `inside_room` is at least this (0.5). Range:
    /// `[0, 1]`.
    pub corner_min_inside_room: Real,
    /// `corner_of_room`: wall normals (paper) or mean directions (reference).
    pub corner_walls: CornerWalls,
    /// `on_wall` distance band ([0, 0.01] m, sigma 0.01 m).
    pub on_wall: DistanceBand,
    /// `against_wall` distance band ([0, 0.3] m, sigma 0.1 m).
    pub against_wall: DistanceBand,
    /// `hang_from_ceiling` distance band ([0, 0.01] m, sigma 0.03 m).
    pub hang_from_ceiling: DistanceBand,
}

impl Default for RelationParams {
    fn default() -> Self {
        RelationParams {
            threshold: 0.5,
            tolerance_m: 1e-6,
            min_half_extent_m: 5e-7,
            side_of_margin: 0.25,
            region_margin: 1e-9,
            face_to_max_deviation_deg: 30.0,
            face_to_mesh_rays: 8,
            face_to_heights: FaceToHeights::Any,
            middle_of_sigma_m: 0.25,
            surround_distance_weight: 0.5,
            surround_angle_weight: 0.5,
            surround_variant: SurroundVariant::Paper,
            on_top_plane: OnTopPlane::TopFace,
            next_to: DistanceBand::new(0.0, 0.5, 0.25),
            near: DistanceBand::new(0.5, 1.5, 0.25),
            across_from: DistanceBand::new(1.5, 4.0, 0.25),
            far: DistanceBand::new(4.0, Real::INFINITY, 0.25),
            arch_next_to: DistanceBand::new(0.0, 0.5, 0.25),
            arch_near: DistanceBand::new(0.5, 1.5, 0.25),
            arch_across_from: DistanceBand::new(1.5, 4.0, 0.25),
            arch_far: DistanceBand::new(4.0, Real::INFINITY, 0.25),
            distance_from: DistanceFrom::Geometry,
            middle_of_room_base_sigma_m: 1.0,
            middle_of_room_size_weight: 0.5,
            middle_of_room_ratio_weight: 1.0,
            room_centre: RoomCentre::AreaCentroid,
            corner_wall: DistanceBand::new(0.0, 0.8, 0.25),
            corner_perpendicular_threshold: 0.15,
            corner_min_inside_room: 0.5,
            corner_walls: CornerWalls::WallNormals,
            on_wall: DistanceBand::new(0.0, 0.01, 0.01),
            against_wall: DistanceBand::new(0.0, 0.3, 0.1),
            hang_from_ceiling: DistanceBand::new(0.0, 0.01, 0.03),
        }
    }
}

impl RelationParams {
    /// The largest `face_to_mesh_rays`: 64 per side, 4,096 rays per target and mesh anchor.
    pub const MAX_FACE_TO_MESH_RAYS: u32 = 64;

    /// The defaults with every quirk switch set to the reference's behaviour: `on_top` from the
    /// centre plane, `surround` with the median and 3-D angles, `middle_of_room` from the
    /// floor's bounds centre, `corner_of_room` from mean directions, distances from the
    /// smaller box. Use this to compare with published SceneEval numbers.
    pub fn reference() -> Self {
        RelationParams {
            on_top_plane: OnTopPlane::CentrePlane,
            surround_variant: SurroundVariant::Reference,
            room_centre: RoomCentre::BoundsCentre,
            corner_walls: CornerWalls::MeanDirections,
            distance_from: DistanceFrom::SmallerBox,
            face_to_heights: FaceToHeights::TargetSpan,
            ..RelationParams::default()
        }
    }

    /// Whether `score` means the relation holds (`score > threshold`).
    #[inline]
    pub fn holds(&self, score: Real) -> bool {
        score > self.threshold
    }

    /// Checks every parameter against its documented range (positive standard deviations,
    /// ordered bands, non-negative margins, tolerances and weights, thresholds and shares in
    /// `[0, 1]`, 1 to [`RelationParams::MAX_FACE_TO_MESH_RAYS`] `face_to` rays per side).
    ///
    /// # Errors
    /// [`RelationError::BadParameter`] naming the first bad field.
    pub fn validate(&self) -> Result<(), RelationError> {
        let bands = [
            ("next_to", &self.next_to),
            ("near", &self.near),
            ("across_from", &self.across_from),
            ("far", &self.far),
            ("arch_next_to", &self.arch_next_to),
            ("arch_near", &self.arch_near),
            ("arch_across_from", &self.arch_across_from),
            ("arch_far", &self.arch_far),
            ("corner_wall", &self.corner_wall),
            ("on_wall", &self.on_wall),
            ("against_wall", &self.against_wall),
            ("hang_from_ceiling", &self.hang_from_ceiling),
        ];
        for (name, band) in bands {
            band.check(name)?;
        }
        let non_negative = [
            ("tolerance_m", self.tolerance_m),
            ("min_half_extent_m", self.min_half_extent_m),
            ("side_of_margin", self.side_of_margin),
            ("region_margin", self.region_margin),
            ("surround_distance_weight", self.surround_distance_weight),
            ("surround_angle_weight", self.surround_angle_weight),
            ("middle_of_room_size_weight", self.middle_of_room_size_weight),
            ("middle_of_room_ratio_weight", self.middle_of_room_ratio_weight),
        ];
        for (name, value) in non_negative {
            if !(value.is_finite() && value >= 0.0) {
                return Err(RelationError::BadParameter {
                    name,
                    value,
                    reason: "must be finite and non-negative",
                });
            }
        }
        let positive = [
            ("face_to_max_deviation_deg", self.face_to_max_deviation_deg),
            ("middle_of_sigma_m", self.middle_of_sigma_m),
            ("middle_of_room_base_sigma_m", self.middle_of_room_base_sigma_m),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(RelationError::BadParameter {
                    name,
                    value,
                    reason: "must be finite and positive",
                });
            }
        }
        let unit = [
            ("threshold", self.threshold),
            (
                "corner_perpendicular_threshold",
                self.corner_perpendicular_threshold,
            ),
            ("corner_min_inside_room", self.corner_min_inside_room),
        ];
        for (name, value) in unit {
            if !(0.0..=1.0).contains(&value) {
                return Err(RelationError::BadParameter {
                    name,
                    value,
                    reason: "must lie in [0, 1]",
                });
            }
        }
        if self.face_to_max_deviation_deg > 180.0 {
            return Err(RelationError::BadParameter {
                name: "face_to_max_deviation_deg",
                value: self.face_to_max_deviation_deg,
                reason: "must be at most 180 degrees",
            });
        }
        if !(1..=Self::MAX_FACE_TO_MESH_RAYS).contains(&self.face_to_mesh_rays) {
            return Err(RelationError::BadParameter {
                name: "face_to_mesh_rays",
                value: f64::from(self.face_to_mesh_rays),
                reason: "must lie in [1, 64]",
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn effective_pass_bands_match_the_reference_notes() {
        // score > 0.5 <=> delta < sigma * sqrt(2 ln 2) = 0.25 * 1.17741 = 0.29435 for sigma 0.25.
        let p = RelationParams::default();
        let cut = 0.25 * (2.0 * std::f64::consts::LN_2).sqrt();
        assert!((cut - 0.294_35).abs() < 1e-5);
        assert!(p.holds(p.next_to.score(0.5 + cut - 1e-9)));
        assert!(!p.holds(p.next_to.score(0.5 + cut + 1e-9)));
        assert!(p.holds(p.far.score(4.0 - cut + 1e-9)));
        assert!(!p.holds(p.far.score(4.0 - cut - 1e-9)));
        assert_eq!(p.far.score(1e9), 1.0);
        // Both ends of a band score exactly 1 (closed or open makes no difference).
        assert_eq!(p.near.score(0.5), 1.0);
        assert_eq!(p.near.score(1.5), 1.0);
        // against_wall: sigma 0.1, so a 0.1 m overshoot gives exp(-0.5).
        assert!((p.against_wall.score(0.4) - (-0.5f64).exp()).abs() < 1e-15);
    }

    #[test]
    fn validation_catches_bad_values() {
        assert!(RelationParams::default().validate().is_ok());
        assert!(RelationParams::reference().validate().is_ok());
        let mut p = RelationParams::default();
        p.near.sigma_m = 0.0;
        assert!(matches!(
            p.validate(),
            Err(RelationError::BadParameter { name: "near", .. })
        ));
        let p = RelationParams {
            side_of_margin: -0.1,
            ..Default::default()
        };
        assert!(matches!(
            p.validate(),
            Err(RelationError::BadParameter {
                name: "side_of_margin",
                ..
            })
        ));
        let p = RelationParams {
            face_to_mesh_rays: 0,
            ..Default::default()
        };
        assert!(p.validate().is_err());
    }

    #[test]
    fn every_numeric_parameter_has_a_checked_range() {
        // One value beyond each documented range; `u32::MAX` rays per side would cast
        // 1.8e19 rays per pair.
        type Mutation = (&'static str, fn(&mut RelationParams));
        let cases: &[Mutation] = &[
            ("threshold", |p| p.threshold = 1.5),
            ("threshold", |p| p.threshold = -0.1),
            ("threshold", |p| p.threshold = Real::NAN),
            ("tolerance_m", |p| p.tolerance_m = Real::INFINITY),
            ("min_half_extent_m", |p| p.min_half_extent_m = -1.0),
            ("region_margin", |p| p.region_margin = Real::NAN),
            ("face_to_max_deviation_deg", |p| p.face_to_max_deviation_deg = 0.0),
            ("face_to_max_deviation_deg", |p| {
                p.face_to_max_deviation_deg = 181.0
            }),
            ("face_to_mesh_rays", |p| {
                p.face_to_mesh_rays = RelationParams::MAX_FACE_TO_MESH_RAYS + 1
            }),
            ("face_to_mesh_rays", |p| p.face_to_mesh_rays = u32::MAX),
            ("middle_of_sigma_m", |p| p.middle_of_sigma_m = 0.0),
            ("surround_angle_weight", |p| p.surround_angle_weight = -0.5),
            ("middle_of_room_base_sigma_m", |p| {
                p.middle_of_room_base_sigma_m = Real::INFINITY
            }),
            ("middle_of_room_size_weight", |p| {
                p.middle_of_room_size_weight = Real::NAN
            }),
            ("corner_perpendicular_threshold", |p| {
                p.corner_perpendicular_threshold = 2.0
            }),
            ("corner_min_inside_room", |p| p.corner_min_inside_room = Real::NAN),
            ("far", |p| p.far.min_m = Real::INFINITY),
            ("on_wall", |p| p.on_wall.max_m = Real::NAN),
            ("against_wall", |p| p.against_wall.sigma_m = Real::INFINITY),
        ];
        for (name, mutate) in cases {
            let mut p = RelationParams::default();
            mutate(&mut p);
            match p.validate() {
                Err(RelationError::BadParameter { name: n, .. }) => assert_eq!(n, *name),
                other => panic!("{name}: expected a bad parameter, got {other:?}"),
            }
        }
        let p = RelationParams {
            threshold: 1.0,
            face_to_mesh_rays: RelationParams::MAX_FACE_TO_MESH_RAYS,
            face_to_max_deviation_deg: 180.0,
            corner_min_inside_room: 0.0,
            ..Default::default()
        };
        assert!(p.validate().is_ok());
    }

    #[cfg(feature = "serde")]
    #[test]
    fn partial_json_fills_defaults() {
        let p: RelationParams = serde_json::from_str(
            r#"{"on_top_plane":"centre_plane","near":{"min_m":0.4,"max_m":1.2,"sigma_m":0.2}}"#,
        )
        .unwrap();
        assert_eq!(p.on_top_plane, OnTopPlane::CentrePlane);
        assert_eq!(p.near, DistanceBand::new(0.4, 1.2, 0.2));
        assert_eq!(p.far, RelationParams::default().far);
        assert!(serde_json::from_str::<RelationParams>(r#"{"bogus":1}"#).is_err());
        // The unbounded end of `far` survives a round trip as null.
        let json = serde_json::to_string(&RelationParams::reference()).unwrap();
        assert!(
            json.contains(r#""far":{"min_m":4.0,"max_m":null,"sigma_m":0.25}"#),
            "{json}"
        );
        let back: RelationParams = serde_json::from_str(&json).unwrap();
        assert_eq!(back, RelationParams::reference());
    }
}
