//! How alike two scene descriptions are: the filter of near duplicates in annotation
//! generation (the paper rejected generated descriptions "too similar to existing entries").
//!
//! # The measure
//! The **Jaccard similarity of the descriptions' content-word sets**: |A ∩ B| / |A ∪ B|, where
//! a description's set holds its words (maximal runs of letters and digits, lower-cased, made
//! [`singular`] by the project's one label normalisation, so `beds` and `bed` are one word)
//! without the [`STOP_WORDS`] (articles, common prepositions,
//! conjunctions and forms of *be*), which every description shares and which would make all
//! descriptions look alike. Two empty sets have similarity 0 (nothing to compare).
//!
//! Word sets, not sequences: a description that reorders or rephrases the same objects and
//! relations ("a bed with a nightstand beside it" / "a nightstand beside the bed") is what
//! the filter is for, and the score does not depend on the length ratio the way containment
//! does.
//!
//! # The threshold
//! [`DEFAULT_THRESHOLD`] = 0.6: a description whose similarity to an existing one is at least
//! this is rejected. Over the 179 single-room rows of SceneEval-500 (15,931 pairs), the mean
//! similarity of two descriptions is 0.06, and only 5 pairs reach 0.6, all deliberate variants
//! of one scene: a living room with a TV, sofa and bookshelf with and without a coffee table
//! (0.875), dining tables set for 4, 8 and 12 people (0.846, 0.647, 0.647), and two living
//! rooms that differ in one clause (0.611); the next pair scores 0.53. So 0.6 rejects copies
//! with a few words changed and keeps every description the authors wrote as a distinct
//! scene.
//!
//! ```
//! use sceneeval_annotation::similarity::{DescriptionIndex, jaccard, word_set};
//! // {bedroom, bed, wardrobe} and {bedroom, bed, desk}: 2 shared of 4 words.
//! let a = word_set("A bedroom with a bed and a wardrobe.");
//! let b = word_set("The bedroom has beds and a desk.");
//! assert_eq!(jaccard(&a, &b), 0.5);
//! let mut index = DescriptionIndex::new(0.6);
//! index.insert("A bedroom with a bed and a wardrobe.");
//! assert!(index.too_similar("A bedroom with beds and a wardrobe").is_some());
//! assert!(index.too_similar("A kitchen with an island and two stools.").is_none());
//! ```

use std::collections::BTreeSet;

use sceneeval_scene::label::singular;

/// The default similarity at and above which a description is too similar to an existing one
/// (see the module docs for why 0.6).
pub const DEFAULT_THRESHOLD: f64 = 0.6;

/// Words left out of a description's word set: articles, common prepositions and
/// conjunctions, and forms of *be* (lower case, compared after lower-casing).
pub const STOP_WORDS: [&str; 32] = [
    "a", "an", "the", "and", "or", "but", "of", "in", "on", "at", "to", "with", "by", "for", "from", "into",
    "onto", "as", "is", "are", "be", "it", "its", "this", "that", "there", "these", "those", "has", "have",
    "which", "while",
];

/// The content-word set of a description (see the module docs).
pub fn word_set(description: &str) -> BTreeSet<String> {
    description
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(str::to_lowercase)
        .filter(|w| !STOP_WORDS.contains(&w.as_str()))
        .map(|w| singular(&w))
        .collect()
}

/// The Jaccard similarity of two word sets, from 0 (nothing shared, or both empty) to 1 (the
/// same set).
pub fn jaccard(a: &BTreeSet<String>, b: &BTreeSet<String>) -> f64 {
    let shared = a.intersection(b).count();
    let union = a.len() + b.len() - shared;
    if union == 0 {
        return 0.0;
    }
    shared as f64 / union as f64
}

/// The existing description a new one is too similar to.
#[derive(Debug, Clone, PartialEq)]
pub struct NearDescription {
    /// Its position in the index (insertion order).
    pub index: usize,
    /// Its text.
    pub description: String,
    /// The similarity, at least the index's threshold.
    pub score: f64,
}

/// Descriptions to compare new ones with, and the threshold of "too similar".
#[derive(Debug, Clone, Default)]
pub struct DescriptionIndex {
    threshold: f64,
    entries: Vec<(String, BTreeSet<String>)>,
}

impl DescriptionIndex {
    /// No descriptions yet; a similarity at or above `threshold` is too similar.
    pub fn new(threshold: f64) -> Self {
        DescriptionIndex {
            threshold,
            entries: Vec::new(),
        }
    }

    /// The threshold.
    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    /// Adds a description.
    pub fn insert(&mut self, description: &str) {
        self.entries.push((description.to_owned(), word_set(description)));
    }

    /// How many descriptions there are.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The most similar description and its similarity (the first of equals), if any.
    pub fn nearest(&self, description: &str) -> Option<NearDescription> {
        let words = word_set(description);
        let mut best: Option<NearDescription> = None;
        for (index, (text, set)) in self.entries.iter().enumerate() {
            let score = jaccard(&words, set);
            if best.as_ref().is_none_or(|b| score > b.score) {
                best = Some(NearDescription {
                    index,
                    description: text.clone(),
                    score,
                });
            }
        }
        best
    }

    /// The most similar description when it is too similar (similarity at least the
    /// threshold).
    pub fn too_similar(&self, description: &str) -> Option<NearDescription> {
        self.nearest(description).filter(|n| n.score >= self.threshold)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// The score is symmetric, from 0 to 1, 1 for a text with itself (when it has a content
        /// word) and for its words in reverse order.
        #[test]
        fn scores_are_symmetric_and_bounded(a in "[a-zA-Z ,.]{0,60}", b in "[a-zA-Z ,.]{0,60}") {
            let (sa, sb) = (word_set(&a), word_set(&b));
            let s = jaccard(&sa, &sb);
            prop_assert!((0.0..=1.0).contains(&s));
            prop_assert_eq!(s, jaccard(&sb, &sa));
            let reversed: Vec<&str> = a.split_whitespace().rev().collect();
            let expected = if sa.is_empty() { 0.0 } else { 1.0 };
            prop_assert_eq!(jaccard(&sa, &word_set(&reversed.join(" "))), expected);
        }
    }

    fn set(words: &[&str]) -> BTreeSet<String> {
        words.iter().map(|w| (*w).to_owned()).collect()
    }

    #[test]
    fn word_sets_drop_stop_words_and_plurals() {
        assert_eq!(
            word_set("There are two Beds, and a king-size bed's shelves."),
            set(&["two", "bed", "king", "size", "s", "shelf"])
        );
        assert!(word_set(" , the of. ").is_empty());
    }

    #[test]
    fn jaccard_by_hand() {
        // {bed, desk, lamp} and {bed, lamp, rug, chair}: shared {bed, lamp} = 2, union 5.
        let a = set(&["bed", "desk", "lamp"]);
        let b = set(&["bed", "lamp", "rug", "chair"]);
        assert_eq!(jaccard(&a, &b), 2.0 / 5.0);
        assert_eq!(jaccard(&b, &a), 0.4);
        assert_eq!(jaccard(&a, &a), 1.0);
        assert_eq!(jaccard(&a, &set(&["sofa"])), 0.0);
        assert_eq!(jaccard(&set(&[]), &set(&[])), 0.0);
    }

    #[test]
    fn descriptions_by_hand() {
        // {living, room, tv, sofa, bookshelf, no, coffee, table} (8) and
        // {living, room, tv, sofa, bookshelf, coffee, table} (7): 7 shared, 8 in the union:
        // 0.875, the most similar pair of SceneEval-500's single-room rows.
        let a = "A living room with a TV, sofa, and bookshelf. There is no coffee table in the room.";
        let b = "A living room with a TV, sofa, bookshelf, and coffee table.";
        assert_eq!(jaccard(&word_set(a), &word_set(b)), 7.0 / 8.0);
        // {bedroom, bed, wardrobe, corner, room, two, nightstand} (7) and
        // {bedroom, bed, wardrobe} (3): 3 / 7.
        let c = "A bedroom with a bed, two nightstands, and a wardrobe in the corner of the room.";
        let d = "A bedroom with a bed and a wardrobe.";
        assert_eq!(jaccard(&word_set(c), &word_set(d)), 3.0 / 7.0);

        let mut index = DescriptionIndex::new(DEFAULT_THRESHOLD);
        assert!(index.is_empty() && index.nearest(a).is_none());
        index.insert(c);
        index.insert(b);
        let near = index.too_similar(a).unwrap();
        assert_eq!((near.index, near.score), (1, 0.875));
        assert_eq!(near.description, b);
        assert_eq!(index.nearest(d).unwrap().index, 0);
        assert!(index.too_similar(d).is_none(), "3/7 is below 0.6");
        assert_eq!(index.len(), 2);
    }
}
