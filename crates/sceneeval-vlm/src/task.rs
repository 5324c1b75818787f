//! The [`Task`] trait and the per-question outcome of asking one.

use std::collections::BTreeMap;
use std::fmt;

use schemars::JsonSchema;
use serde::Serialize;
use serde::de::DeserializeOwned;

use crate::PngImage;
use crate::TaskKind;
use crate::prompt::Template;

/// How the note of an answer paired by position starts.
pub(crate) const PAIRED_BY_POSITION: &str = "paired by position";

/// A typed task: the questions it asks, how its prompt is filled, the wire type of the answer
/// (whose strict JSON Schema is sent) and how an answer is validated and paired with the
/// questions.
///
/// A task asks one or more *questions*, each identified by a key (an object id, a relation key,
/// an (instance, attribute) pair; `()` for single-question tasks). Validation turns the wire
/// answer into one validated item per key and reports problems per key; answers are paired with
/// questions by key; by position only for items whose key is empty or missing in an answer with
/// exactly one item per question ([`Validation::pair_items`]). [`crate::Session::ask`] runs the
/// whole protocol (ask, validate, re-ask once for the questions still without a valid answer,
/// record the rest as unanswered).
pub trait Task: Sync {
    /// The answer as the model writes it (the reference's field names).
    type Response: DeserializeOwned + JsonSchema;
    /// What identifies one question.
    type Key: Clone + Ord + fmt::Debug + fmt::Display + Send + Sync;
    /// One validated answer.
    type Item: Clone + fmt::Debug + Send;

    /// Which task this is.
    fn kind(&self) -> TaskKind;
    /// The template of the user message: by default the task's own
    /// ([`Template::Task`]).
    fn template(&self) -> Template {
        Template::Task(self.kind())
    }
    /// The system prompt: by default every evaluation task's ([`Template::System`]).
    fn system_template(&self) -> Template {
        Template::System
    }
    /// The placeholder values of the template (names without angle brackets); none by
    /// default.
    fn placeholders(&self) -> Vec<(&'static str, String)> {
        Vec::new()
    }
    /// The images, in order; none by default.
    fn images(&self) -> Vec<PngImage> {
        Vec::new()
    }
    /// The questions, in order.
    fn keys(&self) -> Vec<Self::Key>;
    /// Checks an answer and pairs its parts with the questions.
    fn validate(&self, response: Self::Response, out: &mut Validation<Self::Key, Self::Item>);

    /// The same task asking only `keys` (some of its questions, in question order), with the
    /// same keys: what [`crate::Session::ask`] asks again when an answer left only these
    /// questions without a valid answer. `None` (the default) asks the whole task again.
    fn narrowed(&self, keys: &[Self::Key]) -> Option<Self>
    where
        Self: Sized,
    {
        let _ = keys;
        None
    }
}

/// What validating one answer found: the valid items by key, and the problems, by key or for
/// the answer as a whole.
#[derive(Debug, Clone)]
pub struct Validation<K: Ord, I> {
    items: BTreeMap<K, I>,
    problems: BTreeMap<K, Vec<String>>,
    general: Vec<String>,
    /// Questions whose item was paired by position, with the note for the evidence.
    by_position: BTreeMap<K, String>,
    /// What to record for a question whose answer named a category that was not offered, if
    /// it is still invalid after the re-ask: the unmatched item and the note.
    not_offered: BTreeMap<K, (I, String)>,
}

impl<K: Ord + Clone + fmt::Display, I> Default for Validation<K, I> {
    fn default() -> Self {
        Validation::new()
    }
}

impl<K: Ord + Clone + fmt::Display, I> Validation<K, I> {
    /// Nothing found yet.
    pub fn new() -> Self {
        Validation {
            items: BTreeMap::new(),
            problems: BTreeMap::new(),
            general: Vec::new(),
            by_position: BTreeMap::new(),
            not_offered: BTreeMap::new(),
        }
    }

    /// Pairs the items of a list answer with the questions `keys`: an item whose echoed key
    /// (`echoed`; `None` or blank when the model left it empty or out) names a question goes
    /// to that question (`find`: the question an echoed key names); an item without a key goes
    /// to the question at its position, but only when the answer has exactly one item per
    /// question (the model kept the prompt's order but did not copy the keys). An echoed key
    /// that names no question, or an item without a key in an answer of another length, is a
    /// problem with the answer as a whole (`field` names the key field in the message). Items
    /// paired by position are noted, and counted in [`crate::Usage::paired_by_position`].
    ///
    /// ```
    /// use sceneeval_vlm::Validation;
    /// let keys = vec!["a".to_owned(), "b".to_owned()];
    /// let mut v: Validation<String, u32> = Validation::new();
    /// let items = vec![(None, 1), (Some("  "), 2)];
    /// let pairs = v.pair_items(&keys, items, |i| i.0, |k| keys.iter().find(|q| q.as_str() == k).cloned(), "key");
    /// assert_eq!(pairs.iter().map(|(k, i)| (k.as_str(), i.1)).collect::<Vec<_>>(), [("a", 1), ("b", 2)]);
    /// // An unknown key stays an error, and without one item per question nothing is paired by position.
    /// let pairs = v.pair_items(&keys, vec![(Some("c"), 3), (None, 4), (None, 5)], |i| i.0, |_| None, "key");
    /// assert!(pairs.is_empty());
    /// assert_eq!(v.general_problems().len(), 3);
    /// ```
    pub fn pair_items<A>(
        &mut self,
        keys: &[K],
        items: Vec<A>,
        echoed: impl Fn(&A) -> Option<&str>,
        find: impl Fn(&str) -> Option<K>,
        field: &str,
    ) -> Vec<(K, A)> {
        let n = items.len();
        let by_position = n == keys.len();
        let mut pairs = Vec::with_capacity(items.len());
        for (i, item) in items.into_iter().enumerate() {
            match echoed(&item).map(str::trim).filter(|k| !k.is_empty()) {
                Some(k) => match find(k) {
                    Some(key) => pairs.push((key, item)),
                    None => self.general_problem(format!(
                        "an item has {field} {k:?}, which is not one of the {field}s asked about"
                    )),
                },
                None if by_position => {
                    self.note_paired_by_position(keys[i].clone(), i, field);
                    pairs.push((keys[i].clone(), item));
                }
                None => self.general_problem(format!(
                    "item {i} has no {field}, and the answer has {n} items for {} questions, so it \
                     cannot be paired by position; copy each {field} from the prompt",
                    keys.len()
                )),
            }
        }
        pairs
    }

    /// A valid answer to question `key`. A second answer to the same question makes both
    /// invalid ("answered more than once").
    pub fn answer(&mut self, key: K, item: I) {
        // A question with an item or a problem already has an answer: this is the second.
        if self.items.remove(&key).is_some() || self.problems.contains_key(&key) {
            self.problem(
                key,
                "answered more than once; answer each question exactly once".to_owned(),
            );
        } else {
            self.items.insert(key, item);
        }
    }

    /// A problem with the answer to question `key`; the question counts as unanswered in this
    /// attempt.
    pub fn problem(&mut self, key: K, message: String) {
        self.items.remove(&key);
        let list = self.problems.entry(key).or_default();
        if !list.contains(&message) {
            list.push(message);
        }
    }

    /// A problem with the answer as a whole (not JSON, not the schema, an answer to a question
    /// that was not asked).
    pub fn general_problem(&mut self, message: String) {
        self.general.push(message);
    }

    /// An answer to question `key` that names a category that was not offered: a problem (the
    /// question is asked again), and `unmatched`, the answer "none of the offered categories",
    /// to record with `problem` as its note if the answer to the re-asked question is no better
    /// (counted in [`crate::Usage::unmatched_not_offered`]).
    pub fn not_offered(&mut self, key: K, problem: String, unmatched: I) {
        self.problem(key.clone(), problem.clone());
        self.not_offered.insert(key, (unmatched, problem));
    }

    /// The valid item for `key`, if any.
    pub fn item(&self, key: &K) -> Option<&I> {
        self.items.get(key)
    }

    /// The problems with the answer to `key`.
    pub fn problems_for(&self, key: &K) -> &[String] {
        self.problems.get(key).map(Vec::as_slice).unwrap_or(&[])
    }

    /// The problems with the answer as a whole.
    pub fn general_problems(&self) -> &[String] {
        &self.general
    }

    /// Notes that the item for `key` was item `position` of the answer, paired by position
    /// because it had no `field`.
    pub(crate) fn note_paired_by_position(&mut self, key: K, position: usize, field: &str) {
        self.by_position.insert(
            key,
            format!("{PAIRED_BY_POSITION}: item {position} of the answer had no {field}"),
        );
    }

    /// How the item for `key` was paired, when by position.
    pub fn paired_by_position(&self, key: &K) -> Option<&str> {
        self.by_position.get(key).map(String::as_str)
    }

    /// Whether some question has a valid item: the answer is usable (and worth caching).
    pub(crate) fn has_items(&self) -> bool {
        !self.items.is_empty()
    }

    /// The keys of `keys` without a valid item, in order.
    pub(crate) fn missing(&self, keys: &[K]) -> Vec<K> {
        keys.iter()
            .filter(|k| !self.items.contains_key(k))
            .cloned()
            .collect()
    }

    /// What to record for `key` when its answer named a category that was not offered.
    pub(crate) fn take_not_offered(&mut self, key: &K) -> Option<(I, String)> {
        self.not_offered.remove(key)
    }

    /// Marks every key of `keys` that has neither an item nor a problem as not answered.
    pub(crate) fn finish(&mut self, keys: &[K]) {
        for key in keys {
            if !self.items.contains_key(key) && !self.problems.contains_key(key) {
                self.problems
                    .insert(key.clone(), vec![format!("no answer for {key}")]);
            }
        }
    }

    /// Whether every key of `keys` has a valid item.
    pub(crate) fn complete(&self, keys: &[K]) -> bool {
        keys.iter().all(|k| self.items.contains_key(k))
    }

    /// All problems as lines for the re-ask note: per question, then general.
    pub(crate) fn problem_lines(&self) -> Vec<String> {
        let mut lines: Vec<String> = self
            .problems
            .iter()
            .flat_map(|(k, ps)| ps.iter().map(move |p| format!("{k}: {p}")))
            .collect();
        lines.extend(self.general.iter().cloned());
        lines
    }

    /// The reason a question counts as unanswered after this attempt.
    pub(crate) fn reason_for(&self, key: &K) -> String {
        let mut parts: Vec<String> = self.problems_for(key).to_vec();
        parts.extend(self.general.iter().cloned());
        if parts.is_empty() {
            parts.push(format!("no answer for {key}"));
        }
        parts.join("; ")
    }

    pub(crate) fn take_item(&mut self, key: &K) -> Option<I> {
        self.items.remove(key)
    }
}

/// Why a question has no usable answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum UnansweredKind {
    /// The answer was invalid, and so was the answer to the re-asked question.
    Invalid,
    /// The model refused to answer.
    Refused,
    /// The answer was cut off at the token limit.
    Truncated,
}

/// A question without a usable answer, with the reason.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Unanswered {
    /// Why.
    pub kind: UnansweredKind,
    /// What was wrong, in words (the validation problems, the refusal text, ...).
    pub reason: String,
}

impl fmt::Display for Unanswered {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let what = match self.kind {
            UnansweredKind::Invalid => "invalid answer",
            UnansweredKind::Refused => "the model refused",
            UnansweredKind::Truncated => "the answer was truncated",
        };
        write!(f, "{what}: {}", self.reason)
    }
}

/// The outcome of one question: a validated answer or the reason there is none.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Outcome<I> {
    /// A valid answer.
    Answered {
        /// The validated answer.
        answer: I,
        /// 1 when the first answer was valid, 2 when the re-asked one was.
        attempt: u8,
        /// How an imperfect answer was recovered, when it was: paired by position (the model
        /// left the key empty), or recorded as unmatched after naming a category that was not
        /// offered twice.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        note: Option<String>,
    },
    /// No usable answer.
    Unanswered(Unanswered),
}

impl<I> Outcome<I> {
    /// The answer, if there is one.
    pub fn answer(&self) -> Option<&I> {
        match self {
            Outcome::Answered { answer, .. } => Some(answer),
            Outcome::Unanswered(_) => None,
        }
    }

    /// The answer, or why there is none.
    pub fn into_result(self) -> Result<I, Unanswered> {
        match self {
            Outcome::Answered { answer, .. } => Ok(answer),
            Outcome::Unanswered(u) => Err(u),
        }
    }

    /// Whether there is an answer.
    pub fn is_answered(&self) -> bool {
        matches!(self, Outcome::Answered { .. })
    }
}

/// The outcomes of all questions of one task, in question order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Answers<K, I> {
    /// The task.
    pub task: TaskKind,
    /// One outcome per question, in the task's question order.
    pub outcomes: Vec<(K, Outcome<I>)>,
    /// How many requests were sent: 1, or 2 when the task was asked again.
    pub requests: u8,
}

impl<K: PartialEq, I> Answers<K, I> {
    /// The outcome of question `key`.
    pub fn get(&self, key: &K) -> Option<&Outcome<I>> {
        self.outcomes.iter().find(|(k, _)| k == key).map(|(_, o)| o)
    }

    /// The answered questions and their answers.
    pub fn answered(&self) -> impl Iterator<Item = (&K, &I)> {
        self.outcomes
            .iter()
            .filter_map(|(k, o)| o.answer().map(|a| (k, a)))
    }

    /// The unanswered questions and why.
    pub fn unanswered(&self) -> impl Iterator<Item = (&K, &Unanswered)> {
        self.outcomes.iter().filter_map(|(k, o)| match o {
            Outcome::Unanswered(u) => Some((k, u)),
            Outcome::Answered { .. } => None,
        })
    }

    /// The outcome of a single-question task (the first question's outcome).
    pub fn into_single(self) -> Option<Outcome<I>> {
        self.outcomes.into_iter().next().map(|(_, o)| o)
    }
}

/// The key of the only question of a single-question task.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct Single;

impl fmt::Display for Single {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("the answer")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outcomes_serialise_with_a_status_tag() {
        let answered: Outcome<u32> = Outcome::Answered {
            answer: 7,
            attempt: 2,
            note: None,
        };
        assert_eq!(
            serde_json::to_value(&answered).unwrap(),
            serde_json::json!({"status": "answered", "answer": 7, "attempt": 2})
        );
        let refused: Outcome<u32> = Outcome::Unanswered(Unanswered {
            kind: UnansweredKind::Refused,
            reason: "no".into(),
        });
        assert_eq!(
            serde_json::to_value(&refused).unwrap(),
            serde_json::json!({"status": "unanswered", "kind": "refused", "reason": "no"})
        );
        assert_eq!(
            refused.to_owned().into_result().unwrap_err().to_string(),
            "the model refused: no"
        );
    }

    #[test]
    fn duplicates_invalidate_the_question() {
        let mut v: Validation<String, u32> = Validation::new();
        v.answer("a".into(), 1);
        v.answer("b".into(), 2);
        v.answer("a".into(), 3);
        v.answer("a".into(), 4);
        assert!(v.item(&"a".to_owned()).is_none());
        assert_eq!(v.problems_for(&"a".to_owned()).len(), 1);
        assert_eq!(v.item(&"b".to_owned()), Some(&2));
        // A valid answer after an invalid one to the same question is a duplicate too.
        v.problem("c".into(), "bad side".into());
        v.answer("c".into(), 5);
        assert!(v.item(&"c".to_owned()).is_none());
        assert_eq!(v.problems_for(&"c".to_owned()).len(), 2);
        v.finish(&["a".into(), "b".into(), "c".into(), "d".into()]);
        assert_eq!(v.problems_for(&"d".to_owned()), ["no answer for d"]);
        assert!(!v.complete(&["b".into(), "d".into()]));
        assert!(v.complete(&["b".into()]));
    }
}
