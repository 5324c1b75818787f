use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::Value;

use crate::annotation::AnnotationRow;
use crate::fidelity::{FidelityEvaluator, FidelityOutcome, FidelityReport, ObjectViews, Resources};
use crate::plausibility::{self, Deadline, MetricTiming, PlausibilityReport, Sources};
use crate::scene::Scene;
use crate::vlm::Session;
use crate::{EvalError, EvaluationPlan, SharedVlm};

/// The schema name and version written into every per-scene report.
pub const SCENE_REPORT_SCHEMA: &str = "sceneeval.scene-report/1";

/// Runs an [`EvaluationPlan`] on scenes.
///
/// The metrics are dispatched in one place, [`plausibility::evaluate_metrics`]; the evaluator
/// adds the plan, the support-type and functional-side sources, and the report's schema.
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
/// assert_eq!(report.plausibility.summary.col_ob, Some(1.0));
/// assert_eq!(report.plausibility.summary.col_sc, Some(true));
/// ```
#[derive(Debug)]
pub struct Evaluator {
    plan: EvaluationPlan,
    sources: Sources,
    fidelity: FidelityEvaluator,
    vlm: Option<SharedVlm>,
    custom_sources: bool,
    #[cfg(feature = "render")]
    renderer: Option<(crate::render::Renderer, crate::render::RenderSettings)>,
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
            #[cfg(feature = "render")]
            renderer: None,
        })
    }

    /// Uses `vlm` for the fidelity metrics (matching, attributes, relation mapping), each
    /// scene with its own [`Session`] so that its usage is recorded with it.
    pub fn with_vlm(mut self, vlm: SharedVlm) -> Self {
        self.vlm = Some(vlm);
        self
    }

    /// The VLM, if configured.
    pub fn vlm(&self) -> Option<&SharedVlm> {
        self.vlm.as_ref()
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

    /// Object views of `scene` for the VLM, when a VLM and a renderer are configured; `dir`
    /// receives the rendered PNGs.
    #[cfg_attr(not(feature = "render"), allow(unused_variables))]
    pub(crate) fn views_for(
        &self,
        scene: &Scene,
        assets: &crate::io::AssetLibrary,
        dir: Option<std::path::PathBuf>,
    ) -> Result<Option<Box<dyn ObjectViews>>, EvalError> {
        if self.vlm.is_none() {
            return Ok(None);
        }
        #[cfg(feature = "render")]
        if let Some((renderer, settings)) = &self.renderer {
            let v = crate::fidelity::RenderedViews::new(renderer, scene, assets, *settings, dir)?;
            return Ok(Some(Box::new(v)));
        }
        Ok(None)
    }

    /// A session for one scene (its usage is recorded with the scene), when a VLM is configured.
    pub fn scene_session(&self) -> Option<Session<SharedVlm>> {
        self.vlm.clone().map(Session::new)
    }

    /// Whether the VLM answers support types or functional sides: a VLM is configured, the
    /// sources are the default ones and the plan runs support or accessibility.
    pub(crate) fn wants_vlm_sources(&self) -> bool {
        self.vlm.is_some()
            && !self.custom_sources
            && (self.plan.runs(plausibility::Metric::Support)
                || self.plan.runs(plausibility::Metric::Accessibility))
    }

    /// The plausibility sources of one scene with the VLM's answers between what the scene
    /// states and the category tables (`None`: use [`Evaluator::sources`]). Objects that state
    /// their own values are not asked about.
    ///
    /// # Errors
    /// [`EvalError::Fidelity`] when a view cannot be made or the VLM cannot be asked.
    pub fn vlm_sources(
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
            Some(v) if self.plan.runs(plausibility::Metric::Support) => {
                ask_support_types(scene, session, v, |o| o.support_type().is_some())?
            }
            _ => Default::default(),
        };
        let sides = if self.plan.runs(plausibility::Metric::Accessibility) {
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

    /// Evaluates one scene with these sources instead of [`Evaluator::sources`].
    ///
    /// # Errors
    /// As [`Evaluator::evaluate_within`].
    pub fn evaluate_with_sources(
        &self,
        scene: &Scene,
        sources: &Sources,
        deadline: &Deadline,
        timings: &mut Vec<MetricTiming>,
    ) -> Result<SceneReport, EvalError> {
        let report = plausibility::evaluate_metrics(
            scene,
            &self.plan.params,
            sources,
            &self.plan.metrics,
            deadline,
            timings,
        )?;
        Ok(SceneReport {
            schema: SCENE_REPORT_SCHEMA.to_owned(),
            plausibility: report,
            fidelity: None,
        })
    }

    /// Runs the plan's fidelity metrics on `scene` against `row`, asking the VLM through
    /// `session` (see [`Evaluator::scene_session`]) with `views`.
    ///
    /// # Errors
    /// [`EvalError::Fidelity`].
    pub fn evaluate_fidelity(
        &self,
        scene: &Scene,
        scene_name: &str,
        row: &AnnotationRow,
        session: Option<&Session<SharedVlm>>,
        views: Option<&dyn ObjectViews>,
    ) -> Result<FidelityOutcome, EvalError> {
        let res = Resources {
            session,
            views,
            scene_name,
        };
        Ok(self
            .fidelity
            .evaluate(scene, row, &self.plan.fidelity_metrics, &res)?)
    }

    /// Replaces the support-type and functional-side sources (e.g. types given by the generator).
    ///
    /// Given sources replace the VLM's support types and functional sides too.
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

    /// The support-type and functional-side sources.
    #[inline]
    pub fn sources(&self) -> &Sources {
        &self.sources
    }

    /// Evaluates one scene with no time budget.
    ///
    /// # Errors
    /// [`EvalError::Plausibility`] when a metric rejects its parameters.
    pub fn evaluate(&self, scene: &Scene) -> Result<SceneReport, EvalError> {
        self.evaluate_within(scene, &Deadline::none(), &mut Vec::new())
    }

    /// Evaluates one scene, giving up when `deadline` passes, and appends each metric's wall
    /// time to `timings`.
    ///
    /// # Errors
    /// [`EvalError::Plausibility`] when a metric rejects its parameters or the deadline passes
    /// ([`plausibility::PlausibilityError::DeadlineExceeded`]).
    pub fn evaluate_within(
        &self,
        scene: &Scene,
        deadline: &Deadline,
        timings: &mut Vec<MetricTiming>,
    ) -> Result<SceneReport, EvalError> {
        self.evaluate_with_sources(scene, &self.sources, deadline, timings)
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

/// Everything measured on one scene, serialised as the `report` of its `eval.json` (see
/// `docs/formats.md`): the schema, then the fields of the [`PlausibilityReport`] (scene id,
/// object ids, metrics, summary, each metric's evidence) at the same level, then `fidelity`
/// when fidelity metrics ran; their scores `cnt`, `atr`, `oor`, `oar` are also written into
/// `summary`.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneReport {
    /// Always [`SCENE_REPORT_SCHEMA`].
    pub schema: String,
    /// What the plausibility metrics found.
    pub plausibility: PlausibilityReport,
    /// What the fidelity metrics found, when they ran.
    pub fidelity: Option<FidelityReport>,
}

const FIDELITY_SUMMARY_KEYS: [&str; 4] = ["cnt", "atr", "oor", "oar"];

#[derive(Deserialize)]
struct SceneReportWire {
    schema: String,
    #[serde(flatten)]
    plausibility: PlausibilityReport,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    fidelity: Option<FidelityReport>,
}

impl Serialize for SceneReport {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        /// The summary with the fidelity scores after the plausibility numbers.
        #[derive(Serialize)]
        struct Summary<'a> {
            #[serde(flatten)]
            plausibility: &'a plausibility::PlausibilitySummary,
            #[serde(flatten, skip_serializing_if = "Option::is_none")]
            fidelity: Option<crate::fidelity::FidelitySummary>,
        }
        /// The report's fields in the plausibility report's order (destructured below, so a
        /// field added there fails to compile here rather than going missing).
        #[derive(Serialize)]
        struct Wire<'a> {
            schema: &'a str,
            scene_id: &'a Option<String>,
            object_ids: &'a [crate::scene::ObjectId],
            metrics: &'a [crate::Metric],
            summary: Summary<'a>,
            collision: &'a Option<plausibility::CollisionReport>,
            support: &'a Option<plausibility::SupportReport>,
            navigability: &'a Option<plausibility::NavigabilityReport>,
            accessibility: &'a Option<plausibility::AccessibilityReport>,
            out_of_bounds: &'a Option<plausibility::OutOfBoundsReport>,
            opening_clearance: &'a Option<plausibility::OpeningClearanceReport>,
            #[serde(skip_serializing_if = "Option::is_none")]
            fidelity: &'a Option<FidelityReport>,
        }
        let PlausibilityReport {
            scene_id,
            object_ids,
            metrics,
            summary,
            collision,
            support,
            navigability,
            accessibility,
            out_of_bounds,
            opening_clearance,
        } = &self.plausibility;
        Wire {
            schema: &self.schema,
            scene_id,
            object_ids,
            metrics,
            summary: Summary {
                plausibility: summary,
                fidelity: self.fidelity.as_ref().map(|f| f.summary),
            },
            collision,
            support,
            navigability,
            accessibility,
            out_of_bounds,
            opening_clearance,
            fidelity: &self.fidelity,
        }
        .serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for SceneReport {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let mut value = Value::deserialize(deserializer)?;
        if let Some(Value::Object(summary)) = value.get_mut("summary") {
            for k in FIDELITY_SUMMARY_KEYS {
                summary.remove(k);
            }
        }
        let wire: SceneReportWire = serde_json::from_value(value).map_err(serde::de::Error::custom)?;
        Ok(SceneReport {
            schema: wire.schema,
            plausibility: wire.plausibility,
            fidelity: wire.fidelity,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Metric;
    use crate::geom::conventions::pose_from_yaw;
    use crate::geom::{Point2, Point3, Vector3};
    use crate::scene::Category;
    use crate::scene::RoomBuilder;

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
        let plan = EvaluationPlan {
            metrics: vec![Metric::OutOfBounds, Metric::Collision],
            ..EvaluationPlan::default()
        };
        let report = Evaluator::new(plan).unwrap().evaluate(&scene()).unwrap();
        let r = &report.plausibility;
        assert_eq!(
            r.metrics,
            vec![Metric::Collision, Metric::OutOfBounds],
            "canonical order"
        );
        assert!(r.collision.is_some() && r.out_of_bounds.is_some());
        assert!(r.support.is_none() && r.navigability.is_none());
        assert_eq!(r.summary.sup, None);
        assert_eq!(r.summary.col_sc, Some(false));
        // The chair stands entirely outside the 4 x 4 m room: 1 of 2 objects out of bounds.
        assert_eq!(r.summary.oob, Some(0.5));
        assert_eq!(r.scene_id.as_deref(), Some("scene_7"));
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
        let f = &full.plausibility;
        for metric in Metric::ALL {
            let single = Evaluator::new(EvaluationPlan {
                metrics: vec![metric],
                ..EvaluationPlan::default()
            })
            .unwrap()
            .evaluate(&s)
            .unwrap();
            let one = &single.plausibility;
            match metric {
                Metric::Collision => assert_eq!(one.collision, f.collision),
                Metric::Support => assert_eq!(one.support, f.support),
                Metric::Navigability => assert_eq!(one.navigability, f.navigability),
                Metric::Accessibility => assert_eq!(one.accessibility, f.accessibility),
                Metric::OutOfBounds => assert_eq!(one.out_of_bounds, f.out_of_bounds),
                Metric::OpeningClearance => assert_eq!(one.opening_clearance, f.opening_clearance),
            }
        }
        assert_eq!(f.summary.num_doors, Some(1));
        let json = serde_json::to_string(&full).unwrap();
        assert!(json.starts_with(r#"{"schema":"sceneeval.scene-report/1","scene_id":"scene_7","object_ids":["bed","stray"],"metrics":["#), "{json}");
        let back: SceneReport = serde_json::from_str(&json).unwrap();
        assert_eq!(back, full);
    }
}
