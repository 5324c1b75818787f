//! The relation lexicon: free-text relationship words of SceneEval-500 onto predicates,
//! deterministically and without a VLM.
//!
//! A relationship is first normalised ([`sceneeval_scene::label::normalise`]: lower case, `_`
//! for whitespace and hyphens), then a leading `is_`/`are_`/`to_the_`/`in_the_`/`at_the_` and a
//! trailing `_of`/`_to`/`_from`/`_by`/`_with` are tried away in turn until a table word
//! matches (`to_the_left_of` -> `left`, `in_front_of` -> `in_front`, `at_the_foot_of` ->
//! `at_the_foot` -> `foot`). A word in no table is *unknown*: the VLM maps it when one is
//! configured, otherwise the spec is unmapped. A word listed as unmapped below is one no
//! predicate expresses; it is unmapped without asking.
//!
//! # Object-object words ([`OBJECT_WORDS`])
//! The target is the first other object of a candidate group, the anchor the annotation's
//! anchor; every listed predicate must hold (AND), as in the reference.
//!
//! | words | predicates |
//! |---|---|
//! | on, on_top, atop, onto, sit_on, placed_on, rest_on, upon | `on_top` |
//! | within, inside, in, contained_in, into | `inside_of` |
//! | outside | `outside_of` |
//! | near, nearby, close, close_to, around_near | `near` |
//! | next, next_to, beside, adjacent, alongside, by, flank, flanking, side_by_side | `next_to` |
//! | face, faces, facing, face_to, face_towards, facing_towards, toward, towards | `face_to` |
//! | front, in_front | `side_of(front)` |
//! | behind, back, in_back | `side_of(back)` |
//! | left, to_the_left | `side_of(left)` |
//! | right, to_the_right | `side_of(right)` |
//! | above, over | `side_of(top)` |
//! | below, beneath, under, underneath | `side_of(bottom)` |
//! | left_region, left_side_region | `side_region(left)`; likewise right, front, back, top, bottom |
//! | long_side | `long_short_side_of(long)` |
//! | short_side | `long_short_side_of(short)` |
//! | surround, surrounding, around, encircle, circle | `surround` |
//! | across, opposite, across_from | `across_from` |
//! | far, far_away, distant | `far` |
//! | middle, center, centre, centered_on, in_the_middle | `middle_of` |
//! | foot, at_the_foot | `side_of(front)` and `next_to` (the foot of a bed is its front) |
//! | between | unmapped: no predicate tests that the anchor lies between two objects |
//!
//! # Object-architecture words ([`ARCH_WORDS`])
//! The element is the first architecture reference of the entry that names a known element
//! ([`ArchRef::element`](sceneeval_annotation::ArchRef::element): a room type such as
//! `bedroom` counts as `room`).
//!
//! | words | wall | door / window | floor | ceiling | room |
//! |---|---|---|---|---|---|
//! | against, flush | `against_wall` | `next_to(element)` | — | — | — |
//! | on, mounted, mount, hang, hung, hanging, attached | `on_wall` | — | `inside_room` | `hang_from_ceiling` | — |
//! | next, next_to, beside, by, adjacent, alongside, close | `next_to(wall)` | `next_to(element)` | — | — | — |
//! | near, nearby | `near(wall)` | `near(element)` | — | — | — |
//! | across, opposite, facing, face | `across_from(wall)` | `across_from(element)` | — | — | — |
//! | far, away | `far(wall)` | `far(element)` | — | — | — |
//! | corner, in_corner | — | — | — | — | `corner_of_room` |
//! | middle, center, centre, in_middle, in_center | — | — | — | — | `middle_of_room` |
//! | in, inside, within | — | — | `inside_room` | — | `inside_room` |
//!
//! A dash is unmapped: e.g. `corner` of a wall, `against` the ceiling.

use sceneeval_geom::Side;
use sceneeval_relations::{LongShort, Relation};
use sceneeval_scene::ArchElement;
use sceneeval_scene::label::{Synset, normalise};

/// One row of the object-object table.
#[derive(Debug, Clone, Copy)]
pub struct ObjectWord {
    /// The words (normalised).
    pub words: &'static [&'static str],
    /// The predicates that must all hold; empty for a word no predicate expresses.
    pub relations: &'static [Relation],
}

const fn ow(words: &'static [&'static str], relations: &'static [Relation]) -> ObjectWord {
    ObjectWord { words, relations }
}

use Relation as R;

/// The object-object table (see the module docs).
pub const OBJECT_WORDS: &[ObjectWord] = &[
    ow(
        &[
            "on",
            "on_top",
            "atop",
            "onto",
            "sit_on",
            "placed_on",
            "rest_on",
            "upon",
        ],
        &[R::OnTop],
    ),
    ow(
        &["within", "inside", "in", "contained_in", "into"],
        &[R::InsideOf],
    ),
    ow(&["outside"], &[R::OutsideOf]),
    ow(&["near", "nearby", "close", "close_to"], &[R::Near]),
    ow(
        &[
            "next",
            "next_to",
            "beside",
            "adjacent",
            "alongside",
            "by",
            "flank",
            "flanking",
            "side_by_side",
        ],
        &[R::NextTo],
    ),
    ow(
        &[
            "face",
            "faces",
            "facing",
            "face_to",
            "face_towards",
            "facing_towards",
            "toward",
            "towards",
        ],
        &[R::FaceTo],
    ),
    ow(&["front", "in_front"], &[R::SideOf(Side::Front)]),
    ow(&["behind", "back", "in_back"], &[R::SideOf(Side::Back)]),
    ow(&["left", "to_the_left"], &[R::SideOf(Side::Left)]),
    ow(&["right", "to_the_right"], &[R::SideOf(Side::Right)]),
    ow(&["above", "over"], &[R::SideOf(Side::Top)]),
    ow(
        &["below", "beneath", "under", "underneath"],
        &[R::SideOf(Side::Bottom)],
    ),
    ow(&["left_region", "left_side_region"], &[R::SideRegion(Side::Left)]),
    ow(
        &["right_region", "right_side_region"],
        &[R::SideRegion(Side::Right)],
    ),
    ow(
        &["front_region", "front_side_region"],
        &[R::SideRegion(Side::Front)],
    ),
    ow(&["back_region", "back_side_region"], &[R::SideRegion(Side::Back)]),
    ow(&["top_region", "top_side_region"], &[R::SideRegion(Side::Top)]),
    ow(
        &["bottom_region", "bottom_side_region"],
        &[R::SideRegion(Side::Bottom)],
    ),
    ow(&["long_side"], &[R::LongShortSideOf(LongShort::Long)]),
    ow(&["short_side"], &[R::LongShortSideOf(LongShort::Short)]),
    ow(
        &["surround", "surrounding", "around", "encircle", "circle"],
        &[R::Surround],
    ),
    ow(&["across", "opposite", "across_from"], &[R::AcrossFrom]),
    ow(&["far", "far_away", "distant"], &[R::Far]),
    ow(
        &["middle", "center", "centre", "centered_on", "in_the_middle"],
        &[R::MiddleOf],
    ),
    ow(&["foot", "at_the_foot"], &[R::SideOf(Side::Front), R::NextTo]),
    ow(&["between"], &[]),
];

/// What an object-architecture word means per element kind.
#[derive(Debug, Clone, Copy)]
pub struct ArchWord {
    /// The words (normalised).
    pub words: &'static [&'static str],
    /// Against a wall.
    pub wall: Option<Relation>,
    /// Against a door or window: the distance relation's constructor.
    pub opening: Option<fn(ArchElement) -> Relation>,
    /// Against the floor.
    pub floor: Option<Relation>,
    /// Against the ceiling.
    pub ceiling: Option<Relation>,
    /// Against the room.
    pub room: Option<Relation>,
}

const NONE: ArchWord = ArchWord {
    words: &[],
    wall: None,
    opening: None,
    floor: None,
    ceiling: None,
    room: None,
};

/// The object-architecture table (see the module docs).
pub const ARCH_WORDS: &[ArchWord] = &[
    ArchWord {
        words: &["against", "flush"],
        wall: Some(R::AgainstWall),
        opening: Some(R::NextToArch),
        ..NONE
    },
    ArchWord {
        words: &["on", "mounted", "mount", "hang", "hung", "hanging", "attached"],
        wall: Some(R::OnWall),
        floor: Some(R::InsideRoom),
        ceiling: Some(R::HangFromCeiling),
        ..NONE
    },
    ArchWord {
        words: &[
            "next",
            "next_to",
            "beside",
            "by",
            "adjacent",
            "alongside",
            "close",
        ],
        wall: Some(R::NextToArch(ArchElement::Wall)),
        opening: Some(R::NextToArch),
        ..NONE
    },
    ArchWord {
        words: &["near", "nearby"],
        wall: Some(R::NearArch(ArchElement::Wall)),
        opening: Some(R::NearArch),
        ..NONE
    },
    ArchWord {
        words: &["across", "opposite", "facing", "face"],
        wall: Some(R::AcrossFromArch(ArchElement::Wall)),
        opening: Some(R::AcrossFromArch),
        ..NONE
    },
    ArchWord {
        words: &["far", "away"],
        wall: Some(R::FarArch(ArchElement::Wall)),
        opening: Some(R::FarArch),
        ..NONE
    },
    ArchWord {
        words: &["corner", "in_corner"],
        room: Some(R::CornerOfRoom),
        ..NONE
    },
    ArchWord {
        words: &["middle", "center", "centre", "in_middle", "in_center"],
        room: Some(R::MiddleOfRoom),
        ..NONE
    },
    ArchWord {
        words: &["in", "inside", "within"],
        floor: Some(R::InsideRoom),
        room: Some(R::InsideRoom),
        ..NONE
    },
];

/// What the lexicon says about a relationship.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Lookup<T> {
    /// Mapped: the predicates (object-object: all must hold) and the table word used.
    Mapped {
        /// The mapping.
        mapping: T,
        /// The table word that matched.
        word: &'static str,
    },
    /// Known, but no predicate expresses it (here, or for this element).
    Unmapped {
        /// Why.
        reason: String,
    },
    /// Not in the table.
    Unknown,
}

const PREFIXES: [&str; 5] = ["is_", "are_", "to_the_", "in_the_", "at_the_"];
const SUFFIXES: [&str; 5] = ["_of", "_to", "_from", "_by", "_with"];

/// The spellings tried for a word, in order: the word, then without a prefix, without a
/// suffix, and without both.
fn candidates(word: &str) -> Vec<String> {
    let n = normalise(word, Synset::Keep);
    let mut out = vec![n.clone()];
    let strip_prefix = |s: &str| -> Option<String> {
        PREFIXES
            .iter()
            .find_map(|p| s.strip_prefix(p).filter(|r| !r.is_empty()).map(str::to_owned))
    };
    let strip_suffix = |s: &str| -> Option<String> {
        SUFFIXES
            .iter()
            .find_map(|p| s.strip_suffix(p).filter(|r| !r.is_empty()).map(str::to_owned))
    };
    if let Some(p) = strip_prefix(&n) {
        out.push(p.clone());
        if let Some(ps) = strip_suffix(&p) {
            out.push(ps);
        }
    }
    if let Some(s) = strip_suffix(&n) {
        out.push(s.clone());
        if let Some(sp) = strip_prefix(&s) {
            out.push(sp);
        }
    }
    out
}

/// Maps an object-object relationship word.
///
/// ```
/// use sceneeval_fidelity::lexicon::{map_object, Lookup};
/// use sceneeval_relations::Relation;
/// use sceneeval_geom::Side;
/// match map_object("to the left of") {
///     Lookup::Mapped { mapping, .. } => assert_eq!(mapping, vec![Relation::SideOf(Side::Left)]),
///     other => panic!("{other:?}"),
/// }
/// assert!(matches!(map_object("between"), Lookup::Unmapped { .. }));
/// assert_eq!(map_object("in_harmony_with"), Lookup::Unknown);
/// ```
pub fn map_object(relationship: &str) -> Lookup<Vec<Relation>> {
    for c in candidates(relationship) {
        for row in OBJECT_WORDS {
            if let Some(word) = row.words.iter().find(|w| **w == c) {
                return if row.relations.is_empty() {
                    Lookup::Unmapped {
                        reason: format!("no predicate expresses {word:?}"),
                    }
                } else {
                    Lookup::Mapped {
                        mapping: row.relations.to_vec(),
                        word,
                    }
                };
            }
        }
    }
    Lookup::Unknown
}

/// Maps an object-architecture relationship word against an element kind.
///
/// ```
/// use sceneeval_fidelity::lexicon::{map_arch, Lookup};
/// use sceneeval_relations::{ArchElement, Relation};
/// let on = |e| match map_arch("on", e) { Lookup::Mapped { mapping, .. } => Some(mapping), _ => None };
/// assert_eq!(on(ArchElement::Wall), Some(Relation::OnWall));
/// assert_eq!(on(ArchElement::Ceiling), Some(Relation::HangFromCeiling));
/// match map_arch("next", ArchElement::Window) {
///     Lookup::Mapped { mapping, .. } => assert_eq!(mapping, Relation::NextToArch(ArchElement::Window)),
///     other => panic!("{other:?}"),
/// }
/// assert!(matches!(map_arch("corner", ArchElement::Wall), Lookup::Unmapped { .. }));
/// ```
pub fn map_arch(relationship: &str, element: ArchElement) -> Lookup<Relation> {
    for c in candidates(relationship) {
        for row in ARCH_WORDS {
            if let Some(word) = row.words.iter().find(|w| **w == c) {
                let r = match element {
                    ArchElement::Wall => row.wall,
                    ArchElement::Door | ArchElement::Window => row.opening.map(|f| f(element)),
                    ArchElement::Floor => row.floor,
                    ArchElement::Ceiling => row.ceiling,
                    ArchElement::Room => row.room,
                };
                return match r {
                    Some(mapping) => Lookup::Mapped { mapping, word },
                    None => Lookup::Unmapped {
                        reason: format!("no predicate expresses {word:?} with respect to a {element:?}")
                            .to_lowercase(),
                    },
                };
            }
        }
    }
    Lookup::Unknown
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obj(word: &str) -> Vec<Relation> {
        match map_object(word) {
            Lookup::Mapped { mapping, .. } => mapping,
            other => panic!("{word}: {other:?}"),
        }
    }

    fn arch(word: &str, e: ArchElement) -> Relation {
        match map_arch(word, e) {
            Lookup::Mapped { mapping, .. } => mapping,
            other => panic!("{word} {e:?}: {other:?}"),
        }
    }

    /// The words the issue lists, each onto its predicate.
    #[test]
    fn issue_words() {
        use ArchElement as E;
        assert_eq!(obj("on"), [R::OnTop]);
        assert_eq!(obj("within"), [R::InsideOf]);
        assert_eq!(obj("near"), [R::Near]);
        assert_eq!(obj("face"), [R::FaceTo]);
        assert_eq!(obj("front"), [R::SideOf(Side::Front)]);
        assert_eq!(obj("in_front_of"), [R::SideOf(Side::Front)]);
        assert_eq!(obj("next"), [R::NextTo]);
        assert_eq!(obj("right"), [R::SideOf(Side::Right)]);
        assert_eq!(obj("left"), [R::SideOf(Side::Left)]);
        assert_eq!(obj("above"), [R::SideOf(Side::Top)]);
        assert_eq!(obj("surround"), [R::Surround]);
        assert_eq!(obj("across"), [R::AcrossFrom]);
        assert_eq!(obj("long_side"), [R::LongShortSideOf(LongShort::Long)]);
        assert_eq!(obj("short_side"), [R::LongShortSideOf(LongShort::Short)]);
        assert_eq!(obj("inside"), [R::InsideOf]);
        assert_eq!(obj("beside"), [R::NextTo]);
        assert_eq!(obj("behind"), [R::SideOf(Side::Back)]);
        assert_eq!(obj("below"), [R::SideOf(Side::Bottom)]);
        assert_eq!(obj("beneath"), [R::SideOf(Side::Bottom)]);
        assert_eq!(obj("At the foot of"), [R::SideOf(Side::Front), R::NextTo]);
        assert!(matches!(map_object("between"), Lookup::Unmapped { .. }));

        for e in [E::Wall, E::Door, E::Window] {
            assert_eq!(arch("near", e), R::NearArch(e));
            assert_eq!(arch("next", e), R::NextToArch(e));
        }
        assert_eq!(arch("against", E::Wall), R::AgainstWall);
        assert_eq!(arch("against", E::Window), R::NextToArch(ArchElement::Window));
        assert_eq!(arch("against", E::Door), R::NextToArch(ArchElement::Door));
        assert_eq!(arch("on", E::Wall), R::OnWall);
        assert_eq!(arch("corner", E::Room), R::CornerOfRoom);
        assert_eq!(arch("middle", E::Room), R::MiddleOfRoom);
        assert_eq!(arch("center", E::Room), R::MiddleOfRoom);
        assert_eq!(arch("hang", E::Ceiling), R::HangFromCeiling);
        assert!(matches!(map_arch("against", E::Ceiling), Lookup::Unmapped { .. }));
        assert_eq!(map_arch("levitating", E::Wall), Lookup::Unknown);
    }

    #[test]
    fn no_word_is_listed_twice() {
        let mut seen = std::collections::BTreeSet::new();
        for w in OBJECT_WORDS.iter().flat_map(|r| r.words) {
            assert!(seen.insert(*w), "{w} twice in OBJECT_WORDS");
        }
        seen.clear();
        for w in ARCH_WORDS.iter().flat_map(|r| r.words) {
            assert!(seen.insert(*w), "{w} twice in ARCH_WORDS");
        }
    }
}
