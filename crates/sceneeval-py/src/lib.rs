//! Python bindings of SceneEval, importable as `sceneeval` (the extension module
//! `sceneeval._sceneeval`, re-exported by `python/sceneeval/__init__.py`).
//!
//! Built with maturin into abi3 wheels for CPython 3.9 and newer:
//! `pip install ./crates/sceneeval-py`. The Python API (documented in
//! `python/sceneeval/_sceneeval.pyi`):
//!
//! - `relation(name, target, anchor=None, *, side, arch, targets, room, reference, **params)`
//!   and `relation_batch(name, targets, anchors=None, *, side, arch, room, reference, grad,
//!   **params)`: the 23 predicates on boxes given as `(cx, cy, cz, hx, hy, hz, yaw)` rows
//!   (numpy float64 arrays of shape `(N, 7)` for the batch form, `(N, K, 7)` for `surround`'s
//!   groups) or as dicts with `sceneeval relate`'s keys; `grad=True` adds the scores'
//!   derivatives with respect to every row ([`relations::grad_pairs`] and its siblings). Both read their input as the facade's
//!   `sceneeval::relate` does and score through the one dispatcher, so they accept exactly
//!   what `relate` accepts and fail with its messages; rooms given as dicts are prepared once
//!   and kept in a `sceneeval::relate::Session` for the process, as `relate` keeps its rooms.
//! - `Scene.from_boxes(boxes, room, *, rooms, ...)`, `load_scene(path, assets={prefix:
//!   folder})`, `Scene.objects` / `rooms` / `info()` / `boxes()` / `set_pose()` /
//!   `set_boxes()` / `plausibility()` / `relation()`.
//! - `evaluate(scenes, *, assets, out, annotations=None, plan=None, preset=None, ...,
//!   vlm=None)`: the keyword arguments (the request's field names) mapped onto the facade's
//!   [`sceneeval::EvaluationRequest`] ([`run`]), as `sceneeval evaluate` maps its flags: the
//!   same plans, run and files; `vlm` (a dict of [`sceneeval::VlmOptions`]' fields, the
//!   `--vlm-*` settings) asks an OpenAI-compatible endpoint. `evaluation_request(...)` gives
//!   the request itself, as `sceneeval evaluate --print-request` prints it.
//! - `compare(runs, *, paired=False, against_first=False, ci=None, alpha=0.05, rank="tested",
//!   failed="skip", ...)` ([`compare`]): `sceneeval compare` through `sceneeval-report`, the
//!   rows as dicts (`paired=True`: the paired differences, Wilcoxon and Holm, McNemar).
//! - `ensemble(runs, out, *, annotations=None)` ([`ensemble`]): `sceneeval ensemble` through
//!   `sceneeval_run::ensemble`, the same run folder; what the command prints as a dict.
//! - `sceneeval.stats` ([`stats`]): Cohen's and Fleiss' kappa, bootstrap intervals, paired
//!   differences with the Wilcoxon test, Holm, McNemar and majority votes from `sceneeval-stats`.
//!
//! Every computation runs with the GIL released; bad arguments raise `ValueError`, files that
//! cannot be read or evaluated raise `sceneeval.SceneEvalError`, with the Rust error's message
//! and causes. The Rust side is usable on its own, which is how the unit tests check it:
//!
//! ```
//! use sceneeval_py::relations::score_pairs;
//! use sceneeval::relations::{Relation, RelationParams};
//! // A 0.2 m lamp resting on a 1 m table: all of it is above the table's top face.
//! let lamp = [[0.0, 0.0, 1.1, 0.1, 0.1, 0.1, 0.0]];
//! let table = [[0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0]];
//! let on_top = score_pairs(Relation::OnTop, &lamp, &table, &RelationParams::default()).unwrap();
//! assert_eq!(on_top, vec![1.0]);
//! ```

pub mod agreement;
pub mod compare;
pub mod convert;
pub mod ensemble;
pub mod errors;
pub mod relations;
pub mod run;
pub mod scene;
pub mod stats;

/// SceneEval's predicates, scenes, plausibility metrics and evaluation, implemented in Rust.
#[pyo3::pymodule]
mod _sceneeval {
    use pyo3::prelude::*;

    #[pymodule_export]
    use crate::agreement::agreement;
    #[pymodule_export]
    use crate::compare::compare;
    #[pymodule_export]
    use crate::ensemble::ensemble;
    #[pymodule_export]
    use crate::errors::SceneEvalError;
    #[pymodule_export]
    use crate::relations::{relation, relation_batch, relation_names, relation_params_py};
    #[pymodule_export]
    use crate::run::{evaluate, evaluation_request};
    #[pymodule_export]
    use crate::scene::{PyScene, load_scene};
    #[pymodule_export]
    use crate::stats::stats;

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        use sceneeval::relations::{OBJECT_ARCH_NAMES, OBJECT_OBJECT_NAMES};
        m.add("OBJECT_OBJECT_RELATIONS", OBJECT_OBJECT_NAMES.to_vec())?;
        m.add("OBJECT_ARCHITECTURE_RELATIONS", OBJECT_ARCH_NAMES.to_vec())?;
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        // The defaults of `vlm=` (the Rust constants, written once; a test checks the
        // docstrings quote them).
        m.add(
            "DEFAULT_VLM_TIMEOUT_SECONDS",
            sceneeval::DEFAULT_VLM_TIMEOUT_SECONDS,
        )?;
        m.add("DEFAULT_VLM_CONCURRENCY", sceneeval::DEFAULT_VLM_CONCURRENCY)?;
        m.add("DEFAULT_RENDER_SIZE", sceneeval::DEFAULT_RENDER_SIZE)?;
        Ok(())
    }
}
