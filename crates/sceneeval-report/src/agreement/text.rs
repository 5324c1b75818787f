//! The agreement table as Markdown, CSV, LaTeX and JSON (`docs/formats.md`, "Agreement
//! tables").

use std::fmt::Write as _;

use sceneeval_fidelity::FidelityMetric;

use super::{Agreement, AgreementRow, RowKind};
use crate::escape;

/// The CSV columns, in order.
pub const CSV_COLUMNS: [&str; 17] = [
    "kind",
    "a",
    "b",
    "metric",
    "n",
    "agreement",
    "kappa",
    "kappa_low",
    "kappa_high",
    "undefined",
    "tt",
    "tf",
    "ft",
    "ff",
    "left_out_null",
    "left_out_tie",
    "resamples_undefined",
];

/// The rows of one table line: the rows of one (kind, a, b), one per metric and `all`.
pub(crate) struct Line<'a> {
    pub(crate) kind: RowKind,
    pub(crate) a: &'a str,
    pub(crate) b: &'a str,
    pub(crate) cells: Vec<&'a AgreementRow>,
}

impl Agreement {
    /// The rows grouped by (kind, a, b), in order.
    pub(crate) fn lines(&self, kinds: &[RowKind]) -> Vec<Line<'_>> {
        let mut out: Vec<Line<'_>> = Vec::new();
        for row in self.rows.iter().filter(|r| kinds.contains(&r.kind)) {
            match out.last_mut() {
                Some(l) if l.kind == row.kind && l.a == row.a && l.b == row.b => l.cells.push(row),
                _ => out.push(Line {
                    kind: row.kind,
                    a: &row.a,
                    b: &row.b,
                    cells: vec![row],
                }),
            }
        }
        out
    }

    /// The column heads: each metric, then `All`.
    pub(crate) fn heads(&self) -> Vec<String> {
        self.metrics
            .iter()
            .map(|m| m.name().to_uppercase())
            .chain(["All".to_owned()])
            .collect()
    }

    /// CSV: one line per row, the columns [`CSV_COLUMNS`]; numbers at full precision, empty
    /// cells where a value does not exist (the reason in `undefined`).
    ///
    /// # Errors
    /// Never in practice (the writer writes into memory); a CSV error otherwise.
    pub fn to_csv(&self) -> Result<String, csv::Error> {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(CSV_COLUMNS)?;
        let num = |v: Option<f64>| v.map(|v| v.to_string()).unwrap_or_default();
        let count = |v: Option<u64>| v.map(|v| v.to_string()).unwrap_or_default();
        for r in &self.rows {
            let cells = [
                r.kind.name().to_owned(),
                r.a.clone(),
                r.b.clone(),
                r.metric.clone(),
                r.n.to_string(),
                num(r.agreement),
                num(r.kappa),
                num(r.kappa_low),
                num(r.kappa_high),
                r.undefined.clone().unwrap_or_default(),
                count(r.tt),
                count(r.tf),
                count(r.ft),
                count(r.ff),
                r.left_out_null.to_string(),
                r.left_out_tie.to_string(),
                r.resamples_undefined.to_string(),
            ];
            // A name a spreadsheet would run as a formula gets a leading `'`.
            w.write_record(cells.map(sceneeval_files::csv_cell::escape_owned))?;
        }
        let bytes = w.into_inner().map_err(|e| e.into_error())?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// JSON: the whole table (rows, wrong items, notes), pretty-printed.
    #[must_use]
    pub fn to_json(&self) -> String {
        // Strings, numbers and options only: serialising cannot fail.
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }

    /// Markdown: the paper's table (agreement % and kappa per metric, one row per judge or
    /// pair), the annotators' table with Fleiss' kappa, why empty kappas are empty, the
    /// notes, and the items each judge got wrong.
    #[must_use]
    pub fn to_markdown(&self) -> String {
        let mut md = String::new();
        let heads = self.heads();
        let table = |md: &mut String, first: &str, lines: &[Line<'_>], name: &dyn Fn(&Line<'_>) -> String| {
            let _ = write!(md, "| {first} |");
            for h in &heads {
                let _ = write!(md, " {h} % | {h} κ |");
            }
            md.push_str(" n (all) |\n|---|");
            md.push_str(&"---:|---:|".repeat(heads.len()));
            md.push_str("---:|\n");
            for line in lines {
                let _ = write!(md, "| {} |", escape::markdown(&name(line)));
                for cell in &line.cells {
                    let _ = write!(md, " {} | {} |", percent(cell.agreement), kappa_cell(cell));
                }
                let n = line.cells.last().map_or(0, |c| c.n);
                let _ = writeln!(md, " {n} |");
            }
        };
        if self.reference.is_empty() {
            md.push_str("## Agreement of every pair of sources\n\n");
            table(&mut md, "Pair", &self.lines(&[RowKind::Pair]), &|l| {
                format!("{} vs {}", l.a, l.b)
            });
        } else {
            let _ = writeln!(
                md,
                "## Agreement with the reference\n\nReference: the majority of {} ({} item(s) with tied annotators left out).\n",
                self.reference.join(", "),
                self.reference_ties
            );
            table(&mut md, "Judge", &self.lines(&[RowKind::Judge]), &|l| {
                l.a.to_owned()
            });
            let people = self.lines(&[RowKind::Annotators, RowKind::Fleiss]);
            if !people.is_empty() {
                md.push_str("\n## Agreement between the annotators\n\n");
                table(&mut md, "Annotators", &people, &|l| match l.kind {
                    RowKind::Fleiss => format!("Fleiss' κ, all {}", self.reference.len()),
                    _ => format!("{} vs {}", l.a, l.b),
                });
            }
        }
        md.push('\n');
        md.push_str(&self.legend());
        let empty = self.undefined_reasons();
        if !empty.is_empty() {
            md.push_str("\nEmpty κ cells:\n\n");
            for line in empty {
                let _ = writeln!(md, "- {}", escape::markdown(&line));
            }
        }
        if !self.notes.is_empty() {
            md.push_str("\nNotes:\n\n");
            for note in &self.notes {
                let _ = writeln!(md, "- {}", escape::markdown(note));
            }
        }
        if !self.reference.is_empty() {
            md.push_str("\n## Items the judges got wrong\n");
            for judge in self.lines(&[RowKind::Judge]) {
                let wrong: Vec<_> = self.wrong.iter().filter(|w| w.judge == judge.a).collect();
                let _ = writeln!(md, "\n### {} ({})\n", escape::markdown(judge.a), wrong.len());
                if wrong.is_empty() {
                    md.push_str("None.\n");
                }
                for w in wrong {
                    let _ = writeln!(
                        md,
                        "- {}, {} {}: `{}`: judge {}, reference {}",
                        escape::markdown(&w.scene),
                        w.metric.name().to_uppercase(),
                        w.index,
                        w.spec.replace('`', "'"),
                        verdict_word(w.verdict),
                        verdict_word(w.reference)
                    );
                }
            }
        }
        md
    }

    /// LaTeX: the paper's table as a booktabs tabular (agreement % and kappa per metric), the
    /// annotators' table, then the items each judge got wrong as an `itemize` list.
    #[must_use]
    pub fn to_latex(&self) -> String {
        let mut tex = String::new();
        let heads = self.heads();
        let table =
            |tex: &mut String, first: &str, lines: &[Line<'_>], name: &dyn Fn(&Line<'_>) -> String| {
                let _ = writeln!(tex, "\\begin{{tabular}}{{l{}}}", " cc".repeat(heads.len()));
                tex.push_str("\\toprule\n");
                let _ = write!(tex, "{}", escape::latex(first));
                for h in &heads {
                    let _ = write!(tex, " & \\multicolumn{{2}}{{c}}{{{h}}}");
                }
                tex.push_str(" \\\\\n");
                for k in 0..heads.len() {
                    let _ = write!(tex, "\\cmidrule(lr){{{}-{}}}", 2 + 2 * k, 3 + 2 * k);
                }
                tex.push('\n');
                tex.push_str(&" & Agr. (\\%) & $\\kappa$".repeat(heads.len()));
                tex.push_str(" \\\\\n\\midrule\n");
                for line in lines {
                    tex.push_str(&escape::latex(&name(line)));
                    for cell in &line.cells {
                        let agreement = cell
                            .agreement
                            .map_or_else(|| "--".to_owned(), |a| format!("{:.1}", a * 100.0));
                        let kappa = cell.kappa.map_or_else(|| "--".to_owned(), |k| format!("{k:.2}"));
                        let _ = write!(tex, " & {agreement} & {kappa}");
                    }
                    tex.push_str(" \\\\\n");
                }
                tex.push_str("\\bottomrule\n\\end{tabular}\n");
            };
        if self.reference.is_empty() {
            table(&mut tex, "Pair", &self.lines(&[RowKind::Pair]), &|l| {
                format!("{} vs {}", l.a, l.b)
            });
        } else {
            table(&mut tex, "Judge", &self.lines(&[RowKind::Judge]), &|l| {
                l.a.to_owned()
            });
            let people = self.lines(&[RowKind::Annotators, RowKind::Fleiss]);
            if !people.is_empty() {
                tex.push('\n');
                table(&mut tex, "Annotators", &people, &|l| match l.kind {
                    RowKind::Fleiss => "Fleiss' kappa".to_owned(),
                    _ => format!("{} vs {}", l.a, l.b),
                });
            }
            if !self.wrong.is_empty() {
                tex.push_str("\n\\begin{itemize}\n");
                for w in &self.wrong {
                    let _ = writeln!(
                        tex,
                        "\\item {}: {}, {} {}: \\texttt{{{}}} (judge {}, reference {})",
                        escape::latex(&w.judge),
                        escape::latex(&w.scene),
                        w.metric.name().to_uppercase(),
                        w.index,
                        escape::latex(&w.spec),
                        verdict_word(w.verdict),
                        verdict_word(w.reference)
                    );
                }
                tex.push_str("\\end{itemize}\n");
            }
        }
        tex
    }

    /// What the numbers are.
    pub(crate) fn legend(&self) -> String {
        let interval = match (self.resamples, self.seed, self.level) {
            (Some(r), Some(s), Some(l)) => format!(
                " [{:.0} % percentile bootstrap interval of kappa, items resampled {r} times, seed {s}]",
                l * 100.0
            ),
            _ => String::new(),
        };
        format!(
            "%: agreement (share of the items both sides judged with equal verdicts). κ: Cohen's kappa \
             (Fleiss' kappa on the Fleiss line){interval}. n: items compared over all metrics; an item with a \
             null verdict on either side is left out (counted in the CSV's `left_out_null`).\n"
        )
    }

    /// One line per empty kappa: who, which metric, why.
    pub(crate) fn undefined_reasons(&self) -> Vec<String> {
        self.rows
            .iter()
            .filter_map(|r| {
                let why = r.undefined.as_ref()?;
                let who = match r.kind {
                    RowKind::Judge => r.a.clone(),
                    RowKind::Fleiss => "Fleiss".to_owned(),
                    RowKind::Annotators | RowKind::Pair => format!("{} vs {}", r.a, r.b),
                };
                let metric = metric_title(&r.metric);
                Some(format!("{who}, {metric}: {why} (n = {})", r.n))
            })
            .collect()
    }
}

/// `CNT` ... or `All`.
fn metric_title(metric: &str) -> String {
    match metric.parse::<FidelityMetric>() {
        Ok(m) => m.name().to_uppercase(),
        Err(_) => "All".to_owned(),
    }
}

/// Agreement in percent with one decimal, or empty.
pub(crate) fn percent(v: Option<f64>) -> String {
    v.map(|a| format!("{:.1}", a * 100.0)).unwrap_or_default()
}

/// Kappa with two decimals and its interval, or empty.
pub(crate) fn kappa_cell(r: &AgreementRow) -> String {
    match (r.kappa, r.kappa_low, r.kappa_high) {
        (Some(k), Some(l), Some(h)) => format!("{k:.2} [{l:.2}, {h:.2}]"),
        (Some(k), _, _) => format!("{k:.2}"),
        (None, _, _) => String::new(),
    }
}

/// `satisfied` or `not satisfied`.
pub(crate) fn verdict_word(v: bool) -> &'static str {
    if v { "satisfied" } else { "not satisfied" }
}
