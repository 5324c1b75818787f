//! HTML pages: the shell every page shares (inline CSS and a small inline script, nothing
//! fetched from anywhere), the overview and scene pages of a report, the comparison page, and
//! the SVG drawn into them.
//!
//! Wide tables sit in a `div.wide` that scrolls sideways, with the first column (the row's
//! name) kept in view (`position: sticky`), so no column is cut off at any window width.
//!
//! The script sorts tables (`table.sortable`: click a header), filters the scene list
//! (`select#fails`), highlights an object's footprint from its row, and marks the page: the
//! root element gets `data-script="ok"` when the script ran to its end, and
//! `data-script="error"` with `data-script-error` on any script error of the page (a browser
//! test reads these back from the DOM).

pub(crate) mod chart;
pub(crate) mod compare;
pub(crate) mod labels;
pub(crate) mod overview;
pub(crate) mod scene;
pub(crate) mod topview;

use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

use crate::escape;

/// The style sheet of every page: readable on a laptop, printable (controls hidden, tables
/// unbroken where possible).
const CSS: &str = r#"
:root { --fg: #1d2327; --muted: #5f6b73; --line: #d5dbe0; --bg: #ffffff; --head: #f3f5f7; --accent: #1f5f99; }
* { box-sizing: border-box; }
body { margin: 0 auto; max-width: 1180px; padding: 1.2rem 1.5rem 3rem; color: var(--fg); background: var(--bg);
  font: 15px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, sans-serif; }
h1 { font-size: 1.55rem; margin: 0.2rem 0 0.6rem; }
h2 { font-size: 1.2rem; margin: 1.8rem 0 0.6rem; border-bottom: 1px solid var(--line); padding-bottom: 0.2rem; }
h3 { font-size: 1.02rem; margin: 1.2rem 0 0.4rem; }
a { color: var(--accent); }
p.meta, .muted { color: var(--muted); }
nav.crumbs { font-size: 0.9rem; margin-bottom: 0.4rem; }
table { border-collapse: collapse; margin: 0.4rem 0 0.8rem; font-variant-numeric: tabular-nums; }
th, td { border: 1px solid var(--line); padding: 0.22rem 0.5rem; vertical-align: top; }
th { background: var(--head); text-align: left; font-weight: 600; }
td.num, th.num { text-align: right; }
table.sortable th { cursor: pointer; user-select: none; }
table.sortable th[aria-sort="ascending"]::after { content: " \25B2"; font-size: 0.7em; }
table.sortable th[aria-sort="descending"]::after { content: " \25BC"; font-size: 0.7em; }
.wide { overflow-x: auto; max-width: 100%; }
.wide > table > * > tr > :first-child { position: sticky; left: 0; z-index: 1; background: var(--bg); box-shadow: 1px 0 0 var(--line); }
.wide > table > thead > tr > :first-child, .wide > table > tbody > tr > th:first-child { background: var(--head); }
.wide > table > tbody > tr.hi > :first-child { background: #fff6cc; }
.distributions { display: grid; grid-template-columns: repeat(auto-fill, minmax(520px, 1fr)); gap: 0.6rem 1.2rem; }
.distributions svg { max-width: 100%; height: auto; }
.distributions figcaption { font-size: 0.85rem; color: var(--muted); }
.bad { color: #b3261e; font-weight: 600; }
.good { color: #1b7a3a; }
.unknown { color: var(--muted); font-style: italic; }
.box { border: 1px solid var(--line); border-radius: 6px; padding: 0.6rem 0.8rem; margin: 0.6rem 0; background: #fafbfc; }
.error { border-color: #e3a39d; background: #fdf3f2; }
.controls { margin: 0.4rem 0; }
ul.legend { list-style: none; padding: 0; margin: 0.4rem 0; display: flex; flex-wrap: wrap; gap: 0.4rem 1.2rem; }
ul.legend li { display: flex; align-items: center; gap: 0.35rem; font-size: 0.9rem; }
.swatch { display: inline-block; width: 1.1em; height: 0.8em; border: 1px solid #555; }
.swatch.line { height: 0.25em; border: none; }
.topview { display: flex; flex-wrap: wrap; gap: 1rem; align-items: flex-start; }
.topview svg { width: 100%; max-width: 640px; height: auto; border: 1px solid var(--line); background: #fff; }
svg .hi polygon { stroke: #000; stroke-width: 0.06; }
tr.hi { background: #fff6cc; }
figure { margin: 0; }
.views { display: grid; grid-template-columns: repeat(auto-fill, minmax(170px, 1fr)); gap: 0.8rem; }
.views img { width: 100%; height: auto; border: 1px solid var(--line); background: repeating-conic-gradient(#eee 0 25%, #fff 0 50%) 0 0 / 16px 16px; }
.views figcaption { font-size: 0.8rem; color: var(--muted); word-break: break-all; }
details { margin: 0.3rem 0; }
code { font-size: 0.92em; }
@media print {
  body { max-width: none; padding: 0; font-size: 11pt; }
  .controls, nav.crumbs, .noprint { display: none !important; }
  a { color: inherit; text-decoration: none; }
  h2 { break-after: avoid; }
  table, figure, svg { break-inside: avoid; }
  tr[hidden] { display: table-row !important; }
}
"#;

/// The script of every page (see the module documentation). Written for browsers from 2017 on,
/// no library.
const SCRIPT: &str = r##"
(function () {
  "use strict";
  var root = document.documentElement;
  window.addEventListener("error", function (e) {
    root.setAttribute("data-script", "error");
    root.setAttribute("data-script-error", String(e.message));
  });
  function key(td) {
    var v = td.getAttribute("data-v");
    return v === null ? td.textContent.trim() : v;
  }
  function each(list, f) { Array.prototype.forEach.call(list, f); }
  each(document.querySelectorAll("table.sortable"), function (table) {
    var heads = table.tHead.rows[0].cells;
    each(heads, function (th, col) {
      th.addEventListener("click", function () {
        var body = table.tBodies[0];
        var rows = Array.prototype.slice.call(body.rows);
        var numeric = th.getAttribute("data-type") === "num";
        var dir = th.getAttribute("aria-sort") === "ascending" ? -1 : 1;
        each(heads, function (h) { h.removeAttribute("aria-sort"); });
        th.setAttribute("aria-sort", dir === 1 ? "ascending" : "descending");
        rows.sort(function (a, b) {
          var x = key(a.cells[col]), y = key(b.cells[col]);
          if (x === "" || y === "") { return x === y ? 0 : (x === "" ? 1 : -1); }
          if (numeric) { return dir * (parseFloat(x) - parseFloat(y)); }
          return dir * x.localeCompare(y);
        });
        each(rows, function (r) { body.appendChild(r); });
      });
    });
  });
  var filter = document.getElementById("fails");
  if (filter) {
    var apply = function () {
      var want = filter.value, shown = 0;
      each(document.querySelectorAll("#scenes tbody tr"), function (tr) {
        var fails = (tr.getAttribute("data-fails") || "").split(" ");
        var show = want === "" || fails.indexOf(want) >= 0;
        tr.hidden = !show;
        if (show) { shown += 1; }
      });
      var count = document.getElementById("shown");
      if (count) { count.textContent = String(shown); }
    };
    filter.addEventListener("change", apply);
    apply();
  }
  function mark(id, on) {
    each(document.querySelectorAll("[data-object]"), function (x) {
      if (x.getAttribute("data-object") === id) { x.classList.toggle("hi", on); }
    });
  }
  each(document.querySelectorAll("[data-object]"), function (el) {
    el.addEventListener("mouseenter", function () { mark(el.getAttribute("data-object"), true); });
    el.addEventListener("mouseleave", function () { mark(el.getAttribute("data-object"), false); });
  });
  root.setAttribute("data-script", "ok");
})();
"##;

/// A whole page: `title` (escaped here) and `body` (already HTML).
pub(crate) fn page(title: &str, body: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <meta name=\"generator\" content=\"sceneeval-report {}\">\n<title>{}</title>\n<style>{CSS}</style>\n</head>\n\
         <body>\n{body}\n<script>{SCRIPT}</script>\n</body>\n</html>\n",
        env!("CARGO_PKG_VERSION"),
        escape::html(title)
    )
}

/// A `<td>` holding a number (sorting key in `data-v`, empty when missing).
pub(crate) fn num_cell(v: Option<f64>) -> String {
    match v {
        Some(v) => format!("<td class=\"num\" data-v=\"{v}\">{v:.2}</td>"),
        None => "<td class=\"num\" data-v=\"\">-</td>".to_owned(),
    }
}

/// The link from a page in folder `from` to `to`, as a relative URL (each segment
/// percent-encoded), when both resolve to absolute paths.
pub(crate) fn relative_href(from: &Path, to: &Path) -> Option<String> {
    let from = absolute(from)?;
    let to = absolute(to)?;
    let a: Vec<Component<'_>> = from.components().collect();
    let b: Vec<Component<'_>> = to.components().collect();
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut parts: Vec<String> = std::iter::repeat_n("..".to_owned(), a.len() - common).collect();
    for c in &b[common..] {
        parts.push(escape::url_segment(&c.as_os_str().to_string_lossy()));
    }
    Some(if parts.is_empty() {
        ".".to_owned()
    } else {
        parts.join("/")
    })
}

/// `path` made absolute and free of `.` and `..`: canonical when it exists, else its existing
/// parent's canonical form joined with the rest.
fn absolute(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = path.canonicalize() {
        return Some(p);
    }
    let parent = path.parent()?;
    let name = path.file_name()?;
    let parent = if parent.as_os_str().is_empty() {
        Path::new(".")
    } else {
        parent
    };
    Some(absolute(parent)?.join(name))
}

/// A bulleted legend: `(css colour, label, line?)`.
pub(crate) fn legend(items: &[(&str, &str, bool)]) -> String {
    let mut out = String::from("<ul class=\"legend\">");
    for (colour, label, line) in items {
        let _ = write!(
            out,
            "<li><span class=\"swatch{}\" style=\"background:{colour}\"></span>{}</li>",
            if *line { " line" } else { "" },
            escape::html(label)
        );
    }
    out.push_str("</ul>");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_links_between_folders() {
        let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
        let run = dir.path().join("run");
        let pages = run.join("report").join("scenes");
        std::fs::create_dir_all(&pages).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            relative_href(&pages, &run.join("scene_8").join("views").join("front a#1.png")).as_deref(),
            Some("../../scene_8/views/front%20a%231.png")
        );
        assert_eq!(relative_href(&run, &run).as_deref(), Some("."));
        assert_eq!(
            relative_href(
                &pages,
                &dir.path().join("other").join("report").join("index.html")
            )
            .as_deref(),
            Some("../../../other/report/index.html")
        );
    }

    #[test]
    fn the_page_escapes_its_title_and_fetches_nothing() {
        let p = page("<script>x</script>", "<p>body</p>");
        assert!(p.contains("<title>&lt;script&gt;x&lt;/script&gt;</title>"));
        for remote in ["http://", "https://", "//cdn", "@import", "src=\"", "url("] {
            assert!(!p.contains(remote), "{remote}");
        }
    }
}
