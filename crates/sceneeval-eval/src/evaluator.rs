//! [`Evaluator`]: an evaluation plan with what it runs on (the support-type and
//! functional-side sources, a VLM and a renderer), and the per-scene pipeline,
//! [`Evaluator::evaluate_scene`]: the one place that says in which order a scene's metrics
//! run.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use futures_util::future::join;

use sceneeval_annotation::AnnotationRow;
use sceneeval_fidelity::placement::{Asked, ask_functional_sides, ask_support_types};
use sceneeval_fidelity::{
    FidelityError, FidelityEvaluator, MatchingRecord, ObjectViews, Resources, ViewKind,
};
use sceneeval_geom::Side;
use sceneeval_io::AssetLibrary;
use sceneeval_plausibility::{
    self as plausibility, Deadline, FunctionalSidesSource, MetricTiming, PlausibilityError, Sources,
    SupportTypeSource,
};
use sceneeval_results::{
    IncompleteMetric, Metric, ObjectPlacement, PlacementSource, Provenance, SceneReport,
};
use sceneeval_scene::{Scene, SupportType};
use sceneeval_vlm::Session;

use crate::{EvalError, EvaluationPlan, SharedVlm};

/// Runs an [`EvaluationPlan`] on scenes.
///
/// The geometry metrics are dispatched in one place, [`plausibility::evaluate_metrics`], the
/// text-fidelity metrics in [`FidelityEvaluator::evaluate`]; [`Evaluator::evaluate_scene`]
/// runs a scene through both in the plan's order, with the support-type and functional-side
/// sources, and, when configured, the VLM and the renderer of the views it is shown.
///
/// ```
/// use sceneeval_eval::{Evaluator, EvaluationPlan, SceneInputs};
/// use sceneeval_scene::{Category, RoomBuilder, Scene};
/// use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
///
/// let scene = Scene::builder()
///     .name("scene_0")
///     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 4.0)))
///     .add_box("a", Category::new("table"), Vector3::new(0.5, 0.5, 0.4), pose_from_yaw(Point3::new(1.0, 1.0, 0.4), 0.0))
///     .add_box("b", Category::new("table"), Vector3::new(0.5, 0.5, 0.4), pose_from_yaw(Point3::new(1.5, 1.0, 0.4), 0.0))
///     .build()
///     .unwrap();
/// let evaluator = Evaluator::new(EvaluationPlan::geometry_only()).unwrap();
/// let report = evaluator.evaluate_scene(&scene, &SceneInputs::default()).unwrap().report;
/// // The two tables overlap by half a metre: both are in collision.
/// assert_eq!(report.summary.geometry.col_ob, Some(1.0));
/// assert_eq!(report.summary.geometry.col_sc, Some(true));
/// ```
#[derive(Debug)]
pub struct Evaluator {
    plan: EvaluationPlan,
    sources: Sources,
    fidelity: FidelityEvaluator,
    vlm: Option<SharedVlm>,
    custom_sources: bool,
    /// A dry run's evaluator: the geometry metrics are not computed (`PreparedRun::dry_run`).
    skip_geometry: bool,
    #[cfg(feature = "render")]
    renderer: Option<(sceneeval_render::Renderer, sceneeval_render::RenderSettings)>,
    #[cfg(feature = "physics")]
    stability: StabilityRun,
}

/// The stability metric with the plan's parameters, and the decomposition cache its scenes
/// share.
#[cfg(feature = "physics")]
#[derive(Debug)]
struct StabilityRun {
    metric: sceneeval_physics::Stability,
    cache: Arc<sceneeval_physics::DecompositionCache>,
}

/// What the evaluation of one scene may use besides the scene and the evaluator (all optional;
/// see [`Evaluator::evaluate_scene`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct SceneInputs<'a> {
    /// The scene's name in the report (default: the scene's own name, [`Scene::name`]); it also
    /// finds the scene's file when objects are matched from a folder of matching files.
    pub name: Option<&'a str>,
    /// The scene's annotation row, which the text-fidelity metrics check. Without one, a plan's
    /// text-fidelity metrics have nothing to check: the report has no fidelity section and a
    /// warning is logged (a scene the annotations have no row for, in a batch).
    pub row: Option<&'a AnnotationRow>,
    /// The asset library the scene was read with: the renderer draws the VLM's object views
    /// from its meshes and materials.
    pub assets: Option<&'a AssetLibrary>,
    /// A folder receiving the rendered object views (`<dir>/*.png`).
    pub views_dir: Option<&'a Path>,
    /// The time budget (default: none).
    pub deadline: Option<&'a Deadline>,
}

/// A scene settled by [`Evaluator::settle_scene`] (feature `physics`).
#[cfg(feature = "physics")]
#[derive(Debug, Clone)]
pub struct Settled {
    /// The scene with every object at its settled pose (welded objects where they were).
    pub scene: Scene,
    /// The stability metric's report of the simulation.
    pub report: sceneeval_physics::StabilityReport,
    /// Where each object's support type came from and why, when the VLM was asked (`None`
    /// otherwise: the scene and the category tables gave them).
    pub placement: Option<Vec<ObjectPlacement>>,
}

/// What [`Evaluator::evaluate_scene`] found on one scene.
#[derive(Debug, Clone)]
pub struct SceneEvaluation {
    /// The report (`eval.json`'s `report`).
    pub report: SceneReport,
    /// The object matching the text-fidelity metrics used (`matching.json`), when they ran.
    pub matching: Option<MatchingRecord>,
    /// Each geometry metric's wall time, in the order they ran.
    pub timings: Vec<MetricTiming>,
    /// The wall time of the VLM phase, seconds, when text-fidelity metrics ran: every VLM
    /// question of the scene (fidelity and placement, asked together), the renders they need,
    /// and the fidelity metrics' scoring.
    pub fidelity_seconds: Option<f64>,
    /// The stability metric's wall time (decomposition and simulation), seconds, when it ran.
    pub stability_seconds: Option<f64>,
}

impl Evaluator {
    /// An evaluator with the default sources: what each object states, then the built-in
    /// category tables.
    ///
    /// # Errors
    /// [`EvalError::Plan`] when the plan is invalid (see [`EvaluationPlan::validate`]).
    pub fn new(plan: EvaluationPlan) -> Result<Self, EvalError> {
        plan.validate()?;
        let fidelity = FidelityEvaluator::new(plan.fidelity.clone(), plan.relations)?;
        #[cfg(feature = "physics")]
        let stability = StabilityRun {
            metric: sceneeval_physics::Stability::new(plan.stability.clone())?,
            cache: Default::default(),
        };
        Ok(Evaluator {
            plan,
            sources: Sources::default(),
            fidelity,
            vlm: None,
            custom_sources: false,
            skip_geometry: false,
            #[cfg(feature = "render")]
            renderer: None,
            #[cfg(feature = "physics")]
            stability,
        })
    }

    /// Shares `cache` for the stability metric's convex decompositions (feature `physics`;
    /// default: a cache in memory for this evaluator's life). A cache in a folder
    /// ([`sceneeval_physics::DecompositionCache::on_disk`]) lets re-runs and other weld variants
    /// reuse them; `sceneeval evaluate` keeps one in `<out>/physics-cache`
    /// ([`crate::DEFAULT_PHYSICS_CACHE_DIR`]).
    #[cfg(feature = "physics")]
    pub fn with_decomposition_cache(mut self, cache: Arc<sceneeval_physics::DecompositionCache>) -> Self {
        self.stability.cache = cache;
        self
    }

    /// `scene` with every object at its pose after the stability metric's simulation under the
    /// plan's `stability` parameters (whether or not the plan lists the metric; welded objects
    /// stay where they were), with the report that goes with it: what `sceneeval settle` writes
    /// and the Python `Scene.settle` and `Scene.stability` return (feature `physics`).
    ///
    /// Each object's support type comes as [`Evaluator::evaluate_scene`] gets it: what the scene
    /// states; then, with a VLM ([`Evaluator::with_vlm`]) and a renderer for the views it is
    /// shown, the VLM's answer for each object that states none; then the category tables
    /// ([`Evaluator::sources`], unless replaced). [`Settled::placement`] says where each came
    /// from and why when the VLM was asked; an object whose question failed takes the tables'
    /// type, and its provenance says why. The views go to `inputs.views_dir`, read with
    /// `inputs.assets`; `inputs.deadline` bounds the simulation.
    ///
    /// ```
    /// use sceneeval_eval::{Evaluator, EvaluationPlan, SceneInputs};
    /// use sceneeval_scene::{Category, Deadline, RoomBuilder, Scene};
    /// use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
    ///
    /// // A 0.4 m crate 5 cm above the floor.
    /// let scene = Scene::builder()
    ///     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(3.0, 3.0)))
    ///     .add_box("crate", Category::new("box"), Vector3::repeat(0.2),
    ///              pose_from_yaw(Point3::new(1.5, 1.5, 0.25), 0.0))
    ///     .build()
    ///     .unwrap();
    /// let evaluator = Evaluator::new(EvaluationPlan::geometry_only()).unwrap();
    /// let settled = evaluator.settle_scene(&scene, &SceneInputs::default()).unwrap();
    /// assert!(!settled.report.objects[0].stable);
    /// // It landed: its centre is 0.2 m up, within a millimetre.
    /// let z = settled.scene.objects()[0].pose().translation.z;
    /// assert!((z - 0.2).abs() < 1e-3, "{z}");
    /// ```
    ///
    /// # Errors
    /// `EvalError::Physics` as [`sceneeval_physics::Stability::settle`].
    #[cfg(feature = "physics")]
    pub fn settle_scene(&self, scene: &Scene, inputs: &SceneInputs<'_>) -> Result<Settled, EvalError> {
        let none = Deadline::none();
        let deadline = inputs.deadline.unwrap_or(&none);
        let asked = match &self.vlm {
            Some(vlm) if self.wants_support_types() && !self.custom_sources => {
                let session = Session::new(vlm.clone());
                let views = self.views_or_failure(scene, inputs);
                // Settling uses support types only: no functional sides are asked.
                Some(pollster::block_on(self.ask_placement(
                    scene,
                    &session,
                    views.as_deref(),
                    false,
                )))
            }
            _ => None,
        };
        let Some(asked) = asked else {
            let (settled, report) = self.settle_with(scene, &self.sources, deadline)?;
            return Ok(Settled {
                scene: settled,
                report,
                placement: None,
            });
        };
        // A failed question is in the objects' provenance; settling has no metric to mark.
        let mut incomplete = Vec::new();
        let (sources, placement) = self.placement_sources(scene, &asked, &mut incomplete);
        let (settled, report) = self.settle_with(scene, &sources, deadline)?;
        Ok(Settled {
            scene: settled,
            report,
            placement: Some(placement),
        })
    }

    /// The settled scene and report of `scene` with the support types of `sources`.
    #[cfg(feature = "physics")]
    fn settle_with(
        &self,
        scene: &Scene,
        sources: &Sources,
        deadline: &Deadline,
    ) -> Result<(Scene, sceneeval_physics::StabilityReport), EvalError> {
        let run = &self.stability;
        let (poses, report) =
            run.metric
                .settle(scene, &run.support_types(scene, sources), &run.cache, deadline)?;
        let mut settled = scene.clone();
        for (i, pose) in poses.into_iter().enumerate() {
            // The simulation's poses are finite (a diverged one is an error above).
            settled
                .set_pose(i, pose)
                .map_err(|e| sceneeval_physics::PhysicsError::Geometry {
                    object: scene.objects()[i].id().to_string(),
                    reason: e.to_string(),
                })?;
        }
        Ok((settled, report))
    }

    /// Uses `vlm` for the text-fidelity metrics (matching, attributes, relation mapping) and
    /// for the support types and functional sides objects do not state, each scene with its
    /// own [`Session`] so that its usage is recorded with it.
    pub fn with_vlm(mut self, vlm: SharedVlm) -> Self {
        self.vlm = Some(vlm);
        self
    }

    /// The VLM, if configured.
    pub fn vlm(&self) -> Option<&SharedVlm> {
        self.vlm.as_ref()
    }

    /// The same evaluator, computing no geometry metric and no stability: what a dry run asks
    /// the VLM (`sceneeval_run::PreparedRun::dry_run` counts its questions).
    pub fn without_geometry(mut self) -> Self {
        self.skip_geometry = true;
        self
    }

    /// Renders the object views the VLM is shown with `renderer` at `settings` (feature
    /// `render`); without a renderer the VLM-based matching and ATR cannot run.
    #[cfg(feature = "render")]
    pub fn with_renderer(
        mut self,
        renderer: sceneeval_render::Renderer,
        settings: sceneeval_render::RenderSettings,
    ) -> Self {
        self.renderer = Some((renderer, settings));
        self
    }

    /// Replaces the support-type and functional-side sources (e.g. types given by the
    /// generator). Given sources replace the VLM's support types and functional sides too.
    pub fn with_sources(mut self, sources: Sources) -> Self {
        self.sources = sources;
        self.custom_sources = true;
        self
    }

    /// The plan.
    #[inline]
    pub fn plan(&self) -> &EvaluationPlan {
        &self.plan
    }

    /// The support-type and functional-side sources used without a VLM (and for the objects
    /// the VLM gave no answer for, after it).
    #[inline]
    pub fn sources(&self) -> &Sources {
        &self.sources
    }

    /// The digest a result depends on: the plan's [`EvaluationPlan::result_digest`], and the
    /// VLM's model name and settings ([`sceneeval_vlm::Vlm::settings`]) when one is configured
    /// (answers of another model, or of the same model with another image detail or
    /// temperature, are other results).
    pub fn result_digest(&self) -> String {
        let plan = self.plan.result_digest();
        match &self.vlm {
            None => plan,
            Some(v) => {
                use sceneeval_vlm::Vlm;
                // Without settings the digest is the one earlier versions wrote.
                let text = match v.settings() {
                    "" => format!("{plan}\nvlm {}", v.model()),
                    settings => format!("{plan}\nvlm {}\nvlm settings {settings}", v.model()),
                };
                blake3::hash(text.as_bytes()).to_hex().to_string()
            }
        }
    }

    /// What a run folder records of this evaluator (`plan.json`,
    /// [`sceneeval_results::RunPlan`]): [`Evaluator::result_digest`], the resolved plan as a
    /// plan file writes it, and the VLM's model name and settings when one is configured.
    pub fn run_plan(&self) -> sceneeval_results::RunPlan {
        use sceneeval_vlm::Vlm;
        // Serialising a plan (plain data) cannot fail.
        let plan = serde_json::to_value(&self.plan).unwrap_or_default();
        let vlm = self.vlm.as_ref().map(|v| sceneeval_results::JudgeModel {
            model: v.model().to_owned(),
            settings: v.settings().to_owned(),
        });
        sceneeval_results::RunPlan::new(self.result_digest(), plan, vlm)
    }

    /// Evaluates one scene under the whole plan: the per-scene pipeline, the one call for
    /// every plan (geometry, stability, text fidelity, with or without a VLM; settling a scene
    /// is `Evaluator::settle_scene`, feature `physics`).
    ///
    /// 1. With a VLM, and a scene that needs it (text-fidelity metrics with a row, or support
    ///    or accessibility with the default sources), a [`Session`] for the scene and its
    ///    object views (rendered into `inputs.views_dir` when given).
    /// 2. Every VLM question of the scene that does not wait on another is asked together,
    ///    under one [`pollster::block_on`]: the support types and functional sides the objects
    ///    do not state (with the default sources), the matching of every object and the
    ///    relation mappings; then, once the matching is known, the attribute questions
    ///    ([`FidelityEvaluator::evaluate_async`]). The VLM's limit (`--vlm-concurrency`) caps
    ///    what is really in flight; results do not depend on the order answers arrive in.
    /// 3. The support types and functional sides go between what the scene states and the
    ///    category tables (an object the VLM does not answer for takes the table's); where
    ///    each object's came from, and why, is recorded ([`SceneReport::placement`]).
    /// 4. The geometry metrics ([`plausibility::evaluate_metrics`], under the deadline).
    /// 5. When the plan runs stability (feature `physics`), the rigid-body simulation under
    ///    the deadline, with the support types the support metric uses (the same sources, the
    ///    VLM's answers included).
    /// 6. CNT, ATR, OOR, OAR from step 2 when the plan runs text-fidelity metrics and the scene
    ///    has an annotation row. A fidelity plan without a row reports no fidelity section (a
    ///    warning is logged): a batch run gives every scene the row the annotations have for
    ///    it, if any.
    /// 7. The report, built once ([`SceneReport::new`]).
    ///
    /// A metric that cannot be computed, a VLM request that gets no answer at all (the
    /// endpoint down, a refused key, a time-out), or any other error of one metric (a
    /// malformed annotation entry, a scene the stability metric cannot simulate), costs only
    /// the metrics that needed it: they are listed in [`SceneReport::incomplete`] with the
    /// reason (the record's status is then `partial`), every other result is kept. Support
    /// and accessibility (and stability) are computed with the category tables for the
    /// objects whose question failed, and listed too.
    ///
    /// The scene's time budget (`inputs.deadline`) is different: a scene that runs past it is
    /// not evaluated (its results would depend on the machine's speed). The deadline is
    /// checked after the VLM questions, before each metric and inside their long loops.
    ///
    /// # Errors
    /// [`EvalError::Plausibility`] with [`PlausibilityError::DeadlineExceeded`] naming the
    /// stage that was stopped (`vlm` for the VLM questions, a geometry metric's name), or
    /// [`EvalError::Physics`] from the stability metric, when the deadline passes (or is
    /// cancelled) before the scene is done.
    pub fn evaluate_scene(
        &self,
        scene: &Scene,
        inputs: &SceneInputs<'_>,
    ) -> Result<SceneEvaluation, EvalError> {
        let name = inputs.name.or(scene.name());
        let none = Deadline::none();
        let deadline = inputs.deadline.unwrap_or(&none);
        let row = inputs.row.filter(|_| self.plan.has_fidelity());
        if self.plan.has_fidelity() && inputs.row.is_none() {
            tracing::warn!(
                scene = name.unwrap_or_default(),
                "no annotation row: fidelity metrics skipped"
            );
        }
        let session = self.vlm.clone().map(Session::new);
        let views: Option<Box<dyn ObjectViews>> = match &session {
            Some(_) if row.is_some() || self.wants_vlm_sources() => self.views_or_failure(scene, inputs),
            _ => None,
        };

        // Every VLM question together: placement, then the fidelity metrics' questions.
        let start = Instant::now();
        let fidelity_metrics = self.plan.fidelity_metrics();
        let res = Resources {
            session: session.as_ref(),
            views: views.as_deref(),
            scene_name: name.unwrap_or_default(),
        };
        let placement = async {
            match &session {
                Some(s) if self.wants_vlm_sources() => {
                    let sides = self.plan.runs(Metric::Accessibility);
                    Some(self.ask_placement(scene, s, views.as_deref(), sides).await)
                }
                _ => None,
            }
        };
        let fidelity = async {
            match row {
                Some(row) => Some(
                    self.fidelity
                        .evaluate_async(scene, row, &fidelity_metrics, &res)
                        .await,
                ),
                None => None,
            }
        };
        let (asked, fidelity) = pollster::block_on(join(placement, fidelity));
        let vlm_seconds = start.elapsed().as_secs_f64();
        if session.is_some() {
            // A budget spent waiting for the model stops the scene here, named for it.
            deadline.check("vlm").map_err(PlausibilityError::from)?;
        }

        let mut incomplete = Vec::new();
        let mut placement = None;
        let sources = match &asked {
            Some(asked) => {
                let (sources, objects) = self.placement_sources(scene, asked, &mut incomplete);
                placement = Some(objects);
                Some(sources)
            }
            None => None,
        };
        let mut timings = Vec::new();
        let sources = sources.as_ref().unwrap_or(&self.sources);
        let geometry = self.geometry(scene, sources, deadline, &mut timings, &mut incomplete)?;
        #[cfg(feature = "physics")]
        let (stability, stability_seconds) = match self.plan.runs(Metric::Stability) && !self.skip_geometry {
            true => {
                let start = Instant::now();
                let report = match self.stability.evaluate(scene, sources, deadline) {
                    Ok(report) => Some(report),
                    // Stopped by the time budget: the scene fails (see above).
                    Err(e) if deadline.expired() => return Err(e),
                    Err(e) => {
                        tracing::warn!(error = %e, "stability not computed");
                        incomplete.push(IncompleteMetric::new(Metric::Stability, false, &e));
                        None
                    }
                };
                (report, Some(start.elapsed().as_secs_f64()))
            }
            false => (None, None),
        };
        #[cfg(not(feature = "physics"))]
        let stability_seconds = None;
        let (fidelity, matching) = match fidelity {
            Some(mut outcome) => {
                // The scene's whole session: placement questions included, every answer in.
                outcome.report.vlm_usage = session.as_ref().map(Session::usage);
                for f in &outcome.failures {
                    incomplete.push(IncompleteMetric::new(
                        Metric::from(f.metric),
                        f.is_vlm(),
                        f.error.as_ref(),
                    ));
                }
                (Some(outcome.report), outcome.matching)
            }
            None => (None, None),
        };
        let fidelity_seconds = row.map(|_| vlm_seconds);
        let mut report = SceneReport::new(name.map(str::to_owned), geometry, fidelity);
        #[cfg(feature = "physics")]
        if let Some(s) = stability {
            report = report.with_stability(s);
        }
        if let Some(p) = placement {
            report = report.with_placement(p);
        }
        if !incomplete.is_empty() {
            tracing::warn!(
                scene = name.unwrap_or_default(),
                metrics = ?incomplete.iter().map(|m| m.metric.name()).collect::<Vec<_>>(),
                "scene incomplete"
            );
        }
        Ok(SceneEvaluation {
            report: report.with_incomplete(incomplete),
            matching,
            timings,
            fidelity_seconds,
            stability_seconds,
        })
    }

    /// The geometry metrics of the plan, each failure costing only its own metric (they run
    /// together, sharing intermediate results; a failed one is added to `incomplete` and the
    /// others go on), except the deadline's, which stops the scene.
    fn geometry(
        &self,
        scene: &Scene,
        sources: &Sources,
        deadline: &Deadline,
        timings: &mut Vec<MetricTiming>,
        incomplete: &mut Vec<IncompleteMetric>,
    ) -> Result<plausibility::PlausibilityReport, EvalError> {
        // A dry run's evaluator computes no geometry metric.
        let metrics = match self.skip_geometry {
            true => Vec::new(),
            false => self.plan.geometry_metrics(),
        };
        let params = &self.plan.params;
        match plausibility::evaluate_metrics_each(scene, params, sources, &metrics, deadline, timings) {
            Ok((report, failed)) => {
                for (metric, e) in failed {
                    if matches!(e, PlausibilityError::DeadlineExceeded { .. }) {
                        return Err(e.into());
                    }
                    tracing::warn!(%metric, error = %e, "metric not computed");
                    incomplete.push(IncompleteMetric::new(Metric::from(metric), false, &e));
                }
                Ok(report)
            }
            Err(e) => {
                // Parameters the plan's validation let through: no metric could run.
                let report = plausibility::PlausibilityReport::empty(scene, &metrics);
                for &metric in &report.metrics {
                    tracing::warn!(%metric, error = %e, "metric not computed");
                    incomplete.push(IncompleteMetric::new(Metric::from(metric), false, &e));
                }
                Ok(report)
            }
        }
    }

    /// Whether the VLM answers support types or functional sides: a VLM is configured, the
    /// sources are the default ones and the plan runs support or accessibility.
    fn wants_vlm_sources(&self) -> bool {
        self.vlm.is_some()
            && !self.custom_sources
            && (self.wants_support_types() || self.plan.runs(Metric::Accessibility))
    }

    /// Whether the plan asks for support types: the support and stability metrics.
    fn wants_support_types(&self) -> bool {
        self.plan.runs(Metric::Support) || self.plan.runs(Metric::Stability)
    }

    /// Object views of `scene` for the VLM, when a renderer is configured; `dir` receives the
    /// rendered PNGs.
    #[cfg_attr(not(feature = "render"), allow(unused_variables))]
    fn views(
        &self,
        scene: &Scene,
        assets: Option<&AssetLibrary>,
        dir: Option<&Path>,
    ) -> Result<Option<Box<dyn ObjectViews>>, EvalError> {
        #[cfg(feature = "render")]
        if let Some((renderer, settings)) = &self.renderer {
            let empty;
            let assets = match assets {
                Some(a) => a,
                None => {
                    empty = AssetLibrary::new();
                    &empty
                }
            };
            let v = sceneeval_fidelity::RenderedViews::new(
                renderer,
                scene,
                assets,
                *settings,
                dir.map(Path::to_owned),
            )?;
            return Ok(Some(Box::new(v)));
        }
        Ok(None)
    }

    /// [`Evaluator::views`] of the scene's inputs; views that cannot be made are a source
    /// whose every view fails with the reason, so that what needs them is incomplete.
    fn views_or_failure(&self, scene: &Scene, inputs: &SceneInputs<'_>) -> Option<Box<dyn ObjectViews>> {
        match self.views(scene, inputs.assets, inputs.views_dir) {
            Ok(v) => v,
            Err(e) => Some(Box::new(FailedViews(Arc::new(e)))),
        }
    }

    /// Asks the VLM, together, the support types (with views, when the plan's metrics use
    /// them) and, with `sides`, the functional sides the objects do not state.
    async fn ask_placement(
        &self,
        scene: &Scene,
        session: &Session<SharedVlm>,
        views: Option<&dyn ObjectViews>,
        sides: bool,
    ) -> AskedPlacement {
        let support = async {
            match views {
                Some(v) if self.wants_support_types() => {
                    Some(ask_support_types(scene, session, v, |o| o.support_type().is_some()).await)
                }
                _ => None,
            }
        };
        let sides = async {
            match sides {
                true => Some(ask_functional_sides(scene, session, |o| o.functional_sides().is_some()).await),
                false => None,
            }
        };
        let (support, sides) = join(support, sides).await;
        AskedPlacement {
            support,
            sides,
            views: views.is_some(),
        }
    }

    /// The plausibility sources of one scene with the VLM's answers between what the scene
    /// states and the category tables; where each object's values came from and why; the
    /// metrics whose questions failed, added to `incomplete`.
    fn placement_sources(
        &self,
        scene: &Scene,
        asked: &AskedPlacement,
        incomplete: &mut Vec<IncompleteMetric>,
    ) -> (Sources, Vec<ObjectPlacement>) {
        use sceneeval_plausibility::{Chain, FunctionalSidePriors, Stated, SupportTypePriors};
        let sources = Sources::new(
            Chain::new(
                Stated,
                Chain::new(
                    VlmAnswers(answered(asked.support.as_ref())),
                    SupportTypePriors::default(),
                ),
            ),
            Chain::new(
                Stated,
                Chain::new(
                    VlmAnswers(answered(asked.sides.as_ref())),
                    FunctionalSidePriors::default(),
                ),
            ),
        );
        // A failed question costs the metrics that use its answers: support types are the
        // support and stability metrics', functional sides accessibility's.
        for (metrics, map) in [
            (
                &[Metric::Support, Metric::Stability][..],
                asked.support.as_ref().map(failed_first),
            ),
            (
                &[Metric::Accessibility][..],
                asked.sides.as_ref().map(failed_first),
            ),
        ] {
            if let Some(Some(e)) = map {
                for &metric in metrics.iter().filter(|&&m| self.plan.runs(m)) {
                    incomplete.push(IncompleteMetric::new(metric, true, e.as_ref()));
                }
            }
        }
        let not_asked_support = if asked.views {
            "not asked"
        } else {
            "not asked: no renderer for the object views the VLM is shown"
        };
        let objects = scene
            .objects()
            .iter()
            .map(|o| {
                let id = o.id().as_str();
                ObjectPlacement {
                    object: o.id().clone(),
                    support_type: self.wants_support_types().then(|| {
                        let a = sources.support_types.support_type(scene, o);
                        provenance(
                            a,
                            asked.support.as_ref().and_then(|m| m.get(id)),
                            not_asked_support,
                        )
                    }),
                    functional_sides: asked.sides.is_some().then(|| {
                        let a = sources.functional_sides.functional_sides(scene, o);
                        provenance(
                            a,
                            asked.sides.as_ref().and_then(|m| m.get(id)),
                            "not asked: the object has no description or category to describe",
                        )
                    }),
                }
            })
            .collect();
        (sources, objects)
    }
}

/// What the VLM was asked about the objects' placement: per object, by id.
struct AskedPlacement {
    support: Option<BTreeMap<String, Asked<SupportType>>>,
    sides: Option<BTreeMap<String, Asked<Vec<Side>>>>,
    /// Whether there were views to show (support types are asked only with them).
    views: bool,
}

/// The values the VLM answered, by object id.
fn answered<T: Clone>(asked: Option<&BTreeMap<String, Asked<T>>>) -> BTreeMap<String, T> {
    asked
        .into_iter()
        .flatten()
        .filter_map(|(id, a)| a.value().map(|v| (id.clone(), v.clone())))
        .collect()
}

/// The first failed question of `asked`, in object order.
fn failed_first<T>(asked: &BTreeMap<String, Asked<T>>) -> Option<Arc<FidelityError>> {
    asked.values().find_map(|a| match a {
        Asked::Failed(e) => Some(e.clone()),
        _ => None,
    })
}

/// Where a value a source chain gave (`answer`) came from, and why; `asked` is what the VLM
/// gave for the object (`None`: it was not asked, for `not_asked`).
fn provenance<T: Clone>(
    answer: Option<plausibility::Answer<T>>,
    asked: Option<&Asked<T>>,
    not_asked: &str,
) -> Provenance<T> {
    let source = match answer.as_ref().map(|a| a.source.as_str()) {
        Some("scene") => PlacementSource::Scene,
        Some(VLM_SOURCE) => PlacementSource::Vlm,
        Some(_) => PlacementSource::CategoryPrior,
        None => PlacementSource::None,
    };
    let reason = match (source, asked) {
        (PlacementSource::Scene, _) => "stated in the scene file".to_owned(),
        (_, Some(Asked::Answered { reason, .. })) => reason.clone(),
        (_, Some(Asked::Unanswered(why))) => format!("the VLM gave no usable answer: {why}"),
        (_, Some(Asked::Failed(e))) => {
            format!(
                "the VLM request failed: {}",
                sceneeval_files::ErrorChain::new(e.as_ref())
            )
        }
        (_, None) => not_asked.to_owned(),
    };
    let reason = match source {
        PlacementSource::None => format!("{reason}; no category table entry either"),
        _ => reason,
    };
    Provenance {
        value: answer.map(|a| a.value),
        source,
        reason,
    }
}

/// The source name of the VLM's answers in the plausibility reports.
const VLM_SOURCE: &str = "vlm";

#[cfg(feature = "physics")]
impl StabilityRun {
    /// The stability of `scene`, each object's support type from `sources` (as the support
    /// metric asks them), stopping when `deadline` passes.
    fn evaluate(
        &self,
        scene: &Scene,
        sources: &Sources,
        deadline: &Deadline,
    ) -> Result<sceneeval_physics::StabilityReport, EvalError> {
        Ok(self
            .metric
            .evaluate(scene, &self.support_types(scene, sources), &self.cache, deadline)?)
    }

    /// Each object's support type from `sources` (scene order; `None`: no source knows).
    fn support_types(&self, scene: &Scene, sources: &Sources) -> Vec<Option<sceneeval_scene::SupportType>> {
        scene
            .objects()
            .iter()
            .map(|o| sources.support_types.support_type(scene, o).map(|a| a.value))
            .collect()
    }
}

/// The VLM's answers as a plausibility source (named `vlm` in the reports).
struct VlmAnswers<T>(BTreeMap<String, T>);

impl<Q> plausibility::Source<Q> for VlmAnswers<Q::Value>
where
    Q: plausibility::Question,
{
    fn answer(
        &self,
        _scene: &Scene,
        object: &sceneeval_scene::SceneObject,
    ) -> Option<plausibility::Answer<Q::Value>> {
        self.0.get(object.id().as_str()).map(|v| plausibility::Answer {
            value: v.clone(),
            source: VLM_SOURCE.to_owned(),
        })
    }
}

/// Object views that cannot be made, each failing with why (the renderer could not prepare
/// the scene): the metrics that need views are incomplete, the others are computed.
struct FailedViews(Arc<EvalError>);

impl ObjectViews for FailedViews {
    fn view(&self, object: &str, kind: ViewKind) -> Result<sceneeval_vlm::PngImage, FidelityError> {
        Err(FidelityError::View {
            object: object.to_owned(),
            view: kind.name(),
            source: Box::new(self.0.clone()),
        })
    }

    fn made(&self) -> u64 {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Preset;
    use sceneeval_geom::conventions::pose_from_yaw;
    use sceneeval_geom::{Point2, Point3, Vector3};
    use sceneeval_results::SCENE_REPORT_SCHEMA;
    use sceneeval_scene::{Category, RoomBuilder};

    fn scene() -> Scene {
        Scene::builder()
            .name("scene_7")
            .room_builder(
                RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 4.0)).door(
                    0,
                    [1.0, 2.0],
                    [0.0, 2.0],
                ),
            )
            .add_box(
                "bed",
                Category::new("bed"),
                Vector3::new(0.8, 1.0, 0.25),
                pose_from_yaw(Point3::new(2.0, 3.0, 0.25), 0.0),
            )
            .add_box(
                "stray",
                Category::new("chair"),
                Vector3::new(0.25, 0.25, 0.45),
                pose_from_yaw(Point3::new(6.0, 2.0, 0.45), 0.0),
            )
            .build()
            .unwrap()
    }

    fn plan_of(metrics: &[Metric]) -> EvaluationPlan {
        EvaluationPlan {
            metrics: metrics.to_vec(),
            ..EvaluationPlan::default()
        }
    }

    #[test]
    fn result_digest_depends_on_the_vlm_model_and_its_settings() {
        use sceneeval_vlm::Scripted;
        let with = |vlm: Option<Scripted>| {
            let e = Evaluator::new(EvaluationPlan::geometry_only()).unwrap();
            match vlm {
                Some(v) => e.with_vlm(SharedVlm::new(v)),
                None => e,
            }
            .result_digest()
        };
        let none = with(None);
        assert_eq!(none, EvaluationPlan::geometry_only().result_digest());
        let m = with(Some(Scripted::queue("m", [])));
        let low = with(Some(Scripted::queue("m", []).with_settings("detail=low")));
        let high = with(Some(Scripted::queue("m", []).with_settings("detail=high")));
        let other = with(Some(Scripted::queue("m2", [])));
        let all = [&none, &m, &low, &high, &other];
        for (i, a) in all.iter().enumerate() {
            for b in &all[i + 1..] {
                assert_ne!(a, b);
            }
        }
        // Deterministic: the same model and settings give the same digest.
        assert_eq!(
            low,
            with(Some(Scripted::queue("m", []).with_settings("detail=low")))
        );
    }

    /// Functional sides asked of a VLM: the bed's answered, the chair's left out of both
    /// answers; support types not asked (no renderer for the views).
    #[test]
    fn where_each_objects_placement_came_from_is_recorded() {
        use sceneeval_vlm::{AnswerContent, Scripted};
        let vlm = Scripted::from_fn("m", |_| {
            Ok(AnswerContent::Json {
                value: serde_json::json!({"assessments": [{"obj_id": "bed", "obj_description": "",
                    "functional_sides": ["left", "right"], "reason": "climbed into from the sides"}]}),
            })
        });
        let evaluator = Evaluator::new(plan_of(&[Metric::Support, Metric::Accessibility]))
            .unwrap()
            .with_vlm(SharedVlm::new(vlm));
        let report = evaluator
            .evaluate_scene(&scene(), &SceneInputs::default())
            .map(|e| e.report)
            .unwrap();
        let p = report.placement.as_ref().unwrap();
        let sides: Vec<(PlacementSource, &str)> = p
            .iter()
            .map(|o| {
                let s = o.functional_sides.as_ref().unwrap();
                (s.source, s.reason.as_str())
            })
            .collect();
        assert_eq!(sides[0], (PlacementSource::Vlm, "climbed into from the sides"));
        assert_eq!(sides[1].0, PlacementSource::CategoryPrior);
        assert!(
            sides[1]
                .1
                .starts_with("the VLM gave no usable answer: invalid answer: asked twice"),
            "{}",
            sides[1].1
        );
        // The chair's sides are the table's (all four); the bed's the VLM's.
        assert_eq!(
            p[1].functional_sides
                .as_ref()
                .unwrap()
                .value
                .as_ref()
                .unwrap()
                .len(),
            4
        );
        assert_eq!(
            p[0].functional_sides.as_ref().unwrap().value,
            Some(vec![Side::Left, Side::Right])
        );
        for o in p {
            let s = o.support_type.as_ref().unwrap();
            assert_eq!(
                (s.source, s.value),
                (PlacementSource::CategoryPrior, Some(SupportType::Ground))
            );
            assert_eq!(
                s.reason,
                "not asked: no renderer for the object views the VLM is shown"
            );
        }
        // An unanswered question is a fallback, not a failure: the scene is complete.
        assert!(report.incomplete.is_empty());
        let record = sceneeval_results::SceneRecord::ok(sceneeval_results::SceneName::new("scene_7"), report);
        let summary = sceneeval_results::Summary::from_records([&record], None);
        assert_eq!(
            (
                summary.groups[0].support_fallbacks,
                summary.groups[0].sides_fallbacks
            ),
            (2, 1)
        );
    }

    /// The functional-sides request gets no answer (the endpoint is down): accessibility is
    /// computed with the category tables, listed as incomplete, and the scene is partial;
    /// every other metric is complete.
    #[test]
    fn a_failed_placement_question_makes_the_scene_partial_and_keeps_the_rest() {
        use sceneeval_vlm::{Scripted, VlmError};
        let vlm = Scripted::from_fn("m", |req| {
            Err(VlmError::Backend {
                task: req.task.clone(),
                model: "m".into(),
                permanent: false,
                source: "HTTP 503".into(),
            })
        });
        let s = scene();
        let complete = Evaluator::new(EvaluationPlan::geometry_only())
            .unwrap()
            .evaluate_scene(&s, &SceneInputs::default())
            .map(|e| e.report)
            .unwrap();
        let report = Evaluator::new(EvaluationPlan::geometry_only())
            .unwrap()
            .with_vlm(SharedVlm::new(vlm))
            .evaluate_scene(&s, &SceneInputs::default())
            .map(|e| e.report)
            .unwrap();
        let incomplete: Vec<(Metric, bool)> = report.incomplete.iter().map(|m| (m.metric, m.vlm)).collect();
        assert_eq!(incomplete, [(Metric::Accessibility, true)]);
        assert!(
            report.incomplete[0].causes.iter().any(|c| c.contains("HTTP 503")),
            "{:?}",
            report.incomplete[0]
        );
        // Every metric's result is the one without a VLM (the tables answered for all).
        assert_eq!(report.summary, complete.summary);
        assert_eq!(report.accessibility, complete.accessibility);
        let sides = report.placement.as_ref().unwrap()[0]
            .functional_sides
            .as_ref()
            .unwrap();
        assert!(
            sides.reason.starts_with("the VLM request failed: "),
            "{}",
            sides.reason
        );
        let record = sceneeval_results::SceneRecord::ok(sceneeval_results::SceneName::new("scene_7"), report);
        assert_eq!(record.status(), "partial");
        let text = serde_json::to_string(&record).unwrap();
        assert!(text.contains(r#""status":"partial""#), "{text}");
    }

    /// Answers every object's support type (`ground`) and cancels `deadline` on the first
    /// question, as if the time budget ran out while the support metric runs.
    struct CancelInSupport(Deadline);

    impl plausibility::Source<plausibility::SupportTypeOf> for CancelInSupport {
        fn answer(
            &self,
            _: &Scene,
            _: &sceneeval_scene::SceneObject,
        ) -> Option<plausibility::Answer<SupportType>> {
            self.0.cancel();
            Some(plausibility::Answer {
                value: SupportType::Ground,
                source: "test".into(),
            })
        }
    }

    #[test]
    fn the_time_budget_running_out_in_a_metric_fails_the_scene_naming_it() {
        let deadline = Deadline::none();
        let sources = Sources::new(
            CancelInSupport(deadline.clone()),
            plausibility::FunctionalSidePriors::default(),
        );
        let evaluator = Evaluator::new(EvaluationPlan::geometry_only())
            .unwrap()
            .with_sources(sources);
        let inputs = SceneInputs {
            deadline: Some(&deadline),
            ..SceneInputs::default()
        };
        let err = evaluator.evaluate_scene(&scene(), &inputs).unwrap_err();
        assert!(
            matches!(
                err,
                EvalError::Plausibility(PlausibilityError::DeadlineExceeded { stage: "support", .. })
            ),
            "{err}"
        );
        assert_eq!(err.to_string(), "support stopped: the evaluation was cancelled");
        // Without the deadline the same evaluator computes everything.
        let done = evaluator
            .evaluate_scene(&scene(), &SceneInputs::default())
            .unwrap();
        assert!(done.report.incomplete.is_empty() && done.report.support.is_some());
    }

    #[test]
    fn subset_plan_reports_only_its_metrics() {
        let plan = plan_of(&[Metric::OutOfBounds, Metric::Collision]);
        let r = Evaluator::new(plan)
            .unwrap()
            .evaluate_scene(&scene(), &SceneInputs::default())
            .map(|e| e.report)
            .unwrap();
        assert_eq!(
            r.metrics,
            vec![plausibility::Metric::Collision, plausibility::Metric::OutOfBounds],
            "canonical order"
        );
        assert!(r.collision.is_some() && r.out_of_bounds.is_some());
        assert!(r.support.is_none() && r.navigability.is_none());
        assert_eq!(r.summary.geometry.sup, None);
        assert_eq!(r.summary.geometry.col_sc, Some(false));
        // The chair stands entirely outside the 4 x 4 m room: 1 of 2 objects out of bounds.
        assert_eq!(r.summary.geometry.oob, Some(0.5));
        assert_eq!(r.scene.as_deref(), Some("scene_7"));
        let ids: Vec<&str> = r.object_ids.iter().map(|i| i.as_str()).collect();
        assert_eq!(ids, vec!["bed", "stray"]);
    }

    #[test]
    fn full_plan_matches_individual_metrics() {
        let s = scene();
        let full = Evaluator::new(EvaluationPlan::geometry_only())
            .unwrap()
            .evaluate_scene(&s, &SceneInputs::default())
            .map(|e| e.report)
            .unwrap();
        for metric in plausibility::Metric::ALL {
            let one = Evaluator::new(plan_of(&[Metric::from(metric)]))
                .unwrap()
                .evaluate_scene(&s, &SceneInputs::default())
                .map(|e| e.report)
                .unwrap();
            match metric {
                plausibility::Metric::Collision => assert_eq!(one.collision, full.collision),
                plausibility::Metric::Support => assert_eq!(one.support, full.support),
                plausibility::Metric::Navigability => assert_eq!(one.navigability, full.navigability),
                plausibility::Metric::Accessibility => assert_eq!(one.accessibility, full.accessibility),
                plausibility::Metric::OutOfBounds => assert_eq!(one.out_of_bounds, full.out_of_bounds),
                plausibility::Metric::OpeningClearance => {
                    assert_eq!(one.opening_clearance, full.opening_clearance)
                }
            }
        }
        assert_eq!(full.summary.geometry.num_doors, Some(1));
        let json = serde_json::to_string(&full).unwrap();
        assert!(json.starts_with(&format!(r#"{{"schema":"{SCENE_REPORT_SCHEMA}","scene":"scene_7","object_ids":["bed","stray"],"metrics":["#)), "{json}");
        let back: SceneReport = serde_json::from_str(&json).unwrap();
        assert_eq!(back, full);
    }

    /// A 4 x 5 m room holding a desk resting on the floor, a crate floating 5 cm above it, a
    /// picture hung on the far wall (support type `wall` from the category table), and a
    /// shelf hung on the left wall whose file states `wall`, sunk 2 cm into it.
    fn physics_scene() -> Scene {
        use sceneeval_scene::{SceneObject, SupportType};
        let shelf = SceneObject::new_box(
            "shelf",
            Vector3::new(0.1, 0.3, 0.05),
            pose_from_yaw(Point3::new(0.08, 2.5, 1.2), 0.0),
        )
        .unwrap()
        .with_category(Category::new("shelf"))
        .with_support_type(SupportType::Wall);
        Scene::builder()
            .name("scene_3")
            .room_builder(RoomBuilder::rectangle(
                "r0",
                Point2::new(0.0, 0.0),
                Point2::new(4.0, 5.0),
            ))
            .add_box(
                "desk",
                Category::new("desk"),
                Vector3::new(0.5, 0.25, 0.375),
                pose_from_yaw(Point3::new(1.0, 1.0, 0.375), 0.0),
            )
            .add_box(
                "crate",
                Category::new("box"),
                Vector3::new(0.2, 0.2, 0.2),
                pose_from_yaw(Point3::new(3.0, 1.0, 0.25), 0.0),
            )
            .add_box(
                "picture",
                Category::new("picture"),
                Vector3::new(0.3, 0.02, 0.2),
                pose_from_yaw(Point3::new(2.0, 4.98, 1.5), 0.0),
            )
            .object(shelf)
            .build()
            .unwrap()
    }

    #[test]
    fn stability_runs_with_the_support_metrics_sources_and_fills_the_report() {
        use sceneeval_physics::WeldReason;
        let s = physics_scene();
        let plan = EvaluationPlan::from_json_str(r#"{"metrics": ["stability", "support"]}"#).unwrap();
        let done = Evaluator::new(plan)
            .unwrap()
            .evaluate_scene(&s, &SceneInputs::default())
            .unwrap();
        let r = &done.report;
        let st = r.stability.as_ref().unwrap();
        let by_id = |id: &str| st.objects.iter().find(|o| o.id.as_str() == id).unwrap();
        // The desk rests; the crate falls 5 cm (over the 1 cm limit); the picture (category
        // table) and the shelf (stated in the file) are welded as wall-mounted, as support
        // reports them.
        assert!(by_id("desk").stable && !by_id("desk").welded);
        let fallen = by_id("crate");
        assert!(
            !fallen.stable && (fallen.displacement_m - 0.05).abs() < 0.005,
            "{fallen:?}"
        );
        assert_eq!(by_id("picture").weld_reason, Some(WeldReason::Wall));
        assert_eq!(by_id("shelf").weld_reason, Some(WeldReason::Wall));
        let support = r.support.as_ref().unwrap();
        // The same answers, unknown (the crate: no table entry) as `null` here and checked as
        // `ground` there.
        for (o, sup) in st.objects.iter().zip(&support.objects) {
            let known = sup.type_source.as_ref().map(|_| sup.support_type);
            assert_eq!(o.support_type, known, "{}", o.id);
        }
        assert_eq!(by_id("crate").support_type, None);
        // 1 of the 2 free objects moved: frac_unstable 0.5, STAB 0.5.
        assert_eq!(st.frac_unstable, Some(0.5));
        assert_eq!(r.summary.stab, Some(Some(0.5)));
        assert!(done.stability_seconds.is_some());
        // In eval.json: `stab` in the summary, the section after the metrics', read back.
        let json = serde_json::to_value(r).unwrap();
        assert_eq!(json["summary"]["stab"], 0.5);
        assert_eq!(json["stability"]["objects"][2]["weld_reason"], "wall");
        let back: SceneReport = serde_json::from_value(json).unwrap();
        assert_eq!(&back, r);

        // Every weld variant through a plan: with nothing welded the picture and the shelf
        // fall too (3 of 4 unstable); under `penetration` the shelf, 2 cm into its wall, is
        // welded for it and the picture falls (2 of 3).
        for (weld, unstable, shelf) in [
            ("none", 0.75, None),
            ("penetration", 2.0 / 3.0, Some(WeldReason::Penetration)),
            ("combined", 0.5, Some(WeldReason::Wall)),
        ] {
            let plan = EvaluationPlan::from_json_str(&format!(
                r#"{{"metrics": ["stability"], "stability": {{"weld": "{weld}"}}}}"#
            ))
            .unwrap();
            let r = Evaluator::new(plan)
                .unwrap()
                .evaluate_scene(&s, &SceneInputs::default())
                .map(|e| e.report)
                .unwrap();
            let st = r.stability.as_ref().unwrap();
            assert_eq!(st.frac_unstable, Some(unstable), "{weld}");
            assert_eq!(st.objects[3].weld_reason, shelf, "{weld}");
            assert_eq!(r.summary.stab, Some(Some(1.0 - unstable)), "{weld}");
        }
    }

    #[test]
    fn stability_stops_the_scene_at_the_time_budget_and_reports_a_scene_without_rooms() {
        let plan = EvaluationPlan::from_json_str(r#"{"metrics": ["stability"]}"#).unwrap();
        let evaluator = Evaluator::new(plan).unwrap();
        let deadline = Deadline::after(std::time::Duration::ZERO);
        let inputs = SceneInputs {
            deadline: Some(&deadline),
            ..SceneInputs::default()
        };
        // The time budget stops the scene: an error naming the stability metric.
        let err = evaluator.evaluate_scene(&physics_scene(), &inputs).unwrap_err();
        let err = sceneeval_files::ErrorChain::new(&err).to_string();
        assert!(err.starts_with("stability: "), "{err}");
        assert!(err.contains("time budget"), "{err}");
        // A failing metric costs only itself: the scene is partial, stability listed.
        let incomplete = |r: &SceneReport| {
            assert_eq!(r.incomplete.len(), 1, "{:?}", r.incomplete);
            assert_eq!(
                (r.incomplete[0].metric, r.incomplete[0].vlm),
                (Metric::Stability, false)
            );
            let m = &r.incomplete[0];
            sceneeval_files::ErrorChain::from_parts(m.error.as_str(), &m.causes).to_string()
        };
        let roomless = Scene::builder()
            .name("scene_9")
            .add_box(
                "desk",
                Category::new("desk"),
                Vector3::new(0.5, 0.25, 0.375),
                pose_from_yaw(Point3::new(1.0, 1.0, 0.375), 0.0),
            )
            .build()
            .unwrap();
        let err = incomplete(
            &evaluator
                .evaluate_scene(&roomless, &SceneInputs::default())
                .map(|e| e.report)
                .unwrap(),
        );
        assert!(err.contains("has no room"), "{err}");
        // Without the metric the report has neither section nor key.
        let r = Evaluator::new(EvaluationPlan::geometry_only())
            .unwrap()
            .evaluate_scene(&physics_scene(), &SceneInputs::default())
            .map(|e| e.report)
            .unwrap();
        assert!(r.stability.is_none() && r.summary.stab.is_none());
        assert!(!serde_json::to_string(&r).unwrap().contains("stab"));
    }

    #[test]
    fn a_fidelity_plan_runs_in_the_one_call_given_the_row_and_reports_no_fidelity_without_it() {
        let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
                   7,easy,A bedroom with a bed and a chair.,\"eq,1,bed; eq,1,chair\",,,\"eq,1,inside,chair,room\"\n";
        let row = sceneeval_annotation::Annotations::from_csv_str(csv)
            .unwrap()
            .rows
            .remove(0);
        let evaluator = Evaluator::new(EvaluationPlan::full(Preset::Default)).unwrap();
        let s = scene();
        // Without a row the text-fidelity metrics have nothing to check: no section (a batch
        // gives each scene the row the annotations have for it, if any).
        let without = evaluator.evaluate_scene(&s, &SceneInputs::default()).unwrap();
        assert!(without.report.fidelity.is_none() && without.matching.is_none());
        assert!(without.report.summary.fidelity.is_none());

        let inputs = SceneInputs {
            row: Some(&row),
            ..SceneInputs::default()
        };
        let done = evaluator.evaluate_scene(&s, &inputs).unwrap();
        let fidelity = done.report.fidelity.as_ref().unwrap();
        // CNT: one bed and one chair, both present: 2/2. OAR: the chair stands outside the
        // room: 0/1. No VLM: ATR is not judged.
        assert_eq!(fidelity.summary.cnt, Some(1.0));
        assert_eq!(fidelity.summary.oar, Some(0.0));
        assert_eq!(fidelity.summary.atr, None);
        assert_eq!(done.report.summary.fidelity, Some(fidelity.summary));
        assert!(done.matching.is_some() && done.fidelity_seconds.is_some());
        assert_eq!(done.timings.len(), 6);
        // The geometry part is the geometry plan's.
        let geometry = Evaluator::new(EvaluationPlan::geometry_only())
            .unwrap()
            .evaluate_scene(&s, &SceneInputs::default())
            .map(|e| e.report)
            .unwrap();
        assert_eq!(done.report.summary.geometry, geometry.summary.geometry);
    }
}
