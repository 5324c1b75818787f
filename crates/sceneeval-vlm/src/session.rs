//! [`Session`]: asks typed tasks of a [`Vlm`], validates the answers, re-asks once, and sums
//! the usage of a run.

use crate::prompt::{Prompts, Template};
use crate::schema::strict_schema_for;
use crate::task::{Answers, Outcome, Task, Unanswered, UnansweredKind, Validation};
use crate::usage::{Meter, Usage};
use crate::{Answer, AnswerContent, Vlm, VlmError, VlmRequest};

/// A model, the prompts to use with it, and the usage counters of a run.
///
/// [`Session::ask`] is the one way tasks are asked, so every [`Vlm`] implementation gets the
/// same protocol:
///
/// 1. The task's request is sent (system prompt, filled template, images, strict schema).
/// 2. The answer is parsed into the task's response type and validated; each part is paired
///    with its question by key.
/// 3. If some question has no valid answer, the task is asked **once** more, with the list of
///    problems and the previous answer appended to the text (the [`Template::Reask`] note).
///    Each question keeps its first valid answer.
/// 4. A question still without a valid answer is recorded as [`Unanswered`] with the reason. A
///    refused or truncated answer is recorded at once (asking the same again would not help).
///
/// Only a failure to obtain any answer (network, key refused, cache miss in replay) is an
/// error; the caller decides whether to go on (see [`VlmError::is_permanent`]).
///
/// ```
/// use sceneeval_vlm::{AnswerContent, Scripted, Session, check};
/// use serde_json::json;
///
/// let vlm = Scripted::queue("test-model", [
///     AnswerContent::Json { value: json!({"colour": "purple", "reason": "?"}) }, // not offered
///     AnswerContent::Json { value: json!({"colour": "red", "reason": "A red square."}) },
/// ]);
/// let session = Session::new(&vlm);
/// let task = check::EndpointCheck::new();
/// let answers = pollster::block_on(session.ask(&task)).unwrap();
/// assert_eq!(answers.requests, 2, "the invalid colour was asked again once");
/// let answer = answers.into_single().unwrap().into_result().unwrap();
/// assert!(answer.correct);
/// assert_eq!(session.usage().re_asks, 1);
/// assert!(vlm.requests()[1].user_text.contains("\"purple\" is not one of"));
/// ```
#[derive(Debug)]
pub struct Session<V> {
    vlm: V,
    prompts: Prompts,
    meter: Meter,
}

impl<V: Vlm> Session<V> {
    /// A session with the built-in prompts.
    pub fn new(vlm: V) -> Self {
        Session {
            vlm,
            prompts: Prompts::builtin(),
            meter: Meter::default(),
        }
    }

    /// Uses `prompts` instead of the built-in ones.
    pub fn with_prompts(mut self, prompts: Prompts) -> Self {
        self.prompts = prompts;
        self
    }

    /// The model.
    pub fn vlm(&self) -> &V {
        &self.vlm
    }

    /// The prompts.
    pub fn prompts(&self) -> &Prompts {
        &self.prompts
    }

    /// The usage so far.
    pub fn usage(&self) -> Usage {
        self.meter.usage()
    }

    /// The first request [`Session::ask`] sends for `task` (to inspect or log it).
    ///
    /// # Errors
    /// [`VlmError::Prompt`] when an overridden template lacks a value, [`VlmError::Schema`]
    /// when the response type cannot be written as a strict schema.
    pub fn request<T: Task>(&self, task: &T) -> Result<VlmRequest, VlmError> {
        let values = task.placeholders();
        let pairs: Vec<(&str, &str)> = values.iter().map(|(n, v)| (*n, v.as_str())).collect();
        Ok(VlmRequest {
            task: task.kind().name().to_owned(),
            system: self.prompts.text(Template::System).to_owned(),
            user_text: self.prompts.fill(task.template(), &pairs)?,
            images: task.images(),
            schema: strict_schema_for::<T::Response>(task.kind().name())?,
        })
    }

    /// Asks `task`, validates the answer, re-asks once if needed (see the type's docs).
    ///
    /// # Errors
    /// A [`VlmError`] when no answer could be obtained for a request, or the request could not
    /// be built ([`Session::request`]).
    pub async fn ask<T: Task>(&self, task: &T) -> Result<Answers<T::Key, T::Item>, VlmError> {
        let keys = task.keys();
        let request = self.request(task)?;
        let first = self.send(&request, 1).await?;
        let mut v1 = match check(task, &first.content, &keys) {
            Checked::Unusable(why) => {
                tracing::warn!(task = %task.kind(), reason = %why, "no usable answer");
                return Ok(self.collect(task, keys, 1, |_| Outcome::Unanswered(why.clone())));
            }
            Checked::Validated(v) => v,
        };
        if v1.complete(&keys) {
            return Ok(self.collect(task, keys, 1, |key| match v1.take_item(key) {
                Some(answer) => Outcome::Answered { answer, attempt: 1 },
                None => invalid(v1.reason_for(key)),
            }));
        }

        let problems = v1.problem_lines();
        tracing::warn!(task = %task.kind(), ?problems, "invalid answer; asking again once");
        self.meter.re_ask();
        let problem_list: Vec<String> = problems.iter().map(|p| format!("- {p}")).collect();
        let note = self.prompts.fill(
            Template::Reask,
            &[
                ("PROBLEMS", &problem_list.join("\n")),
                ("PREVIOUS_ANSWER", &previous_answer_text(&first.content)),
            ],
        )?;
        let mut again = request;
        again.user_text = format!("{}\n\n{note}", again.user_text);
        let second = self.send(&again, 2).await?;
        let mut second = check(task, &second.content, &keys);
        Ok(self.collect(task, keys, 2, |key| {
            if let Some(answer) = v1.take_item(key) {
                return Outcome::Answered { answer, attempt: 1 };
            }
            match &mut second {
                Checked::Unusable(why) => Outcome::Unanswered(why.clone()),
                Checked::Validated(v2) => match v2.take_item(key) {
                    Some(answer) => Outcome::Answered { answer, attempt: 2 },
                    None => invalid(format!(
                        "asked twice; second answer: {}; first answer: {}",
                        v2.reason_for(key),
                        v1.reason_for(key)
                    )),
                },
            }
        }))
    }

    async fn send(&self, request: &VlmRequest, attempt: u8) -> Result<Answer, VlmError> {
        match self.vlm.answer(request).await {
            Ok(answer) => {
                self.meter.answer(answer.usage, answer.from_cache);
                tracing::debug!(
                    task = %request.task,
                    attempt,
                    from_cache = answer.from_cache,
                    prompt_tokens = answer.usage.prompt_tokens,
                    completion_tokens = answer.usage.completion_tokens,
                    "answer received"
                );
                Ok(answer)
            }
            Err(e) => {
                self.meter.failure();
                Err(e)
            }
        }
    }

    /// The outcome of every question, in question order; counts them.
    fn collect<T: Task>(
        &self,
        task: &T,
        keys: Vec<T::Key>,
        requests: u8,
        mut outcome: impl FnMut(&T::Key) -> Outcome<T::Item>,
    ) -> Answers<T::Key, T::Item> {
        let outcomes: Vec<(T::Key, Outcome<T::Item>)> = keys
            .into_iter()
            .map(|key| {
                let o = outcome(&key);
                if let Outcome::Unanswered(why) = &o {
                    tracing::warn!(task = %task.kind(), question = %key, reason = %why, "question unanswered");
                }
                (key, o)
            })
            .collect();
        let answered = outcomes.iter().filter(|(_, o)| o.is_answered()).count() as u64;
        self.meter.outcomes(answered, outcomes.len() as u64 - answered);
        Answers {
            task: task.kind(),
            outcomes,
            requests,
        }
    }
}

fn invalid<I>(reason: String) -> Outcome<I> {
    Outcome::Unanswered(Unanswered {
        kind: UnansweredKind::Invalid,
        reason,
    })
}

enum Checked<K: Ord, I> {
    /// Refused or truncated: not asked again.
    Unusable(Unanswered),
    Validated(Validation<K, I>),
}

/// Parses and validates one answer against the task's questions.
fn check<T: Task>(task: &T, content: &AnswerContent, keys: &[T::Key]) -> Checked<T::Key, T::Item> {
    let mut v = Validation::new();
    match content {
        AnswerContent::Refusal { text } => {
            return Checked::Unusable(Unanswered {
                kind: UnansweredKind::Refused,
                reason: text.clone(),
            });
        }
        AnswerContent::Truncated { text } => {
            return Checked::Unusable(Unanswered {
                kind: UnansweredKind::Truncated,
                reason: format!(
                    "the reply stopped at the token limit (finish_reason \"length\") after {} characters",
                    text.chars().count()
                ),
            });
        }
        AnswerContent::NotJson { error, .. } => {
            v.general_problem(format!("the answer is not valid JSON ({error})"));
        }
        AnswerContent::Json { value } => match serde_json::from_value::<T::Response>(value.clone()) {
            Ok(response) => task.validate(response, &mut v),
            Err(e) => v.general_problem(format!("the answer does not follow the response schema ({e})")),
        },
    }
    v.finish(keys);
    Checked::Validated(v)
}

/// The previous answer as shown in the re-ask note.
fn previous_answer_text(content: &AnswerContent) -> String {
    match content {
        AnswerContent::Json { value } => value.to_string(),
        AnswerContent::NotJson { text, .. }
        | AnswerContent::Refusal { text }
        | AnswerContent::Truncated { text } => text.clone(),
    }
}
