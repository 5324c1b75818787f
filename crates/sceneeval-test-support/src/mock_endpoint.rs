//! A mock OpenAI-compatible chat-completions endpoint on 127.0.0.1, with the standard library
//! only (a thread per connection), that answers every request after a fixed latency and counts,
//! at the server, how many requests were in flight at once: what the VLM transport's tests and
//! the throughput benchmark (`benches/benches/vlm_throughput.rs`) measure against.
//!
//! ```
//! use std::time::Duration;
//! use sceneeval_test_support::mock_endpoint::{MockEndpoint, completion};
//! let server = MockEndpoint::start(Duration::ZERO, |_, _| completion(&serde_json::json!({"ok": true})));
//! assert!(server.url().starts_with("http://127.0.0.1:") && server.url().ends_with("/v1"));
//! assert_eq!(server.requests(), 0);
//! ```

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Shutdown, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use serde_json::{Value, json};

/// A reply of the mock endpoint.
#[derive(Debug, Clone, PartialEq)]
pub struct Reply {
    /// The HTTP status.
    pub status: u16,
    /// Extra headers (`x-ratelimit-*`, `retry-after`, ...).
    pub headers: Vec<(String, String)>,
    /// The body (JSON text).
    pub body: String,
}

impl Reply {
    /// The reply with one more header.
    pub fn with_header(mut self, name: &str, value: &str) -> Self {
        self.headers.push((name.to_owned(), value.to_owned()));
        self
    }
}

/// A 200 chat completion whose message is `value` as JSON text, with usage 100 prompt and 20
/// completion tokens.
pub fn completion(value: &Value) -> Reply {
    let body = json!({
        "id": "chatcmpl-mock",
        "object": "chat.completion",
        "model": "mock",
        "choices": [{"index": 0, "message": {"role": "assistant", "content": value.to_string(), "refusal": null},
                     "finish_reason": "stop"}],
        "usage": {"prompt_tokens": 100, "completion_tokens": 20, "total_tokens": 120}
    });
    Reply {
        status: 200,
        headers: Vec::new(),
        body: body.to_string(),
    }
}

/// An error reply with status `status` and OpenAI's error body.
pub fn error(status: u16, message: &str) -> Reply {
    Reply {
        status,
        headers: Vec::new(),
        body: json!({"error": {"message": message}}).to_string(),
    }
}

/// What the responder is given: the request's position (from 0) and its JSON body.
type Responder = dyn Fn(usize, &Value) -> Reply + Send + Sync;

struct Shared {
    latency: Duration,
    respond: Box<Responder>,
    requests: AtomicUsize,
    in_flight: AtomicUsize,
    peak: AtomicUsize,
    bodies: Mutex<Vec<Value>>,
    stop: AtomicBool,
}

/// The running endpoint; stops accepting connections when dropped.
pub struct MockEndpoint {
    port: u16,
    shared: Arc<Shared>,
}

impl std::fmt::Debug for MockEndpoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MockEndpoint")
            .field("port", &self.port)
            .finish_non_exhaustive()
    }
}

impl MockEndpoint {
    /// Listens on a free port of 127.0.0.1; answers `POST .../chat/completions` with
    /// `respond(n, body)` after `latency` (the time the request counts as in flight).
    ///
    /// # Panics
    /// When no port of 127.0.0.1 can be bound (test scaffolding).
    #[allow(clippy::expect_used)] // Test scaffolding: no listener, no test.
    pub fn start(
        latency: Duration,
        respond: impl Fn(usize, &Value) -> Reply + Send + Sync + 'static,
    ) -> Self {
        let listener = TcpListener::bind("127.0.0.1:0").expect("a port on 127.0.0.1");
        let port = listener.local_addr().expect("the listener's address").port();
        let shared = Arc::new(Shared {
            latency,
            respond: Box::new(respond),
            requests: AtomicUsize::new(0),
            in_flight: AtomicUsize::new(0),
            peak: AtomicUsize::new(0),
            bodies: Mutex::new(Vec::new()),
            stop: AtomicBool::new(false),
        });
        let accepting = shared.clone();
        std::thread::spawn(move || {
            for stream in listener.incoming() {
                if accepting.stop.load(Ordering::SeqCst) {
                    break;
                }
                let Ok(stream) = stream else { continue };
                let conn = accepting.clone();
                std::thread::spawn(move || serve(stream, &conn));
            }
        });
        MockEndpoint { port, shared }
    }

    /// The base URL: `http://127.0.0.1:<port>/v1`.
    pub fn url(&self) -> String {
        format!("http://127.0.0.1:{}/v1", self.port)
    }

    /// Requests received so far.
    pub fn requests(&self) -> usize {
        self.shared.requests.load(Ordering::SeqCst)
    }

    /// The most requests that were in flight at the server at once.
    pub fn peak_in_flight(&self) -> usize {
        self.shared.peak.load(Ordering::SeqCst)
    }

    /// The JSON bodies received, in the order they arrived.
    pub fn bodies(&self) -> Vec<Value> {
        self.shared
            .bodies
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone()
    }
}

impl Drop for MockEndpoint {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        // Wakes the accepting thread so that it sees the flag.
        let _ = TcpStream::connect(("127.0.0.1", self.port));
    }
}

/// Serves one connection's requests (HTTP/1.1, kept alive) until the client closes it.
fn serve(stream: TcpStream, shared: &Shared) {
    let Ok(mut writer) = stream.try_clone() else {
        return;
    };
    let mut reader = BufReader::new(stream);
    loop {
        let mut length = 0usize;
        let mut line = String::new();
        let mut first = true;
        loop {
            line.clear();
            match reader.read_line(&mut line) {
                Ok(0) | Err(_) => return,
                Ok(_) => {}
            }
            if line == "\r\n" || line == "\n" {
                break;
            }
            if first {
                first = false;
                continue;
            }
            if let Some((name, value)) = line.split_once(':')
                && name.trim().eq_ignore_ascii_case("content-length")
            {
                length = value.trim().parse().unwrap_or(0);
            }
        }
        let mut body = vec![0u8; length];
        if reader.read_exact(&mut body).is_err() {
            return;
        }
        if shared.stop.load(Ordering::SeqCst) {
            let _ = writer.shutdown(Shutdown::Both);
            return;
        }
        let n = shared.requests.fetch_add(1, Ordering::SeqCst);
        let now = shared.in_flight.fetch_add(1, Ordering::SeqCst) + 1;
        shared.peak.fetch_max(now, Ordering::SeqCst);
        let body: Value = serde_json::from_slice(&body).unwrap_or(Value::Null);
        shared
            .bodies
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(body.clone());
        std::thread::sleep(shared.latency);
        let reply = (shared.respond)(n, &body);
        shared.in_flight.fetch_sub(1, Ordering::SeqCst);
        let mut head = format!(
            "HTTP/1.1 {} Mock\r\nContent-Type: application/json\r\nContent-Length: {}\r\n",
            reply.status,
            reply.body.len()
        );
        for (name, value) in &reply.headers {
            head.push_str(&format!("{name}: {value}\r\n"));
        }
        head.push_str("\r\n");
        if writer.write_all(head.as_bytes()).is_err() || writer.write_all(reply.body.as_bytes()).is_err() {
            return;
        }
    }
}

/// The task (response schema name) of a request body.
pub fn task_of(body: &Value) -> &str {
    body["response_format"]["json_schema"]["name"]
        .as_str()
        .unwrap_or("")
}

/// The user text of a request body.
pub fn user_text(body: &Value) -> &str {
    body["messages"][1]["content"][0]["text"].as_str().unwrap_or("")
}

/// A valid answer to any object-level task of the fixture scenes, worked out from the request
/// alone (so that it does not depend on the order requests arrive in): matching picks an
/// offered category by a hash of the object's image; attributes are all satisfied; support
/// type `ground`; every object used from the front; the endpoint check's square is red. The
/// relationship-mapping tasks are answered with no assessment (the session asks again once,
/// then records the relations as unanswered): two requests each.
pub fn generic_answer(body: &Value) -> Value {
    let text = user_text(body);
    // The last JSON array of a line of the prompt (the categories or attributes offered).
    let last_list = |marker: &str| -> Vec<String> {
        text.rsplit_once(marker)
            .and_then(|(_, rest)| rest.lines().find(|l| l.trim_start().starts_with('[')))
            .and_then(|l| serde_json::from_str::<Vec<String>>(l.trim()).ok())
            .unwrap_or_default()
    };
    match task_of(body) {
        "obj_matching" => {
            let categories = last_list("specified to match against:");
            let image = body["messages"][1]["content"][1]["image_url"]["url"]
                .as_str()
                .unwrap_or("");
            // FNV-1a of the image's data URL.
            let hash = image.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
                (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
            });
            match categories.get((hash % categories.len().max(1) as u64) as usize) {
                Some(c) => json!({"provided_categories": categories, "matched": true, "matched_category": c,
                                  "actual_category": c, "reason": "mock"}),
                None => json!({"provided_categories": [], "matched": false, "matched_category": "",
                               "actual_category": "thing", "reason": "mock"}),
            }
        }
        "obj_attribute" => {
            let attributes = last_list("The attribute requirements are as follows:");
            let count: usize = text
                .rsplit_once("Here are the renderings of ")
                .and_then(|(_, rest)| rest.split_whitespace().next())
                .and_then(|n| n.parse().ok())
                .unwrap_or(0);
            let category = text
                .rsplit_once("with category ")
                .and_then(|(_, rest)| {
                    serde_json::Deserializer::from_str(rest)
                        .into_iter::<String>()
                        .next()
                })
                .and_then(Result::ok)
                .unwrap_or_default();
            let assessments: Vec<Value> = (0..count)
                .flat_map(|i| {
                    attributes.iter().map(
                        move |a| json!({"instance": i, "attribute": a, "satisfied": true, "reason": "mock"}),
                    )
                })
                .collect();
            json!({"category": category, "num_instances": count, "assessments": assessments})
        }
        "obj_support_type" => json!({"support_type": "ground", "reason": "mock"}),
        "obj_functional_sides" => json!({"assessments": text
            .split("obj_id: \"")
            .skip(1)
            .filter_map(|rest| rest.split('"').next())
            .map(|id| json!({"obj_id": id, "obj_description": "", "functional_sides": ["front"], "reason": "mock"}))
            .collect::<Vec<_>>()}),
        "endpoint_check" => json!({"colour": "red", "reason": "a red square"}),
        _ => json!({"assessments": []}),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn body(task: &str, text: &str, image: &str) -> Value {
        json!({"response_format": {"json_schema": {"name": task}},
               "messages": [{"role": "system", "content": "s"},
                            {"role": "user", "content": [{"type": "text", "text": text},
                                                         {"type": "image_url", "image_url": {"url": image}}]}]})
    }

    #[test]
    fn generic_answers_follow_the_prompt() {
        let m = generic_answer(&body(
            "obj_matching",
            "...specified to match against:\n[\"bed\", \"chair\"]",
            "data:x",
        ));
        assert_eq!(m["matched"], true);
        assert!(["bed", "chair"].contains(&m["matched_category"].as_str().unwrap()));
        let a = generic_answer(&body(
            "obj_attribute",
            "The attribute requirements are as follows:\n[\"red\", \"tall\"]\nHere are the renderings of 2 instances of object with category \"chair\" in the scene.",
            "",
        ));
        assert_eq!(
            (a["category"].as_str(), a["num_instances"].as_u64()),
            (Some("chair"), Some(2))
        );
        assert_eq!(a["assessments"].as_array().unwrap().len(), 4);
        let s = generic_answer(&body(
            "obj_functional_sides",
            "obj_id: \"a\", x; obj_id: \"b\"",
            "",
        ));
        assert_eq!(s["assessments"].as_array().unwrap().len(), 2);
    }

    #[test]
    fn the_endpoint_answers_after_its_latency_and_counts_what_is_in_flight() {
        let server = MockEndpoint::start(Duration::from_millis(500), |n, _| {
            completion(&json!({"n": n})).with_header("x-test", "1")
        });
        let url = server.url().replace("http://", "");
        let host = url.trim_end_matches("/v1").to_owned();
        let send = |host: String| {
            std::thread::spawn(move || {
                let mut s = TcpStream::connect(host).unwrap();
                let body = b"{\"a\":1}";
                write!(
                    s,
                    "POST /v1/chat/completions HTTP/1.1\r\nHost: x\r\nContent-Length: {}\r\n\r\n",
                    body.len()
                )
                .unwrap();
                s.write_all(body).unwrap();
                let mut r = BufReader::new(s);
                let (mut head, mut line, mut length) = (String::new(), String::new(), 0);
                while r.read_line(&mut line).unwrap() > 2 {
                    if let Some(v) = line.strip_prefix("Content-Length: ") {
                        length = v.trim().parse().unwrap();
                    }
                    head.push_str(&line);
                    line.clear();
                }
                let mut body = vec![0; length];
                r.read_exact(&mut body).unwrap();
                head + &String::from_utf8(body).unwrap()
            })
        };
        let (a, b) = (send(host.clone()), send(host));
        let (a, b) = (a.join().unwrap(), b.join().unwrap());
        assert!(a.starts_with("HTTP/1.1 200") && a.contains("x-test: 1"), "{a}");
        assert!(b.contains("\"n\\\":"), "{b}");
        assert_eq!(server.requests(), 2);
        assert_eq!(server.peak_in_flight(), 2, "both waited 500 ms at once");
        assert_eq!(server.bodies(), vec![json!({"a": 1}); 2]);
    }
}
