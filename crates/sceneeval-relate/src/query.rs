//! A query as its front end read it: the relation's name and argument, and operands that are
//! declared names or objects and rooms written in place.

use std::borrow::Cow;
use std::fmt;
use std::marker::PhantomData;

use serde::Deserialize;
use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde_json::value::RawValue;

use super::ObjectSpec;

/// An object operand: the name of a declared object, or an object written in place.
///
/// In JSON a string is a name and an object is an [`ObjectSpec`]; names are borrowed from
/// the text unless they have escapes.
#[derive(Debug, Clone, PartialEq)]
pub enum Operand<'a> {
    /// A declared object's name.
    Name(Cow<'a, str>),
    /// A box or an asset object (boxed: a query's fields stay small to move).
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
/// (the key of the session's prepared rooms; read as a `sceneeval_scene::RoomSpec` only when
/// the room is not prepared yet).
#[derive(Debug, Clone)]
pub enum RoomOperand<'a> {
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
                _ => serde_json::from_str::<String>(text)
                    .map(|t| RoomOperand::Name(Cow::Owned(t)))
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

/// One relation query: the relation's name with its `side` or `arch` argument (as
/// [`sceneeval_relations::Relation::from_fields`] reads them), and the operands its kind uses,
/// each a declared name or written in place. It borrows what the front end parsed
/// (`sceneeval relate`'s line); [`super::Session::score`] answers it.
#[derive(Debug, Clone, Copy, Default)]
pub struct Query<'q> {
    /// The relation's name, perhaps with its argument (`side_of(left)`).
    pub relation: &'q str,
    /// A side (`left`, ..., `bottom`) or `long`/`short`.
    pub side: Option<&'q str>,
    /// An architecture element: `wall`, `door` or `window`.
    pub arch: Option<&'q str>,
    /// The object being located.
    pub target: Option<&'q Operand<'q>>,
    /// The reference object.
    pub anchor: Option<&'q Operand<'q>>,
    /// The objects around the anchor (`surround`).
    pub targets: Option<&'q [Operand<'q>]>,
    /// The room (object-architecture relations).
    pub room: Option<&'q RoomOperand<'q>>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn operands_are_names_or_objects_and_escapes_are_read() {
        let name: Operand<'_> = serde_json::from_str(r#""caf\u00e9""#).unwrap();
        assert_eq!(name, Operand::Name(Cow::Owned("café".into())));
        let name: Operand<'_> = serde_json::from_str(r#""bed""#).unwrap();
        assert!(matches!(name, Operand::Name(Cow::Borrowed("bed"))));
        let inline: Operand<'_> = serde_json::from_str(r#"{"center":[0,0,0],"half_size":[1,1,1]}"#).unwrap();
        assert!(matches!(&inline, Operand::Inline(o) if matches!(**o, ObjectSpec::Box(_))));
        assert!(serde_json::from_str::<Operand<'_>>("3").is_err());
        let room: RoomOperand<'_> = serde_json::from_str(r#""r1""#).unwrap();
        assert!(matches!(room, RoomOperand::Name(Cow::Borrowed("r1"))));
        let room: RoomOperand<'_> = serde_json::from_str(r#""r\u0031""#).unwrap();
        assert!(matches!(&room, RoomOperand::Name(Cow::Owned(n)) if n == "r1"));
        let room: RoomOperand<'_> = serde_json::from_str(r#"{"floor":[]}"#).unwrap();
        assert!(matches!(room, RoomOperand::Inline(r) if r.get() == r#"{"floor":[]}"#));
        let err = serde_json::from_str::<RoomOperand<'_>>("3")
            .unwrap_err()
            .to_string();
        assert!(err.contains("a declared room's name or a room object"), "{err}");
    }
}
