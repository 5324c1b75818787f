//! Escaping for every output language: scene ids, categories, run names and a model's reasons
//! are untrusted text, and each goes through one of these before it reaches a file.

use std::fmt::Write as _;

/// `text` for HTML and SVG, as element content or a double- or single-quoted attribute value:
/// `&`, `<`, `>`, `"` and `'` become character references.
///
/// ```
/// assert_eq!(
///     sceneeval_report::escape::html(r#"<img src=x onerror="a('b')">&"#),
///     "&lt;img src=x onerror=&quot;a(&#39;b&#39;)&quot;&gt;&amp;"
/// );
/// ```
pub fn html(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// `text` for LaTeX running text: the ten special characters are written as commands, and line
/// breaks as spaces (a table cell holds one line).
///
/// ```
/// assert_eq!(
///     sceneeval_report::escape::latex(r"50% of A_1 & {B} ~ $x^2$ \o/ #1"),
///     r"50\% of A\_1 \& \{B\} \textasciitilde{} \$x\textasciicircum{}2\$ \textbackslash{}o/ \#1"
/// );
/// ```
pub fn latex(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\\' => out.push_str(r"\textbackslash{}"),
            '~' => out.push_str(r"\textasciitilde{}"),
            '^' => out.push_str(r"\textasciicircum{}"),
            '&' | '%' | '$' | '#' | '_' | '{' | '}' => {
                out.push('\\');
                out.push(c);
            }
            '\n' | '\r' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// `text` for a Markdown table cell: the characters Markdown or the table would read
/// (`\`, `` ` ``, `*`, `_`, `[`, `]`, `<`, `>`, `|`, `#`, `~`) are escaped with a backslash, and line
/// breaks become spaces.
///
/// ```
/// assert_eq!(sceneeval_report::escape::markdown("a|b *c* <d>"), r"a\|b \*c\* \<d\>");
/// ```
pub fn markdown(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\\' | '`' | '*' | '_' | '[' | ']' | '<' | '>' | '|' | '#' | '~' => {
                out.push('\\');
                out.push(c);
            }
            '\n' | '\r' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// One path segment (a file or folder name) for a relative URL: every byte other than ASCII
/// letters, digits, `-`, `.`, `_` and `~` is percent-encoded (so `%`, `#`, `?`, `/` and spaces
/// in a view's file name cannot change what the link points to).
///
/// ```
/// assert_eq!(sceneeval_report::escape::url_segment("front_idx0%2Fa b#.png"), "front_idx0%252Fa%20b%23.png");
/// ```
pub fn url_segment(segment: &str) -> String {
    let mut out = String::with_capacity(segment.len());
    for b in segment.bytes() {
        if b.is_ascii_alphanumeric() || matches!(b, b'-' | b'.' | b'_' | b'~') {
            out.push(b as char);
        } else {
            let _ = write!(out, "%{b:02X}");
        }
    }
    out
}

/// A file name for an untrusted name (a scene's): ASCII letters, digits, `-` and `_` are kept,
/// every other byte becomes `~` and its two hex digits, so distinct names give distinct file
/// names and none can leave its folder (`..` and `/` are encoded).
///
/// ```
/// assert_eq!(sceneeval_report::escape::file_name("scene_12"), "scene_12");
/// assert_eq!(sceneeval_report::escape::file_name("../x.y"), "~2E~2E~2Fx~2Ey");
/// ```
pub fn file_name(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for b in name.bytes() {
        if b.is_ascii_alphanumeric() || matches!(b, b'-' | b'_') {
            out.push(b as char);
        } else {
            let _ = write!(out, "~{b:02X}");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_escape_leaves_no_active_character() {
        let evil = "</script><script>alert(1)</script>\"' & \\ $ % # _ { } ~ ^ | * ` [ ] \n x";
        let h = html(evil);
        assert!(
            !h.contains('<') && !h.contains('>') && !h.contains('"') && !h.contains('\''),
            "{h}"
        );
        let l = latex(evil);
        // Without the three commands, every special character left is escaped by a backslash.
        let bare = l
            .replace(r"\textbackslash{}", "")
            .replace(r"\textasciitilde{}", "")
            .replace(r"\textasciicircum{}", "");
        for special in ['$', '%', '#', '_', '{', '}', '&'] {
            for (k, _) in bare.match_indices(special) {
                assert!(bare[..k].ends_with('\\'), "{special} at {k} in {bare}");
            }
        }
        assert!(!bare.contains('~') && !bare.contains('^'), "{bare}");
        assert!(!l.contains('\n'));
        let m = markdown(evil);
        assert!(!m.contains('\n'));
        for (k, _) in m.match_indices('|') {
            assert_eq!(&m[k - 1..k], "\\", "{m}");
        }
        assert_eq!(file_name("a b/c"), "a~20b~2Fc");
        assert_eq!(url_segment("é"), "%C3%A9");
    }
}
