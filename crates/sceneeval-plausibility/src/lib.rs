//! The implicit-expectation (plausibility) metrics of SceneEval: collision (COL), support
//! (SUP), navigability (NAV), accessibility (ACC), out-of-bounds (OOB) and the reference's
//! v1.1 opening clearance, each with per-object evidence in a serde report.
//!
//! Every metric is a function of a [`sceneeval_scene::Scene`] and its parameter struct (whose
//! defaults are the reference's, documented with units and the reference's parameter name);
//! [`evaluate`] runs them all and [`evaluate_metrics`] (the one dispatcher; [`evaluate_metrics_each`]
//! goes on past a failed metric) any subset, under a [`Deadline`], into one [`PlausibilityReport`]
//! type. Support types and functional sides,
//! which the reference asks a VLM for, come from [`Source`] implementations (one generic trait
//! per [`Question`]: caller-given maps, what the scene states, built-in category tables, or
//! chains of these), never from the geometry being checked.
//!
//! Results are deterministic: no random sampling (the reference's random surface and face
//! samples are replaced by exact clipping or fixed lattices), and work spread over rayon
//! threads is collected in order, so a report is bit-identical for any thread count.
//!
//! For loops that move objects (layout optimisers), [`LayoutChecks`] prepares the rooms once
//! and then answers a metric's per-object question for one object at a time, with the
//! metric's own code and without allocating.
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
//! - Floor coverings can be left out of collision (`exclude_floor_coverings` with
//!   `floor_covering_words` in [`CollisionParams`], default off as in the original reference)
//!   and walked over by the 2-D metrics (`walkable_height_m` in [`NavigabilityParams`],
//!   [`AccessibilityParams`] and [`OpeningClearanceParams`], default 0 as in the reference).
//! - Footprints on the floor plan are convex hulls of the projected meshes, not the bounding
//!   rectangles the reference draws (an oval bath leaves a corridor open beside its corners):
//!   `footprint` ([`Footprint::BoundingBox`] for the reference) in [`NavigabilityParams`] and
//!   [`AccessibilityParams`].
//! - Collision forgives contacts within `contact_tolerance_m` by proven penetration depth
//!   rather than by the reference's 5 mm push, and counts nested objects.
//!
//! # Cost
//! Every metric grows as `n log n` in the number of objects: collision's broad phase looks
//! every box up in a bounding-volume hierarchy and its narrow phase is a bounded search per overlapping pair
//! ([`collision_with_work`] counts its point queries); support, accessibility, clearance and
//! out-of-bounds find what a ray, strip or box can meet through a bounding-volume hierarchy
//! ([`support_with_work`], [`accessibility_with_work`] count its box tests; accessibility's exact
//! clipping also counts its polygon pieces, which copies of an object at one place do not
//! multiply, and stops at [`MAX_STRIP_PIECES`] per strip); navigability
//! works on runs of free pixels per row, so its memory grows with rows, not pixels. Per-mesh
//! tables (inside tests, hierarchies) are built once per mesh and shared by every object
//! placing it. Objects that pile up are the exception: `k` copies of an object at one place
//! make `k^2` overlapping pairs for collision, `k` supporters under each of their rays for
//! support and `k^2` footprint subtractions for their strips, so those metrics grow as `k^2`
//! there (polynomially; docs/performance.md has the figures).
//!
//! # Example
//! ```
//! use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
//! use sceneeval_plausibility::{evaluate, PlausibilityParams, Sources};
//! use sceneeval_scene::{Category, RoomBuilder, Scene};
//!
//! let scene = Scene::builder()
//!     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
//!         .door(0, [1.0, 1.9], [0.0, 2.1]))
//!     // A bed against the far wall, and a nightstand 1 cm into it.
//!     // (half extents: a 1.6 x 2.0 x 0.6 m bed, a 0.5 x 0.4 x 0.6 m nightstand)
//!     .add_box("bed", Category::new("bed"), Vector3::new(0.8, 1.0, 0.3),
//!              pose_from_yaw(Point3::new(2.0, 3.95, 0.3), 0.0))
//!     .add_box("nightstand", Category::new("nightstand"), Vector3::new(0.25, 0.2, 0.3),
//!              pose_from_yaw(Point3::new(0.96, 4.7, 0.3), 0.0))
//!     .build()
//!     .unwrap();
//!
//! let report = evaluate(&scene, &PlausibilityParams::default(), &Sources::default()).unwrap();
//! let s = &report.summary;
//! assert_eq!(s.col_sc, Some(true));      // the nightstand overlaps the bed by 1 cm
//! assert_eq!(s.col_ob, Some(1.0));
//! assert_eq!(s.sup, Some(1.0));          // both stand on the floor
//! assert_eq!(s.oob, Some(0.0));          // both inside the room
//! assert!(s.nav.unwrap() > 0.99);        // one free region
//! assert_eq!(s.doors_blocked, Some(0));
//!
//! // A subset of the metrics, under a time budget, with each metric's wall time.
//! use sceneeval_plausibility::{evaluate_metrics, Deadline, Metric};
//! let mut timings = Vec::new();
//! let only = evaluate_metrics(&scene, &PlausibilityParams::default(), &Sources::default(),
//!     &[Metric::OutOfBounds, Metric::Collision],
//!     &Deadline::after(std::time::Duration::from_secs(60)), &mut timings).unwrap();
//! assert_eq!(only.metrics, vec![Metric::Collision, Metric::OutOfBounds]);
//! assert_eq!(only.collision, report.collision);
//! assert!(only.support.is_none() && only.summary.sup.is_none());
//! assert_eq!(timings.len(), 2);
//! ```

mod accessibility;
mod category;
mod clearance;
mod collision;
mod contact;
#[cfg(feature = "images")]
mod diagnostics;
mod error;
mod index;
mod layout;
mod navigability;
mod objects;
mod oob;
mod plane;
mod raster;
mod sources;
mod support;

use std::fmt;

use sceneeval_geom::Real;
use sceneeval_scene::{ObjectId, Scene};
use serde::{Deserialize, Serialize};

pub use accessibility::{
    AccessibilityParams, AccessibilityReport, AccessibilityWork, MAX_STRIP_PIECES, ObjectAccess, SideAccess,
    accessibility, accessibility_with_work,
};
pub use clearance::{
    BlockingObject, OpeningClearance, OpeningClearanceParams, OpeningClearanceReport, OpeningSide,
    SideClearance, opening_clearance,
};
pub use collision::{
    CollisionParams, CollisionReport, CollisionWork, ContactKind, ObjectCollision, PairContact, collision,
    collision_with_work,
};
pub use contact::Contact;
#[cfg(feature = "images")]
pub use diagnostics::write_diagnostics;
pub use error::PlausibilityError;
pub use index::IndexWork;
pub use layout::{LayoutChecks, LayoutScratch};
pub use navigability::{
    NavigabilityParams, NavigabilityReport, OccupancyMap, RoomNavigability, navigability, occupancy_map,
};
pub use objects::{DEFAULT_WALKABLE_HEIGHT, Footprint};
pub use oob::{ObjectBounds, OutOfBoundsParams, OutOfBoundsReport, out_of_bounds};
pub use raster::{Grid, Resolution};
pub use sceneeval_geom::DepthSearch;
pub use sceneeval_scene::Deadline;
pub use sources::{
    Answer, Chain, FUNCTIONAL_SIDES_TABLE, FunctionalSidePriors, FunctionalSidesOf, FunctionalSidesSource,
    GivenFunctionalSides, GivenSupportTypes, Question, SUPPORT_TYPE_TABLE, Source, Stated, SupportType,
    SupportTypeOf, SupportTypePriors, SupportTypeSource,
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

/// A plausibility metric.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Metric {
    /// Object collision (COL_ob, COL_sc): [`collision`].
    Collision,
    /// Object support (SUP): [`support`].
    Support,
    /// Scene navigability (NAV): [`navigability`].
    Navigability,
    /// Accessibility of functional sides (ACC): [`accessibility`].
    Accessibility,
    /// Objects out of bounds (OOB): [`out_of_bounds`].
    OutOfBounds,
    /// Door and window clearance (reference v1.1): [`opening_clearance`].
    OpeningClearance,
}

impl Metric {
    /// Every metric, in the order they run and are reported.
    pub const ALL: [Metric; 6] = [
        Metric::Collision,
        Metric::Support,
        Metric::Navigability,
        Metric::Accessibility,
        Metric::OutOfBounds,
        Metric::OpeningClearance,
    ];

    /// The snake-case name used in plan files, reports and on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            Metric::Collision => "collision",
            Metric::Support => "support",
            Metric::Navigability => "navigability",
            Metric::Accessibility => "accessibility",
            Metric::OutOfBounds => "out_of_bounds",
            Metric::OpeningClearance => "opening_clearance",
        }
    }
}

impl fmt::Display for Metric {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Metric {
    type Err = PlausibilityError;

    /// Parses a metric name, ignoring ASCII case and surrounding spaces.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim();
        Metric::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(t))
            .ok_or_else(|| PlausibilityError::UnknownMetric { name: s.to_owned() })
    }
}

impl PlausibilityParams {
    /// Checks every parameter of every metric against its documented range (each field's
    /// docs state it), including what can be known without a scene about raster sizes (a
    /// raster of more than 65,536 pixels per side is refused), so that a bad value is reported
    /// before any scene is read. Rasters sized by a scene (a metres-per-pixel navigability
    /// raster over its floors, an opening's occlusion map) are checked against the same
    /// budget per scene, before anything is allocated for them.
    ///
    /// # Errors
    /// [`PlausibilityError::InvalidParameter`] or [`PlausibilityError::RasterTooLarge`] naming
    /// the metric and the parameter.
    pub fn validate(&self) -> Result<(), PlausibilityError> {
        self.collision.validate()?;
        self.support.validate()?;
        navigability::validate(&self.navigability)?;
        accessibility::validate(&self.accessibility)?;
        self.out_of_bounds.validate()?;
        self.opening_clearance.validate()
    }
}

/// The scene-level numbers of the metrics that ran; a field is `None` when its metric did not
/// run or does not apply (no objects, no doors, no object with a functional side).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PlausibilitySummary {
    /// **COL_ob**: share of (tested) objects in collision, in [0, 1].
    pub col_ob: Option<Real>,
    /// **COL_sc**: whether any pair of objects collides.
    pub col_sc: Option<bool>,
    /// **SUP**: share of supported objects, in [0, 1].
    pub sup: Option<Real>,
    /// **NAV**: largest connected free region over all free floor, in [0, 1].
    pub nav: Option<Real>,
    /// Whether every room with a door can be entered (`None` also when no room has a door).
    pub all_rooms_reachable: Option<bool>,
    /// **ACC**: mean best-side accessibility over objects with functional sides, in [0, 1].
    pub acc: Option<Real>,
    /// **OOB**: share of objects out of bounds, in [0, 1].
    pub oob: Option<Real>,
    /// Number of doors checked.
    pub num_doors: Option<usize>,
    /// Doors with an object in their clearance box.
    pub doors_blocked: Option<usize>,
    /// Number of windows checked.
    pub num_windows: Option<usize>,
    /// Windows with an object in their clearance box.
    pub windows_blocked: Option<usize>,
}

impl PlausibilitySummary {
    /// The scene-level numbers of a report's metrics.
    pub fn of(report: &PlausibilityReport) -> Self {
        let c = report.collision.as_ref();
        let nav = report.navigability.as_ref();
        let oc = report.opening_clearance.as_ref();
        PlausibilitySummary {
            col_ob: c.and_then(|c| c.col_ob),
            col_sc: c.map(|c| c.col_sc),
            sup: report.support.as_ref().and_then(|s| s.sup),
            nav: nav.map(|n| n.nav),
            all_rooms_reachable: nav.and_then(|n| n.all_rooms_reachable),
            acc: report.accessibility.as_ref().and_then(|a| a.acc),
            oob: report.out_of_bounds.as_ref().and_then(|o| o.oob),
            num_doors: oc.map(|o| o.num_doors),
            doors_blocked: oc.map(|o| o.doors_blocked),
            num_windows: oc.map(|o| o.num_windows),
            windows_blocked: oc.map(|o| o.windows_blocked),
        }
    }
}

/// What the metrics found on one scene: the scene-level numbers and each metric's
/// per-object evidence (`None` for a metric that did not run).
///
/// The summary's type is a parameter so that a report of more metrics can carry its own
/// scene-level numbers in the same place and flatten this report into its own
/// (`sceneeval_results::SceneReport`; see [`PlausibilityReport::with_summary`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlausibilityReport<S = PlausibilitySummary> {
    /// The scene's name (its file stem, `scene_12`), if it has one. Written `scene`; read also
    /// from `scene_id`, its key before `sceneeval.scene-report/2` (the benchmark id, `12`, is
    /// the record's `scene_id`).
    #[serde(alias = "scene_id")]
    pub scene: Option<String>,
    /// The object ids, in scene order.
    pub object_ids: Vec<ObjectId>,
    /// The metrics that ran, in the order of [`Metric::ALL`].
    pub metrics: Vec<Metric>,
    /// The scene-level numbers.
    pub summary: S,
    /// Collision.
    pub collision: Option<CollisionReport>,
    /// Support.
    pub support: Option<SupportReport>,
    /// Navigability.
    pub navigability: Option<NavigabilityReport>,
    /// Accessibility.
    pub accessibility: Option<AccessibilityReport>,
    /// Out-of-bounds.
    pub out_of_bounds: Option<OutOfBoundsReport>,
    /// Opening clearance.
    pub opening_clearance: Option<OpeningClearanceReport>,
}

impl<S> PlausibilityReport<S> {
    /// The same report with the summary `summary` makes of this one's.
    pub fn with_summary<T>(self, summary: impl FnOnce(S) -> T) -> PlausibilityReport<T> {
        PlausibilityReport {
            scene: self.scene,
            object_ids: self.object_ids,
            metrics: self.metrics,
            summary: summary(self.summary),
            collision: self.collision,
            support: self.support,
            navigability: self.navigability,
            accessibility: self.accessibility,
            out_of_bounds: self.out_of_bounds,
            opening_clearance: self.opening_clearance,
        }
    }
}

impl<S> PlausibilityReport<S> {
    /// A report of scene-level numbers only: `summary` of the metrics `metrics` on the scene
    /// named `scene`, without object ids or per-metric sections (what a summary or a
    /// comparison reads of a report; the one way tests build one by hand).
    ///
    /// ```
    /// use sceneeval_plausibility::{Metric, PlausibilityReport, PlausibilitySummary};
    /// let summary = PlausibilitySummary { sup: Some(1.0), ..PlausibilitySummary::default() };
    /// let report = PlausibilityReport::of_summary(Some("scene_1".into()), vec![Metric::Support], summary);
    /// assert!(report.support.is_none() && report.object_ids.is_empty());
    /// ```
    pub fn of_summary(scene: Option<String>, metrics: Vec<Metric>, summary: S) -> Self {
        PlausibilityReport {
            scene,
            object_ids: Vec::new(),
            metrics,
            summary,
            collision: None,
            support: None,
            navigability: None,
            accessibility: None,
            out_of_bounds: None,
            opening_clearance: None,
        }
    }
}

impl PlausibilityReport {
    /// The report of `scene` before any metric ran: the metrics of `metrics` in the order of
    /// [`Metric::ALL`], each without a result yet, and a summary of nothing.
    pub fn empty(scene: &Scene, metrics: &[Metric]) -> Self {
        PlausibilityReport {
            object_ids: scene.objects().iter().map(|o| o.id().clone()).collect(),
            ..PlausibilityReport::of_summary(
                scene.name().map(str::to_owned),
                Metric::ALL.into_iter().filter(|m| metrics.contains(m)).collect(),
                PlausibilitySummary::default(),
            )
        }
    }
}

/// How long one metric took on one scene (wall time, for performance logs; never part of a
/// report, which stays identical from run to run).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MetricTiming {
    /// The metric.
    pub metric: Metric,
    /// Wall time in seconds.
    pub seconds: f64,
}

/// Runs every metric on `scene`, sharing the per-object footprints and the floor
/// decomposition between them; [`evaluate_metrics`] runs a subset under a deadline.
///
/// # Errors
/// The first [`PlausibilityError`] of any metric (all are parameter errors).
pub fn evaluate(
    scene: &Scene,
    params: &PlausibilityParams,
    sources: &Sources,
) -> Result<PlausibilityReport, PlausibilityError> {
    evaluate_metrics(
        scene,
        params,
        sources,
        &Metric::ALL,
        &Deadline::none(),
        &mut Vec::new(),
    )
}

/// Runs the metrics in `metrics` (in the order of [`Metric::ALL`], each once) on `scene`,
/// sharing per-scene precomputation between them, and appends each metric's wall time to
/// `timings` as it finishes. The deadline is checked before each metric and inside the long
/// loops (see [`Deadline`]).
///
/// This is the one place that dispatches metrics: the per-metric functions ([`collision`],
/// [`support`], ...) give the same results. [`evaluate_metrics_each`] goes on past a failed
/// metric.
///
/// # Errors
/// [`PlausibilityError::InvalidParameter`] / [`PlausibilityError::RasterTooLarge`] for bad
/// parameters (checked before any metric runs), [`PlausibilityError::DeadlineExceeded`] when
/// the deadline passes, naming the metric that was running; otherwise the first metric's error
/// (the metrics after it do not run).
pub fn evaluate_metrics(
    scene: &Scene,
    params: &PlausibilityParams,
    sources: &Sources,
    metrics: &[Metric],
    deadline: &Deadline,
    timings: &mut Vec<MetricTiming>,
) -> Result<PlausibilityReport, PlausibilityError> {
    let mut failure = None;
    let report = run_metrics(scene, params, sources, metrics, deadline, timings, &mut |_, e| {
        failure = Some(e);
        false
    })?;
    match failure {
        Some(e) => Err(e),
        None => Ok(report),
    }
}

/// [`evaluate_metrics`], going on past a metric that fails: the report holds every metric
/// that ran to the end, and each failed metric comes with its error, in the order of
/// [`Metric::ALL`]. Once the deadline has passed, every remaining metric fails at once with
/// [`PlausibilityError::DeadlineExceeded`] naming it, so the call returns promptly.
///
/// ```
/// use std::time::Duration;
/// use sceneeval_plausibility::{evaluate_metrics_each, Deadline, Metric, PlausibilityParams, Sources};
/// use sceneeval_scene::Scene;
///
/// let scene = Scene::builder().build().unwrap();
/// let (report, failed) = evaluate_metrics_each(&scene, &PlausibilityParams::default(),
///     &Sources::default(), &[Metric::Collision, Metric::Support],
///     &Deadline::after(Duration::ZERO), &mut Vec::new()).unwrap();
/// assert!(report.collision.is_none() && report.support.is_none());
/// assert_eq!(failed.iter().map(|(m, _)| *m).collect::<Vec<_>>(), [Metric::Collision, Metric::Support]);
/// assert!(failed[1].1.to_string().starts_with("support stopped: the scene's time budget of 0 s"));
/// ```
///
/// # Errors
/// [`PlausibilityError::InvalidParameter`] / [`PlausibilityError::RasterTooLarge`] for bad
/// parameters (checked before any metric runs).
pub fn evaluate_metrics_each(
    scene: &Scene,
    params: &PlausibilityParams,
    sources: &Sources,
    metrics: &[Metric],
    deadline: &Deadline,
    timings: &mut Vec<MetricTiming>,
) -> Result<(PlausibilityReport, Vec<(Metric, PlausibilityError)>), PlausibilityError> {
    let mut failed = Vec::new();
    let report = run_metrics(scene, params, sources, metrics, deadline, timings, &mut |m, e| {
        failed.push((m, e));
        true
    })?;
    Ok((report, failed))
}

/// The dispatcher of [`evaluate_metrics`] and [`evaluate_metrics_each`]: each failed metric
/// is handed to `failed`, which says whether to go on.
fn run_metrics(
    scene: &Scene,
    params: &PlausibilityParams,
    sources: &Sources,
    metrics: &[Metric],
    deadline: &Deadline,
    timings: &mut Vec<MetricTiming>,
    failed: &mut dyn FnMut(Metric, PlausibilityError) -> bool,
) -> Result<PlausibilityReport, PlausibilityError> {
    params.validate()?;
    let mut report = PlausibilityReport::empty(scene, metrics);
    let mut shared = Shared::default();
    for metric in report.metrics.clone() {
        let start = std::time::Instant::now();
        match run_metric(scene, params, sources, metric, deadline, &mut shared, &mut report) {
            Ok(()) => timings.push(MetricTiming {
                metric,
                seconds: start.elapsed().as_secs_f64(),
            }),
            Err(e) => {
                tracing::debug!(scene = ?scene.name(), %metric, error = %e, "metric not computed");
                if !failed(metric, e) {
                    break;
                }
            }
        }
    }
    report.summary = PlausibilitySummary::of(&report);
    tracing::debug!(scene = ?scene.name(), summary = ?report.summary, "plausibility");
    Ok(report)
}

/// What several metrics compute on the way, kept for the next.
#[derive(Default)]
struct Shared {
    infos: Option<Vec<objects::ObjectInfo>>,
    pieces: Option<Vec<plane::FloorPiece>>,
}

/// The objects' footprints, computed on the first call for `metric` and kept.
fn shared_infos<'a>(
    slot: &'a mut Option<Vec<objects::ObjectInfo>>,
    scene: &Scene,
    deadline: &Deadline,
    metric: Metric,
) -> Result<&'a [objects::ObjectInfo], PlausibilityError> {
    if slot.is_none() {
        *slot = Some(objects::object_infos_within(scene, deadline, metric.name())?);
    }
    Ok(slot.as_deref().unwrap_or_default())
}

/// Runs one metric into its field of `report`.
fn run_metric(
    scene: &Scene,
    params: &PlausibilityParams,
    sources: &Sources,
    metric: Metric,
    deadline: &Deadline,
    shared: &mut Shared,
    report: &mut PlausibilityReport,
) -> Result<(), PlausibilityError> {
    deadline.check(metric.name())?;
    let Shared { infos, pieces } = shared;
    match metric {
        Metric::Collision => {
            report.collision = Some(collision::collision_with(scene, &params.collision, deadline)?.0);
        }
        Metric::Support => {
            report.support = Some(
                support::support_with(scene, &params.support, sources.support_types.as_ref(), deadline)?.0,
            );
        }
        Metric::Navigability => {
            let infos = shared_infos(infos, scene, deadline, metric)?;
            report.navigability = Some(navigability::navigability_with(
                scene,
                &params.navigability,
                infos,
                deadline,
            )?);
        }
        Metric::Accessibility => {
            let infos = shared_infos(infos, scene, deadline, metric)?;
            let pieces = pieces.get_or_insert_with(|| accessibility::scene_floor_pieces(scene));
            report.accessibility = Some(accessibility::accessibility_with(
                scene,
                &params.accessibility,
                sources.functional_sides.as_ref(),
                infos,
                pieces,
                deadline,
            )?);
        }
        Metric::OutOfBounds => {
            let pieces = pieces.get_or_insert_with(|| accessibility::scene_floor_pieces(scene));
            report.out_of_bounds = Some(oob::out_of_bounds_with(
                scene,
                &params.out_of_bounds,
                pieces,
                deadline,
            )?);
        }
        Metric::OpeningClearance => {
            let infos = shared_infos(infos, scene, deadline, metric)?;
            report.opening_clearance = Some(clearance::opening_clearance_with(
                scene,
                &params.opening_clearance,
                infos,
                deadline,
            )?);
        }
    }
    Ok(())
}
