//! [`Evaluator`]: an evaluation plan with what it runs on (the support-type and
//! functional-side sources, a VLM and a renderer), and the per-scene pipeline,
//! [`Evaluator::evaluate_scene`]: the one place that says in which order a scene's metrics
//! run.

use std::path::Path;
use std::time::Instant;

use crate::annotation::AnnotationRow;
use crate::fidelity::{FidelityEvaluator, FidelityReport, MatchingRecord, ObjectViews, Resources};
use crate::io::AssetLibrary;
use crate::plausibility::{self, Deadline, MetricTiming, Sources};
use crate::scene::Scene;
use crate::vlm::Session;
use crate::{EvalError, EvaluationPlan, Metric, SceneReport, SharedVlm};

/// Runs an [`EvaluationPlan`] on scenes.
///
/// The geometry metrics are dispatched in one place, [`plausibility::evaluate_metrics`], the
/// text-fidelity metrics in [`FidelityEvaluator::evaluate`]; [`Evaluator::evaluate_scene`]
/// runs a scene through both in the plan's order, with the support-type and functional-side
/// sources, and, when configured, the VLM and the renderer of the views it is shown.
///
/// ```
/// use sceneeval::{Evaluator, EvaluationPlan};
/// use sceneeval::scene::{Category, RoomBuilder, Scene};
/// use sceneeval::geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
///
/// let scene = Scene::builder()
///     .id("scene_0")
///     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 4.0)))
///     .add_box("a", Category::new("table"), Vector3::new(0.5, 0.5, 0.4), pose_from_yaw(Point3::new(1.0, 1.0, 0.4), 0.0))
///     .add_box("b", Category::new("table"), Vector3::new(0.5, 0.5, 0.4), pose_from_yaw(Point3::new(1.5, 1.0, 0.4), 0.0))
///     .build()
///     .unwrap();
/// let report = Evaluator::new(EvaluationPlan::geometry_only()).unwrap().evaluate(&scene).unwrap();
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
    renderer: Option<(crate::render::Renderer, crate::render::RenderSettings)>,
    #[cfg(feature = "physics")]
    stability: StabilityRun,
}

/// The stability metric with the plan's parameters, and the decomposition cache its scenes
/// share.
#[cfg(feature = "physics")]
#[derive(Debug)]
struct StabilityRun {
    metric: crate::physics::Stability,
    cache: std::sync::Arc<crate::physics::DecompositionCache>,
}

/// What the evaluation of one scene may use besides the scene and the evaluator (all optional;
/// see [`Evaluator::evaluate_scene`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct SceneInputs<'a> {
    /// The scene's name in the report (default: the scene's own id, [`Scene::id`]); it also
    /// finds the scene's file when objects are matched from a folder of matching files.
    pub name: Option<&'a str>,
    /// The scene's annotation row, which the text-fidelity metrics check.
    pub row: Option<&'a AnnotationRow>,
    /// The asset library the scene was read with: the renderer draws the VLM's object views
    /// from its meshes and materials.
    pub assets: Option<&'a AssetLibrary>,
    /// A folder receiving the rendered object views (`<dir>/*.png`).
    pub views_dir: Option<&'a Path>,
    /// The time budget (default: none).
    pub deadline: Option<&'a Deadline>,
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
    /// The text-fidelity metrics' wall time together (matching, renders and VLM requests
    /// included), seconds, when they ran.
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
            metric: crate::physics::Stability::new(plan.stability.clone())?,
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
    /// ([`crate::physics::DecompositionCache::on_disk`]) lets re-runs and other weld variants
    /// reuse them; `sceneeval evaluate` keeps one in `<out>/physics-cache`
    /// ([`crate::DEFAULT_PHYSICS_CACHE_DIR`]).
    #[cfg(feature = "physics")]
    pub fn with_decomposition_cache(
        mut self,
        cache: std::sync::Arc<crate::physics::DecompositionCache>,
    ) -> Self {
        self.stability.cache = cache;
        self
    }

    /// The stability of `scene` under the plan's `stability` parameters (whether or not the
    /// plan lists the metric), each object's support type from [`Evaluator::sources`] (what
    /// the scene states, then the category tables, unless replaced), stopping when
    /// `deadline` passes (feature `physics`).
    ///
    /// # Errors
    /// `EvalError::Physics` as [`crate::physics::Stability::evaluate`].
    #[cfg(feature = "physics")]
    pub fn stability(
        &self,
        scene: &Scene,
        deadline: &Deadline,
    ) -> Result<crate::physics::StabilityReport, EvalError> {
        self.stability.evaluate(scene, &self.sources, deadline)
    }

    /// `scene` with every object at its pose after the stability metric's simulation (welded
    /// objects where they were), with the report that goes with it: what `sceneeval settle`
    /// writes. Parameters and support types as [`Evaluator::stability`] (feature `physics`).
    ///
    /// ```
    /// use sceneeval::{Deadline, Evaluator, EvaluationPlan};
    /// use sceneeval::scene::{Category, RoomBuilder, Scene};
    /// use sceneeval::geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
    ///
    /// // A 0.4 m crate 5 cm above the floor.
    /// let scene = Scene::builder()
    ///     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(3.0, 3.0)))
    ///     .add_box("crate", Category::new("box"), Vector3::repeat(0.2),
    ///              pose_from_yaw(Point3::new(1.5, 1.5, 0.25), 0.0))
    ///     .build()
    ///     .unwrap();
    /// let evaluator = Evaluator::new(EvaluationPlan::geometry_only()).unwrap();
    /// let (settled, report) = evaluator.settle(&scene, &Deadline::none()).unwrap();
    /// assert!(!report.objects[0].stable);
    /// // It landed: its centre is 0.2 m up, within a millimetre.
    /// let z = settled.objects()[0].pose().translation.z;
    /// assert!((z - 0.2).abs() < 1e-3, "{z}");
    /// ```
    ///
    /// # Errors
    /// As [`Evaluator::stability`].
    #[cfg(feature = "physics")]
    pub fn settle(
        &self,
        scene: &Scene,
        deadline: &Deadline,
    ) -> Result<(Scene, crate::physics::StabilityReport), EvalError> {
        let run = &self.stability;
        let (poses, report) = run.metric.settle(
            scene,
            &run.support_types(scene, &self.sources),
            &run.cache,
            &|| deadline.expired(),
        )?;
        let mut settled = scene.clone();
        for (i, pose) in poses.into_iter().enumerate() {
            // The simulation's poses are finite (a diverged one is an error above).
            settled
                .set_pose(i, pose)
                .map_err(|e| crate::physics::PhysicsError::Geometry {
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

    /// The same evaluator, computing no geometry metric: what a dry run asks the VLM.
    pub(crate) fn without_geometry(mut self) -> Self {
        self.skip_geometry = true;
        self
    }

    /// Renders the object views the VLM is shown with `renderer` at `settings` (feature
    /// `render`); without a renderer the VLM-based matching and ATR cannot run.
    #[cfg(feature = "render")]
    pub fn with_renderer(
        mut self,
        renderer: crate::render::Renderer,
        settings: crate::render::RenderSettings,
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
    /// VLM's model name and settings ([`crate::vlm::Vlm::settings`]) when one is configured
    /// (answers of another model, or of the same model with another image detail or
    /// temperature, are other results).
    pub fn result_digest(&self) -> String {
        let plan = self.plan.result_digest();
        match &self.vlm {
            None => plan,
            Some(v) => {
                use crate::vlm::Vlm;
                // Without settings the digest is the one earlier versions wrote.
                let text = match v.settings() {
                    "" => format!("{plan}\nvlm {}", v.model()),
                    settings => format!("{plan}\nvlm {}\nvlm settings {settings}", v.model()),
                };
                blake3::hash(text.as_bytes()).to_hex().to_string()
            }
        }
    }

    /// Evaluates one scene under the whole plan. Without a time budget, annotation row or VLM
    /// this is [`Evaluator::evaluate_scene`] with no inputs.
    ///
    /// # Errors
    /// [`EvalError::NoAnnotationRow`] when the plan runs text-fidelity metrics (they need the
    /// scene's row: call [`Evaluator::evaluate_scene`] with it); otherwise as
    /// [`Evaluator::evaluate_scene`].
    pub fn evaluate(&self, scene: &Scene) -> Result<SceneReport, EvalError> {
        if self.plan.has_fidelity() {
            return Err(EvalError::NoAnnotationRow {
                scene: scene.id().unwrap_or("the scene").to_owned(),
            });
        }
        Ok(self.evaluate_scene(scene, &SceneInputs::default())?.report)
    }

    /// Evaluates one scene under the whole plan: the per-scene pipeline.
    ///
    /// 1. With a VLM, and a scene that needs it (text-fidelity metrics with a row, or support
    ///    or accessibility with the default sources), a [`Session`] for the scene and its
    ///    object views (rendered into `inputs.views_dir` when given).
    /// 2. With a VLM and the default sources, the support types and functional sides the
    ///    objects do not state are asked of the VLM; they go between what the scene states and
    ///    the category tables (an object the VLM does not answer for takes the table's).
    /// 3. The geometry metrics ([`plausibility::evaluate_metrics`], under the deadline).
    /// 4. When the plan runs stability (feature `physics`), the rigid-body simulation under
    ///    the deadline, with the support types the support metric uses (the same sources, the
    ///    VLM's answers included).
    /// 5. When the plan runs text-fidelity metrics and the scene has an annotation row, CNT,
    ///    ATR, OOR, OAR ([`FidelityEvaluator::evaluate`]). A fidelity plan without a row
    ///    reports no fidelity section (a warning is logged): a batch run gives every scene
    ///    the row the annotations have for it, if any.
    /// 6. The report, built once ([`SceneReport::new`]).
    ///
    /// # Errors
    /// [`EvalError::Plausibility`] when a metric rejects its parameters or the deadline passes,
    /// [`EvalError::Fidelity`] when a view cannot be made, the VLM cannot be asked or an
    /// annotation entry is malformed, `EvalError::Physics` (feature `physics`) when the
    /// stability metric cannot simulate the scene or the deadline passes.
    pub fn evaluate_scene(
        &self,
        scene: &Scene,
        inputs: &SceneInputs<'_>,
    ) -> Result<SceneEvaluation, EvalError> {
        let name = inputs.name.or(scene.id());
        let none = Deadline::none();
        let deadline = inputs.deadline.unwrap_or(&none);
        let fidelity_runs = self.plan.has_fidelity() && inputs.row.is_some();
        if self.plan.has_fidelity() && inputs.row.is_none() {
            tracing::warn!(
                scene = name.unwrap_or_default(),
                "no annotation row: fidelity metrics skipped"
            );
        }
        let session = self.vlm.clone().map(Session::new);
        let views = match &session {
            Some(_) if fidelity_runs || self.wants_vlm_sources() => {
                self.views(scene, inputs.assets, inputs.views_dir)?
            }
            _ => None,
        };
        let vlm_sources = match &session {
            Some(s) => self.vlm_sources(scene, s, views.as_deref())?,
            None => None,
        };
        let mut timings = Vec::new();
        let sources = vlm_sources.as_ref().unwrap_or(&self.sources);
        let geometry = plausibility::evaluate_metrics(
            scene,
            &self.plan.params,
            sources,
            &if self.skip_geometry {
                Vec::new()
            } else {
                self.plan.geometry_metrics()
            },
            deadline,
            &mut timings,
        )?;
        #[cfg(feature = "physics")]
        let (stability, stability_seconds) = match self.plan.runs(Metric::Stability) && !self.skip_geometry {
            true => {
                let start = Instant::now();
                let report = self.stability.evaluate(scene, sources, deadline)?;
                (Some(report), Some(start.elapsed().as_secs_f64()))
            }
            false => (None, None),
        };
        #[cfg(not(feature = "physics"))]
        let stability_seconds = None;
        let mut fidelity: Option<FidelityReport> = None;
        let mut matching = None;
        let mut fidelity_seconds = None;
        if let (true, Some(row)) = (fidelity_runs, inputs.row) {
            let start = Instant::now();
            let res = Resources {
                session: session.as_ref(),
                views: views.as_deref(),
                scene_name: name.unwrap_or_default(),
            };
            let outcome = self
                .fidelity
                .evaluate(scene, row, &self.plan.fidelity_metrics(), &res)?;
            fidelity_seconds = Some(start.elapsed().as_secs_f64());
            fidelity = Some(outcome.report);
            matching = Some(outcome.matching);
        }
        let report = SceneReport::new(name.map(str::to_owned), geometry, fidelity);
        #[cfg(feature = "physics")]
        let report = match stability {
            Some(s) => report.with_stability(s),
            None => report,
        };
        Ok(SceneEvaluation {
            report,
            matching,
            timings,
            fidelity_seconds,
            stability_seconds,
        })
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
            let v = crate::fidelity::RenderedViews::new(
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

    /// The plausibility sources of one scene with the VLM's answers between what the scene
    /// states and the category tables (`None`: use [`Evaluator::sources`]). Objects that state
    /// their own values are not asked about.
    fn vlm_sources(
        &self,
        scene: &Scene,
        session: &Session<SharedVlm>,
        views: Option<&dyn ObjectViews>,
    ) -> Result<Option<Sources>, EvalError> {
        use crate::fidelity::placement::{ask_functional_sides, ask_support_types};
        use crate::plausibility::{Chain, FunctionalSidePriors, Stated, SupportTypePriors};
        if !self.wants_vlm_sources() {
            return Ok(None);
        }
        let support = match views {
            Some(v) if self.wants_support_types() => {
                ask_support_types(scene, session, v, |o| o.support_type().is_some())?
            }
            _ => Default::default(),
        };
        let sides = if self.plan.runs(Metric::Accessibility) {
            ask_functional_sides(scene, session, |o| o.functional_sides().is_some())?
        } else {
            Default::default()
        };
        Ok(Some(Sources::new(
            Chain::new(
                Stated,
                Chain::new(VlmAnswers(support), SupportTypePriors::default()),
            ),
            Chain::new(
                Stated,
                Chain::new(VlmAnswers(sides), FunctionalSidePriors::default()),
            ),
        )))
    }
}

#[cfg(feature = "physics")]
impl StabilityRun {
    /// The stability of `scene`, each object's support type from `sources` (as the support
    /// metric asks them), stopping when `deadline` passes.
    fn evaluate(
        &self,
        scene: &Scene,
        sources: &Sources,
        deadline: &Deadline,
    ) -> Result<crate::physics::StabilityReport, EvalError> {
        Ok(self
            .metric
            .evaluate(scene, &self.support_types(scene, sources), &self.cache, &|| {
                deadline.expired()
            })?)
    }

    /// Each object's support type from `sources` (scene order; `None`: no source knows).
    fn support_types(&self, scene: &Scene, sources: &Sources) -> Vec<Option<crate::scene::SupportType>> {
        scene
            .objects()
            .iter()
            .map(|o| sources.support_types.support_type(scene, o).map(|a| a.value))
            .collect()
    }
}

/// The VLM's answers as a plausibility source (named `vlm` in the reports).
struct VlmAnswers<T>(std::collections::BTreeMap<String, T>);

impl<Q> plausibility::Source<Q> for VlmAnswers<Q::Value>
where
    Q: plausibility::Question,
{
    fn answer(
        &self,
        _scene: &Scene,
        object: &crate::scene::SceneObject,
    ) -> Option<plausibility::Answer<Q::Value>> {
        self.0.get(object.id().as_str()).map(|v| plausibility::Answer {
            value: v.clone(),
            source: "vlm".to_owned(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::conventions::pose_from_yaw;
    use crate::geom::{Point2, Point3, Vector3};
    use crate::scene::{Category, RoomBuilder};
    use crate::{Preset, SCENE_REPORT_SCHEMA};

    fn scene() -> Scene {
        Scene::builder()
            .id("scene_7")
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
        use crate::vlm::Scripted;
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

    #[test]
    fn subset_plan_reports_only_its_metrics() {
        let plan = plan_of(&[Metric::OutOfBounds, Metric::Collision]);
        let r = Evaluator::new(plan).unwrap().evaluate(&scene()).unwrap();
        assert_eq!(
            r.geometry_metrics,
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
            .evaluate(&s)
            .unwrap();
        for metric in plausibility::Metric::ALL {
            let one = Evaluator::new(plan_of(&[Metric::from(metric)]))
                .unwrap()
                .evaluate(&s)
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
        assert!(json.starts_with(&format!(r#"{{"schema":"{SCENE_REPORT_SCHEMA}","scene_id":"scene_7","object_ids":["bed","stray"],"metrics":["#)), "{json}");
        let back: SceneReport = serde_json::from_str(&json).unwrap();
        assert_eq!(back, full);
    }

    /// A 4 x 5 m room holding a desk resting on the floor, a crate floating 5 cm above it, a
    /// picture hung on the far wall (support type `wall` from the category table), and a
    /// shelf hung on the left wall whose file states `wall`, sunk 2 cm into it.
    fn physics_scene() -> Scene {
        use crate::scene::{SceneObject, SupportType};
        let shelf = SceneObject::new_box(
            "shelf",
            Vector3::new(0.1, 0.3, 0.05),
            pose_from_yaw(Point3::new(0.08, 2.5, 1.2), 0.0),
        )
        .unwrap()
        .with_category(Category::new("shelf"))
        .with_support_type(SupportType::Wall);
        Scene::builder()
            .id("scene_3")
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
        use crate::physics::WeldReason;
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
            let r = Evaluator::new(plan).unwrap().evaluate(&s).unwrap();
            let st = r.stability.unwrap();
            assert_eq!(st.frac_unstable, Some(unstable), "{weld}");
            assert_eq!(st.objects[3].weld_reason, shelf, "{weld}");
            assert_eq!(r.summary.stab, Some(Some(1.0 - unstable)), "{weld}");
        }
    }

    #[test]
    fn stability_obeys_the_time_budget_and_reports_a_scene_without_rooms() {
        let plan = EvaluationPlan::from_json_str(r#"{"metrics": ["stability"]}"#).unwrap();
        let evaluator = Evaluator::new(plan).unwrap();
        let deadline = Deadline::none();
        deadline.cancel();
        let inputs = SceneInputs {
            deadline: Some(&deadline),
            ..SceneInputs::default()
        };
        let err = evaluator.evaluate_scene(&physics_scene(), &inputs).unwrap_err();
        assert!(err.to_string().contains("time budget"), "{err}");
        let roomless = Scene::builder()
            .id("scene_9")
            .add_box(
                "desk",
                Category::new("desk"),
                Vector3::new(0.5, 0.25, 0.375),
                pose_from_yaw(Point3::new(1.0, 1.0, 0.375), 0.0),
            )
            .build()
            .unwrap();
        let err = evaluator.evaluate(&roomless).unwrap_err();
        assert!(err.to_string().contains("has no room"), "{err}");
        // Without the metric the report has neither section nor key.
        let r = Evaluator::new(EvaluationPlan::geometry_only())
            .unwrap()
            .evaluate(&physics_scene())
            .unwrap();
        assert!(r.stability.is_none() && r.summary.stab.is_none());
        assert!(!serde_json::to_string(&r).unwrap().contains("stab"));
    }

    #[test]
    fn a_fidelity_plan_runs_in_one_call_given_the_row_and_refuses_without_it() {
        let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
                   7,easy,A bedroom with a bed and a chair.,\"eq,1,bed; eq,1,chair\",,,\"eq,1,inside,chair,room\"\n";
        let row = crate::annotation::Annotations::from_csv_str(csv)
            .unwrap()
            .rows
            .remove(0);
        let evaluator = Evaluator::new(EvaluationPlan::full(Preset::Default)).unwrap();
        let s = scene();
        let err = evaluator.evaluate(&s).unwrap_err();
        assert!(matches!(err, EvalError::NoAnnotationRow { .. }), "{err}");
        assert!(err.to_string().contains("evaluate_scene"), "{err}");

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
            .evaluate(&s)
            .unwrap();
        assert_eq!(done.report.summary.geometry, geometry.summary.geometry);
    }
}
