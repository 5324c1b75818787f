//! One line of `sceneeval relate`'s input answered: parsed once into borrowed, typed fields
//! ([`crate::line`]; a query by name through a scanner of its own, every other line through
//! serde_json), asked of a [`Session`], and the answer line written ([`write_answer`]). The
//! format (schema version [`SCHEMA_VERSION`]) is documented in `docs/formats.md`
//! ("`sceneeval relate` JSON lines"); the front end only frames the stream (reading lines,
//! numbering them, flushing).
//!
//! ```
//! use sceneeval_relate::{Session, answer_line};
//! use sceneeval_relations::RelationParams;
//! use sceneeval_io::AssetLibrary;
//! let mut session = Session::new(RelationParams::default(), AssetLibrary::new(), 8);
//! let line = r#"{"id":1,"relation":"near","target":{"center":[0,0,0.3],"half_size":[0.3,0.3,0.3]},
//!               "anchor":{"center":[1.2,0,0.3],"half_size":[0.3,0.3,0.3]}}"#;
//! let mut out = Vec::new();
//! sceneeval_relate::write_answer(&mut out, &answer_line(line, 1, &mut session)).unwrap();
//! assert_eq!(String::from_utf8(out).unwrap(), "{\"id\":1,\"score\":1.0,\"holds\":true}\n");
//! ```

use std::io::{self, Write};

use sceneeval_geom::Real;
use serde::Serialize;

use crate::flat;
use crate::line::{DeclareOnly, IdOnly, Line, LineKind, RawText};
use crate::{Session, error_path};

/// The only line-schema version this build understands.
pub const SCHEMA_VERSION: u64 = 1;

/// One answer line: `{"id", "score", "holds"}`, `{"id", "declared"}` or `{"id", "error"}`.
/// The id is the line's JSON text, echoed byte for byte (a 30-digit integer stays a 30-digit
/// integer).
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum Answer<'a> {
    /// A query's score and whether the relation holds.
    Score {
        /// The line's id.
        id: RawText<'a>,
        /// The score, in [0, 1].
        score: Real,
        /// Whether the score passes the threshold.
        holds: bool,
    },
    /// A declaration's name.
    Declared {
        /// The line's id.
        id: RawText<'a>,
        /// The name declared.
        declared: String,
    },
    /// Why the line could not be answered.
    Error {
        /// The line's id, `null` when it could not be read.
        id: RawText<'a>,
        /// What is wrong.
        error: String,
    },
}

/// Writes `answer` and a newline. A score, the answer of almost every line, is written field by
/// field (the id's raw text, the score as serde_json writes a number): the same bytes as
/// serialising the enum, at a fifth of the cost.
pub fn write_answer(out: &mut impl Write, answer: &Answer<'_>) -> io::Result<()> {
    match answer {
        Answer::Score { id, score, holds } => {
            out.write_all(b"{\"id\":")?;
            out.write_all(id.0.as_bytes())?;
            out.write_all(b",\"score\":")?;
            serde_json::to_writer(&mut *out, score)?;
            out.write_all(if *holds {
                b",\"holds\":true}\n"
            } else {
                b",\"holds\":false}\n"
            })
        }
        other => {
            serde_json::to_writer(&mut *out, other)?;
            out.write_all(b"\n")
        }
    }
}

impl<'a> Answer<'a> {
    /// The error answer of the line with `id`.
    pub fn error(id: RawText<'a>, error: impl Into<String>) -> Self {
        Answer::Error {
            id,
            error: error.into(),
        }
    }
}

/// The id of a line that did not parse as a whole, verbatim, or `null`.
fn raw_id(text: &str) -> RawText<'_> {
    match serde_json::from_str::<IdOnly<'_>>(text) {
        Ok(IdOnly { id: Some(id) }) => id,
        _ => RawText::NULL,
    }
}

/// The line in `text` (one JSON object), built in the caller's `slot` (a line is a few hundred
/// bytes: it is not moved once per call): through the fast scanner ([`flat::read`]) when it is
/// a flat object of plain strings and integers, else through serde_json, whose errors are the
/// answer's.
#[inline]
fn parse_line<'a, 's>(text: &'a str, slot: &'s mut Option<Line<'a>>) -> serde_json::Result<&'s Line<'a>> {
    let line = slot.insert(Line::default());
    if flat::read(text, line).is_none() {
        *line = serde_json::from_str(text)?;
    }
    Ok(line)
}

/// The error answer of a line that serde_json could not read as a [`Line`]: `invalid JSON`
/// when the text is not JSON, else `invalid query` with the path of the key at fault
/// (`target.half_size`, `targets[1].center`) and, for a declaration, its name.
fn unreadable(text: &str, e: &serde_json::Error) -> String {
    if !e.is_data() && serde_json::from_str::<serde::de::IgnoredAny>(text).is_err() {
        return format!("invalid JSON: {e}");
    }
    let path = error_path::<Line<'_>>(text).unwrap_or_default();
    let declared = serde_json::from_str::<DeclareOnly<'_>>(text)
        .ok()
        .and_then(|d| d.declare)
        .and_then(|raw| serde_json::from_str::<String>(raw.get()).ok());
    match (declared, path.is_empty()) {
        (Some(name), false) => format!("invalid declaration of {name:?}: {path}: {e}"),
        (Some(name), true) => format!("invalid declaration of {name:?}: {e}"),
        (None, false) => format!("invalid query: {path}: {e}"),
        (None, true) => format!("invalid query: {e}"),
    }
}

/// Answers one non-blank line (line `number` of the input; a failed declaration names it).
pub fn answer_line<'t>(text: &'t str, number: usize, session: &mut Session) -> Answer<'t> {
    // Checked first: serde would also read a struct from an array of its fields.
    if !text.trim_ascii_start().starts_with('{') {
        return match serde_json::from_str::<serde::de::IgnoredAny>(text) {
            Ok(_) => Answer::error(RawText::NULL, "a line must be a JSON object"),
            Err(e) => Answer::error(RawText::NULL, format!("invalid JSON: {e}")),
        };
    }
    let mut slot = None;
    let line = match parse_line(text, &mut slot) {
        Ok(line) => line,
        // The line may be well-formed JSON whose id can be read even when the rest cannot be
        // converted (for example a number too large for a double elsewhere).
        Err(e) => return Answer::error(raw_id(text), unreadable(text, &e)),
    };
    let id = line.id.unwrap_or(RawText::NULL);
    if let Some(version) = line.version
        && version.0 != "1"
    {
        return Answer::error(
            id,
            format!(
                "unsupported schema version {} (this build reads version {SCHEMA_VERSION})",
                version.0
            ),
        );
    }
    let declared = |name: &str| Answer::Declared {
        id,
        declared: name.to_owned(),
    };
    let answer = match line.kind() {
        Ok(LineKind::Query(query)) => session.score(&query).map(|score| Answer::Score {
            id,
            score,
            holds: session.holds(score),
        }),
        Ok(LineKind::DeclareObject(name, object)) => session
            .declare_object(name, object, number)
            .map(|()| declared(name)),
        Ok(LineKind::DeclareRoom(name, room)) => {
            session.declare_room(name, room, number).map(|()| declared(name))
        }
        Err(e) => return Answer::error(id, e),
    };
    answer.unwrap_or_else(|e| Answer::error(id, e.to_string()))
}

#[cfg(test)]
mod tests {
    use sceneeval_io::AssetLibrary;
    use sceneeval_relations::RelationParams;
    use serde_json::Value;

    use super::*;

    fn session() -> Session {
        Session::new(RelationParams::default(), AssetLibrary::new(), 8)
    }

    fn answer(line: &str) -> Value {
        serde_json::to_value(answer_line(line, 1, &mut session())).unwrap()
    }

    #[test]
    fn answers_and_errors_have_the_documented_keys() {
        let ok = answer(
            r#"{"id":"q1","relation":"on_top","target":{"center":[0,0,1.1],"half_size":[0.1,0.1,0.1],"yaw":0},
                "anchor":{"center":[0,0,0.5],"half_size":[0.5,0.5,0.5],"yaw":0}}"#,
        );
        assert_eq!(ok, serde_json::json!({"id": "q1", "score": 1.0, "holds": true}));
        let bad = answer(r#"{"id":7,"relation":"beside"}"#);
        assert_eq!(bad["id"], 7);
        assert!(
            bad["error"].as_str().unwrap().contains("unknown relation"),
            "{bad}"
        );
        let broken = answer("{not json");
        assert_eq!(broken["id"], Value::Null);
        assert!(
            broken["error"].as_str().unwrap().starts_with("invalid JSON"),
            "{broken}"
        );
        let array = answer("[1, 2]");
        assert_eq!(array["error"], "a line must be a JSON object");
        let declared =
            answer(r#"{"id":"d","declare":"bed","object":{"center":[0,0,0.3],"half_size":[0.8,1,0.3]}}"#);
        assert_eq!(declared, serde_json::json!({"id": "d", "declared": "bed"}));
    }

    #[test]
    fn ids_are_echoed_verbatim() {
        for id in [
            "123456789012345678901234567890",
            "-0.10000000000000000000001",
            "1e400",
            r#""caf\u00e9""#,
            r#"{"run": 3, "k": [1, 2.50]}"#,
        ] {
            let line = format!(r#"{{"id":{id},"relation":"beside"}}"#);
            let out = serde_json::to_string(&answer_line(&line, 1, &mut session())).unwrap();
            assert!(out.starts_with(&format!(r#"{{"id":{id},"error":"#)), "{out}");
        }
    }

    #[test]
    fn answers_are_written_as_serialising_them_writes_them() {
        let ids = [
            "0",
            "-12",
            "1e400",
            r#""caf\u00e9""#,
            r#"{"run": 3, "k": [1, 2.50]}"#,
            "null",
        ];
        let scores = [
            0.0,
            -0.0,
            1.0,
            0.1,
            1.0 / 3.0,
            5e-324,
            1e-7,
            123456789.0,
            f64::NAN,
        ];
        for id in ids {
            let id = RawText(id);
            for score in scores {
                for holds in [false, true] {
                    let answer = Answer::Score { id, score, holds };
                    let mut written = Vec::new();
                    write_answer(&mut written, &answer).unwrap();
                    let mut expected = serde_json::to_vec(&answer).unwrap();
                    expected.push(b'\n');
                    assert_eq!(
                        String::from_utf8(written).unwrap(),
                        String::from_utf8(expected).unwrap()
                    );
                }
            }
            for answer in [
                Answer::error(id, "line 3: \"quoted\" and \u{1} escaped"),
                Answer::Declared {
                    id,
                    declared: "bed".into(),
                },
            ] {
                let mut written = Vec::new();
                write_answer(&mut written, &answer).unwrap();
                let mut expected = serde_json::to_vec(&answer).unwrap();
                expected.push(b'\n');
                assert_eq!(written, expected);
            }
        }
    }

    #[test]
    fn room_names_with_and_without_escapes() {
        let mut s = session();
        let room = r#"{"floor":[[0,0],[4,0],[4,5],[0,5]]}"#;
        let target = r#"{"center":[2,2,0.3],"half_size":[0.5,0.5,0.3]}"#;
        for name in ["bedroom", "b\\u00e9d", "say \\\"hi\\\""] {
            let declared = serde_json::to_value(answer_line(
                &format!(r#"{{"id":1,"declare":"{name}","room":{room}}}"#),
                1,
                &mut s,
            ))
            .unwrap();
            assert!(declared.get("declared").is_some(), "{name}: {declared}");
            let scored = serde_json::to_value(answer_line(
                &format!(r#"{{"id":2,"relation":"inside_room","target":{target},"room":"{name}"}}"#),
                2,
                &mut s,
            ))
            .unwrap();
            assert_eq!(scored["score"], 1.0, "{name}: {scored}");
        }
        // "b\u00e9d" and "béd" are one name.
        let scored = serde_json::to_value(answer_line(
            &format!(r#"{{"id":3,"relation":"inside_room","target":{target},"room":"béd"}}"#),
            3,
            &mut s,
        ))
        .unwrap();
        assert_eq!(scored["score"], 1.0, "{scored}");
    }
}
