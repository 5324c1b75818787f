//! The chat-completions wire format (private): the request body and the parts of the reply
//! that are read.

use base64::Engine;
use serde::{Deserialize, Serialize};

use sceneeval_vlm::schema::{Ordered, ordered};
use sceneeval_vlm::{AnswerContent, TokenUsage, VlmRequest};

use crate::{ImageDetail, TokenLimitField};

#[derive(Serialize)]
pub(crate) struct ChatRequest<'a> {
    model: &'a str,
    messages: [Message<'a>; 2],
    response_format: ResponseFormat<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    seed: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    temperature: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_tokens: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_completion_tokens: Option<u32>,
}

#[derive(Serialize)]
#[serde(tag = "role", rename_all = "lowercase")]
enum Message<'a> {
    System { content: &'a str },
    User { content: Vec<Part<'a>> },
}

#[derive(Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
enum Part<'a> {
    Text { text: &'a str },
    ImageUrl { image_url: ImageUrl },
}

#[derive(Serialize)]
struct ImageUrl {
    url: String,
    detail: ImageDetail,
}

#[derive(Serialize)]
struct ResponseFormat<'a> {
    #[serde(rename = "type")]
    kind: &'static str,
    json_schema: JsonSchemaFormat<'a>,
}

#[derive(Serialize)]
struct JsonSchemaFormat<'a> {
    name: &'a str,
    strict: bool,
    schema: Ordered<'a>,
}

/// Sampling settings sent with every request.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Sampling {
    pub detail: ImageDetail,
    pub seed: Option<u64>,
    pub temperature: Option<f32>,
    pub max_tokens: Option<u32>,
    pub token_limit_field: TokenLimitField,
}

impl Sampling {
    /// The settings as canonical text, `name=value` pairs in a fixed order joined by `;`,
    /// leaving out what is not sent: the client's `Vlm::settings`.
    pub(crate) fn canonical(&self) -> String {
        let detail = match self.detail {
            ImageDetail::Low => "low",
            ImageDetail::High => "high",
            ImageDetail::Auto => "auto",
        };
        let mut parts = vec![format!("detail={detail}")];
        if let Some(seed) = self.seed {
            parts.push(format!("seed={seed}"));
        }
        if let Some(t) = self.temperature {
            // Shortest text that reads back as the same f32 (`0`, `0.7`).
            parts.push(format!("temperature={t}"));
        }
        if let Some(n) = self.max_tokens {
            parts.push(format!("{}={n}", self.token_limit_field.name()));
        }
        parts.join(";")
    }
}

/// The request body: system message, then one user message with the text and the images as
/// `data:image/png;base64` URLs, and the strict JSON schema.
pub(crate) fn request_body(
    model: &str,
    request: &VlmRequest,
    s: Sampling,
) -> Result<Vec<u8>, serde_json::Error> {
    let mut content = Vec::with_capacity(1 + request.images.len());
    content.push(Part::Text {
        text: &request.user_text,
    });
    for image in &request.images {
        let b64 = base64::engine::general_purpose::STANDARD.encode(image.bytes());
        content.push(Part::ImageUrl {
            image_url: ImageUrl {
                url: format!("data:image/png;base64,{b64}"),
                detail: s.detail,
            },
        });
    }
    let body = ChatRequest {
        model,
        messages: [
            Message::System {
                content: &request.system,
            },
            Message::User { content },
        ],
        response_format: ResponseFormat {
            kind: "json_schema",
            json_schema: JsonSchemaFormat {
                name: &request.schema.name,
                strict: true,
                schema: ordered(&request.schema.schema),
            },
        },
        seed: s.seed,
        temperature: s.temperature,
        max_tokens: s
            .max_tokens
            .filter(|_| s.token_limit_field == TokenLimitField::MaxTokens),
        max_completion_tokens: s
            .max_tokens
            .filter(|_| s.token_limit_field == TokenLimitField::MaxCompletionTokens),
    };
    serde_json::to_vec(&body)
}

#[derive(Deserialize)]
pub(crate) struct ChatResponse {
    choices: Vec<Choice>,
    #[serde(default)]
    usage: Option<UsageWire>,
}

#[derive(Deserialize)]
struct Choice {
    message: ChoiceMessage,
    #[serde(default)]
    finish_reason: Option<String>,
}

#[derive(Deserialize)]
struct ChoiceMessage {
    #[serde(default)]
    content: Option<String>,
    #[serde(default)]
    refusal: Option<String>,
}

#[derive(Deserialize)]
struct UsageWire {
    #[serde(default)]
    prompt_tokens: Option<u64>,
    #[serde(default)]
    completion_tokens: Option<u64>,
}

/// The `{"error": {"message": ...}}` body of an error reply.
#[derive(Deserialize)]
pub(crate) struct ErrorBody {
    pub error: ErrorDetail,
}

#[derive(Deserialize)]
pub(crate) struct ErrorDetail {
    #[serde(default)]
    pub message: Option<String>,
}

impl ChatResponse {
    /// The answer of the first choice, or a message saying why there is none.
    pub(crate) fn into_answer(self) -> Result<(AnswerContent, TokenUsage), String> {
        let usage = self.usage.map_or_else(TokenUsage::default, |u| TokenUsage {
            prompt_tokens: u.prompt_tokens.unwrap_or(0),
            completion_tokens: u.completion_tokens.unwrap_or(0),
        });
        let choice = self
            .choices
            .into_iter()
            .next()
            .ok_or_else(|| "the reply has no choices".to_owned())?;
        let text = choice.message.content.unwrap_or_default();
        let content = match (choice.message.refusal, choice.finish_reason.as_deref()) {
            (Some(refusal), _) if !refusal.trim().is_empty() => AnswerContent::Refusal { text: refusal },
            (_, Some("length")) => AnswerContent::Truncated { text },
            (_, Some("content_filter")) => AnswerContent::Refusal {
                text: "the server's content filter stopped the reply".to_owned(),
            },
            _ => parse_content(&text),
        };
        Ok((content, usage))
    }
}

/// Parses a reply text as JSON; a reply wrapped in a Markdown code fence (some servers without
/// schema-constrained decoding do that) is unwrapped first.
fn parse_content(text: &str) -> AnswerContent {
    let direct = AnswerContent::from_text(text);
    if matches!(direct, AnswerContent::Json { .. }) {
        return direct;
    }
    let trimmed = text.trim();
    let inner = trimmed
        .strip_prefix("```json")
        .or_else(|| trimmed.strip_prefix("```"))
        .and_then(|t| t.strip_suffix("```"));
    match inner.map(AnswerContent::from_text) {
        Some(json @ AnswerContent::Json { .. }) => json,
        _ => direct,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn reply(body: serde_json::Value) -> (AnswerContent, TokenUsage) {
        serde_json::from_value::<ChatResponse>(body)
            .unwrap()
            .into_answer()
            .unwrap()
    }

    #[test]
    fn sampling_settings_as_canonical_text() {
        let mut s = Sampling {
            detail: ImageDetail::Low,
            seed: Some(42),
            temperature: Some(0.0),
            max_tokens: None,
            token_limit_field: TokenLimitField::MaxTokens,
        };
        assert_eq!(s.canonical(), "detail=low;seed=42;temperature=0");
        s.detail = ImageDetail::High;
        s.temperature = Some(0.7);
        s.max_tokens = Some(300);
        assert_eq!(
            s.canonical(),
            "detail=high;seed=42;temperature=0.7;max_tokens=300"
        );
        s.token_limit_field = TokenLimitField::MaxCompletionTokens;
        assert_eq!(
            s.canonical(),
            "detail=high;seed=42;temperature=0.7;max_completion_tokens=300"
        );
        s.seed = None;
        s.temperature = None;
        s.max_tokens = None;
        s.detail = ImageDetail::Auto;
        assert_eq!(s.canonical(), "detail=auto");
    }

    #[test]
    fn reply_kinds() {
        let (c, u) = reply(
            json!({"choices": [{"message": {"content": "{\"a\":1}"}, "finish_reason": "stop"}],
                                  "usage": {"prompt_tokens": 7, "completion_tokens": 3, "total_tokens": 10}}),
        );
        assert_eq!(
            c,
            AnswerContent::Json {
                value: json!({"a": 1})
            }
        );
        assert_eq!((u.prompt_tokens, u.completion_tokens), (7, 3));
        let (c, _) = reply(
            json!({"choices": [{"message": {"content": null, "refusal": "No."}, "finish_reason": "stop"}]}),
        );
        assert_eq!(c, AnswerContent::Refusal { text: "No.".into() });
        let (c, _) =
            reply(json!({"choices": [{"message": {"content": "{\"a\":"}, "finish_reason": "length"}]}));
        assert_eq!(
            c,
            AnswerContent::Truncated {
                text: "{\"a\":".into()
            }
        );
        let (c, _) = reply(json!({"choices": [{"message": {"content": "```json\n{\"a\": 2}\n```"}}]}));
        assert_eq!(
            c,
            AnswerContent::Json {
                value: json!({"a": 2})
            }
        );
        let (c, _) = reply(json!({"choices": [{"message": {"content": "not json"}}]}));
        assert!(matches!(c, AnswerContent::NotJson { .. }));
        let none = serde_json::from_value::<ChatResponse>(json!({"choices": []}))
            .unwrap()
            .into_answer();
        assert!(none.is_err());
    }
}
