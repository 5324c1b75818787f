//! Category labels in comparable form, for matching by labels.
//!
//! [`canonical`] turns a label into its comparable form:
//! 1. the one normalisation of labels ([`sceneeval_scene::label::normalise`]): trimmed and
//!    lower-cased, runs of whitespace, hyphens and underscores as one `_` (`Table Lamp`,
//!    `table-lamp` and `table_lamp` are the same), a WordNet synset suffix dropped (`bed.n.01`,
//!    the category HSSD assets state, is `bed`);
//! 2. the last word is made singular with English plural rules
//!    ([`sceneeval_scene::label::singular`]: `shelves` -> `shelf`, `benches` -> `bench`,
//!    `bookcases` -> `bookcase`, `plants` -> `plant`; words ending in `ss`, `us` or `is` are
//!    left as they are);
//! 3. the result is looked up in [`SYNONYMS`] and replaced by its canonical word.
//!
//! [`match_label`] matches an object's category to one of the annotated categories: an equal
//! canonical form first; otherwise, when exactly one annotated category equals the object
//! category's last word (its head noun: `dining_chair` -> `chair`), that one.

use sceneeval_scene::label::{Synset, normalise, singular_head};

/// Synonyms and their canonical word, both in normalised singular form.
///
/// | word | canonical |
/// |---|---|
/// | couch, settee | sofa |
/// | television, tv_set | tv |
/// | refrigerator | fridge |
/// | bookcase, book_shelf | bookshelf |
/// | bedside_table, night_stand, nightstand_table | nightstand |
/// | carpet | rug |
/// | potted_plant, houseplant, house_plant | plant |
/// | ceiling_light | ceiling_lamp |
/// | closet | wardrobe |
pub const SYNONYMS: &[(&str, &str)] = &[
    ("couch", "sofa"),
    ("settee", "sofa"),
    ("television", "tv"),
    ("tv_set", "tv"),
    ("refrigerator", "fridge"),
    ("bookcase", "bookshelf"),
    ("book_shelf", "bookshelf"),
    ("bedside_table", "nightstand"),
    ("night_stand", "nightstand"),
    ("nightstand_table", "nightstand"),
    ("carpet", "rug"),
    ("potted_plant", "plant"),
    ("houseplant", "plant"),
    ("house_plant", "plant"),
    ("ceiling_light", "ceiling_lamp"),
    ("closet", "wardrobe"),
];

/// The comparable form of a label (see the module docs).
///
/// ```
/// use sceneeval_fidelity::labels::canonical;
/// assert_eq!(canonical("Table Lamps"), "table_lamp");
/// assert_eq!(canonical("couch"), "sofa");
/// assert_eq!(canonical("Book-Shelves"), "bookshelf");
/// assert_eq!(canonical("glass"), "glass");
/// assert_eq!(canonical("bed.n.01"), "bed");
/// ```
pub fn canonical(label: &str) -> String {
    let joined = singular_head(&normalise(label, Synset::Strip));
    SYNONYMS
        .iter()
        .find(|(w, _)| *w == joined)
        .map_or(joined, |(_, c)| (*c).to_owned())
}

/// How a label matched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LabelMatch {
    /// Equal canonical forms.
    Exact,
    /// The object category's last word is the annotated category.
    HeadNoun,
}

/// The annotated category (index into `categories`) an object labelled `label` matches, if
/// any (see the module docs).
///
/// ```
/// use sceneeval_fidelity::labels::{match_label, LabelMatch};
/// let cats = ["sofa".to_owned(), "chair".to_owned(), "dining_table".to_owned()];
/// assert_eq!(match_label("Couch", &cats), Some((0, LabelMatch::Exact)));
/// assert_eq!(match_label("dining chair", &cats), Some((1, LabelMatch::HeadNoun)));
/// assert_eq!(match_label("table", &cats), None);
/// ```
pub fn match_label(label: &str, categories: &[String]) -> Option<(usize, LabelMatch)> {
    let c = canonical(label);
    if c.is_empty() {
        return None;
    }
    let canon: Vec<String> = categories.iter().map(|k| canonical(k)).collect();
    if let Some(i) = canon.iter().position(|k| *k == c) {
        return Some((i, LabelMatch::Exact));
    }
    let head = c.rsplit_once('_').map(|(_, l)| l)?;
    let mut hits = canon.iter().enumerate().filter(|(_, k)| k.as_str() == head);
    match (hits.next(), hits.next()) {
        (Some((i, _)), None) => Some((i, LabelMatch::HeadNoun)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plurals_and_spacing() {
        for (a, b) in [
            ("chairs", "chair"),
            ("benches", "bench"),
            ("boxes", "box"),
            ("shelves", "shelf"),
            ("libraries", "library"),
            ("dining  chairs", "dining_chair"),
            ("Dining-Chair", "dining_chair"),
            ("glass", "glass"),
            ("cactus", "cactus"),
            ("bus", "bus"),
            ("tv", "tv"),
            ("television", "tv"),
            ("bookcases", "bookshelf"),
            ("bedside tables", "nightstand"),
            ("bed.n.01", "bed"),
            ("Dining_Chair.n.01", "dining_chair"),
            ("couch.n.01", "sofa"),
        ] {
            assert_eq!(canonical(a), b, "{a}");
        }
    }

    #[test]
    fn head_noun_only_when_unique_and_not_exact() {
        let cats = vec!["chair".to_owned(), "dining_chair".to_owned()];
        assert_eq!(match_label("dining chair", &cats), Some((1, LabelMatch::Exact)));
        assert_eq!(
            match_label("office chair", &cats),
            Some((0, LabelMatch::HeadNoun))
        );
        let cats = vec!["desk".to_owned()];
        assert_eq!(match_label("", &cats), None);
    }
}
