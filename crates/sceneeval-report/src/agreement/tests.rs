//! Agreement against hand-computed cases: perfect, chance, one class, all null, ties, Fleiss.

#![allow(clippy::unwrap_used, clippy::panic, clippy::float_cmp)]

use std::path::Path;

use sceneeval_stats::Bootstrap;

use super::*;

/// One label line; the spec text is `spec <metric> <index>`.
fn line(annotator: &str, scene: &str, metric: &str, index: usize, v: Option<bool>) -> String {
    let v = v.map_or_else(|| "null".to_owned(), |v| v.to_string());
    format!(
        r#"{{"scene": "{scene}", "metric": "{metric}", "index": {index}, "spec": "spec {metric} {index}", "satisfied": {v}, "annotator": "{annotator}"}}"#
    )
}

/// A label file of `annotator`'s verdicts on `oor` specs 0.. of scene `s`.
fn file(name: &str, lines: &[(&str, &[Option<bool>])]) -> LabelFile {
    let mut text = String::new();
    for (annotator, verdicts) in lines {
        for (k, v) in verdicts.iter().enumerate() {
            text.push_str(&line(annotator, "s", "oor", k, *v));
            text.push('\n');
        }
    }
    LabelFile::from_jsonl_str(Path::new(name), &text).unwrap()
}

const T: Option<bool> = Some(true);
const F: Option<bool> = Some(false);
const N: Option<bool> = None;

fn no_bootstrap() -> AgreementOptions {
    AgreementOptions { bootstrap: None }
}

fn judge_row<'a>(table: &'a Agreement, judge: &str, metric: &str) -> &'a AgreementRow {
    table
        .rows
        .iter()
        .find(|r| r.kind == RowKind::Judge && r.a == judge && r.metric == metric)
        .unwrap()
}

#[test]
fn perfect_agreement_is_one() {
    let reference = file("ref.jsonl", &[("alice", &[T, F, T, F])]);
    let judge = file("judge.jsonl", &[("vlm", &[T, F, T, F])]);
    let table = agreement(&[reference], &[Source::Labels(judge)], &no_bootstrap()).unwrap();
    assert_eq!(table.metrics, [FidelityMetric::Oor]);
    let r = judge_row(&table, "vlm", "oor");
    assert_eq!((r.n, r.agreement, r.kappa), (4, Some(1.0), Some(1.0)));
    assert_eq!((r.tt, r.tf, r.ft, r.ff), (Some(2), Some(0), Some(0), Some(2)));
    // `all` pools the one metric: the same numbers.
    assert_eq!(judge_row(&table, "vlm", "all").kappa, Some(1.0));
    assert!(table.wrong.is_empty());
}

#[test]
fn chance_agreement_is_zero() {
    // p_o = 2/4; each side half true: p_e = (2*2 + 2*2)/16 = 1/2; kappa = 0.
    let reference = file("ref.jsonl", &[("alice", &[T, F, T, F])]);
    let judge = file("judge.jsonl", &[("vlm", &[T, T, F, F])]);
    let table = agreement(&[reference], &[Source::Labels(judge)], &no_bootstrap()).unwrap();
    let r = judge_row(&table, "vlm", "oor");
    assert_eq!((r.n, r.agreement, r.kappa), (4, Some(0.5), Some(0.0)));
    assert_eq!((r.tt, r.tf, r.ft, r.ff), (Some(1), Some(1), Some(1), Some(1)));
    // The two wrong items: spec 1 (judge true, people false) and spec 2.
    let wrong: Vec<(usize, bool, bool)> = table
        .wrong
        .iter()
        .map(|w| (w.index, w.verdict, w.reference))
        .collect();
    assert_eq!(wrong, [(1, true, false), (2, false, true)]);
    assert_eq!(table.wrong[0].spec, "spec oor 1");
    let md = table.to_markdown();
    assert!(
        md.contains("- s, OOR 1: `spec oor 1`: judge satisfied, reference not satisfied"),
        "{md}"
    );
}

#[test]
fn a_hand_computed_kappa() {
    // Judge T T F T F, people T F F F F: p_o = 3/5; rows (judge) F 2, T 3; columns F 4, T 1;
    // p_e = (2*4 + 3*1)/25 = 11/25; kappa = (15 - 11)/(25 - 11) = 4/14 = 2/7.
    let reference = file("ref.jsonl", &[("alice", &[T, F, F, F, F])]);
    let judge = file("judge.jsonl", &[("vlm", &[T, T, F, T, F])]);
    let table = agreement(&[reference], &[Source::Labels(judge)], &no_bootstrap()).unwrap();
    let r = judge_row(&table, "vlm", "oor");
    assert_eq!(r.agreement, Some(0.6));
    assert_eq!(r.kappa, Some(4.0 / 14.0));
    assert_eq!((r.tt, r.tf, r.ft, r.ff), (Some(1), Some(2), Some(0), Some(2)));
}

#[test]
fn one_class_leaves_kappa_empty_and_says_why() {
    let reference = file("ref.jsonl", &[("alice", &[T, T, T])]);
    let judge = file("judge.jsonl", &[("vlm", &[T, T, T])]);
    let table = agreement(
        &[reference],
        &[Source::Labels(judge)],
        &AgreementOptions::default(),
    )
    .unwrap();
    let r = judge_row(&table, "vlm", "oor");
    assert_eq!((r.n, r.agreement, r.kappa), (3, Some(1.0), None));
    assert!(r.undefined.as_deref().unwrap().starts_with("one class only"));
    assert_eq!((r.kappa_low, r.kappa_high), (None, None));
    let md = table.to_markdown();
    assert!(md.contains("| vlm | 100.0 |  | 100.0 |  | 3 |"), "{md}");
    assert!(md.contains("- vlm, OOR: one class only"), "{md}");
    let csv = table.to_csv().unwrap();
    assert!(
        csv.contains("judge,vlm,reference,oor,3,1,,,,\"one class only"),
        "{csv}"
    );
}

#[test]
fn all_null_leaves_every_item_out_counted() {
    let reference = file("ref.jsonl", &[("alice", &[T, F, T])]);
    let judge = file("judge.jsonl", &[("vlm", &[N, N, N])]);
    let table = agreement(
        &[reference],
        &[Source::Labels(judge)],
        &AgreementOptions::default(),
    )
    .unwrap();
    let r = judge_row(&table, "vlm", "oor");
    assert_eq!((r.n, r.agreement, r.kappa, r.left_out_null), (0, None, None, 3));
    assert_eq!(r.undefined.as_deref(), Some("no items"));
    // The reference could not tell either: still null, counted.
    let reference = file("ref.jsonl", &[("alice", &[N, N])]);
    let judge = file("judge.jsonl", &[("vlm", &[T, F])]);
    let table = agreement(&[reference], &[Source::Labels(judge)], &no_bootstrap()).unwrap();
    assert_eq!(judge_row(&table, "vlm", "oor").left_out_null, 2);
}

#[test]
fn tied_annotators_leave_the_item_out() {
    // Item 0: alice T, bob F: a tie, left out. Item 1: both F. Item 2: alice T, bob null: T.
    let reference = file("ref.jsonl", &[("alice", &[T, F, T]), ("bob", &[F, F, N])]);
    let judge = file("judge.jsonl", &[("vlm", &[T, F, T])]);
    let table = agreement(&[reference], &[Source::Labels(judge)], &no_bootstrap()).unwrap();
    assert_eq!(table.reference, ["alice", "bob"]);
    assert_eq!(table.reference_ties, 1);
    let r = judge_row(&table, "vlm", "oor");
    assert_eq!((r.n, r.left_out_tie, r.kappa), (2, 1, Some(1.0)));
    // alice vs bob: items 0 and 1 (item 2 null for bob): p_o = 1/2, alice T F, bob F F:
    // p_e = (1*0 + 1*2)/4 = 1/2 -> kappa 0.
    let pair = table
        .rows
        .iter()
        .find(|r| r.kind == RowKind::Annotators && r.metric == "oor")
        .unwrap();
    assert_eq!((pair.a.as_str(), pair.b.as_str()), ("alice", "bob"));
    assert_eq!((pair.n, pair.left_out_null, pair.kappa), (2, 1, Some(0.0)));
}

#[test]
fn fleiss_over_the_items_every_annotator_judged() {
    // Items (yes, no): (3,0) (0,3) (2,1) (1,2), and item 4 which carol did not judge.
    // P_i = 1, 1, 1/3, 1/3: mean 2/3; p_yes = 6/12: P_e = 1/2; kappa = (2/3 - 1/2)/(1/2) = 1/3.
    let reference = file(
        "ref.jsonl",
        &[
            ("alice", &[T, F, T, F, T]),
            ("bob", &[T, F, T, T, T]),
            ("carol", &[T, F, F, F]),
        ],
    );
    let judge = file("judge.jsonl", &[("vlm", &[T, F, T, F, T])]);
    let table = agreement(&[reference], &[Source::Labels(judge)], &no_bootstrap()).unwrap();
    let fleiss = table
        .rows
        .iter()
        .find(|r| r.kind == RowKind::Fleiss && r.metric == "oor")
        .unwrap();
    assert_eq!((fleiss.a.as_str(), fleiss.b.as_str()), ("*", "*"));
    assert_eq!((fleiss.n, fleiss.left_out_null, fleiss.agreement), (4, 1, None));
    assert!((fleiss.kappa.unwrap() - 1.0 / 3.0).abs() < 1e-15, "{fleiss:?}");
    // Three annotator pairs, each on oor and all.
    assert_eq!(
        table
            .rows
            .iter()
            .filter(|r| r.kind == RowKind::Annotators)
            .count(),
        6
    );
    let csv = table.to_csv().unwrap();
    assert!(
        csv.starts_with("kind,a,b,metric,n,agreement,kappa,kappa_low,kappa_high,"),
        "{csv}"
    );
    assert!(csv.contains("\nfleiss,*,*,oor,4,,0.3333333333333333,"), "{csv}");
}

#[test]
fn metrics_are_pooled_in_all() {
    // cnt: judge T F vs people T F; oor: judge T vs people F.
    let text = [
        line("alice", "s", "cnt", 0, T),
        line("alice", "s", "cnt", 1, F),
        line("alice", "t", "oor", 0, F),
    ]
    .join("\n");
    let judge_text = [
        line("vlm", "s", "cnt", 0, T),
        line("vlm", "s", "cnt", 1, F),
        line("vlm", "t", "oor", 0, T),
    ]
    .join("\n");
    let reference = LabelFile::from_jsonl_str(Path::new("r"), &text).unwrap();
    let judge = LabelFile::from_jsonl_str(Path::new("j"), &judge_text).unwrap();
    let table = agreement(&[reference], &[Source::Labels(judge)], &no_bootstrap()).unwrap();
    assert_eq!(table.metrics, [FidelityMetric::Cnt, FidelityMetric::Oor]);
    // All: judge T F T, people T F F: p_o = 2/3; rows F 1, T 2; columns F 2, T 1;
    // p_e = (1*2 + 2*1)/9 = 4/9; kappa = (6 - 4)/(9 - 4) = 2/5.
    let all = judge_row(&table, "vlm", "all");
    assert_eq!((all.n, all.kappa), (3, Some(0.4)));
    // OOR: one item, the judge all true, the people all false: p_e = 0, kappa = 0 (defined).
    assert_eq!(judge_row(&table, "vlm", "oor").kappa, Some(0.0));
    let tex = table.to_latex();
    assert!(
        tex.contains("\\multicolumn{2}{c}{CNT} & \\multicolumn{2}{c}{OOR} & \\multicolumn{2}{c}{All}"),
        "{tex}"
    );
    assert!(
        tex.contains("vlm & 100.0 & 1.00 & 0.0 & 0.00 & 66.7 & 0.40 \\\\"),
        "{tex}"
    );
    assert!(
        tex.contains("\\item vlm: t, OOR 0: \\texttt{spec oor 0} (judge satisfied, reference not satisfied)"),
        "{tex}"
    );
}

#[test]
fn without_a_reference_every_pair() {
    let a = file("a.jsonl", &[("alice", &[T, F, T, F]), ("bob", &[T, F, F, F])]);
    let b = file("b.jsonl", &[("carol", &[T, F, T, F])]);
    let table = agreement(&[], &[Source::Labels(a), Source::Labels(b)], &no_bootstrap()).unwrap();
    let pairs: Vec<(&str, &str)> = table
        .rows
        .iter()
        .filter(|r| r.metric == "all")
        .map(|r| (r.a.as_str(), r.b.as_str()))
        .collect();
    assert_eq!(pairs, [("alice", "bob"), ("alice", "carol"), ("bob", "carol")]);
    assert!(table.rows.iter().all(|r| r.kind == RowKind::Pair));
    let md = table.to_markdown();
    assert!(md.contains("| alice vs carol | 100.0 | 1.00 |"), "{md}");
    // One rater alone has no pair.
    let lone = file("a.jsonl", &[("alice", &[T])]);
    assert!(matches!(
        agreement(&[], &[Source::Labels(lone)], &no_bootstrap()),
        Err(AgreementError::Nothing(_))
    ));
}

#[test]
fn the_bootstrap_is_seeded_and_stays_around_kappa() {
    let reference = file("ref.jsonl", &[("alice", &[T, F, F, F, F, T, T, F, T, F])]);
    let judge = file("judge.jsonl", &[("vlm", &[T, T, F, T, F, T, F, F, T, F])]);
    let options = AgreementOptions {
        bootstrap: Some(Bootstrap::new(500, 0.9).unwrap().with_seed(7)),
    };
    let once = agreement(
        std::slice::from_ref(&reference),
        &[Source::Labels(judge.clone())],
        &options,
    )
    .unwrap();
    let again = agreement(&[reference], &[Source::Labels(judge)], &options).unwrap();
    assert_eq!(once, again);
    let r = judge_row(&once, "vlm", "oor");
    let (k, l, h) = (r.kappa.unwrap(), r.kappa_low.unwrap(), r.kappa_high.unwrap());
    assert!(l <= k && k <= h && l < h, "{r:?}");
    assert_eq!(
        (once.resamples, once.seed, once.level),
        (Some(500), Some(7), Some(0.9))
    );
    // Perfect agreement: every defined resample has kappa 1.
    let perfect = agreement(
        &[file("r", &[("alice", &[T, F, T, F])])],
        &[Source::Labels(file("j", &[("vlm", &[T, F, T, F])]))],
        &AgreementOptions::default(),
    )
    .unwrap();
    let r = judge_row(&perfect, "vlm", "oor");
    assert_eq!((r.kappa_low, r.kappa_high), (Some(1.0), Some(1.0)));
    assert!(
        r.resamples_undefined > 0,
        "one-class resamples are counted: {r:?}"
    );
}

#[test]
fn names_and_spec_texts_must_fit() {
    let reference = file("ref.jsonl", &[("alice", &[T])]);
    let twin = file("judge.jsonl", &[("alice", &[T])]);
    let err = agreement(
        std::slice::from_ref(&reference),
        &[Source::Labels(twin)],
        &no_bootstrap(),
    )
    .unwrap_err();
    assert!(
        err.to_string()
            .contains("two raters are named \"alice\": ref.jsonl and judge.jsonl"),
        "{err}"
    );
    let other = LabelFile::from_jsonl_str(
        Path::new("judge.jsonl"),
        &line("vlm", "s", "oor", 0, T).replace("spec oor 0", "another text"),
    )
    .unwrap();
    let err = agreement(&[reference], &[Source::Labels(other)], &no_bootstrap()).unwrap_err();
    assert!(
        err.to_string().starts_with(
            "judge.jsonl:1: oor spec 0 of s is \"another text\" here but \"spec oor 0\" in ref.jsonl:1"
        ),
        "{err}"
    );
}
