//! An entry in plain English, for a person who judges whether a scene satisfies it
//! (`sceneeval judge`): `eq,2,next_to,0,bed,nightstand` is "2 nightstands next to the bed".
//!
//! The rules, kept simple and stated here: the count reads `eq,n` "n" (`eq,0` "no"), `ge,n`
//! "at least n", `gt,n` "more than n", `le,n` "at most n", `lt,n` "fewer than n"; a category
//! or relationship has its `_` read as spaces; a category is plural unless the quantity is 1,
//! made plural by English's regular rules (`-s`; `-es` after s, x, z, ch, sh; consonant + y
//! to `-ies`; `-lf` to `-lves`), which irregular nouns do not follow; a reference `chair:1`
//! reads "chair 1". A malformed entry reads as written.

use crate::{CountSpec, Entry, EntryKind, OaRel, ObjAttr, ObjCount, ObjRef, OoRel, Quantifier};

/// An entry in plain English ([`crate::words`] states the rules).
pub trait InWords {
    /// The entry in words.
    fn in_words(&self) -> String;
}

/// `text` parsed as an entry of kind `T`, in words; a malformed entry as written.
///
/// ```
/// use sceneeval_annotation::{OoRel, words::entry_in_words};
/// assert_eq!(entry_in_words::<OoRel>("eq,2,next_to,0,bed,nightstand"), "2 nightstands next to the bed");
/// assert_eq!(entry_in_words::<OoRel>("not,an,entry"), "not,an,entry");
/// ```
pub fn entry_in_words<T: EntryKind + InWords>(text: &str) -> String {
    match Entry::<T>::parse(text) {
        Entry::Parsed(entry) => entry.in_words(),
        Entry::Malformed(m) => m.text().to_owned(),
    }
}

/// `eq,2` as "2", `ge,1` as "at least 1", `eq,0` as "no".
fn count(c: &CountSpec) -> String {
    let n = c.quantity;
    match c.quantifier {
        Quantifier::Eq if n == 0 => "no".to_owned(),
        Quantifier::Eq => n.to_string(),
        Quantifier::Ge => format!("at least {n}"),
        Quantifier::Gt => format!("more than {n}"),
        Quantifier::Le => format!("at most {n}"),
        Quantifier::Lt => format!("fewer than {n}"),
    }
}

/// `floor_lamp` as "floor lamp".
fn spaced(name: &str) -> String {
    name.replace('_', " ").trim().to_owned()
}

/// The plural of `noun` by English's regular rules (of its last word).
fn plural(noun: &str) -> String {
    let lower = noun.to_ascii_lowercase();
    let consonant_y = lower.ends_with('y')
        && lower
            .chars()
            .rev()
            .nth(1)
            .is_some_and(|c| c.is_ascii_alphabetic() && !"aeiou".contains(c));
    if consonant_y {
        format!("{}ies", &noun[..noun.len() - 1])
    } else if lower.ends_with("lf") {
        format!("{}ves", &noun[..noun.len() - 1])
    } else if ["s", "x", "z", "ch", "sh"].iter().any(|e| lower.ends_with(e)) {
        format!("{noun}es")
    } else {
        format!("{noun}s")
    }
}

/// `n` of a category: singular when the quantity is 1.
fn counted(c: &CountSpec, category: &str) -> String {
    let noun = spaced(category);
    if c.quantity == 1 {
        format!("{} {noun}", count(c))
    } else {
        format!("{} {}", count(c), plural(&noun))
    }
}

/// `chair:1` as "chair 1".
fn reference(r: &ObjRef) -> String {
    match r.instance {
        Some(k) => format!("{} {k}", spaced(&r.category)),
        None => spaced(&r.category),
    }
}

/// "a", "a and b", "a, b and c".
fn listed(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

impl InWords for ObjCount {
    /// `eq,2,chair`: "2 chairs".
    fn in_words(&self) -> String {
        counted(&self.count, &self.category)
    }
}

impl InWords for ObjAttr {
    /// `eq,1,bed,red`: "1 red bed".
    fn in_words(&self) -> String {
        let attribute = spaced(&self.attribute);
        let noun = spaced(&self.category);
        let noun = if self.count.quantity == 1 {
            noun
        } else {
            plural(&noun)
        };
        format!("{} {attribute} {noun}", count(&self.count))
    }
}

impl InWords for OoRel {
    /// `eq,2,next_to,0,bed,nightstand`: "2 nightstands next to the bed";
    /// `eq,1,surround,0,table,chair:0,chair:1`: "1 group of chair 0 and chair 1 surround the
    /// table"; without an anchor (`-1`): "1 group of desk and chair: next to each other".
    fn in_words(&self) -> String {
        let relationship = spaced(&self.relationship);
        let groups = |c: &CountSpec| format!("{} group{}", count(c), if c.quantity == 1 { "" } else { "s" });
        match self.anchor_ref() {
            Some(anchor) => {
                let others: Vec<&ObjRef> = self
                    .refs
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| Some(*k) != self.anchor)
                    .map(|(_, r)| r)
                    .collect();
                let anchor = reference(anchor);
                match others.as_slice() {
                    [one] if one.instance.is_none() => {
                        format!(
                            "{} {relationship} the {anchor}",
                            counted(&self.count, &one.category)
                        )
                    }
                    _ => {
                        let names: Vec<String> = others.iter().map(|r| reference(r)).collect();
                        format!(
                            "{} of {} {relationship} the {anchor}",
                            groups(&self.count),
                            listed(&names)
                        )
                    }
                }
            }
            None => {
                let names: Vec<String> = self.refs.iter().map(reference).collect();
                format!("{} of {}: {relationship}", groups(&self.count), listed(&names))
            }
        }
    }
}

impl InWords for OaRel {
    /// `gt,2,against,bookshelf,wall`: "more than 2 bookshelves against the wall".
    fn in_words(&self) -> String {
        let arch: Vec<String> = self.arch.iter().map(|a| spaced(a.as_str())).collect();
        let object = match self.object.instance {
            Some(_) => format!("{} {}", count(&self.count), reference(&self.object)),
            None => counted(&self.count, &self.object.category),
        };
        format!("{object} {} the {}", spaced(&self.relationship), listed(&arch))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_in_words() {
        let cases: [(&str, String); 4] = [
            ("eq,2,nightstand", entry_in_words::<ObjCount>("eq,2,nightstand")),
            ("eq,0,floor_lamp", entry_in_words::<ObjCount>("eq,0,floor_lamp")),
            ("ge,1,bookshelf", entry_in_words::<ObjCount>("ge,1,bookshelf")),
            ("lt,3,box", entry_in_words::<ObjCount>("lt,3,box")),
        ];
        let expected = [
            "2 nightstands",
            "no floor lamps",
            "at least 1 bookshelf",
            "fewer than 3 boxes",
        ];
        for ((text, words), want) in cases.iter().zip(expected) {
            assert_eq!(words, want, "{text}");
        }
        assert_eq!(entry_in_words::<ObjAttr>("eq,1,bed,red"), "1 red bed");
        assert_eq!(
            entry_in_words::<ObjAttr>("ge,2,chair,dark_wooden"),
            "at least 2 dark wooden chairs"
        );
        assert_eq!(
            entry_in_words::<OoRel>("eq,2,next_to,0,bed,nightstand"),
            "2 nightstands next to the bed"
        );
        assert_eq!(
            entry_in_words::<OoRel>("eq,1,surround,0,table,chair:0,chair:1,chair:2"),
            "1 group of chair 0, chair 1 and chair 2 surround the table"
        );
        assert_eq!(
            entry_in_words::<OoRel>("eq,1,face,1,sofa,tv_stand"),
            "1 sofa face the tv stand"
        );
        assert_eq!(
            entry_in_words::<OoRel>("eq,2,next_to,-1,desk,chair"),
            "2 groups of desk and chair: next to"
        );
        assert_eq!(
            entry_in_words::<OaRel>("gt,2,against,bookshelf,wall"),
            "more than 2 bookshelves against the wall"
        );
        assert_eq!(
            entry_in_words::<OaRel>("eq,1,between,bed,window,door"),
            "1 bed between the window and door"
        );
        // Malformed entries read as written.
        assert_eq!(entry_in_words::<ObjCount>("two,chairs"), "two,chairs");
    }

    #[test]
    fn regular_plurals() {
        for (one, many) in [
            ("chair", "chairs"),
            ("shelf", "shelves"),
            ("bench", "benches"),
            ("dish", "dishes"),
            ("vase", "vases"),
            ("armchair", "armchairs"),
            ("toy", "toys"),
            ("library", "libraries"),
            ("floor lamp", "floor lamps"),
        ] {
            assert_eq!(plural(one), many);
        }
    }
}
