//! Findings stay small whatever the input: a problem repeated over the items of one entry is
//! one finding with its number of occurrences, and every piece of input a finding quotes is
//! at most `MAX_QUOTE_CHARS` characters (issue 29: one finding per extra reference, each
//! quoting the whole entry, printed 1.1 GB for a 109 KB file).

use proptest::prelude::*;
use sceneeval_annotation::{
    AnnotationRow, Annotations, Difficulty, Finding, FindingCode, MAX_QUOTE_CHARS, MAX_QUOTED_ITEMS,
};

/// `n` items made by `item`, joined by `,`.
fn items(n: usize, item: impl Fn(usize) -> String) -> String {
    (0..n).map(item).collect::<Vec<_>>().join(",")
}

/// A row with `n` extra items in every way an entry can repeat a problem: undefined
/// references, bad and empty references, unknown architecture references, attributes, names
/// with spaces, an entry repeated `n` times, `n` surplus cells, and an ID of `n` digits.
fn row_with_extra(n: usize) -> AnnotationRow {
    let mut row = AnnotationRow::new("7".repeat(n), Difficulty::Easy, "A bedroom.");
    row.set_cell("ObjCount", &vec!["eq,1,bed"; n].join("; "));
    row.set_cell("ObjAttr", &format!("eq,1,bed,{}", items(n, |i| format!("a{i}"))));
    let oo_rel = [
        format!("eq,1,near,0,bed,{}", items(n, |i| format!("x{i}"))),
        format!("eq,1,near,0,bed,{}", items(n, |i| format!("chair:k{i}"))),
        format!("eq,1,near,0,bed,{}", items(n, |_| String::new())),
        format!("eq,1,near,0,bed,{}", items(n, |i| format!("my chair {i}"))),
    ];
    row.set_cell("OORel", &oo_rel.join("; "));
    row.set_cell(
        "OARel",
        &format!("eq,1,against,bed,{}", items(n, |i| format!("wall_{i}x"))),
    );
    row.overflow = vec!["extra".to_owned(); n];
    row
}

fn text_of(findings: &[Finding]) -> String {
    findings.iter().map(|f| format!("{f}\n")).collect()
}

#[test]
fn an_entry_with_thousands_of_extra_references_gives_a_few_short_findings() {
    let findings = sceneeval_annotation::validate_row(&row_with_extra(2_000), 0);
    let text = text_of(&findings);
    // One finding per problem and place (measured: 11 findings, 3.6 KB), where every extra
    // reference had its own finding quoting the whole entry (about 8,000 findings of up to
    // 20 KB each).
    assert!(findings.len() <= 20, "{} findings:\n{text}", findings.len());
    assert!(text.len() <= 8_000, "{} bytes:\n{text}", text.len());
    let occurrences = |code| -> usize {
        findings
            .iter()
            .filter(|f| f.code == code)
            .map(|f| f.occurrences)
            .sum()
    };
    // x0..x1999 and the 2,000 names with spaces have no ObjCount entry: one finding per entry.
    assert_eq!(occurrences(FindingCode::UndefinedCategory), 4_000);
    assert_eq!(
        findings
            .iter()
            .filter(|f| f.code == FindingCode::UndefinedCategory)
            .count(),
        2
    );
    assert_eq!(occurrences(FindingCode::BadReference), 2_000);
    assert_eq!(occurrences(FindingCode::EmptyName), 2_000);
    assert_eq!(occurrences(FindingCode::UnknownArchReference), 2_000);
    assert_eq!(occurrences(FindingCode::DuplicateEntry), 1_999);
    assert!(text.contains("(and 1999 more like it)"), "{text}");
    // The output does not grow with the number of extra items (only their counts' digits).
    let smaller = text_of(&sceneeval_annotation::validate_row(&row_with_extra(500), 0));
    assert!(
        smaller.len().abs_diff(text.len()) <= 100,
        "{} vs {}",
        smaller.len(),
        text.len()
    );
}

#[test]
fn duplicate_ids_quote_a_bounded_id() {
    let long = "9".repeat(10_000);
    let rows = vec![
        AnnotationRow::new(long.clone(), Difficulty::Easy, "A room."),
        AnnotationRow::new(long, Difficulty::Easy, "A room."),
    ];
    let findings = Annotations::from_rows(rows).validate();
    let duplicate = findings
        .iter()
        .find(|f| f.code == FindingCode::DuplicateId)
        .unwrap();
    assert_eq!(duplicate.row.chars().count(), MAX_QUOTE_CHARS);
    assert!(duplicate.row.ends_with('…'));
    assert!(duplicate.to_string().len() < 400, "{duplicate}");
}

/// The pieces of `text` between backticks or double quotes (the names, entries and cells a
/// message quotes; the generated names contain neither).
fn quoted(text: &str) -> Vec<&str> {
    let mut out: Vec<&str> = text.split('`').skip(1).step_by(2).collect();
    out.extend(text.split('"').skip(1).step_by(2));
    out
}

fn name() -> impl Strategy<Value = String> {
    // Short and long names, with the characters that raise findings (spaces, hyphens, `:`),
    // digits, and two-byte letters (the bound counts characters).
    prop_oneof![
        "[a-z_]{1,8}",
        "[a-zé -]{0,12}",
        "[a-z0-9_:é -]{60,300}",
        "(wall|window|door|floor)_[0-9]{1,3}",
    ]
}

fn entry() -> impl Strategy<Value = String> {
    (
        prop::sample::select(vec!["eq", "ge", "lt", "EQ", "x"]),
        prop::sample::select(vec!["0", "1", "3", "-2"]),
        prop::collection::vec(name(), 1..40),
    )
        .prop_map(|(q, n, names)| format!("{q},{n},{}", names.join(",")))
}

fn cell() -> impl Strategy<Value = String> {
    prop::collection::vec(entry(), 0..6).prop_map(|entries| entries.join("; "))
}

fn any_row() -> impl Strategy<Value = AnnotationRow> {
    (
        prop_oneof!["[0-9]{1,3}", "[a-z0-9 ]{0,200}"],
        prop::sample::select(vec![
            Difficulty::Easy,
            Difficulty::Hard,
            Difficulty::Other("x".repeat(150)),
        ]),
        [cell(), cell(), cell(), cell()],
        prop::collection::vec("[a-z ]{0,120}", 0..12),
    )
        .prop_map(|(id, difficulty, cells, overflow)| {
            let mut row = AnnotationRow::new(id, difficulty, "A room; with a table.");
            for (column, cell) in ["ObjCount", "ObjAttr", "OORel", "OARel"].iter().zip(&cells) {
                row.set_cell(column, cell);
            }
            row.overflow = overflow;
            row
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn every_quote_of_a_finding_is_at_most_the_bound(rows in prop::collection::vec(any_row(), 1..3)) {
        let findings = Annotations::from_rows(rows).validate();
        for f in &findings {
            let line = f.to_string();
            prop_assert!(f.row.chars().count() <= MAX_QUOTE_CHARS, "{line}");
            if let Some(entry) = &f.entry {
                prop_assert!(entry.chars().count() <= MAX_QUOTE_CHARS, "{line}");
            }
            for piece in quoted(&f.message) {
                prop_assert!(piece.chars().count() <= MAX_QUOTE_CHARS, "{piece:?} in {line}");
            }
            // A suggestion is one quoted entry or a list of at most MAX_QUOTED_ITEMS of them.
            if let Some(s) = &f.suggestion {
                let most = MAX_QUOTED_ITEMS * (MAX_QUOTE_CHARS + 2) + 32;
                prop_assert!(s.chars().count() <= most, "{line}");
            }
            prop_assert!(line.chars().count() <= 2_000, "{line}");
            prop_assert!(f.occurrences >= 1);
        }
    }
}
