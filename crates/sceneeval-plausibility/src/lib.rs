//! The implicit-expectation (plausibility) metrics of SceneEval: collision (COL), support
//! (SUP), navigability (NAV), accessibility (ACC), out-of-bounds (OOB) and the reference's
//! v1.1 opening clearance, each with per-object evidence in a serde report.
//!
//! Every metric is a function of a [`sceneeval_scene::Scene`] and its parameter struct (whose
//! defaults are the reference's, documented with units and the reference's parameter name);
//! [`evaluate`] runs them all. Support types and functional sides, which the reference asks a
//! VLM for, come from [`SupportTypeSource`] and [`FunctionalSidesSource`] implementations
//! (caller-given maps, built-in category tables, or chains of both), never from the geometry
//! being checked.
//!
//! Results are deterministic: no random sampling (the reference's random surface and face
//! samples are replaced by exact clipping or fixed lattices), and work spread over rayon
//! threads is collected in order, so a report is bit-identical for any thread count.
//!
//! The docs of each metric function state its exact semantics and where (and why) they differ
//! from the reference implementation. The crate feature `images` (default) adds
//! [`write_diagnostics`], which draws the occupancy map, access strips and blocked openings.
//!
//! | metric | function | scene-level number |
//! |---|---|---|
//! | collision | [`collision`] | `col_ob`, `col_sc` |
//! | support | [`support`] | `sup` |
//! | navigability | [`navigability`] | `nav`, `all_rooms_reachable` |
//! | accessibility | [`accessibility`] | `acc` |
//! | out-of-bounds | [`out_of_bounds`] | `oob` |
//! | opening clearance | [`opening_clearance`] | `doors_blocked`, `windows_blocked` |
//!
//! # Open meshes
//! Most real assets (3D-FUTURE, Objaverse, Sweet Home 3D) are not watertight. An object's
//! solid is then where its surface's generalized winding number is at least 1/2
//! ([`sceneeval_geom::Mesh::contains_point`]): a box missing a face (a desk top without an
//! underside, an armchair without a bottom) keeps its inside, as if the hole were lidded; a
//! cavity closed on five sides (a drawer, a shelf compartment) counts as solid; a single sheet
//! encloses nothing. Closed meshes of several touching or overlapping parts are the union of
//! their parts. Collision treats open and closed meshes alike on that basis (see
//! [`collision`]); the 2-D metrics use only the projected surface, so they do not depend on
//! it.
//!
//! # Deliberate deviations, and the parameters that restore the reference
//! - Floor coverings (rugs, carpets, mats, by the words of an object's category or
//!   description) are walked over: `exclude_floor_coverings` (default `true`, with
//!   `floor_covering_words`) in [`CollisionParams`], [`NavigabilityParams`],
//!   [`AccessibilityParams`] and [`OpeningClearanceParams`].
//! - Footprints on the floor plan are convex hulls of the projected meshes, not the bounding
//!   rectangles the reference draws (an oval bath leaves a corridor open beside its corners):
//!   `footprint` ([`Footprint::BoundingBox`] for the reference) in [`NavigabilityParams`] and
//!   [`AccessibilityParams`].
//! - Collision forgives contacts within `contact_tolerance` by proven penetration depth
//!   rather than by the reference's 5 mm push, and counts nested objects.
//!
//! # Cost
//! Every metric grows as `n log n` in the number of objects: collision's broad phase is a
//! sweep over boxes and its narrow phase a bounded search per overlapping pair
//! ([`collision_with_work`] counts its point queries); support, accessibility, clearance and
//! out-of-bounds find what a ray, strip or box can meet through a bounding-volume hierarchy
//! ([`support_with_work`], [`accessibility_with_work`] count its box tests); navigability
//! works on runs of free pixels per row, so its memory grows with rows, not pixels. Per-mesh
//! tables (inside tests, hierarchies) are built once per mesh and shared by every object
//! placing it.
//!
//! # Example
//! ```
//! use sceneeval_geom::{Point2, Point3, Vector3};
//! use sceneeval_plausibility::{evaluate, PlausibilityParams, Sources};
//! use sceneeval_scene::{RoomBuilder, Scene};
//!
//! let scene = Scene::builder()
//!     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
//!         .door(0, [1.0, 1.9], [0.0, 2.1]))
//!     // A bed against the far wall, and a nightstand 1 cm into it.
//!     .add_box("bed", "bed", Point3::new(2.0, 3.95, 0.3), Vector3::new(1.6, 2.0, 0.6), 0.0)
//!     .add_box("nightstand", "nightstand", Point3::new(0.96, 4.7, 0.3),
//!              Vector3::new(0.5, 0.4, 0.6), 0.0)
//!     .build()
//!     .unwrap();
//!
//! let report = evaluate(&scene, &PlausibilityParams::default(), &Sources::default()).unwrap();
//! let s = &report.summary;
//! assert!(s.col_sc);                     // the nightstand overlaps the bed by 1 cm
//! assert_eq!(s.col_ob, Some(1.0));
//! assert_eq!(s.sup, Some(1.0));          // both stand on the floor
//! assert_eq!(s.oob, Some(0.0));          // both inside the room
//! assert!(s.nav > 0.99);                 // one free region
//! assert_eq!(s.doors_blocked, 0);
//! ```

mod accessibility;
mod category;
mod clearance;
mod collision;
#[cfg(feature = "images")]
mod diagnostics;
mod error;
mod index;
mod navigability;
mod objects;
mod oob;
mod plane;
mod raster;
mod sources;
mod support;

use std::fmt;

use sceneeval_geom::Real;
use sceneeval_scene::Scene;
use serde::{Deserialize, Serialize};

pub use accessibility::{
    AccessibilityParams, AccessibilityReport, ObjectAccess, SideAccess, accessibility,
    accessibility_with_work,
};
pub use category::normalize_category;
pub use clearance::{
    BlockingObject, OpeningClearance, OpeningClearanceParams, OpeningClearanceReport, OpeningSide,
    SideClearance, opening_clearance,
};
pub use collision::{
    CollisionParams, CollisionReport, CollisionWork, ContactKind, ObjectCollision, PairContact, collision,
    collision_with_work,
};
#[cfg(feature = "images")]
pub use diagnostics::write_diagnostics;
pub use error::PlausibilityError;
pub use index::IndexWork;
pub use navigability::{
    NavigabilityParams, NavigabilityReport, OccupancyMap, RoomNavigability, navigability, occupancy_map,
};
pub use objects::Footprint;
pub use oob::{ObjectBounds, OutOfBoundsParams, OutOfBoundsReport, out_of_bounds};
pub use raster::{Grid, Resolution};
pub use sceneeval_geom::DepthSearch;
pub use sources::{
    Answer, Chain, FUNCTIONAL_SIDES_TABLE, FunctionalSidePriors, FunctionalSidesSource, GivenFunctionalSides,
    GivenSupportTypes, SUPPORT_TYPE_TABLE, Stated, SupportType, SupportTypePriors, SupportTypeSource,
};
pub use support::{ObjectSupport, SupportParams, SupportReport, Supporter, support, support_with_work};

/// The parameters of every metric, each with the reference's defaults.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct PlausibilityParams {
    /// Collision.
    pub collision: CollisionParams,
    /// Support.
    pub support: SupportParams,
    /// Navigability.
    pub navigability: NavigabilityParams,
    /// Accessibility.
    pub accessibility: AccessibilityParams,
    /// Out-of-bounds.
    pub out_of_bounds: OutOfBoundsParams,
    /// Opening clearance.
    pub opening_clearance: OpeningClearanceParams,
}

/// Where [`evaluate`] takes support types and functional sides from. The default asks the
/// scene first (what its objects state, [`Stated`]), then the built-in category tables
/// ([`SupportTypePriors`], [`FunctionalSidePriors`]).
pub struct Sources {
    /// Support types for [`support`].
    pub support_types: Box<dyn SupportTypeSource>,
    /// Functional sides for [`accessibility`].
    pub functional_sides: Box<dyn FunctionalSidesSource>,
}

impl Sources {
    /// Sources from any two implementations.
    pub fn new(
        support_types: impl SupportTypeSource + 'static,
        functional_sides: impl FunctionalSidesSource + 'static,
    ) -> Self {
        Sources {
            support_types: Box::new(support_types),
            functional_sides: Box::new(functional_sides),
        }
    }
}

impl Default for Sources {
    fn default() -> Self {
        Sources::new(
            Chain::new(Stated, SupportTypePriors::default()),
            Chain::new(Stated, FunctionalSidePriors::default()),
        )
    }
}

impl fmt::Debug for Sources {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Sources").finish_non_exhaustive()
    }
}

/// The scene-level numbers of every metric.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlausibilitySummary {
    /// Share of (tested) objects in collision; `None` without objects.
    pub col_ob: Option<Real>,
    /// Whether any pair of objects collides.
    pub col_sc: bool,
    /// Share of supported objects; `None` without objects.
    pub sup: Option<Real>,
    /// Largest connected free region over all free floor, in [0, 1].
    pub nav: Real,
    /// Whether every room with a door can be entered; `None` when no room has a door.
    pub all_rooms_reachable: Option<bool>,
    /// Mean best-side accessibility; `None` when no object has a functional side.
    pub acc: Option<Real>,
    /// Share of objects out of bounds; `None` without objects.
    pub oob: Option<Real>,
    /// Doors with an object in their clearance box.
    pub doors_blocked: usize,
    /// Windows with an object in their clearance box.
    pub windows_blocked: usize,
}

/// Every metric of one scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlausibilityReport {
    /// The scene's name, if it has one.
    pub scene_id: Option<String>,
    /// Number of objects.
    pub num_objects: usize,
    /// The scene-level numbers.
    pub summary: PlausibilitySummary,
    /// Collision.
    pub collision: CollisionReport,
    /// Support.
    pub support: SupportReport,
    /// Navigability.
    pub navigability: NavigabilityReport,
    /// Accessibility.
    pub accessibility: AccessibilityReport,
    /// Out-of-bounds.
    pub out_of_bounds: OutOfBoundsReport,
    /// Opening clearance.
    pub opening_clearance: OpeningClearanceReport,
}

/// Runs every metric on `scene`, sharing the per-object footprints and the floor
/// decomposition between them.
///
/// # Errors
/// The first [`PlausibilityError`] of any metric (all are parameter errors).
pub fn evaluate(
    scene: &Scene,
    params: &PlausibilityParams,
    sources: &Sources,
) -> Result<PlausibilityReport, PlausibilityError> {
    let infos = objects::object_infos(scene);
    let pieces = accessibility::scene_floor_pieces(scene);
    let collision = collision(scene, &params.collision)?;
    let support = support(scene, &params.support, sources.support_types.as_ref())?;
    navigability_params_check(params)?;
    let navigability = navigability::navigability_with(scene, &params.navigability, &infos)?;
    let accessibility = accessibility::accessibility_with(
        scene,
        &params.accessibility,
        sources.functional_sides.as_ref(),
        &infos,
        &pieces,
    )?;
    let out_of_bounds = oob::out_of_bounds_with(scene, &params.out_of_bounds, &pieces)?;
    let opening_clearance = clearance::opening_clearance_with(scene, &params.opening_clearance, &infos)?;
    let summary = PlausibilitySummary {
        col_ob: collision.col_ob,
        col_sc: collision.col_sc,
        sup: support.sup,
        nav: navigability.nav,
        all_rooms_reachable: navigability.all_rooms_reachable,
        acc: accessibility.acc,
        oob: out_of_bounds.oob,
        doors_blocked: opening_clearance.doors_blocked,
        windows_blocked: opening_clearance.windows_blocked,
    };
    tracing::debug!(scene = ?scene.id(), ?summary, "plausibility");
    Ok(PlausibilityReport {
        scene_id: scene.id().map(str::to_owned),
        num_objects: scene.objects().len(),
        summary,
        collision,
        support,
        navigability,
        accessibility,
        out_of_bounds,
        opening_clearance,
    })
}

fn navigability_params_check(params: &PlausibilityParams) -> Result<(), PlausibilityError> {
    // `navigability_with` and `accessibility_with` skip validation; run it once here.
    navigability::validate(&params.navigability)?;
    accessibility::validate(&params.accessibility)
}
