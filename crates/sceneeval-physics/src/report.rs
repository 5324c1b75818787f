//! The stability report: per object, whether it stayed where it was put, with the evidence.

use sceneeval_geom::na::{Quaternion, Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Real};
use sceneeval_scene::{ObjectId, SupportType};
use serde::{Deserialize, Serialize};

use crate::WeldMode;

/// Why an object was welded (fixed in place) before the simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WeldReason {
    /// Its support type is `wall` (architectural welds).
    Wall,
    /// Its support type is `ceiling` (architectural welds).
    Ceiling,
    /// It interpenetrates another object, the floor or a wall by more than the weld depth
    /// (penetration welds). An object that is both wall-supported and interpenetrating is
    /// reported with its support reason.
    Penetration,
}

/// A pose as written in reports: the object origin's world position and its rotation as a
/// unit quaternion `[x, y, z, w]` (the same pose type the scene places objects with).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// World position of the object's origin, metres.
    pub position: [Real; 3],
    /// Rotation, unit quaternion `[x, y, z, w]`.
    pub rotation: [Real; 4],
}

impl Pose {
    /// The pose of `iso` (`world_from_object`).
    pub fn from_isometry(iso: &Isometry3) -> Self {
        let t = iso.translation.vector;
        let q = iso.rotation.quaternion();
        Pose {
            position: [t.x, t.y, t.z],
            rotation: [q.i, q.j, q.k, q.w],
        }
    }

    /// The pose as an isometry (`world_from_object`; the quaternion is normalised).
    pub fn to_isometry(&self) -> Isometry3 {
        let [x, y, z] = self.position;
        let [i, j, k, w] = self.rotation;
        Isometry3::from_parts(
            Translation3::new(x, y, z),
            UnitQuaternion::new_normalize(Quaternion::new(w, i, j, k)),
        )
    }
}

/// The deepest interpenetration found for an object before the simulation, with what it
/// interpenetrates.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Interpenetration {
    /// The other object's id, or the floor's or the wall's id.
    pub with: String,
    /// Penetration depth in metres (of the convex pieces, as the simulation sees them).
    pub depth_m: Real,
}

/// The verdict on one object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectStability {
    /// The object's id.
    pub id: ObjectId,
    /// Whether it stayed: displacement and rotation both within their (inclusive) limits.
    /// Welded objects are stable.
    pub stable: bool,
    /// How far its centre of mass moved, metres (0 for a welded object).
    pub displacement_m: Real,
    /// The angle of its rotation from start to end, radians in [0, pi] (0 for a welded object).
    pub rotation_rad: Real,
    /// Whether it was fixed in place.
    pub welded: bool,
    /// Why it was fixed in place; `null` when it was free.
    pub weld_reason: Option<WeldReason>,
    /// Where the object ended (its starting pose when welded): evidence, and what
    /// `sceneeval settle` writes.
    pub final_pose: Pose,
    /// The support type the weld decision used (`null`: unknown, treated as `ground`).
    pub support_type: Option<SupportType>,
    /// The deepest interpenetration at the start, when deeper than the weld depth (checked
    /// under every weld mode, welding only under `penetration` and `combined`).
    pub interpenetration: Option<Interpenetration>,
    /// How its rigid body was made, and of how many convex pieces.
    pub body: BodyShape,
}

/// How an object's rigid body was made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct BodyShape {
    /// The decomposition's kind.
    pub kind: DecompositionKind,
    /// Number of convex pieces.
    pub pieces: usize,
}

/// The stability of one scene under one weld mode (`report.stability` in `eval.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StabilityReport {
    /// The weld mode simulated.
    pub weld: WeldMode,
    /// One verdict per object, in scene order.
    pub objects: Vec<ObjectStability>,
    /// Objects free to move (not welded).
    pub num_free: usize,
    /// Free objects that were unstable.
    pub num_unstable: usize,
    /// Unstable objects over free objects; `null` when no object was free to move (see
    /// `frac_unstable_missing`).
    pub frac_unstable: Option<Real>,
    /// Why `frac_unstable` is `null` (no object, or every object welded).
    pub frac_unstable_missing: Option<String>,
    /// Simulated time in seconds: the duration, or less when every free body came to rest
    /// and fell asleep first.
    pub simulated_s: Real,
    /// Time steps taken.
    pub steps: usize,
}

impl StabilityReport {
    /// The share of free objects that stayed (the `STAB` column), `None` when none was free.
    pub fn frac_stable(&self) -> Option<Real> {
        self.frac_unstable.map(|u| 1.0 - u)
    }
}

/// How an object's convex pieces were made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DecompositionKind {
    /// A box object: one exact cuboid.
    Box,
    /// V-HACD pieces (hulls of the mesh's own surface).
    Vhacd,
    /// The convex hull of the whole mesh: a closed mesh that fills its hull up to the
    /// concavity, or a mesh of which no V-HACD piece had volume.
    ConvexHull,
    /// The mesh has no volume at all: its bounding box, at least 1 mm thick.
    FlatBox,
}

// The codes are the decomposition cache's (feature `simulate`).
#[cfg_attr(not(feature = "simulate"), allow(dead_code))]
impl DecompositionKind {
    pub(crate) fn code(self) -> u8 {
        match self {
            DecompositionKind::Box => 0,
            DecompositionKind::Vhacd => 1,
            DecompositionKind::ConvexHull => 2,
            DecompositionKind::FlatBox => 3,
        }
    }

    pub(crate) fn from_code(code: u8) -> Option<Self> {
        [
            DecompositionKind::Box,
            DecompositionKind::Vhacd,
            DecompositionKind::ConvexHull,
            DecompositionKind::FlatBox,
        ]
        .into_iter()
        .find(|k| k.code() == code)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poses_round_trip_and_serialize_as_documented() {
        let iso = Isometry3::new(
            sceneeval_geom::Vector3::new(1.0, 2.0, 0.5),
            sceneeval_geom::Vector3::z() * 0.3,
        );
        let p = Pose::from_isometry(&iso);
        let back = p.to_isometry();
        assert!((back.translation.vector - iso.translation.vector).norm() == 0.0);
        assert!(back.rotation.angle_to(&iso.rotation) < 1e-15);
        let json = serde_json::to_value(WeldReason::Penetration).unwrap();
        assert_eq!(json, "penetration");
        let none: Option<WeldReason> = None;
        assert_eq!(serde_json::to_value(none).unwrap(), serde_json::Value::Null);
    }
}
