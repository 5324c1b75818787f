use serde::{Deserialize, Serialize};

use crate::plausibility::{self, Deadline, MetricTiming, PlausibilityReport, Sources};
use crate::scene::Scene;
use crate::{EvalError, EvaluationPlan};

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
}

impl Evaluator {
    /// An evaluator with the default sources: what each object states, then the built-in
    /// category tables.
    ///
    /// # Errors
    /// [`EvalError::Plan`] when the plan is invalid (see [`EvaluationPlan::validate`]).
    pub fn new(plan: EvaluationPlan) -> Result<Self, EvalError> {
        plan.validate()?;
        Ok(Evaluator {
            plan,
            sources: Sources::default(),
        })
    }

    /// Replaces the support-type and functional-side sources (e.g. types given by the generator).
    pub fn with_sources(mut self, sources: Sources) -> Self {
        self.sources = sources;
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
        let report = plausibility::evaluate_metrics(
            scene,
            &self.plan.params,
            &self.sources,
            &self.plan.metrics,
            deadline,
            timings,
        )?;
        Ok(SceneReport {
            schema: SCENE_REPORT_SCHEMA.to_owned(),
            plausibility: report,
        })
    }
}

/// Everything measured on one scene, serialised as the `report` of its `eval.json` (see
/// `docs/formats.md`): the schema, then the fields of the [`PlausibilityReport`] (scene id,
/// object ids, metrics, summary, each metric's evidence) at the same level.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneReport {
    /// Always [`SCENE_REPORT_SCHEMA`].
    pub schema: String,
    /// What the plausibility metrics found.
    #[serde(flatten)]
    pub plausibility: PlausibilityReport,
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
