//! The 23 predicates from Python: one query (`relation`) and the vectorised form over numpy
//! arrays of boxes (`relation_batch`). Boxes and rooms are read as the facade's
//! `sceneeval::relate` reads them (`BoxSpec`, `sceneeval::scene::RoomSpec`), rooms are kept
//! prepared in one `sceneeval::relate::Session` for the process, and every score goes through
//! the one dispatcher (`sceneeval::relations::score`), so they accept the inputs and give the
//! errors of `sceneeval relate`.

use std::sync::{Arc, LazyLock, Mutex, PoisonError};

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use sceneeval::geom::Obb;
use sceneeval::io::AssetLibrary;
use sceneeval::relate::{BoxSpec, Session, from_value, under};
use sceneeval::relations::grad::{self, BoxGrad};
use sceneeval::relations::{
    self as rel, ObjectGeom, Operands, Relation, RelationError, RelationKind, RelationParams, Targets, batch,
};
use sceneeval::scene::{Room, RoomSpec};

use crate::convert::{row_groups, rows, to_json};
use crate::errors::{chain, deprecation_warning, detached, relation_error, value_error};

/// The columns of a box row: centre x, y, z, half extents x, y, z, yaw.
pub const BOX_COLUMNS: usize = 7;

/// A box from its row `(cx, cy, cz, hx, hy, hz, yaw)`.
pub fn box_spec_from_row(row: &[f64; BOX_COLUMNS]) -> BoxSpec {
    BoxSpec::from_yaw([row[0], row[1], row[2]], [row[3], row[4], row[5]], row[6])
}

/// The oriented boxes of `rows`; a bad row is named `what[i]` in the error
/// (`targets[3].center is not finite`).
///
/// ```
/// use sceneeval_py::relations::obbs_from_rows;
/// let boxes = obbs_from_rows(&[[0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0]], "targets").unwrap();
/// assert_eq!(boxes[0].half_extents.x, 0.5);
/// let err = obbs_from_rows(&[[0.0; 7], [f64::NAN, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0]], "targets").unwrap_err();
/// assert_eq!(err.to_string(), "targets[1].center is not finite");
/// ```
///
/// # Errors
/// The error of [`BoxSpec::to_obb`] for the first bad row.
pub fn obbs_from_rows(rows: &[[f64; BOX_COLUMNS]], what: &str) -> Result<Vec<Obb>, RelationError> {
    let mut out = Vec::with_capacity(rows.len());
    obbs_into(rows, what, 0, &mut out)?;
    Ok(out)
}

/// The oriented box of the row `(cx, cy, cz, hx, hy, hz, yaw)`: the box
/// [`BoxSpec::to_obb`] makes of [`box_spec_from_row`], and its error with the box named by
/// `name()` (called only for a bad row, so a good row allocates nothing).
///
/// # Errors
/// As [`BoxSpec::to_obb`].
#[inline]
pub fn obb_from_row(row: &[f64; BOX_COLUMNS], name: impl FnOnce() -> String) -> Result<Obb, RelationError> {
    BoxSpec::yaw_obb([row[0], row[1], row[2]], [row[3], row[4], row[5]], row[6], name)
}

/// Replaces the content of `out` with the oriented boxes of `rows`, whose first row is row
/// `first` of the caller's array (for the error's index).
fn obbs_into(
    rows: &[[f64; BOX_COLUMNS]],
    what: &str,
    first: usize,
    out: &mut Vec<Obb>,
) -> Result<(), RelationError> {
    out.clear();
    for (i, row) in rows.iter().enumerate() {
        out.push(obb_from_row(row, || format!("{what}[{}]", first + i))?);
    }
    Ok(())
}

/// Rows scored per chunk by the batch forms: the boxes of a chunk are built into buffers
/// reused from chunk to chunk, so memory stays small and in cache whatever the batch size.
const CHUNK: usize = 1024;

/// A box given from Python: a sequence of seven numbers or a dict with `relate`'s keys
/// (`center`, `half_size`, and `yaw` or `rotation`). A room, or a list of boxes, given where a
/// box belongs is told where it goes.
pub fn box_spec(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<BoxSpec> {
    if obj.is_instance_of::<PyDict>() {
        let value = to_json(obj, what)?;
        if value.get("floor").is_some() && value.get("center").is_none() {
            return Err(value_error(format!(
                "{what} is a room (a dict with \"floor\"), not a box: give a room as room=, as in \
                 relation(\"against_wall\", target, room=room)"
            )));
        }
        return from_value(value).map_err(|(path, e)| value_error(format!("{}: {e}", under(what, &path))));
    }
    let wrong = || {
        let list_of_boxes = (obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>())
            && obj.get_item(0).is_ok_and(|first| {
                first.is_instance_of::<PyDict>()
                    || first.is_instance_of::<PyList>()
                    || first.is_instance_of::<PyTuple>()
                    || first.hasattr("__len__").unwrap_or(false)
            });
        if list_of_boxes {
            return value_error(format!(
                "{what} is a list of boxes, not a box: surround takes its boxes as targets=[...] (with target \
                 None), as in relation(\"surround\", None, anchor, targets=boxes)"
            ));
        }
        value_error(format!(
            "{what} must be a sequence of 7 numbers (cx, cy, cz, hx, hy, hz, yaw) or a dict with the keys \
             center, half_size and yaw or rotation"
        ))
    };
    let numbers: Vec<f64> = obj.extract().map_err(|_| wrong())?;
    let row: [f64; BOX_COLUMNS] = numbers.try_into().map_err(|_| wrong())?;
    Ok(box_spec_from_row(&row))
}

/// A room given from Python: a dict with `relate`'s room keys (`floor`, `floor_z`, `height`,
/// `wall_thickness`, `openings`). `what` names it in errors (`room`, `rooms[2]`).
pub fn room_spec(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<RoomSpec> {
    room_json(obj, what).and_then(|value| room_from_json(value, what))
}

/// The room dict as JSON, checked to be a dict (and not a box).
fn room_json(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<serde_json::Value> {
    let expected = "a dict with the keys floor (a list of [x, y] points) and optionally floor_z, height, \
                    wall_thickness, openings";
    if !obj.is_instance_of::<PyDict>() {
        let is_box = obj.extract::<Vec<f64>>().is_ok_and(|n| n.len() == BOX_COLUMNS);
        return Err(value_error(if is_box {
            format!("{what} is a box (7 numbers), not a room: a room is {expected}")
        } else {
            format!("{what} must be {expected}")
        }));
    }
    let value = to_json(obj, what)?;
    if value.get("floor").is_none()
        && let Some(key) = ["center", "half_size"]
            .into_iter()
            .find(|k| value.get(k).is_some())
    {
        return Err(value_error(format!(
            "{what} is a box (a dict with \"{key}\"), not a room: a room is {expected}"
        )));
    }
    Ok(value)
}

/// The room of a room dict's JSON value; an error names the key at fault
/// (`room.floor[2]: ...`).
pub fn room_from_json(value: serde_json::Value, what: &str) -> PyResult<RoomSpec> {
    from_value(value).map_err(|(path, e)| value_error(format!("{}: {e}", under(what, &path))))
}

/// How many rooms given as dicts stay prepared at once (see [`RoomArg::prepare`]).
pub const ROOMS_KEPT: usize = 64;

/// The session of the process: the rooms given as dicts to `relation` and `relation_batch`,
/// prepared and kept by the JSON text of the dict, as `sceneeval relate` keeps its rooms
/// written in place.
static SESSION: LazyLock<Mutex<Session>> = LazyLock::new(|| {
    Mutex::new(Session::new(
        RelationParams::default(),
        AssetLibrary::new(),
        ROOMS_KEPT,
    ))
});

/// A room dict as read while the GIL is held: its JSON value and text (the key it is kept
/// under).
#[derive(Debug)]
pub struct RoomArg {
    key: String,
    value: serde_json::Value,
}

/// The room dict `obj`, read (see [`room_spec`] for the keys) but not yet prepared.
///
/// # Errors
/// `ValueError` for anything but a room dict.
pub fn room_arg(obj: &Bound<'_, PyAny>) -> PyResult<RoomArg> {
    let value = room_json(obj, "room")?;
    let key = serde_json::to_string(&value).map_err(|e| value_error(format!("room: {e}")))?;
    Ok(RoomArg { key, value })
}

impl RoomArg {
    /// The prepared room: one of the last [`ROOMS_KEPT`] distinct rooms given, found by the
    /// dict's JSON text, or else read and prepared (walls cut around their openings, the
    /// floor triangulated) and kept in `session`. Call it with the GIL released.
    ///
    /// # Errors
    /// `ValueError` for a dict that is not a valid room, with `relate`'s message.
    pub fn prepare_in(self, session: &Mutex<Session>) -> PyResult<Arc<Room>> {
        let RoomArg { key, value } = self;
        session
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .room_with(&key, || {
                room_from_json(value, "room")?
                    .build()
                    .map_err(|e| value_error(chain(&e)))
            })
    }

    /// [`RoomArg::prepare_in`] the process's session.
    ///
    /// # Errors
    /// As [`RoomArg::prepare_in`].
    pub fn prepare(self) -> PyResult<Arc<Room>> {
        self.prepare_in(&SESSION)
    }
}

/// The predicates' parameters: the defaults (or the reference's with `reference`), then each
/// keyword argument by its field name in `RelationParams` (`side_of_margin=0.3`,
/// `near=(0.4, 1.2, 0.2)` or `near={"min_m": 0.4, "max_m": 1.2, "sigma_m": 0.2}`,
/// `on_top_plane="centre_plane"`), validated. A name a plan file used before the unit-suffix
/// rule (`middle_of_sigma`, `near={"min": ...}`) is read as its new one, as in a plan file
/// (`sceneeval::eval::RENAMED_KEYS`), with a `DeprecationWarning` naming the new one.
pub fn relation_params(reference: bool, overrides: Option<&Bound<'_, PyDict>>) -> PyResult<RelationParams> {
    let base = if reference {
        RelationParams::reference()
    } else {
        RelationParams::default()
    };
    let Some(overrides) = overrides.filter(|d| !d.is_empty()) else {
        return Ok(base);
    };
    let mut value = serde_json::to_value(base).map_err(|e| value_error(e.to_string()))?;
    if let (serde_json::Value::Object(fields), serde_json::Value::Object(given)) =
        (&mut value, to_json(overrides.as_any(), "parameter")?)
    {
        for (name, v) in renamed_read(overrides.py(), given)? {
            if !fields.contains_key(&name) {
                return Err(value_error(format!(
                    "unknown parameter {name:?}: see sceneeval.relation_params() for the names"
                )));
            }
            fields.insert(name, v);
        }
    }
    let params: RelationParams =
        serde_json::from_value(value).map_err(|e| value_error(format!("parameters: {e}")))?;
    params.validate().map_err(|e| relation_error(&e))?;
    Ok(params)
}

/// `given` (keyword arguments of [`relation_params`]) with the names of plans written before
/// the unit-suffix rule read as the new ones, each with a `DeprecationWarning`.
fn renamed_read(
    py: Python<'_>,
    given: serde_json::Map<String, serde_json::Value>,
) -> PyResult<serde_json::Map<String, serde_json::Value>> {
    const AT: &str = "params.relations.";
    let mut plan = serde_json::Map::new();
    plan.insert(
        "params".into(),
        serde_json::json!({"relations": serde_json::Value::Object(given)}),
    );
    let renamed = sceneeval::eval::read_renamed_keys(&mut plan).map_err(|e| {
        value_error(match e {
            sceneeval::eval::EvalError::Plan { message, .. } => message.replace(AT, ""),
            other => other.to_string(),
        })
    })?;
    for (old, new) in renamed {
        let (old, new) = (old.trim_start_matches(AT), new.trim_start_matches(AT));
        deprecation_warning(
            py,
            &format!("{old} is deprecated: write {new} (the unit-suffix rule)"),
            1,
        )?;
    }
    match plan.remove("params") {
        Some(serde_json::Value::Object(mut params)) => match params.remove("relations") {
            Some(serde_json::Value::Object(given)) => Ok(given),
            _ => Ok(serde_json::Map::new()),
        },
        _ => Ok(serde_json::Map::new()),
    }
}

/// The score in [0, 1] of one spatial relation (it holds when the score is above 0.5).
///
/// name: one of the 23 relations (see relation_names()); side_of, side_region and
/// long_short_side_of take side= (left, right, front, back, top, bottom; long or short),
/// the distance relations next_to, near, across_from and far take arch= (wall, door, window)
/// to relate an object to the room. The name may carry its argument: "side_of(left)".
///
/// Object-object relations score target relative to anchor; surround scores targets=[...]
/// around anchor (target is None); object-architecture relations score target in room.
/// A box is (cx, cy, cz, hx, hy, hz, yaw) in metres and radians (yaw 0: front faces -y) or a
/// dict with the keys of `sceneeval relate` (center, half_size, yaw or rotation); a room is a
/// dict with its room keys (floor, floor_z, height, wall_thickness, openings). A room is
/// prepared (walls cut around their openings, floor triangulated) once and kept, with the
/// last 64 distinct rooms given (found by their content), so a loop asking about one room
/// prepares it once; relation_batch shares these rooms.
///
/// reference=True selects every reference-parity switch (RelationParams::reference);
/// any other keyword sets one parameter by its name in relation_params(), e.g.
/// side_of_margin=0.3 or near=(0.4, 1.2, 0.2) (min_m, max_m, sigma_m).
///
/// Raises ValueError for an unknown name, a missing or extra operand or argument, a NaN or
/// infinite number, or a bad parameter, with the message `sceneeval relate` gives.
#[pyfunction]
#[pyo3(signature = (name, target, anchor=None, *, side=None, arch=None, targets=None, room=None, reference=false, **params))]
#[allow(clippy::too_many_arguments)] // The Python signature is fixed by issue 15.
pub fn relation(
    py: Python<'_>,
    name: &str,
    target: Option<&Bound<'_, PyAny>>,
    anchor: Option<&Bound<'_, PyAny>>,
    side: Option<&str>,
    arch: Option<&str>,
    targets: Option<&Bound<'_, PyAny>>,
    room: Option<&Bound<'_, PyAny>>,
    reference: bool,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<f64> {
    let relation = Relation::from_fields(name, side, arch).map_err(|e| relation_error(&e))?;
    let params = relation_params(reference, params)?;
    let target = target.map(|t| box_spec(t, "target")).transpose()?;
    let anchor = anchor.map(|a| box_spec(a, "anchor")).transpose()?;
    let targets = match targets {
        None => None,
        Some(list) => {
            let mut specs = Vec::new();
            for (i, item) in list.try_iter()?.enumerate() {
                specs.push(box_spec(&item?, &format!("targets[{i}]"))?);
            }
            Some(specs)
        }
    };
    // The boxes are checked, then the room.
    let obb = |spec: &BoxSpec, what: &str| spec.to_obb(what).map_err(|e| relation_error(&e));
    let target = target.map(|b| obb(&b, "target")).transpose()?;
    let anchor = anchor.map(|b| obb(&b, "anchor")).transpose()?;
    let targets = targets
        .map(|ts| {
            ts.iter()
                .enumerate()
                .map(|(i, b)| obb(b, &format!("targets[{i}]")))
                .collect::<PyResult<Vec<Obb>>>()
        })
        .transpose()?;
    let room = room.map(room_arg).transpose()?;
    detached(py, || {
        let room = room.map(RoomArg::prepare).transpose()?;
        let views: Option<Vec<ObjectGeom<'_>>> = targets
            .as_ref()
            .map(|ts| ts.iter().map(ObjectGeom::from_box).collect());
        let operands = Operands {
            target: target.as_ref().map(ObjectGeom::from_box),
            anchor: anchor.as_ref().map(ObjectGeom::from_box),
            targets: views.as_deref().map(Targets::Objects),
            rooms: room.as_deref().map(std::slice::from_ref),
        };
        rel::score(relation, &operands, &params).map_err(|e| relation_error(&e))
    })
}

/// The scores of one relation for N boxes (or N groups of boxes), as a float64 array of
/// shape (N,).
///
/// targets: a float64 array of shape (N, 7), one box (cx, cy, cz, hx, hy, hz, yaw) per row.
/// Object-object relations take anchors of shape (N, 7) (row i is the anchor of target i)
/// or (1, 7) (one anchor for every target); object-architecture relations take room (a dict
/// as for relation()) instead. surround takes N groups of K targets, targets of shape
/// (N, K, 7), and anchors of shape (N, 7) or (1, 7): score i is surround of the K boxes
/// of group i around anchor i. name, side, arch, reference and the parameter keywords are as
/// for relation().
///
/// The scores equal relation() called row by row (group by group for surround). Computed
/// with the GIL released.
///
/// grad=True returns the scores with their gradients, (scores, d_targets, d_anchors):
/// ``d_targets[i]`` and ``d_anchors[i]`` are the derivatives of score i with respect to the seven
/// numbers of its target and anchor rows, in the rows' order (cx, cy, cz, hx, hy, hz, yaw),
/// float64 arrays of shape (N, 7) (d_targets (N, K, 7) for surround; d_anchors has one row
/// per score also when one anchor row is shared: sum it for that row's gradient).
/// Object-architecture relations (room=) return (scores, d_targets): the room is fixed. The
/// scores are those of grad=False, bit for bit; the derivatives are exact where the score is
/// differentiable and one-sided at its kinks (see sceneeval_relations::grad in the Rust
/// documentation).
///
/// Raises ValueError when an array is not a float64 numpy array of the right shape, holds a
/// NaN or infinite number, or when the relation or its arguments are wrong.
#[pyfunction]
#[pyo3(signature = (name, targets, anchors=None, *, side=None, arch=None, room=None, reference=false, grad=false, **params))]
#[allow(clippy::too_many_arguments)] // The Python signature is fixed by issues 15 and 27.
pub fn relation_batch<'py>(
    py: Python<'py>,
    name: &str,
    targets: &Bound<'py, PyAny>,
    anchors: Option<&Bound<'py, PyAny>>,
    side: Option<&str>,
    arch: Option<&str>,
    room: Option<&Bound<'py, PyAny>>,
    reference: bool,
    grad: bool,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let relation = Relation::from_fields(name, side, arch).map_err(|e| relation_error(&e))?;
    let params = relation_params(reference, params)?;
    let kind = relation.kind();
    if kind != RelationKind::ObjectArchitecture && room.is_some() {
        return Err(value_error(format!(
            "relation {relation} relates objects to each other: give anchors, not room"
        )));
    }
    if kind == RelationKind::ObjectArchitecture && anchors.is_some() {
        return Err(value_error(format!(
            "relation {relation} relates objects to the room: give room, not anchors"
        )));
    }
    let anchors_of = |expected: usize| -> PyResult<Vec<[f64; BOX_COLUMNS]>> {
        let anchors = anchors.ok_or_else(|| {
            value_error(format!(
                "relation {relation} needs anchors: a float64 array of shape (N, 7) or (1, 7)"
            ))
        })?;
        let anchor_rows = rows::<BOX_COLUMNS>(anchors, "anchors")?;
        if anchor_rows.len() != expected && anchor_rows.len() != 1 {
            let per = if kind == RelationKind::MultiTarget {
                "one per group of targets"
            } else {
                "one per target"
            };
            return Err(value_error(format!(
                "anchors has {} rows: expected {expected} ({per}) or 1 (the same anchor for every {})",
                anchor_rows.len(),
                if kind == RelationKind::MultiTarget {
                    "group"
                } else {
                    "target"
                },
            )));
        }
        Ok(anchor_rows)
    };
    let err = |e: RelationError| relation_error(&e);
    match kind {
        RelationKind::ObjectObject => {
            let target_rows = rows::<BOX_COLUMNS>(targets, "targets")?;
            let anchor_rows = anchors_of(target_rows.len())?;
            if grad {
                let g = detached(py, || {
                    grad_pairs(relation, &target_rows, &anchor_rows, &params).map_err(err)
                })?;
                return g.into_python(py, &[target_rows.len()]);
            }
            let scores = detached(py, || {
                score_pairs(relation, &target_rows, &anchor_rows, &params).map_err(err)
            })?;
            Ok(PyArray1::from_vec(py, scores).into_any())
        }
        RelationKind::MultiTarget => {
            let (target_rows, n, k) = row_groups::<BOX_COLUMNS>(
                targets,
                "targets",
                &format!("(N, K, 7) for {relation} (N groups of K targets)"),
            )?;
            let anchor_rows = anchors_of(n)?;
            if grad {
                let g = detached(py, || {
                    grad_groups(relation, &target_rows, n, &anchor_rows, &params).map_err(err)
                })?;
                return g.into_python(py, &[n, k]);
            }
            let scores = detached(py, || {
                score_groups(relation, &target_rows, n, &anchor_rows, &params).map_err(err)
            })?;
            Ok(PyArray1::from_vec(py, scores).into_any())
        }
        RelationKind::ObjectArchitecture => {
            let target_rows = rows::<BOX_COLUMNS>(targets, "targets")?;
            let room = room.ok_or_else(|| {
                value_error(format!(
                    "relation {relation} needs room: a dict with relate's room keys (floor, ...)"
                ))
            })?;
            let room = room_arg(room)?;
            if grad {
                let g = detached(py, || {
                    let room = room.prepare()?;
                    grad_in_room(relation, &target_rows, &room, &params).map_err(err)
                })?;
                return g.into_python(py, &[target_rows.len()]);
            }
            let scores = detached(py, || {
                let room = room.prepare()?;
                score_in_room(relation, &target_rows, &room, &params).map_err(err)
            })?;
            Ok(PyArray1::from_vec(py, scores).into_any())
        }
    }
}

/// Scores with their gradients, as `relation_batch(..., grad=True)` returns them: per score
/// the derivatives with respect to the seven numbers of its target row(s) and of its anchor
/// row, in the rows' order `(cx, cy, cz, hx, hy, hz, yaw)` ([`BoxGrad::to_array`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BatchGradient {
    /// The scores, bit for bit those of the score forms ([`score_pairs`], ...).
    pub scores: Vec<f64>,
    /// With respect to each target row, in the order of the rows (`surround`: group by group).
    pub d_targets: Vec<[f64; BOX_COLUMNS]>,
    /// With respect to each score's anchor row, one per score (also when the anchor row is
    /// shared); `None` for object-architecture relations (the room is fixed).
    pub d_anchors: Option<Vec<[f64; BOX_COLUMNS]>>,
}

impl BatchGradient {
    fn with_capacity(scores: usize, targets: usize, anchors: bool) -> Self {
        BatchGradient {
            scores: Vec::with_capacity(scores),
            d_targets: Vec::with_capacity(targets),
            d_anchors: anchors.then(|| Vec::with_capacity(scores)),
        }
    }

    /// The Python tuple `(scores, d_targets, d_anchors)`, or `(scores, d_targets)` without
    /// anchors; `d_targets` has the shape `targets` followed by 7.
    fn into_python<'py>(self, py: Python<'py>, targets: &[usize]) -> PyResult<Bound<'py, PyAny>> {
        let n = self.scores.len();
        let scores = PyArray1::from_vec(py, self.scores).into_any();
        let shape: Vec<usize> = targets.iter().copied().chain([BOX_COLUMNS]).collect();
        let d_targets = PyArray1::from_vec(py, self.d_targets.into_flattened())
            .reshape(shape)?
            .into_any();
        match self.d_anchors {
            None => Ok(PyTuple::new(py, [scores, d_targets])?.into_any()),
            Some(d) => {
                let d_anchors = PyArray1::from_vec(py, d.into_flattened())
                    .reshape([n, BOX_COLUMNS])?
                    .into_any();
                Ok(PyTuple::new(py, [scores, d_targets, d_anchors])?.into_any())
            }
        }
    }
}

/// [`score_pairs`] with the gradients of the scores ([`grad::pair`]).
///
/// ```
/// use sceneeval_py::relations::grad_pairs;
/// use sceneeval::relations::{Relation, RelationParams};
/// // A 0.5 m cube half sunk into a 1 m table (z from 0.75 to 1.25; on_top's plane is the top
/// // face, z = 1, moved out by its 1e-6 m tolerance): (1.25 - 0.999999) / 0.5 of it is above.
/// // Raising it by dz raises that share by dz / 0.5: d score / d cz = 2; lowering the table
/// // raises it alike (d / d anchor cz = -2).
/// let cube = [[0.0, 0.0, 1.0, 0.25, 0.25, 0.25, 0.0]];
/// let table = [[0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0]];
/// let g = grad_pairs(Relation::OnTop, &cube, &table, &RelationParams::default()).unwrap();
/// assert!((g.scores[0] - 0.500002).abs() < 1e-9);
/// assert!((g.d_targets[0][2] - 2.0).abs() < 1e-9);
/// assert!((g.d_anchors.unwrap()[0][2] + 2.0).abs() < 1e-9);
/// ```
///
/// # Errors
/// As [`score_pairs`]; anchor rows that are neither one nor one per target are a
/// [`RelationError::LengthMismatch`].
pub fn grad_pairs(
    relation: Relation,
    target_rows: &[[f64; BOX_COLUMNS]],
    anchor_rows: &[[f64; BOX_COLUMNS]],
    params: &RelationParams,
) -> Result<BatchGradient, RelationError> {
    let n = target_rows.len();
    let shared = match anchor_rows {
        [only] if n != 1 => Some(obb_from_row(only, || "anchors[0]".to_owned())?),
        _ if anchor_rows.len() == n => None,
        _ => {
            return Err(RelationError::LengthMismatch {
                what: "anchors",
                got: anchor_rows.len(),
                expected: n,
            });
        }
    };
    let mut out = BatchGradient::with_capacity(n, n, true);
    let d_anchors = out.d_anchors.get_or_insert_default();
    for (i, row) in target_rows.iter().enumerate() {
        let target = obb_from_row(row, || format!("targets[{i}]"))?;
        let anchor = match shared {
            Some(anchor) => anchor,
            None => obb_from_row(&anchor_rows[i], || format!("anchors[{i}]"))?,
        };
        let g = grad::pair(
            relation,
            &ObjectGeom::from_box(&target),
            &ObjectGeom::from_box(&anchor),
            params,
        )?;
        out.scores.push(g.score);
        out.d_targets.push(g.target.to_array());
        d_anchors.push(g.anchor.to_array());
    }
    Ok(out)
}

/// [`score_in_room`] with the gradients of the scores with respect to the targets
/// ([`grad::arch_rooms`]).
///
/// # Errors
/// As [`score_in_room`].
pub fn grad_in_room(
    relation: Relation,
    target_rows: &[[f64; BOX_COLUMNS]],
    room: &Room,
    params: &RelationParams,
) -> Result<BatchGradient, RelationError> {
    let n = target_rows.len();
    let mut out = BatchGradient::with_capacity(n, n, false);
    let rooms = std::slice::from_ref(room);
    for (i, row) in target_rows.iter().enumerate() {
        let target = obb_from_row(row, || format!("targets[{i}]"))?;
        let g = grad::arch_rooms(relation, &ObjectGeom::from_box(&target), rooms, params)?;
        out.scores.push(g.score);
        out.d_targets.push(g.target.to_array());
    }
    Ok(out)
}

/// `out[i]` = the relation of target row i to anchor row i (or to the only anchor row).
///
/// ```
/// use sceneeval_py::relations::score_pairs;
/// use sceneeval::relations::{Relation, RelationParams};
/// // Two unit cubes 1.3 m apart centre to centre: a 0.3 m gap, inside next_to's [0, 0.5] m.
/// let targets = [[0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0], [9.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0]];
/// let anchor = [[1.3, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0]];
/// let scores = score_pairs(Relation::NextTo, &targets, &anchor,
/// &RelationParams::default()).unwrap();
/// assert_eq!(scores[0], 1.0);
/// // 9 - 1.3 - 1 = 6.7 m apart: 6.2 m beyond the band, exp(-6.2^2 / (2 * 0.25^2)) = exp(-307.52).
/// assert!((scores[1] / (-307.52f64).exp() - 1.0).abs() < 1e-9);
/// ```
///
/// # Errors
/// [`RelationError`] for a bad row (named by its index) or a relation that is not
/// object-object.
pub fn score_pairs(
    relation: Relation,
    target_rows: &[[f64; BOX_COLUMNS]],
    anchor_rows: &[[f64; BOX_COLUMNS]],
    params: &RelationParams,
) -> Result<Vec<f64>, RelationError> {
    let mut out = vec![0.0; target_rows.len()];
    let (mut targets, mut anchors) = (Vec::with_capacity(CHUNK), Vec::with_capacity(CHUNK));
    let broadcast = anchor_rows.len() == 1 && target_rows.len() != 1;
    if broadcast {
        obbs_into(anchor_rows, "anchors", 0, &mut anchors)?;
    }
    for (k, (chunk, out)) in target_rows.chunks(CHUNK).zip(out.chunks_mut(CHUNK)).enumerate() {
        let first = k * CHUNK;
        obbs_into(chunk, "targets", first, &mut targets)?;
        if broadcast {
            let anchor = ObjectGeom::from_box(&anchors[0]);
            for (t, o) in targets.iter().zip(out.iter_mut()) {
                *o = batch::score_pair(relation, &ObjectGeom::from_box(t), &anchor, params)?;
            }
        } else {
            let rows = anchor_rows
                .get(first..first + chunk.len())
                .ok_or(RelationError::LengthMismatch {
                    what: "anchors",
                    got: anchor_rows.len(),
                    expected: target_rows.len(),
                })?;
            obbs_into(rows, "anchors", first, &mut anchors)?;
            for ((t, a), o) in targets.iter().zip(&anchors).zip(out.iter_mut()) {
                *o = batch::score_pair(
                    relation,
                    &ObjectGeom::from_box(t),
                    &ObjectGeom::from_box(a),
                    params,
                )?;
            }
        }
    }
    Ok(out)
}

/// `out[i]` = the object-architecture relation of target row i in `room`.
///
/// # Errors
/// [`RelationError`] for a bad row, or a relation that is not object-architecture.
pub fn score_in_room(
    relation: Relation,
    target_rows: &[[f64; BOX_COLUMNS]],
    room: &Room,
    params: &RelationParams,
) -> Result<Vec<f64>, RelationError> {
    let mut out = vec![0.0; target_rows.len()];
    let mut targets = Vec::with_capacity(CHUNK);
    for (k, (chunk, out)) in target_rows.chunks(CHUNK).zip(out.chunks_mut(CHUNK)).enumerate() {
        obbs_into(chunk, "targets", k * CHUNK, &mut targets)?;
        // One small allocation per chunk of 1024 rows.
        let views: Vec<ObjectGeom<'_>> = targets.iter().map(ObjectGeom::from_box).collect();
        batch::score_objects_in_rooms(relation, &views, std::slice::from_ref(room), params, out)?;
    }
    Ok(out)
}

/// `out[i]` = the multi-target relation (`surround`) of group i of `target_rows` (`groups`
/// groups of equally many rows, in order) around anchor row i, or around the only anchor row.
///
/// ```
/// use sceneeval_py::relations::score_groups;
/// use sceneeval::relations::{Relation, RelationParams};
/// let chair = |x: f64, y: f64| [x, y, 0.4, 0.25, 0.25, 0.4, 0.0];
/// // Four chairs 1 m from the table at 90-degree gaps: score 1. Four chairs at one place:
/// // equal distances (distance terms 1, weight 0.5) but every gap is 0 against the ideal 90
/// // degrees (angle terms 0, weight 0.5): 0.5.
/// let targets = [chair(1.0, 0.0), chair(0.0, 1.0), chair(-1.0, 0.0), chair(0.0, -1.0),
///                chair(1.0, 0.0), chair(1.0, 0.0), chair(1.0, 0.0), chair(1.0, 0.0)];
/// let table = [[0.0, 0.0, 0.4, 0.5, 0.5, 0.4, 0.0]];
/// let scores = score_groups(Relation::Surround, &targets, 2, &table, &RelationParams::default()).unwrap();
/// assert_eq!(scores, vec![1.0, 0.5]);
/// ```
///
/// # Errors
/// [`RelationError`] for a bad row (named `targets[i][j]` or `anchors[i]`), rows that do not
/// split into `groups` groups or anchors that are neither one nor one per group, a relation
/// that is not multi-target, or too many targets for the reference `surround`.
pub fn score_groups(
    relation: Relation,
    target_rows: &[[f64; BOX_COLUMNS]],
    groups: usize,
    anchor_rows: &[[f64; BOX_COLUMNS]],
    params: &RelationParams,
) -> Result<Vec<f64>, RelationError> {
    let mut out = Vec::with_capacity(groups);
    each_group(relation, target_rows, groups, anchor_rows, |targets, anchor| {
        let centre = |j: usize| targets[j].center;
        let group = Targets::Centres {
            count: targets.len(),
            centre: &centre,
        };
        out.push(rel::score(
            relation,
            &Operands::surround(group, ObjectGeom::from_box(anchor)),
            params,
        )?);
        Ok(())
    })?;
    Ok(out)
}

/// [`score_groups`] with the gradients of the scores ([`grad::surround`]): `d_targets` row
/// by row of `target_rows`, `d_anchors` one per group.
///
/// # Errors
/// As [`score_groups`].
pub fn grad_groups(
    relation: Relation,
    target_rows: &[[f64; BOX_COLUMNS]],
    groups: usize,
    anchor_rows: &[[f64; BOX_COLUMNS]],
    params: &RelationParams,
) -> Result<BatchGradient, RelationError> {
    let mut out = BatchGradient::with_capacity(groups, target_rows.len(), true);
    let d_anchors = out.d_anchors.get_or_insert_default();
    let mut d = Vec::new();
    each_group(relation, target_rows, groups, anchor_rows, |targets, anchor| {
        // One small allocation per group (the views borrow this group's boxes).
        let views: Vec<ObjectGeom<'_>> = targets.iter().map(ObjectGeom::from_box).collect();
        d.resize(targets.len(), BoxGrad::ZERO);
        let (score, d_anchor) = grad::surround(&views, &ObjectGeom::from_box(anchor), params, &mut d)?;
        out.scores.push(score);
        out.d_targets.extend(d.iter().map(BoxGrad::to_array));
        d_anchors.push(d_anchor.to_array());
        Ok(())
    })?;
    Ok(out)
}

/// Calls `each(targets, anchor)` for every group of `target_rows` (`groups` groups of equally
/// many rows, in order) with its anchor (row i, or the only anchor row), the boxes built from
/// the rows; checks that the relation is multi-target and the rows' counts.
fn each_group(
    relation: Relation,
    target_rows: &[[f64; BOX_COLUMNS]],
    groups: usize,
    anchor_rows: &[[f64; BOX_COLUMNS]],
    mut each: impl FnMut(&[Obb], &Obb) -> Result<(), RelationError>,
) -> Result<(), RelationError> {
    if relation.kind() != RelationKind::MultiTarget {
        return Err(RelationError::WrongKind {
            relation: relation.to_string(),
            actual: relation.kind().describe(),
            expected: "a multi-target relation (surround)",
        });
    }
    let k = target_rows.len().checked_div(groups).unwrap_or(0);
    if k * groups != target_rows.len() {
        return Err(RelationError::LengthMismatch {
            what: "targets",
            got: target_rows.len(),
            expected: k * groups,
        });
    }
    let broadcast = anchor_rows.len() == 1;
    if !broadcast && anchor_rows.len() != groups {
        return Err(RelationError::LengthMismatch {
            what: "anchors",
            got: anchor_rows.len(),
            expected: groups,
        });
    }
    let mut targets = Vec::with_capacity(k);
    let shared = if broadcast {
        Some(obb_from_row(&anchor_rows[0], || "anchors[0]".to_owned())?)
    } else {
        None
    };
    for i in 0..groups {
        targets.clear();
        for j in 0..k {
            let row = &target_rows[i * k + j];
            targets.push(obb_from_row(row, || format!("targets[{i}][{j}]"))?);
        }
        let anchor = match shared {
            Some(anchor) => anchor,
            None => obb_from_row(&anchor_rows[i], || format!("anchors[{i}]"))?,
        };
        each(&targets, &anchor)?;
    }
    Ok(())
}

/// Every relation with every argument, in the printed form relation() accepts (side_of(left),
/// next_to(wall), ...).
#[pyfunction]
pub fn relation_names() -> Vec<String> {
    Relation::all().map(|r| r.to_string()).collect()
}

/// The predicates' parameters as a dict: the defaults (or the reference's with reference=True) with
/// the keyword arguments given applied and validated. Lengths are metres, angles degrees.
#[pyfunction(name = "relation_params")]
#[pyo3(signature = (*, reference=false, **params))]
pub fn relation_params_py<'py>(
    py: Python<'py>,
    reference: bool,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    crate::convert::to_python(py, &relation_params(reference, params)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(x: f64) -> [f64; BOX_COLUMNS] {
        [x, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0]
    }

    #[test]
    fn bad_rows_are_named_by_their_index_in_the_whole_array() {
        // Row 1500 lies in the second chunk of 1024 rows: its name counts from the array's start.
        let mut rows = vec![cube(0.0); 2000];
        rows[1500][6] = f64::INFINITY;
        let anchors = vec![cube(2.0); 2000];
        let err = score_pairs(Relation::Near, &rows, &anchors, &RelationParams::default()).unwrap_err();
        assert_eq!(err.to_string(), "targets[1500].yaw is not finite");
        let mut anchors = anchors;
        anchors[1999][3] = -1.0;
        let err = score_pairs(
            Relation::Near,
            &vec![cube(0.0); 2000],
            &anchors,
            &RelationParams::default(),
        )
        .unwrap_err();
        assert!(
            err.to_string().contains("anchors[1999] is not a valid box"),
            "{err}"
        );
    }

    #[test]
    fn one_anchor_row_scores_every_target_against_it() {
        let params = RelationParams::default();
        let targets: Vec<_> = (0..3000).map(|i| cube(f64::from(i) * 0.001)).collect();
        let anchor = [cube(2.25)];
        let broadcast = score_pairs(Relation::Near, &targets, &anchor, &params).unwrap();
        let paired = score_pairs(Relation::Near, &targets, &vec![anchor[0]; 3000], &params).unwrap();
        assert_eq!(broadcast, paired);
        // Target 0: a 1.25 m gap to the anchor, inside near's [0.5, 1.5] m band.
        assert_eq!(broadcast[0], 1.0);
    }

    #[test]
    fn room_scores_match_one_query_at_a_time() {
        let params = RelationParams::default();
        let room = RoomSpec::new(vec![[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]]);
        let rows: Vec<_> = (0..1100)
            .map(|i| [f64::from(i) * 0.004, 1.5, 0.4, 0.3, 0.3, 0.4, 0.0])
            .collect();
        let room = room.build().unwrap();
        let scores = score_in_room(Relation::InsideRoom, &rows, &room, &params).unwrap();
        for (i, row) in rows.iter().enumerate().step_by(97) {
            let target = box_spec_from_row(row).to_obb("target").unwrap();
            let one = rel::score(
                Relation::InsideRoom,
                &Operands::in_rooms(ObjectGeom::from_box(&target), std::slice::from_ref(&room)),
                &params,
            );
            assert_eq!(scores[i], one.unwrap(), "row {i}");
        }
        // Row 0 is centred on the wall x = 0: half of it is inside.
        assert!((scores[0] - 0.5).abs() < 1e-9);
        assert!(score_pairs(Relation::InsideRoom, &rows, &rows, &params).is_err());
    }

    #[test]
    fn groups_score_as_surround_queries_one_by_one() {
        let params = RelationParams::default();
        let chair = |x: f64, y: f64| [x, y, 0.4, 0.25, 0.25, 0.4, 0.3];
        // Three groups of four around three anchors.
        let mut rows = Vec::new();
        let mut anchors = Vec::new();
        for g in 0..3 {
            let d = 1.0 + f64::from(g) * 0.3;
            rows.extend([
                chair(d, 0.0),
                chair(0.0, d),
                chair(-d, 0.1 * f64::from(g)),
                chair(0.2 * f64::from(g), -d),
            ]);
            anchors.push([0.0, 0.0, 0.4, 0.5, 0.5, 0.4, 0.0]);
        }
        let scores = score_groups(Relation::Surround, &rows, 3, &anchors, &params).unwrap();
        for (g, score) in scores.iter().enumerate() {
            let anchor = box_spec_from_row(&anchors[g]).to_obb("anchor").unwrap();
            let targets = obbs_from_rows(&rows[g * 4..g * 4 + 4], "targets").unwrap();
            let views: Vec<ObjectGeom<'_>> = targets.iter().map(ObjectGeom::from_box).collect();
            let one = rel::score(
                Relation::Surround,
                &Operands::surround(Targets::Objects(&views), ObjectGeom::from_box(&anchor)),
                &params,
            );
            assert_eq!(*score, one.unwrap(), "group {g}");
        }
        // Group 0: four chairs 1 m away at 90-degree gaps, score 1.
        assert_eq!(scores[0], 1.0);
        // One anchor row for every group.
        let shared = score_groups(Relation::Surround, &rows, 3, &anchors[..1], &params).unwrap();
        assert_eq!(shared, scores);
        // No target in each of two groups: fewer than three targets score 0.
        assert_eq!(
            score_groups(Relation::Surround, &[], 2, &anchors[..1], &params).unwrap(),
            vec![0.0, 0.0]
        );
        assert!(
            score_groups(Relation::Surround, &[], 0, &anchors[..1], &params)
                .unwrap()
                .is_empty()
        );
        // A bad row is named by its group and position.
        let mut bad = rows.clone();
        bad[6][2] = f64::NAN;
        let err = score_groups(Relation::Surround, &bad, 3, &anchors, &params).unwrap_err();
        assert_eq!(err.to_string(), "targets[1][2].center is not finite");
        assert!(score_groups(Relation::Surround, &rows, 3, &anchors[..2], &params).is_err());
        assert!(score_groups(Relation::Surround, &rows[..11], 3, &anchors, &params).is_err());
        assert!(score_groups(Relation::Near, &rows, 3, &anchors, &params).is_err());
        // The reference variant refuses more targets than its limit, as relation() does.
        let many = vec![chair(1.0, 0.0); sceneeval::relations::SURROUND_REFERENCE_MAX_TARGETS + 1];
        let err = score_groups(
            Relation::Surround,
            &many,
            1,
            &anchors[..1],
            &RelationParams::reference(),
        );
        assert!(
            matches!(err, Err(RelationError::TooManyTargets { .. })),
            "{err:?}"
        );
    }

    #[test]
    fn gradient_forms_give_the_scores_bit_for_bit_and_the_kernels_gradients() {
        let params = RelationParams::default();
        let targets: Vec<_> = (0..40)
            .map(|i| {
                let t = f64::from(i);
                [0.1 * t, 0.05 * t, 0.4, 0.3, 0.25, 0.4, 0.2 * t]
            })
            .collect();
        let anchors: Vec<_> = (0..40)
            .map(|i| [1.0, 0.5 + 0.02 * f64::from(i), 0.5, 0.5, 0.4, 0.5, 0.1])
            .collect();
        for relation in Relation::all().filter(|r| r.kind() == RelationKind::ObjectObject) {
            let scores = score_pairs(relation, &targets, &anchors, &params).unwrap();
            let g = grad_pairs(relation, &targets, &anchors, &params).unwrap();
            assert_eq!(g.scores, scores, "{relation}");
            let d_anchors = g.d_anchors.unwrap();
            assert_eq!((g.d_targets.len(), d_anchors.len()), (40, 40));
            let (t, a) = (
                obbs_from_rows(&targets[7..8], "t").unwrap(),
                obbs_from_rows(&anchors[7..8], "a").unwrap(),
            );
            let one = grad::pair(
                relation,
                &ObjectGeom::from_box(&t[0]),
                &ObjectGeom::from_box(&a[0]),
                &params,
            )
            .unwrap();
            assert_eq!(
                (g.d_targets[7], d_anchors[7]),
                (one.target.to_array(), one.anchor.to_array())
            );
            // One anchor row for every target: one anchor gradient per score, as when repeated.
            let shared = grad_pairs(relation, &targets, &anchors[..1], &params).unwrap();
            let repeated = grad_pairs(relation, &targets, &vec![anchors[0]; 40], &params).unwrap();
            assert_eq!(shared, repeated, "{relation}");
        }
        assert!(matches!(
            grad_pairs(Relation::Near, &targets, &anchors[..2], &params),
            Err(RelationError::LengthMismatch { what: "anchors", .. })
        ));
        assert!(grad_pairs(Relation::OnWall, &targets, &anchors, &params).is_err());
        let room = RoomSpec::new(vec![[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]])
            .build()
            .unwrap();
        for relation in Relation::all().filter(|r| r.kind() == RelationKind::ObjectArchitecture) {
            let g = grad_in_room(relation, &targets, &room, &params).unwrap();
            assert_eq!(
                g.scores,
                score_in_room(relation, &targets, &room, &params).unwrap(),
                "{relation}"
            );
            assert_eq!((g.d_targets.len(), g.d_anchors), (40, None));
        }
        // Row 0 (centred on the corner (0, 0) of the floor, a quarter of it over the floor):
        // moving it by dx along +x puts dx / 0.6 more of its width over the floor, so the share
        // grows by 0.5 dx / 0.6 (the other half of the depth stays out).
        let g = grad_in_room(Relation::InsideRoom, &targets[..1], &room, &params).unwrap();
        assert!((g.scores[0] - 0.25).abs() < 1e-9, "{}", g.scores[0]);
        assert!(
            (g.d_targets[0][0] - 0.5 / 0.6).abs() < 1e-9,
            "{:?}",
            g.d_targets[0]
        );
        let err = grad_in_room(Relation::InsideRoom, &[[f64::NAN; 7]], &room, &params).unwrap_err();
        assert_eq!(err.to_string(), "targets[0].center is not finite");
    }

    #[test]
    fn surround_gradients_come_per_target_and_per_group() {
        let params = RelationParams::default();
        let chair = |x: f64, y: f64| [x, y, 0.4, 0.25, 0.25, 0.4, 0.3];
        let rows = [
            chair(1.0, 0.0),
            chair(0.0, 1.2),
            chair(-1.0, 0.1),
            chair(0.2, -1.0),
            chair(1.0, 0.0),
            chair(0.0, 1.0),
            chair(-1.0, 0.0),
            chair(0.0, -1.0),
        ];
        let anchors = [[0.0, 0.0, 0.4, 0.5, 0.5, 0.4, 0.0]];
        let g = grad_groups(Relation::Surround, &rows, 2, &anchors, &params).unwrap();
        assert_eq!(
            g.scores,
            score_groups(Relation::Surround, &rows, 2, &anchors, &params).unwrap()
        );
        let d_anchors = g.d_anchors.unwrap();
        assert_eq!((g.d_targets.len(), d_anchors.len()), (8, 2));
        // Group 1 is evenly spread (score 1, its maximum): no derivative. Group 0 is not.
        assert_eq!(g.scores[1], 1.0);
        assert!(g.d_targets[4..].iter().flatten().all(|d| d.abs() < 1e-12));
        assert!(g.d_targets[..4].iter().flatten().any(|d| d.abs() > 1e-3));
        // Moving everything together changes nothing: the anchor's centre derivative is minus
        // the sum of the targets'.
        for c in 0..3 {
            let sum: f64 = g.d_targets[..4].iter().map(|d| d[c]).sum();
            assert!((d_anchors[0][c] + sum).abs() < 1e-12);
        }
        assert!(grad_groups(Relation::Near, &rows, 2, &anchors, &params).is_err());
        let many = vec![chair(1.0, 0.0); sceneeval::relations::SURROUND_REFERENCE_MAX_TARGETS + 1];
        let err = grad_groups(
            Relation::Surround,
            &many,
            1,
            &anchors,
            &RelationParams::reference(),
        );
        assert!(
            matches!(err, Err(RelationError::TooManyTargets { .. })),
            "{err:?}"
        );
    }

    #[test]
    fn rooms_are_built_once_per_key_and_failures_are_not_kept() {
        // The errors are Python exceptions: their text needs the interpreter.
        Python::initialize();
        let session = Mutex::new(Session::new(RelationParams::default(), AssetLibrary::new(), 4));
        let arg = |key: &str, value: serde_json::Value| RoomArg {
            key: key.to_owned(),
            value,
        };
        let square = serde_json::json!({"floor": [[0, 0], [4, 0], [4, 3], [0, 3]]});
        let a = arg("a", square.clone()).prepare_in(&session).unwrap();
        let again = arg("a", square.clone()).prepare_in(&session).unwrap();
        assert!(Arc::ptr_eq(&a, &again));
        assert_eq!(session.lock().unwrap().rooms_built(), 1);
        // Two points are no floor: the builder's error, not kept.
        let line = serde_json::json!({"floor": [[0, 0], [4, 0]]});
        let err = arg("b", line).prepare_in(&session).unwrap_err();
        assert!(err.to_string().contains("room: "), "{err}");
        assert!(arg("b", square).prepare_in(&session).is_ok());
        assert_eq!(session.lock().unwrap().rooms_built(), 2);
        // A key that does not read as a room names the key at fault.
        let bad = serde_json::json!({"floor": [[0, 0], [4, 0, 1], [4, 3]]});
        let err = arg("c", bad).prepare_in(&session).unwrap_err();
        assert!(err.to_string().contains("room.floor[1]: "), "{err}");
    }
}
