//! Rows for the validation tests.

use super::{FindingCode, validate_row};
use crate::row::{AnnotationRow, Difficulty};

/// A row with ID 0, difficulty easy and the four entry cells given.
pub(super) fn row(obj_count: &str, obj_attr: &str, oo_rel: &str, oa_rel: &str) -> AnnotationRow {
    let mut r = AnnotationRow::new("0", Difficulty::Easy, "A room.");
    r.set_cell("ObjCount", obj_count);
    r.set_cell("ObjAttr", obj_attr);
    r.set_cell("OORel", oo_rel);
    r.set_cell("OARel", oa_rel);
    r
}

/// The codes found, without `difficulty-object-count` (the test rows are all "easy").
pub(super) fn codes(r: &AnnotationRow) -> Vec<FindingCode> {
    validate_row(r, 0)
        .into_iter()
        .map(|f| f.code)
        .filter(|&c| c != FindingCode::DifficultyObjectCount)
        .collect()
}
