//! The comparison as an HTML page: the tables with their emphasis, the standings, the notes,
//! links to each run's report, and the fidelity specs whose verdicts differ between runs.

use std::fmt::Write as _;
use std::path::Path;

use super::{page, relative_href};
use sceneeval_results::Better;

use crate::compare::paired_text::Style;
use crate::compare::{Comparison, Emphasis, RunHead, SceneDifference, average, standing_order, text_arrow};
use crate::escape::{self, html};
use crate::report::{DEFAULT_DIR, INDEX, SCENES_DIR};

/// The link from the page in `page_dir` to `scene`'s page in the report of `run` where
/// `sceneeval report RUN` writes it by default (`RUN/report/scenes/<scene>.html`, relative),
/// when that file exists; `None` when the run has no report there (a report written elsewhere
/// with `--out` is not found).
fn scene_href(run: &RunHead, scene: &str, page_dir: &Path) -> Option<String> {
    let page = run
        .dir
        .join(DEFAULT_DIR)
        .join(SCENES_DIR)
        .join(format!("{}.html", escape::file_name(scene)));
    page.is_file().then(|| relative_href(page_dir, &page)).flatten()
}

impl Comparison {
    /// The comparison as one self-contained HTML page that will be written into the folder
    /// `page_dir` (links to each run's report, `RUN/report/index.html`, and its scene pages are
    /// relative to it, and given only for reports that exist). Every name is escaped.
    pub fn to_html(&self, page_dir: &Path) -> String {
        let mut b = String::from(
            "<h1>SceneEval comparison</h1><h2>Runs</h2><table id=\"runs\"><thead><tr><th>run</th><th>folder</th><th>report</th></tr></thead><tbody>",
        );
        for run in &self.runs {
            let index = run.dir.join(DEFAULT_DIR).join(INDEX);
            let link = match index.is_file().then(|| relative_href(page_dir, &index)).flatten() {
                Some(href) => format!("<a href=\"{}\">report</a>", html(&href)),
                None => format!(
                    "<span class=\"muted\">none (sceneeval report {})</span>",
                    html(&run.dir.display().to_string())
                ),
            };
            let _ = write!(
                b,
                "<tr><td>{}</td><td><code>{}</code></td><td>{link}</td></tr>",
                html(&run.name),
                html(&run.dir.display().to_string())
            );
        }
        b.push_str("</tbody></table>");
        for (t, table) in self.tables.iter().enumerate() {
            let _ = write!(
                b,
                "<h2>{} ({})</h2><div class=\"wide\"><table class=\"values\" id=\"values-{t}\"><thead><tr><th>run</th>",
                html(&table.group),
                crate::compare::scenes(table.scenes)
            );
            for c in &self.columns {
                let _ = write!(
                    b,
                    "<th class=\"num\">{} {}</th>",
                    html(c.name),
                    text_arrow(c.better)
                );
            }
            b.push_str("</tr></thead><tbody>");
            for (run, row) in self.runs.iter().zip(&table.cells) {
                let _ = write!(b, "<tr><th>{}</th>", html(&run.name));
                for cell in row {
                    let v = match cell.emphasis() {
                        Emphasis::Bold => format!("<strong>{}</strong>", cell.value_text()),
                        Emphasis::Italic => format!("<em>{}</em>", cell.value_text()),
                        Emphasis::Plain => cell.value_text(),
                    };
                    let ci = cell
                        .ci_text()
                        .map(|t| format!(" <small>{t}</small>"))
                        .unwrap_or_default();
                    let _ = write!(
                        b,
                        "<td class=\"num\">{v} <small class=\"muted\">({})</small>{ci}</td>",
                        cell.n
                    );
                }
                b.push_str("</tr>");
            }
            b.push_str("</tbody></table></div><ul class=\"coverage\">");
            for line in self.coverage_lines() {
                let _ = write!(b, "<li>{}</li>", html(&line));
            }
            b.push_str("</ul><div class=\"wide\"><table class=\"standings\"><thead><tr><th class=\"num\">place</th><th>run</th><th class=\"num\">points</th><th class=\"num\">average rank</th><th class=\"num\">1st</th><th class=\"num\">2nd</th><th class=\"num\">3rd</th>");
            for c in &self.columns {
                let _ = write!(b, "<th class=\"num\">{}</th>", html(c.name));
            }
            b.push_str("</tr></thead><tbody>");
            for k in standing_order(table) {
                let s = &table.standings[k];
                let _ = write!(
                    b,
                    "<tr><td class=\"num\">{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>",
                    s.place,
                    html(&self.runs[k].name),
                    s.points,
                    average(s.average_rank),
                    s.places[0],
                    s.places[1],
                    s.places[2]
                );
                for c in &table.cells[k] {
                    let _ = write!(
                        b,
                        "<td class=\"num\">{}</td>",
                        c.rank.map_or("-".to_owned(), |r| r.to_string())
                    );
                }
                b.push_str("</tr>");
            }
            b.push_str("</tbody></table></div>");
        }
        if !self.notes.is_empty() {
            b.push_str("<div class=\"box\" id=\"notes\"><strong>Notes</strong><ul>");
            for note in &self.notes {
                let _ = write!(b, "<li>{}</li>", html(note));
            }
            b.push_str("</ul></div>");
        }
        let _ = write!(b, "<p class=\"muted\">{}</p>", html(&self.legend()));
        self.paired_html(&mut b);
        self.scene_differences_html(&mut b, page_dir);

        b.push_str("<h2>Scene by scene</h2>");
        if self.differences.is_empty() {
            b.push_str("<p id=\"differences\">No fidelity spec of the common scenes has different verdicts in different runs.</p>");
        } else {
            let _ = write!(
                b,
                "<p>Fidelity specs of the common scenes whose verdicts differ between runs: {}.</p>\
                 <div class=\"wide\"><table id=\"differences\" class=\"sortable\"><thead><tr><th>scene</th><th>metric</th><th>spec</th>",
                self.differences.len()
            );
            for run in &self.runs {
                let _ = write!(b, "<th>{}</th>", html(&run.name));
            }
            b.push_str("</tr></thead><tbody>");
            for d in &self.differences {
                let _ = write!(
                    b,
                    "<tr><td>{}</td><td>{}</td><td><code>{}</code></td>",
                    html(&d.scene),
                    html(d.metric.columns()[0]),
                    html(&d.spec)
                );
                for (run, v) in self.runs.iter().zip(&d.verdicts) {
                    let text = match scene_href(run, &d.scene, page_dir) {
                        Some(href) => format!("<a href=\"{}\">{}</a>", html(&href), v.name()),
                        None => v.name().to_owned(),
                    };
                    let class = match v {
                        crate::compare::Verdict::Satisfied => "good",
                        crate::compare::Verdict::NotSatisfied => "bad",
                        crate::compare::Verdict::NotJudged => "unknown",
                    };
                    let _ = write!(b, "<td class=\"{class}\">{text}</td>");
                }
                b.push_str("</tr>");
            }
            b.push_str("</tbody></table></div>");
        }
        page("SceneEval comparison", &b)
    }

    /// Per pair of runs, the scenes' own differences `b - a` (`table#scene-differences-K`, K the
    /// pair's position), the largest first, each value linking to its run's scene page
    /// ([`scene_href`]); nothing without `--paired`.
    fn scene_differences_html(&self, b: &mut String, page_dir: &Path) {
        for (k, pair) in self.pairs.iter().enumerate() {
            let (ra, rb) = (&self.runs[pair.a], &self.runs[pair.b]);
            let listed: Vec<&SceneDifference> =
                pair.scenes.iter().filter(|d| d.difference() != 0.0).collect();
            let _ = write!(
                b,
                "<h3>Differences per scene: {} - {}</h3><p>Each scene's own difference in each column (percentage \
                 points, b - a; green where b is better, red where a is), the largest first: {} of the {} scene values \
                 both runs have differ; the equal ones are not listed.</p>",
                html(&rb.name),
                html(&ra.name),
                listed.len(),
                pair.scenes.len()
            );
            if listed.is_empty() {
                continue;
            }
            let _ = write!(
                b,
                "<div class=\"wide\"><table class=\"sortable scene-differences\" id=\"scene-differences-{k}\"><thead><tr>\
                 <th>scene</th><th>column</th><th class=\"num\" data-type=\"num\">{} (a)</th>\
                 <th class=\"num\" data-type=\"num\">{} (b)</th><th class=\"num\" data-type=\"num\">b - a</th>\
                 </tr></thead><tbody>",
                html(&ra.name),
                html(&rb.name)
            );
            let (ha, hb): (Vec<Option<String>>, Vec<Option<String>>) = listed
                .iter()
                .map(|d| {
                    (
                        scene_href(ra, &d.scene, page_dir),
                        scene_href(rb, &d.scene, page_dir),
                    )
                })
                .unzip();
            for ((d, href_a), href_b) in listed.iter().zip(&ha).zip(&hb) {
                let value = |v: f64, href: &Option<String>| match href {
                    Some(h) => format!(
                        "<td class=\"num\" data-v=\"{v}\"><a href=\"{}\">{v:.2}</a></td>",
                        html(h)
                    ),
                    None => format!("<td class=\"num\" data-v=\"{v}\">{v:.2}</td>"),
                };
                let diff = d.difference();
                let _ = write!(
                    b,
                    "<tr data-scene=\"{}\"><td>{}</td><td>{} {}</td>{}{}<td class=\"num {}\" data-v=\"{diff}\">{diff:+.2}</td></tr>",
                    html(&d.scene),
                    html(&d.scene),
                    html(d.column.name),
                    text_arrow(d.column.better),
                    value(d.a, href_a),
                    value(d.b, href_b),
                    if (diff > 0.0) == matches!(d.column.better, Better::Higher) {
                        "good"
                    } else {
                        "bad"
                    }
                );
            }
            b.push_str("</tbody></table></div>");
            for (run, hrefs) in [(ra, &ha), (rb, &hb)] {
                if hrefs.iter().any(Option::is_none) {
                    let _ = write!(
                        b,
                        "<p class=\"muted\">{}'s values are not linked where it has no scene page \
                         (<code>{}</code>; <code>sceneeval report {}</code> writes them).</p>",
                        html(&run.name),
                        html(&run.dir.join(DEFAULT_DIR).join(SCENES_DIR).display().to_string()),
                        html(&run.dir.display().to_string())
                    );
                }
            }
        }
    }

    /// The paired comparisons: a table of differences with significance marks, McNemar's
    /// tests, the pairs' notes and the legend (nothing without `--paired`).
    fn paired_html(&self, b: &mut String) {
        if self.pairs.is_empty() {
            return;
        }
        b.push_str(
            "<h2>Paired differences (b - a)</h2><div class=\"wide\"><table id=\"paired\"><thead><tr><th>a</th><th>b</th>\
             <th>column</th><th class=\"num\">n</th><th class=\"num\">b - a</th><th>interval</th><th class=\"num\">p</th>\
             <th class=\"num\">p (Holm)</th><th>better</th></tr></thead><tbody>",
        );
        for cells in self.paired_cells(&Style::HTML) {
            let _ = write!(
                b,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td>{}</td>\
                 <td class=\"num\">{}</td><td class=\"num\">{}</td><td>{}</td></tr>",
                cells[0], cells[1], cells[2], cells[3], cells[4], cells[5], cells[6], cells[7], cells[8]
            );
        }
        b.push_str("</tbody></table></div>");
        if self.pairs.iter().any(|p| !p.verdicts.is_empty()) {
            b.push_str(
                "<h3>Fidelity verdicts (McNemar)</h3><div class=\"wide\"><table id=\"mcnemar\"><thead><tr><th>a</th><th>b</th>\
                 <th>metric</th><th class=\"num\">specs</th><th class=\"num\">a only</th><th class=\"num\">b only</th>\
                 <th class=\"num\">b - a</th><th class=\"num\">p</th><th class=\"num\">p (Holm)</th></tr></thead><tbody>",
            );
            for cells in self.verdict_cells(&Style::HTML) {
                let [a, bn, metric, rest @ ..] = &cells;
                let _ = write!(b, "<tr><td>{a}</td><td>{bn}</td><td>{metric}</td>");
                for c in rest {
                    let _ = write!(b, "<td class=\"num\">{c}</td>");
                }
                b.push_str("</tr>");
            }
            b.push_str("</tbody></table></div>");
        }
        let notes = self.paired_notes();
        if !notes.is_empty() {
            b.push_str("<div class=\"box\" id=\"paired-notes\"><strong>Paired notes</strong><ul>");
            for note in &notes {
                let _ = write!(b, "<li>{}</li>", html(note));
            }
            b.push_str("</ul></div>");
        }
        let _ = write!(b, "<p class=\"muted\">{}</p>", html(&self.paired_legend()));
    }
}
