//! Text fidelity of SceneEval: does a generated scene contain what its description asked for?
//!
//! Each SceneEval-500 annotation row states object counts (`ObjCount`), attributes
//! (`ObjAttr`), object-object relationships (`OORel`) and object-architecture relationships
//! (`OARel`). This crate checks a [`Scene`](sceneeval_scene::Scene) against a row:
//!
//! 1. **Matching** ([`matching`]): which scene objects are instances of which annotated
//!    category, from the VLM (one request per object with its front view, optionally with its
//!    dimensions), from the objects' labels ([`labels`]: normalisation, plurals, a small
//!    synonym table, no VLM), or from a file in the reference's `obj_matching_result.json`
//!    shape. The matching is written per scene as `matching.json` with its source and reasons.
//! 2. **CNT**: matched objects per category against the quantifier.
//! 3. **ATR**: the VLM judges each matched instance's attributes from its front and size
//!    views; not judged without a VLM.
//! 4. **OOR**: the relationship is mapped onto predicates ([`lexicon`], or the VLM with the
//!    reference's prompt; unknown words go to the VLM when there is one), every candidate
//!    group (anchor x combinations of the other objects) is scored, satisfied groups are
//!    counted against the quantifier.
//! 5. **OAR**: likewise for each matched object against walls, doors, windows, floor,
//!    ceiling or room.
//!
//! Scores are the reference's: satisfied specs / specs per scene. The reference's faults are
//! fixed, each with a switch in [`FidelityParams`] where the fix changes published numbers
//! (the table there); [`FidelityParams::reference`] sets them all.
//!
//! VLM requests go through a [`sceneeval_vlm::Session`] (validation, one re-ask, unanswered
//! items recorded); the questions that wait on no other are asked together
//! ([`FidelityEvaluator::evaluate_async`]). A spec whose verdict a missing answer could change
//! has none (`satisfied: null`, counted in [`MetricResult::unanswered`], left out of the
//! score); a metric that cannot be computed is a [`MetricFailure`] and costs no other metric.
//! Views come from an [`ObjectViews`] (feature `render`: `RenderedViews`, each view rendered
//! once per object and reused by every metric).
//!
//! # Example
//! Labels and the lexicon, no VLM: two chairs next to a table, one lamp missing.
//! ```
//! use sceneeval_annotation::Annotations;
//! use sceneeval_fidelity::{FidelityEvaluator, FidelityMetric, FidelityParams, Resources};
//! use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
//! use sceneeval_relations::RelationParams;
//! use sceneeval_scene::{Category, RoomBuilder, Scene};
//! use sceneeval_vlm::Scripted;
//!
//! let scene = Scene::builder()
//!     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 4.0)))
//!     .add_box("t", Category::new("table"), Vector3::new(0.5, 0.5, 0.4), pose_from_yaw(Point3::new(2.0, 2.0, 0.4), 0.0))
//!     .add_box("c1", Category::new("chairs"), Vector3::new(0.2, 0.2, 0.45), pose_from_yaw(Point3::new(1.2, 2.0, 0.45), 0.0))
//!     .add_box("c2", Category::new("Chair"), Vector3::new(0.2, 0.2, 0.45), pose_from_yaw(Point3::new(2.8, 2.0, 0.45), 0.0))
//!     .build()?;
//! let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
//!     0,easy,A table with two chairs and a lamp.,\"eq,1,table; eq,2,chair; eq,1,lamp\",,\
//!     \"eq,2,next_to,0,table,chair\",\"eq,1,middle,table,room\"\n";
//! let row = Annotations::from_csv_str(csv)?.rows.remove(0);
//!
//! let evaluator = FidelityEvaluator::new(FidelityParams::default(), RelationParams::default())?;
//! let res = Resources::<Scripted> { session: None, views: None, scene_name: "scene_0" };
//! let out = evaluator.evaluate(&scene, &row, &FidelityMetric::ALL, &res)?;
//! let s = out.report.summary;
//! // CNT: table and chairs hold, the lamp is missing: 2/3.
//! assert_eq!(s.cnt, Some(2.0 / 3.0));
//! // ATR: no specs. OOR: both chairs are 0.3 m from the table: 1/1. OAR: table centred: 1/1.
//! assert_eq!((s.atr, s.oor, s.oar), (None, Some(1.0), Some(1.0)));
//! assert_eq!(out.report.oor.as_ref().unwrap().specs[0].count_satisfied, 2);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod error;
mod evaluate;
pub mod labels;
pub mod lexicon;
pub mod matching;
mod params;
pub mod placement;
mod report;
mod views;

pub use error::FidelityError;
pub use evaluate::{FidelityEvaluator, FidelityOutcome, MAX_RECORDED_GROUPS, MetricFailure, Resources};
pub use matching::{
    MATCHING_FILE, MATCHING_SCHEMA, Matching, MatchingRecord, MatchingSource, REFERENCE_MATCHING_FILE,
    matching_file_for,
};
pub use params::{
    DEFAULT_MAX_CANDIDATE_GROUPS, FidelityMetric, FidelityParams, MatchingMethod, RelationMapping,
};
pub use report::{
    ArchCandidate, AtrSpec, AttributeAssessment, CandidateGroup, CntSpec, FidelityReport, FidelitySummary,
    MappingSource, MappingStatus, MatchingSummary, MetricResult, OarSpec, OorSpec, Participants,
    PredicateResult, RelationMappingInfo, Revote, SpecCount,
};
#[cfg(feature = "render")]
pub use views::RenderedViews;
pub use views::{MemoViews, ObjectViews, ViewKind};
