//! The request a [`crate::Vlm`] answers and the answer it gives.

use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::{PngImage, TokenUsage};

/// One structured request: a system prompt, one user message (text, then images) and the JSON
/// Schema the answer must follow.
///
/// Built by [`crate::Session`] from a [`crate::Task`]; implementations of [`crate::Vlm`] turn
/// it into their wire format. Requests are independent: there is no conversation history (the
/// reference resets its history before every task, so this loses nothing).
#[derive(Debug, Clone, PartialEq)]
pub struct VlmRequest {
    /// The task name (`obj_matching`, ... see [`crate::TaskKind`]), used in logs and errors.
    pub task: String,
    /// The system prompt.
    pub system: String,
    /// The user message's text: instructions and examples first, the scene-specific part last.
    pub user_text: String,
    /// The user message's images, sent after the text, in this order.
    pub images: Vec<PngImage>,
    /// The JSON Schema of the expected answer, already normalised for strict mode.
    pub schema: ResponseSchema,
}

/// A named JSON Schema for structured output (`response_format.json_schema` in the OpenAI
/// API: a name matching `^[A-Za-z0-9_-]{1,64}$` and the schema itself).
///
/// Serialises as `{"name": ..., "schema": ...}` with the schema's properties in declaration
/// order ([`crate::schema::ordered`]).
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct ResponseSchema {
    /// The schema name (the task name for the built-in tasks).
    pub name: String,
    /// The schema (see [`crate::schema`] for the strict-mode rules it follows).
    pub schema: Value,
}

impl Serialize for ResponseSchema {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut out = serializer.serialize_struct("ResponseSchema", 2)?;
        out.serialize_field("name", &self.name)?;
        out.serialize_field("schema", &crate::schema::ordered(&self.schema))?;
        out.end()
    }
}

/// What a [`crate::Vlm`] answered to one request.
#[derive(Debug, Clone, PartialEq)]
pub struct Answer {
    /// The content of the answer.
    pub content: AnswerContent,
    /// Tokens the request used as reported by the server (zero when it reports none, and for
    /// scripted answers).
    pub usage: TokenUsage,
    /// Whether the answer was read from a cache rather than produced now.
    pub from_cache: bool,
}

impl Answer {
    /// A fresh (not cached) answer.
    pub fn new(content: AnswerContent, usage: TokenUsage) -> Self {
        Answer {
            content,
            usage,
            from_cache: false,
        }
    }
}

/// The content of an answer: parsed JSON, or one of the ways a model's reply can be unusable.
///
/// Serialised with a `kind` tag (`json`, `not_json`, `refusal`, `truncated`), as stored in
/// cache files.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum AnswerContent {
    /// The reply parsed as JSON (not yet checked against the schema).
    Json {
        /// The parsed reply.
        value: Value,
    },
    /// The reply is not JSON (servers without schema-constrained decoding can produce this).
    NotJson {
        /// The reply as received.
        text: String,
        /// The JSON parser's message.
        error: String,
    },
    /// The model refused to answer (OpenAI's `message.refusal`).
    Refusal {
        /// The refusal message.
        text: String,
    },
    /// The reply was cut off at the token limit (`finish_reason: "length"`).
    Truncated {
        /// The partial reply.
        text: String,
    },
}

impl AnswerContent {
    /// Parses a reply text: [`AnswerContent::Json`] when it is JSON, else
    /// [`AnswerContent::NotJson`].
    pub fn from_text(text: &str) -> Self {
        match serde_json::from_str::<Value>(text) {
            Ok(value) => AnswerContent::Json { value },
            Err(e) => AnswerContent::NotJson {
                text: text.to_owned(),
                error: e.to_string(),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn content_from_text_and_tagged_serialisation() {
        let ok = AnswerContent::from_text(r#"{"a": 1}"#);
        assert_eq!(
            ok,
            AnswerContent::Json {
                value: serde_json::json!({"a": 1})
            }
        );
        let bad = AnswerContent::from_text("{\"a\": ");
        assert!(matches!(bad, AnswerContent::NotJson { .. }));
        let json = serde_json::to_value(AnswerContent::Refusal { text: "no".into() }).unwrap();
        assert_eq!(json, serde_json::json!({"kind": "refusal", "text": "no"}));
    }
}
