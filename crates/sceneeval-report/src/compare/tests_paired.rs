//! Hand-computed paired comparisons, tested ranks, failed scenes at the worst value and
//! McNemar on fidelity verdicts: the arithmetic of every expected value is in the comments.

use sceneeval_fidelity::FidelityReport;
use sceneeval_plausibility::{self as plausibility, PlausibilityReport, PlausibilitySummary};
use sceneeval_results::{Preset, SceneName, SceneRecord, SceneReport, Stage};
use sceneeval_stats::special::normal_cdf;

use super::tests::{fingerprint, record};
use super::*;

type P = plausibility::Metric;

const M: [P; 3] = [P::Support, P::Navigability, P::OutOfBounds];

fn s(sup: f64, nav: f64) -> PlausibilitySummary {
    PlausibilitySummary {
        sup: Some(sup),
        nav: Some(nav),
        oob: Some(0.0),
        ..PlausibilitySummary::default()
    }
}

fn run(name: &str, scenes: &[(f64, f64)]) -> Run {
    let records = scenes
        .iter()
        .enumerate()
        .map(|(k, &(sup, nav))| record(&format!("scene_{k}"), &M, s(sup, nav), "p"))
        .collect();
    Run::from_records(name, format!("runs/{name}"), records)
}

/// A: SUP and NAV 50 on five scenes.
/// B: SUP 50, 60, 70, 80, 10 (differences 0, +10, +20, +30, -40); NAV 60, 60, 40, 70, 50
///    (differences +10, +10, -10, +20, 0). OOB 0 everywhere.
/// C: scene_0 (SUP 90: +40), scene_1 failed, no other scene.
fn abc() -> Vec<Run> {
    let a = run("A", &[(0.5, 0.5); 5]);
    let b = run("B", &[(0.5, 0.6), (0.6, 0.6), (0.7, 0.4), (0.8, 0.7), (0.1, 0.5)]);
    let err = std::io::Error::other("crashed");
    let c = Run::from_records(
        "C",
        "runs/C",
        vec![
            record("scene_0", &M, s(0.9, 0.5), "p"),
            SceneRecord::failed(SceneName::new("scene_1"), Stage::Load, &err)
                .with_fingerprint(fingerprint("p")),
        ],
    );
    vec![a, b, c]
}

fn paired_options(pairing: Pairing) -> CompareOptions {
    CompareOptions {
        paired: Some(pairing),
        ..CompareOptions::default()
    }
}

#[test]
fn exact_normal_zero_and_single_differences_by_hand() {
    let c = compare(&abc(), &paired_options(Pairing::AgainstFirst)).unwrap();
    assert_eq!(c.pairs.len(), 2, "against the first: (A, B) and (A, C)");
    let ab = &c.pairs[0];
    assert_eq!((ab.a, ab.b), (0, 1));
    let names: Vec<&str> = ab.rows.iter().map(|r| r.column.name).collect();
    assert_eq!(names, ["SUP", "NAV", "OOB"]);
    let [sup, nav, oob] = [&ab.rows[0], &ab.rows[1], &ab.rows[2]];

    // SUP: 5 scenes, one zero; |d| 10, 20, 30, 40 ranked 1..4, R+ = 1 + 2 + 3 = 6, R- = 4.
    // Null counts of R+ for n = 4 (sums 0..10): 1 1 1 2 2 2 2 2 1 1 1 over 16 patterns;
    // P(T >= 6) = (2 + 2 + 1 + 1 + 1) / 16 = 7/16 < P(T <= 6) = 11/16: p = 14/16 = 0.875.
    assert_eq!((sup.n, sup.zeros, sup.method), (5, 1, "exact"));
    assert_eq!(sup.p, Ok(0.875));
    // Mean (0 + 10 + 20 + 30 - 40) / 5 = 4 percentage points (from full-precision values).
    assert!((sup.mean_difference.unwrap() - 4.0).abs() < 1e-9);
    let [lo, hi] = sup.interval.unwrap();
    assert!(lo < 4.0 && 4.0 < hi && lo >= -40.0 && hi <= 30.0, "{lo} {hi}");

    // NAV: differences +10, +10, -10, +20 (one zero): |d| ranks 2, 2, 2, 4 (a tie of three),
    // R+ = 2 + 2 + 4 = 8. Ties: the normal approximation. Mean 4 * 5 / 4 = 5;
    // σ² = (4 * 5 * 9 - (27 - 3) / 2) / 24 = 168 / 24 = 7; z = (8 - 5 - 0.5) / √7.
    assert_eq!((nav.n, nav.zeros, nav.method), (5, 1, "normal"));
    let p_nav = 2.0 * normal_cdf(-2.5 / 7f64.sqrt());
    assert!((nav.p.unwrap() - p_nav).abs() < 1e-12, "{:?} {p_nav}", nav.p);
    assert!((p_nav - 0.344_705).abs() < 1e-5);
    assert!((nav.mean_difference.unwrap() - 6.0).abs() < 1e-9);

    // OOB: every difference zero: the mean is 0, its interval [0, 0], and no p-value.
    assert_eq!((oob.n, oob.zeros), (5, 5));
    assert_eq!(oob.mean_difference, Some(0.0));
    assert_eq!(oob.interval, Some([0.0, 0.0]));
    assert_eq!(oob.p, Err(sceneeval_stats::Undefined::TooFewDifferences));
    assert_eq!(oob.p_holm, None);
    assert_eq!(
        oob.note().unwrap(),
        "no p-value: 0 non-zero difference(s) of 5 scene(s), a test needs at least two"
    );

    // Holm over the two p-values of the pair (m = 2): NAV 2 p_nav = 0.689 first, then SUP
    // max(0.689, 1 * 0.875) = 0.875.
    assert!((nav.p_holm.unwrap() - 2.0 * p_nav).abs() < 1e-12);
    assert_eq!(sup.p_holm, Some(0.875));
    assert!(!sup.significant(0.05) && !nav.significant(0.05));
    // SUP favours B (higher is better and the mean difference is positive).
    assert_eq!(sup.favours_b(), Some(true));

    // (A, C): one scene both have, one non-zero difference: no p-value, with a note; the
    // scenes C lacks or failed are named.
    let ac = &c.pairs[1];
    assert_eq!((ac.rows[0].n, ac.rows[0].zeros), (1, 0));
    assert!((ac.rows[0].mean_difference.unwrap() - 40.0).abs() < 1e-9);
    assert!(ac.rows[0].p.is_err());
    assert_eq!(
        ac.notes,
        [
            "A and C: 4 scene(s) not evaluated by both, left out of their paired statistics: scene_1 (failed in C), \
          scene_2 (not in C), scene_3 (not in C), scene_4 (not in C)."
        ]
    );
    let notes = c.paired_notes();
    assert!(
        notes.contains(
            &"C - A, SUP: no p-value: 1 non-zero difference(s) of 1 scene(s), a test needs at least two."
                .to_owned()
        ),
        "{notes:?}"
    );

    // CSV: the issue's columns first; p-values in full precision, empty where there is none.
    let csv = c.to_paired_csv().unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "kind,a,b,metric,n,mean_diff,diff_low,diff_high,p_value,p_holm,better,method,zeros,a_only,b_only,favours,note"
    );
    let sup_row: Vec<&str> = lines[1].split(',').collect();
    assert_eq!(&sup_row[..5], ["paired", "A", "B", "SUP", "5"]);
    assert_eq!(sup_row[5], "4.000000");
    assert_eq!(
        &sup_row[8..16],
        ["0.875", "0.875", "higher", "exact", "1", "", "", "B"]
    );
    let nav_row: Vec<&str> = lines[2].split(',').collect();
    assert_eq!(nav_row[8].parse::<f64>().unwrap(), nav.p.unwrap());
    assert!(
        lines[3].starts_with("paired,A,B,OOB,5,0.000000,0.000000,0.000000,,,lower,none,5,,,,\"no p-value"),
        "{csv}"
    );
    assert!(
        lines[4]
            .starts_with("paired,A,C,SUP,1,40.000000,40.000000,40.000000,,,higher,none,0,,,C,\"no p-value"),
        "{csv}"
    );

    // Markdown and LaTeX carry the table of differences, the notes and the legend.
    let md = c.to_markdown();
    assert!(md.contains("### Paired differences (b - a)"), "{md}");
    assert!(md.contains("| A | B | SUP ↑ | 5 | +4.00 | ["), "{md}");
    assert!(md.contains("| 0.875 | 0.875 |  |"), "{md}");
    assert!(
        md.contains("| A | B | OOB ↓ | 5 | +0.00 | [+0.00, +0.00] | - | - |  |"),
        "{md}"
    );
    assert!(md.contains("two-sided Wilcoxon signed-rank test"), "{md}");
    let latex = c.to_latex();
    assert!(
        latex.contains(r"A & B & SUP $\uparrow$ & 5 & +4.00 & ["),
        "{latex}"
    );
    assert!(
        latex.contains("% Note: A and C: 4 scene(s) not evaluated by both"),
        "{latex}"
    );
    // The LaTeX row is the Markdown one's cells (without the favoured run), in LaTeX.
    assert!(
        latex.contains("\nA & B & OOB $\\downarrow$ & 5 & +0.00 & [+0.00, +0.00] & - & - \\\\\n"),
        "{latex}"
    );
    use crate::compare::paired_text::Style;
    let (md_cells, tex_cells) = (c.paired_cells(&Style::MARKDOWN), c.paired_cells(&Style::LATEX));
    assert_eq!(md_cells.len(), tex_cells.len());
    for (m, t) in md_cells.iter().zip(&tex_cells) {
        assert_eq!(m[3..], t[3..], "{m:?} {t:?}");
    }
    let html = c.to_html(std::path::Path::new("."));
    assert!(html.contains("<table id=\"paired\">"), "{html}");
    assert!(
        html.contains("<td>SUP ↑</td><td class=\"num\">5</td><td class=\"num\">+4.00</td>"),
        "{html}"
    );
    assert!(
        html.contains("<li>C: 3 of 5 scenes missing (scene_2, scene_3, scene_4), 1 failed (scene_1)</li>")
    );
}

#[test]
fn every_pair_and_warnings_for_other_plans_and_presets() {
    let mut runs = abc();
    runs.truncate(2);
    // B's records made with another plan and the reference preset.
    runs[1].records = runs[1]
        .records
        .iter()
        .map(|r| {
            let mut f = fingerprint("other");
            f.preset = Some(Preset::Reference);
            r.clone().with_fingerprint(f)
        })
        .collect();
    runs.push(run("D", &[(0.5, 0.5); 5]));
    let c = compare(&runs, &paired_options(Pairing::All)).unwrap();
    let pairs: Vec<(usize, usize)> = c.pairs.iter().map(|p| (p.a, p.b)).collect();
    assert_eq!(pairs, [(0, 1), (0, 2), (1, 2)]);
    assert_eq!(
        c.pairs[0].notes,
        [
            "A and B used different plans (result digests): A p, B other; their differences may not be comparable.",
            "A and B used different presets: A default, B reference; their differences may not be comparable."
        ]
    );
    assert!(c.pairs[1].notes.is_empty(), "A and D: same plan and preset");
}

#[test]
fn tested_ranks_share_a_place_until_a_test_separates_runs() {
    // SUP on 8 scenes. A: 50 everywhere. B: 55, 60, ..., 90 (differences to A +5 ... +40,
    // untied): exact p = 2 / 2^8 = 0.0078 < 0.05, B beats A. C: A but 51 on scene_0: one
    // non-zero difference to A, no test, they share a rank; C to B: +4, +10, ..., +40,
    // untied and of one sign: p = 0.0078, B beats C.
    let a = run("A", &[(0.5, 0.5); 8]);
    let b: Vec<(f64, f64)> = (1..=8).map(|k| (0.5 + 0.05 * f64::from(k), 0.5)).collect();
    let b = run("B", &b);
    let mut c: Vec<(f64, f64)> = vec![(0.5, 0.5); 8];
    c[0].0 = 0.51;
    let c = run("C", &c);
    let runs = [a, b, c];
    let tested = compare(&runs, &CompareOptions::default()).unwrap();
    let sup =
        |c: &Comparison| -> Vec<Option<usize>> { c.tables[0].cells.iter().map(|r| r[0].rank).collect() };
    assert_eq!(sup(&tested), [Some(2), Some(1), Some(2)]);
    // NAV and OOB: equal everywhere, everyone first.
    assert!(tested.tables[0].cells.iter().all(|r| r[1].rank == Some(1)));
    // Bold follows the best value whatever the ranking: B's SUP; italic: C's (second by value).
    assert_eq!(tested.tables[0].cells[1][0].emphasis(), Emphasis::Bold);
    assert_eq!(tested.tables[0].cells[2][0].emphasis(), Emphasis::Italic);
    // By mean: B 1, C 2 (50.125), A 3.
    let by_mean = compare(
        &runs,
        &CompareOptions {
            rank: RankBy::Mean,
            ..CompareOptions::default()
        },
    )
    .unwrap();
    assert_eq!(sup(&by_mean), [Some(3), Some(1), Some(2)]);
    assert!(by_mean.legend().contains("Ranks by mean (--rank mean)"));
    assert!(
        tested
            .legend()
            .contains("Holm-adjusted across the pair's columns, p < 0.05")
    );
    // A stricter alpha: 0.0078 > 0.005, nobody separated.
    let strict = compare(
        &runs,
        &CompareOptions {
            alpha: 0.005,
            ..CompareOptions::default()
        },
    )
    .unwrap();
    assert_eq!(sup(&strict), [Some(1), Some(1), Some(1)]);
    assert!(matches!(
        compare(
            &runs,
            &CompareOptions {
                alpha: 1.5,
                ..CompareOptions::default()
            }
        ),
        Err(ReportError::Alpha(_))
    ));
}

#[test]
fn failed_and_missing_scenes_at_the_worst_value() {
    // X: SUP 100, OOB 0 on three scenes. Y: scene_0 the same, scene_1 failed, scene_2 missing.
    let m = [P::Support, P::OutOfBounds];
    let good = || PlausibilitySummary {
        sup: Some(1.0),
        oob: Some(0.0),
        ..PlausibilitySummary::default()
    };
    let x = Run::from_records(
        "X",
        "x",
        (0..3)
            .map(|k| record(&format!("scene_{k}"), &m, good(), "p"))
            .collect(),
    );
    let err = std::io::Error::other("crashed");
    let y = Run::from_records(
        "Y",
        "y",
        vec![
            record("scene_0", &m, good(), "p"),
            SceneRecord::failed(SceneName::new("scene_1"), Stage::Load, &err),
        ],
    );
    let runs = [x, y];
    // Skipped: both 100 / 0 over scene_0 alone.
    let skip = compare(&runs, &CompareOptions::default()).unwrap();
    assert_eq!(skip.tables[0].cells[1][0].value, Some(100.0));
    assert_eq!(skip.tables[0].scenes, 1);
    // Worst: Y's SUP (100 + 0 + 0) / 3, OOB (0 + 100 + 100) / 3, over the 3 scenes.
    let worst = compare(
        &runs,
        &CompareOptions {
            failed: FailedScenes::Worst,
            ..CompareOptions::default()
        },
    )
    .unwrap();
    let t = &worst.tables[0];
    assert_eq!(t.scenes, 3);
    assert!((t.cells[1][0].value.unwrap() - 100.0 / 3.0).abs() < 1e-12);
    assert!((t.cells[1][1].value.unwrap() - 200.0 / 3.0).abs() < 1e-12);
    assert_eq!((t.cells[1][0].n, t.cells[0][0].value), (3, Some(100.0)));
    assert!(
        worst
            .notes
            .iter()
            .any(|n| n.starts_with("Values over every scene of any run (3)"))
    );
    assert!(
        worst
            .legend()
            .contains("a failed or missing scene at the column's worst value")
    );
    assert_eq!(
        worst.coverage_lines(),
        ["Y: 1 of 3 scenes missing (scene_2), 1 failed (scene_1)"]
    );
}

#[test]
fn a_column_no_run_has_a_value_in_is_left_out() {
    // ACC has no value in any run (no object with functional sides): left out, with a note.
    let m = [P::Navigability, P::Accessibility];
    let nav = || PlausibilitySummary {
        nav: Some(1.0),
        acc: None,
        ..PlausibilitySummary::default()
    };
    let a = Run::from_records("A", "a", vec![record("scene_0", &m, nav(), "p")]);
    let b = Run::from_records("B", "b", vec![record("scene_0", &m, nav(), "p")]);
    let c = compare(&[a, b], &paired_options(Pairing::All)).unwrap();
    let names: Vec<&str> = c.columns.iter().map(|c| c.name).collect();
    assert_eq!(names, ["NAV"]);
    assert!(
        c.notes
            .contains(&"ACC left out: no run has a value in it.".to_owned()),
        "{:?}",
        c.notes
    );
    let md = c.to_markdown();
    assert!(!md.contains("ACC ↑") && !md.contains("| ACC |"), "{md}");
    assert!(!c.to_latex().contains("ACC $"));
    assert_eq!(c.pairs[0].rows.len(), 1);
}

/// A record of `name` with CNT specs of these verdicts (`None`: not judged).
fn cnt_record(name: &str, verdicts: &[Option<bool>]) -> SceneRecord {
    let specs: Vec<serde_json::Value> = verdicts
        .iter()
        .enumerate()
        .map(|(k, v)| {
            serde_json::json!({
                "spec": format!("eq,1,thing{k}"), "quantifier": "eq", "quantity": 1,
                "category": format!("thing{k}"), "objects": [], "count_in_scene": 1, "satisfied": v
            })
        })
        .collect();
    let judged: Vec<bool> = verdicts.iter().flatten().copied().collect();
    let share = judged.iter().filter(|v| **v).count() as f64 / judged.len() as f64;
    let fidelity: FidelityReport = serde_json::from_value(serde_json::json!({
        "relation_mapping": "lexicon",
        "cnt": {"message": "", "satisfied": 0, "total": verdicts.len(), "score": share, "specs": specs},
        "summary": {"cnt": share, "atr": null, "oor": null, "oar": null}
    }))
    .unwrap();
    let geometry = PlausibilityReport::of_summary(
        Some(name.into()),
        vec![P::Support],
        PlausibilitySummary {
            sup: Some(1.0),
            ..PlausibilitySummary::default()
        },
    );
    let mut f = fingerprint("p");
    f.annotation = Some("row-digest".to_owned());
    SceneRecord::ok(
        SceneName::new(name),
        SceneReport::new(Some(name.into()), geometry, Some(fidelity)),
    )
    .with_fingerprint(f)
}

#[test]
fn mcnemar_on_the_specs_both_runs_judged() {
    let t = Some(true);
    let f = Some(false);
    // Scene 0: (a, b) = (t, t), (t, f), (f, t), (f, t); scene 1: (f, t), (f, t), (None, t),
    // (f, f). Judged in both: 7; a only b = 1, b only c = 4: p = 2 P(X <= 1), X ~ B(5, 1/2)
    // = 2 * 6/32 = 0.375. Difference (4 - 1) / 7 = +42.86 points.
    let a = Run::from_records(
        "A",
        "a",
        vec![
            cnt_record("scene_0", &[t, t, f, f]),
            cnt_record("scene_1", &[f, f, None, f]),
        ],
    );
    let b = Run::from_records(
        "B",
        "b",
        vec![
            cnt_record("scene_0", &[t, f, t, t]),
            cnt_record("scene_1", &[t, t, t, f]),
        ],
    );
    let c = compare(&[a, b], &paired_options(Pairing::All)).unwrap();
    let v = &c.pairs[0].verdicts;
    assert_eq!(v.len(), 1);
    assert_eq!(v[0].metric, Metric::Cnt);
    assert_eq!((v[0].n, v[0].test.b, v[0].test.c), (7, 1, 4));
    assert_eq!(v[0].test.p, 0.375);
    assert_eq!(v[0].p_holm, Some(0.375));
    assert!((v[0].difference().unwrap() - 300.0 / 7.0).abs() < 1e-12);
    let csv = c.to_paired_csv().unwrap();
    assert!(
        csv.contains("\nmcnemar,A,B,CNT,7,42.857143,,,0.375,0.375,higher,exact,,1,4,B,\n"),
        "{csv}"
    );
    assert!(
        c.to_markdown()
            .contains("| A | B | CNT | 7 | 1 | 4 | +42.86 | 0.375 | 0.375 |")
    );
    let latex = c.to_latex();
    assert!(
        latex.contains("\nA & B & CNT & 7 & 1 & 4 & +42.86 & 0.375 & 0.375 \\\\\n"),
        "{latex}"
    );
    // The HTML row is the same cells.
    let html = c.to_html(std::path::Path::new("."));
    assert!(
        html.contains(
            "<tr><td>A</td><td>B</td><td>CNT</td><td class=\"num\">7</td><td class=\"num\">1</td><td class=\"num\">4</td>\
             <td class=\"num\">+42.86</td><td class=\"num\">0.375</td><td class=\"num\">0.375</td></tr>"
        ),
        "{html}"
    );
}
