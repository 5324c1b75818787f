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
        Ok(Evaluator {
            plan,
            sources: Sources::default(),
            fidelity,
            vlm: None,
            custom_sources: false,
            skip_geometry: false,
            #[cfg(feature = "render")]
            renderer: None,
        })
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
    /// 4. When the plan runs text-fidelity metrics and the scene has an annotation row, CNT,
    ///    ATR, OOR, OAR ([`FidelityEvaluator::evaluate`]). A fidelity plan without a row
    ///    reports no fidelity section (a warning is logged): a batch run gives every scene
    ///    the row the annotations have for it, if any.
    /// 5. The report, built once ([`SceneReport::new`]).
    ///
    /// # Errors
    /// [`EvalError::Plausibility`] when a metric rejects its parameters or the deadline passes,
    /// [`EvalError::Fidelity`] when a view cannot be made, the VLM cannot be asked or an
    /// annotation entry is malformed.
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
        let geometry = plausibility::evaluate_metrics(
            scene,
            &self.plan.params,
            vlm_sources.as_ref().unwrap_or(&self.sources),
            &if self.skip_geometry {
                Vec::new()
            } else {
                self.plan.geometry_metrics()
            },
            deadline,
            &mut timings,
        )?;
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
        Ok(SceneEvaluation {
            report: SceneReport::new(name.map(str::to_owned), geometry, fidelity),
            matching,
            timings,
            fidelity_seconds,
        })
    }

    /// Whether the VLM answers support types or functional sides: a VLM is configured, the
    /// sources are the default ones and the plan runs support or accessibility.
    fn wants_vlm_sources(&self) -> bool {
        self.vlm.is_some()
            && !self.custom_sources
            && (self.plan.runs(Metric::Support) || self.plan.runs(Metric::Accessibility))
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
            Some(v) if self.plan.runs(Metric::Support) => {
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
