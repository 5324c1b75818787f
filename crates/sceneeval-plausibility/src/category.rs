//! Category names as keys of the prior tables, in the one normalisation of labels
//! ([`sceneeval_scene::label`], synset suffixes dropped: `bed.n.01` is a bed).

use sceneeval_scene::label::{Synset, normalise, singular, singular_head};

/// The keys tried, in order, when looking a raw category up in a prior table: the normalised
/// name, the same with its last word made singular, and the last word alone (the head noun,
/// so `king_size_bed` finds `bed`), singular.
pub(crate) fn lookup_keys(raw: &str) -> Vec<String> {
    let norm = normalise(raw, Synset::Strip);
    if norm.is_empty() {
        return Vec::new();
    }
    let last = norm.rsplit_once('_').map_or(norm.as_str(), |(_, l)| l);
    let mut keys = vec![norm.clone()];
    for k in [singular_head(&norm), last.to_owned(), singular(last)] {
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys
}

/// Whether `raw` contains one of `words` (already normalised with [`normalise`]) as a
/// whole word (after normalisation and making each word singular), e.g. `bath_mats` contains
/// `mat` but `matte_lamp` does not.
pub(crate) fn has_word(raw: &str, words: &[String]) -> bool {
    let norm = normalise(raw, Synset::Strip);
    norm.split('_').any(|w| {
        let s = singular(w);
        words.iter().any(|x| x == w || *x == s)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_fall_back_to_head_noun() {
        assert_eq!(
            lookup_keys("King Size Beds"),
            vec!["king_size_beds", "king_size_bed", "beds", "bed"]
        );
        assert_eq!(lookup_keys("sofa"), vec!["sofa"]);
        assert_eq!(lookup_keys("bed.n.01"), vec!["bed"]);
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
