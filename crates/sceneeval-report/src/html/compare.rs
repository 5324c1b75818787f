//! The comparison as an HTML page: the tables with their emphasis, the standings, the notes,
//! links to each run's report, and the fidelity specs whose verdicts differ between runs.

use std::fmt::Write as _;
use std::path::Path;

use super::{page, relative_href};
use crate::compare::{Comparison, Emphasis, average, standing_order, text_arrow};
use crate::escape::{self, html};
use crate::report::{INDEX, SCENES_DIR};

impl Comparison {
    /// The comparison as one self-contained HTML page that will be written into the folder
    /// `page_dir` (links to each run's report, `RUN/report/index.html`, and its scene pages are
    /// relative to it, and given only for reports that exist). Every name is escaped.
    pub fn to_html(&self, page_dir: &Path) -> String {
        let mut b = String::from(
            "<h1>SceneEval comparison</h1><h2>Runs</h2><table id=\"runs\"><thead><tr><th>run</th><th>folder</th><th>report</th></tr></thead><tbody>",
        );
        for run in &self.runs {
            let index = run.dir.join(crate::report::DEFAULT_DIR).join(INDEX);
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
            b.push_str("</tbody></table></div><div class=\"wide\"><table class=\"standings\"><thead><tr><th class=\"num\">place</th><th>run</th><th class=\"num\">points</th><th class=\"num\">average rank</th><th class=\"num\">1st</th><th class=\"num\">2nd</th><th class=\"num\">3rd</th>");
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
                    let scene_page = run
                        .dir
                        .join(crate::report::DEFAULT_DIR)
                        .join(SCENES_DIR)
                        .join(format!("{}.html", escape::file_name(&d.scene)));
                    let text = match scene_page
                        .is_file()
                        .then(|| relative_href(page_dir, &scene_page))
                        .flatten()
                    {
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
}
