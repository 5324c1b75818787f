//! Every relationship word of the real SceneEval-500 single-room CSV is in the lexicon.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use sceneeval_annotation::{Annotations, ArchRef};
use sceneeval_fidelity::lexicon::{Lookup, map_arch, map_object};

/// The CSV beside the repository, unless `SCENEEVAL500_CSV` names it.
const CSV: &str = "../../../shared/data/sceneeval500-single-room.csv";

/// Reads the real CSV (not part of the repository), so it is ignored by default: run it with
/// `SCENEEVAL500_CSV=/path/to/sceneeval500-single-room.csv cargo test -p sceneeval-fidelity
/// --test lexicon_csv -- --ignored`. It fails, naming the path, when the file is absent.
#[test]
#[ignore = "needs the SceneEval-500 CSV (SCENEEVAL500_CSV), outside the repository"]
fn every_relationship_word_of_the_real_csv_is_covered() {
    let path = match std::env::var_os("SCENEEVAL500_CSV") {
        Some(p) => std::path::PathBuf::from(p),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join(CSV),
    };
    let annotations = Annotations::read_csv(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut words = 0;
    for row in &annotations.rows {
        for r in row.oo_rels() {
            words += 1;
            assert!(
                !matches!(map_object(&r.relationship), Lookup::Unknown),
                "row {}: {:?} is not in the object lexicon",
                row.id,
                r.relationship
            );
        }
        for r in row.oa_rels() {
            words += 1;
            let class = r.arch.iter().find_map(ArchRef::element).expect("a known element");
            assert!(
                matches!(map_arch(&r.relationship, class), Lookup::Mapped { .. }),
                "row {}: {:?} with {class:?} is not mapped",
                row.id,
                r.relationship
            );
        }
    }
    assert!(words > 500, "{words} relationships read");
}
