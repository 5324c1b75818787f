//! One page per scene: its scores, the top view with what is wrong with each object, the
//! evidence of every metric, the images the run wrote, and every fidelity spec with its
//! verdict and the evidence behind it.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use sceneeval_fidelity::{FidelityReport, MetricResult, RelationMappingInfo};
use sceneeval_files::ErrorChain;
use sceneeval_results::{Metric, Outcome, SceneRecord, SceneReport, Stage};
use sceneeval_scene::inspect::SceneInfo;
use serde::Serialize;

use super::topview::{self, Overlay, Problem};
use super::{legend, num_cell, page};
use crate::escape::html;
use crate::run::{Description, scene_values};

/// An image the run wrote, with its link from the page.
#[derive(Debug, Clone)]
pub(crate) struct Image {
    /// The file name.
    pub name: String,
    /// Its URL from the page.
    pub href: String,
}

/// A link to another scene's page: the scene's name and the page's URL from this page.
#[derive(Debug, Clone)]
pub(crate) struct SceneLink {
    /// The scene.
    pub scene: String,
    /// The URL of its page from this page.
    pub href: String,
}

/// What a scene page shows.
pub(crate) struct ScenePage<'a> {
    /// The run's name.
    pub run: &'a str,
    /// The record.
    pub record: &'a SceneRecord,
    /// Its difficulty.
    pub difficulty: Option<&'a str>,
    /// The scene as read from its file, or why it could not be read.
    pub scene: Result<SceneInfo<'a>, String>,
    /// The views the run wrote for the VLM.
    pub views: Vec<Image>,
    /// The diagnostic images the run wrote.
    pub diagnostics: Vec<Image>,
    /// The navigability image over the top view, when the run wrote it.
    pub overlay: Option<Overlay>,
    /// Remarks about the geometry (a scene file changed since the run).
    pub remarks: Vec<String>,
    /// The summary columns the run has.
    pub columns: &'a [(&'static str, Metric)],
    /// The scene's description, or why there is none.
    pub description: Description<'a>,
    /// The pages of the scenes before and after this one in the overview's order.
    pub previous: Option<SceneLink>,
    /// See `previous`.
    pub next: Option<SceneLink>,
    /// The run's agreement with people's labels, when the report shows them.
    pub labels: Option<&'a crate::agreement::Agreement>,
}

/// The page's HTML.
pub(crate) fn scene_page(p: &ScenePage<'_>) -> String {
    let r = p.record;
    let mut b = String::new();
    let _ = write!(
        b,
        "<nav class=\"crumbs\"><a href=\"../index.html\">{}</a> / {}</nav>",
        html(p.run),
        html(r.scene.as_str()),
    );
    neighbours(&mut b, p);
    let _ = write!(b, "<h1>{}</h1>", html(r.scene.as_str()));
    let _ = write!(
        b,
        "<p class=\"meta\">benchmark id {}; difficulty {}; status <span id=\"status\">{}</span></p>",
        html(r.scene.id().unwrap_or("-")),
        html(p.difficulty.unwrap_or("-")),
        if r.report().is_some() { "ok" } else { "failed" }
    );
    description(&mut b, p.description);
    if let Outcome::Failed { stage, error, causes } = &r.outcome {
        let _ = write!(
            b,
            "<div class=\"box error\" id=\"failure\"><strong>Failed in the {} stage.</strong><pre>{}</pre></div>",
            match stage {
                Stage::Load => "load",
                Stage::Evaluate => "evaluate",
            },
            html(&format!("{:#}", ErrorChain::from_parts(error.as_str(), causes)))
        );
    }
    let report = r.report();
    if let Some(report) = report {
        let values = scene_values(r);
        b.push_str("<h2>Scores</h2><div class=\"wide\"><table id=\"scores\"><thead><tr>");
        for (c, m) in p.columns {
            let _ = write!(
                b,
                "<th class=\"num\">{} {}</th>",
                html(c),
                crate::compare::text_arrow(m.better())
            );
        }
        b.push_str("</tr></thead><tbody><tr>");
        for (c, _) in p.columns {
            b.push_str(&num_cell(values.value(c)));
        }
        b.push_str("</tr></tbody></table></div><p class=\"muted\">Percent, this scene alone (as in summary_scenes.csv).</p>");
        top_view(&mut b, p, report);
        geometry_evidence(&mut b, report);
        stability(&mut b, report);
        if let Some(f) = &report.fidelity {
            fidelity(&mut b, f);
        }
        super::labels::scene_section(&mut b, p.run, p.labels, r);
    } else {
        top_view_only(&mut b, p);
    }
    views(&mut b, &p.views);
    images(&mut b, "Diagnostic images", "diagnostics", &p.diagnostics);
    page(&format!("{} - {}", r.scene, p.run), &b)
}

fn top_view(b: &mut String, p: &ScenePage<'_>, report: &SceneReport) {
    b.push_str("<h2>Top view</h2>");
    let problems = topview::problems(report);
    let ids: Vec<&str> = report.object_ids.iter().map(|i| i.as_str()).collect();
    let numbers: BTreeMap<&str, usize> = ids.iter().enumerate().map(|(k, id)| (*id, k + 1)).collect();
    let categories: BTreeMap<&str, &str> = match &p.scene {
        Ok(info) => info
            .objects
            .iter()
            .filter_map(|o| Some((o.id, o.category?)))
            .collect(),
        Err(_) => BTreeMap::new(),
    };
    b.push_str("<div class=\"topview\">");
    match &p.scene {
        Ok(info) => b.push_str(&topview::draw(
            info,
            Some(report),
            &problems,
            &numbers,
            p.overlay.as_ref(),
        )),
        Err(why) => {
            let _ = write!(
                b,
                "<div class=\"box error\" id=\"no-topview\">Top view not drawn: {}</div>",
                html(why)
            );
        }
    }
    b.push_str("<div>");
    b.push_str(&legend(&topview::legend_items()));
    b.push_str(match (&p.scene, &p.overlay) {
        (Ok(_), Some(_)) => {
            "<p class=\"muted\">Under the objects: the navigability map of the run's diagnostics (green: the largest \
             free region, yellow: other free regions, red: floor blocked for a 0.2 m robot).</p>"
        }
        (Ok(_), None) => {
            "<p class=\"muted\">The navigable region is not in the record: a run evaluated with diagnostics draws it \
             (diagnostics/navigability.png), and it is shown here.</p>"
        }
        (Err(_), _) => "",
    });
    for remark in &p.remarks {
        let _ = write!(b, "<p class=\"muted\">{}</p>", html(remark));
    }
    b.push_str(
        "<p class=\"muted\">The thick edge of a footprint is the object's front. Footprints are the objects' \
                oriented boxes seen from above.</p></div></div>",
    );
    b.push_str(
        "<h3>Objects</h3><div class=\"wide\"><table id=\"objects\" class=\"sortable\"><thead><tr>\
         <th class=\"num\" data-type=\"num\">#</th><th>object</th><th>category</th><th>what is wrong</th></tr></thead><tbody>",
    );
    for (k, id) in ids.iter().enumerate() {
        let list = problems.get(*id);
        let mut wrong = String::new();
        for (problem, text) in list.into_iter().flatten() {
            let _ = write!(
                wrong,
                "<div><span class=\"swatch\" style=\"background:{}\"></span> <strong>{}</strong>: {}</div>",
                problem.colour(),
                html(problem.label()),
                html(text)
            );
        }
        if wrong.is_empty() {
            wrong.push_str("<span class=\"good\">nothing found</span>");
        }
        let keys: Vec<&str> = list.into_iter().flatten().map(|(p, _)| p.key()).collect();
        let _ = write!(
            b,
            "<tr data-object=\"{}\" data-problems=\"{}\"><td class=\"num\" data-v=\"{}\">{}</td><td><code>{}</code></td>\
             <td>{}</td><td>{wrong}</td></tr>",
            html(id),
            keys.join(" "),
            k + 1,
            k + 1,
            html(id),
            html(categories.get(id).copied().unwrap_or("-"))
        );
    }
    b.push_str("</tbody></table></div>");
}

/// A failed scene: the top view when its file can still be read.
fn top_view_only(b: &mut String, p: &ScenePage<'_>) {
    if let Ok(info) = &p.scene {
        let numbers: BTreeMap<&str, usize> = info
            .objects
            .iter()
            .enumerate()
            .map(|(k, o)| (o.id, k + 1))
            .collect();
        b.push_str("<h2>Top view</h2><div class=\"topview\">");
        b.push_str(&topview::draw(info, None, &BTreeMap::new(), &numbers, None));
        b.push_str("</div><p class=\"muted\">Nothing was measured on this scene; the drawing is the file as it is now.</p>");
    }
}

/// The stability metric's verdicts: how far each object moved and turned under physics, and
/// which were welded in place and why.
fn stability(b: &mut String, report: &SceneReport) {
    use sceneeval_physics::WeldReason;
    let Some(s) = &report.stability else {
        return;
    };
    let _ = write!(
        b,
        "<h2>Physical stability</h2><p>Weld mode <code>{}</code>: {} of {} free objects moved or turned beyond \
         the limits{}; {:.2} s simulated in {} steps.</p><table id=\"stability\"><thead><tr><th>object</th>\
         <th>verdict</th><th class=\"num\">moved (m)</th><th class=\"num\">turned (rad)</th><th>welded</th></tr>\
         </thead><tbody>",
        s.weld.name(),
        s.num_unstable,
        s.num_free,
        s.frac_unstable_missing
            .as_deref()
            .map(|why| format!(" ({})", html(why)))
            .unwrap_or_default(),
        s.simulated_s,
        s.steps
    );
    for o in &s.objects {
        let _ = write!(
            b,
            "<tr><td><code>{}</code></td><td class=\"{}\">{}</td><td class=\"num\">{:.4}</td>\
             <td class=\"num\">{:.4}</td><td>{}</td></tr>",
            html(o.id.as_str()),
            if o.stable { "good" } else { "bad" },
            match (o.welded, o.stable) {
                (true, _) => "welded",
                (false, true) => "stable",
                (false, false) => "unstable",
            },
            o.displacement_m,
            o.rotation_rad,
            match o.weld_reason {
                None => "no",
                Some(WeldReason::Wall) => "yes: on a wall",
                Some(WeldReason::Ceiling) => "yes: on the ceiling",
                Some(WeldReason::Penetration) => "yes: interpenetrating",
            }
        );
    }
    b.push_str("</tbody></table>");
}

fn geometry_evidence(b: &mut String, report: &SceneReport) {
    b.push_str("<h2>Geometry evidence</h2>");
    if report.metrics.is_empty() {
        b.push_str("<p class=\"muted\">No geometry metric ran.</p>");
        return;
    }
    if let Some(c) = &report.collision {
        let colliding: Vec<_> = c.contacts.iter().filter(|x| x.colliding).collect();
        let _ = write!(
            b,
            "<h3>Collision</h3><p>{} of {} objects in collision; {} colliding pairs.</p>",
            c.num_in_collision, c.num_tested, c.num_colliding_pairs
        );
        if !colliding.is_empty() {
            b.push_str("<table><thead><tr><th>object</th><th>object</th><th>how</th><th class=\"num\">depth (m)</th></tr></thead><tbody>");
            for x in colliding {
                let _ = write!(
                    b,
                    "<tr><td><code>{}</code></td><td><code>{}</code></td><td>{}</td><td class=\"num\">{:.4}</td></tr>",
                    html(x.a.as_str()),
                    html(x.b.as_str()),
                    html(&match &x.kind {
                        sceneeval_plausibility::ContactKind::Surface => "surfaces cross".to_owned(),
                        sceneeval_plausibility::ContactKind::Nested { inner } =>
                            format!("{} inside the other", inner.as_str()),
                    }),
                    x.depth
                );
            }
            b.push_str("</tbody></table>");
        }
    }
    if let Some(s) = &report.support {
        let _ = write!(
            b,
            "<h3>Support</h3><p>{} of {} objects supported.</p>",
            s.num_supported,
            s.objects.len()
        );
    }
    if let Some(n) = &report.navigability {
        let _ = write!(
            b,
            "<h3>Navigability</h3><p>NAV {:.2}%: the largest free region is {} of {} free pixels ({} regions, {:.2} m² \
             free); every room reachable: {}.</p>",
            100.0 * n.nav,
            n.largest_component_pixels,
            n.free_pixels,
            n.num_components,
            n.free_area,
            yes_no(n.all_rooms_reachable)
        );
    }
    if let Some(a) = &report.accessibility {
        let _ = write!(
            b,
            "<h3>Accessibility</h3><p>{} objects scored, {} without functional sides.</p>",
            a.num_scored, a.num_unknown
        );
    }
    if let Some(o) = &report.out_of_bounds {
        let _ = write!(
            b,
            "<h3>Out of bounds</h3><p>{} of {} objects out of bounds.</p>",
            o.num_out,
            o.objects.len()
        );
    }
    if let Some(c) = &report.opening_clearance {
        let _ = write!(
            b,
            "<h3>Doors and windows</h3><p>{} of {} doors and {} of {} windows blocked.</p>",
            c.doors_blocked, c.num_doors, c.windows_blocked, c.num_windows
        );
        if !c.openings.is_empty() {
            b.push_str("<table id=\"openings\"><thead><tr><th>opening</th><th>wall</th><th>blocked</th><th>by</th></tr></thead><tbody>");
            for o in &c.openings {
                let by: Vec<String> = o
                    .sides
                    .iter()
                    .flat_map(|s| &s.blocking)
                    .map(|x| format!("{} ({:.0}%)", x.id.as_str(), 100.0 * x.occluded_fraction))
                    .collect();
                let _ = write!(
                    b,
                    "<tr><td>{} <code>{}</code></td><td><code>{}</code></td><td class=\"{}\">{}</td><td>{}</td></tr>",
                    o.kind.name(),
                    html(&o.opening),
                    html(&o.wall),
                    if o.blocked { "bad" } else { "good" },
                    if o.blocked { "yes" } else { "no" },
                    html(&by.join(", "))
                );
            }
            b.push_str("</tbody></table>");
        }
    }
    b.push_str("<p class=\"muted\">Per-object findings are in the table of objects above.</p>");
}

fn fidelity(b: &mut String, f: &FidelityReport) {
    b.push_str("<h2>Text fidelity</h2>");
    match &f.matching {
        Some(m) => {
            let _ = write!(
                b,
                "<p>Object matching ({}): {}{}</p>",
                html(&name_of(&m.source)),
                html(&m.message),
                if m.unanswered > 0 {
                    format!(" {} objects unanswered.", m.unanswered)
                } else {
                    String::new()
                },
            );
        }
        None => b.push_str("<p>Object matching: none could be made (the metrics that need it failed).</p>"),
    }
    let _ = write!(
        b,
        "<p>Relation mapping: {}.</p>",
        html(&name_of(&f.relation_mapping))
    );
    if let Some(m) = &f.cnt {
        section(b, "CNT: object counts", "cnt", m, |s| {
            (
                s.spec.clone(),
                s.satisfied,
                format!(
                    "{} in the scene{}",
                    s.count_in_scene,
                    if s.objects.is_empty() {
                        String::new()
                    } else {
                        format!(": {}", s.objects.join(", "))
                    }
                ),
            )
        });
    }
    if let Some(m) = &f.atr {
        section(b, "ATR: object attributes", "atr", m, |s| {
            let mut e = format!(
                "objects: {}; with every attribute: {}",
                if s.objects.is_empty() {
                    "none".to_owned()
                } else {
                    s.objects.join(", ")
                },
                s.count_satisfied
                    .map_or("not asked".to_owned(), |n| n.to_string())
            );
            for a in &s.assessments {
                let _ = write!(
                    e,
                    "\n{} {}: {} ({})",
                    a.object,
                    a.attribute,
                    match a.satisfied {
                        Some(true) => "yes",
                        Some(false) => "no",
                        None => "unanswered",
                    },
                    a.reason
                );
            }
            if let Some(n) = &s.note {
                let _ = write!(e, "\nnote: {n}");
            }
            if let Some(u) = &s.unanswered {
                let _ = write!(e, "\nunanswered: {u}");
            }
            (s.spec.clone(), s.satisfied, e)
        });
    }
    if let Some(m) = &f.oor {
        section(b, "OOR: object-object relationships", "oor", m, |s| {
            let mut e = mapping(&s.mapping);
            let _ = write!(
                e,
                "\nall objects present: {}; candidate groups: {} ({} evaluated), {} satisfied",
                yes_no(Some(s.all_objects_present)),
                s.num_candidate_groups,
                s.groups_evaluated,
                s.count_satisfied
            );
            for g in s.groups.iter().take(16) {
                let results: Vec<String> = g
                    .results
                    .iter()
                    .map(|r| {
                        format!(
                            "{} {:.2}{}",
                            r.relation,
                            r.score,
                            if r.holds { " holds" } else { "" }
                        )
                    })
                    .collect();
                let _ = write!(
                    e,
                    "\n{} group: anchor {}, {}: {}",
                    if g.satisfied { "✓" } else { "✗" },
                    g.anchor,
                    g.others.join(", "),
                    results.join("; ")
                );
            }
            if s.groups.len() > 16 {
                let _ = write!(e, "\n... and {} more groups in eval.json", s.groups.len() - 16);
            }
            (s.spec.clone(), s.satisfied, e)
        });
    }
    if let Some(m) = &f.oar {
        section(b, "OAR: object-architecture relationships", "oar", m, |s| {
            let mut e = mapping(&s.mapping);
            let _ = write!(
                e,
                "\nobject present: {}; {} satisfied",
                yes_no(Some(s.obj_present)),
                s.count_satisfied
            );
            for c in &s.candidates {
                let _ = write!(
                    e,
                    "\n{} {:.2}{}",
                    c.object,
                    c.score,
                    if c.holds { " holds" } else { "" }
                );
            }
            (s.spec.clone(), s.satisfied, e)
        });
    }
    if !f.warnings.is_empty() {
        b.push_str("<h3>Warnings</h3><ul>");
        for w in &f.warnings {
            let _ = write!(b, "<li>{}</li>", html(w));
        }
        b.push_str("</ul>");
    }
}

/// One fidelity metric: its message and a row per spec (the spec, its verdict, the evidence as
/// lines of text).
fn section<T>(
    b: &mut String,
    title: &str,
    id: &str,
    m: &MetricResult<T>,
    row: impl Fn(&T) -> (String, Option<bool>, String),
) {
    let _ = write!(
        b,
        "<h3>{}</h3><p>{}{}</p><table class=\"specs\" id=\"specs-{id}\"><thead><tr><th>spec</th><th>verdict</th>\
         <th>evidence</th></tr></thead><tbody>",
        html(title),
        html(&m.message),
        m.not_judged
            .as_deref()
            .map(|n| format!(" Not judged: {}.", html(n)))
            .unwrap_or_default()
    );
    for spec in &m.specs {
        let (text, verdict, evidence) = row(spec);
        let lines: Vec<String> = evidence.lines().map(html).collect();
        let _ = write!(
            b,
            "<tr><td><code>{}</code></td><td class=\"{}\">{}</td><td>{}</td></tr>",
            html(&text),
            match verdict {
                Some(true) => "good",
                Some(false) => "bad",
                None => "unknown",
            },
            match verdict {
                Some(true) => "satisfied",
                Some(false) => "not satisfied",
                None => "not judged",
            },
            lines.join("<br>")
        );
    }
    b.push_str("</tbody></table>");
}

fn mapping(m: &RelationMappingInfo) -> String {
    format!(
        "mapping: {} ({}{}){}{}",
        name_of(&m.status),
        name_of(&m.source),
        m.word
            .as_deref()
            .map(|w| format!(", word {w}"))
            .unwrap_or_default(),
        if m.relations.is_empty() {
            String::new()
        } else {
            format!(" to {}", m.relations.join(" and "))
        },
        if m.reason.is_empty() {
            String::new()
        } else {
            format!("; {}", m.reason)
        }
    )
}

/// The links to the previous and next scene pages (`nav#neighbours`), in the overview's
/// order; nothing when the run has one scene.
fn neighbours(b: &mut String, p: &ScenePage<'_>) {
    if p.previous.is_none() && p.next.is_none() {
        return;
    }
    b.push_str("<nav class=\"crumbs\" id=\"neighbours\">");
    match &p.previous {
        Some(l) => {
            let _ = write!(
                b,
                "<a rel=\"prev\" href=\"{}\">&larr; {}</a>",
                html(&l.href),
                html(&l.scene)
            );
        }
        None => b.push_str("<span class=\"muted\">first scene</span>"),
    }
    b.push_str(" | ");
    match &p.next {
        Some(l) => {
            let _ = write!(
                b,
                "<a rel=\"next\" href=\"{}\">{} &rarr;</a>",
                html(&l.href),
                html(&l.scene)
            );
        }
        None => b.push_str("<span class=\"muted\">last scene</span>"),
    }
    b.push_str("</nav>");
}

/// The scene's description (`#description`), or why the page has none.
fn description(b: &mut String, d: Description<'_>) {
    let none = |b: &mut String, why: &str| {
        let _ = write!(
            b,
            "<p class=\"unknown\" id=\"description\">no description: {}</p>",
            html(why)
        );
    };
    match d {
        Description::Text {
            id,
            text,
            run_had_row,
        } => {
            let _ = write!(
                b,
                "<blockquote class=\"box\" id=\"description\">{}</blockquote><p class=\"muted\">The description of \
                 annotation row {}{}.</p>",
                html(text),
                html(id),
                match run_had_row {
                    Some(true) =>
                        " of the annotations given to the report (the run evaluated with a row for this scene)",
                    Some(false) => {
                        " of the annotations given to the report; the run had no annotation row for this scene, so \
                         its fidelity metrics did not use this description"
                    }
                    None =>
                        " of the annotations given to the report (the record does not say which row the run used)",
                }
            );
        }
        Description::NoRow => none(b, "the run has no annotation row"),
        Description::NotGiven => none(
            b,
            "the run records only a digest of its annotation row; give the report the annotation file the run \
             used (--annotations FILE)",
        ),
        Description::NotInGiven => none(
            b,
            "the run had an annotation row, but the annotations given to the report have none for this scene",
        ),
    }
}

/// The object views the run rendered for the VLM (`<scene>/views/*.png`), or a sentence saying
/// none were kept.
fn views(b: &mut String, list: &[Image]) {
    if list.is_empty() {
        b.push_str(
            "<h2>Views shown to the VLM</h2><p class=\"muted\" id=\"no-views\">No views kept: the run wrote no \
             object views for this scene (a run keeps them in <code>&lt;scene&gt;/views/</code> when its \
             text-fidelity metrics rendered objects for the VLM).</p>",
        );
        return;
    }
    images(b, "Views shown to the VLM", "views", list);
}

fn images(b: &mut String, title: &str, id: &str, list: &[Image]) {
    if list.is_empty() {
        return;
    }
    let _ = write!(b, "<h2>{}</h2><div class=\"views\" id=\"{id}\">", html(title));
    for img in list {
        let _ = write!(
            b,
            "<figure><a href=\"{href}\"><img src=\"{href}\" alt=\"{alt}\" loading=\"lazy\"></a>\
             <figcaption>{name}</figcaption></figure>",
            href = html(&img.href),
            alt = html(&alt_text(&img.name)),
            name = html(&img.name)
        );
    }
    b.push_str("</div>");
}

/// The alt text of an image the run wrote, from its file name: the views' names
/// (`front_<id>.png`, `size_<id>.png`, `surroundings_<id>.png`, `top.png`, as
/// `sceneeval-render` names them) say what they show; any other name is given as is.
fn alt_text(file: &str) -> String {
    let stem = file.strip_suffix(".png").unwrap_or(file);
    for (prefix, before, after) in [
        ("front_", "front view of object ", ""),
        ("size_", "object ", " beside a 170 cm figure"),
        ("surroundings_", "object ", " with its surroundings"),
        ("top_", "top view of objects ", ""),
    ] {
        if let Some(id) = stem.strip_prefix(prefix) {
            return format!("{before}{id}{after}");
        }
    }
    match stem {
        "top" => "top view of the whole scene".to_owned(),
        "navigability" => "navigability map".to_owned(),
        _ => file.to_owned(),
    }
}

/// `yes`, `no` or `-`.
fn yes_no(v: Option<bool>) -> &'static str {
    match v {
        Some(true) => "yes",
        Some(false) => "no",
        None => "-",
    }
}

/// The name serde writes for a unit enum value (`lexicon`, `not_needed`).
fn name_of<T: Serialize>(value: &T) -> String {
    match serde_json::to_value(value) {
        Ok(serde_json::Value::String(s)) => s,
        _ => "-".to_owned(),
    }
}

/// The problem keys of a record's objects, for the scene list's filter.
pub(crate) fn problem_keys(report: &SceneReport) -> Vec<&'static str> {
    let problems = topview::problems(report);
    Problem::ALL
        .into_iter()
        .filter(|p| problems.values().flatten().any(|(q, _)| q == p))
        .map(Problem::key)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alt_texts_say_what_a_view_shows() {
        assert_eq!(alt_text("front_idx0_bed.png"), "front view of object idx0_bed");
        assert_eq!(
            alt_text("size_idx1_chair.png"),
            "object idx1_chair beside a 170 cm figure"
        );
        assert_eq!(
            alt_text("surroundings_lamp.png"),
            "object lamp with its surroundings"
        );
        assert_eq!(alt_text("top_a+b.c.png"), "top view of objects a+b.c");
        assert_eq!(alt_text("top.png"), "top view of the whole scene");
        assert_eq!(alt_text("navigability.png"), "navigability map");
        assert_eq!(alt_text("other.png"), "other.png");
    }

    #[test]
    fn views_are_lazy_images_with_alt_text_or_a_sentence_when_none_were_kept() {
        let mut b = String::new();
        views(&mut b, &[]);
        assert!(b.contains("id=\"no-views\""), "{b}");
        assert!(!b.contains("<img"), "{b}");
        let mut b = String::new();
        views(
            &mut b,
            &[Image {
                name: "front_a&b.png".into(),
                href: "../../s/views/front_a%26b.png".into(),
            }],
        );
        assert!(
            b.contains(
                "<img src=\"../../s/views/front_a%26b.png\" alt=\"front view of object a&amp;b\" loading=\"lazy\">"
            ),
            "{b}"
        );
        assert!(!b.contains("no-views"), "{b}");
    }

    #[test]
    fn descriptions_or_why_there_is_none() {
        let text = |d| {
            let mut b = String::new();
            description(&mut b, d);
            b
        };
        let t = text(Description::Text {
            id: "7",
            text: "A <small> bedroom.",
            run_had_row: Some(true),
        });
        assert!(
            t.contains("<blockquote class=\"box\" id=\"description\">A &lt;small&gt; bedroom.</blockquote>"),
            "{t}"
        );
        assert!(t.contains("annotation row 7 of"), "{t}");
        let t = text(Description::Text {
            id: "7",
            text: "x",
            run_had_row: Some(false),
        });
        assert!(t.contains("the run had no annotation row"), "{t}");
        assert_eq!(
            text(Description::NoRow),
            "<p class=\"unknown\" id=\"description\">no description: the run has no annotation row</p>"
        );
        assert!(text(Description::NotGiven).contains("--annotations FILE"));
        assert!(text(Description::NotInGiven).contains("have none for this scene"));
    }
}
