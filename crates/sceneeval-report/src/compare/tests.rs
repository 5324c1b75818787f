//! Hand-computed comparisons: the arithmetic of every expected value is in the comments.

use std::collections::BTreeMap;

use sceneeval_plausibility::{self as plausibility, PlausibilityReport, PlausibilitySummary};
use sceneeval_results::{
    FileDigest, Fingerprint, Preset, SceneName, SceneRecord, SceneReport, Stage, TOOL_VERSION,
};

use super::*;

type P = plausibility::Metric;

/// A record of `name` that ran `metrics` and found `summary`, with a fingerprint of `plan`.
pub(super) fn record(name: &str, metrics: &[P], summary: PlausibilitySummary, plan: &str) -> SceneRecord {
    let geometry = PlausibilityReport::of_summary(Some(name.into()), metrics.to_vec(), summary);
    SceneRecord::ok(
        SceneName::new(name),
        SceneReport::new(Some(name.into()), geometry, None),
    )
    .with_fingerprint(fingerprint(plan))
}

pub(super) fn fingerprint(plan: &str) -> Fingerprint {
    Fingerprint {
        tool: TOOL_VERSION.to_owned(),
        schema: sceneeval_results::RECORD_SCHEMA.to_owned(),
        scene: FileDigest {
            path: "scenes/x.json".into(),
            blake3: None,
        },
        plan: plan.to_owned(),
        preset: Some(Preset::Default),
        annotation: None,
        assets: vec![],
    }
}

/// Ranks by mean, as before `--rank tested`.
fn by_mean() -> CompareOptions {
    CompareOptions {
        rank: RankBy::Mean,
        ..CompareOptions::default()
    }
}

/// SUP and OOB of one scene.
fn sup_oob(sup: f64, oob: f64) -> PlausibilitySummary {
    PlausibilitySummary {
        sup: Some(sup),
        oob: Some(oob),
        ..PlausibilitySummary::default()
    }
}

/// Three runs of two scenes, SUP (higher is better) and OOB (lower is better):
/// - A: SUP (100 + 50) / 2 = 75, OOB (0 + 50) / 2 = 25;
/// - B: SUP (100 + 50) / 2 = 75, OOB (0 + 0) / 2 = 0;
/// - C: SUP (50 + 50) / 2 = 50, OOB (0 + 100) / 2 = 50.
fn three_runs() -> Vec<Run> {
    let m = [P::Support, P::OutOfBounds];
    let run = |name: &str, s0: (f64, f64), s1: (f64, f64)| {
        Run::from_records(
            name,
            format!("runs/{name}"),
            vec![
                record("scene_1", &m, sup_oob(s1.0, s1.1), "p"),
                record("scene_0", &m, sup_oob(s0.0, s0.1), "p"),
            ],
        )
    };
    vec![
        run("A", (1.0, 0.0), (0.5, 0.5)),
        run("B", (1.0, 0.0), (0.5, 0.0)),
        run("C", (0.5, 0.0), (0.5, 1.0)),
    ]
}

#[test]
fn ties_lower_is_better_and_rank_points_by_hand() {
    let c = compare(&three_runs(), &by_mean()).unwrap();
    assert!(c.notes.is_empty(), "{:?}", c.notes);
    assert_eq!(c.scenes, ["scene_0", "scene_1"]);
    let names: Vec<&str> = c.columns.iter().map(|c| c.name).collect();
    assert_eq!(names, ["SUP", "OOB"]);
    let t = &c.tables[0];
    let values: Vec<Vec<Option<f64>>> = t
        .cells
        .iter()
        .map(|r| r.iter().map(|c| c.value).collect())
        .collect();
    assert_eq!(
        values,
        [
            [Some(75.0), Some(25.0)],
            [Some(75.0), Some(0.0)],
            [Some(50.0), Some(50.0)]
        ]
    );
    // SUP: A and B tie first (75), C is third (competition ranking: no second).
    // OOB, lower is better: B first (0), A second (25), C third (50).
    let ranks: Vec<Vec<Option<usize>>> = t
        .cells
        .iter()
        .map(|r| r.iter().map(|c| c.rank).collect())
        .collect();
    assert_eq!(
        ranks,
        [[Some(1), Some(2)], [Some(1), Some(1)], [Some(3), Some(3)]]
    );
    // Points N - rank + 1 with N = 3: A 3 + 2 = 5, B 3 + 3 = 6, C 1 + 1 = 2.
    let points: Vec<usize> = t.standings.iter().map(|s| s.points).collect();
    assert_eq!(points, [5, 6, 2]);
    // Average ranks: A (1 + 2) / 2 = 1.5, B 1, C 3. Places: B first, A second, C third.
    let avg: Vec<Option<f64>> = t.standings.iter().map(|s| s.average_rank).collect();
    assert_eq!(avg, [Some(1.5), Some(1.0), Some(3.0)]);
    let places: Vec<[usize; 3]> = t.standings.iter().map(|s| s.places).collect();
    assert_eq!(places, [[1, 1, 0], [2, 0, 0], [0, 0, 2]]);
    let place: Vec<usize> = t.standings.iter().map(|s| s.place).collect();
    assert_eq!(place, [2, 1, 3]);

    let legend = c.legend();
    assert_eq!(
        c.to_markdown(),
        format!(
            "### all (2 scenes)\n\n\
             | run | SUP ↑ | OOB ↓ |\n\
             |---|---:|---:|\n\
             | A | **75.00** (2) | *25.00* (2) |\n\
             | B | **75.00** (2) | **0.00** (2) |\n\
             | C | 50.00 (2) | 50.00 (2) |\n\
             \n\
             - Every run has all 2 scenes, none failed.\n\
             \n\
             | place | run | points | average rank | 1st | 2nd | 3rd | SUP | OOB |\n\
             |---:|---|---:|---:|---:|---:|---:|---:|---:|\n\
             | 1 | B | 6 | 1.00 | 2 | 0 | 0 | 1 | 1 |\n\
             | 2 | A | 5 | 1.50 | 1 | 1 | 0 | 1 | 2 |\n\
             | 3 | C | 2 | 3.00 | 0 | 0 | 2 | 3 | 3 |\n\
             \n\
             {legend}\n"
        )
    );
    assert_eq!(
        c.to_csv().unwrap(),
        "group,scenes,run,column,better,value,n,ci_low,ci_high,rank,points,missing,failed\n\
         all,2,A,SUP,higher,75.0000,2,,,1,3,,\n\
         all,2,A,OOB,lower,25.0000,2,,,2,2,,\n\
         all,2,B,SUP,higher,75.0000,2,,,1,3,,\n\
         all,2,B,OOB,lower,0.0000,2,,,1,3,,\n\
         all,2,C,SUP,higher,50.0000,2,,,3,1,,\n\
         all,2,C,OOB,lower,50.0000,2,,,3,1,,\n"
    );
    let latex = c.to_latex();
    let table: Vec<&str> = latex.lines().filter(|l| !l.starts_with('%')).collect();
    assert_eq!(
        table,
        [
            r"\begin{tabular}{lrrrrrrr}",
            r"\toprule",
            r"Method & SUP $\uparrow$ & OOB $\downarrow$ & Points & Avg.\ rank & 1st & 2nd & 3rd \\",
            r"\midrule",
            r"A & \textbf{75.00} {\scriptsize (2)} & \textit{25.00} {\scriptsize (2)} & 5 & 1.50 & 1 & 1 & 0 \\",
            r"B & \textbf{75.00} {\scriptsize (2)} & \textbf{0.00} {\scriptsize (2)} & 6 & 1.00 & 2 & 0 & 0 \\",
            r"C & 50.00 {\scriptsize (2)} & 50.00 {\scriptsize (2)} & 2 & 3.00 & 0 & 0 & 2 \\",
            r"\multicolumn{8}{l}{\footnotesize Every run has all 2 scenes, none failed.} \\",
            r"\bottomrule",
            r"\end{tabular}",
        ]
    );
    assert!(latex.starts_with("% sceneeval compare: A, B, C\n"), "{latex}");
}

#[test]
fn a_metric_missing_from_one_run_failed_and_partial_scenes_and_other_plans_are_noted() {
    let both = [P::Collision, P::Support];
    let sup = |s: f64| PlausibilitySummary {
        sup: Some(s),
        col_ob: Some(0.0),
        col_sc: Some(false),
        ..PlausibilitySummary::default()
    };
    let err = std::io::Error::other("asset missing");
    let a = Run::from_records(
        "A",
        "runs/a",
        vec![
            record("scene_0", &both, sup(1.0), "aaaa"),
            record("scene_1", &both, sup(0.5), "aaaa"),
            record("scene_2", &both, sup(1.0), "aaaa"),
            // Partial: the run ran support, this scene has none.
            record("scene_3", &[P::Collision], sup(1.0), "aaaa"),
            // Status partial: support listed as not computed (its value is not compared).
            {
                let r = record("scene_5", &both, sup(1.0), "aaaa");
                let report = r.report().unwrap().clone().with_incomplete(vec![
                    sceneeval_results::IncompleteMetric::new(Metric::Support, false, &err),
                ]);
                SceneRecord::ok(SceneName::new("scene_5"), report).with_fingerprint(fingerprint("aaaa"))
            },
        ],
    );
    let b = Run::from_records(
        "B",
        "runs/b",
        vec![
            record("scene_0", &[P::Support], sup(0.0), "bbbb"),
            record("scene_1", &[P::Support], sup(1.0), "bbbb"),
            SceneRecord::failed(SceneName::new("scene_2"), Stage::Load, &err),
            record("scene_3", &[P::Support], sup(1.0), "bbbb"),
            record("scene_4", &[P::Support], sup(1.0), "bbbb"),
            record("scene_5", &[P::Support], sup(1.0), "bbbb"),
        ],
    );
    let c = compare(&[a, b], &by_mean()).unwrap();
    // Only SUP is shared; collision is A's alone.
    let names: Vec<&str> = c.columns.iter().map(|c| c.name).collect();
    assert_eq!(names, ["SUP"]);
    assert_eq!(c.scenes, ["scene_0", "scene_1"]);
    assert_eq!(
        c.notes,
        [
            "COL_ob, COL_sc (collision) left out: not evaluated by B.",
            "The runs used different plans (result digests: metrics or parameters differ): A aaaa, B bbbb; their \
             numbers may not be comparable.",
            "Compared on the 2 of 6 scenes every run evaluated in full; left out: scene_2 (failed in B), scene_3 \
             (partial in A: no support), scene_4 (not in A), scene_5 (partial in A: no support).",
        ]
    );
    // SUP over scene_0 and scene_1 only: A (100 + 50) / 2 = 75, B (0 + 100) / 2 = 50.
    let t = &c.tables[0];
    assert_eq!(t.cells[0][0].value, Some(75.0));
    assert_eq!(t.cells[1][0].value, Some(50.0));
    assert_eq!((t.cells[0][0].n, t.cells[1][0].n), (2, 2));
    // Two runs: A first (2 points), B second (1 point).
    assert_eq!((t.cells[0][0].points, t.cells[1][0].points), (2, 1));
    let md = c.to_markdown();
    assert!(
        md.contains("Notes:\n\n- COL\\_ob, COL\\_sc (collision) left out"),
        "{md}"
    );
    // Every table names what each run lacks among the 6 scenes of either run.
    assert_eq!(
        c.coverage_lines(),
        [
            "A: 1 of 6 scenes missing (scene_4)",
            "B: 1 of 6 scenes failed (scene_2)"
        ]
    );
    assert!(
        md.contains("- A: 1 of 6 scenes missing (scene\\_4)\n- B: 1 of 6 scenes failed (scene\\_2)\n"),
        "{md}"
    );
    let csv = c.to_csv().unwrap();
    assert!(
        csv.contains("\nall,2,A,SUP,higher,75.0000,2,,,1,2,scene_4,\n"),
        "{csv}"
    );
    assert!(
        csv.contains("\nall,2,B,SUP,higher,50.0000,2,,,2,1,,scene_2\n"),
        "{csv}"
    );
    let latex = c.to_latex();
    assert!(
        latex.contains(r"\multicolumn{7}{l}{\footnotesize B: 1 of 6 scenes failed (scene\_2)} \\"),
        "{latex}"
    );
}

#[test]
fn a_column_without_values_is_not_ranked_and_names_are_escaped() {
    // ACC has a value only where an object has functional sides: run "x|y" has none.
    let acc = |v: Option<f64>| PlausibilitySummary {
        acc: v,
        nav: Some(1.0),
        ..PlausibilitySummary::default()
    };
    let m = [P::Navigability, P::Accessibility];
    let a = Run::from_records("x|y", "a", vec![record("scene_0", &m, acc(None), "p")]);
    let b = Run::from_records("*b*", "b", vec![record("scene_0", &m, acc(Some(0.5)), "p")]);
    let c = compare(&[a, b], &CompareOptions::default()).unwrap();
    let t = &c.tables[0];
    // NAV: both 100, tied first, 2 points each. ACC: only *b* has a value: first of N = 1, 1 point.
    assert_eq!(t.cells[0][1].value, None);
    assert_eq!(
        (t.cells[0][1].rank, t.cells[0][1].points, t.cells[0][1].n),
        (None, 0, 0)
    );
    assert_eq!((t.cells[1][1].rank, t.cells[1][1].points), (Some(1), 1));
    assert_eq!((t.standings[0].points, t.standings[1].points), (2, 3));
    let md = c.to_markdown();
    assert!(md.contains("| x\\|y | **100.00** (1) | - (0) |"), "{md}");
    assert!(md.contains("| \\*b\\* |"), "{md}");
    assert!(c.to_latex().contains("x|y & "), "LaTeX needs no escape for |");
}

#[test]
fn by_difficulty_and_intervals() {
    let mut runs = three_runs();
    let d: BTreeMap<String, String> = [("scene_0", "easy"), ("scene_1", "hard")]
        .map(|(s, d)| (s.to_owned(), d.to_owned()))
        .into_iter()
        .collect();
    runs[0] = runs[0].clone().with_difficulties(d);
    let options = CompareOptions {
        by_difficulty: true,
        ci: Some(0.95),
        ..CompareOptions::default()
    };
    let c = compare(&runs, &options).unwrap();
    let groups: Vec<(&str, usize)> = c.tables.iter().map(|t| (t.group.as_str(), t.scenes)).collect();
    assert_eq!(groups, [("all", 2), ("easy", 1), ("hard", 1)]);
    // Easy is scene_0 alone: SUP A 100, B 100, C 50.
    let easy: Vec<Option<f64>> = c.tables[1].cells.iter().map(|r| r[0].value).collect();
    assert_eq!(easy, [Some(100.0), Some(100.0), Some(50.0)]);
    // One scene: every resample is that scene, the interval is the value.
    assert_eq!(c.tables[1].cells[0][0].ci, Some([100.0, 100.0]));
    // Two scenes 100 and 50 (A's SUP): means 100, 75, 50 with probabilities 1/4, 1/2, 1/4, so
    // the 2.5 % and 97.5 % quantiles are 50 and 100.
    assert_eq!(c.tables[0].cells[0][0].ci, Some([50.0, 100.0]));
    assert!(c.to_markdown().contains("| A | **75.00** (2) [50.00, 100.00] |"));
    assert!(
        c.legend()
            .contains("95% bootstrap interval over scenes (1000 resamples")
    );
    assert!(
        c.to_latex()
            .contains(r"\multicolumn{8}{l}{\textit{easy (1 scene)}} \\")
    );
    assert!(matches!(
        compare(
            &runs,
            &CompareOptions {
                ci: Some(1.0),
                ..CompareOptions::default()
            }
        ),
        Err(ReportError::ConfidenceLevel(_))
    ));
    assert!(matches!(
        compare(&[], &CompareOptions::default()),
        Err(ReportError::NoRuns)
    ));
    // Without difficulties, --by difficulty says so.
    let c = compare(&three_runs(), &options).unwrap();
    assert_eq!(c.tables.len(), 1);
    assert!(c.notes[0].starts_with("No run has difficulties"), "{:?}", c.notes);
}

#[test]
fn csv_cells_a_spreadsheet_would_run_are_escaped_and_numbers_are_not() {
    // Run names are the user's (`--names`, folder names): a formula is written as text.
    let mut runs = three_runs();
    runs[0] = runs[0].clone().with_name("=HYPERLINK(\"http://x\",\"A\")");
    runs[1] = runs[1].clone().with_name("-B");
    let csv = compare(&runs, &by_mean()).unwrap().to_csv().unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[1],
        "all,2,\"'=HYPERLINK(\"\"http://x\"\",\"\"A\"\")\",SUP,higher,75.0000,2,,,1,3,,"
    );
    assert_eq!(lines[4], "all,2,'-B,OOB,lower,0.0000,2,,,1,3,,");
    assert_eq!(lines[6], "all,2,C,OOB,lower,50.0000,2,,,3,1,,");
}
