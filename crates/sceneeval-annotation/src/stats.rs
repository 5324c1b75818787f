//! Dataset statistics in the layout of the paper's Table 1.

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use crate::Annotations;
use crate::row::{AnnotationRow, Difficulty};

/// Per-difficulty averages per scene, as in the paper's Table 1 (Scenes, Words, Obj,
/// ObjCount, ObjAttr, OORel, OARel).
///
/// Definitions (per scene, then averaged over the scenes of the group):
/// - **Words**: runs of non-whitespace characters in the description.
/// - **Obj** (objects specified): the sum over the parsed `ObjCount` entries of the count
///   the entry names, [`crate::CountSpec::nominal`]: `eq,n`, `ge,n` and `le,n` count n,
///   `gt,n` counts n+1, `lt,n` counts n-1, so `eq,0` (an absent object) counts 0. The paper's
///   hard example "specifies 14 large and 13 small objects" with five plural categories, which
///   this definition reproduces when plurals are written `ge,2`.
/// - **ObjCount, ObjAttr, OORel, OARel**: entries in the field as written, malformed and
///   repeated entries included (the file's size, not what the reference would score).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    /// One group per difficulty present: easy, medium, hard, then any other labels (sorted),
    /// then `all`.
    pub groups: Vec<GroupStats>,
}

/// Averages per scene over the rows of one difficulty.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GroupStats {
    /// `easy`, `medium`, `hard`, another label found in the file, or `all`.
    pub difficulty: String,
    /// Number of scenes (rows).
    pub scenes: usize,
    /// Mean words per description.
    pub words: f64,
    /// Mean objects specified.
    pub objects: f64,
    /// Mean `ObjCount` entries.
    pub obj_count: f64,
    /// Mean `ObjAttr` entries.
    pub obj_attr: f64,
    /// Mean `OORel` entries.
    pub oo_rel: f64,
    /// Mean `OARel` entries.
    pub oa_rel: f64,
}

impl GroupStats {
    fn of<'a>(difficulty: &str, rows: impl Iterator<Item = &'a AnnotationRow>) -> Option<GroupStats> {
        // Sums are exact integers (u64 -> f64 is exact below 2^53); one division at the end,
        // so the result does not depend on row order.
        let mut n = 0usize;
        let mut sums = [0u64; 6];
        for r in rows {
            n += 1;
            let values = [
                r.word_count() as u64,
                r.objects_specified(),
                r.obj_count.len() as u64,
                r.obj_attr.len() as u64,
                r.oo_rel.len() as u64,
                r.oa_rel.len() as u64,
            ];
            for (s, v) in sums.iter_mut().zip(values) {
                *s = s.saturating_add(v);
            }
        }
        if n == 0 {
            return None;
        }
        let mean = |i: usize| sums[i] as f64 / n as f64;
        Some(GroupStats {
            difficulty: difficulty.to_owned(),
            scenes: n,
            words: mean(0),
            objects: mean(1),
            obj_count: mean(2),
            obj_attr: mean(3),
            oo_rel: mean(4),
            oa_rel: mean(5),
        })
    }
}

impl Stats {
    /// The statistics of a file.
    pub fn of(annotations: &Annotations) -> Stats {
        let rows = &annotations.rows;
        let mut groups = Vec::new();
        for level in Difficulty::LEVELS {
            groups.extend(GroupStats::of(
                level.as_str(),
                rows.iter().filter(|r| r.difficulty == level),
            ));
        }
        let mut others: Vec<&str> = rows
            .iter()
            .filter_map(|r| match &r.difficulty {
                Difficulty::Other(s) => Some(s.as_str()),
                _ => None,
            })
            .collect();
        others.sort_unstable();
        others.dedup();
        for label in others {
            let rows = rows
                .iter()
                .filter(|r| matches!(&r.difficulty, Difficulty::Other(s) if s == label));
            let name = if label.is_empty() { "(none)" } else { label };
            groups.extend(GroupStats::of(name, rows));
        }
        groups.extend(GroupStats::of("all", rows.iter()));
        Stats { groups }
    }

    /// A Markdown table in the paper's layout, two decimals.
    pub fn to_markdown(&self) -> String {
        let mut s = String::from(
            "| Difficulty | Scenes | Words | Obj | ObjCount | ObjAttr | OORel | OARel |\n\
             |---|---:|---:|---:|---:|---:|---:|---:|\n",
        );
        for g in &self.groups {
            // Writing to a String cannot fail.
            let _ = writeln!(
                s,
                "| {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |",
                capitalise(&g.difficulty),
                g.scenes,
                g.words,
                g.objects,
                g.obj_count,
                g.obj_attr,
                g.oo_rel,
                g.oa_rel
            );
        }
        s
    }
}

fn capitalise(s: &str) -> String {
    let mut chars = s.chars();
    match chars.next() {
        Some(c) => c.to_uppercase().chain(chars).collect(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_computed_table() {
        let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
            0,easy,A bed and two nightstands.,\"eq,1,bed; eq,2,nightstand\",\"eq,1,bed,large\",\"eq,1,left,0,bed,nightstand\",\n\
            1,easy,No sofa here.,\"eq,0,sofa; gt,1,chair\",,,\"eq,1,against,chair,wall\"\n\
            2,hard,\"Lots of books, a desk.\",\"ge,2,book; eq,1,desk; x\",,,\n\
            3,weird,A lamp.,\"eq,1,lamp\",,,\n";
        let s = Stats::of(&Annotations::from_csv_str(csv).unwrap());
        let labels: Vec<&str> = s.groups.iter().map(|g| g.difficulty.as_str()).collect();
        assert_eq!(labels, ["easy", "hard", "weird", "all"]);
        let easy = &s.groups[0];
        assert_eq!(easy.scenes, 2);
        // Words: 5 ("A bed and two nightstands.") + 3 ("No sofa here.") = 8 -> 4.0.
        assert_eq!(easy.words, 4.0);
        // Obj: (1 + 2) + (0 + 2) = 5 -> 2.5 (gt,1 counts 2; eq,0 counts 0).
        assert_eq!(easy.objects, 2.5);
        // ObjCount entries 2 + 2 -> 2.0; ObjAttr 1 + 0 -> 0.5; OORel 1 + 0; OARel 0 + 1.
        assert_eq!(
            (easy.obj_count, easy.obj_attr, easy.oo_rel, easy.oa_rel),
            (2.0, 0.5, 0.5, 0.5)
        );
        // Hard: the malformed "x" counts as an entry but not as objects: 2 + 1 = 3 objects.
        let hard = &s.groups[1];
        assert_eq!(
            (hard.scenes, hard.words, hard.objects, hard.obj_count),
            (1, 5.0, 3.0, 3.0)
        );
        let all = &s.groups[3];
        assert_eq!(all.scenes, 4);
        // Words 5 + 3 + 5 + 2 = 15 -> 3.75; objects 3 + 2 + 3 + 1 = 9 -> 2.25.
        assert_eq!((all.words, all.objects), (3.75, 2.25));
        let md = s.to_markdown();
        assert!(
            md.contains("| Easy | 2 | 4.00 | 2.50 | 2.00 | 0.50 | 0.50 | 0.50 |"),
            "{md}"
        );
        assert!(md.contains("| All | 4 | 3.75 | 2.25 |"), "{md}");
    }

    #[test]
    fn empty_file() {
        let s = Stats::of(&Annotations::new());
        assert!(s.groups.is_empty());
        assert_eq!(s.to_markdown().lines().count(), 2);
    }
}
