//! The parameters of the stability metric, with their documented defaults and ranges.

use sceneeval_geom::Real;
use serde::{Deserialize, Serialize};

use crate::PhysicsError;

/// Gravity, metres per second squared, along world -z.
pub const GRAVITY: Real = 9.81;

/// What is fixed in place (welded to the world) before the simulation starts.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WeldMode {
    /// Objects whose support type is `wall` or `ceiling`: nothing in a rigid-body simulation
    /// holds a shelf on a wall or a lamp under the ceiling, so they would fall by design.
    #[default]
    Architectural,
    /// Objects that interpenetrate another object, the floor or a wall by more than
    /// [`StabilityParams::penetration_depth_m`]: the simulation would push them apart, which is
    /// the collision metric's finding, not an instability.
    Penetration,
    /// Both: [`WeldMode::Architectural`] and [`WeldMode::Penetration`].
    Combined,
    /// Nothing: every object is free to move.
    None,
}

impl WeldMode {
    /// All four modes.
    pub const ALL: [WeldMode; 4] = [
        WeldMode::Architectural,
        WeldMode::Penetration,
        WeldMode::Combined,
        WeldMode::None,
    ];

    /// `"architectural"`, `"penetration"`, `"combined"` or `"none"`.
    pub const fn name(self) -> &'static str {
        match self {
            WeldMode::Architectural => "architectural",
            WeldMode::Penetration => "penetration",
            WeldMode::Combined => "combined",
            WeldMode::None => "none",
        }
    }

    /// Whether objects supported by a wall or the ceiling are welded.
    pub const fn welds_architectural(self) -> bool {
        matches!(self, WeldMode::Architectural | WeldMode::Combined)
    }

    /// Whether interpenetrating objects are welded.
    pub const fn welds_penetrating(self) -> bool {
        matches!(self, WeldMode::Penetration | WeldMode::Combined)
    }
}

impl std::str::FromStr for WeldMode {
    type Err = String;

    /// The mode of that name ([`WeldMode::name`], ignoring ASCII case and surrounding spaces);
    /// the error lists the four names.
    ///
    /// ```
    /// use sceneeval_physics::WeldMode;
    /// assert_eq!("Combined".parse::<WeldMode>(), Ok(WeldMode::Combined));
    /// assert!("glued".parse::<WeldMode>().unwrap_err().contains("architectural, penetration"));
    /// ```
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        WeldMode::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| {
                format!("unknown weld mode {s:?} (expected architectural, penetration, combined or none)")
            })
    }
}

/// How much each object weighs.
///
/// Only mass *ratios* between objects change a verdict (gravity and rigid contacts are
/// otherwise mass-independent), so a uniform density gives the same verdicts for any value.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MassModel {
    /// A uniform density in kg/m³ over the object's convex pieces (default, 1000): a wardrobe
    /// outweighs the vase on it, and the centre of mass and inertia follow the shape. Written
    /// `{"density_kg_m3": 1000}` in a plan.
    #[serde(rename = "density_kg_m3")]
    Density(Real),
    /// Every object weighs this many kilograms, spread uniformly over its convex pieces (the
    /// SceneSmith fork gives every object 1 kg). Written `{"per_object_kg": 1}` in a plan.
    #[serde(rename = "per_object_kg")]
    PerObject(Real),
}

impl Default for MassModel {
    fn default() -> Self {
        MassModel::Density(1000.0)
    }
}

/// Parameters of the convex decomposition of object meshes (parry's V-HACD).
///
/// They are part of the decomposition cache's key: changing one decomposes every mesh again.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DecompositionParams {
    /// Voxels along the longest side of a mesh's bounds (8 to 128; default 64). The voxels
    /// only choose how the mesh is cut: each piece is the convex hull of the mesh's own
    /// surface inside its voxels, so the resolution never grows the mesh.
    pub resolution: u32,
    /// Largest concavity V-HACD leaves in a piece, as a share of the mesh's size (0 to 1;
    /// default 0.01).
    pub concavity: Real,
    /// Most convex pieces per mesh (1 to 256; default 32).
    pub max_pieces: u32,
}

impl Default for DecompositionParams {
    fn default() -> Self {
        DecompositionParams {
            resolution: 64,
            concavity: 0.01,
            max_pieces: 32,
        }
    }
}

/// Parameters of the stability metric (plan parameters `params.stability.*`).
///
/// Every field has a default (below); unknown fields are rejected. [`StabilityParams::validate`]
/// checks every range before anything is simulated.
///
/// ```
/// use sceneeval_physics::{StabilityParams, WeldMode};
/// let params: StabilityParams = serde_json::from_str(r#"{"weld": "combined", "duration_s": 2}"#).unwrap();
/// assert_eq!(params.weld, WeldMode::Combined);
/// assert_eq!(params.time_step_s, 0.001);
/// assert!(params.validate().is_ok());
/// assert!(serde_json::from_str::<StabilityParams>(r#"{"duraton_s": 2}"#).is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StabilityParams {
    /// What is welded before simulating (default [`WeldMode::Architectural`]).
    pub weld: WeldMode,
    /// The most simulated time in seconds (above 0, at most 60; default 5, as the SceneSmith
    /// fork); the simulation stops earlier once every free body has come to rest (see
    /// [`StabilityParams::sleep_speed_m_s`]).
    pub duration_s: Real,
    /// Time step in seconds (1e-4 to 0.02; default 0.001, as the fork: see the crate docs for
    /// what coarser steps change).
    pub time_step_s: Real,
    /// An object whose centre of mass moved more than this many metres is unstable (at most
    /// 10; default 0.01; the limit itself is stable).
    pub displacement_limit_m: Real,
    /// An object that turned by more than this many radians is unstable (0 to pi; default
    /// 0.1; the limit itself is stable).
    pub rotation_limit_rad: Real,
    /// Interpenetration deeper than this many metres welds an object under
    /// [`WeldMode::Penetration`] and [`WeldMode::Combined`] (at most 1; default 0.001).
    pub penetration_depth_m: Real,
    /// Coulomb friction coefficient of every contact (0 to 10; default 0.5).
    pub friction: Real,
    /// How much objects weigh (default [`MassModel::Density`] 1000 kg/m³).
    pub mass: MassModel,
    /// A body whose fastest point moves slower than this (m/s) for
    /// [`StabilityParams::sleep_time_s`] is put to sleep; once every free body sleeps the
    /// simulation stops early (0 to 1; default 0.001; 0 turns sleeping and the early stop
    /// off).
    pub sleep_speed_m_s: Real,
    /// How long a body must stay slower than [`StabilityParams::sleep_speed_m_s`] before it
    /// sleeps, in seconds (above 0, at most 60; default 0.5).
    pub sleep_time_s: Real,
    /// The convex decomposition of object meshes.
    pub decomposition: DecompositionParams,
}

impl Default for StabilityParams {
    fn default() -> Self {
        StabilityParams {
            weld: WeldMode::default(),
            duration_s: 5.0,
            time_step_s: 0.001,
            displacement_limit_m: 0.01,
            rotation_limit_rad: 0.1,
            penetration_depth_m: 0.001,
            friction: 0.5,
            mass: MassModel::default(),
            sleep_speed_m_s: 0.001,
            sleep_time_s: 0.5,
            decomposition: DecompositionParams::default(),
        }
    }
}

/// Most time steps one simulation may take (60 s at 0.1 ms).
pub const MAX_STEPS: usize = 600_000;

impl StabilityParams {
    /// Checks every parameter against its documented range.
    ///
    /// # Errors
    /// [`PhysicsError::InvalidParameter`] naming the first parameter out of range.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        range("duration_s", self.duration_s, 0.0, false, 60.0)?;
        range("time_step_s", self.time_step_s, 1e-4, true, 0.02)?;
        range("displacement_limit_m", self.displacement_limit_m, 0.0, true, 10.0)?;
        range(
            "rotation_limit_rad",
            self.rotation_limit_rad,
            0.0,
            true,
            std::f64::consts::PI,
        )?;
        range("penetration_depth_m", self.penetration_depth_m, 0.0, true, 1.0)?;
        range("friction", self.friction, 0.0, true, 10.0)?;
        match self.mass {
            MassModel::Density(d) => range("mass.density_kg_m3", d, 0.0, false, 1e5)?,
            MassModel::PerObject(m) => range("mass.per_object_kg", m, 0.0, false, 1e6)?,
        }
        range("sleep_speed_m_s", self.sleep_speed_m_s, 0.0, true, 1.0)?;
        range("sleep_time_s", self.sleep_time_s, 0.0, false, 60.0)?;
        let d = &self.decomposition;
        range(
            "decomposition.resolution",
            Real::from(d.resolution),
            8.0,
            true,
            128.0,
        )?;
        range("decomposition.concavity", d.concavity, 0.0, false, 1.0)?;
        range(
            "decomposition.max_pieces",
            Real::from(d.max_pieces),
            1.0,
            true,
            256.0,
        )?;
        Ok(())
    }

    /// The number of time steps of one simulation: `duration_s / time_step_s` rounded up (at
    /// most [`MAX_STEPS`] for valid parameters).
    pub fn steps(&self) -> usize {
        let n = (self.duration_s / self.time_step_s).ceil();
        if n.is_finite() && n > 0.0 {
            // Valid parameters give at most 600,000; the `min` bounds invalid ones too.
            (n as usize).min(MAX_STEPS)
        } else {
            0
        }
    }
}

/// `value` must be finite, above `min` (or equal to it when `min_inclusive`) and at most `max`.
fn range(
    name: &'static str,
    value: Real,
    min: Real,
    min_inclusive: bool,
    max: Real,
) -> Result<(), PhysicsError> {
    let above = if min_inclusive { value >= min } else { value > min };
    if value.is_finite() && above && value <= max {
        return Ok(());
    }
    let reason = match (min_inclusive, value.is_finite()) {
        (_, false) => "must be finite".to_owned(),
        (true, true) => format!("must lie in [{min}, {max}]"),
        (false, true) => format!("must lie in ({min}, {max}]"),
    };
    Err(PhysicsError::InvalidParameter { name, value, reason })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_round_trip() {
        let p = StabilityParams::default();
        p.validate().unwrap();
        // 5 s at 1 ms.
        assert_eq!(p.steps(), 5000);
        let json = serde_json::to_string(&p).unwrap();
        assert!(json.contains(r#""weld":"architectural""#), "{json}");
        assert!(json.contains(r#""mass":{"density_kg_m3":1000.0}"#), "{json}");
        let back: StabilityParams = serde_json::from_str(&json).unwrap();
        assert_eq!(back, p);
    }

    #[test]
    fn every_range_is_checked() {
        type Breaks = fn(&mut StabilityParams);
        let bad: [(&str, Breaks); 12] = [
            ("duration_s", |p| p.duration_s = 0.0),
            ("duration_s", |p| p.duration_s = 61.0),
            ("time_step_s", |p| p.time_step_s = 1e-5),
            ("time_step_s", |p| p.time_step_s = f64::NAN),
            ("displacement_limit_m", |p| p.displacement_limit_m = -0.01),
            ("rotation_limit_rad", |p| p.rotation_limit_rad = 4.0),
            ("penetration_depth_m", |p| p.penetration_depth_m = f64::INFINITY),
            ("friction", |p| p.friction = -1.0),
            ("mass.density_kg_m3", |p| p.mass = MassModel::Density(0.0)),
            ("mass.per_object_kg", |p| p.mass = MassModel::PerObject(-1.0)),
            ("decomposition.resolution", |p| p.decomposition.resolution = 512),
            ("decomposition.max_pieces", |p| p.decomposition.max_pieces = 0),
        ];
        for (name, set) in bad {
            let mut p = StabilityParams::default();
            set(&mut p);
            match p.validate() {
                Err(PhysicsError::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
                other => panic!("{name}: {other:?}"),
            }
        }
    }

    #[test]
    fn mass_models_and_modes_parse_by_name() {
        let p: StabilityParams =
            serde_json::from_str(r#"{"weld": "none", "mass": {"per_object_kg": 1.0}}"#).unwrap();
        assert_eq!(p.weld, WeldMode::None);
        assert_eq!(p.mass, MassModel::PerObject(1.0));
        assert!(serde_json::from_str::<StabilityParams>(r#"{"mass": {"grams": 1}}"#).is_err());
        assert!(serde_json::from_str::<StabilityParams>(r#"{"decomposition": {"res": 1}}"#).is_err());
        for m in WeldMode::ALL {
            let s = serde_json::to_string(&m).unwrap();
            assert_eq!(s, format!("\"{}\"", m.name()));
        }
        assert!(WeldMode::Combined.welds_architectural() && WeldMode::Combined.welds_penetrating());
        assert!(!WeldMode::None.welds_architectural() && !WeldMode::None.welds_penetrating());
    }
}
