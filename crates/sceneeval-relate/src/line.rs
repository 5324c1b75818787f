//! One input line of `sceneeval relate`, as borrowed, typed fields (no intermediate
//! `serde_json::Value`): a query (its operands are [`Operand`]/[`RoomOperand`]), or a
//! declaration of a named object or room.
//!
//! Lines are read by the fast scanner (`flat`) or by serde_json into a `Line` (see
//! [`crate::answer_line`]); this module defines what a line is, and [`RawText`], the JSON text
//! of an id echoed as written.

use std::borrow::Cow;
use std::fmt;
use std::marker::PhantomData;

use crate::{Operand, Query, RoomOperand};
use serde::de::{self, Deserializer, Visitor};
use serde::ser::{self, Serializer};
use serde::{Deserialize, Serialize};
use serde_json::value::RawValue;

/// Every key a line may have. Which combinations are allowed is checked after parsing
/// ([`Line::kind`]); unknown keys are errors here.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Line<'a> {
    /// Schema version, as written.
    #[serde(default, borrow)]
    pub version: Option<RawText<'a>>,
    /// The client's id, echoed byte for byte.
    #[serde(default, borrow)]
    pub id: Option<RawText<'a>>,
    /// A declaration: the name being declared.
    #[serde(default, borrow)]
    pub declare: Option<Text<'a>>,
    /// A declaration's object.
    #[serde(default, borrow)]
    pub object: Option<Operand<'a>>,
    /// A query's relation name.
    #[serde(default, borrow)]
    pub relation: Option<Text<'a>>,
    /// A side argument.
    #[serde(default, borrow)]
    pub side: Option<Text<'a>>,
    /// An architecture element argument.
    #[serde(default, borrow)]
    pub arch: Option<Text<'a>>,
    /// The object being located.
    #[serde(default, borrow)]
    pub target: Option<Operand<'a>>,
    /// The reference object.
    #[serde(default, borrow)]
    pub anchor: Option<Operand<'a>>,
    /// The objects around the anchor (`surround`).
    #[serde(default, borrow)]
    pub targets: Option<Vec<Operand<'a>>>,
    /// The room: a query's operand, or a declaration's room.
    #[serde(default, borrow)]
    pub room: Option<RoomOperand<'a>>,
}

/// What a line asks for.
pub(crate) enum LineKind<'l, 'a> {
    /// A relation query.
    Query(Query<'l>),
    /// `declare` with `object`.
    DeclareObject(&'l str, &'l Operand<'a>),
    /// `declare` with `room`.
    DeclareRoom(&'l str, &'l RoomOperand<'a>),
}

impl<'a> Line<'a> {
    /// The line's kind, or why its keys do not make one.
    #[inline]
    pub fn kind(&self) -> Result<LineKind<'_, 'a>, String> {
        let Some(name) = &self.declare else {
            if self.object.is_some() {
                return Err("\"object\" belongs to declarations (with \"declare\"); a query names its objects \"target\", \"anchor\" or \"targets\"".into());
            }
            let Some(relation) = &self.relation else {
                return Err("a line needs \"relation\" (a query) or \"declare\" (a declaration)".into());
            };
            return Ok(LineKind::Query(Query {
                relation: relation.0.as_ref(),
                side: self.side.as_ref().map(|t| t.0.as_ref()),
                arch: self.arch.as_ref().map(|t| t.0.as_ref()),
                target: self.target.as_ref(),
                anchor: self.anchor.as_ref(),
                targets: self.targets.as_deref(),
                room: self.room.as_ref(),
            }));
        };
        let query_keys = [
            ("relation", self.relation.is_some()),
            ("side", self.side.is_some()),
            ("arch", self.arch.is_some()),
            ("target", self.target.is_some()),
            ("anchor", self.anchor.is_some()),
            ("targets", self.targets.is_some()),
        ];
        if let Some((key, _)) = query_keys.iter().find(|(_, present)| *present) {
            return Err(format!(
                "a declaration has \"declare\" and one of \"object\" or \"room\" (and optionally \"id\", \"version\"), not \"{key}\""
            ));
        }
        let name = name.0.as_ref();
        if name.is_empty() {
            return Err("a declared name must not be empty".into());
        }
        match (&self.object, &self.room) {
            (Some(object), None) => Ok(LineKind::DeclareObject(name, object)),
            (None, Some(room)) => Ok(LineKind::DeclareRoom(name, room)),
            (Some(_), Some(_)) => Err(format!(
                "declaration of {name:?}: give either \"object\" or \"room\", not both"
            )),
            (None, None) => Err(format!("declaration of {name:?} needs \"object\" or \"room\"")),
        }
    }
}

/// A JSON value's text as written, without the whitespace around it: an id or a version,
/// echoed byte for byte (a 30-digit integer stays a 30-digit integer). Valid JSON by
/// construction: read by serde_json as a `RawValue`, or by the fast path as a string without
/// escapes or an integer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RawText<'a>(pub &'a str);

impl RawText<'static> {
    /// JSON `null`.
    pub const NULL: Self = RawText("null");
}

impl<'de: 'a, 'a> Deserialize<'de> for RawText<'a> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        <&'a RawValue>::deserialize(deserializer).map(|raw| RawText(raw.get()))
    }
}

impl Serialize for RawText<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serde_json::from_str::<&RawValue>(self.0)
            .map_err(ser::Error::custom)?
            .serialize(serializer)
    }
}

/// A JSON string, borrowed from the line unless it has escapes.
#[derive(Debug)]
pub(crate) struct Text<'a>(pub Cow<'a, str>);

impl<'de: 'a, 'a> Deserialize<'de> for Text<'a> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_str(TextVisitor(PhantomData))
    }
}

struct TextVisitor<'a>(PhantomData<&'a ()>);

impl<'de: 'a, 'a> Visitor<'de> for TextVisitor<'a> {
    type Value = Text<'a>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a string")
    }

    fn visit_borrowed_str<E: de::Error>(self, v: &'de str) -> Result<Self::Value, E> {
        Ok(Text(Cow::Borrowed(v)))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
        Ok(Text(Cow::Owned(v.to_owned())))
    }
}

/// Just the id of a line, every other field skipped: the id of a line that does not parse.
#[derive(Debug, Deserialize)]
pub(crate) struct IdOnly<'a> {
    #[serde(default, borrow)]
    pub id: Option<RawText<'a>>,
}

/// Just the `declare` value of a line, as written: the name a declaration that does not
/// parse is named by in its error. (Read apart from [`IdOnly`], so that a line's id is read
/// exactly as it always was, whatever its `declare` holds.)
#[derive(Debug, Deserialize)]
pub(crate) struct DeclareOnly<'a> {
    #[serde(default, borrow)]
    pub declare: Option<&'a RawValue>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ObjectSpec;

    #[test]
    fn operands_are_names_or_objects_and_escapes_are_read() {
        let line: Line<'_> = serde_json::from_str(
            r#"{"relation":"near","target":"caf\u00e9","anchor":{"center":[0,0,0],"half_size":[1,1,1]},
                "room":"r1"}"#,
        )
        .unwrap();
        assert!(matches!(&line.target, Some(Operand::Name(n)) if n == "café"));
        assert!(matches!(&line.anchor, Some(Operand::Inline(o)) if matches!(**o, ObjectSpec::Box(_))));
        assert!(matches!(&line.room, Some(RoomOperand::Name(n)) if n == "r1"));
        let line: Line<'_> = serde_json::from_str(r#"{"relation":"near","room":{"floor":[]}}"#).unwrap();
        assert!(matches!(&line.room, Some(RoomOperand::Inline(r)) if r.get() == r#"{"floor":[]}"#));
        assert!(serde_json::from_str::<Line<'_>>(r#"{"relation":"near","room":3}"#).is_err());
        assert!(serde_json::from_str::<Line<'_>>(r#"{"relation":"near","target":3}"#).is_err());
    }

    #[test]
    fn declarations_take_one_thing_and_nothing_of_a_query() {
        let kind = |text: &str| {
            let line: Line<'_> = serde_json::from_str(text).unwrap();
            line.kind().map(|k| match k {
                LineKind::Query(_) => "query".to_owned(),
                LineKind::DeclareObject(n, _) => format!("object {n}"),
                LineKind::DeclareRoom(n, _) => format!("room {n}"),
            })
        };
        assert_eq!(
            kind(r#"{"declare":"bed","object":"other"}"#).unwrap(),
            "object bed"
        );
        assert_eq!(kind(r#"{"declare":"r","room":{}}"#).unwrap(), "room r");
        assert_eq!(kind(r#"{"relation":"near"}"#).unwrap(), "query");
        for (text, expect) in [
            (r#"{"declare":"bed"}"#, "needs \"object\" or \"room\""),
            (r#"{"declare":"bed","object":"a","room":"b"}"#, "not both"),
            (
                r#"{"declare":"bed","object":"a","relation":"near"}"#,
                "not \"relation\"",
            ),
            (r#"{"declare":"","room":"b"}"#, "empty"),
            (r#"{"object":"a"}"#, "belongs to declarations"),
            (r#"{"id":1}"#, "needs \"relation\""),
        ] {
            let e = kind(text).unwrap_err();
            assert!(e.contains(expect), "{text}: {e}");
        }
    }
}
