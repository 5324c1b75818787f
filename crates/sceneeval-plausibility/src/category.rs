//! Normalisation of free-text category names for the prior tables.

/// Normalises a category name for table lookup: lower case; `_`, `-`, `.`-free words joined by
/// single `_`; a WordNet synset suffix such as `.n.01` removed (`bed.n.01` becomes `bed`).
///
/// ```
/// use sceneeval_plausibility::normalize_category;
/// assert_eq!(normalize_category("Dining-Table"), "dining_table");
/// assert_eq!(normalize_category("  coffee   table "), "coffee_table");
/// assert_eq!(normalize_category("bed.n.01"), "bed");
/// ```
pub fn normalize_category(raw: &str) -> String {
    let lower = raw.trim().to_lowercase();
    // Strip a WordNet synset suffix `.<pos>.<nn>`.
    let base = match lower.split_once('.') {
        Some((head, tail)) if is_synset_suffix(tail) => head.to_owned(),
        _ => lower,
    };
    base.split(|c: char| c == '_' || c == '-' || c.is_whitespace())
        .filter(|w| !w.is_empty())
        .collect::<Vec<_>>()
        .join("_")
}

fn is_synset_suffix(tail: &str) -> bool {
    let mut parts = tail.split('.');
    matches!(
        (parts.next(), parts.next(), parts.next()),
        (Some(pos), Some(num), None)
            if pos.len() == 1 && !num.is_empty() && num.chars().all(|c| c.is_ascii_digit())
    )
}

/// The singular of one English word by simple suffix rules: `shelves` -> `shelf`, `boxes` ->
/// `box`, `bookcases` -> `bookcase`, `lamps` -> `lamp`; words ending in `ss`, `us` or `is` and
/// words of three letters or fewer are kept.
pub(crate) fn singular(word: &str) -> String {
    let n = word.len();
    if n <= 3 || word.ends_with("ss") || word.ends_with("us") || word.ends_with("is") {
        return word.to_owned();
    }
    if let Some(stem) = word.strip_suffix("ves") {
        return format!("{stem}f");
    }
    if let Some(stem) = word.strip_suffix("ies") {
        return format!("{stem}y");
    }
    for suffix in ["ches", "shes", "xes", "sses", "zes"] {
        if word.ends_with(suffix) {
            return word[..n - 2].to_owned();
        }
    }
    match word.strip_suffix('s') {
        Some(stem) => stem.to_owned(),
        None => word.to_owned(),
    }
}

/// The keys tried, in order, when looking a raw category up in a prior table: the normalised
/// name, the same with its last word made singular, and the last word alone (the head noun,
/// so `king_size_bed` finds `bed`), singular.
pub(crate) fn lookup_keys(raw: &str) -> Vec<String> {
    let norm = normalize_category(raw);
    if norm.is_empty() {
        return Vec::new();
    }
    let mut keys = vec![norm.clone()];
    let (head, last) = match norm.rsplit_once('_') {
        Some((h, l)) => (Some(h), l),
        None => (None, norm.as_str()),
    };
    let last_singular = singular(last);
    let full_singular = match head {
        Some(h) => format!("{h}_{last_singular}"),
        None => last_singular.clone(),
    };
    for k in [full_singular, last.to_owned(), last_singular] {
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys
}

/// Whether `raw` contains one of `words` (already normalised with [`normalize_category`]) as a
/// whole word (after normalisation and making each word singular), e.g. `bath_mats` contains
/// `mat` but `matte_lamp` does not.
pub(crate) fn has_word(raw: &str, words: &[String]) -> bool {
    let norm = normalize_category(raw);
    norm.split('_').any(|w| {
        let s = singular(w);
        words.iter().any(|x| x == w || *x == s)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalises_separators_case_and_synsets() {
        assert_eq!(normalize_category("Dining_Table"), "dining_table");
        assert_eq!(normalize_category("dining table"), "dining_table");
        assert_eq!(normalize_category("dining--table"), "dining_table");
        assert_eq!(normalize_category("chair.n.01"), "chair");
        assert_eq!(normalize_category("3d.model"), "3d.model");
        assert_eq!(normalize_category("   "), "");
    }

    #[test]
    fn plurals() {
        for (p, s) in [
            ("shelves", "shelf"),
            ("boxes", "box"),
            ("benches", "bench"),
            ("bookcases", "bookcase"),
            ("lamps", "lamp"),
            ("glass", "glass"),
            ("cactus", "cactus"),
            ("bus", "bus"),
            ("libraries", "library"),
        ] {
            assert_eq!(singular(p), s, "{p}");
        }
    }

    #[test]
    fn keys_fall_back_to_head_noun() {
        assert_eq!(
            lookup_keys("King Size Beds"),
            vec!["king_size_beds", "king_size_bed", "beds", "bed"]
        );
        assert_eq!(lookup_keys("sofa"), vec!["sofa"]);
        assert!(lookup_keys("").is_empty());
    }

    #[test]
    fn whole_words_only() {
        let words = vec!["mat".to_owned(), "rug".to_owned()];
        assert!(has_word("bath_mats", &words));
        assert!(has_word("Persian Rug", &words));
        assert!(!has_word("matte_lamp", &words));
        assert!(!has_word("drugstore", &words));
    }
}
