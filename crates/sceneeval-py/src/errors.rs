//! Rust errors as Python exceptions, and computations run without the GIL that never let a
//! panic reach Python.

use std::error::Error;
use std::panic::{AssertUnwindSafe, catch_unwind};

use pyo3::exceptions::{PyDeprecationWarning, PyException, PyRuntimeError, PyUserWarning, PyValueError};
use pyo3::prelude::*;
use sceneeval::EvalError;
use sceneeval::relations::RelationError;

pyo3::create_exception!(
    sceneeval,
    SceneEvalError,
    PyException,
    "A scene, asset, annotation or result file could not be read, evaluated or written. The \
     message names the file and, where it applies, the JSON pointer, the object id or the \
     asset."
);

/// The message of `e` followed by each cause not already part of it, joined by `": "`
/// ([`sceneeval::ErrorChain`], as the CLI prints an error chain).
pub fn chain(e: &(dyn Error + 'static)) -> String {
    sceneeval::ErrorChain::new(e).to_string()
}

/// A `ValueError` for a bad argument.
pub fn value_error(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

/// Issues a Python warning of `category` with `message`, as `warnings.warn(message, category,
/// stacklevel)` does (1: the line that called into the package).
fn warn<T: pyo3::PyTypeInfo>(py: Python<'_>, message: &str, stacklevel: i32) -> PyResult<()> {
    let message = std::ffi::CString::new(message).map_err(|e| value_error(e.to_string()))?;
    PyErr::warn(py, &py.get_type::<T>(), &message, stacklevel)
}

/// Issues a Python `UserWarning` with `message` (a note of the computation: the comparison's,
/// the ensemble's geometry differences, a run's warnings).
pub fn user_warning(py: Python<'_>, message: &str) -> PyResult<()> {
    warn::<PyUserWarning>(py, message, 1)
}

/// Issues a Python `DeprecationWarning` with `message` (an old name, and the one to use),
/// `stacklevel` as `warnings.warn`'s.
pub fn deprecation_warning(py: Python<'_>, message: &str, stacklevel: i32) -> PyResult<()> {
    warn::<PyDeprecationWarning>(py, message, stacklevel)
}

/// A relation query that was wrong: always the caller's argument, so a `ValueError`.
pub fn relation_error(e: &RelationError) -> PyErr {
    value_error(chain(e))
}

/// A `SceneEvalError` carrying `e`'s message and causes.
pub fn scene_error(e: &(dyn Error + 'static)) -> PyErr {
    SceneEvalError::new_err(chain(e))
}

/// An evaluation error: a bad plan or request is a `ValueError` (requests through
/// [`crate::run::request_error`], which names the keyword), anything else a `SceneEvalError`.
pub fn eval_error(e: &EvalError) -> PyErr {
    match e {
        EvalError::Plan { .. } => value_error(chain(e)),
        EvalError::Request { .. } => crate::run::request_error(e),
        other => scene_error(other),
    }
}

/// Runs `f` with the GIL released. A panic (a bug: the library code does not panic on bad
/// input) becomes a `RuntimeError` instead of unwinding into Python.
pub fn detached<T, F>(py: Python<'_>, f: F) -> PyResult<T>
where
    F: FnOnce() -> PyResult<T> + Send,
    T: Send,
{
    py.detach(|| {
        catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|payload| {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown cause".to_owned());
            Err(PyRuntimeError::new_err(format!(
                "internal error in sceneeval (please report it): {what}"
            )))
        })
    })
}
