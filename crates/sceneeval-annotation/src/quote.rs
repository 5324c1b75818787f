//! Bounded quotes of input text: a finding or an entry problem quotes at most
//! [`MAX_QUOTE_CHARS`] characters of any one cell, entry or name, and lists at most
//! [`MAX_QUOTED_ITEMS`] items, so that what validation prints grows linearly with the file
//! however long its cells are.

use std::borrow::Cow;

/// The most characters of input text quoted in one piece: a finding's `row` and `entry`, and
/// each ID, cell, entry, name or suggested entry in its message and suggestion. A longer text
/// is cut to its first `MAX_QUOTE_CHARS - 1` characters followed by `…`.
pub const MAX_QUOTE_CHARS: usize = 80;

/// The most items a finding's message or suggestion lists (names, entries, cells); the rest
/// are counted ("and 12 more").
pub const MAX_QUOTED_ITEMS: usize = 5;

/// `text` when it has at most [`MAX_QUOTE_CHARS`] characters, else its first
/// `MAX_QUOTE_CHARS - 1` characters and `…`. Reads at most `MAX_QUOTE_CHARS + 1` characters.
pub(crate) fn excerpt(text: &str) -> Cow<'_, str> {
    let mut chars = text.char_indices();
    match chars.nth(MAX_QUOTE_CHARS - 1) {
        Some((cut, _)) if chars.next().is_some() => Cow::Owned(format!("{}…", &text[..cut])),
        _ => Cow::Borrowed(text),
    }
}

/// `text` quoted in backticks, cut by [`excerpt`].
pub(crate) fn ticked(text: &str) -> String {
    format!("`{}`", excerpt(text))
}

/// The first [`MAX_QUOTED_ITEMS`] of `items` shown by `show` and joined by `separator`, then
/// ` and N more` when there are more. Only the shown items are rendered.
pub(crate) fn list<T>(
    items: impl IntoIterator<Item = T>,
    separator: &str,
    show: impl Fn(T) -> String,
) -> String {
    let mut out = String::new();
    let mut rest = 0usize;
    for (i, item) in items.into_iter().enumerate() {
        if i >= MAX_QUOTED_ITEMS {
            rest += 1;
            continue;
        }
        if i > 0 {
            out.push_str(separator);
        }
        out.push_str(&show(item));
    }
    if rest > 0 {
        out.push_str(&format!(" and {rest} more"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn excerpts_keep_short_texts_and_cut_long_ones_to_the_bound() {
        assert_eq!(excerpt("eq,1,bed"), "eq,1,bed");
        let exact = "a".repeat(MAX_QUOTE_CHARS);
        assert_eq!(excerpt(&exact), exact.as_str());
        // 81 characters: 79 kept, then the ellipsis, 80 in all.
        let long = format!("{exact}b");
        let cut = excerpt(&long);
        assert_eq!(cut.chars().count(), MAX_QUOTE_CHARS);
        assert_eq!(cut, format!("{}…", &exact[..MAX_QUOTE_CHARS - 1]));
        // Characters, not bytes: 200 two-byte letters give 79 of them and the ellipsis.
        let wide = "é".repeat(200);
        let cut = excerpt(&wide);
        assert_eq!(cut.chars().count(), MAX_QUOTE_CHARS);
        assert!(cut.starts_with("éé") && cut.ends_with("é…"));
        assert_eq!(ticked("bed"), "`bed`");
    }

    #[test]
    fn lists_show_the_first_items_and_count_the_rest() {
        let show = |s: &str| s.to_owned();
        assert_eq!(list(["a", "b"], ", ", show), "a, b");
        assert_eq!(list(Vec::<&str>::new(), ", ", show), "");
        // 7 items: the first 5 shown, 2 counted.
        assert_eq!(
            list(["a", "b", "c", "d", "e", "f", "g"], "; ", show),
            "a; b; c; d; e and 2 more"
        );
        let many: Vec<String> = (0..3_000).map(|i| format!("x{i}")).collect();
        assert_eq!(
            list(&many, ", ", |s| ticked(s)),
            "`x0`, `x1`, `x2`, `x3`, `x4` and 2995 more"
        );
    }
}
