//! The report's `index.html`: the run's summary table per difficulty, charts of the metrics,
//! and the scenes with their scores, sortable and filterable by the metric they fail.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use sceneeval_results::{Better, GroupSummary, Metric, Outcome, Summary, difficulty_groups};

use super::chart::{GROUP_COLOURS, bars, strips};
use super::scene::problem_keys;
use super::topview::Problem;
use super::{legend, num_cell, page};
use crate::compare::text_arrow;
use crate::escape::html;
use crate::run::{Run, scene_of, scene_values};

/// Whether a scene's value of a column is not the best possible: below 100 % where higher is
/// better, above 0 % where lower is better.
pub(crate) fn fails(value: f64, better: Better) -> bool {
    match better {
        Better::Higher => value < 100.0 - 1e-9,
        Better::Lower => value > 1e-9,
    }
}

/// The overview page. `pages` maps a scene to its page's URL.
pub(crate) fn overview(
    run: &Run,
    columns: &[(&'static str, Metric)],
    pages: &BTreeMap<String, String>,
) -> String {
    let summary = Summary::from_records(&run.records, None);
    let groups = run.summary();
    let evaluated = run.records.iter().filter(|r| r.report().is_some()).count();
    let mut b = String::new();
    let _ = write!(
        b,
        "<h1>SceneEval report: {}</h1><p class=\"meta\">Run folder <code>{}</code>: {} scenes, {} evaluated, {} failed. \
         Preset <code>{}</code>; plan digest <code>{}</code>.</p>",
        html(&run.name),
        html(&run.dir.display().to_string()),
        run.records.len(),
        evaluated,
        run.records.len() - evaluated,
        html(summary.preset.as_deref().unwrap_or("not recorded")),
        html(
            &summary
                .plan_digest
                .as_deref()
                .map_or_else(|| "not recorded".to_owned(), |d| d.chars().take(16).collect())
        )
    );

    unreadable(&mut b, run);
    summary_table(&mut b, columns, &groups);
    charts(&mut b, columns, &groups);
    distributions(&mut b, run, columns);
    super::labels::overview_section(&mut b, run, pages);
    scenes_table(&mut b, run, columns, pages);
    page(&format!("SceneEval report: {}", run.name), &b)
}

/// The records of the run folder that could not be read, each with why (`ul#unreadable`);
/// nothing when every record was read. Their scenes are in no table.
fn unreadable(b: &mut String, run: &Run) {
    if run.unreadable.is_empty() {
        return;
    }
    let _ = write!(
        b,
        "<div class=\"box\"><p>{} record(s) of the run folder could not be read; their scenes are in no table \
         below:</p><ul id=\"unreadable\">",
        run.unreadable.len()
    );
    for u in &run.unreadable {
        let _ = write!(
            b,
            "<li><code>{}</code>: {}</li>",
            html(&u.path.display().to_string()),
            html(&u.reason)
        );
    }
    b.push_str("</ul></div>");
}

/// The run's summary table, one row per group.
fn summary_table(b: &mut String, columns: &[(&'static str, Metric)], groups: &[GroupSummary]) {
    b.push_str(
        "<h2>Summary</h2><div class=\"wide\"><table id=\"summary\"><thead><tr><th>group</th>\
                <th class=\"num\">scenes</th><th class=\"num\">evaluated</th><th class=\"num\">failed</th>",
    );
    for (c, m) in columns {
        let _ = write!(b, "<th class=\"num\">{} {}</th>", html(c), text_arrow(m.better()));
    }
    b.push_str("</tr></thead><tbody>");
    for g in groups {
        let _ = write!(
            b,
            "<tr><th>{}</th><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>",
            html(&g.group),
            g.scenes,
            g.evaluated,
            g.failed
        );
        for (c, _) in columns {
            b.push_str(&num_cell(g.value(c)));
        }
        b.push_str("</tr>");
    }
    b.push_str(
        "</tbody></table></div><p class=\"muted\">Percent, macro-averaged over each group's evaluated scenes, as in \
         summary.md; ↑ higher is better, ↓ lower is better; - no scene of the group has a value.</p>",
    );
}

/// The charts of the metrics per group, with their legend.
fn charts(b: &mut String, columns: &[(&'static str, Metric)], groups: &[GroupSummary]) {
    b.push_str("<h2>Charts</h2><div class=\"wide\">");
    let chart_columns: Vec<(&str, Better)> = columns.iter().map(|(c, m)| (*c, m.better())).collect();
    let chart_groups: Vec<(&str, Vec<Option<f64>>)> = groups
        .iter()
        .map(|g| {
            (
                g.group.as_str(),
                columns.iter().map(|(c, _)| g.value(c)).collect(),
            )
        })
        .collect();
    b.push_str(&bars(&chart_columns, &chart_groups));
    b.push_str("</div>");
    let items: Vec<(&str, &str, bool)> = groups
        .iter()
        .enumerate()
        .map(|(k, g)| (GROUP_COLOURS[k % GROUP_COLOURS.len()], g.group.as_str(), false))
        .collect();
    b.push_str(&legend(&items));
}

/// Each metric column's values over the scenes, a strip plot per column with a row per group
/// (`#distributions`), each scene a dot at its own value (percent, as in the scene table);
/// the scenes without a value (failed, or the metric not computed) are named under the plot,
/// not drawn.
fn distributions(b: &mut String, run: &Run, columns: &[(&'static str, Metric)]) {
    b.push_str(
        "<h2>Distributions</h2><p class=\"muted\">Each scene's own value (percent, as in the scene table) per \
         group; equal values are piled up. Hover a dot for its scene.</p><div class=\"distributions\" \
         id=\"distributions\">",
    );
    let names: Vec<&str> = run.records.iter().map(scene_of).collect();
    let groups = difficulty_groups(&names, |s| run.difficulty(s));
    let values: BTreeMap<&str, (bool, GroupSummary)> = run
        .records
        .iter()
        .map(|r| (scene_of(r), (r.report().is_some(), scene_values(r))))
        .collect();
    for (c, m) in columns {
        let value = |s: &str| {
            values
                .get(s)
                .and_then(|(ok, v)| if *ok { v.value(c) } else { None })
        };
        let rows: Vec<(&str, Vec<(&str, f64)>)> = groups
            .iter()
            .map(|(g, scenes)| {
                let plotted = scenes.iter().filter_map(|s| Some((*s, value(s)?))).collect();
                (g.as_str(), plotted)
            })
            .collect();
        let _ = write!(b, "<figure data-column=\"{}\">", html(c));
        b.push_str(&strips(c, m.better(), &rows));
        let missing: Vec<String> = names
            .iter()
            .filter(|s| value(s).is_none())
            .map(|s| {
                let failed = values.get(s).is_some_and(|(ok, _)| !ok);
                format!("{} ({})", html(s), if failed { "failed" } else { "no value" })
            })
            .collect();
        if !missing.is_empty() {
            let _ = write!(
                b,
                "<figcaption class=\"missing\">Not plotted ({}): {}</figcaption>",
                missing.len(),
                missing.join(", ")
            );
        }
        b.push_str("</figure>");
    }
    b.push_str("</div>");
}

/// The scenes with their values, filterable by what they fail and sortable.
fn scenes_table(
    b: &mut String,
    run: &Run,
    columns: &[(&'static str, Metric)],
    pages: &BTreeMap<String, String>,
) {
    b.push_str(
        "<h2>Scenes</h2><div class=\"controls\"><label for=\"fails\">Show </label><select id=\"fails\">\
         <option value=\"\">every scene</option><option value=\"failed\">scenes that failed to evaluate</option>",
    );
    for (c, m) in columns {
        let _ = write!(
            b,
            "<option value=\"{c}\">scenes that fail {c} ({})</option>",
            match m.better() {
                Better::Higher => "below 100 %",
                Better::Lower => "above 0 %",
            },
            c = html(c)
        );
    }
    for p in Problem::ALL {
        let _ = write!(
            b,
            "<option value=\"{}\">scenes with an object {}</option>",
            p.key(),
            html(p.label())
        );
    }
    b.push_str("</select> <span class=\"muted\"><span id=\"shown\"></span> shown</span></div>");
    let numbered = run.records.iter().all(|r| r.scene.number().is_some());
    let _ = write!(
        b,
        "<div class=\"wide\"><table id=\"scenes\" class=\"sortable\"><thead><tr><th data-type=\"{}\">scene</th>\
         <th>difficulty</th><th>status</th>",
        if numbered { "num" } else { "text" }
    );
    for (c, m) in columns {
        let _ = write!(
            b,
            "<th class=\"num\" data-type=\"num\">{} {}</th>",
            html(c),
            text_arrow(m.better())
        );
    }
    b.push_str("</tr></thead><tbody>");
    for r in &run.records {
        let name = r.scene.as_str();
        let values = scene_values(r);
        let mut tokens: Vec<&str> = Vec::new();
        match &r.outcome {
            Outcome::Failed { .. } => {
                tokens.push("failed");
                tokens.extend(columns.iter().map(|(c, _)| *c));
            }
            Outcome::Ok { report } | Outcome::Partial { report } => {
                if matches!(r.outcome, Outcome::Partial { .. }) {
                    tokens.push("partial");
                }
                for (c, m) in columns {
                    if values.value(c).is_some_and(|v| fails(v, m.better())) {
                        tokens.push(c);
                    }
                }
                tokens.extend(problem_keys(report));
            }
        }
        let link = match pages.get(name) {
            Some(href) => format!("<a href=\"{}\">{}</a>", html(href), html(name)),
            None => html(name),
        };
        let _ = write!(
            b,
            "<tr data-scene=\"{}\" data-fails=\"{}\"><td data-v=\"{}\">{link}</td><td>{}</td><td class=\"{}\">{}</td>",
            html(name),
            html(&tokens.join(" ")),
            r.scene.number().map_or_else(|| html(name), |n| n.to_string()),
            html(run.difficulty(name).unwrap_or("-")),
            match r.status() {
                "ok" => "good",
                "partial" => "unknown",
                _ => "bad",
            },
            r.status()
        );
        for (c, _) in columns {
            b.push_str(&num_cell(if r.report().is_some() {
                values.value(c)
            } else {
                None
            }));
        }
        b.push_str("</tr>");
    }
    let _ = write!(
        b,
        "</tbody></table></div><p class=\"muted\">Click a column's name to sort. Values in percent, each scene \
         alone; a scene fails a column when its value is not the best possible. {} of the run's scenes have a page.</p>",
        pages.len()
    );
}
