//! The paired comparisons and the scenes each run lacks as Markdown, CSV and LaTeX.

use std::fmt::Write as _;

use sceneeval_stats::bootstrap::DEFAULT_RESAMPLES;

use sceneeval_results::Better;

use super::{Comparison, PairComparison, text_arrow};
use crate::ReportError;
use crate::escape;

/// The columns of [`Comparison::to_paired_csv`].
pub const PAIRED_CSV_COLUMNS: [&str; 17] = [
    "kind",
    "a",
    "b",
    "metric",
    "n",
    "mean_diff",
    "diff_low",
    "diff_high",
    "p_value",
    "p_holm",
    "better",
    "method",
    "zeros",
    "a_only",
    "b_only",
    "favours",
    "note",
];

/// A difference in percentage points with two decimals and its sign.
fn signed(d: f64) -> String {
    format!("{d:+.2}")
}

/// A p-value for a table: three significant digits, scientific below 0.001.
pub(crate) fn p_text(p: f64) -> String {
    if p == 0.0 || p >= 1e-3 {
        format!("{p:.3}")
    } else {
        format!("{p:.2e}")
    }
}

/// How a table writes the paired rows: names escaped, a column's direction, the mark of a
/// significant difference.
pub(crate) struct Style {
    /// Escapes a run's or column's name.
    pub escape: fn(&str) -> String,
    /// A column's direction (`↑`, `$\uparrow$`).
    pub arrow: fn(Better) -> &'static str,
    /// Appended to a significant difference (`*`, `$^{*}$`).
    pub mark: &'static str,
}

impl Style {
    /// Markdown (and plain text): `↑`, `*`.
    pub(crate) const MARKDOWN: Style = Style {
        escape: escape::markdown,
        arrow: text_arrow,
        mark: "*",
    };
    /// HTML: names escaped for HTML, `↑`, `*`.
    pub(crate) const HTML: Style = Style {
        escape: escape::html,
        arrow: text_arrow,
        mark: "*",
    };
    /// LaTeX: `$\uparrow$`, `$^{*}$`.
    pub(crate) const LATEX: Style = Style {
        escape: escape::latex,
        arrow: |b| match b {
            Better::Higher => "$\\uparrow$",
            Better::Lower => "$\\downarrow$",
        },
        mark: "$^{*}$",
    };
}

impl Comparison {
    /// The cells of the table of paired differences, one row per pair of runs and column, in
    /// `style`: a, b, column with its direction, n, b - a (marked when significant), interval,
    /// p, p (Holm), the run a significant difference favours (empty otherwise).
    pub(crate) fn paired_cells(&self, style: &Style) -> Vec<[String; 9]> {
        let esc = style.escape;
        self.pairs
            .iter()
            .flat_map(|pair| pair.rows.iter().map(move |row| (pair, row)))
            .map(|(pair, row)| {
                let mark = if row.significant(self.alpha) {
                    style.mark
                } else {
                    ""
                };
                let better = match (row.significant(self.alpha), row.favours_b()) {
                    (true, Some(true)) => esc(&self.runs[pair.b].name),
                    (true, Some(false)) => esc(&self.runs[pair.a].name),
                    _ => String::new(),
                };
                [
                    esc(&self.runs[pair.a].name),
                    esc(&self.runs[pair.b].name),
                    format!("{} {}", esc(row.column.name), (style.arrow)(row.column.better)),
                    row.n.to_string(),
                    row.mean_difference
                        .map_or_else(|| "-".to_owned(), |d| format!("{}{mark}", signed(d))),
                    row.interval.map_or_else(
                        || "-".to_owned(),
                        |[lo, hi]| format!("[{}, {}]", signed(lo), signed(hi)),
                    ),
                    row.p.map_or_else(|_| "-".to_owned(), p_text),
                    row.p_holm.map_or_else(|| "-".to_owned(), p_text),
                    better,
                ]
            })
            .collect()
    }

    /// The cells of the McNemar table, one row per pair of runs and fidelity metric, the run
    /// names escaped as `style` does: a, b, metric, specs, a only, b only, b - a, p, p (Holm).
    pub(crate) fn verdict_cells(&self, style: &Style) -> Vec<[String; 9]> {
        let escape = style.escape;
        self.pairs
            .iter()
            .flat_map(|pair| pair.verdicts.iter().map(move |v| (pair, v)))
            .map(|(pair, v)| {
                [
                    escape(&self.runs[pair.a].name),
                    escape(&self.runs[pair.b].name),
                    v.metric.columns()[0].to_string(),
                    v.n.to_string(),
                    v.test.b.to_string(),
                    v.test.c.to_string(),
                    v.difference().map_or_else(|| "-".to_owned(), signed),
                    p_text(v.test.p),
                    v.p_holm.map_or_else(|| "-".to_owned(), p_text),
                ]
            })
            .collect()
    }

    /// The sentence under every table for each run that lacks or failed scenes, or one
    /// sentence saying every run has every scene.
    pub fn coverage_lines(&self) -> Vec<String> {
        let lacking: Vec<String> = self
            .coverage
            .iter()
            .filter(|c| !c.missing.is_empty() || !c.failed.is_empty())
            .map(|c| c.sentence(&self.runs[c.run].name))
            .collect();
        if lacking.is_empty() {
            let total = self.coverage.first().map_or(0, |c| c.total);
            vec![format!(
                "Every run has all {}, none failed.",
                super::scenes(total)
            )]
        } else {
            lacking
        }
    }

    /// The legend of the paired tables.
    pub fn paired_legend(&self) -> String {
        format!(
            "Paired differences b - a in percentage points over the scenes both runs evaluated with a value (n); \
             [lo, hi]: {}% paired bootstrap interval (scenes resampled, {DEFAULT_RESAMPLES} resamples, fixed seed, \
             percentile method); p: two-sided Wilcoxon signed-rank test (zero differences dropped, differences \
             rounded to 1e-9; exact up to 50 untied non-zero differences, else normal with tie and continuity \
             correction; none from fewer than two non-zero differences); p (Holm): adjusted across the pair's \
             columns; *: p (Holm) < {}. Verdicts: McNemar's exact test on the specs both runs judged (a only: \
             satisfied in a alone; b only: in b alone), Holm across the pair's metrics.",
            (self.paired_level * 1e4).round() / 1e2,
            self.alpha
        )
    }

    /// The notes of the pairs: their warnings, then every row without a p-value.
    pub fn paired_notes(&self) -> Vec<String> {
        let mut out = Vec::new();
        for pair in &self.pairs {
            out.extend(pair.notes.iter().cloned());
            for row in &pair.rows {
                if let Some(note) = row.note() {
                    out.push(format!("{}: {note}.", self.pair_name(pair, row.column.name)));
                }
            }
        }
        out
    }

    fn pair_name(&self, pair: &PairComparison, column: &str) -> String {
        format!(
            "{} - {}, {column}",
            self.runs[pair.b].name, self.runs[pair.a].name
        )
    }

    /// Markdown of the paired comparisons (empty without pairs).
    pub(crate) fn paired_markdown(&self) -> String {
        let mut out = String::new();
        if self.pairs.is_empty() {
            return out;
        }
        let md = escape::markdown;
        out.push_str("### Paired differences (b - a)\n\n");
        out.push_str("| a | b | column | n | b - a | interval | p | p (Holm) | better |\n");
        out.push_str("|---|---|---|---:|---:|---|---:|---:|---|\n");
        for cells in self.paired_cells(&Style::MARKDOWN) {
            let _ = writeln!(out, "| {} |", cells.join(" | "));
        }
        out.push('\n');
        if self.pairs.iter().any(|p| !p.verdicts.is_empty()) {
            out.push_str("### Fidelity verdicts (McNemar)\n\n");
            out.push_str("| a | b | metric | specs | a only | b only | b - a | p | p (Holm) |\n");
            out.push_str("|---|---|---|---:|---:|---:|---:|---:|---:|\n");
            for cells in self.verdict_cells(&Style::MARKDOWN) {
                let _ = writeln!(out, "| {} |", cells.join(" | "));
            }
            out.push('\n');
        }
        let notes = self.paired_notes();
        if !notes.is_empty() {
            out.push_str("Paired notes:\n\n");
            for note in notes {
                let _ = writeln!(out, "- {}", md(&note));
            }
            out.push('\n');
        }
        out.push_str(&self.paired_legend());
        out.push('\n');
        out
    }

    /// A booktabs `tabular` of the paired comparisons (empty without pairs), notes as `%`
    /// comments.
    pub(crate) fn paired_latex(&self) -> String {
        let mut out = String::new();
        if self.pairs.is_empty() {
            return out;
        }
        let tex = escape::latex;
        out.push_str("\n% Paired differences (b - a)\n\\begin{tabular}{lllrrlrr}\n\\toprule\n");
        out.push_str(
            "a & b & Metric & $n$ & $b - a$ & Interval & $p$ & $p_{\\mathrm{Holm}}$ \\\\\n\\midrule\n",
        );
        for cells in self.paired_cells(&Style::LATEX) {
            // No column of the favoured run: the mark says which differences are significant.
            let _ = writeln!(out, "{} \\\\", cells[..8].join(" & "));
        }
        out.push_str("\\bottomrule\n\\end{tabular}\n");
        if self.pairs.iter().any(|p| !p.verdicts.is_empty()) {
            out.push_str(
                "\n% Fidelity verdicts (McNemar's exact test)\n\\begin{tabular}{lllrrrrrr}\n\\toprule\n",
            );
            out.push_str(
                "a & b & Metric & Specs & $a$ only & $b$ only & $b - a$ & $p$ & $p_{\\mathrm{Holm}}$ \\\\\n\\midrule\n",
            );
            for cells in self.verdict_cells(&Style::LATEX) {
                let _ = writeln!(out, "{} \\\\", cells.join(" & "));
            }
            out.push_str("\\bottomrule\n\\end{tabular}\n");
        }
        for note in self.paired_notes() {
            let _ = writeln!(out, "% Note: {}", tex(&note));
        }
        let _ = writeln!(out, "% {}", tex(&self.paired_legend()));
        out
    }

    /// The paired comparisons as CSV, one row per pair and column (`kind` = `paired`) and per
    /// pair and fidelity metric (`kind` = `mcnemar`), with the columns of
    /// [`PAIRED_CSV_COLUMNS`] (docs/formats.md describes each): differences with six decimals,
    /// p-values in full precision (the shortest text that reads back as the same number),
    /// empty cells where there is no value, the reason in `note`.
    ///
    /// # Errors
    /// [`ReportError::Csv`] when the CSV writer fails.
    pub fn to_paired_csv(&self) -> Result<String, ReportError> {
        let csv_error = |source| ReportError::Csv {
            path: "(compare --paired)".into(),
            source,
        };
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(PAIRED_CSV_COLUMNS).map_err(csv_error)?;
        for row in self.paired_records() {
            w.write_record(row.cells().map(sceneeval_files::csv_cell::escape_owned))
                .map_err(csv_error)?;
        }
        let bytes = w.into_inner().map_err(|e| csv_error(e.into_error().into()))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// The rows of [`Comparison::to_paired_csv`], typed (what Python's
    /// `sceneeval.compare(runs, paired=True)` returns as dicts).
    pub fn paired_records(&self) -> Vec<PairedRecord> {
        let mut out = Vec::new();
        for pair in &self.pairs {
            let (a, b) = (&self.runs[pair.a].name, &self.runs[pair.b].name);
            for row in &pair.rows {
                out.push(PairedRecord {
                    kind: "paired",
                    a: a.clone(),
                    b: b.clone(),
                    metric: row.column.name.to_owned(),
                    n: row.n,
                    mean_diff: row.mean_difference,
                    diff_low: row.interval.map(|i| i[0]),
                    diff_high: row.interval.map(|i| i[1]),
                    p_value: row.p.ok(),
                    p_holm: row.p_holm,
                    better: row.column.better.name(),
                    method: row.method,
                    zeros: Some(row.zeros),
                    a_only: None,
                    b_only: None,
                    favours: favours(row.favours_b(), a, b),
                    note: row.note(),
                });
            }
            for v in &pair.verdicts {
                let diff = v.difference();
                out.push(PairedRecord {
                    kind: "mcnemar",
                    a: a.clone(),
                    b: b.clone(),
                    metric: v.metric.columns()[0].to_owned(),
                    n: v.n,
                    mean_diff: diff,
                    diff_low: None,
                    diff_high: None,
                    p_value: Some(v.test.p),
                    p_holm: v.p_holm,
                    better: "higher",
                    method: "exact",
                    zeros: None,
                    a_only: Some(v.test.b),
                    b_only: Some(v.test.c),
                    favours: favours(diff.filter(|d| *d != 0.0).map(|d| d > 0.0), a, b),
                    note: (v.n == 0).then(|| "no spec judged in both runs".to_owned()),
                });
            }
        }
        out
    }
}

/// One row of the paired comparison (`compare --paired --format csv`), its fields in
/// [`PAIRED_CSV_COLUMNS`]' order; `docs/formats.md` describes each.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PairedRecord {
    /// `paired` (a metric column, Wilcoxon) or `mcnemar` (a fidelity metric's verdicts).
    pub kind: &'static str,
    /// The first run's name.
    pub a: String,
    /// The second run's name; differences are `b - a`.
    pub b: String,
    /// The summary column (`paired`) or fidelity metric (`mcnemar`).
    pub metric: String,
    /// Scenes both runs evaluated with a value (`paired`); specs both judged (`mcnemar`).
    pub n: usize,
    /// The mean difference `b - a` in percentage points (`mcnemar`: of the satisfied share).
    pub mean_diff: Option<f64>,
    /// The paired bootstrap interval's low end.
    pub diff_low: Option<f64>,
    /// Its high end.
    pub diff_high: Option<f64>,
    /// The two-sided p-value (Wilcoxon, or McNemar's exact test).
    pub p_value: Option<f64>,
    /// Holm-adjusted across the pair's columns (`paired`) or metrics (`mcnemar`).
    pub p_holm: Option<f64>,
    /// `higher` or `lower`: which way the column improves.
    pub better: &'static str,
    /// `exact`, `normal` or `none`.
    pub method: &'static str,
    /// Zero differences dropped from the test (`paired`).
    pub zeros: Option<usize>,
    /// Specs satisfied in a only (`mcnemar`).
    pub a_only: Option<u64>,
    /// Specs satisfied in b only (`mcnemar`).
    pub b_only: Option<u64>,
    /// The run the mean difference favours, if any.
    pub favours: Option<String>,
    /// Why there is no p-value, if so.
    pub note: Option<String>,
}

impl PairedRecord {
    /// The CSV cells: differences with six decimals, p-values in full precision, empty
    /// where there is no value.
    pub fn cells(&self) -> [String; 17] {
        let num = |v: Option<f64>| v.map(|v| format!("{v:.6}")).unwrap_or_default();
        let full = |v: Option<f64>| v.map(|v| v.to_string()).unwrap_or_default();
        let int = |v: Option<u64>| v.map(|v| v.to_string()).unwrap_or_default();
        [
            self.kind.to_owned(),
            self.a.clone(),
            self.b.clone(),
            self.metric.clone(),
            self.n.to_string(),
            num(self.mean_diff),
            num(self.diff_low),
            num(self.diff_high),
            full(self.p_value),
            full(self.p_holm),
            self.better.to_owned(),
            self.method.to_owned(),
            int(self.zeros.map(|z| z as u64)),
            int(self.a_only),
            int(self.b_only),
            self.favours.clone().unwrap_or_default(),
            self.note.clone().unwrap_or_default(),
        ]
    }
}

/// The run a difference favours (`Some(true)`: b), or `None`.
fn favours(b: Option<bool>, a_name: &str, b_name: &str) -> Option<String> {
    b.map(|b| if b { b_name } else { a_name }.to_owned())
}
