use serde::{Deserialize, Serialize};

use crate::plausibility::{
    self, AccessibilityReport, CollisionReport, NavigabilityReport, OpeningClearanceReport,
    OutOfBoundsReport, Sources, SupportReport,
};
use crate::scene::Scene;
use crate::{EvalError, EvaluationPlan, Metric};

/// The schema name and version written into every per-scene report.
pub const SCENE_REPORT_SCHEMA: &str = "sceneeval.scene-report/1";

/// Runs an [`EvaluationPlan`] on scenes.
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
/// assert_eq!(report.summary.col_ob, Some(1.0));
/// assert_eq!(report.summary.col_sc, Some(true));
/// ```
#[derive(Debug)]
pub struct Evaluator {
    plan: EvaluationPlan,
    sources: Sources,
}

impl Evaluator {
    /// An evaluator with the built-in category tables as support-type and functional-side sources.
    ///
    /// # Errors
    /// [`EvalError::Plan`] when the plan lists no metric or one twice.
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

    /// Evaluates one scene.
    ///
    /// # Errors
    /// [`EvalError::Metric`] or [`EvalError::Plausibility`] when a metric rejects its parameters.
    pub fn evaluate(&self, scene: &Scene) -> Result<SceneReport, EvalError> {
        let plan = &self.plan;
        let params = &plan.params;
        let metric_err = |metric: Metric| move |source| EvalError::Metric { metric, source };
        let mut report = SceneReport::empty(scene, plan);
        if Metric::GEOMETRY_ONLY.iter().all(|m| plan.runs(*m)) {
            // Every metric: let the plausibility crate share its per-scene precomputation.
            let all =
                plausibility::evaluate(scene, params, &self.sources).map_err(EvalError::Plausibility)?;
            report.collision = Some(all.collision);
            report.support = Some(all.support);
            report.navigability = Some(all.navigability);
            report.accessibility = Some(all.accessibility);
            report.out_of_bounds = Some(all.out_of_bounds);
            report.opening_clearance = Some(all.opening_clearance);
        } else {
            for metric in Metric::GEOMETRY_ONLY.into_iter().filter(|m| plan.runs(*m)) {
                let err = metric_err(metric);
                match metric {
                    Metric::Collision => {
                        report.collision =
                            Some(plausibility::collision(scene, &params.collision).map_err(err)?)
                    }
                    Metric::Support => {
                        report.support = Some(
                            plausibility::support(
                                scene,
                                &params.support,
                                self.sources.support_types.as_ref(),
                            )
                            .map_err(err)?,
                        )
                    }
                    Metric::Navigability => {
                        report.navigability =
                            Some(plausibility::navigability(scene, &params.navigability).map_err(err)?)
                    }
                    Metric::Accessibility => {
                        report.accessibility = Some(
                            plausibility::accessibility(
                                scene,
                                &params.accessibility,
                                self.sources.functional_sides.as_ref(),
                            )
                            .map_err(err)?,
                        )
                    }
                    Metric::OutOfBounds => {
                        report.out_of_bounds =
                            Some(plausibility::out_of_bounds(scene, &params.out_of_bounds).map_err(err)?)
                    }
                    Metric::OpeningClearance => {
                        report.opening_clearance = Some(
                            plausibility::opening_clearance(scene, &params.opening_clearance).map_err(err)?,
                        )
                    }
                }
            }
        }
        report.summary = SceneSummary::of(&report);
        Ok(report)
    }
}

/// The scene-level numbers of one evaluated scene; a field is `None` when its metric did not
/// run or does not apply (e.g. no objects, no doors).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SceneSummary {
    /// Share of objects in collision (COL_ob), in [0, 1].
    pub col_ob: Option<f64>,
    /// Whether any two objects collide (COL_sc).
    pub col_sc: Option<bool>,
    /// Share of supported objects (SUP), in [0, 1].
    pub sup: Option<f64>,
    /// Largest connected free floor region over all free floor (NAV), in [0, 1].
    pub nav: Option<f64>,
    /// Whether every room with a door can be entered from it.
    pub all_rooms_reachable: Option<bool>,
    /// Mean best-side accessibility over objects with functional sides (ACC), in [0, 1].
    pub acc: Option<f64>,
    /// Share of objects out of bounds (OOB), in [0, 1].
    pub oob: Option<f64>,
    /// Number of doors.
    pub num_doors: Option<usize>,
    /// Doors with an object in their clearance space.
    pub doors_blocked: Option<usize>,
    /// Number of windows.
    pub num_windows: Option<usize>,
    /// Windows with an object in their clearance space.
    pub windows_blocked: Option<usize>,
}

impl SceneSummary {
    fn of(report: &SceneReport) -> Self {
        let c = report.collision.as_ref();
        let oc = report.opening_clearance.as_ref();
        let nav = report.navigability.as_ref();
        SceneSummary {
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

/// Everything measured on one scene: the scene-level summary and each metric's per-object
/// evidence. Serialised as the `report` of a scene's `eval.json` (see `docs/formats.md`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneReport {
    /// Always [`SCENE_REPORT_SCHEMA`].
    pub schema: String,
    /// The scene's name (the file stem for scenes read from disk).
    pub scene_id: String,
    /// The object ids, in scene order.
    pub object_ids: Vec<String>,
    /// The metrics that ran.
    pub metrics: Vec<Metric>,
    /// Scene-level numbers.
    pub summary: SceneSummary,
    /// Collision evidence.
    pub collision: Option<CollisionReport>,
    /// Support evidence.
    pub support: Option<SupportReport>,
    /// Navigability evidence.
    pub navigability: Option<NavigabilityReport>,
    /// Accessibility evidence.
    pub accessibility: Option<AccessibilityReport>,
    /// Out-of-bounds evidence.
    pub out_of_bounds: Option<OutOfBoundsReport>,
    /// Door and window clearance evidence.
    pub opening_clearance: Option<OpeningClearanceReport>,
}

impl SceneReport {
    fn empty(scene: &Scene, plan: &EvaluationPlan) -> Self {
        SceneReport {
            schema: SCENE_REPORT_SCHEMA.to_owned(),
            scene_id: scene.id().unwrap_or_default().to_owned(),
            object_ids: scene.objects().iter().map(|o| o.id().to_string()).collect(),
            metrics: Metric::GEOMETRY_ONLY
                .into_iter()
                .filter(|m| plan.runs(*m))
                .collect(),
            summary: SceneSummary::default(),
            collision: None,
            support: None,
            navigability: None,
            accessibility: None,
            out_of_bounds: None,
            opening_clearance: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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
        assert_eq!(
            report.metrics,
            vec![Metric::Collision, Metric::OutOfBounds],
            "canonical order"
        );
        assert!(report.collision.is_some() && report.out_of_bounds.is_some());
        assert!(report.support.is_none() && report.navigability.is_none());
        assert_eq!(report.summary.sup, None);
        assert_eq!(report.summary.col_sc, Some(false));
        // The chair stands entirely outside the 4 x 4 m room: 1 of 2 objects out of bounds.
        assert_eq!(report.summary.oob, Some(0.5));
        assert_eq!(report.scene_id, "scene_7");
        assert_eq!(report.object_ids, vec!["bed", "stray"]);
    }

    #[test]
    fn full_plan_matches_individual_metrics() {
        let s = scene();
        let full = Evaluator::new(EvaluationPlan::geometry_only())
            .unwrap()
            .evaluate(&s)
            .unwrap();
        for metric in Metric::GEOMETRY_ONLY {
            let single = Evaluator::new(EvaluationPlan {
                metrics: vec![metric],
                ..EvaluationPlan::default()
            })
            .unwrap()
            .evaluate(&s)
            .unwrap();
            match metric {
                Metric::Collision => assert_eq!(single.collision, full.collision),
                Metric::Support => assert_eq!(single.support, full.support),
                Metric::Navigability => assert_eq!(single.navigability, full.navigability),
                Metric::Accessibility => assert_eq!(single.accessibility, full.accessibility),
                Metric::OutOfBounds => assert_eq!(single.out_of_bounds, full.out_of_bounds),
                Metric::OpeningClearance => assert_eq!(single.opening_clearance, full.opening_clearance),
            }
        }
        assert_eq!(full.summary.num_doors, Some(1));
        let json = serde_json::to_string(&full).unwrap();
        let back: SceneReport = serde_json::from_str(&json).unwrap();
        assert_eq!(back, full);
    }
}
