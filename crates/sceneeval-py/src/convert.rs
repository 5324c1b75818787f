//! Python values to and from the JSON data model, so that dicts given from Python are read by
//! the same serde definitions (and give the same errors) as the JSON of `sceneeval relate` and
//! `eval.json`, and results reach Python as plain dicts, lists, floats and strings.

use numpy::{
    PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde::Serialize;
use serde_json::{Map, Number, Value};

use crate::errors::value_error;

/// `obj` as a JSON value. `what` names it in errors (`target`, `room.floor[2]`). Dicts need
/// string keys; numpy arrays and scalars are read through `tolist()`; NaN and infinite
/// numbers are refused (JSON has none).
///
/// # Errors
/// `ValueError` naming the position of an unsupported value.
pub fn to_json(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Value> {
    if obj.is_none() {
        return Ok(Value::Null);
    }
    if let Ok(b) = obj.cast::<PyBool>() {
        return Ok(Value::Bool(b.is_true()));
    }
    if obj.is_instance_of::<PyInt>() {
        if let Ok(i) = obj.extract::<i64>() {
            return Ok(Value::from(i));
        }
        return Err(value_error(format!("{what} is an integer too large for 64 bits")));
    }
    if let Ok(f) = obj.cast::<PyFloat>() {
        let v = f.value();
        return Number::from_f64(v)
            .map(Value::Number)
            .ok_or_else(|| value_error(format!("{what} is not finite")));
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(Value::String(s.to_cow()?.into_owned()));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut map = Map::new();
        for (k, v) in d.iter() {
            let key = k
                .cast::<PyString>()
                .map_err(|_| value_error(format!("{what} has a key that is not a string: {k}")))?
                .to_cow()?
                .into_owned();
            let inner = to_json(&v, &format!("{what}.{key}"))?;
            map.insert(key, inner);
        }
        return Ok(Value::Object(map));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (i, item) in obj.try_iter()?.enumerate() {
            items.push(to_json(&item?, &format!("{what}[{i}]"))?);
        }
        return Ok(Value::Array(items));
    }
    if obj.hasattr("tolist")? {
        let plain = obj.call_method0("tolist")?;
        if !plain.is(obj) {
            return to_json(&plain, what);
        }
    }
    Err(value_error(format!(
        "{what}: unsupported value of type {}",
        obj.get_type().name()?
    )))
}

/// `value` as plain Python values (through `json.loads`, so numbers round-trip exactly).
///
/// # Errors
/// When `value` cannot be serialised (it always can for this crate's report types).
pub fn to_python<'py>(py: Python<'py>, value: &impl Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("serialising a result: {e}")))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// A float64 numpy array, borrowed for reading. `what` names the argument in errors,
/// `shape_hint` the shape expected (`(N, 7)`).
///
/// # Errors
/// `ValueError` for anything that is not a float64 numpy array.
pub fn float64_array<'py>(
    obj: &Bound<'py, PyAny>,
    what: &str,
    shape_hint: &str,
) -> PyResult<PyReadonlyArrayDyn<'py, f64>> {
    let expected = format!("a numpy float64 array of shape {shape_hint}");
    let array = obj.cast::<PyUntypedArray>().map_err(|_| {
        let type_name = obj
            .get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_else(|_| "?".to_owned());
        value_error(format!(
            "{what} must be {expected}, got a {type_name} (convert with numpy.asarray({what}, dtype=numpy.float64))"
        ))
    })?;
    let dtype = array.dtype();
    if !dtype.is_equiv_to(&numpy::dtype::<f64>(obj.py())) {
        return Err(value_error(format!(
            "{what} must be {expected}, got dtype {dtype} (convert with {what}.astype(numpy.float64))"
        )));
    }
    array
        .cast::<PyArrayDyn<f64>>()
        .map_err(|_| value_error(format!("{what} must be {expected}")))?
        .try_readonly()
        .map_err(|e| value_error(format!("{what}: {e}")))
}

/// `what must be a numpy float64 array of shape {hint}, got shape (3, 6)`.
fn wrong_shape(what: &str, hint: &str, shape: &[usize]) -> PyErr {
    let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
    value_error(format!(
        "{what} must be a numpy float64 array of shape {hint}, got shape ({})",
        dims.join(", ")
    ))
}

/// The array's values in C (row-major) order, `C` at a time: one copy of the buffer when it
/// is C-contiguous.
fn copy_rows<const C: usize>(array: &PyReadonlyArrayDyn<'_, f64>) -> Vec<[f64; C]> {
    let to_row = |row: &[f64]| {
        let mut r = [0.0; C];
        r.copy_from_slice(row);
        r
    };
    if let Ok(flat) = array.as_slice() {
        return flat.chunks_exact(C).map(to_row).collect();
    }
    let view = array.as_array();
    let mut out = Vec::with_capacity(view.len() / C.max(1));
    let mut row = [0.0; C];
    for (i, v) in view.iter().enumerate() {
        row[i % C] = *v;
        if i % C == C - 1 {
            out.push(row);
        }
    }
    out
}

/// The rows of a float64 numpy array of shape `(N, C)`, copied row-major. `what` names the
/// argument in errors.
///
/// # Errors
/// `ValueError` for anything else: not a numpy array, another dtype, another number of
/// dimensions or columns.
pub fn rows<const C: usize>(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[f64; C]>> {
    let hint = format!("(N, {C})");
    let array = float64_array(obj, what, &hint)?;
    let shape = array.shape();
    if shape.len() != 2 || shape[1] != C {
        return Err(wrong_shape(what, &hint, shape));
    }
    Ok(copy_rows(&array))
}

/// The rows of a float64 numpy array of shape `(N, K, C)` (N groups of K rows), copied
/// row-major, with N and K. `hint` is the shape expected as shown in errors.
///
/// # Errors
/// As [`rows`].
pub fn row_groups<const C: usize>(
    obj: &Bound<'_, PyAny>,
    what: &str,
    hint: &str,
) -> PyResult<(Vec<[f64; C]>, usize, usize)> {
    let array = float64_array(obj, what, hint)?;
    let shape = array.shape();
    if shape.len() != 3 || shape[2] != C {
        return Err(wrong_shape(what, hint, shape));
    }
    let (n, k) = (shape[0], shape[1]);
    Ok((copy_rows(&array), n, k))
}
