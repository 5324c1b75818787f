//! Bar charts of percentages as inline SVG, drawn here (no plotting library).

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
    let mut out = format!(
        "<svg class=\"chart\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {width} {height}\" \
         width=\"{width}\" height=\"{height}\" role=\"img\" aria-label=\"metric values in percent\" \
         font-family=\"system-ui, sans-serif\" font-size=\"11\">"
    );
    for tick in [0.0, 25.0, 50.0, 75.0, 100.0] {
        let x = LABEL + PLOT * tick / 100.0;
        let _ = write!(
            out,
            "<line x1=\"{x}\" y1=\"{}\" x2=\"{x}\" y2=\"{height}\" stroke=\"#d5dbe0\"/>\
             <text x=\"{x}\" y=\"12\" text-anchor=\"middle\" fill=\"#5f6b73\">{tick}%</text>",
            TOP - 4.0
        );
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

#[cfg(test)]
mod tests {
    use super::*;

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
