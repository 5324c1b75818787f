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

/// Usage of a [`crate::Session`] so far: requests, cache hits, re-asks, outcomes and tokens.
///
/// Tokens are counted separately for answers obtained now (what the run cost) and answers read
/// from the cache (what they cost when they were first obtained).
///
/// Serialised flat, as `vlm_usage` in a scene's `eval.json`: `requests`, `cache_hits`,
/// `failed_requests`, `re_asks`, `answered`, `unanswered`, `prompt_tokens`,
/// `completion_tokens` (the tokens obtained now). `cached_tokens` is not written: what a
/// cached answer cost is in its cache file, and a record states what its run spent.
///
/// ```
/// use sceneeval_vlm::{TokenUsage, Usage};
/// let usage = Usage {
///     requests: 3,
///     cache_hits: 1,
///     tokens: TokenUsage { prompt_tokens: 120, completion_tokens: 9 },
///     ..Usage::default()
/// };
/// assert_eq!(
///     serde_json::to_string(&usage).unwrap(),
///     r#"{"requests":3,"cache_hits":1,"failed_requests":0,"re_asks":0,"answered":0,"unanswered":0,"prompt_tokens":120,"completion_tokens":9}"#
/// );
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Usage {
    /// Requests answered (fresh and cached; failed requests not included).
    pub requests: u64,
    /// Requests answered from the cache.
    pub cache_hits: u64,
    /// Requests that failed with an error.
    pub failed_requests: u64,
    /// Tasks asked a second time because of an invalid answer.
    pub re_asks: u64,
    /// Questions answered validly.
    pub answered: u64,
    /// Questions recorded as unanswered.
    pub unanswered: u64,
    /// Tokens of the answers obtained now.
    #[serde(flatten)]
    pub tokens: TokenUsage,
    /// Tokens of the answers read from the cache (not serialised).
    #[serde(skip)]
    pub cached_tokens: TokenUsage,
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

    /// A task asked a second time.
    pub fn re_ask(&self) {
        self.re_asks.fetch_add(1, Ordering::Relaxed);
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
        m.re_ask();
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
        // Read back from a record: everything but the cached tokens.
        let back: Usage = serde_json::from_str(&serde_json::to_string(&u).unwrap()).unwrap();
        assert_eq!(
            back,
            Usage {
                cached_tokens: TokenUsage::default(),
                ..u
            }
        );
    }
}
