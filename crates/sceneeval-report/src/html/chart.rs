//! Bar charts and strip plots of percentages as inline SVG, drawn here (no plotting library,
//! no script: the same values always give the same bytes).

use std::fmt::Write as _;

use sceneeval_results::Better;

use crate::compare::text_arrow;
use crate::escape;

/// Colours of the groups, in order (the first for `all`).
pub(crate) const GROUP_COLOURS: [&str; 7] = [
    "#1f5f99", "#2ca02c", "#ff7f0e", "#d62728", "#9467bd", "#8c564b", "#7f7f7f",
];

const LABEL: f64 = 110.0;
const PLOT: f64 = 420.0;
const VALUE: f64 = 70.0;
const BAR: f64 = 12.0;
const GAP: f64 = 2.0;
const BLOCK_GAP: f64 = 10.0;
const TOP: f64 = 22.0;

/// A horizontal bar chart: per column (its name and direction), one bar per group (0 to 100 %),
/// `values[group][column]`; a missing value is written as "no value". Groups are told apart by
/// [`GROUP_COLOURS`] and named in each bar's tooltip.
pub(crate) fn bars(columns: &[(&str, Better)], groups: &[(&str, Vec<Option<f64>>)]) -> String {
    let per_block = groups.len() as f64 * (BAR + GAP) - GAP + BLOCK_GAP;
    let height = TOP + columns.len() as f64 * per_block;
    let width = LABEL + PLOT + VALUE;
    let mut out = svg_start("chart", width, height, "metric values in percent");
    for tick in [0.0, 25.0, 50.0, 75.0, 100.0] {
        grid_line(&mut out, LABEL + PLOT * tick / 100.0, TOP - 4.0, height, tick);
    }
    for (c, (name, better)) in columns.iter().enumerate() {
        let y0 = TOP + c as f64 * per_block;
        let mid = y0 + (per_block - BLOCK_GAP) / 2.0;
        let _ = write!(
            out,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"end\" font-weight=\"600\">{} {}</text>",
            LABEL - 8.0,
            mid + 4.0,
            escape::html(name),
            text_arrow(*better)
        );
        for (g, (group, values)) in groups.iter().enumerate() {
            let y = y0 + g as f64 * (BAR + GAP);
            let colour = GROUP_COLOURS[g % GROUP_COLOURS.len()];
            match values.get(c).copied().flatten() {
                Some(v) => {
                    let w = PLOT * v.clamp(0.0, 100.0) / 100.0;
                    let _ = write!(
                        out,
                        "<rect x=\"{LABEL}\" y=\"{y}\" width=\"{w:.2}\" height=\"{BAR}\" fill=\"{colour}\">\
                         <title>{}: {} {v:.2}%</title></rect>\
                         <text x=\"{:.2}\" y=\"{}\">{v:.2}</text>",
                        escape::html(group),
                        escape::html(name),
                        LABEL + w + 4.0,
                        y + BAR - 2.0
                    );
                }
                None => {
                    let _ = write!(
                        out,
                        "<text x=\"{}\" y=\"{}\" fill=\"#5f6b73\" font-style=\"italic\">{}: no value</text>",
                        LABEL + 4.0,
                        y + BAR - 2.0,
                        escape::html(group)
                    );
                }
            }
        }
    }
    out.push_str("</svg>");
    out
}

/// The opening tag of a chart of class `class`, `width` by `height` units, described by
/// `label` (HTML-escaped by the caller) for screen readers; every chart's text in one font.
fn svg_start(class: &str, width: f64, height: f64, label: &str) -> String {
    format!(
        "<svg class=\"{class}\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {width} {height}\" \
         width=\"{width}\" height=\"{height}\" role=\"img\" aria-label=\"{label}\" \
         font-family=\"system-ui, sans-serif\" font-size=\"11\">"
    )
}

/// A vertical grid line at `x` from `top` to `bottom`, labelled `percent` % above the plot.
fn grid_line(out: &mut String, x: f64, top: f64, bottom: f64, percent: f64) {
    let _ = write!(
        out,
        "<line x1=\"{x}\" y1=\"{top}\" x2=\"{x}\" y2=\"{bottom}\" stroke=\"#d5dbe0\"/>\
         <text x=\"{x}\" y=\"12\" text-anchor=\"middle\" fill=\"#5f6b73\">{percent}%</text>"
    );
}

const STRIP_LABEL: f64 = 96.0;
const STRIP_PLOT: f64 = 400.0;
const STRIP_ROW: f64 = 40.0;
const STRIP_TOP: f64 = 20.0;
const STRIP_RIGHT: f64 = 16.0;
/// Radius of a scene's dot, and the vertical step between dots that would overlap.
const DOT: f64 = 3.5;
const DOT_STEP: f64 = 5.0;
/// Dots stacked on either side of a row's middle before they overlap.
const DOT_LEVELS: usize = 3;

/// The axis of a strip plot: 0 to 100 %, widened to the next multiple of 25 when a value lies
/// outside.
fn strip_axis(rows: &[(&str, Vec<(&str, f64)>)]) -> (f64, f64) {
    let values = rows.iter().flat_map(|(_, v)| v.iter().map(|(_, x)| *x));
    let (lo, hi) = values.fold((0.0_f64, 100.0_f64), |(lo, hi), x| (lo.min(x), hi.max(x)));
    ((lo / 25.0).floor() * 25.0, (hi / 25.0).ceil() * 25.0)
}

/// The vertical offset of the `level`-th dot of a pile: 0, -step, +step, -2 step, ...
fn pile_offset(level: usize) -> f64 {
    let k = level.div_ceil(2) as f64;
    if level % 2 == 1 {
        -k * DOT_STEP
    } else {
        k * DOT_STEP
    }
}

/// One metric's values over the scenes as a strip plot: a row per group (`rows`: its name and
/// its scenes with their values, in percent), a dot per scene on a 0-100 % axis (wider when a
/// value lies outside), named with its value in the dot's tooltip. Dots that would overlap are
/// piled up and down the row's middle in value order (at most [`DOT_LEVELS`] each way, then
/// drawn over the last), so the drawing depends only on the values. Scenes without a value are
/// not in `rows`: the caller names them.
pub(crate) fn strips(name: &str, better: Better, rows: &[(&str, Vec<(&str, f64)>)]) -> String {
    let (lo, hi) = strip_axis(rows);
    let x_of = |v: f64| STRIP_LABEL + STRIP_PLOT * (v - lo) / (hi - lo);
    let height = STRIP_TOP + rows.len() as f64 * STRIP_ROW;
    let width = STRIP_LABEL + STRIP_PLOT + STRIP_RIGHT;
    let label = format!(
        "{} {} per scene, in percent",
        escape::html(name),
        text_arrow(better)
    );
    let mut out = svg_start("strips", width, height, &label);
    let mut tick = lo;
    while tick <= hi {
        grid_line(&mut out, x_of(tick), STRIP_TOP - 4.0, height, tick);
        tick += 25.0;
    }
    for (g, (group, values)) in rows.iter().enumerate() {
        let mid = STRIP_TOP + g as f64 * STRIP_ROW + STRIP_ROW / 2.0;
        let colour = GROUP_COLOURS[g % GROUP_COLOURS.len()];
        let _ = write!(
            out,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{} ({})</text>",
            STRIP_LABEL - 8.0,
            mid + 4.0,
            escape::html(group),
            values.len()
        );
        let mut sorted: Vec<&(&str, f64)> = values.iter().collect();
        sorted.sort_by(|a, b| a.1.total_cmp(&b.1));
        // The dots placed so far, (x, level); a new dot takes the lowest level no dot within
        // a diameter of it holds.
        let mut placed: Vec<(f64, usize)> = Vec::new();
        for (scene, v) in sorted {
            let x = x_of(*v);
            let level = (0..=2 * DOT_LEVELS)
                .find(|l| {
                    !placed
                        .iter()
                        .any(|(px, pl)| pl == l && (px - x).abs() < 2.0 * DOT)
                })
                .unwrap_or(2 * DOT_LEVELS);
            placed.push((x, level));
            let _ = write!(
                out,
                "<circle cx=\"{x:.2}\" cy=\"{:.2}\" r=\"{DOT}\" fill=\"{colour}\" fill-opacity=\"0.75\" \
                 data-scene=\"{}\"><title>{}: {} {v:.2}%</title></circle>",
                mid + pile_offset(level),
                escape::html(scene),
                escape::html(scene),
                escape::html(name)
            );
        }
    }
    out.push_str("</svg>");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_place_each_scene_at_its_value_and_pile_up_equal_ones() {
        let svg = strips(
            "NAV",
            Better::Higher,
            &[
                ("all", vec![("a", 50.0), ("b", 50.0), ("c", 100.0), ("d", 50.0)]),
                ("<easy>", vec![("a", 0.0)]),
            ],
        );
        // 50 % is 200 units into the 400-unit plot after the 96-unit label: x = 296; the three
        // scenes at 50 % pile at the row's middle (40), 5 above and 5 below.
        for (scene, cy) in [("a", "40.00"), ("b", "35.00"), ("d", "45.00")] {
            assert!(
                svg.contains(&format!("cx=\"296.00\" cy=\"{cy}\" r=\"3.5\" fill=\"#1f5f99\" fill-opacity=\"0.75\" data-scene=\"{scene}\"")),
                "{scene}: {svg}"
            );
        }
        assert!(svg.contains("cx=\"496.00\" cy=\"40.00\""), "{svg}");
        // The second row (middle 80), its own colour; names escaped.
        assert!(
            svg.contains("cx=\"96.00\" cy=\"80.00\" r=\"3.5\" fill=\"#2ca02c\""),
            "{svg}"
        );
        assert!(svg.contains("&lt;easy&gt; (1)"), "{svg}");
        assert!(svg.contains("all (4)"), "{svg}");
        assert!(!svg.contains("<easy>"));
        // The same values give the same bytes.
        assert_eq!(
            svg,
            strips(
                "NAV",
                Better::Higher,
                &[
                    ("all", vec![("a", 50.0), ("b", 50.0), ("c", 100.0), ("d", 50.0)]),
                    ("<easy>", vec![("a", 0.0)]),
                ],
            )
        );
    }

    #[test]
    fn the_strip_axis_widens_to_the_values() {
        assert_eq!(strip_axis(&[("all", vec![("a", 40.0)])]), (0.0, 100.0));
        assert_eq!(
            strip_axis(&[("all", vec![("a", 130.0), ("b", -3.0)])]),
            (-25.0, 150.0)
        );
        assert_eq!(
            (0..6).map(pile_offset).collect::<Vec<_>>(),
            [0.0, -5.0, 5.0, -10.0, 10.0, -15.0]
        );
    }

    #[test]
    fn bars_are_proportional_and_names_escaped() {
        let svg = bars(
            &[("SUP", Better::Higher), ("<b>", Better::Lower)],
            &[
                ("all", vec![Some(50.0), None]),
                ("easy", vec![Some(100.0), Some(0.0)]),
            ],
        );
        // 50 % of the 420-unit plot, and 100 %.
        assert!(svg.contains("width=\"210.00\""), "{svg}");
        assert!(svg.contains("width=\"420.00\""), "{svg}");
        assert!(svg.contains("all: no value"), "{svg}");
        assert!(svg.contains("&lt;b&gt; ↓"), "{svg}");
        assert!(!svg.contains("<b>"));
    }
}
