//! Property: any writable annotation file survives write then parse unchanged, in CSV and in
//! JSON, and writing is a fixpoint.

use proptest::prelude::*;
use sceneeval_annotation::{
    AnnotationRow, Annotations, ArchRef, CountSpec, Difficulty, Entry, EntryKind, OaRel, ObjAttr, ObjCount,
    ObjRef, OoRel, Quantifier,
};

fn name() -> impl Strategy<Value = String> {
    // Open-vocabulary names: letters, digits, `_`, an inner space at most (a name-format warning,
    // but representable), never `,` `;` `:` or surrounding spaces.
    "[a-zA-Z][a-z0-9_]{0,8}( [a-z]{1,4})?"
}

fn count() -> impl Strategy<Value = CountSpec> {
    (prop::sample::select(Quantifier::ALL.to_vec()), 0u64..20).prop_map(|(q, n)| CountSpec::new(q, n))
}

fn obj_ref() -> impl Strategy<Value = ObjRef> {
    (name(), prop::option::of(0u32..5)).prop_map(|(category, instance)| ObjRef { category, instance })
}

fn arch_ref() -> impl Strategy<Value = ArchRef> {
    prop_oneof![
        prop::sample::select(sceneeval_annotation::vocab::ARCH_ELEMENTS.to_vec()).prop_map(ArchRef::parse),
        prop::sample::select(sceneeval_annotation::vocab::ROOM_TYPES.to_vec()).prop_map(ArchRef::parse),
        "custom_[a-z]{1,6}".prop_map(ArchRef::Unknown),
    ]
}

/// Malformed entry texts (for every field kind).
fn malformed<T: EntryKind + std::fmt::Debug>() -> impl Strategy<Value = Entry<T>> {
    prop_oneof![
        name().prop_map(|n| format!("eq,x,{n}")),
        name().prop_map(|n| format!("EQ,1,{n}")),
        Just("eq,1".to_owned()),
        name().prop_map(|n| format!("ge,-2,{n},{n}")),
    ]
    .prop_map(|t| Entry::<T>::parse(&t))
    .prop_filter("malformed", |e| e.malformed().is_some())
}

fn entries<T: EntryKind + std::fmt::Debug + 'static>(
    parsed: impl Strategy<Value = T> + 'static,
) -> impl Strategy<Value = Vec<Entry<T>>> {
    prop::collection::vec(
        prop_oneof![4 => parsed.prop_map(Entry::Parsed), 1 => malformed::<T>()],
        0..5,
    )
}

fn difficulty() -> impl Strategy<Value = Difficulty> {
    prop_oneof![
        Just(Difficulty::Easy),
        Just(Difficulty::Medium),
        Just(Difficulty::Hard),
        "[a-z]{0,8}"
            .prop_filter("not a level", |s| !["easy", "medium", "hard"]
                .contains(&s.as_str()))
            .prop_map(Difficulty::Other),
    ]
}

fn row() -> impl Strategy<Value = AnnotationRow> {
    let id = prop_oneof!["[0-9]{1,3}", "[a-z0-9_-]{0,5}", "['=+@-]{0,2}[a-z0-9]{0,3}"];
    // Descriptions with commas, semicolons, quotes, line breaks, non-ASCII text, and the
    // characters a spreadsheet runs as a formula at the start (escaped with a `'`).
    let description = "['=+@-]{0,3}[a-zA-Z0-9 ,;\"'.\n\r\té=+@-]{0,60}".prop_map(|s| s.trim().to_owned());
    let obj_count = entries((count(), name()).prop_map(|(c, n)| ObjCount::new(c, n)));
    let obj_attr = entries((count(), name(), name()).prop_map(|(c, n, a)| ObjAttr::new(c, n, a)));
    let oo_rel = entries(
        (
            count(),
            name(),
            prop::collection::vec(obj_ref(), 2..5),
            prop::option::of(0usize..6),
        )
            .prop_map(|(c, r, refs, anchor)| OoRel::new(c, r, anchor, refs)),
    );
    let oa_rel = entries(
        (
            count(),
            name(),
            obj_ref(),
            prop::collection::vec(arch_ref(), 1..3),
        )
            .prop_map(|(c, r, o, arch)| OaRel::new(c, r, o, arch)),
    );
    let extra = prop::collection::btree_map(
        prop::sample::select(vec!["Category", "SceneEvalID", "is_house", "Notes, more"])
            .prop_map(str::to_owned),
        "[ -~\n]{1,12}",
        0..3,
    );
    (
        id,
        difficulty(),
        description,
        obj_count,
        obj_attr,
        oo_rel,
        oa_rel,
        extra,
    )
        .prop_map(
            |(id, difficulty, description, obj_count, obj_attr, oo_rel, oa_rel, extra)| AnnotationRow {
                id,
                difficulty,
                description,
                obj_count,
                obj_attr,
                oo_rel,
                oa_rel,
                extra,
                overflow: Vec::new(),
            },
        )
}

fn annotations() -> impl Strategy<Value = Annotations> {
    prop::collection::vec(row(), 0..6).prop_flat_map(|rows| {
        let columns = Annotations::from_rows(rows.clone()).columns;
        Just(columns).prop_shuffle().prop_map(move |columns| Annotations {
            columns,
            rows: rows.clone(),
        })
    })
}

/// A cell a spreadsheet would run is written with a leading `'` and read back without it;
/// numbers and other text are written as they are.
#[test]
fn formula_cells_are_escaped_and_read_back() {
    let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel,Notes\n\
               -5,easy,\"=HYPERLINK(\"\"http://x\"\")\",\"eq,1,bed\",,,,@me\n\
               6,easy,'quoted' text,,,,,'=kept\n";
    let a = Annotations::from_csv_str(csv).unwrap();
    // A file written by another tool: `'=kept` loses its first quote (it is read as escaped).
    assert_eq!(a.rows[1].extra["Notes"], "=kept");
    let mut a = a;
    a.rows[1].extra.insert("Notes".into(), "'=kept".into());
    a.rows[1].description = "- a list, then a bed".into();
    let text = a.to_csv_string().unwrap();
    assert_eq!(
        text,
        "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel,Notes\n\
         -5,easy,\"'=HYPERLINK(\"\"http://x\"\")\",\"eq,1,bed\",,,,'@me\n\
         6,easy,\"'- a list, then a bed\",,,,,''=kept\n"
    );
    let b = Annotations::from_csv_str(&text).unwrap();
    assert_eq!(b, a);
    assert_eq!(b.rows[0].description, "=HYPERLINK(\"http://x\")");
    assert_eq!(b.rows[0].id, "-5");
    assert_eq!(b.rows[1].extra["Notes"], "'=kept");
}

proptest! {
    #[test]
    fn csv_write_then_parse_is_identity(a in annotations()) {
        let text = a.to_csv_string().unwrap();
        let b = Annotations::from_csv_str(&text).unwrap();
        prop_assert_eq!(&b, &a);
        prop_assert_eq!(b.to_csv_string().unwrap(), text);
    }

    #[test]
    fn json_write_then_parse_is_identity(a in annotations()) {
        let text = a.to_json_string().unwrap();
        let b = Annotations::from_json_str(&text).unwrap();
        prop_assert_eq!(&b, &a);
        prop_assert_eq!(b.to_json_string().unwrap(), text);
    }

    #[test]
    fn csv_and_json_agree(a in annotations()) {
        let via_csv = Annotations::from_csv_str(&a.to_csv_string().unwrap()).unwrap();
        let via_json = Annotations::from_json_str(&a.to_json_string().unwrap()).unwrap();
        prop_assert_eq!(via_csv, via_json);
    }

    /// Ragged rows (cells beyond the header) keep their cells through a round trip.
    #[test]
    fn overflow_cells_survive(a in annotations(), cells in prop::collection::vec("[ -~]{0,6}", 1..3)) {
        let mut a = a;
        a.columns = a.effective_columns();
        if let Some(r) = a.rows.first_mut() {
            r.overflow = cells;
        }
        let b = Annotations::from_csv_str(&a.to_csv_string().unwrap()).unwrap();
        prop_assert_eq!(b, a);
    }

    /// Validation never panics and is deterministic.
    #[test]
    fn validation_is_total_and_deterministic(a in annotations()) {
        let f1 = a.validate();
        let f2 = a.validate();
        prop_assert_eq!(f1, f2);
        let _ = a.stats().to_markdown();
    }
}
