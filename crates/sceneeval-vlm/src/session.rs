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
/// 1. The task's request is sent (its system prompt, filled template, images, strict schema).
/// 2. The answer is parsed into the task's response type and validated; each part is paired
///    with its question by key, or by position when the model left the keys empty in an
///    answer with one item per question ([`Validation::pair_items`]; noted and counted).
/// 3. If some question has no valid answer, it is asked **once** more, with the list of
///    problems and the previous answer appended to the text (the [`Template::Reask`] note);
///    when the task can be narrowed ([`Task::narrowed`]) only the questions without a valid
///    answer are asked. Each question keeps its first valid answer.
/// 4. A question still without a valid answer is recorded as [`Unanswered`] with the reason,
///    except a category that was not offered, named again: that question is answered "none of
///    the offered categories" with the reason as its note. A refused or truncated answer is
///    recorded at once (asking the same again would not help).
/// 5. The model is told whether each answer was usable ([`Vlm::judged`]), so that a cache
///    keeps only usable answers; a cached answer that is not usable is asked afresh once.
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
            system: self.prompts.text(task.system_template()).to_owned(),
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
        let (first, checked) = self.send_checked(task, &request, &keys, 1).await?;
        let mut v1 = match checked {
            Checked::Unusable(why) => {
                tracing::warn!(task = %task.kind(), reason = %why, "no usable answer");
                let outcomes = keys
                    .into_iter()
                    .map(|k| (k, Outcome::Unanswered(why.clone())))
                    .collect();
                return Ok(self.collect(task, outcomes, 1, Recoveries::default()));
            }
            Checked::Validated(v) => v,
        };
        let mut recoveries = Recoveries::default();
        if v1.complete(&keys) {
            let outcomes = keys
                .into_iter()
                .map(|key| {
                    let o = match v1.take_item(&key) {
                        Some(answer) => Outcome::Answered {
                            answer,
                            attempt: 1,
                            note: recoveries.by_position(&v1, &key),
                        },
                        None => invalid(v1.reason_for(&key)),
                    };
                    (key, o)
                })
                .collect();
            return Ok(self.collect(task, outcomes, 1, recoveries));
        }

        // Ask again, for the questions still without a valid answer only when the task can be
        // narrowed to them.
        let missing = v1.missing(&keys);
        let problems = v1.problem_lines();
        tracing::warn!(task = %task.kind(), ?problems, questions = missing.len(), "invalid answer; asking again once");
        self.meter.re_ask(missing.len() as u64);
        let narrowed = (missing.len() < keys.len())
            .then(|| task.narrowed(&missing))
            .flatten();
        let problem_list: Vec<String> = problems.iter().map(|p| format!("- {p}")).collect();
        let note = self.prompts.fill(
            Template::Reask,
            &[
                ("PROBLEMS", &problem_list.join("\n")),
                ("PREVIOUS_ANSWER", &previous_answer_text(&first.content)),
            ],
        )?;
        let (mut again, second) = match &narrowed {
            Some(n) => {
                let r = self.request(n)?;
                let keys2 = n.keys();
                (r, (n, keys2))
            }
            None => (request, (task, keys.clone())),
        };
        again.user_text = format!("{}\n\n{note}", again.user_text);
        let (second_task, second_keys) = second;
        let (_, mut checked2) = self.send_checked(second_task, &again, &second_keys, 2).await?;
        let outcomes = keys
            .into_iter()
            .map(|key| {
                if let Some(answer) = v1.take_item(&key) {
                    let note = recoveries.by_position(&v1, &key);
                    return (
                        key,
                        Outcome::Answered {
                            answer,
                            attempt: 1,
                            note,
                        },
                    );
                }
                let (second_reason, second_unmatched) = match &mut checked2 {
                    Checked::Unusable(why) => (why.to_string(), None),
                    Checked::Validated(v2) => {
                        if let Some(answer) = v2.take_item(&key) {
                            let note = recoveries.by_position(v2, &key);
                            return (
                                key,
                                Outcome::Answered {
                                    answer,
                                    attempt: 2,
                                    note,
                                },
                            );
                        }
                        (v2.reason_for(&key), v2.take_not_offered(&key))
                    }
                };
                // A category not offered, named again (or the second answer unusable): the
                // question is answered "none of the offered categories", with the reason.
                if let Some((answer, problem)) = second_unmatched.or_else(|| v1.take_not_offered(&key)) {
                    let note =
                        format!("recorded as none of the offered categories after asking twice: {problem}");
                    recoveries.unmatched_not_offered += 1;
                    return (
                        key,
                        Outcome::Answered {
                            answer,
                            attempt: 2,
                            note: Some(note),
                        },
                    );
                }
                let o = invalid(format!(
                    "asked twice; second answer: {second_reason}; first answer: {}",
                    v1.reason_for(&key)
                ));
                (key, o)
            })
            .collect();
        Ok(self.collect(task, outcomes, 2, recoveries))
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

    /// Sends `request` (asking `task`'s questions `keys`), checks the answer and tells the
    /// model whether it was usable ([`Vlm::judged`]: a cache keeps only usable answers). A
    /// cached answer that is not usable (a cache of an earlier version) is asked afresh once.
    async fn send_checked<T: Task>(
        &self,
        task: &T,
        request: &VlmRequest,
        keys: &[T::Key],
        attempt: u8,
    ) -> Result<(Answer, Checked<T::Key, T::Item>), VlmError> {
        let mut answer = self.send(request, attempt).await?;
        let mut checked = check(task, &answer.content, keys);
        let usable = |c: &Checked<T::Key, T::Item>| matches!(c, Checked::Validated(v) if v.has_items());
        self.vlm.judged(request, &answer, usable(&checked));
        if answer.from_cache && !usable(&checked) {
            tracing::info!(task = %request.task, "the cached answer is not usable; asking afresh");
            answer = self.send(request, attempt).await?;
            checked = check(task, &answer.content, keys);
            self.vlm.judged(request, &answer, usable(&checked));
        }
        Ok((answer, checked))
    }

    /// The answers of a task from the outcome of every question, in question order; counts
    /// them.
    fn collect<T: Task>(
        &self,
        task: &T,
        outcomes: Vec<(T::Key, Outcome<T::Item>)>,
        requests: u8,
        recoveries: Recoveries,
    ) -> Answers<T::Key, T::Item> {
        let mut answered = 0;
        for (key, o) in &outcomes {
            match o {
                Outcome::Unanswered(why) => {
                    tracing::warn!(task = %task.kind(), question = %key, reason = %why, "question unanswered");
                }
                Outcome::Answered { note: Some(note), .. } => {
                    answered += 1;
                    tracing::info!(task = %task.kind(), question = %key, %note, "imperfect answer recovered");
                }
                Outcome::Answered { .. } => answered += 1,
            }
        }
        self.meter.outcomes(answered, outcomes.len() as u64 - answered);
        self.meter
            .recoveries(recoveries.paired_by_position, recoveries.unmatched_not_offered);
        Answers {
            task: task.kind(),
            outcomes,
            requests,
        }
    }
}

/// The recoveries of one task's answers, counted as its outcomes are decided.
#[derive(Debug, Default)]
struct Recoveries {
    paired_by_position: u64,
    unmatched_not_offered: u64,
}

impl Recoveries {
    /// The note of the item for `key` of `v` when it was paired by position (counted).
    fn by_position<K: Ord + Clone + std::fmt::Display, I>(
        &mut self,
        v: &Validation<K, I>,
        key: &K,
    ) -> Option<String> {
        let note = v.paired_by_position(key).map(str::to_owned);
        self.paired_by_position += u64::from(note.is_some());
        note
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
