//! [`FidelityError`]: everything that stops the fidelity metrics of a scene.

use std::path::PathBuf;

use sceneeval_vlm::VlmError;

/// Why the fidelity metrics of a scene could not be computed.
///
/// An invalid or missing VLM answer is not an error (the item is recorded as unanswered and
/// has no verdict unless the missing answer cannot change it); only bad input and a failure
/// to obtain any answer are. [`crate::FidelityEvaluator::evaluate_async`] records each as the
/// failure of the metrics that needed it, never of the others.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FidelityError {
    /// An annotation entry of the scene does not follow its grammar (an unknown quantifier
    /// among others: the reference silently reuses the previous entry's verdict, Q18).
    #[error("annotation row {row:?}, {field}: entry {entry:?} is malformed: {problems}")]
    MalformedEntry {
        /// The annotation row's ID.
        row: String,
        /// The column (`ObjCount`, `ObjAttr`, `OORel`, `OARel`).
        field: &'static str,
        /// The entry text.
        entry: String,
        /// What is wrong, `; `-separated.
        problems: String,
    },
    /// A matching file cannot be read.
    #[error("cannot read the matching file {path}")]
    MatchingFile {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// A matching file is not in the `obj_matching_result.json` shape or does not fit the
    /// scene and its annotation.
    #[error("matching file {path}: {message}")]
    MatchingFormat {
        /// The file.
        path: PathBuf,
        /// What is wrong (with the JSON pointer where there is one).
        message: String,
    },
    /// The matching source needs a VLM (or views) and none is configured.
    #[error("{what} needs {needs}, which is not configured")]
    Unavailable {
        /// What was asked for.
        what: String,
        /// What is missing.
        needs: &'static str,
    },
    /// A VLM request got no answer at all (network, refused key, cache miss in replay).
    #[error("the VLM could not be asked ({task})")]
    Vlm {
        /// The task.
        task: String,
        /// The cause (boxed: it is large).
        #[source]
        source: Box<VlmError>,
    },
    /// An object view could not be made.
    #[error("cannot make the {view} view of object {object:?}")]
    View {
        /// The object id.
        object: String,
        /// The view (`front`, `size`, `surroundings`).
        view: &'static str,
        /// The cause.
        #[source]
        source: Box<dyn std::error::Error + Send + Sync + 'static>,
    },
    /// A predicate could not be evaluated for a spec (a scene without rooms for an
    /// object-architecture relation, an unknown floor id).
    #[error("relation {relation} for {spec:?}")]
    Relation {
        /// The spec text.
        spec: String,
        /// The relation.
        relation: String,
        /// The cause.
        #[source]
        source: sceneeval_relations::RelationError,
    },
    /// The parameters are invalid.
    #[error("fidelity parameter {name}: {message}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A file could not be written.
    #[error("cannot write {path}")]
    Write {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
}
