//! The built-in category tables: support types and functional sides by normalised category,
//! each row with the reason for it, and the sources that look objects up in them.

use std::collections::BTreeMap;

use sceneeval_geom::Side;
use sceneeval_scene::label::{Synset, normalise};
use sceneeval_scene::{Scene, SceneObject};
use serde::{Deserialize, Serialize};

use super::{Answer, FunctionalSidesOf, Source, SupportType, SupportTypeOf};
use crate::category::lookup_keys;

/// The built-in support-type prior: `(normalised category, type, why)`.
///
/// Looked up by [`normalise`] (synset suffix dropped) of the object's category, then its singular,
/// then its head noun (last word), so `Table Lamps` finds `table_lamp` and `king_size_bed`
/// finds `bed`. Categories not listed are unknown.
pub const SUPPORT_TYPE_TABLE: &[(&str, SupportType, &str)] = &[
    // Hanging from the ceiling.
    ("ceiling_lamp", SupportType::Ceiling, "mounted on the ceiling"),
    ("ceiling_light", SupportType::Ceiling, "mounted on the ceiling"),
    ("chandelier", SupportType::Ceiling, "hangs from the ceiling"),
    ("pendant_lamp", SupportType::Ceiling, "hangs from the ceiling"),
    ("pendant_light", SupportType::Ceiling, "hangs from the ceiling"),
    ("ceiling_fan", SupportType::Ceiling, "mounted on the ceiling"),
    // On a wall.
    (
        "painting",
        SupportType::Wall,
        "the paper's example: painting on the wall",
    ),
    ("picture", SupportType::Wall, "framed pictures hang on walls"),
    ("poster", SupportType::Wall, "posters hang on walls"),
    ("wall_art", SupportType::Wall, "hangs on a wall by definition"),
    (
        "mirror",
        SupportType::Wall,
        "a plain mirror hangs on a wall (floor mirrors say so)",
    ),
    ("wall_lamp", SupportType::Wall, "mounted on a wall by definition"),
    ("sconce", SupportType::Wall, "a wall-mounted light"),
    ("wall_clock", SupportType::Wall, "hangs on a wall by definition"),
    ("wall_shelf", SupportType::Wall, "mounted on a wall by definition"),
    (
        "wall_cabinet",
        SupportType::Wall,
        "mounted on a wall by definition",
    ),
    ("whiteboard", SupportType::Wall, "mounted on a wall"),
    ("tapestry", SupportType::Wall, "hangs on a wall"),
    // On another object.
    ("table_lamp", SupportType::Object, "stands on a table"),
    ("desk_lamp", SupportType::Object, "stands on a desk"),
    (
        "book",
        SupportType::Object,
        "the paper's example: book on the table",
    ),
    ("vase", SupportType::Object, "stands on a table or shelf"),
    ("laptop", SupportType::Object, "used on a desk or table"),
    ("monitor", SupportType::Object, "stands on a desk"),
    ("keyboard", SupportType::Object, "lies on a desk"),
    ("computer_mouse", SupportType::Object, "lies on a desk"),
    (
        "cup",
        SupportType::Object,
        "small item placed on a surface (paper's prompt)",
    ),
    ("mug", SupportType::Object, "small item placed on a surface"),
    ("bowl", SupportType::Object, "small item placed on a surface"),
    ("plate", SupportType::Object, "small item placed on a surface"),
    ("bottle", SupportType::Object, "small item placed on a surface"),
    ("candle", SupportType::Object, "small item placed on a surface"),
    ("alarm_clock", SupportType::Object, "stands on a nightstand"),
    ("pillow", SupportType::Object, "lies on a bed or sofa"),
    ("cushion", SupportType::Object, "lies on a sofa or chair"),
    ("remote", SupportType::Object, "small item placed on a surface"),
    (
        "photo_frame",
        SupportType::Object,
        "a standing frame on a shelf or desk",
    ),
    ("television", SupportType::Object, "usually stands on a TV stand"),
    ("tv", SupportType::Object, "usually stands on a TV stand"),
    ("microwave", SupportType::Object, "stands on a counter"),
    (
        "potted_plant",
        SupportType::Ground,
        "a pot standing on the floor (small ones say table_plant)",
    ),
    ("table_plant", SupportType::Object, "a small plant on a table"),
    // On the floor.
    ("bed", SupportType::Ground, "furniture standing on the floor"),
    ("bunk_bed", SupportType::Ground, "furniture standing on the floor"),
    ("crib", SupportType::Ground, "furniture standing on the floor"),
    ("sofa", SupportType::Ground, "furniture standing on the floor"),
    ("couch", SupportType::Ground, "furniture standing on the floor"),
    ("armchair", SupportType::Ground, "furniture standing on the floor"),
    ("chair", SupportType::Ground, "furniture standing on the floor"),
    (
        "dining_chair",
        SupportType::Ground,
        "furniture standing on the floor",
    ),
    (
        "office_chair",
        SupportType::Ground,
        "furniture standing on the floor",
    ),
    ("stool", SupportType::Ground, "furniture standing on the floor"),
    ("bench", SupportType::Ground, "furniture standing on the floor"),
    ("ottoman", SupportType::Ground, "furniture standing on the floor"),
    (
        "table",
        SupportType::Ground,
        "the paper's example: table on the ground",
    ),
    (
        "dining_table",
        SupportType::Ground,
        "furniture standing on the floor",
    ),
    (
        "coffee_table",
        SupportType::Ground,
        "furniture standing on the floor",
    ),
    (
        "side_table",
        SupportType::Ground,
        "furniture standing on the floor",
    ),
    (
        "end_table",
        SupportType::Ground,
        "furniture standing on the floor",
    ),
    (
        "console_table",
        SupportType::Ground,
        "furniture standing on the floor",
    ),
    (
        "nightstand",
        SupportType::Ground,
        "furniture standing on the floor",
    ),
    ("desk", SupportType::Ground, "furniture standing on the floor"),
    ("wardrobe", SupportType::Ground, "furniture standing on the floor"),
    ("closet", SupportType::Ground, "furniture standing on the floor"),
    ("dresser", SupportType::Ground, "furniture standing on the floor"),
    ("cabinet", SupportType::Ground, "furniture standing on the floor"),
    (
        "sideboard",
        SupportType::Ground,
        "furniture standing on the floor",
    ),
    (
        "bookshelf",
        SupportType::Ground,
        "free-standing shelving (wall shelves say wall_shelf)",
    ),
    ("bookcase", SupportType::Ground, "furniture standing on the floor"),
    (
        "shelf",
        SupportType::Ground,
        "free-standing shelving unit, the common 3D-FUTURE asset",
    ),
    ("tv_stand", SupportType::Ground, "furniture standing on the floor"),
    (
        "floor_lamp",
        SupportType::Ground,
        "stands on the floor by definition",
    ),
    ("rug", SupportType::Ground, "lies on the floor"),
    ("carpet", SupportType::Ground, "lies on the floor"),
    ("mat", SupportType::Ground, "lies on the floor"),
    (
        "plant",
        SupportType::Ground,
        "large indoor plants stand on the floor",
    ),
    (
        "refrigerator",
        SupportType::Ground,
        "appliance standing on the floor",
    ),
    ("fridge", SupportType::Ground, "appliance standing on the floor"),
    ("stove", SupportType::Ground, "appliance standing on the floor"),
    ("oven", SupportType::Ground, "appliance standing on the floor"),
    (
        "washing_machine",
        SupportType::Ground,
        "appliance standing on the floor",
    ),
    (
        "dishwasher",
        SupportType::Ground,
        "appliance standing on the floor",
    ),
    ("toilet", SupportType::Ground, "fixture standing on the floor"),
    ("bathtub", SupportType::Ground, "fixture standing on the floor"),
    ("piano", SupportType::Ground, "instrument standing on the floor"),
    (
        "kitchen_island",
        SupportType::Ground,
        "furniture standing on the floor",
    ),
    (
        "shoe_rack",
        SupportType::Ground,
        "furniture standing on the floor",
    ),
    ("coat_rack", SupportType::Ground, "stands on the floor"),
    ("trash_can", SupportType::Ground, "stands on the floor"),
    ("chest", SupportType::Ground, "furniture standing on the floor"),
];

/// The built-in functional-sides prior: `(normalised category, sides, why)`. The rows marked
/// "paper" are the examples of the paper's functional-sides prompt; an empty list means the
/// object has no functional side (skipped by the metric).
pub const FUNCTIONAL_SIDES_TABLE: &[(&str, &[Side], &str)] = &[
    (
        "bed",
        &[Side::Front, Side::Left, Side::Right],
        "paper: three sides of equal importance",
    ),
    ("dining_table", ALL4, "paper: usable from every side"),
    ("desk", &[Side::Front], "paper: a significant front side"),
    ("sofa", &[Side::Front], "paper: a significant front side"),
    ("dining_chair", ALL4, "paper: can be moved, all sides functional"),
    ("stool", ALL4, "paper: can be moved, all sides functional"),
    ("couch", &[Side::Front], "as sofa"),
    ("armchair", &[Side::Front], "as sofa: heavy, used from the front"),
    ("chair", ALL4, "as dining_chair: can be moved"),
    ("office_chair", ALL4, "as dining_chair: can be moved"),
    (
        "bench",
        &[Side::Front, Side::Back],
        "seated from either long side",
    ),
    ("ottoman", ALL4, "as stool"),
    ("table", ALL4, "as dining_table"),
    ("coffee_table", ALL4, "as dining_table"),
    ("kitchen_island", ALL4, "as dining_table"),
    ("side_table", &[Side::Front], "reached from its front"),
    ("end_table", &[Side::Front], "as side_table"),
    ("nightstand", &[Side::Front], "drawers at the front"),
    ("console_table", &[Side::Front], "used from the front"),
    (
        "wardrobe",
        &[Side::Front],
        "doors at the front (the paper's text)",
    ),
    ("closet", &[Side::Front], "as wardrobe"),
    ("dresser", &[Side::Front], "drawers at the front"),
    ("cabinet", &[Side::Front], "doors at the front"),
    ("sideboard", &[Side::Front], "doors at the front"),
    ("bookshelf", &[Side::Front], "open at the front"),
    ("bookcase", &[Side::Front], "open at the front"),
    ("shelf", &[Side::Front], "open at the front"),
    ("tv_stand", &[Side::Front], "used from the front"),
    ("refrigerator", &[Side::Front], "door at the front"),
    ("fridge", &[Side::Front], "door at the front"),
    ("stove", &[Side::Front], "used from the front"),
    ("oven", &[Side::Front], "door at the front"),
    ("washing_machine", &[Side::Front], "door at the front"),
    ("dishwasher", &[Side::Front], "door at the front"),
    ("toilet", &[Side::Front], "used from the front"),
    ("bathtub", &[Side::Front], "entered from its open long side"),
    ("piano", &[Side::Front], "played from the front"),
    ("shoe_rack", &[Side::Front], "used from the front"),
    ("chest", &[Side::Front], "opened from the front"),
    ("crib", &[Side::Front, Side::Left, Side::Right], "as bed"),
    ("bunk_bed", &[Side::Front, Side::Left, Side::Right], "as bed"),
    // No functional side: small items on surfaces (paper), wall and ceiling items, coverings.
    ("cup", &[], "paper: small objects have no functional side"),
    ("mug", &[], "small object"),
    ("book", &[], "paper: small objects have no functional side"),
    ("vase", &[], "small object"),
    ("bowl", &[], "small object"),
    ("plate", &[], "small object"),
    ("bottle", &[], "small object"),
    ("candle", &[], "small object"),
    ("laptop", &[], "small object on a surface"),
    ("monitor", &[], "small object on a surface"),
    ("keyboard", &[], "small object on a surface"),
    ("table_lamp", &[], "small object on a surface"),
    ("desk_lamp", &[], "small object on a surface"),
    ("alarm_clock", &[], "small object on a surface"),
    ("pillow", &[], "small object on a surface"),
    ("cushion", &[], "small object on a surface"),
    ("photo_frame", &[], "small object on a surface"),
    ("floor_lamp", &[], "needs no access area"),
    ("plant", &[], "needs no access area"),
    ("potted_plant", &[], "needs no access area"),
    ("trash_can", &[], "needs no access area"),
    ("coat_rack", &[], "needs no access area"),
    ("rug", &[], "a floor covering is walked on, not accessed"),
    ("carpet", &[], "a floor covering"),
    ("mat", &[], "a floor covering"),
    ("painting", &[], "on a wall, above the floor"),
    ("picture", &[], "on a wall, above the floor"),
    ("mirror", &[], "on a wall, above the floor"),
    ("ceiling_lamp", &[], "on the ceiling"),
    ("chandelier", &[], "on the ceiling"),
    ("pendant_lamp", &[], "on the ceiling"),
];

const ALL4: &[Side] = &[Side::Front, Side::Back, Side::Left, Side::Right];

fn lookup<'t, T>(table: &'t [(&'static str, T, &'static str)], category: &str) -> Option<&'t T> {
    lookup_keys(category)
        .iter()
        .find_map(|k| table.iter().find(|(key, _, _)| key == k).map(|(_, v, _)| v))
}

/// Support types by category ([`SUPPORT_TYPE_TABLE`], extended or overridden with
/// [`SupportTypePriors::with`]). Objects without a category, or with one not in the table,
/// are unknown. Source name `category_prior`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SupportTypePriors {
    /// Extra rows by normalised category, consulted before the built-in table.
    pub extra: BTreeMap<String, SupportType>,
}

impl SupportTypePriors {
    /// Adds or overrides a row (the category is normalised).
    pub fn with(mut self, category: &str, support_type: SupportType) -> Self {
        self.extra
            .insert(normalise(category, Synset::Strip), support_type);
        self
    }

    /// The prior for a raw category name.
    pub fn lookup(&self, category: &str) -> Option<SupportType> {
        let keys = lookup_keys(category);
        keys.iter()
            .find_map(|k| self.extra.get(k).copied())
            .or_else(|| lookup(SUPPORT_TYPE_TABLE, category).copied())
    }
}

impl Source<SupportTypeOf> for SupportTypePriors {
    fn answer(&self, _scene: &Scene, object: &SceneObject) -> Option<Answer<SupportType>> {
        let value = self.lookup(object.category()?)?;
        Some(Answer {
            value,
            source: "category_prior".to_owned(),
        })
    }
}

/// Functional sides by category ([`FUNCTIONAL_SIDES_TABLE`], extended or overridden with
/// [`FunctionalSidePriors::with`]). Source name `category_prior`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct FunctionalSidePriors {
    /// Extra rows by normalised category, consulted before the built-in table.
    pub extra: BTreeMap<String, Vec<Side>>,
}

impl FunctionalSidePriors {
    /// Adds or overrides a row (the category is normalised).
    pub fn with(mut self, category: &str, sides: Vec<Side>) -> Self {
        self.extra.insert(normalise(category, Synset::Strip), sides);
        self
    }

    /// The prior for a raw category name.
    pub fn lookup(&self, category: &str) -> Option<Vec<Side>> {
        let keys = lookup_keys(category);
        keys.iter()
            .find_map(|k| self.extra.get(k).cloned())
            .or_else(|| lookup(FUNCTIONAL_SIDES_TABLE, category).map(|s| s.to_vec()))
    }
}

impl Source<FunctionalSidesOf> for FunctionalSidePriors {
    fn answer(&self, _scene: &Scene, object: &SceneObject) -> Option<Answer<Vec<Side>>> {
        let value = self.lookup(object.category()?)?;
        Some(Answer {
            value,
            source: "category_prior".to_owned(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn tables_have_unique_normalised_keys() {
        let mut seen = HashSet::new();
        for (k, _, why) in SUPPORT_TYPE_TABLE {
            assert_eq!(normalise(k, Synset::Strip), *k);
            assert!(seen.insert(*k), "duplicate {k}");
            assert!(!why.is_empty());
        }
        seen.clear();
        for (k, sides, why) in FUNCTIONAL_SIDES_TABLE {
            assert_eq!(normalise(k, Synset::Strip), *k);
            assert!(seen.insert(*k), "duplicate {k}");
            assert!(!why.is_empty());
            assert!(sides.iter().all(|s| Side::HORIZONTAL.contains(s)));
        }
    }

    #[test]
    fn paper_examples_are_in_the_tables() {
        let p = FunctionalSidePriors::default();
        assert_eq!(p.lookup("bed"), Some(vec![Side::Front, Side::Left, Side::Right]));
        assert_eq!(p.lookup("Dining Table").map(|s| s.len()), Some(4));
        assert_eq!(p.lookup("desks"), Some(vec![Side::Front]));
        assert_eq!(p.lookup("sofa"), Some(vec![Side::Front]));
        assert_eq!(p.lookup("dining-chair").map(|s| s.len()), Some(4));
        assert_eq!(p.lookup("stool").map(|s| s.len()), Some(4));
        assert_eq!(p.lookup("cups"), Some(vec![]));
        assert_eq!(p.lookup("spaceship"), None);
        let s = SupportTypePriors::default();
        assert_eq!(s.lookup("Table Lamps"), Some(SupportType::Object));
        assert_eq!(s.lookup("king size bed"), Some(SupportType::Ground));
        assert_eq!(s.lookup("painting.n.01"), Some(SupportType::Wall));
        assert_eq!(s.lookup("chandeliers"), Some(SupportType::Ceiling));
        assert_eq!(s.lookup("teleporter"), None);
        let custom = s
            .with("Teleporter", SupportType::Ceiling)
            .with("bed", SupportType::Wall);
        assert_eq!(custom.lookup("teleporters"), Some(SupportType::Ceiling));
        assert_eq!(
            custom.lookup("bed"),
            Some(SupportType::Wall),
            "extra rows override"
        );
    }
}
