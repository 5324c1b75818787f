//! Compare finished SceneEval runs and look at one: paper tables across methods, and a
//! browsable static report of a run.
//!
//! Everything here reads what a run wrote (`<scene>/eval.json`, `summary_scenes.csv`, the view
//! and diagnostic images) through the result types of `sceneeval-results`
//! ([`sceneeval_results::SceneRecord`], [`sceneeval_results::Summary`]), every section of a
//! record included (stability too, without the simulation); nothing is evaluated again.
//!
//! - [`Run`]: a run folder's records and the difficulty of each scene.
//! - [`compare()`]: the runs side by side on what they share ([`Comparison`]), with ranks and
//!   rank points, written as Markdown, CSV, LaTeX (booktabs) or HTML.
//! - [`write_report`]: a folder with `index.html` (the run's table per difficulty, SVG charts,
//!   the scenes sortable and filterable by the metric they fail) and a page per scene (an SVG
//!   top view coloured by what is wrong with each object, the evidence of every metric and
//!   fidelity spec, the images the run wrote), opened from disk with no server or network.
//!
//! - [`labels`]: human verdicts on a run's specs (label files), and [`agreement()`]: how far a
//!   judge agrees with people (Cohen's and Fleiss' kappa with bootstrap intervals) as
//!   Markdown, CSV, LaTeX or JSON (`docs/judge.md`).
//!
//! The formats are described in `docs/formats.md` ("Comparison tables", "The static report").
//!
//! Every string that reaches a file is escaped for its language ([`escape`]), and every file is
//! written through [`sceneeval_files::write_atomic`].
//!
//! # Example
//! ```
//! use sceneeval_eval::{Evaluator, EvaluationPlan, SceneInputs};
//! use sceneeval_results::{SceneName, SceneRecord};
//! use sceneeval_scene::{Category, RoomBuilder, Scene};
//! use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
//! use sceneeval_report::{CompareOptions, Run, compare};
//!
//! // One scene, evaluated twice: once with the bed inside the room, once half outside.
//! let record = |x: f64| {
//!     let scene = Scene::builder()
//!         .name("scene_0")
//!         .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0)))
//!         .add_box("bed", Category::new("bed"), Vector3::new(0.8, 1.0, 0.25),
//!                  pose_from_yaw(Point3::new(x, 2.5, 0.25), 0.0))
//!         .build()
//!         .unwrap();
//!     let evaluator = Evaluator::new(EvaluationPlan::geometry_only()).unwrap();
//!     let report = evaluator.evaluate_scene(&scene, &SceneInputs::default()).unwrap().report;
//!     SceneRecord::ok(SceneName::new("scene_0"), report)
//! };
//! let a = Run::from_records("inside", "runs/a", vec![record(2.0)]);
//! let b = Run::from_records("outside", "runs/b", vec![record(4.0)]);
//! let table = compare(&[a, b], &CompareOptions::default()).unwrap();
//! let md = table.to_markdown();
//! // OOB: lower is better; the run with the bed inside has 0 % and is bold.
//! assert!(md.contains("OOB ↓"), "{md}");
//! assert!(md.contains("| inside |"), "{md}");
//! assert!(table.to_latex().contains("\\textbf{0.00}"));
//! ```

pub mod agreement;
mod assets;
pub mod compare;
mod error;
pub mod escape;
mod html;
pub mod judge;
pub mod label_writer;
pub mod labels;
mod report;
mod run;
mod within;

pub use agreement::{Agreement, AgreementError, AgreementOptions, AgreementRow, Source, agreement};
pub use assets::recorded_assets;
pub use compare::{CompareOptions, Comparison, compare};
pub use error::ReportError;
pub use html::topview::{OUTLINE, outlined as outlined_top_view};
pub use report::{
    DEFAULT_DIR, FILES_DIR, INDEX, NoTopView, RecordedScenes, ReportOptions, SCENES_DIR, Written,
    write_report,
};
pub use run::{Description, Run, Unreadable, metrics_in, scene_values, summary_columns};
