//! What asking costs: [`TokenUsage`] (tokens of one request, or summed) and [`Usage`] (requests,
//! cache hits, re-asks, outcomes and tokens of a session), the one usage type of the VLM layer
//! and of the reports (`vlm_usage` in `eval.json`).

use std::sync::atomic::{AtomicU64, Ordering};

use serde::{Deserialize, Serialize};

/// Token counts of one request, or summed over many.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct TokenUsage {
    /// Input tokens (text and images).
    pub prompt_tokens: u64,
    /// Output tokens.
    pub completion_tokens: u64,
}

impl TokenUsage {
    /// Input plus output tokens.
    pub fn total(&self) -> u64 {
        self.prompt_tokens + self.completion_tokens
    }
}

impl std::ops::AddAssign for TokenUsage {
    fn add_assign(&mut self, rhs: TokenUsage) {
        self.prompt_tokens += rhs.prompt_tokens;
        self.completion_tokens += rhs.completion_tokens;
    }
}

/// Usage of a [`crate::Session`] so far: requests, cache hits, re-asks, recoveries, outcomes and
/// tokens.
///
/// Tokens are counted separately for answers obtained now (what the run cost) and answers read
/// from the cache (what they cost when they were first obtained).
///
/// Serialised flat, as `vlm_usage` in a scene's `eval.json`, with what the scene's result rests
/// on and nothing that depends on the run that produced it, so that a scene answered partly
/// from the cache has the same record as one answered afresh: `requests`, `failed_requests`,
/// `re_asks`, `re_asked_questions`, `paired_by_position`, `unmatched_not_offered`,
/// `answered`, `unanswered`, and `prompt_tokens` and `completion_tokens` of every answer used
/// (fresh and cached). `cache_hits` and the split of the tokens between fresh and cached
/// answers are not written (a run reports them as it goes); read back, the tokens are all in
/// [`Usage::tokens`].
///
/// ```
/// use sceneeval_vlm::{TokenUsage, Usage};
/// let usage = Usage {
///     requests: 3,
///     cache_hits: 1,
///     tokens: TokenUsage { prompt_tokens: 120, completion_tokens: 9 },
///     cached_tokens: TokenUsage { prompt_tokens: 60, completion_tokens: 4 },
///     ..Usage::default()
/// };
/// assert_eq!(
///     serde_json::to_string(&usage).unwrap(),
///     r#"{"requests":3,"failed_requests":0,"re_asks":0,"re_asked_questions":0,"paired_by_position":0,"unmatched_not_offered":0,"answered":0,"unanswered":0,"prompt_tokens":180,"completion_tokens":13}"#
/// );
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(into = "UsageRecord", from = "UsageRecord")]
pub struct Usage {
    /// Requests answered (fresh and cached; failed requests not included).
    pub requests: u64,
    /// Requests answered from the cache (not serialised).
    pub cache_hits: u64,
    /// Requests that failed with an error.
    pub failed_requests: u64,
    /// Tasks asked a second time because some question had no valid answer.
    pub re_asks: u64,
    /// Questions asked a second time (a re-ask asks only the questions without a valid
    /// answer when the task can be narrowed to them).
    pub re_asked_questions: u64,
    /// Answers paired with their question by position because the model left the key empty
    /// or out (in an answer with one item per question).
    pub paired_by_position: u64,
    /// Questions recorded as "none of the offered categories" because the model named a
    /// category that was not offered, and did so again when asked again.
    pub unmatched_not_offered: u64,
    /// Questions answered validly.
    pub answered: u64,
    /// Questions recorded as unanswered.
    pub unanswered: u64,
    /// Tokens of the answers obtained now (serialised together with [`Usage::cached_tokens`]).
    pub tokens: TokenUsage,
    /// Tokens of the answers read from the cache.
    pub cached_tokens: TokenUsage,
}

impl Usage {
    /// Tokens of every answer used, fresh and cached.
    pub fn all_tokens(&self) -> TokenUsage {
        let mut t = self.tokens;
        t += self.cached_tokens;
        t
    }
}

/// [`Usage`] as written into records (see its docs).
#[derive(Serialize, Deserialize)]
#[serde(default)]
#[derive(Default)]
struct UsageRecord {
    requests: u64,
    failed_requests: u64,
    re_asks: u64,
    re_asked_questions: u64,
    paired_by_position: u64,
    unmatched_not_offered: u64,
    answered: u64,
    unanswered: u64,
    prompt_tokens: u64,
    completion_tokens: u64,
}

impl From<Usage> for UsageRecord {
    fn from(u: Usage) -> Self {
        let t = u.all_tokens();
        UsageRecord {
            requests: u.requests,
            failed_requests: u.failed_requests,
            re_asks: u.re_asks,
            re_asked_questions: u.re_asked_questions,
            paired_by_position: u.paired_by_position,
            unmatched_not_offered: u.unmatched_not_offered,
            answered: u.answered,
            unanswered: u.unanswered,
            prompt_tokens: t.prompt_tokens,
            completion_tokens: t.completion_tokens,
        }
    }
}

impl From<UsageRecord> for Usage {
    fn from(r: UsageRecord) -> Self {
        Usage {
            requests: r.requests,
            cache_hits: 0,
            failed_requests: r.failed_requests,
            re_asks: r.re_asks,
            re_asked_questions: r.re_asked_questions,
            paired_by_position: r.paired_by_position,
            unmatched_not_offered: r.unmatched_not_offered,
            answered: r.answered,
            unanswered: r.unanswered,
            tokens: TokenUsage {
                prompt_tokens: r.prompt_tokens,
                completion_tokens: r.completion_tokens,
            },
            cached_tokens: TokenUsage::default(),
        }
    }
}

/// The counters behind [`Usage`], shared by concurrent requests: a [`crate::Session`]'s, or
/// a whole run's (the facade's shared model counts every scene's answers with one).
///
/// ```
/// use sceneeval_vlm::{Meter, TokenUsage};
/// let meter = Meter::default();
/// meter.answer(TokenUsage { prompt_tokens: 10, completion_tokens: 2 }, false);
/// meter.answer(TokenUsage { prompt_tokens: 10, completion_tokens: 2 }, true);
/// meter.failure();
/// let usage = meter.usage();
/// assert_eq!((usage.requests, usage.cache_hits, usage.failed_requests), (2, 1, 1));
/// assert_eq!(usage.tokens.total() + usage.cached_tokens.total(), 24);
/// ```
#[derive(Debug, Default)]
pub struct Meter {
    requests: AtomicU64,
    cache_hits: AtomicU64,
    failed_requests: AtomicU64,
    re_asks: AtomicU64,
    re_asked_questions: AtomicU64,
    paired_by_position: AtomicU64,
    unmatched_not_offered: AtomicU64,
    answered: AtomicU64,
    unanswered: AtomicU64,
    prompt_tokens: AtomicU64,
    completion_tokens: AtomicU64,
    cached_prompt_tokens: AtomicU64,
    cached_completion_tokens: AtomicU64,
}

impl Meter {
    /// An answer received, fresh or from the cache, with the tokens it used.
    pub fn answer(&self, usage: TokenUsage, from_cache: bool) {
        self.requests.fetch_add(1, Ordering::Relaxed);
        let (p, c) = if from_cache {
            self.cache_hits.fetch_add(1, Ordering::Relaxed);
            (&self.cached_prompt_tokens, &self.cached_completion_tokens)
        } else {
            (&self.prompt_tokens, &self.completion_tokens)
        };
        p.fetch_add(usage.prompt_tokens, Ordering::Relaxed);
        c.fetch_add(usage.completion_tokens, Ordering::Relaxed);
    }

    /// A request that got no answer.
    pub fn failure(&self) {
        self.failed_requests.fetch_add(1, Ordering::Relaxed);
    }

    /// A task asked a second time, for `questions` of its questions.
    pub fn re_ask(&self, questions: u64) {
        self.re_asks.fetch_add(1, Ordering::Relaxed);
        self.re_asked_questions.fetch_add(questions, Ordering::Relaxed);
    }

    /// Answers paired by position, and questions recorded as unmatched after naming a
    /// category not offered.
    pub fn recoveries(&self, paired_by_position: u64, unmatched_not_offered: u64) {
        self.paired_by_position
            .fetch_add(paired_by_position, Ordering::Relaxed);
        self.unmatched_not_offered
            .fetch_add(unmatched_not_offered, Ordering::Relaxed);
    }

    /// The outcomes of a task's questions.
    pub fn outcomes(&self, answered: u64, unanswered: u64) {
        self.answered.fetch_add(answered, Ordering::Relaxed);
        self.unanswered.fetch_add(unanswered, Ordering::Relaxed);
    }

    /// The counts so far.
    pub fn usage(&self) -> Usage {
        let get = |a: &AtomicU64| a.load(Ordering::Relaxed);
        Usage {
            requests: get(&self.requests),
            cache_hits: get(&self.cache_hits),
            failed_requests: get(&self.failed_requests),
            re_asks: get(&self.re_asks),
            re_asked_questions: get(&self.re_asked_questions),
            paired_by_position: get(&self.paired_by_position),
            unmatched_not_offered: get(&self.unmatched_not_offered),
            answered: get(&self.answered),
            unanswered: get(&self.unanswered),
            tokens: TokenUsage {
                prompt_tokens: get(&self.prompt_tokens),
                completion_tokens: get(&self.completion_tokens),
            },
            cached_tokens: TokenUsage {
                prompt_tokens: get(&self.cached_prompt_tokens),
                completion_tokens: get(&self.cached_completion_tokens),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn usage_adds() {
        let mut u = TokenUsage {
            prompt_tokens: 10,
            completion_tokens: 2,
        };
        u += TokenUsage {
            prompt_tokens: 5,
            completion_tokens: 1,
        };
        assert_eq!((u.prompt_tokens, u.completion_tokens, u.total()), (15, 3, 18));
    }

    #[test]
    fn the_meter_counts_fresh_and_cached_tokens_apart() {
        let m = Meter::default();
        let t = |p, c| TokenUsage {
            prompt_tokens: p,
            completion_tokens: c,
        };
        m.answer(t(100, 10), false);
        m.answer(t(50, 5), true);
        m.failure();
        m.re_ask(2);
        m.recoveries(1, 1);
        m.outcomes(3, 1);
        let u = m.usage();
        assert_eq!(
            (
                u.requests,
                u.cache_hits,
                u.failed_requests,
                u.re_asks,
                u.answered,
                u.unanswered
            ),
            (2, 1, 1, 1, 3, 1)
        );
        assert_eq!((u.tokens, u.cached_tokens), (t(100, 10), t(50, 5)));
        assert_eq!(
            (
                u.re_asked_questions,
                u.paired_by_position,
                u.unmatched_not_offered
            ),
            (2, 1, 1)
        );
        // Read back from a record: every count but the cache hits, all tokens together.
        let back: Usage = serde_json::from_str(&serde_json::to_string(&u).unwrap()).unwrap();
        assert_eq!(
            back,
            Usage {
                cache_hits: 0,
                tokens: t(150, 15),
                cached_tokens: TokenUsage::default(),
                ..u
            }
        );
        // A record of an earlier version (with `cache_hits`, without the recoveries) reads.
        let old: Usage = serde_json::from_str(
            r#"{"requests":2,"cache_hits":1,"failed_requests":0,"re_asks":1,"answered":3,"unanswered":0,"prompt_tokens":5,"completion_tokens":1}"#,
        )
        .unwrap();
        assert_eq!((old.requests, old.re_asks, old.tokens), (2, 1, t(5, 1)));
    }
}
