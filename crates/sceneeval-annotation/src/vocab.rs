//! The small closed vocabularies the schema and the validator rely on.
//!
//! Categories, attributes and relationships are open vocabulary in SceneEval-500; only the
//! architecture references are a closed set (the paper's appendix "Annotation Schema": `wall`,
//! `floor`, `ceiling`, `window`, `door`, `room`, or a room type). The adjective lists are used
//! by one heuristic only, the `non-atomic-attribute` and `attribute-category-swapped` checks,
//! and are deliberately short: a word missing here makes the heuristic miss a case, it never
//! makes a valid entry an error.

/// Architectural element names accepted as architecture references, in the paper's order
/// (the names of [`sceneeval_scene::ArchElement::ALL`]).
pub const ARCH_ELEMENTS: [&str; 6] = sceneeval_scene::ArchElement::NAMES;

/// Room types accepted as architecture references (for scenes with several rooms).
///
/// The ten room types of SceneEval-500 (bedroom, living room, dining room, playroom, gaming
/// room, kitchen, bathroom, basement, den, office) plus common rooms of homes and apartments.
/// Names use `_` for spaces, as the authors' guidelines ask. Anything else is reported as an
/// unknown architecture reference.
pub const ROOM_TYPES: [&str; 41] = [
    "bedroom",
    "living_room",
    "dining_room",
    "playroom",
    "gaming_room",
    "kitchen",
    "bathroom",
    "basement",
    "den",
    "office",
    "master_bedroom",
    "guest_room",
    "guest_bedroom",
    "kids_room",
    "nursery",
    "home_office",
    "study",
    "library",
    "game_room",
    "media_room",
    "home_theater",
    "family_room",
    "lounge",
    "studio",
    "gym",
    "home_gym",
    "laundry_room",
    "utility_room",
    "storage_room",
    "mudroom",
    "pantry",
    "closet",
    "walk_in_closet",
    "hallway",
    "corridor",
    "entryway",
    "foyer",
    "garage",
    "attic",
    "sunroom",
    "loft",
];

/// Colour adjectives (the heuristic word list of the atomic-attribute check).
pub const COLOURS: [&str; 36] = [
    "red",
    "orange",
    "yellow",
    "green",
    "blue",
    "purple",
    "violet",
    "pink",
    "brown",
    "black",
    "white",
    "gray",
    "grey",
    "beige",
    "tan",
    "cream",
    "ivory",
    "navy",
    "teal",
    "turquoise",
    "gold",
    "golden",
    "silver",
    "maroon",
    "burgundy",
    "olive",
    "charcoal",
    "crimson",
    "lavender",
    "magenta",
    "cyan",
    "indigo",
    "khaki",
    "coral",
    "mint",
    "colorful",
];

/// Material adjectives (and material nouns used as adjectives, e.g. "glass").
pub const MATERIALS: [&str; 40] = [
    "wooden",
    "wood",
    "oak",
    "pine",
    "walnut",
    "maple",
    "mahogany",
    "teak",
    "bamboo",
    "metal",
    "metallic",
    "steel",
    "iron",
    "brass",
    "bronze",
    "copper",
    "aluminum",
    "aluminium",
    "chrome",
    "glass",
    "crystal",
    "marble",
    "stone",
    "granite",
    "concrete",
    "ceramic",
    "porcelain",
    "leather",
    "fabric",
    "velvet",
    "linen",
    "cotton",
    "wool",
    "woolen",
    "wicker",
    "rattan",
    "plastic",
    "acrylic",
    "cardboard",
    "upholstered",
];

/// Shape adjectives.
pub const SHAPES: [&str; 15] = [
    "round",
    "circular",
    "square",
    "rectangular",
    "oval",
    "triangular",
    "hexagonal",
    "octagonal",
    "cylindrical",
    "spherical",
    "curved",
    "cubic",
    "flat",
    "l_shaped",
    "u_shaped",
];

/// Size adjectives.
pub const SIZES: [&str; 21] = [
    "small",
    "large",
    "big",
    "tiny",
    "huge",
    "tall",
    "short",
    "long",
    "wide",
    "narrow",
    "low",
    "high",
    "mini",
    "giant",
    "oversized",
    "compact",
    "sizable",
    "spacious",
    "massive",
    "little",
    "medium",
];

/// Is `word` one of the colour, material, shape or size adjectives above (ASCII case
/// insensitive)?
pub fn is_known_adjective(word: &str) -> bool {
    let lower = word.to_ascii_lowercase();
    let w = lower.as_str();
    COLOURS.contains(&w) || MATERIALS.contains(&w) || SHAPES.contains(&w) || SIZES.contains(&w)
}

/// The known adjectives among the words of `attribute`, split at `_`, `-` and spaces.
///
/// Two or more known adjectives make an attribute non-atomic ("round_wooden"). Compound words
/// from the lists (`l_shaped`, `u_shaped`) are matched before splitting so they count once.
pub fn known_adjective_words(attribute: &str) -> Vec<String> {
    let words: Vec<&str> = attribute
        .split(['_', '-', ' '])
        .filter(|w| !w.is_empty())
        .collect();
    let mut found = Vec::new();
    let mut i = 0;
    while i < words.len() {
        if i + 1 < words.len() {
            let pair = format!("{}_{}", words[i], words[i + 1]);
            if is_known_adjective(&pair) {
                found.push(pair);
                i += 2;
                continue;
            }
        }
        if is_known_adjective(words[i]) {
            found.push(words[i].to_owned());
        }
        i += 1;
    }
    found
}

/// Is `name` one of [`ARCH_ELEMENTS`]?
pub fn is_arch_element(name: &str) -> bool {
    ARCH_ELEMENTS.contains(&name)
}

/// Is `name` one of [`ROOM_TYPES`]?
pub fn is_room_type(name: &str) -> bool {
    ROOM_TYPES.contains(&name)
}

/// Levenshtein edit distance between two short strings (bytes compared as chars).
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for (i, ca) in a.iter().enumerate() {
        cur[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitution = prev[j] + usize::from(ca != cb);
            cur[j + 1] = substitution.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// What an unknown architecture reference most likely meant, if anything.
///
/// In order: an instance id such as `wall_1` or `kitchen2` (forbidden by the authors'
/// guidelines) suggests its stem; a different spelling of a known name (case, spaces or
/// hyphens instead of `_`) suggests that name; a known name within a small edit distance
/// (1 for names up to 4 letters, 2 otherwise) suggests the closest one (ties: the first in
/// [`ARCH_ELEMENTS`] then [`ROOM_TYPES`] order).
pub fn suggest_arch(name: &str) -> Option<ArchSuggestion> {
    let known = ARCH_ELEMENTS.iter().chain(ROOM_TYPES.iter());
    let stem = name.trim_end_matches(|c: char| c.is_ascii_digit());
    if stem.len() < name.len() {
        let stem = stem.trim_end_matches(['_', '-', ' ']);
        if is_arch_element(stem) || is_room_type(stem) {
            return Some(ArchSuggestion::InstanceId(stem.to_owned()));
        }
    }
    let normalised = name.trim().to_ascii_lowercase().replace([' ', '-'], "_");
    if normalised != name && (is_arch_element(&normalised) || is_room_type(&normalised)) {
        return Some(ArchSuggestion::Spelling(normalised));
    }
    let mut best: Option<(usize, &str)> = None;
    let length = normalised.chars().count();
    for candidate in known {
        let limit = if candidate.len() <= 4 { 1 } else { 2 };
        // The distance is at least the difference in length: a long name is compared with
        // nothing, so the work stays linear in its length.
        if length.abs_diff(candidate.chars().count()) > limit {
            continue;
        }
        let d = edit_distance(&normalised, candidate);
        if d <= limit && best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, candidate));
        }
    }
    best.map(|(_, c)| ArchSuggestion::Spelling(c.to_owned()))
}

/// A suggestion for an unknown architecture reference.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ArchSuggestion {
    /// The reference names one instance (`wall_1`); the schema wants the type (`wall`).
    InstanceId(String),
    /// The reference looks like a misspelling of this known name.
    Spelling(String),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edit_distance_hand_values() {
        // kitten -> sitting: k->s, e->i, insert g = 3.
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "wall"), 4);
        assert_eq!(edit_distance("walls", "wall"), 1);
        assert_eq!(edit_distance("wall", "wall"), 0);
    }

    #[test]
    fn adjective_words_split_and_compounds() {
        assert_eq!(known_adjective_words("round_wooden"), vec!["round", "wooden"]);
        assert_eq!(known_adjective_words("round wooden"), vec!["round", "wooden"]);
        assert_eq!(known_adjective_words("l_shaped"), vec!["l_shaped"]);
        assert_eq!(known_adjective_words("large_l_shaped"), vec!["large", "l_shaped"]);
        assert_eq!(known_adjective_words("stainless_steel"), vec!["steel"]);
        assert_eq!(known_adjective_words("queen_size"), Vec::<String>::new());
        assert!(is_known_adjective("Red"));
    }

    #[test]
    fn arch_suggestions() {
        assert_eq!(
            suggest_arch("wall_1"),
            Some(ArchSuggestion::InstanceId("wall".into()))
        );
        assert_eq!(
            suggest_arch("kitchen5"),
            Some(ArchSuggestion::InstanceId("kitchen".into()))
        );
        assert_eq!(
            suggest_arch("walls"),
            Some(ArchSuggestion::Spelling("wall".into()))
        );
        assert_eq!(
            suggest_arch("Wall"),
            Some(ArchSuggestion::Spelling("wall".into()))
        );
        assert_eq!(
            suggest_arch("living room"),
            Some(ArchSuggestion::Spelling("living_room".into()))
        );
        assert_eq!(
            suggest_arch("windw"),
            Some(ArchSuggestion::Spelling("window".into()))
        );
        assert_eq!(suggest_arch("spaceship"), None);
        // Two edits from "door" but the limit for 4-letter names is 1.
        assert_eq!(suggest_arch("dxxr"), None);
    }

    #[test]
    fn lists_have_no_duplicates() {
        for list in [
            &COLOURS[..],
            &MATERIALS[..],
            &SHAPES[..],
            &SIZES[..],
            &ROOM_TYPES[..],
        ] {
            let mut v = list.to_vec();
            v.sort_unstable();
            v.dedup();
            assert_eq!(v.len(), list.len());
        }
    }
}
