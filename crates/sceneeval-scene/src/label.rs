//! Labels (categories, attributes, relationship words, room ids) in comparable form: the one
//! normalisation every crate compares free text in.
//!
//! [`normalise`] trims, lower-cases, and joins the words (separated by runs of whitespace,
//! `-` and `_`) with single `_`s, so `Dining Table`, `dining-table` and ` dining__table ` are all
//! `dining_table`. Whether it also drops a WordNet synset suffix (`bed.n.01` becomes `bed`) is
//! its [`Synset`] argument: category lookups drop it (scenes built from HSSD assets state their
//! categories as synsets), comparisons of a label with the labels it was chosen from keep it.
//! [`singular`] and [`singular_head`] make English plurals singular with one set of suffix
//! rules.
//!
//! ```
//! use sceneeval_scene::label::{normalise, singular, singular_head, Synset};
//! assert_eq!(normalise("  Dining-Table ", Synset::Keep), "dining_table");
//! assert_eq!(normalise("bed.n.01", Synset::Strip), "bed");
//! assert_eq!(normalise("bed.n.01", Synset::Keep), "bed.n.01");
//! assert_eq!(singular("shelves"), "shelf");
//! assert_eq!(singular_head("king_size_beds"), "king_size_bed");
//! ```

/// What [`normalise`] does with a WordNet synset suffix `.<part of speech>.<sense number>`
/// (`bed.n.01`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Synset {
    /// Keep it: the label is compared with labels it was chosen from (a VLM's answer with the
    /// categories it was offered, a relationship word with a lexicon), where `bed.n.01` and
    /// `bed.n.02` must stay different.
    Keep,
    /// Drop it: the label names a category to look up (a prior table, the annotated
    /// categories), where `bed.n.01` is a bed.
    Strip,
}

/// The comparable form of a label: trimmed and lower-cased (Unicode), its words (separated by
/// runs of whitespace, `-` and `_`) joined by single `_`s; with [`Synset::Strip`], a WordNet
/// synset suffix after the first `.` removed first (`bed.n.01` becomes `bed`; `3d.model` is
/// kept, its tail is not a synset suffix).
///
/// ```
/// use sceneeval_scene::label::{normalise, Synset};
/// assert_eq!(normalise("Coffee   Table", Synset::Keep), "coffee_table");
/// assert_eq!(normalise("__x__", Synset::Keep), "x");
/// assert_eq!(normalise("dining\tchair", Synset::Keep), "dining_chair");
/// assert_eq!(normalise("Dining_Chair.n.01", Synset::Strip), "dining_chair");
/// assert_eq!(normalise("3d.model", Synset::Strip), "3d.model");
/// ```
pub fn normalise(label: &str, synset: Synset) -> String {
    let lower = label.trim().to_lowercase();
    let base = match (synset, lower.split_once('.')) {
        (Synset::Strip, Some((head, tail))) if is_synset_suffix(tail) => head,
        _ => lower.as_str(),
    };
    let mut out = String::with_capacity(base.len());
    for word in base
        .split(|c: char| c == '_' || c == '-' || c.is_whitespace())
        .filter(|w| !w.is_empty())
    {
        if !out.is_empty() {
            out.push('_');
        }
        out.push_str(word);
    }
    out
}

/// Whether `tail` (what follows a label's first `.`) is a synset suffix: one part-of-speech
/// character, `.`, and a sense number.
fn is_synset_suffix(tail: &str) -> bool {
    let mut parts = tail.split('.');
    matches!(
        (parts.next(), parts.next(), parts.next()),
        (Some(pos), Some(num), None)
            if pos.len() == 1 && !num.is_empty() && num.chars().all(|c| c.is_ascii_digit())
    )
}

/// The singular of one lower-case English word, by regular suffix rules: `shelves` -> `shelf`
/// (`-ves` -> `-f`, which covers the furniture words; `knives` is irregular), `libraries` ->
/// `library`, `benches`/`dishes`/`boxes`/`glasses`/`buzzes` drop `-es`, other words drop a final `s`
/// (`bookcases` -> `bookcase`, `lamps` -> `lamp`). Words of three letters or fewer and words
/// ending in `ss`, `us` or `is` are kept (`glass`, `cactus`, `bus`, `tv`).
///
/// ```
/// use sceneeval_scene::label::singular;
/// for (plural, one) in [("shelves", "shelf"), ("boxes", "box"), ("benches", "bench"),
///                       ("libraries", "library"), ("lamps", "lamp"), ("glass", "glass")] {
///     assert_eq!(singular(plural), one);
/// }
/// ```
pub fn singular(word: &str) -> String {
    const KEEP: [&str; 3] = ["ss", "us", "is"];
    if word.len() <= 3 || KEEP.iter().any(|k| word.ends_with(k)) {
        return word.to_owned();
    }
    if let Some(stem) = word.strip_suffix("ies") {
        return format!("{stem}y");
    }
    if let Some(stem) = word.strip_suffix("ves") {
        return format!("{stem}f");
    }
    if ["ches", "shes", "xes", "sses", "zes"]
        .iter()
        .any(|s| word.ends_with(s))
    {
        return word[..word.len() - 2].to_owned();
    }
    word.strip_suffix('s').unwrap_or(word).to_owned()
}

/// A normalised label with its last word (its head noun) made [`singular`]:
/// `king_size_beds` -> `king_size_bed`, `shelves` -> `shelf`.
pub fn singular_head(normalised: &str) -> String {
    match normalised.rsplit_once('_') {
        Some((head, last)) => format!("{head}_{}", singular(last)),
        None => singular(normalised),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separators_case_and_synsets() {
        for (raw, keep, strip) in [
            ("Dining_Table", "dining_table", "dining_table"),
            ("dining table", "dining_table", "dining_table"),
            ("dining--table", "dining_table", "dining_table"),
            ("  coffee   table ", "coffee_table", "coffee_table"),
            ("chair.n.01", "chair.n.01", "chair"),
            ("Bed.N.12", "bed.n.12", "bed"),
            ("3d.model", "3d.model", "3d.model"),
            ("a.b.c.d", "a.b.c.d", "a.b.c.d"),
            ("bed.n.", "bed.n.", "bed.n."),
            ("   ", "", ""),
            ("tv\u{a0}stand", "tv_stand", "tv_stand"),
        ] {
            assert_eq!(normalise(raw, Synset::Keep), keep, "{raw:?}");
            assert_eq!(normalise(raw, Synset::Strip), strip, "{raw:?}");
        }
    }

    #[test]
    fn plurals() {
        for (p, s) in [
            ("shelves", "shelf"),
            ("boxes", "box"),
            ("benches", "bench"),
            ("brushes", "brush"),
            ("waltzes", "waltz"),
            ("bookcases", "bookcase"),
            ("lamps", "lamp"),
            ("glass", "glass"),
            ("glasses", "glass"),
            ("cactus", "cactus"),
            ("bus", "bus"),
            ("tvs", "tvs"),
            ("libraries", "library"),
            ("chair", "chair"),
        ] {
            assert_eq!(singular(p), s, "{p}");
        }
        assert_eq!(singular_head("king_size_beds"), "king_size_bed");
        assert_eq!(singular_head("sofa"), "sofa");
        assert_eq!(singular_head(""), "");
    }
}
