//! The checks of one row: its own cells (ID, difficulty, description, surplus cells), each
//! entry field in turn, then the difficulty against the number of objects it specifies.

use super::field::check_field;
use super::oa_rel::check_oa_rel;
use super::obj_attr::check_obj_attr;
use super::obj_count::{Counts, check_obj_count};
use super::oo_rel::check_oo_rel;
use super::{FindingCode, RowCtx};
use crate::quote::{excerpt, list};
use crate::row::{Difficulty, Field};

pub(super) fn check_row(ctx: &mut RowCtx<'_>) {
    let row = ctx.row;
    if row.id.is_empty() {
        ctx.push(
            FindingCode::MissingId,
            Field::Id,
            None,
            "the ID cell is empty".into(),
            None,
        );
    } else if row.id.parse::<u64>().is_err() {
        ctx.push(
            FindingCode::NonIntegerId,
            Field::Id,
            None,
            format!(
                "ID {:?} is not a non-negative integer; scene files are named scene_<ID>.json",
                ctx.id
            ),
            None,
        );
    }
    if let Difficulty::Other(text) = &row.difficulty {
        ctx.push(
            FindingCode::UnknownDifficulty,
            Field::Difficulty,
            None,
            format!("difficulty {:?} is not easy, medium or hard", excerpt(text)),
            None,
        );
    }
    if row.description.is_empty() {
        ctx.push(
            FindingCode::EmptyDescription,
            Field::Description,
            None,
            "the description is empty".into(),
            None,
        );
    } else if row.description.contains(';') {
        ctx.push(
            FindingCode::DescriptionSemicolon,
            Field::Description,
            None,
            "the description contains `;`; it is kept whole here, but the reference implementation \
             truncates it at the first `;`"
                .into(),
            None,
        );
    }
    if !row.overflow.is_empty() {
        ctx.push(
            FindingCode::RaggedRow,
            Field::Row,
            None,
            format!(
                "the row has {} cell(s) beyond the header's last column ({}); an unquoted comma \
                 in a cell shifts every later column",
                row.overflow.len(),
                list(&row.overflow, ", ", |c| format!("{:?}", excerpt(c)))
            ),
            Some("quote cells that contain commas".into()),
        );
    }

    let counts = Counts::of(row);
    check_field(ctx, &row.obj_count, |e, c| check_obj_count(e, c, &counts));
    check_field(ctx, &row.obj_attr, |e, c| check_obj_attr(e, c, &counts));
    check_field(ctx, &row.oo_rel, |e, c| check_oo_rel(e, c, &counts));
    check_field(ctx, &row.oa_rel, |e, c| check_oa_rel(e, c, &counts));
    check_difficulty(ctx);
}

/// Object-count bounds of the difficulty levels (paper, section "SceneEval-500").
fn difficulty_bounds(d: &Difficulty) -> Option<(u64, Option<u64>)> {
    match d {
        Difficulty::Easy => Some((0, Some(4))),
        Difficulty::Medium => Some((5, Some(8))),
        Difficulty::Hard => Some((9, None)),
        Difficulty::Other(_) => None,
    }
}

fn check_difficulty(ctx: &mut RowCtx<'_>) {
    let row = ctx.row;
    let Some((min, max)) = difficulty_bounds(&row.difficulty) else {
        return;
    };
    if row.obj_count.iter().any(|e| e.malformed().is_some()) {
        return;
    }
    let n = row.objects_specified();
    if n < min || max.is_some_and(|m| n > m) {
        let range = match max {
            Some(m) => format!("{min}-{m}"),
            None => format!("at least {min}"),
        };
        ctx.push(
            FindingCode::DifficultyObjectCount,
            Field::Difficulty,
            None,
            format!(
                "ObjCount specifies {n} objects; {} descriptions specify {range}",
                row.difficulty
            ),
            None,
        );
    }
}
#[cfg(test)]
mod tests {
    use super::super::test_support::{codes, row};
    use super::super::validate_row;
    use super::*;
    use crate::row::AnnotationRow;

    #[test]
    fn row_level_findings() {
        let mut r = row("eq,1,bed", "", "", "");
        r.id = "x1".into();
        r.difficulty = Difficulty::Other("expert".into());
        r.description = "A bed; nothing else.".into();
        r.overflow = vec!["extra".into()];
        assert_eq!(
            codes(&r),
            vec![
                FindingCode::NonIntegerId,
                FindingCode::UnknownDifficulty,
                FindingCode::DescriptionSemicolon,
                FindingCode::RaggedRow
            ]
        );
        r.id.clear();
        r.description.clear();
        let c = codes(&r);
        assert!(c.contains(&FindingCode::MissingId) && c.contains(&FindingCode::EmptyDescription));
    }

    #[test]
    fn difficulty_object_counts() {
        let all = |r: &AnnotationRow| validate_row(r, 0).into_iter().map(|f| f.code).collect::<Vec<_>>();
        // eq,5 + gt,1 (counts 2) + eq,0 = 7 objects.
        let mut r = row("eq,5,chair; gt,1,cup; eq,0,table", "", "", "");
        assert_eq!(all(&r), vec![FindingCode::DifficultyObjectCount]);
        r.difficulty = Difficulty::Medium;
        assert_eq!(all(&r), vec![]);
        r.difficulty = Difficulty::Hard;
        assert_eq!(all(&r), vec![FindingCode::DifficultyObjectCount]);
    }
}
