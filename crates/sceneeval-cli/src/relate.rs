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
use sceneeval::geom::{Matrix3, Obb, Point2, Point3, Real, Rotation3, Vector3};
use sceneeval::relations::{ObjectGeom, Relation, RelationKind, RelationParams, arch, batch, surround};
use sceneeval::scene::{Room, RoomBuilder};
use serde::de::IgnoredAny;
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

/// A query line as written by clients (schema version 1).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct QueryLine {
    #[serde(default)]
    version: Option<u64>,
    #[serde(default)]
    #[allow(dead_code, reason = "echoed verbatim from the text, see `raw_id`")]
    id: Option<IgnoredAny>,
    relation: String,
    #[serde(default)]
    side: Option<String>,
    #[serde(default)]
    arch: Option<String>,
    #[serde(default)]
    target: Option<BoxSpec>,
    #[serde(default)]
    anchor: Option<BoxSpec>,
    #[serde(default)]
    targets: Option<Vec<BoxSpec>>,
    #[serde(default)]
    room: Option<RoomSpec>,
}

/// A solid box: centre, half extents, and either a yaw (radians about +z) or a 3x3
/// row-major rotation matrix (nested rows or nine numbers).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BoxSpec {
    center: [Real; 3],
    half_size: [Real; 3],
    #[serde(default)]
    yaw: Option<Real>,
    #[serde(default)]
    rotation: Option<RotationSpec>,
}

#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum RotationSpec {
    Rows([[Real; 3]; 3]),
    Flat([Real; 9]),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RoomSpec {
    floor: Vec<[Real; 2]>,
    #[serde(default)]
    floor_z: Real,
    #[serde(default = "default_height")]
    height: Real,
    #[serde(default = "default_thickness")]
    wall_thickness: Real,
    #[serde(default)]
    openings: Vec<OpeningLine>,
}

fn default_height() -> Real {
    2.8
}

fn default_thickness() -> Real {
    0.1
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct OpeningLine {
    kind: String,
    wall: usize,
    along: [Real; 2],
    height: [Real; 2],
}

/// Answers one non-blank line.
fn answer_line(text: &str, params: &RelationParams) -> Answer {
    // The line may be well-formed JSON whose id can be read even when the rest cannot be
    // converted (for example a number too large for a double elsewhere).
    let id = raw_id(text);
    let value: Value = match serde_json::from_str(text) {
        Ok(v) => v,
        Err(e) => return Answer::error(id, format!("invalid JSON: {e}")),
    };
    if !value.is_object() {
        return Answer::error(id, "a query must be a JSON object");
    }
    let query: QueryLine = match serde_json::from_value(value) {
        Ok(q) => q,
        Err(e) => return Answer::error(id, format!("invalid query: {e}")),
    };
    match evaluate(&query, params) {
        Ok(score) => Answer::Score {
            id,
            score,
            holds: params.holds(score),
        },
        Err(e) => Answer::error(id, format!("{e:#}")),
    }
}

fn evaluate(q: &QueryLine, params: &RelationParams) -> anyhow::Result<Real> {
    if let Some(v) = q.version
        && v != SCHEMA_VERSION
    {
        anyhow::bail!("unsupported schema version {v} (this build reads version {SCHEMA_VERSION})");
    }
    let relation = parse_relation(q)?;
    match relation.kind() {
        RelationKind::ObjectObject => {
            unexpected(q.targets.is_some(), "targets", relation)?;
            unexpected(q.room.is_some(), "room", relation)?;
            let target = build_box(required(q.target.as_ref(), "target", relation)?, "target")?;
            let anchor = build_box(required(q.anchor.as_ref(), "anchor", relation)?, "anchor")?;
            Ok(batch::score_pair(
                relation,
                &ObjectGeom::from_box(&target),
                &ObjectGeom::from_box(&anchor),
                params,
            )?)
        }
        RelationKind::MultiTarget => {
            unexpected(q.target.is_some(), "target (use targets)", relation)?;
            unexpected(q.room.is_some(), "room", relation)?;
            let anchor = build_box(required(q.anchor.as_ref(), "anchor", relation)?, "anchor")?;
            let boxes = required(q.targets.as_ref(), "targets", relation)?
                .iter()
                .enumerate()
                .map(|(i, b)| build_box(b, &format!("targets[{i}]")))
                .collect::<anyhow::Result<Vec<Obb>>>()?;
            let views: Vec<ObjectGeom<'_>> = boxes.iter().map(ObjectGeom::from_box).collect();
            Ok(surround(&views, &ObjectGeom::from_box(&anchor), params))
        }
        RelationKind::ObjectArchitecture => {
            unexpected(q.anchor.is_some(), "anchor", relation)?;
            unexpected(q.targets.is_some(), "targets", relation)?;
            let target = build_box(required(q.target.as_ref(), "target", relation)?, "target")?;
            let room = build_room(required(q.room.as_ref(), "room", relation)?)?;
            Ok(arch::score_rooms(
                relation,
                &ObjectGeom::from_box(&target),
                std::slice::from_ref(&room),
                params,
            )?)
        }
    }
}

/// The relation from `relation` plus `side` (sides, long/short) or `arch` (wall/door/window).
/// `relation` may also carry its argument itself, as in `side_of(left)`.
fn parse_relation(q: &QueryLine) -> anyhow::Result<Relation> {
    let name = q.relation.trim();
    if name.contains('(') || name.contains(':') {
        if q.side.is_some() || q.arch.is_some() {
            anyhow::bail!("relation {name:?} already names its argument; drop \"side\"/\"arch\"");
        }
        return Ok(name.parse::<Relation>()?);
    }
    let distance = matches!(
        name.to_ascii_lowercase().as_str(),
        "next_to" | "near" | "across_from" | "across" | "far" | "far_from"
    );
    match (&q.side, &q.arch) {
        (Some(_), Some(_)) => anyhow::bail!("give either \"side\" or \"arch\", not both"),
        (Some(side), None) if distance => {
            anyhow::bail!("relation {name} takes no side {side:?}; for walls, doors and windows use \"arch\"")
        }
        (Some(side), None) => Ok(Relation::from_parts(name, Some(side))?),
        (None, Some(element)) => Ok(Relation::from_arch_mapping(name, Some(element))?),
        (None, None) => {
            let r = Relation::from_parts(name, None)?;
            if distance && q.room.is_some() && q.anchor.is_none() {
                anyhow::bail!(
                    "relation {name} with a room needs \"arch\": \"wall\", \"door\" or \"window\" \
                     (without it, it relates two objects and needs an anchor)"
                );
            }
            Ok(r)
        }
    }
}

fn required<'q, T>(field: Option<&'q T>, name: &str, relation: Relation) -> anyhow::Result<&'q T> {
    field.ok_or_else(|| anyhow::anyhow!("relation {relation} needs \"{name}\""))
}

fn unexpected(present: bool, name: &str, relation: Relation) -> anyhow::Result<()> {
    if present {
        anyhow::bail!("relation {relation} does not use \"{name}\"");
    }
    Ok(())
}

fn finite(values: &[Real], what: &str) -> anyhow::Result<()> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        anyhow::bail!("{what} is not finite")
    }
}

fn build_box(spec: &BoxSpec, what: &str) -> anyhow::Result<Obb> {
    finite(&spec.center, &format!("{what}.center"))?;
    finite(&spec.half_size, &format!("{what}.half_size"))?;
    let center = Point3::from(spec.center);
    let half = Vector3::from(spec.half_size);
    let rotation = match (spec.yaw, &spec.rotation) {
        (Some(_), Some(_)) => anyhow::bail!("{what}: give either \"yaw\" or \"rotation\", not both"),
        (Some(yaw), None) => {
            finite(&[yaw], &format!("{what}.yaw"))?;
            Rotation3::from_axis_angle(&Vector3::z_axis(), yaw)
        }
        (None, None) => Rotation3::identity(),
        (None, Some(r)) => {
            let rows = match r {
                RotationSpec::Rows(rows) => *rows,
                RotationSpec::Flat(f) => [[f[0], f[1], f[2]], [f[3], f[4], f[5]], [f[6], f[7], f[8]]],
            };
            finite(rows.as_flattened(), &format!("{what}.rotation"))?;
            let m = Matrix3::from_fn(|i, j| rows[i][j]);
            Rotation3::from_matrix_unchecked(m)
        }
    };
    Obb::new(center, half, rotation).with_context(|| format!("{what} is not a valid box"))
}

fn build_room(spec: &RoomSpec) -> anyhow::Result<Room> {
    for (i, p) in spec.floor.iter().enumerate() {
        finite(p, &format!("room.floor[{i}]"))?;
    }
    finite(
        &[spec.floor_z, spec.height, spec.wall_thickness],
        "room.floor_z/height/wall_thickness",
    )?;
    let outline = spec.floor.iter().map(|p| Point2::new(p[0], p[1])).collect();
    let mut room = RoomBuilder::polygon("room", outline)
        .floor_z(spec.floor_z)
        .wall_height(spec.height)
        .wall_thickness(spec.wall_thickness);
    for (i, o) in spec.openings.iter().enumerate() {
        finite(&o.along, &format!("room.openings[{i}].along"))?;
        finite(&o.height, &format!("room.openings[{i}].height"))?;
        room = match o.kind.to_ascii_lowercase().as_str() {
            "door" => room.door(o.wall, o.along, o.height),
            "window" => room.window(o.wall, o.along, o.height),
            other => anyhow::bail!("room.openings[{i}].kind {other:?} is not \"door\" or \"window\""),
        };
    }
    room.build().map_err(|e| anyhow::anyhow!("room: {e}"))
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
