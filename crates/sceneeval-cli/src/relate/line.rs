//! One input line of `sceneeval relate`, parsed in one pass into borrowed, typed fields (no
//! intermediate `serde_json::Value`): a query, or a declaration of a named object or room.
//!
//! [`Line::parse`] reads the commonest lines, flat objects of plain strings and an integer id
//! (a query by name), with a scanner of its own ([`super::flat`]) and every other line with
//! serde_json; both give the same [`Line`].

use std::borrow::Cow;
use std::fmt;
use std::marker::PhantomData;

use sceneeval::relations::spec::ObjectSpec;
use serde::de::{self, Deserializer, MapAccess, Visitor};
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
    Query(&'l Line<'a>),
    /// `declare` with `object`.
    DeclareObject(&'l str, &'l Operand<'a>),
    /// `declare` with `room`.
    DeclareRoom(&'l str, &'l RoomOperand<'a>),
}

impl<'a> Line<'a> {
    /// The line in `text` (one JSON object), built in the caller's `slot` (a line is a few
    /// hundred bytes: it is not moved once per call): through the fast path when it is a flat
    /// object of plain strings and integers, else through serde_json, whose errors are the
    /// answer's.
    #[inline]
    pub fn parse<'s>(text: &'a str, slot: &'s mut Option<Line<'a>>) -> serde_json::Result<&'s Self> {
        let line = slot.insert(Line::default());
        if super::flat::read(text, line).is_none() {
            *line = serde_json::from_str(text)?;
        }
        Ok(line)
    }

    /// The line's kind, or why its keys do not make one.
    pub fn kind(&self) -> Result<LineKind<'_, 'a>, String> {
        let Some(name) = &self.declare else {
            if self.object.is_some() {
                return Err("\"object\" belongs to declarations (with \"declare\"); a query names its objects \"target\", \"anchor\" or \"targets\"".into());
            }
            if self.relation.is_none() {
                return Err("a line needs \"relation\" (a query) or \"declare\" (a declaration)".into());
            }
            return Ok(LineKind::Query(self));
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
pub(crate) struct RawText<'a>(pub &'a str);

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

/// An object operand: the name of a declared object, or an object written in place.
#[derive(Debug)]
pub(crate) enum Operand<'a> {
    /// A declared object's name.
    Name(Cow<'a, str>),
    /// A box or an asset object (boxed: a line's fields stay small to move).
    Inline(Box<ObjectSpec>),
}

impl<'de: 'a, 'a> Deserialize<'de> for Operand<'a> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(OperandVisitor(PhantomData))
    }
}

struct OperandVisitor<'a>(PhantomData<&'a ()>);

impl<'de: 'a, 'a> Visitor<'de> for OperandVisitor<'a> {
    type Value = Operand<'a>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a declared object's name or an object (a box or an asset)")
    }

    fn visit_borrowed_str<E: de::Error>(self, v: &'de str) -> Result<Self::Value, E> {
        Ok(Operand::Name(Cow::Borrowed(v)))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
        Ok(Operand::Name(Cow::Owned(v.to_owned())))
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
        ObjectSpec::deserialize(de::value::MapAccessDeserializer::new(map))
            .map(|o| Operand::Inline(Box::new(o)))
    }
}

/// A room operand: a declared room's name, or a room written in place, kept as its JSON text
/// (the key of the prepared-room cache; parsed only when the room is not cached).
#[derive(Debug)]
pub(crate) enum RoomOperand<'a> {
    /// A declared room's name.
    Name(Cow<'a, str>),
    /// The room's JSON object, as written.
    Inline(&'a RawValue),
}

impl<'de: 'a, 'a> Deserialize<'de> for RoomOperand<'a> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let raw = <&'a RawValue>::deserialize(deserializer)?;
        let text = raw.get();
        if text.starts_with('"') {
            // A valid JSON string without a backslash is its own content between the quotes;
            // only one with escapes is parsed again.
            match text.strip_prefix('"').and_then(|t| t.strip_suffix('"')) {
                Some(inner) if !inner.contains('\\') => Ok(RoomOperand::Name(Cow::Borrowed(inner))),
                _ => serde_json::from_str::<Text<'a>>(text)
                    .map(|t| RoomOperand::Name(t.0))
                    .map_err(de::Error::custom),
            }
        } else if text.starts_with('{') {
            Ok(RoomOperand::Inline(raw))
        } else {
            Err(de::Error::invalid_value(
                de::Unexpected::Other(text),
                &"a declared room's name or a room object",
            ))
        }
    }
}

/// Just the id of a line, every other field skipped: the id of a line that does not parse.
#[derive(Debug, Deserialize)]
pub(crate) struct IdOnly<'a> {
    #[serde(default, borrow)]
    pub id: Option<RawText<'a>>,
}

#[cfg(test)]
mod tests {
    use super::*;

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
