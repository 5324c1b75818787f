//! CSV cells that a spreadsheet opens as text, not as a formula ("CSV injection").
//!
//! A spreadsheet runs a cell that starts with `=`, `+`, `-` or `@` as a formula (and some
//! treat a leading tab or carriage return the same way), so a scene name, a description or an
//! error message written into a CSV file could run when a colleague opens it. Every CSV writer
//! of the workspace passes each cell through [`escape`]: such a text cell gets a leading `'`,
//! which spreadsheets show as text. Numbers stay numbers: a cell that is a plain decimal
//! number (`-0.5`, `+3`, `-1e-3`, `.25`) is never changed.
//!
//! The rule is reversible, and the readers of CSV files the tool wrote (annotation files,
//! `summary_scenes.csv`) pass each cell through [`unescape`], so `unescape(escape(s)) == s`
//! for every string:
//!
//! - a cell *needs escaping* when it starts with `=`, `+`, `-`, `@`, a tab or a carriage
//!   return and is not a number, or when it starts with `'` and the rest needs escaping (so a
//!   text that itself starts with `'=` keeps its quote: `'=x` is written `''=x`);
//! - [`escape`] puts a `'` before a cell that needs escaping, and leaves every other cell as it
//!   is;
//! - [`unescape`] takes the first `'` off a cell whose rest needs escaping, and leaves every
//!   other cell as it is.
//!
//! ```
//! use sceneeval_files::csv_cell::{escape, unescape};
//!
//! assert_eq!(escape("=HYPERLINK(\"http://x\")"), "'=HYPERLINK(\"http://x\")");
//! assert_eq!(escape("-0.5"), "-0.5");
//! assert_eq!(escape("- a bed"), "'- a bed");
//! assert_eq!(escape("a bed"), "a bed");
//! assert_eq!(unescape("'@sum(A1)"), "@sum(A1)");
//! assert_eq!(unescape("'quoted'"), "'quoted'");
//! ```

use std::borrow::Cow;

/// The first characters a spreadsheet may run as a formula.
const TRIGGERS: [char; 6] = ['=', '+', '-', '@', '\t', '\r'];

/// Whether `cell` is a plain decimal number: an optional sign, digits with an optional
/// decimal point (at least one digit), an optional exponent (`e` or `E`, optional sign,
/// digits). `inf`, `NaN`, hexadecimal and thousands separators are not numbers here.
pub fn is_number(cell: &str) -> bool {
    let b = cell.as_bytes();
    let mut i = usize::from(matches!(b.first(), Some(b'+' | b'-')));
    let digits = |i: &mut usize| {
        let start = *i;
        while b.get(*i).is_some_and(u8::is_ascii_digit) {
            *i += 1;
        }
        *i - start
    };
    let mut mantissa = digits(&mut i);
    if b.get(i) == Some(&b'.') {
        i += 1;
        mantissa += digits(&mut i);
    }
    if mantissa == 0 {
        return false;
    }
    if matches!(b.get(i), Some(b'e' | b'E')) {
        i += 1;
        if matches!(b.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        if digits(&mut i) == 0 {
            return false;
        }
    }
    i == b.len()
}

/// Whether `cell` needs a leading `'` (see the module's rule).
pub fn needs_escape(cell: &str) -> bool {
    let mut rest = cell;
    // A run of quotes before a trigger: each level keeps its quote.
    while let Some(r) = rest.strip_prefix('\'') {
        rest = r;
    }
    rest.starts_with(TRIGGERS) && !is_number(rest)
}

/// The cell as written into a CSV file: with a leading `'` when it [needs escaping](needs_escape),
/// unchanged otherwise.
pub fn escape(cell: &str) -> Cow<'_, str> {
    if needs_escape(cell) {
        Cow::Owned(format!("'{cell}"))
    } else {
        Cow::Borrowed(cell)
    }
}

/// [`escape`] of an owned cell: the same string back when it needs no escaping.
pub fn escape_owned(cell: String) -> String {
    if needs_escape(&cell) {
        format!("'{cell}")
    } else {
        cell
    }
}

/// The cell as it was before [`escape`]: without its first `'` when the rest needs escaping,
/// unchanged otherwise.
pub fn unescape(cell: &str) -> &str {
    match cell.strip_prefix('\'') {
        Some(rest) if needs_escape(rest) => rest,
        _ => cell,
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use proptest::prelude::*;

    use super::*;

    #[test]
    fn numbers_are_plain_decimals() {
        for n in ["0", "-0.5", "+3", "-1e-3", ".25", "5.", "1E+10", "-0.0000", "100"] {
            assert!(is_number(n), "{n}");
            assert_eq!(escape(n), n);
        }
        for t in [
            "", "-", "+", ".", "-.", "1e", "-1e+", "1.2.3", "--1", "-inf", "NaN", "0x10", "1,5", "-1 m", " 1",
        ] {
            assert!(!is_number(t), "{t:?}");
        }
    }

    #[test]
    fn formulas_and_their_quoted_forms_are_escaped() {
        let cases = [
            ("=1+2", "'=1+2"),
            ("+cmd|' /C calc'!A0", "'+cmd|' /C calc'!A0"),
            ("-2+3", "'-2+3"),
            ("@SUM(A1:A2)", "'@SUM(A1:A2)"),
            ("\t=1", "'\t=1"),
            ("\r=1", "'\r=1"),
            ("-inf", "'-inf"),
            ("'=1", "''=1"),
            ("''@x", "'''@x"),
            ("'quoted'", "'quoted'"),
            ("'-0.5", "'-0.5"),
            ("a=1", "a=1"),
            ("", ""),
            ("scene_0", "scene_0"),
        ];
        for (text, written) in cases {
            assert_eq!(escape(text), written, "{text:?}");
            assert_eq!(unescape(written), text, "{written:?}");
        }
    }

    proptest! {
        #[test]
        fn every_text_reads_back(s in "['=+\\-@\t\r0-9.eE a-z]{0,8}") {
            let w = escape(&s);
            prop_assert_eq!(unescape(&w), s.as_str());
            // What is written never starts a formula, unless it is a number.
            prop_assert!(!w.starts_with(TRIGGERS) || is_number(&w));
        }

        #[test]
        fn text_that_needs_no_escape_is_read_as_it_is(s in "['=+\\-@\t\r0-9.eE a-z]{0,8}") {
            if !needs_escape(&s) {
                prop_assert_eq!(unescape(&s), s.as_str());
            }
        }
    }
}
