//! `sceneeval relate`: answers spatial-relation queries given as JSON lines, one answer line
//! per query line, so that any language can use the predicates.
//!
//! The line schema (version 1) is documented in `docs/formats.md` ("`sceneeval relate` JSON
//! lines"). A line that cannot be answered gets `{"id": ..., "error": "..."}` (the id when it
//! could be read, else `null`) and processing goes on. Blank lines are skipped. Exit status: 0
//! when every query was answered with a score, 2 when some line got an error answer, 1 when
//! the input could not be read at all.

use std::fs::File;
use std::io::{self, BufRead, BufReader, BufWriter, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use sceneeval::geom::Real;
use sceneeval::relations::RelationParams;
use sceneeval::relations::spec::QuerySpec;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use serde_json::value::RawValue;

/// The only line-schema version this build understands.
pub const SCHEMA_VERSION: u64 = 1;

/// Arguments of `sceneeval relate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Read queries from this file instead of standard input (one JSON object per line).
    #[arg(long, short, value_name = "FILE")]
    pub input: Option<PathBuf>,
    /// Use the reference implementation's behaviour where it differs from the paper
    /// (`on_top` from the centre plane, `surround` with the median, `corner_of_room` from mean
    /// directions, `middle_of_room` from the bounds centre, distances from the smaller box).
    #[arg(long)]
    pub reference: bool,
}

/// Runs the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let params = if args.reference {
        RelationParams::reference()
    } else {
        RelationParams::default()
    };
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let failed = match &args.input {
        Some(path) => {
            let file = File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
            answer_all(BufReader::new(file), &mut out, &params)
                .with_context(|| format!("reading {}", path.display()))?
        }
        None => answer_all(io::stdin().lock(), &mut out, &params).context("reading standard input")?,
    };
    Ok(if failed == 0 {
        ExitCode::SUCCESS
    } else {
        tracing::warn!(failed, "some queries could not be answered");
        ExitCode::from(2)
    })
}

/// Answers every line of `input`; returns how many lines got an error answer. Each answer is
/// flushed at once, so a client can write one query and wait for its answer.
fn answer_all(
    mut input: impl BufRead,
    out: &mut impl Write,
    params: &RelationParams,
) -> anyhow::Result<usize> {
    let mut failed = 0;
    let mut line = Vec::new();
    let mut number = 0usize;
    loop {
        line.clear();
        if input.read_until(b'\n', &mut line)? == 0 {
            break;
        }
        number += 1;
        let answer = match std::str::from_utf8(&line) {
            Ok(text) if text.trim().is_empty() => continue,
            Ok(text) => answer_line(text, params),
            Err(e) => Answer::error(null_id(), format!("line {number}: not UTF-8: {e}")),
        };
        let answer = match answer {
            Answer::Error { id, error } => {
                failed += 1;
                Answer::Error {
                    id,
                    error: if error.starts_with("line ") {
                        error
                    } else {
                        format!("line {number}: {error}")
                    },
                }
            }
            ok => ok,
        };
        serde_json::to_writer(&mut *out, &answer)?;
        out.write_all(b"\n")?;
        out.flush()?;
    }
    Ok(failed)
}

/// One answer line: `{"id", "score", "holds"}` or `{"id", "error"}`. The id is the query's
/// JSON text, echoed byte for byte (a 30-digit integer stays a 30-digit integer).
#[derive(Debug, Serialize)]
#[serde(untagged)]
enum Answer {
    Score {
        id: Box<RawValue>,
        score: Real,
        holds: bool,
    },
    Error {
        id: Box<RawValue>,
        error: String,
    },
}

impl Answer {
    fn error(id: Box<RawValue>, error: impl Into<String>) -> Self {
        Answer::Error {
            id,
            error: error.into(),
        }
    }
}

/// Just the id of a line, as written, every other field skipped without being converted.
#[derive(Debug, Deserialize)]
struct IdOnly<'a> {
    #[serde(default, borrow)]
    id: Option<&'a RawValue>,
}

/// JSON `null`.
fn null_id() -> Box<RawValue> {
    RawValue::NULL.to_owned()
}

/// The id of a line, verbatim, or `null` when it cannot be read.
fn raw_id(text: &str) -> Box<RawValue> {
    match serde_json::from_str::<IdOnly<'_>>(text) {
        Ok(IdOnly { id: Some(id) }) => id.to_owned(),
        _ => null_id(),
    }
}

/// The fields of a query line that are not part of the query itself.
const LINE_FIELDS: [&str; 2] = ["version", "id"];

/// Answers one non-blank line.
fn answer_line(text: &str, params: &RelationParams) -> Answer {
    // The line may be well-formed JSON whose id can be read even when the rest cannot be
    // converted (for example a number too large for a double elsewhere).
    let id = raw_id(text);
    let mut object = match serde_json::from_str::<Value>(text) {
        Ok(Value::Object(object)) => object,
        Ok(_) => return Answer::error(id, "a query must be a JSON object"),
        Err(e) => return Answer::error(id, format!("invalid JSON: {e}")),
    };
    if let Some(version) = object.get("version")
        && version.as_u64() != Some(SCHEMA_VERSION)
    {
        return Answer::error(
            id,
            format!("unsupported schema version {version} (this build reads version {SCHEMA_VERSION})"),
        );
    }
    for field in LINE_FIELDS {
        object.remove(field);
    }
    let query: QuerySpec = match serde_json::from_value(Value::Object(object)) {
        Ok(q) => q,
        Err(e) => return Answer::error(id, format!("invalid query: {e}")),
    };
    match query.score(params) {
        Ok(score) => Answer::Score {
            id,
            score,
            holds: params.holds(score),
        },
        Err(e) => Answer::error(id, e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn answer(line: &str) -> Value {
        serde_json::to_value(answer_line(line, &RelationParams::default())).unwrap()
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
    }

    #[test]
    fn ids_are_echoed_verbatim() {
        let params = RelationParams::default();
        for id in [
            "123456789012345678901234567890",
            "-0.10000000000000000000001",
            "1e400",
            r#""caf\u00e9""#,
            r#"{"run": 3, "k": [1, 2.50]}"#,
        ] {
            let line = format!(r#"{{"id":{id},"relation":"beside"}}"#);
            let out = serde_json::to_string(&answer_line(&line, &params)).unwrap();
            assert!(out.starts_with(&format!(r#"{{"id":{id},"error":"#)), "{out}");
        }
    }
}
