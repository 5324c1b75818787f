//! Annotation fixture rows: the example descriptions quoted in the SceneEval paper annotated
//! by hand following the schema and the authors' guidelines, and a file of malformed rows
//! that exercises every validation finding of `sceneeval-annotation`.
//!
//! | file | function | content |
//! |---|---|---|
//! | `paper_examples.csv` | [`paper_examples`] | 5 rows, no validation errors |
//! | `malformed.csv` | [`malformed_rows`] | one or more rows per finding code, labelled in an `Exercises` column |
//!
//! The paper's descriptions are quoted verbatim (Tables "Example scene descriptions" and
//! "Two hard descriptions"); the annotations are ours, written from the text with the rules
//! of the data-generation system prompt: categories without attributes (`fridge` + `mini`),
//! one atomic attribute per entry, `_` instead of spaces, anchor index 0 with the anchor first,
//! pairwise relationships written once with a quantity, plurals as `ge,2`, architecture as
//! types only, nothing "on the floor". The medium example is the basement gaming room of the
//! paper's annotation figure. IDs are local to this file.
//!
//! The rows for the generated fixture scenes are written by [`crate::scene_annotations`].

use std::io;
use std::path::Path;

use sceneeval_annotation::{
    AnnotationRow, Annotations, ArchRef, CountSpec, Difficulty, Entry, OaRel, ObjAttr, ObjCount, ObjRef,
    OoRel, Quantifier,
};

/// File name of the paper examples.
pub const PAPER_EXAMPLES_FILE: &str = "paper_examples.csv";
/// File name of the malformed rows.
pub const MALFORMED_FILE: &str = "malformed.csv";
/// The files [`write_all`] writes, in order.
pub const FILES: [&str; 2] = [PAPER_EXAMPLES_FILE, MALFORMED_FILE];

const EQ: Quantifier = Quantifier::Eq;
const GE: Quantifier = Quantifier::Ge;

fn cnt(q: Quantifier, n: u64, category: &str) -> Entry<ObjCount> {
    Entry::Parsed(ObjCount::new(CountSpec::new(q, n), category))
}

fn attr(q: Quantifier, n: u64, category: &str, attribute: &str) -> Entry<ObjAttr> {
    Entry::Parsed(ObjAttr::new(CountSpec::new(q, n), category, attribute))
}

/// An object-object relationship with the anchor first (anchor index 0).
fn oo(q: Quantifier, n: u64, relationship: &str, anchor: &str, others: &[&str]) -> Entry<OoRel> {
    let refs = std::iter::once(anchor)
        .chain(others.iter().copied())
        .map(ObjRef::new)
        .collect();
    Entry::Parsed(OoRel::new(CountSpec::new(q, n), relationship, Some(0), refs))
}

fn oa(q: Quantifier, n: u64, relationship: &str, object: &str, arch: &str) -> Entry<OaRel> {
    Entry::Parsed(OaRel::new(
        CountSpec::new(q, n),
        relationship,
        ObjRef::new(object),
        vec![ArchRef::parse(arch)],
    ))
}

fn row(id: u32, difficulty: Difficulty, description: &str) -> AnnotationRow {
    let mut r = AnnotationRow::new(id.to_string(), difficulty, description);
    r.extra
        .insert("Source".to_owned(), "SceneEval paper (WACV 2026)".to_owned());
    r
}

/// The easy example (paper, Table "Example scene descriptions"): three large objects.
fn easy() -> AnnotationRow {
    let mut r = row(
        0,
        Difficulty::Easy,
        "A simple bedroom featuring a twin bed against the wall, with a wardrobe positioned in the \
         corner of the room, and a desk next to the window.",
    );
    r.obj_count = vec![cnt(EQ, 1, "bed"), cnt(EQ, 1, "wardrobe"), cnt(EQ, 1, "desk")];
    r.obj_attr = vec![attr(EQ, 1, "bed", "twin")];
    r.oa_rel = vec![
        oa(EQ, 1, "against", "bed", "wall"),
        oa(EQ, 1, "corner", "wardrobe", "room"),
        oa(EQ, 1, "next_to", "desk", "window"),
    ];
    r
}

/// The medium example, the basement gaming room of the paper's annotation figure: three large
/// objects (desk, bean bag chair, cabinet) and four small ones (two monitors, fridge, popcorn
/// machine).
fn medium() -> AnnotationRow {
    let mut r = row(
        1,
        Difficulty::Medium,
        "This entertaining basement layout features a large gaming setup with two monitors on a \
         desk against one wall, while a comfy bean bag chair is positioned nearby for casual \
         seating. Across from the gaming area, a small cabinet with a mini fridge and a popcorn \
         machine on top completes the setup.",
    );
    r.obj_count = vec![
        cnt(EQ, 2, "monitor"),
        cnt(EQ, 1, "desk"),
        cnt(EQ, 1, "bean_bag_chair"),
        cnt(EQ, 1, "cabinet"),
        cnt(EQ, 1, "fridge"),
        cnt(EQ, 1, "popcorn_machine"),
    ];
    r.obj_attr = vec![
        attr(EQ, 1, "bean_bag_chair", "comfy"),
        attr(EQ, 1, "cabinet", "small"),
        attr(EQ, 1, "fridge", "mini"),
    ];
    r.oo_rel = vec![
        oo(EQ, 2, "on", "desk", &["monitor"]),
        oo(EQ, 1, "near", "desk", &["bean_bag_chair"]),
        oo(EQ, 1, "across_from", "desk", &["cabinet"]),
        oo(EQ, 1, "on", "cabinet", &["fridge"]),
        oo(EQ, 1, "on", "cabinet", &["popcorn_machine"]),
    ];
    r.oa_rel = vec![oa(EQ, 1, "against", "desk", "wall")];
    r
}

/// The hard example: three rooms, 14 large and 13 small objects (the five plural categories
/// counted as `ge,2`, which gives the paper's 27).
fn hard() -> AnnotationRow {
    let mut r = row(
        2,
        Difficulty::Hard,
        "This cozy bedroom features a full-size bed against a wall with two nightstands on each \
         side where the left one has a small clock. A small desk sits in the corner with a \
         comfortable chair for studying or working. Opposite the bed, a spacious dresser provides \
         additional storage. Adjacent to the bedroom, the living room has a recliner and an ottoman \
         facing a low coffee table with a small vase and magazines. A large bookshelf in the corner \
         holds books and board games, while an wide couch provides space for gatherings. Just off \
         the living room, a small gaming room with a gaming console and two beanbag chairs offers a \
         dedicated space for entertainment, complete with a small shelf for controllers and \
         headsets.",
    );
    r.obj_count = vec![
        cnt(EQ, 1, "bed"),
        cnt(EQ, 2, "nightstand"),
        cnt(EQ, 1, "clock"),
        cnt(EQ, 1, "desk"),
        cnt(EQ, 1, "chair"),
        cnt(EQ, 1, "dresser"),
        cnt(EQ, 1, "recliner"),
        cnt(EQ, 1, "ottoman"),
        cnt(EQ, 1, "coffee_table"),
        cnt(EQ, 1, "vase"),
        cnt(GE, 2, "magazine"),
        cnt(EQ, 1, "bookshelf"),
        cnt(GE, 2, "book"),
        cnt(GE, 2, "board_game"),
        cnt(EQ, 1, "couch"),
        cnt(EQ, 1, "gaming_console"),
        cnt(EQ, 2, "bean_bag_chair"),
        cnt(EQ, 1, "shelf"),
        cnt(GE, 2, "controller"),
        cnt(GE, 2, "headset"),
    ];
    r.obj_attr = vec![
        attr(EQ, 1, "bed", "full_size"),
        attr(EQ, 1, "clock", "small"),
        attr(EQ, 1, "desk", "small"),
        attr(EQ, 1, "chair", "comfortable"),
        attr(EQ, 1, "dresser", "spacious"),
        attr(EQ, 1, "coffee_table", "low"),
        attr(EQ, 1, "vase", "small"),
        attr(EQ, 1, "bookshelf", "large"),
        attr(EQ, 1, "couch", "wide"),
        attr(EQ, 1, "shelf", "small"),
    ];
    r.oo_rel = vec![
        oo(EQ, 1, "left", "bed", &["nightstand"]),
        oo(EQ, 1, "right", "bed", &["nightstand"]),
        oo(EQ, 1, "on", "nightstand", &["clock"]),
        oo(EQ, 1, "near", "desk", &["chair"]),
        oo(EQ, 1, "across_from", "bed", &["dresser"]),
        oo(EQ, 1, "face", "coffee_table", &["recliner"]),
        oo(EQ, 1, "face", "coffee_table", &["ottoman"]),
        oo(EQ, 1, "on", "coffee_table", &["vase"]),
        oo(GE, 2, "on", "coffee_table", &["magazine"]),
        oo(GE, 2, "on", "bookshelf", &["book"]),
        oo(GE, 2, "on", "bookshelf", &["board_game"]),
        oo(GE, 2, "on", "shelf", &["controller"]),
        oo(GE, 2, "on", "shelf", &["headset"]),
    ];
    r.oa_rel = vec![
        oa(EQ, 1, "against", "bed", "wall"),
        oa(EQ, 1, "in", "bed", "bedroom"),
        oa(EQ, 1, "corner", "desk", "bedroom"),
        oa(EQ, 1, "in", "couch", "living_room"),
        oa(EQ, 1, "corner", "bookshelf", "living_room"),
        oa(EQ, 1, "in", "gaming_console", "gaming_room"),
        oa(EQ, 2, "in", "bean_bag_chair", "gaming_room"),
        oa(EQ, 1, "in", "shelf", "gaming_room"),
    ];
    r
}

/// The manually written hard description (paper, Table "Two hard descriptions", top).
fn teenager_bedroom() -> AnnotationRow {
    let mut r = row(
        3,
        Difficulty::Hard,
        "A teenager's bedroom features a comfortable twin bed with a backboard in the far corner, \
         with boxes underneath it. At the foot of the bed is a small desk equipped with a monitor, \
         an external keyboard and mouse, and a desk lamp on the right for visibility, accompanied \
         by a rolling chair. Next to the bed, a nightstand with an additional floor lamp nearby \
         provides space for a phone and other valuables. A sizable wooden wardrobe with multiple \
         drawers offers ample storage for clothes, while a coffee table beside it holds books and \
         board games. In the center of the room, a tan-colored rug creates a cozy spot to sit, and \
         the walls are adorned with various posters and pictures.",
    );
    r.obj_count = vec![
        cnt(EQ, 1, "bed"),
        cnt(GE, 2, "box"),
        cnt(EQ, 1, "desk"),
        cnt(EQ, 1, "monitor"),
        cnt(EQ, 1, "keyboard"),
        cnt(EQ, 1, "mouse"),
        cnt(EQ, 1, "desk_lamp"),
        cnt(EQ, 1, "chair"),
        cnt(EQ, 1, "nightstand"),
        cnt(EQ, 1, "floor_lamp"),
        cnt(EQ, 1, "phone"),
        cnt(EQ, 1, "wardrobe"),
        cnt(EQ, 1, "coffee_table"),
        cnt(GE, 2, "book"),
        cnt(GE, 2, "board_game"),
        cnt(EQ, 1, "rug"),
        cnt(GE, 2, "poster"),
        cnt(GE, 2, "picture"),
    ];
    r.obj_attr = vec![
        attr(EQ, 1, "bed", "comfortable"),
        attr(EQ, 1, "bed", "twin"),
        attr(EQ, 1, "desk", "small"),
        attr(EQ, 1, "keyboard", "external"),
        attr(EQ, 1, "chair", "rolling"),
        attr(EQ, 1, "wardrobe", "sizable"),
        attr(EQ, 1, "wardrobe", "wooden"),
        attr(EQ, 1, "wardrobe", "multi_drawer"),
        attr(EQ, 1, "rug", "tan"),
    ];
    r.oo_rel = vec![
        oo(GE, 2, "under", "bed", &["box"]),
        oo(EQ, 1, "at_the_foot_of", "bed", &["desk"]),
        oo(EQ, 1, "on", "desk", &["monitor"]),
        oo(EQ, 1, "on", "desk", &["keyboard"]),
        oo(EQ, 1, "on", "desk", &["mouse"]),
        oo(EQ, 1, "on", "desk", &["desk_lamp"]),
        oo(EQ, 1, "right", "desk", &["desk_lamp"]),
        oo(EQ, 1, "near", "desk", &["chair"]),
        oo(EQ, 1, "next_to", "bed", &["nightstand"]),
        oo(EQ, 1, "near", "nightstand", &["floor_lamp"]),
        oo(EQ, 1, "on", "nightstand", &["phone"]),
        oo(EQ, 1, "beside", "wardrobe", &["coffee_table"]),
        oo(GE, 2, "on", "coffee_table", &["book"]),
        oo(GE, 2, "on", "coffee_table", &["board_game"]),
    ];
    r.oa_rel = vec![
        oa(EQ, 1, "corner", "bed", "room"),
        oa(EQ, 1, "middle_of", "rug", "room"),
        oa(GE, 2, "on", "poster", "wall"),
        oa(GE, 2, "on", "picture", "wall"),
    ];
    r
}

/// The LLM-generated hard description (paper, Table "Two hard descriptions", bottom). Its
/// description contains `;`, which the reference truncates (a `description-semicolon`
/// warning, the only finding of this file).
fn master_bedroom() -> AnnotationRow {
    let mut r = row(
        4,
        Difficulty::Hard,
        "A luxurious master bedroom features a canopy bed with an upholstered headboard. Two white \
         nightstands stand beside it; one supports a marble table lamp and a photo frame, the other \
         holds a green potted plant and an alarm clock. A tufted bench sits at the foot of the bed. \
         Along one wall, a double-door wardrobe with patterned panels provides storage. Opposite, a \
         wooden vanity desk topped with three metal candlesticks and a decorative tray is paired \
         with an armless cushioned stool. A tall floor plant and a tripod floor lamp flank the desk \
         on the left and right, respectively. Above a low dresser, a wall-mounted mirror reflects a \
         crystal chandelier hanging from the ceiling. A plush area rug covers the floor under the \
         bed.",
    );
    r.obj_count = vec![
        cnt(EQ, 1, "bed"),
        cnt(EQ, 2, "nightstand"),
        cnt(EQ, 1, "table_lamp"),
        cnt(EQ, 1, "photo_frame"),
        cnt(EQ, 1, "potted_plant"),
        cnt(EQ, 1, "alarm_clock"),
        cnt(EQ, 1, "bench"),
        cnt(EQ, 1, "wardrobe"),
        cnt(EQ, 1, "vanity_desk"),
        cnt(EQ, 3, "candlestick"),
        cnt(EQ, 1, "tray"),
        cnt(EQ, 1, "stool"),
        cnt(EQ, 1, "floor_plant"),
        cnt(EQ, 1, "floor_lamp"),
        cnt(EQ, 1, "dresser"),
        cnt(EQ, 1, "mirror"),
        cnt(EQ, 1, "chandelier"),
        cnt(EQ, 1, "rug"),
    ];
    r.obj_attr = vec![
        attr(EQ, 1, "bed", "canopy"),
        attr(EQ, 1, "bed", "upholstered_headboard"),
        attr(EQ, 2, "nightstand", "white"),
        attr(EQ, 1, "table_lamp", "marble"),
        attr(EQ, 1, "potted_plant", "green"),
        attr(EQ, 1, "bench", "tufted"),
        attr(EQ, 1, "wardrobe", "double_door"),
        attr(EQ, 1, "wardrobe", "patterned"),
        attr(EQ, 1, "vanity_desk", "wooden"),
        attr(EQ, 3, "candlestick", "metal"),
        attr(EQ, 1, "tray", "decorative"),
        attr(EQ, 1, "stool", "armless"),
        attr(EQ, 1, "stool", "cushioned"),
        attr(EQ, 1, "floor_plant", "tall"),
        attr(EQ, 1, "floor_lamp", "tripod"),
        attr(EQ, 1, "dresser", "low"),
        attr(EQ, 1, "mirror", "wall_mounted"),
        attr(EQ, 1, "chandelier", "crystal"),
        attr(EQ, 1, "rug", "plush"),
    ];
    r.oo_rel = vec![
        oo(EQ, 2, "beside", "bed", &["nightstand"]),
        oo(EQ, 1, "on", "nightstand", &["table_lamp"]),
        oo(EQ, 1, "on", "nightstand", &["photo_frame"]),
        oo(EQ, 1, "on", "nightstand", &["potted_plant"]),
        oo(EQ, 1, "on", "nightstand", &["alarm_clock"]),
        oo(EQ, 1, "at_the_foot_of", "bed", &["bench"]),
        oo(EQ, 1, "across_from", "wardrobe", &["vanity_desk"]),
        oo(EQ, 3, "on", "vanity_desk", &["candlestick"]),
        oo(EQ, 1, "on", "vanity_desk", &["tray"]),
        oo(EQ, 1, "near", "vanity_desk", &["stool"]),
        oo(EQ, 1, "left", "vanity_desk", &["floor_plant"]),
        oo(EQ, 1, "right", "vanity_desk", &["floor_lamp"]),
        oo(EQ, 1, "above", "dresser", &["mirror"]),
        oo(EQ, 1, "under", "bed", &["rug"]),
    ];
    r.oa_rel = vec![
        oa(EQ, 1, "against", "wardrobe", "wall"),
        oa(EQ, 1, "on", "mirror", "wall"),
        oa(EQ, 1, "hang_from", "chandelier", "ceiling"),
    ];
    r
}

/// The example descriptions of the paper, annotated (see the module docs).
pub fn paper_examples() -> Annotations {
    Annotations::from_rows(vec![
        easy(),
        medium(),
        hard(),
        teenager_bedroom(),
        master_bedroom(),
    ])
}

/// Rows that exercise every validation finding, as CSV text. The `Exercises` column names the
/// finding code(s) each row is written for; a row may raise a few more as a consequence (the
/// ragged row shifts its later cells).
pub fn malformed_rows() -> String {
    MALFORMED.to_owned()
}

const MALFORMED: &str = r#"ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel,Exercises
,easy,A bedroom with a bed.,"eq,1,bed",,,,missing-id
1,easy,A bedroom with a bed.,"eq,1,bed",,,,
1,easy,A second row with the same ID.,"eq,1,sofa",,,,duplicate-id
scene-three,easy,A bedroom with a bed.,"eq,1,bed",,,,non-integer-id
4,expert,A bedroom with a bed.,"eq,1,bed",,,,unknown-difficulty
5,easy,,"eq,1,bed",,,,empty-description
6,easy,A bedroom with a bed; the reference keeps only this first part.,"eq,1,bed",,,,description-semicolon
7,easy,A bedroom with a bed, and a desk.,"eq,1,bed; eq,1,desk",,,,ragged-row
8,easy,A bedroom with a bed.,"EQ,1,bed; more,1,bed",,,,unknown-quantifier
9,easy,A bedroom with two beds.,"eq,two,bed",,,,bad-quantity
10,easy,A round wooden table and a lamp left of a bed.,"eq,1,table; eq,1,bed; eq,1,lamp","eq,1,table,round,wooden","eq,1,left,bed,lamp",,wrong-field-count
11,easy,A bedroom with a bed.,"eq,1,bed; eq,1,",,,"eq,1,against,bed,",empty-name
12,easy,A nightstand left of a bed.,"eq,1,bed; eq,1,nightstand",,"eq,1,left,first,bed,nightstand",,bad-anchor-index
13,easy,Three chairs around a table.,"eq,1,table; eq,3,chair",,"eq,1,surround,0,table,chair:a,chair:b,chair:c",,bad-reference
14,easy,A red sofa and a lamp near a bed.,"eq,1,bed","eq,1,sofa,red","eq,1,near,0,bed,lamp","eq,1,against,desk,wall",undefined-category
15,easy,A desk near the door and two windows.,"eq,1,desk; eq,2,window",,"eq,1,near,0,desk,door",,arch-as-object
16,easy,A nightstand left of a bed.,"eq,1,bed; eq,1,nightstand",,"eq,1,left,14,bed,nightstand",,anchor-out-of-range
17,easy,A round wooden table.,"eq,1,table","eq,1,table,round_wooden",,,non-atomic-attribute
18,easy,A bedroom with a red bed.,"eq,1,bed","eq,1,red,bed",,,attribute-category-swapped
19,easy,A bedroom with a bed.,"eq,1,bed; eq,1,bed",,,"eq,1,against,bed,wall; eq,1,against,bed,wall",duplicate-entry
20,easy,There are no chairs but there is a chair.,"eq,0,chair; ge,1,chair","lt,0,chair,red",,,contradictory-counts
21,easy,Two blue armchairs.,"eq,1,armchair","eq,2,armchair,blue",,,attribute-exceeds-count
22,easy,Two chairs next to a table and three chairs around it.,"eq,1,table; eq,1,chair",,"eq,2,next_to,0,table,chair; eq,1,surround,0,table,chair:0,chair:1,chair:2","eq,2,against,chair,wall",relationship-exceeds-count
23,easy,A painting on the wall and a desk by the window.,"eq,1,painting; eq,1,desk",,,"eq,1,on,painting,wall_1; eq,1,next_to,desk,windw; eq,1,in,desk,spaceship",unknown-arch-reference
24,easy,A king-size bed and a floor lamp.,"eq,1,bed; eq,1,floor lamp","eq,1,bed,king-size",,,name-format
25,easy,Six chairs.,"eq,6,chair",,,,difficulty-object-count
"#;

/// Writes [`PAPER_EXAMPLES_FILE`] and [`MALFORMED_FILE`] into `dir` (which must exist).
///
/// # Errors
/// The IO error of a file that cannot be written.
pub fn write_all(dir: &Path) -> io::Result<()> {
    paper_examples()
        .write_csv(dir.join(PAPER_EXAMPLES_FILE))
        .map_err(io::Error::other)?;
    std::fs::write(dir.join(MALFORMED_FILE), malformed_rows())
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_annotation::{FindingCode, Severity};

    #[test]
    fn paper_examples_have_no_errors() {
        let a = paper_examples();
        let findings = a.validate();
        let codes: Vec<(String, FindingCode)> = findings.iter().map(|f| (f.row.clone(), f.code)).collect();
        // The only finding: the master bedroom's description has a `;` (Q24).
        assert_eq!(codes, vec![("4".to_owned(), FindingCode::DescriptionSemicolon)]);
        assert!(findings.iter().all(|f| f.severity == Severity::Warning));
    }

    /// The object totals the paper gives for its examples (Table "Example scene descriptions"
    /// caption): easy 3 large; medium 3 large + 4 small = 7; hard 14 large + 13 small = 27.
    #[test]
    fn paper_examples_match_the_captions() {
        let a = paper_examples();
        let objects: Vec<u64> = a.rows.iter().map(|r| r.objects_specified()).collect();
        assert_eq!(objects[..3], [3, 7, 27]);
        // Both Table "Two hard descriptions" rows are hard: at least nine objects.
        assert!(objects[3] >= 9 && objects[4] >= 9, "{objects:?}");
    }

    #[test]
    fn malformed_rows_raise_every_finding() {
        let a = Annotations::from_csv_str(&malformed_rows()).unwrap();
        let findings = a.validate();
        for code in FindingCode::ALL {
            assert!(findings.iter().any(|f| f.code == *code), "no {code} finding");
        }
        // Each row raises the finding its `Exercises` column names.
        for (i, row) in a.rows.iter().enumerate() {
            let Some(label) = row.extra.get("Exercises") else {
                continue;
            };
            for code in label.split(' ') {
                assert!(
                    findings
                        .iter()
                        .any(|f| f.row_index == i && f.code.as_str() == code),
                    "row {i} ({:?}) does not raise {code}",
                    row.id
                );
            }
        }
        // The ragged row's label is pushed beyond the header.
        let ragged = a.get("7").unwrap();
        assert_eq!(ragged.overflow, vec!["ragged-row"]);
    }

    #[test]
    fn written_files_read_back() {
        let dir = tempfile::tempdir().unwrap();
        write_all(dir.path()).unwrap();
        let paper = Annotations::read_csv(dir.path().join(PAPER_EXAMPLES_FILE)).unwrap();
        assert_eq!(paper, paper_examples());
        let malformed = std::fs::read_to_string(dir.path().join(MALFORMED_FILE)).unwrap();
        assert_eq!(malformed, malformed_rows());
        // Malformed entries and the ragged row's extra cell survive a write and a read.
        let a = Annotations::from_csv_str(&malformed).unwrap();
        assert_eq!(Annotations::from_csv_str(&a.to_csv_string().unwrap()).unwrap(), a);
    }
}
