//! The top view of a scene as SVG: floors, walls with their doors and windows, blocked access
//! strips, and every object's footprint coloured by what the record says is wrong with it.
//!
//! World coordinates are metres with z up; the drawing looks down the z axis with +y up the page
//! (SVG y = -world y), one SVG unit per metre.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use sceneeval_plausibility::{AccessibilityReport, Grid, Supporter};
use sceneeval_results::SceneReport;
use sceneeval_scene::inspect::SceneInfo;

use crate::escape;

/// What can be wrong with an object, in the order a footprint's colour is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Problem {
    /// In collision with another object.
    Collision,
    /// Less than the threshold share of its surface over a floor.
    OutOfBounds,
    /// Not held by what it should rest on.
    Unsupported,
    /// In the clearance of a blocked door or window.
    BlocksOpening,
    /// No functional side fully free.
    AccessBlocked,
    /// Moved or turned beyond the stability metric's limits under physics.
    Unstable,
}

impl Problem {
    pub(crate) const ALL: [Problem; 6] = [
        Problem::Collision,
        Problem::OutOfBounds,
        Problem::Unsupported,
        Problem::BlocksOpening,
        Problem::AccessBlocked,
        Problem::Unstable,
    ];

    pub(crate) const fn colour(self) -> &'static str {
        match self {
            Problem::Collision => "#d62728",
            Problem::OutOfBounds => "#9467bd",
            Problem::Unsupported => "#ff7f0e",
            Problem::BlocksOpening => "#8c564b",
            Problem::AccessBlocked => "#e377c2",
            Problem::Unstable => "#bcbd22",
        }
    }

    pub(crate) const fn label(self) -> &'static str {
        match self {
            Problem::Collision => "in collision",
            Problem::OutOfBounds => "out of bounds",
            Problem::Unsupported => "unsupported",
            Problem::BlocksOpening => "blocking a door or window",
            Problem::AccessBlocked => "access blocked (no functional side fully free)",
            Problem::Unstable => "unstable (moves under physics)",
        }
    }

    /// The short name used in the scene list's filter and in `data-problems`.
    pub(crate) const fn key(self) -> &'static str {
        match self {
            Problem::Collision => "collision",
            Problem::OutOfBounds => "out-of-bounds",
            Problem::Unsupported => "unsupported",
            Problem::BlocksOpening => "blocks-opening",
            Problem::AccessBlocked => "access-blocked",
            Problem::Unstable => "unstable",
        }
    }
}

/// Colour of a footprint with nothing wrong (or not checked).
pub(crate) const FINE: &str = "#c9d6e0";
const FLOOR: &str = "#f4f1ea";
const WALL: &str = "#3d4449";
const DOOR: &str = "#2a7ab8";
const WINDOW: &str = "#7fc4e8";
const BLOCKED: &str = "#d62728";
const STRIP: &str = "#c2185b";

/// The legend of the top view: `(colour, label, drawn as a line)`.
pub(crate) fn legend_items() -> Vec<(&'static str, &'static str, bool)> {
    let mut items: Vec<(&str, &str, bool)> = Problem::ALL
        .iter()
        .map(|p| (p.colour(), p.label(), false))
        .collect();
    items.push((FINE, "nothing wrong found", false));
    items.push((DOOR, "door", true));
    items.push((WINDOW, "window", true));
    items.push((BLOCKED, "blocked door or window", true));
    items.push((STRIP, "blocked access strip", true));
    items
}

/// Each object's problems with what the record says about them, by object id.
pub(crate) fn problems(report: &SceneReport) -> BTreeMap<String, Vec<(Problem, String)>> {
    let mut out: BTreeMap<String, Vec<(Problem, String)>> = BTreeMap::new();
    let mut add = |id: &str, p: Problem, text: String| out.entry(id.to_owned()).or_default().push((p, text));
    if let Some(c) = &report.collision {
        for o in c.objects.iter().filter(|o| o.in_collision) {
            let with: Vec<&str> = o.colliding_with.iter().map(|i| i.as_str()).collect();
            add(
                o.id.as_str(),
                Problem::Collision,
                format!(
                    "in collision with {} (deepest {:.3} m)",
                    with.join(", "),
                    o.max_depth
                ),
            );
        }
    }
    if let Some(b) = &report.out_of_bounds {
        for o in b.objects.iter().filter(|o| o.out_of_bounds) {
            add(
                o.id.as_str(),
                Problem::OutOfBounds,
                format!(
                    "{:.1}% of its surface over no floor",
                    100.0 * (1.0 - o.ratio_in_bounds)
                ),
            );
        }
    }
    if let Some(s) = &report.support {
        for o in s.objects.iter().filter(|o| !o.supported) {
            let touching: Vec<String> = o.supporters.iter().map(supporter).collect();
            add(
                o.id.as_str(),
                Problem::Unsupported,
                format!(
                    "should rest on {} ({}); touches {}{}",
                    o.support_type,
                    o.type_source.as_deref().unwrap_or("source not recorded"),
                    if touching.is_empty() {
                        "nothing".to_owned()
                    } else {
                        touching.join(", ")
                    },
                    o.min_gap.map(|g| format!("; gap {g:.3} m")).unwrap_or_default()
                ),
            );
        }
    }
    if let Some(c) = &report.opening_clearance {
        for opening in c.openings.iter().filter(|o| o.blocked) {
            for side in opening.sides.iter().filter(|s| s.blocked) {
                for b in &side.blocking {
                    add(
                        b.id.as_str(),
                        Problem::BlocksOpening,
                        format!(
                            "blocks {} {} ({:.0}% of it covered)",
                            opening.kind.name(),
                            opening.opening,
                            100.0 * b.occluded_fraction
                        ),
                    );
                }
            }
        }
    }
    if let Some(a) = &report.accessibility {
        for o in &a.objects {
            if let Some(score) = o.score
                && score < 1.0
            {
                let blockers: Vec<&str> = o
                    .sides
                    .iter()
                    .flat_map(|s| &s.blocked_by)
                    .map(|i| i.as_str())
                    .collect();
                add(
                    o.id.as_str(),
                    Problem::AccessBlocked,
                    format!(
                        "best functional side {} {:.0}% free{}",
                        o.best_side.map(|s| s.name()).unwrap_or("-"),
                        100.0 * score,
                        if blockers.is_empty() {
                            String::new()
                        } else {
                            format!("; blocked by {}", blockers.join(", "))
                        }
                    ),
                );
            }
        }
    }
    if let Some(s) = &report.stability {
        for o in s.objects.iter().filter(|o| !o.stable) {
            add(
                o.id.as_str(),
                Problem::Unstable,
                format!(
                    "under physics moved {:.3} m and turned {:.3} rad",
                    o.displacement_m, o.rotation_rad
                ),
            );
        }
    }
    for list in out.values_mut() {
        list.sort_by_key(|(p, _)| *p);
    }
    out
}

fn supporter(s: &Supporter) -> String {
    match s {
        Supporter::Object(id) => id.as_str().to_owned(),
        Supporter::Floor(f) => format!("floor {f}"),
        Supporter::Wall(w) => format!("wall {w}"),
        Supporter::Ceiling(c) => format!("ceiling {c}"),
    }
}

/// The navigability image of the run (`diagnostics/navigability.png`) and the grid it covers.
#[derive(Debug, Clone)]
pub(crate) struct Overlay {
    /// Its URL from the page.
    pub href: String,
    /// The grid of the record's navigability report.
    pub grid: Grid,
}

/// The top view of `info`, footprints coloured by `problems` and labelled with `numbers` (the
/// object's row in the page's object table); blocked openings and access strips from `report`
/// when the scene was evaluated.
pub(crate) fn draw(
    info: &SceneInfo<'_>,
    report: Option<&SceneReport>,
    problems: &BTreeMap<String, Vec<(Problem, String)>>,
    numbers: &BTreeMap<&str, usize>,
    overlay: Option<&Overlay>,
) -> String {
    let footprints: Vec<[[f64; 2]; 4]> = info
        .objects
        .iter()
        .map(|o| footprint(o.center, o.size, o.yaw))
        .collect();
    let mut xs: Vec<f64> = Vec::new();
    let mut ys: Vec<f64> = Vec::new();
    for room in &info.rooms {
        xs.extend(room.floor.iter().map(|p| p[0]));
        ys.extend(room.floor.iter().map(|p| p[1]));
    }
    for f in &footprints {
        xs.extend(f.iter().map(|p| p[0]));
        ys.extend(f.iter().map(|p| p[1]));
    }
    let finite = |v: &Vec<f64>| v.iter().copied().filter(|x| x.is_finite()).collect::<Vec<f64>>();
    let (xs, ys) = (finite(&xs), finite(&ys));
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let max = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (mut x0, mut x1, mut y0, mut y1) = (min(&xs), max(&xs), min(&ys), max(&ys));
    if !(x0.is_finite() && x1.is_finite() && y0.is_finite() && y1.is_finite()) {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    let span = (x1 - x0).max(y1 - y0).max(0.5);
    let margin = 0.04 * span + 0.2;
    let (vx, vy, vw, vh) = (
        x0 - margin,
        -(y1 + margin),
        x1 - x0 + 2.0 * margin,
        y1 - y0 + 2.0 * margin,
    );
    let line = span / 250.0;
    let font = span / 45.0;

    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"topview\" viewBox=\"{vx:.3} {vy:.3} {vw:.3} {vh:.3}\" \
         role=\"img\" aria-label=\"top view of the scene\" font-family=\"system-ui, sans-serif\">"
    );
    floors(&mut svg, info);
    if let Some(o) = overlay {
        navigable(&mut svg, o);
    }
    if let Some(a) = report.and_then(|r| r.accessibility.as_ref()) {
        blocked_strips(&mut svg, a, line);
    }
    walls(&mut svg, info, report, line);
    objects(&mut svg, info, &footprints, problems, numbers, line, font);
    svg.push_str("</svg>");
    svg
}

/// The colour of the outline around the objects a spec names ([`outlined`]).
pub const OUTLINE: &str = "#d81b60";

/// The top view of `info` (floors, walls, openings, every object's footprint) with the objects
/// `named` outlined in [`OUTLINE`] and numbered 1, 2, ... in their order, for a person judging
/// a spec (`sceneeval judge`). A standalone SVG document (`image/svg+xml`); ids not in the
/// scene are left out.
pub fn outlined(info: &SceneInfo<'_>, named: &[&str]) -> String {
    let numbers: BTreeMap<&str, usize> = named.iter().enumerate().map(|(k, id)| (*id, k + 1)).collect();
    let mut svg = draw(info, None, &BTreeMap::new(), &numbers, None);
    // The scene's extent, as `draw` measures it, sets the outline's width (2.5 times the
    // walls' line).
    let corners: Vec<[f64; 2]> = info
        .rooms
        .iter()
        .flat_map(|r| r.floor.iter().copied())
        .chain(
            info.objects
                .iter()
                .flat_map(|o| footprint(o.center, o.size, o.yaw)),
        )
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect();
    let extent = |k: usize| {
        let (lo, hi) = corners
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p[k]), hi.max(p[k]))
            });
        if hi >= lo { hi - lo } else { 0.0 }
    };
    let width = 2.5 * extent(0).max(extent(1)).max(0.5) / 250.0;
    let mut outlines = String::new();
    for o in info.objects.iter().filter(|o| numbers.contains_key(o.id)) {
        let _ = write!(
            outlines,
            "<polygon class=\"outline\" data-object=\"{}\" points=\"{}\" fill=\"none\" stroke=\"{OUTLINE}\" stroke-width=\"{width:.4}\"/>",
            escape::html(o.id),
            points(&footprint(o.center, o.size, o.yaw))
        );
    }
    if let Some(end) = svg.rfind("</svg>") {
        svg.insert_str(end, &outlines);
    }
    svg
}

/// The rooms' floors.
fn floors(svg: &mut String, info: &SceneInfo<'_>) {
    for room in &info.rooms {
        let _ = write!(
            svg,
            "<polygon class=\"floor\" points=\"{}\" fill=\"{FLOOR}\"><title>{} ({:.2} m²)</title></polygon>",
            points(&room.floor),
            escape::html(&format!(
                "room {}{}",
                room.id,
                room.kind.map(|k| format!(", {k}")).unwrap_or_default()
            )),
            room.floor_area
        );
    }
}

/// The run's navigable region over the floor.
fn navigable(svg: &mut String, o: &Overlay) {
    let g = &o.grid;
    let (w, h) = (g.width as f64 * g.pixel, g.height as f64 * g.pixel);
    let _ = write!(
        svg,
        "<image class=\"navigable\" href=\"{}\" x=\"{:.3}\" y=\"{:.3}\" width=\"{w:.3}\" height=\"{h:.3}\" \
         opacity=\"0.45\" preserveAspectRatio=\"none\"/>",
        escape::html(&o.href),
        g.x0,
        -(g.y0 + h)
    );
}

/// The access strips of objects' sides that something blocks.
fn blocked_strips(svg: &mut String, a: &AccessibilityReport, line: f64) {
    for o in &a.objects {
        for side in o.sides.iter().filter(|s| !s.blocked_by.is_empty()) {
            let pts: Vec<[f64; 2]> = side.strip.iter().map(|p| [p.x, p.y]).collect();
            let _ = write!(
                svg,
                "<polygon class=\"strip\" points=\"{}\" fill=\"none\" stroke=\"{STRIP}\" stroke-width=\"{line:.4}\" \
                 stroke-dasharray=\"{:.4}\"><title>{}</title></polygon>",
                points(&pts),
                3.0 * line,
                escape::html(&format!(
                    "{} side of {}: blocked",
                    side.side.name(),
                    o.id.as_str()
                ))
            );
        }
    }
}

/// The walls, with their doors and windows (blocked ones dashed, with what blocks them).
fn walls(svg: &mut String, info: &SceneInfo<'_>, report: Option<&SceneReport>, line: f64) {
    let blocked: BTreeMap<&str, Vec<&str>> = report
        .and_then(|r| r.opening_clearance.as_ref())
        .into_iter()
        .flat_map(|c| &c.openings)
        .filter(|o| o.blocked)
        .map(|o| {
            let by = o
                .sides
                .iter()
                .flat_map(|s| &s.blocking)
                .map(|b| b.id.as_str())
                .collect();
            (o.opening.as_str(), by)
        })
        .collect();
    for room in &info.rooms {
        for wall in &room.walls {
            let _ = write!(
                svg,
                "<line class=\"wall\" x1=\"{:.3}\" y1=\"{:.3}\" x2=\"{:.3}\" y2=\"{:.3}\" stroke=\"{WALL}\" \
                 stroke-width=\"{:.4}\" stroke-linecap=\"square\"><title>{}</title></line>",
                wall.start[0],
                -wall.start[1],
                wall.end[0],
                -wall.end[1],
                2.0 * line,
                escape::html(&format!("wall {}", wall.id))
            );
            let dir = [wall.end[0] - wall.start[0], wall.end[1] - wall.start[1]];
            let len = (dir[0] * dir[0] + dir[1] * dir[1]).sqrt().max(1e-12);
            for opening in &wall.openings {
                let at = |t: f64| [wall.start[0] + dir[0] * t / len, wall.start[1] + dir[1] * t / len];
                let (a, b) = (at(opening.along[0]), at(opening.along[1]));
                let blockers = blocked.get(opening.id);
                let colour = match (blockers, opening.kind) {
                    (Some(_), _) => BLOCKED,
                    (None, "door") => DOOR,
                    (None, _) => WINDOW,
                };
                let title = match blockers {
                    Some(by) => format!("{} {}: blocked by {}", opening.kind, opening.id, by.join(", ")),
                    None => format!("{} {}", opening.kind, opening.id),
                };
                let _ = write!(
                    svg,
                    "<line class=\"opening\" x1=\"{:.3}\" y1=\"{:.3}\" x2=\"{:.3}\" y2=\"{:.3}\" stroke=\"{colour}\" \
                     stroke-width=\"{:.4}\"{}><title>{}</title></line>",
                    a[0],
                    -a[1],
                    b[0],
                    -b[1],
                    5.0 * line,
                    if blockers.is_some() {
                        format!(" stroke-dasharray=\"{:.4}\"", 4.0 * line)
                    } else {
                        String::new()
                    },
                    escape::html(&title)
                );
            }
        }
    }
}

/// The objects' footprints, lowest top first, coloured by their first problem.
fn objects(
    svg: &mut String,
    info: &SceneInfo<'_>,
    footprints: &[[[f64; 2]; 4]],
    problems: &BTreeMap<String, Vec<(Problem, String)>>,
    numbers: &BTreeMap<&str, usize>,
    line: f64,
    font: f64,
) {
    // Lowest top first, so what is seen from above is drawn last (a rug under the bed).
    let mut order: Vec<usize> = (0..info.objects.len()).collect();
    let top = |k: usize| info.objects[k].center[2] + info.objects[k].size[2] / 2.0;
    order.sort_by(|&a, &b| top(a).total_cmp(&top(b)).then(a.cmp(&b)));
    for k in order {
        let (o, f) = (&info.objects[k], &footprints[k]);
        let list = problems.get(o.id);
        let colour = list.and_then(|l| l.first()).map_or(FINE, |(p, _)| p.colour());
        let mut title = format!(
            "{}{}",
            numbers.get(o.id).map(|n| format!("{n}. ")).unwrap_or_default(),
            o.id
        );
        if let Some(c) = o.category {
            let _ = write!(title, " ({c})");
        }
        for (_, text) in list.into_iter().flatten() {
            let _ = write!(title, "\n{text}");
        }
        let front = [f[0], f[1]];
        let centre = [o.center[0], o.center[1]];
        let _ = write!(
            svg,
            "<g class=\"object\" data-object=\"{}\"><title>{}</title>\
             <polygon points=\"{}\" fill=\"{colour}\" fill-opacity=\"0.85\" stroke=\"#333\" stroke-width=\"{line:.4}\"/>\
             <polyline points=\"{}\" fill=\"none\" stroke=\"#111\" stroke-width=\"{:.4}\"/>",
            escape::html(o.id),
            escape::html(&title),
            points(f),
            points(&front),
            2.5 * line
        );
        if let Some(n) = numbers.get(o.id) {
            let _ = write!(
                svg,
                "<text x=\"{:.3}\" y=\"{:.3}\" font-size=\"{font:.3}\" text-anchor=\"middle\" \
                 dominant-baseline=\"central\" fill=\"#111\">{n}</text>",
                centre[0], -centre[1]
            );
        }
        svg.push_str("</g>");
    }
}

/// The corners of a box's footprint: `centre`, full `size` (width x, depth y), turned by `yaw`
/// about +z; the first two corners are the front edge (local -y).
pub(crate) fn footprint(centre: [f64; 3], size: [f64; 3], yaw: f64) -> [[f64; 2]; 4] {
    let (s, c) = yaw.sin_cos();
    let (hw, hd) = (size[0] / 2.0, size[1] / 2.0);
    [(-hw, -hd), (hw, -hd), (hw, hd), (-hw, hd)]
        .map(|(x, y)| [centre[0] + c * x - s * y, centre[1] + s * x + c * y])
}

/// SVG `points` of world xy points (y flipped).
fn points(pts: &[[f64; 2]]) -> String {
    pts.iter()
        .map(|p| format!("{:.3},{:.3}", p[0], -p[1]))
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn footprints_follow_the_yaw_with_the_front_first() {
        // A 2 x 1 m box at the origin, yaw 0: front edge at y = -0.5.
        let f = footprint([0.0, 0.0, 0.0], [2.0, 1.0, 1.0], 0.0);
        assert_eq!(f, [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]]);
        // Turned 90 degrees: the front (local -y) faces world +x, so the front edge is at x = 0.5.
        let f = footprint([0.0, 0.0, 0.0], [2.0, 1.0, 1.0], std::f64::consts::FRAC_PI_2);
        assert!(
            (f[0][0] - 0.5).abs() < 1e-12 && (f[1][0] - 0.5).abs() < 1e-12,
            "{f:?}"
        );
        assert_eq!(points(&[[1.0, 2.0]]), "1.000,-2.000");
    }
}
