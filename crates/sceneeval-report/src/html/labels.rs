//! The people's verdicts in a run's report (`sceneeval report RUN --labels LABELS...`): on the
//! overview page the agreement table (the rows and numbers `sceneeval agreement --reference
//! LABELS RUN` prints: the run against the annotators' majority, the annotators' pairs and
//! Fleiss' kappa), with the specs where the run and the people disagree linked to their
//! scenes; on each scene page those specs marked (`table#disagreements`, `tr.disagree`).
//! Nothing is shown for a report without labels ([`Run::labels`] is `None`).

use std::collections::BTreeMap;
use std::fmt::Write as _;

use sceneeval_results::SceneRecord;

use crate::Run;
use crate::agreement::text::{kappa_cell, percent, verdict_word};
use crate::agreement::{Agreement, RowKind, WrongItem};
use crate::escape::html;

/// The items `agreement` lists as the run's disagreements with the people, for `scene` or all
/// (`scene` = `None`).
fn disagreements<'a>(
    agreement: &'a Agreement,
    run: &'a str,
    scene: Option<&'a str>,
) -> impl Iterator<Item = &'a WrongItem> {
    agreement
        .wrong
        .iter()
        .filter(move |w| w.judge == run && scene.is_none_or(|s| w.scene == s))
}

/// The mark of a spec where the run and the people disagree.
const MARK: &str = "⚑";

/// The overview page's section (`section#labels`): the agreement table, the notes, and the
/// specs the run got wrong, each linked to its scene's page (`pages`: scene to URL).
pub(crate) fn overview_section(b: &mut String, run: &Run, pages: &BTreeMap<String, String>) {
    let Some(a) = run.labels() else {
        return;
    };
    let _ = write!(
        b,
        "<section id=\"labels\"><h2>Agreement with people</h2><p>Reference: the majority of {} ({} item(s) with \
         tied annotators left out). The same numbers as <code>sceneeval agreement --reference LABELS RUN</code>.</p>",
        html(&a.reference.join(", ")),
        a.reference_ties
    );
    let heads = a.heads();
    b.push_str("<div class=\"wide\"><table id=\"agreement\"><thead><tr><th>rater</th>");
    for h in &heads {
        let _ = write!(
            b,
            "<th class=\"num\">{0} %</th><th class=\"num\">{0} κ</th>",
            html(h)
        );
    }
    b.push_str("<th class=\"num\">n (all)</th></tr></thead><tbody>");
    for line in a.lines(&[RowKind::Judge, RowKind::Annotators, RowKind::Fleiss]) {
        let name = match line.kind {
            RowKind::Judge => format!("{} (this run)", line.a),
            RowKind::Fleiss => format!("Fleiss' κ, all {} annotators", a.reference.len()),
            RowKind::Annotators | RowKind::Pair => format!("{} vs {}", line.a, line.b),
        };
        let _ = write!(b, "<tr class=\"{}\"><td>{}</td>", line.kind.name(), html(&name));
        for cell in &line.cells {
            let _ = write!(
                b,
                "<td class=\"num\">{}</td><td class=\"num\">{}</td>",
                percent(cell.agreement),
                html(&kappa_cell(cell))
            );
        }
        let _ = write!(
            b,
            "<td class=\"num\">{}</td></tr>",
            line.cells.last().map_or(0, |c| c.n)
        );
    }
    b.push_str("</tbody></table></div>");
    let _ = write!(b, "<p class=\"muted\">{}</p>", html(&a.legend()));
    let notes: Vec<String> = a
        .undefined_reasons()
        .into_iter()
        .chain(a.notes.iter().cloned())
        .collect();
    if !notes.is_empty() {
        b.push_str("<ul class=\"muted\">");
        for n in &notes {
            let _ = write!(b, "<li>{}</li>", html(n));
        }
        b.push_str("</ul>");
    }
    let wrong: Vec<&WrongItem> = disagreements(a, &run.name, None).collect();
    let _ = write!(
        b,
        "<h3>Specs where the run and the people disagree ({})</h3>",
        wrong.len()
    );
    if wrong.is_empty() {
        b.push_str("<p>None: the run agrees with the people on every spec both judged.</p>");
    } else {
        b.push_str("<ul id=\"disagreements\">");
        for w in wrong {
            let scene = match pages.get(&w.scene) {
                Some(href) => format!("<a href=\"{}\">{}</a>", html(href), html(&w.scene)),
                None => html(&w.scene),
            };
            let _ = write!(
                b,
                "<li>{MARK} {scene}, {} {}: <code>{}</code>: run {}, people {}</li>",
                w.metric.name().to_uppercase(),
                w.index,
                html(&w.spec),
                verdict_word(w.verdict),
                verdict_word(w.reference)
            );
        }
        b.push_str("</ul>");
    }
    b.push_str("</section>");
}

/// A scene page's section (`section#labels`): the specs of `record`'s scene where the run and
/// the people disagree, marked, with both verdicts; nothing without labels.
pub(crate) fn scene_section(b: &mut String, run: &str, labels: Option<&Agreement>, record: &SceneRecord) {
    let Some(a) = labels else {
        return;
    };
    let scene = record.scene.as_str();
    let wrong: Vec<&WrongItem> = disagreements(a, run, Some(scene)).collect();
    let _ = write!(
        b,
        "<section id=\"labels\"><h2>People's verdicts</h2><p>Reference: the majority of {}.</p>",
        html(&a.reference.join(", "))
    );
    if wrong.is_empty() {
        b.push_str("<p>No spec of this scene where the run and the people disagree.</p></section>");
        return;
    }
    b.push_str(
        "<table id=\"disagreements\"><thead><tr><th></th><th>metric</th><th class=\"num\">index</th><th>spec</th>\
         <th>run</th><th>people</th></tr></thead><tbody>",
    );
    for w in wrong {
        let _ = write!(
            b,
            "<tr class=\"disagree\"><td class=\"bad\" title=\"the run and the people disagree\">{MARK}</td><td>{}</td>\
             <td class=\"num\">{}</td><td><code>{}</code></td><td>{}</td><td>{}</td></tr>",
            w.metric.name().to_uppercase(),
            w.index,
            html(&w.spec),
            verdict_word(w.verdict),
            verdict_word(w.reference)
        );
    }
    b.push_str("</tbody></table></section>");
}
