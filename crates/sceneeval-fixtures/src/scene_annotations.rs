//! One SceneEval-500 style annotation row per fixture scene, written to
//! `annotations/fixture_scenes.csv` with `sceneeval-annotation`'s types and writer.
//!
//! - `ID` is the scene number, `Description` the scene's one-sentence description.
//! - `ObjCount` is derived from the scene itself: one `eq,n,category` entry per category, in
//!   order of first appearance (categories with `_` for spaces), so it always holds.
//! - `Difficulty` follows the paper's levels from the number of objects specified: at most 4
//!   easy, 5 to 8 medium, 9 or more hard.
//! - `ObjAttr`, `OORel` and `OARel` are written by hand below. Every entry holds in its scene:
//!   the flaws of the flawed scenes (collision, floating, out of bounds, blocked door, an
//!   object inside another) are plausibility flaws, which the annotation schema cannot state,
//!   so their rows describe what the scene does satisfy. The geometry behind each relation is
//!   noted next to it (distances are between the objects' boxes).
//!
//! The generator validates every row with `sceneeval_annotation::validate` and refuses to
//! write one with an error finding.

use std::path::{Path, PathBuf};

use sceneeval_annotation::{AnnotationRow, Annotations, Difficulty, Severity, validate};

use crate::FixtureError;
use crate::spec::{Model, SceneSpec};

/// The file written into the annotation folder.
pub const FILE_NAME: &str = "fixture_scenes.csv";

/// Hand-written entries of one scene.
struct Entries {
    obj_attr: &'static [&'static str],
    oo_rel: &'static [&'static str],
    oa_rel: &'static [&'static str],
}

/// The hand-written entries of each scene, by scene number (a table: one item per scene).
static ENTRIES: [Entries; 13] = [
    // Scene 0.
    Entries {
        obj_attr: &["eq,1,bed,double", "eq,1,wardrobe,tall"],
        oo_rel: &[
            // 5 cm on each side.
            "eq,2,next_to,0,bed,nightstand",
            "eq,2,on,0,nightstand,table_lamp",
            // Painting z 1.3..1.9 over the headboard (1.1), inside the bed's footprint.
            "eq,1,above,0,bed,painting",
            // Rug 0.6 m beyond the bed's foot, centred on it.
            "eq,1,in_front_of,0,bed,rug",
        ],
        oa_rel: &[
            "eq,1,against,bed,wall",
            "eq,1,against,wardrobe,wall",
            "eq,1,on,painting,wall",
            "eq,1,hang,ceiling_lamp,ceiling",
        ],
    },
    // Scene 1.
    Entries {
        obj_attr: &["eq,1,sofa,grey", "eq,1,tv,flat_screen", "eq,1,rug,rectangular"],
        oo_rel: &[
            // The sofa faces +x, the TV is straight ahead at the same y.
            "eq,1,face,0,tv,sofa",
            "eq,1,in_front_of,0,sofa,coffee_table",
            "eq,1,on,0,rug,coffee_table",
            "eq,1,above,0,tv_stand,tv",
        ],
        oa_rel: &[
            "eq,1,on,tv,wall",
            "eq,1,against,sofa,wall",
            "eq,1,corner,floor_lamp,room",
            "eq,1,corner,plant,room",
            "eq,1,on,painting,wall",
        ],
    },
    // Scene 2.
    Entries {
        obj_attr: &["eq,1,dining_table,rectangular", "eq,6,chair,wooden"],
        oo_rel: &[
            "eq,1,surround,0,dining_table,chair:0,chair:1,chair:2,chair:3,chair:4,chair:5",
            // Every chair is 5 cm from the table.
            "eq,6,next_to,0,dining_table,chair",
            "eq,1,above,0,dining_table,ceiling_lamp",
        ],
        oa_rel: &[
            "eq,1,against,bookshelf,wall",
            "eq,1,corner,plant,room",
            "eq,1,corner,floor_lamp,room",
            "eq,1,on,painting,wall",
            "eq,1,hang,ceiling_lamp,ceiling",
        ],
    },
    // Scene 3.
    Entries {
        obj_attr: &["eq,1,desk,rectangular"],
        oo_rel: &["eq,1,in_front_of,0,desk,chair", "eq,1,on,0,desk,table_lamp"],
        oa_rel: &[
            "eq,1,against,desk,wall",
            // Against the diagonal wall.
            "eq,1,against,bookshelf,wall",
            "eq,1,corner,floor_lamp,room",
            "eq,1,corner,plant,room",
            "eq,1,on,painting,wall",
            // Rug centre (2.0, 2.6), 0.51 m from the floor's bounding-box centre (2.5, 2.5).
            "eq,1,middle_of,rug,room",
        ],
    },
    // Scene 4.
    Entries {
        obj_attr: &["eq,1,bed,double", "eq,1,wardrobe,wide", "eq,1,plant,small"],
        oo_rel: &[
            "eq,2,next_to,0,bed,nightstand",
            // The sofa faces -x; the TV 4.35 m away at x 4.2, y 1.6..2.8.
            "eq,1,face,0,tv,sofa",
            "eq,1,on,0,tv_stand,tv",
            "eq,1,in_front_of,0,sofa,coffee_table",
        ],
        oa_rel: &[
            "eq,1,in,bed,bedroom",
            "eq,1,in,wardrobe,bedroom",
            "eq,1,in,sofa,living_room",
            "eq,1,against,sofa,wall",
        ],
    },
    // Scene 5.
    Entries {
        obj_attr: &["eq,1,wardrobe,tall"],
        oo_rel: &[
            "eq,1,next_to,0,wardrobe,nightstand",
            "eq,1,on,0,nightstand,table_lamp",
        ],
        oa_rel: &["eq,1,against,bed,wall", "eq,1,against,wardrobe,wall"],
    },
    // Scene 6.
    Entries {
        obj_attr: &["eq,1,bookshelf,tall"],
        oo_rel: &["eq,1,in_front_of,0,desk,chair", "eq,1,on,0,desk,table_lamp"],
        oa_rel: &[
            "eq,1,against,desk,wall",
            "eq,1,against,bookshelf,wall",
            "eq,1,corner,floor_lamp,room",
        ],
    },
    // Scene 7.
    Entries {
        obj_attr: &["eq,1,sofa,grey"],
        // Boxes 0.45 m apart in x (2.55 to 3.0) and 0.05 m in y.
        oo_rel: &["eq,1,near,0,sofa,coffee_table"],
        oa_rel: &[
            "eq,1,corner,floor_lamp,room",
            "eq,1,corner,plant,room",
            "eq,1,on,painting,wall",
        ],
    },
    // Scene 8.
    Entries {
        obj_attr: &["eq,1,wardrobe,tall"],
        // 0.18 m between the bed's side and the nightstand.
        oo_rel: &["eq,1,next_to,0,bed,nightstand"],
        // 2 cm from the door's wall, covering the door.
        oa_rel: &["eq,1,next_to,wardrobe,door", "eq,1,against,bed,wall"],
    },
    // Scene 9.
    Entries {
        obj_attr: &["eq,1,storage_box,small"],
        oo_rel: &["eq,1,inside,0,wardrobe,storage_box"],
        oa_rel: &["eq,1,against,wardrobe,wall", "eq,1,against,bookshelf,wall"],
    },
    // Scene 10.
    Entries {
        obj_attr: &["eq,1,rug,rectangular"],
        oo_rel: &[],
        oa_rel: &[
            "eq,1,middle_of,rug,room",
            "eq,1,corner,plant,room",
            "eq,1,corner,floor_lamp,room",
            "eq,1,on,painting,wall",
            "eq,1,hang,ceiling_lamp,ceiling",
        ],
    },
    // Scene 11.
    Entries {
        obj_attr: &[],
        oo_rel: &[
            "eq,2,next_to,0,bed,nightstand",
            "eq,1,on,0,nightstand,table_lamp",
            // The desk faces -x; the chair 6 cm beyond its front, within its width.
            "eq,1,in_front_of,0,desk,chair",
        ],
        oa_rel: &[
            "eq,1,against,bed,wall",
            "eq,1,against,wardrobe,wall",
            "eq,1,against,desk,wall",
        ],
    },
    // Scene 12.
    Entries {
        obj_attr: &["eq,2,sofa,grey"],
        oo_rel: &[
            "eq,20,on,0,desk,table_lamp",
            // Each chair is 5 cm from its desk (chairs of the next row may count too).
            "ge,20,next_to,0,desk,chair",
            "ge,12,next_to,0,dining_table,chair",
            "eq,1,on,0,tv_stand,tv",
        ],
        oa_rel: &[
            "eq,6,against,bookshelf,wall",
            "eq,2,on,painting,wall",
            "eq,10,hang,ceiling_lamp,ceiling",
        ],
    },
];

/// The entries of a scene without hand-written ones.
static NO_ENTRIES: Entries = Entries {
    obj_attr: &[],
    oo_rel: &[],
    oa_rel: &[],
};

/// The hand-written entries of scene `number`.
fn entries(number: u32) -> &'static Entries {
    usize::try_from(number)
        .ok()
        .and_then(|n| ENTRIES.get(n))
        .unwrap_or(&NO_ENTRIES)
}

/// The annotation category of a placement: its category with `_` for spaces.
fn category(model: &Model) -> String {
    let c = match model {
        Model::Asset(id) => crate::assets::asset(id).map_or(*id, |a| a.category),
        Model::Box { category, .. } => category,
    };
    c.replace(' ', "_")
}

/// `eq,n,category` for every category of the scene, in order of first appearance.
fn obj_counts(spec: &SceneSpec) -> Vec<(String, u64)> {
    let mut counts: Vec<(String, u64)> = Vec::new();
    for p in &spec.objects {
        let c = category(&p.model);
        match counts.iter_mut().find(|(k, _)| *k == c) {
            Some((_, n)) => *n += 1,
            None => counts.push((c, 1)),
        }
    }
    counts
}

/// The paper's difficulty level for a number of specified objects.
fn difficulty(objects: u64) -> Difficulty {
    match objects {
        0..=4 => Difficulty::Easy,
        5..=8 => Difficulty::Medium,
        _ => Difficulty::Hard,
    }
}

/// The annotation row of one scene.
pub fn row(spec: &SceneSpec) -> AnnotationRow {
    let counts = obj_counts(spec);
    let total = counts.iter().map(|(_, n)| n).sum();
    let mut row = AnnotationRow::new(spec.number.to_string(), difficulty(total), spec.description);
    let count_texts: Vec<String> = counts.iter().map(|(c, n)| format!("eq,{n},{c}")).collect();
    let e = entries(spec.number);
    row.set_cell("ObjCount", &count_texts.join("; "));
    row.set_cell("ObjAttr", &e.obj_attr.join("; "));
    row.set_cell("OORel", &e.oo_rel.join("; "));
    row.set_cell("OARel", &e.oa_rel.join("; "));
    row
}

/// The annotations of every scene in `specs`, one row each, in order.
pub fn annotations(specs: &[SceneSpec]) -> Annotations {
    Annotations::from_rows(specs.iter().map(row).collect())
}

/// Writes [`FILE_NAME`] (and the annotation files of [`crate::annotations`]) into `dir`;
/// returns the file names written.
///
/// # Errors
/// [`FixtureError::Annotation`] when a row has a validation error or a file cannot be written.
pub fn write(dir: &Path, specs: &[SceneSpec]) -> Result<Vec<PathBuf>, FixtureError> {
    let path = dir.join(FILE_NAME);
    let all = annotations(specs);
    if let Some(f) = validate(&all).into_iter().find(|f| f.severity == Severity::Error) {
        return Err(FixtureError::Annotation {
            path,
            reason: format!("row {} {}: {}", f.row, f.field, f.message),
        });
    }
    all.write_csv(&path).map_err(|e| FixtureError::Annotation {
        path: path.clone(),
        reason: e.to_string(),
    })?;
    crate::annotations::write_all(dir).map_err(|e| FixtureError::Annotation {
        path: dir.to_owned(),
        reason: e.to_string(),
    })?;
    let mut written: Vec<PathBuf> = crate::annotations::FILES.iter().map(PathBuf::from).collect();
    written.push(PathBuf::from(FILE_NAME));
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes;

    #[test]
    fn every_scene_row_is_valid_without_warnings() {
        let specs = scenes::all();
        let all = annotations(&specs);
        let findings = validate(&all);
        assert!(findings.is_empty(), "{findings:#?}");
        assert_eq!(all.ids().count(), specs.len());
    }

    #[test]
    fn object_counts_and_difficulty_follow_the_scene() {
        let specs = scenes::all();
        // Scene 0: bed, 2 nightstands, 2 table lamps, wardrobe, rug, painting, ceiling lamp.
        let r = row(&specs[0]);
        assert_eq!(
            r.entry_texts(sceneeval_annotation::Field::ObjCount).unwrap(),
            [
                "eq,1,bed",
                "eq,2,nightstand",
                "eq,2,table_lamp",
                "eq,1,wardrobe",
                "eq,1,rug",
                "eq,1,painting",
                "eq,1,ceiling_lamp"
            ]
        );
        assert_eq!(r.objects_specified(), 9);
        assert_eq!(r.difficulty, Difficulty::Hard);
        // Scene 8: wardrobe, bed, nightstand, ceiling lamp: 4 objects, easy.
        assert_eq!(row(&specs[8]).difficulty, Difficulty::Easy);
        // Scene 12: 20 desk chairs + 12 meeting chairs.
        let large = row(&specs[12]);
        assert!(
            large
                .obj_counts()
                .any(|c| c.category == "chair" && c.count.quantity == 32)
        );
    }

    #[test]
    fn csv_round_trips() {
        let all = annotations(&scenes::all());
        let text = all.to_csv_string().unwrap();
        let back = Annotations::from_csv_str(&text).unwrap();
        assert_eq!(back.to_csv_string().unwrap(), text);
        assert_eq!(back.get("5").unwrap().description, scenes::all()[5].description);
    }
}
