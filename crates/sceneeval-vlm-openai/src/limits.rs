//! When a request may start: the concurrency limit that halves on 429 and grows back, the
//! client's own requests- and tokens-per-minute caps, and the server's `x-ratelimit-*` headers.

use std::sync::Mutex;
use std::time::{Duration, Instant};

use reqwest::header::HeaderMap;
use tokio::sync::Notify;

/// A duration in OpenAI's `x-ratelimit-reset-*` format (Go's): numbers with units `h`, `m`,
/// `s`, `ms`, `us` (or `µs`) and `ns`, run together (`6m0s`, `1s`, `20ms`, `1m30.5s`), or a bare
/// number of seconds (`2`, `0.5`, as some compatible servers write it). `None` for anything
/// else.
///
/// ```
/// use std::time::Duration;
/// use sceneeval_vlm_openai::parse_reset_duration;
/// assert_eq!(parse_reset_duration("6m0s"), Some(Duration::from_secs(360)));
/// assert_eq!(parse_reset_duration("20ms"), Some(Duration::from_millis(20)));
/// assert_eq!(parse_reset_duration("1m30.5s"), Some(Duration::from_millis(90_500)));
/// assert_eq!(parse_reset_duration("soon"), None);
/// ```
pub fn parse_reset_duration(text: &str) -> Option<Duration> {
    let text = text.trim();
    if text.is_empty() {
        return None;
    }
    if let Ok(seconds) = text.parse::<f64>() {
        return (seconds >= 0.0)
            .then(|| Duration::try_from_secs_f64(seconds).ok())
            .flatten();
    }
    let mut total = 0.0f64;
    let mut rest = text;
    while !rest.is_empty() {
        let number_len = rest
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(rest.len());
        let value: f64 = rest[..number_len].parse().ok()?;
        rest = &rest[number_len..];
        let unit_len = rest
            .find(|c: char| c.is_ascii_digit() || c == '.')
            .unwrap_or(rest.len());
        let seconds_per_unit = match &rest[..unit_len] {
            "h" => 3600.0,
            "m" => 60.0,
            "s" => 1.0,
            "ms" => 1e-3,
            "us" | "µs" => 1e-6,
            "ns" => 1e-9,
            _ => return None,
        };
        rest = &rest[unit_len..];
        total += value * seconds_per_unit;
    }
    Duration::try_from_secs_f64(total).ok()
}

/// What a reply's `x-ratelimit-*` headers say about the server's limits (each part only when
/// its header is present and readable).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct RateLimitHeaders {
    /// `x-ratelimit-remaining-requests`.
    pub remaining_requests: Option<u64>,
    /// `x-ratelimit-remaining-tokens`.
    pub remaining_tokens: Option<u64>,
    /// `x-ratelimit-reset-requests`: until the request limit is whole again.
    pub reset_requests: Option<Duration>,
    /// `x-ratelimit-reset-tokens`: until the token limit is whole again.
    pub reset_tokens: Option<Duration>,
}

impl RateLimitHeaders {
    pub(crate) fn read(headers: &HeaderMap) -> Self {
        let text = |name: &str| headers.get(name).and_then(|v| v.to_str().ok()).map(str::trim);
        let count = |name: &str| text(name).and_then(|v| v.parse::<u64>().ok());
        let reset = |name: &str| text(name).and_then(parse_reset_duration);
        RateLimitHeaders {
            remaining_requests: count("x-ratelimit-remaining-requests"),
            remaining_tokens: count("x-ratelimit-remaining-tokens"),
            reset_requests: reset("x-ratelimit-reset-requests"),
            reset_tokens: reset("x-ratelimit-reset-tokens"),
        }
    }
}

/// The client's own caps on the request rate, as [`crate::OpenAiConfig`] sets them.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct RateCaps {
    pub requests_per_minute: Option<u32>,
    pub tokens_per_minute: Option<u64>,
}

/// Decides when each attempt may start.
///
/// - **Concurrency**: at most `limit` attempts in flight; `limit` starts at the configured
///   maximum, halves on a 429 (once per "generation": replies to attempts started before the
///   last halving do not halve it again) and grows by one after `limit` successful attempts in
///   a row, back up to the maximum (additive increase, multiplicative decrease).
/// - **Pacing**: with a requests-per-minute cap, attempts start at least `60 s / rpm` apart;
///   with a tokens-per-minute cap, an attempt of `n` estimated tokens keeps the next one back by
///   `n * 60 s / tpm` (evenly spaced, no burst).
/// - **Server limits**: when the last reply said no requests remain, or fewer tokens than the
///   attempt's estimate, attempts wait until the reset the reply announced.
#[derive(Debug)]
pub(crate) struct Limiter {
    max: usize,
    caps: RateCaps,
    state: Mutex<State>,
    notify: Notify,
}

#[derive(Debug)]
struct State {
    limit: usize,
    in_flight: usize,
    successes: usize,
    generation: u64,
    /// The earliest start the caps allow (none yet: now).
    next_request: Option<Instant>,
    next_tokens: Option<Instant>,
    server: ServerLimits,
    rate_limited: u64,
    paced: Duration,
}

/// The server's limits as last reported, with the instants the reports reach.
#[derive(Debug, Default)]
struct ServerLimits {
    remaining_requests: Option<u64>,
    requests_reset_at: Option<Instant>,
    remaining_tokens: Option<u64>,
    tokens_reset_at: Option<Instant>,
}

/// One attempt's place in the limiter, given back when dropped.
#[derive(Debug)]
pub(crate) struct Slot<'a> {
    limiter: &'a Limiter,
    generation: u64,
}

/// The limiter's counters, for [`crate::ClientStats`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct LimiterStats {
    pub limit: usize,
    pub rate_limited: u64,
    pub paced: Duration,
}

/// What happened to an attempt, for the concurrency limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Verdict {
    /// Answered (or failed in a way that says nothing about load).
    Success,
    /// The server answered 429.
    RateLimited,
    /// Anything else (a timeout, a 5xx): the limit stays.
    Other,
}

impl Limiter {
    pub(crate) fn new(max: usize, caps: RateCaps) -> Self {
        Limiter {
            max,
            caps,
            state: Mutex::new(State {
                limit: max,
                in_flight: 0,
                successes: 0,
                generation: 0,
                next_request: None,
                next_tokens: None,
                server: ServerLimits::default(),
                rate_limited: 0,
                paced: Duration::ZERO,
            }),
            notify: Notify::new(),
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    pub(crate) fn stats(&self) -> LimiterStats {
        let s = self.lock();
        LimiterStats {
            limit: s.limit,
            rate_limited: s.rate_limited,
            paced: s.paced,
        }
    }

    /// Waits until an attempt of `tokens` estimated tokens may start, and takes its slot.
    pub(crate) async fn acquire(&self, tokens: u64) -> Slot<'_> {
        loop {
            let notified = self.notify.notified();
            tokio::pin!(notified);
            notified.as_mut().enable();
            let wait = {
                let mut s = self.lock();
                match self.try_start(&mut s, tokens, Instant::now()) {
                    Start::Now => {
                        return Slot {
                            limiter: self,
                            generation: s.generation,
                        };
                    }
                    Start::After(wait) => {
                        s.paced += wait;
                        Some(wait)
                    }
                    Start::WhenFree => None,
                }
            };
            match wait {
                Some(wait) => tokio::time::sleep(wait).await,
                None => notified.await,
            }
        }
    }

    /// Starts an attempt at `now` if every limit allows it.
    fn try_start(&self, s: &mut State, tokens: u64, now: Instant) -> Start {
        if s.in_flight >= s.limit {
            return Start::WhenFree;
        }
        let server = &mut s.server;
        if server.requests_reset_at.is_some_and(|t| t <= now) {
            server.remaining_requests = None;
            server.requests_reset_at = None;
        }
        if server.tokens_reset_at.is_some_and(|t| t <= now) {
            server.remaining_tokens = None;
            server.tokens_reset_at = None;
        }
        let mut ready = [s.next_request, s.next_tokens]
            .into_iter()
            .flatten()
            .fold(now, Instant::max);
        if server.remaining_requests == Some(0)
            && let Some(at) = server.requests_reset_at
        {
            ready = ready.max(at);
        }
        if server.remaining_tokens.is_some_and(|left| left < tokens)
            && let Some(at) = server.tokens_reset_at
        {
            ready = ready.max(at);
        }
        if ready > now {
            return Start::After(ready - now);
        }
        // Taken: the caps' next start and what the server has left.
        if let Some(rpm) = self.caps.requests_per_minute.filter(|r| *r > 0) {
            s.next_request = Some(now + Duration::from_secs(60) / rpm);
        }
        if let Some(tpm) = self.caps.tokens_per_minute.filter(|t| *t > 0) {
            s.next_tokens = Some(now + Duration::from_secs_f64(tokens as f64 * 60.0 / tpm as f64));
        }
        if let Some(left) = &mut server.remaining_requests {
            *left = left.saturating_sub(1);
        }
        if let Some(left) = &mut server.remaining_tokens {
            *left = left.saturating_sub(tokens);
        }
        s.in_flight += 1;
        Start::Now
    }

    /// Records what the server said about its limits in a reply.
    pub(crate) fn observe(&self, headers: RateLimitHeaders) {
        let now = Instant::now();
        let mut s = self.lock();
        let server = &mut s.server;
        if let Some(n) = headers.remaining_requests {
            server.remaining_requests = Some(n);
            server.requests_reset_at = headers.reset_requests.map(|d| now + d);
        }
        if let Some(n) = headers.remaining_tokens {
            server.remaining_tokens = Some(n);
            server.tokens_reset_at = headers.reset_tokens.map(|d| now + d);
        }
    }
}

enum Start {
    Now,
    After(Duration),
    WhenFree,
}

impl Slot<'_> {
    /// Ends the attempt with `verdict`, adapting the concurrency limit.
    pub(crate) fn finish(self, verdict: Verdict) {
        let limiter = self.limiter;
        {
            let mut s = limiter.lock();
            match verdict {
                Verdict::RateLimited => {
                    s.rate_limited += 1;
                    s.successes = 0;
                    if self.generation == s.generation {
                        s.limit = (s.limit / 2).max(1);
                        s.generation += 1;
                    }
                }
                Verdict::Success => {
                    s.successes += 1;
                    if s.successes >= s.limit && s.limit < limiter.max {
                        s.limit += 1;
                        s.successes = 0;
                    }
                }
                Verdict::Other => {}
            }
        }
        // Dropping the slot frees its place and wakes the waiters.
    }
}

impl Drop for Slot<'_> {
    fn drop(&mut self) {
        {
            let mut s = self.limiter.lock();
            s.in_flight = s.in_flight.saturating_sub(1);
        }
        // Every waiter looks again: the limit may have grown as well as a place been freed.
        self.limiter.notify.notify_waiters();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use reqwest::header::HeaderValue;

    #[test]
    fn reset_durations_in_openais_format() {
        let d = |s: &str| parse_reset_duration(s);
        assert_eq!(d("1s"), Some(Duration::from_secs(1)));
        assert_eq!(d("6m0s"), Some(Duration::from_secs(360)));
        assert_eq!(d("20ms"), Some(Duration::from_millis(20)));
        // 1 h 2 m 3.5 s = 3600 + 120 + 3.5 = 3723.5 s.
        assert_eq!(d("1h2m3.5s"), Some(Duration::from_millis(3_723_500)));
        assert_eq!(d("7.66s"), Some(Duration::from_millis(7_660)));
        assert_eq!(d("250us"), Some(Duration::from_micros(250)));
        assert_eq!(d("250µs"), Some(Duration::from_micros(250)));
        assert_eq!(d("0s"), Some(Duration::ZERO));
        assert_eq!(d(" 2 "), Some(Duration::from_secs(2)));
        for bad in ["", "s", "1x", "-1s", "1.2.3s", "m5", "-3", "1e400"] {
            assert_eq!(d(bad), None, "{bad}");
        }
    }

    #[test]
    fn headers_are_read() {
        let mut h = HeaderMap::new();
        h.insert("x-ratelimit-remaining-requests", HeaderValue::from_static("0"));
        h.insert("x-ratelimit-reset-requests", HeaderValue::from_static("1s"));
        h.insert("x-ratelimit-remaining-tokens", HeaderValue::from_static("149984"));
        h.insert("x-ratelimit-reset-tokens", HeaderValue::from_static("6m0s"));
        assert_eq!(
            RateLimitHeaders::read(&h),
            RateLimitHeaders {
                remaining_requests: Some(0),
                remaining_tokens: Some(149_984),
                reset_requests: Some(Duration::from_secs(1)),
                reset_tokens: Some(Duration::from_secs(360)),
            }
        );
        assert_eq!(
            RateLimitHeaders::read(&HeaderMap::new()),
            RateLimitHeaders::default()
        );
    }

    fn start(l: &Limiter, tokens: u64, now: Instant) -> Start {
        let mut s = l.lock();
        l.try_start(&mut s, tokens, now)
    }

    fn after(start: Start) -> Option<Duration> {
        match start {
            Start::After(d) => Some(d),
            _ => None,
        }
    }

    #[test]
    fn caps_space_the_starts() {
        // 120 requests per minute: one every 60 / 120 = 0.5 s.
        let l = Limiter::new(
            8,
            RateCaps {
                requests_per_minute: Some(120),
                tokens_per_minute: None,
            },
        );
        let t0 = Instant::now();
        assert!(matches!(start(&l, 10, t0), Start::Now));
        assert_eq!(after(start(&l, 10, t0)), Some(Duration::from_millis(500)));
        assert!(matches!(
            start(&l, 10, t0 + Duration::from_millis(500)),
            Start::Now
        ));
        // 6,000 tokens per minute: 300 tokens hold the next start back 300 * 60 / 6000 = 3 s.
        let l = Limiter::new(
            8,
            RateCaps {
                requests_per_minute: None,
                tokens_per_minute: Some(6_000),
            },
        );
        assert!(matches!(start(&l, 300, t0), Start::Now));
        assert_eq!(after(start(&l, 300, t0)), Some(Duration::from_secs(3)));
        assert_eq!(
            after(start(&l, 300, t0 + Duration::from_secs(1))),
            Some(Duration::from_secs(2))
        );
    }

    #[test]
    fn server_limits_hold_starts_until_the_reset() {
        let l = Limiter::new(8, RateCaps::default());
        l.observe(RateLimitHeaders {
            remaining_requests: Some(1),
            reset_requests: Some(Duration::from_secs(2)),
            remaining_tokens: Some(1_000),
            reset_tokens: Some(Duration::from_secs(5)),
        });
        let now = Instant::now();
        // One request left: it starts, the next waits about 2 s for the reset.
        assert!(matches!(start(&l, 100, now), Start::Now));
        let wait = after(start(&l, 100, now)).unwrap();
        assert!(
            wait > Duration::from_millis(1_500) && wait <= Duration::from_secs(2),
            "{wait:?}"
        );
        // After the request reset: 900 tokens left, so a 950-token attempt waits for the token
        // reset (5 s after the headers) and a 900-token one starts.
        let later = now + Duration::from_secs(2);
        let wait = after(start(&l, 950, later)).unwrap();
        assert!(
            wait > Duration::from_millis(2_500) && wait <= Duration::from_secs(3),
            "{wait:?}"
        );
        assert!(matches!(start(&l, 900, later), Start::Now));
        // After the token reset nothing is known: anything starts.
        assert!(matches!(
            start(&l, 1_000_000, now + Duration::from_secs(6)),
            Start::Now
        ));
    }

    #[test]
    fn concurrency_halves_on_429_and_grows_back() {
        let l = Limiter::new(8, RateCaps::default());
        let now = Instant::now();
        let slot = |g| Slot {
            limiter: &l,
            generation: g,
        };
        for _ in 0..3 {
            assert!(matches!(start(&l, 0, now), Start::Now));
        }
        // Three attempts of generation 0 meet a 429: the first halves 8 to 4, the others
        // were started under the old limit and change nothing.
        for _ in 0..3 {
            slot(0).finish(Verdict::RateLimited);
        }
        assert_eq!((l.stats().limit, l.stats().rate_limited), (4, 3));
        // A 429 of the new generation halves again: 2; then 1, and never below 1.
        assert!(matches!(start(&l, 0, now), Start::Now));
        slot(1).finish(Verdict::RateLimited);
        assert!(matches!(start(&l, 0, now), Start::Now));
        slot(2).finish(Verdict::RateLimited);
        assert!(matches!(start(&l, 0, now), Start::Now));
        slot(3).finish(Verdict::RateLimited);
        assert_eq!(l.stats().limit, 1);
        // Growing back: +1 after `limit` successes: 1 success -> 2, 2 more -> 3, 3 more -> 4.
        let mut limits = Vec::new();
        for _ in 0..6 {
            assert!(matches!(start(&l, 0, now), Start::Now));
            slot(4).finish(Verdict::Success);
            limits.push(l.stats().limit);
        }
        assert_eq!(limits, [2, 2, 3, 3, 3, 4]);
        // A full limiter makes the next attempt wait for a free place.
        let full = Limiter::new(1, RateCaps::default());
        {
            let mut s = full.lock();
            assert!(matches!(full.try_start(&mut s, 0, now), Start::Now));
            assert!(matches!(full.try_start(&mut s, 0, now), Start::WhenFree));
        }
    }
}
