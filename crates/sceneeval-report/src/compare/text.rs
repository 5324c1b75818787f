//! The comparison as Markdown, CSV and LaTeX.

use std::fmt::Write as _;

use sceneeval_results::Better;
use sceneeval_stats::bootstrap::DEFAULT_RESAMPLES;

use super::{Cell, Comparison, Table};
use crate::ReportError;
use crate::escape;

/// How a value is emphasised: bold when first, italic when second.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Emphasis {
    Bold,
    Italic,
    Plain,
}

impl Cell {
    pub(crate) fn emphasis(&self) -> Emphasis {
        match self.value_rank {
            Some(1) => Emphasis::Bold,
            Some(2) => Emphasis::Italic,
            _ => Emphasis::Plain,
        }
    }

    /// The value with two decimals, or `-`.
    pub(crate) fn value_text(&self) -> String {
        self.value.map_or_else(|| "-".to_owned(), |v| format!("{v:.2}"))
    }

    /// The interval as `[lo, hi]`, when there is one.
    pub(crate) fn ci_text(&self) -> Option<String> {
        self.ci.map(|[lo, hi]| format!("[{lo:.2}, {hi:.2}]"))
    }
}

/// "1 scene", "3 scenes".
pub(crate) fn scenes(n: usize) -> String {
    format!("{n} scene{}", if n == 1 { "" } else { "s" })
}

/// `↑` or `↓`.
pub(crate) fn arrow(better: Better) -> &'static str {
    match better {
        Better::Higher => "↑",
        Better::Lower => "↓",
    }
}

impl Comparison {
    /// The legend under every table: what the numbers, emphasis and ranks mean.
    pub fn legend(&self) -> String {
        let mut s = String::from(match self.failed {
            super::FailedScenes::Skip => {
                "Values are percentages, macro-averaged over each group's common scenes as summary.csv averages \
                 them; (n): the scenes behind a value."
            }
            super::FailedScenes::Worst => {
                "Values are percentages, averaged over every scene of any run, a failed or missing scene at the \
                 column's worst value (0 where higher is better, 100 where lower is better); (n): the scenes behind \
                 a value."
            }
        });
        s.push_str(" ↑ higher is better, ↓ lower is better. Bold: best value; italic: second.");
        match self.rank {
            super::RankBy::Tested => {
                let _ = write!(
                    s,
                    " Ranks: 1 + the number of runs better in the column by a paired two-sided Wilcoxon signed-rank \
                     test on the scenes both have, Holm-adjusted across the pair's columns, p < {}; runs no test \
                     separates share a rank.",
                    self.alpha
                );
            }
            super::RankBy::Mean => s.push_str(
                " Ranks by mean (--rank mean): competition ranks (1224: equal values, as printed, share the best \
                 rank), whatever their uncertainty.",
            ),
        }
        s.push_str(" A run ranked r of the N runs with a value gets N - r + 1 points.");
        if let Some(level) = self.ci {
            let _ = write!(
                s,
                " [lo, hi]: {}% bootstrap interval over scenes ({DEFAULT_RESAMPLES} resamples, fixed seed, \
                 percentile method).",
                (level * 1e4).round() / 1e2
            );
        }
        s
    }

    /// The tables as GitHub Markdown: per group, the values, then the standings sorted by
    /// points; then the notes and the legend. Every name is escaped.
    pub fn to_markdown(&self) -> String {
        let mut out = String::new();
        for table in &self.tables {
            let _ = writeln!(
                out,
                "### {} ({})\n",
                escape::markdown(&table.group),
                scenes(table.scenes)
            );
            let mut header = vec!["run".to_owned()];
            header.extend(
                self.columns
                    .iter()
                    .map(|c| format!("{} {}", c.name, arrow(c.better))),
            );
            let _ = writeln!(out, "| {} |", header.join(" | "));
            let _ = writeln!(out, "|---|{}", "---:|".repeat(self.columns.len()));
            for (run, row) in self.runs.iter().zip(&table.cells) {
                let mut cells = vec![escape::markdown(&run.name)];
                cells.extend(row.iter().map(|c| {
                    let v = match c.emphasis() {
                        Emphasis::Bold => format!("**{}**", c.value_text()),
                        Emphasis::Italic => format!("*{}*", c.value_text()),
                        Emphasis::Plain => c.value_text(),
                    };
                    let ci = c.ci_text().map(|t| format!(" {t}")).unwrap_or_default();
                    format!("{v} ({}){ci}", c.n)
                }));
                let _ = writeln!(out, "| {} |", cells.join(" | "));
            }
            out.push('\n');
            for line in self.coverage_lines() {
                let _ = writeln!(out, "- {}", escape::markdown(&line));
            }
            out.push('\n');
            let mut header: Vec<String> = ["place", "run", "points", "average rank", "1st", "2nd", "3rd"]
                .map(str::to_owned)
                .to_vec();
            header.extend(self.columns.iter().map(|c| c.name.to_owned()));
            let _ = writeln!(out, "| {} |", header.join(" | "));
            let _ = writeln!(out, "|---:|---|{}", "---:|".repeat(header.len() - 2));
            for k in standing_order(table) {
                let s = &table.standings[k];
                let mut cells = vec![
                    s.place.to_string(),
                    escape::markdown(&self.runs[k].name),
                    s.points.to_string(),
                    average(s.average_rank),
                    s.places[0].to_string(),
                    s.places[1].to_string(),
                    s.places[2].to_string(),
                ];
                cells.extend(
                    table.cells[k]
                        .iter()
                        .map(|c| c.rank.map_or("-".to_owned(), |r| r.to_string())),
                );
                let _ = writeln!(out, "| {} |", cells.join(" | "));
            }
            out.push('\n');
        }
        if !self.notes.is_empty() {
            out.push_str("Notes:\n\n");
            for note in &self.notes {
                let _ = writeln!(out, "- {}", escape::markdown(note));
            }
            out.push('\n');
        }
        out.push_str(&self.legend());
        out.push('\n');
        let paired = self.paired_markdown();
        if !paired.is_empty() {
            out.push('\n');
            out.push_str(&paired);
        }
        out
    }

    /// The values as CSV, one row per group, run and column: `group, scenes, run, column,
    /// better, value, n, ci_low, ci_high, rank, points, missing, failed` (values with four
    /// decimals, empty cells where there is none; `missing` and `failed`: the run's scenes
    /// missing or failed among every scene of any run, space-separated).
    ///
    /// # Errors
    /// [`ReportError::Csv`] when the CSV writer fails.
    pub fn to_csv(&self) -> Result<String, ReportError> {
        let csv_error = |source| ReportError::Csv {
            path: "(compare)".into(),
            source,
        };
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record([
            "group", "scenes", "run", "column", "better", "value", "n", "ci_low", "ci_high", "rank",
            "points", "missing", "failed",
        ])
        .map_err(csv_error)?;
        let num = |v: Option<f64>| v.map(|v| format!("{v:.4}")).unwrap_or_default();
        for table in &self.tables {
            for ((run, row), coverage) in self.runs.iter().zip(&table.cells).zip(&self.coverage) {
                for (column, cell) in self.columns.iter().zip(row) {
                    // A run name or group a spreadsheet would run gets a leading `'`.
                    let cells = [
                        table.group.clone(),
                        table.scenes.to_string(),
                        run.name.clone(),
                        column.name.to_owned(),
                        column.better.name().to_owned(),
                        num(cell.value),
                        cell.n.to_string(),
                        num(cell.ci.map(|c| c[0])),
                        num(cell.ci.map(|c| c[1])),
                        cell.rank.map(|r| r.to_string()).unwrap_or_default(),
                        cell.points.to_string(),
                        coverage.missing.join(" "),
                        coverage.failed.join(" "),
                    ];
                    w.write_record(cells.map(sceneeval_files::csv_cell::escape_owned))
                        .map_err(csv_error)?;
                }
            }
        }
        let bytes = w.into_inner().map_err(|e| csv_error(e.into_error().into()))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// The values as one booktabs `tabular` a paper can `\input` (packages `booktabs` and, for
    /// the arrows, `amsmath` or `amssymb` are not needed: `$\uparrow$` is plain LaTeX): a
    /// row per run, a column per metric column, then points, average rank and first, second,
    /// third places; with several groups, each opens with its name. The notes and the legend
    /// follow as `%` comments. Every name is escaped.
    pub fn to_latex(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "% sceneeval compare: {}",
            escape::latex(
                &self
                    .runs
                    .iter()
                    .map(|r| r.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        );
        let width = 1 + self.columns.len() + 5;
        let _ = writeln!(
            out,
            "\\begin{{tabular}}{{l{}rrrrr}}",
            "r".repeat(self.columns.len())
        );
        out.push_str("\\toprule\n");
        let mut header = vec!["Method".to_owned()];
        header.extend(self.columns.iter().map(|c| {
            format!(
                "{} $\\{}arrow$",
                escape::latex(c.name),
                match c.better {
                    Better::Higher => "up",
                    Better::Lower => "down",
                }
            )
        }));
        header.extend(["Points", "Avg.\\ rank", "1st", "2nd", "3rd"].map(str::to_owned));
        let _ = writeln!(out, "{} \\\\", header.join(" & "));
        for table in &self.tables {
            out.push_str("\\midrule\n");
            if self.tables.len() > 1 {
                let _ = writeln!(
                    out,
                    "\\multicolumn{{{width}}}{{l}}{{\\textit{{{} ({})}}}} \\\\",
                    escape::latex(&table.group),
                    scenes(table.scenes)
                );
            }
            for ((run, row), s) in self.runs.iter().zip(&table.cells).zip(&table.standings) {
                let mut cells = vec![escape::latex(&run.name)];
                cells.extend(row.iter().map(|c| {
                    let v = match c.emphasis() {
                        Emphasis::Bold => format!("\\textbf{{{}}}", c.value_text()),
                        Emphasis::Italic => format!("\\textit{{{}}}", c.value_text()),
                        Emphasis::Plain => c.value_text(),
                    };
                    let ci = c
                        .ci_text()
                        .map(|t| format!(" {{\\scriptsize {t}}}"))
                        .unwrap_or_default();
                    format!("{v} {{\\scriptsize ({})}}{ci}", c.n)
                }));
                cells.push(s.points.to_string());
                cells.push(average(s.average_rank));
                cells.extend(s.places.iter().map(usize::to_string));
                let _ = writeln!(out, "{} \\\\", cells.join(" & "));
            }
            for line in self.coverage_lines() {
                let _ = writeln!(
                    out,
                    "\\multicolumn{{{width}}}{{l}}{{\\footnotesize {}}} \\\\",
                    escape::latex(&line)
                );
            }
        }
        out.push_str("\\bottomrule\n\\end{tabular}\n");
        for note in &self.notes {
            let _ = writeln!(out, "% Note: {}", escape::latex(note));
        }
        let _ = writeln!(out, "% {}", escape::latex(&self.legend()));
        out.push_str(&self.paired_latex());
        out
    }
}

/// The runs' indices by place, then by run order.
pub(crate) fn standing_order(table: &Table) -> Vec<usize> {
    let mut order: Vec<usize> = (0..table.standings.len()).collect();
    order.sort_by_key(|&k| (table.standings[k].place, k));
    order
}

/// An average rank with two decimals, or `-`.
pub(crate) fn average(rank: Option<f64>) -> String {
    rank.map_or_else(|| "-".to_owned(), |r| format!("{r:.2}"))
}
