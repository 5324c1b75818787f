//! `sceneeval annotations review`: the server the test starts on 127.0.0.1 (the `sceneeval`
//! binary), spoken to over plain TCP (security refusals, malformed requests, the validator's
//! findings, decisions written to the files, Ctrl-C, a second review continuing, hostile
//! clients: a huge declared body, a silent client, headers sent byte by byte, Ctrl-C with a
//! slow client connected), and the page driven in headless Chromium when it is installed
//! (`SCENEEVAL_REQUIRE_BROWSER=1` makes a missing browser a failure).

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use common::page::{PageProcess, token_in};
use serde_json::{Value, json};

/// Row 5 has its attribute and category swapped (`eq,1,red,bed`, an error of the validator);
/// row 6 is clean. The rejected file adds a near copy (ID 7 once reviewed) and a refusal (no
/// candidate).
const FILE: &str = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
    5,easy,A bedroom with a red bed.,\"eq,1,bed\",\"eq,1,red,bed\",,\n\
    6,easy,A kitchen with a fridge and a stove.,\"eq,1,fridge; eq,1,stove\",,,\n";

const REJECTED: &str = concat!(
    r#"{"difficulty":"easy","candidate":{"description":"A study with a desk.","difficulty":"easy","obj_count":["eq,1,desk"],"obj_attr":[],"oo_rel":[],"oa_rel":[]},"reason":"too_similar","near_id":"3","near_description":"A study with a desk and a lamp.","score":0.67}"#,
    "\n",
    r#"{"difficulty":"easy","candidate":null,"reason":"refused","detail":"no"}"#,
    "\n"
);

fn setup() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("mine.csv");
    std::fs::write(&file, FILE).unwrap();
    std::fs::write(dir.path().join("mine.csv.rejected.jsonl"), REJECTED).unwrap();
    (dir, file)
}

/// A running `sceneeval annotations review FILE --no-open`, killed when dropped.
struct Review(PageProcess);

impl std::ops::Deref for Review {
    type Target = PageProcess;
    fn deref(&self) -> &PageProcess {
        &self.0
    }
}

impl std::ops::DerefMut for Review {
    fn deref_mut(&mut self) -> &mut PageProcess {
        &mut self.0
    }
}

impl Review {
    fn start(file: &Path) -> Review {
        Review::spawn(Command::new(assert_cmd::cargo::cargo_bin("sceneeval")), file)
    }

    /// As [`Review::start`], under `umask MASK` (the shell `exec`s the binary: same process).
    fn start_under_umask(file: &Path, mask: &str) -> Review {
        let mut sh = Command::new("sh");
        sh.arg("-c")
            .arg(format!("umask {mask} && exec \"$0\" \"$@\""))
            .arg(assert_cmd::cargo::cargo_bin("sceneeval"));
        Review::spawn(sh, file)
    }

    fn spawn(mut command: Command, file: &Path) -> Review {
        command.args(["annotations", "review", "--no-open"]).arg(file);
        Review(PageProcess::spawn(command))
    }

    /// Sends `head` (request line and headers without the final blank line) with `body`,
    /// returns the status and the body.
    fn raw(&self, head: &str, body: &str) -> (u16, String) {
        let request = format!(
            "{head}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
            body.len()
        );
        let (status, _, body) = self.exchange(request.as_bytes());
        (status, body)
    }

    /// Sends `request` as it is on a new connection and reads the response to its end:
    /// status, head, body.
    fn exchange(&self, request: &[u8]) -> (u16, String, String) {
        let mut stream = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        stream.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
        stream.write_all(request).unwrap();
        let mut response = String::new();
        stream.read_to_string(&mut response).unwrap();
        let (head, body) = response
            .split_once("\r\n\r\n")
            .unwrap_or_else(|| panic!("no response head in {response:?}"));
        let status = head.split(' ').nth(1).unwrap().parse().unwrap();
        (status, head.to_owned(), body.to_owned())
    }

    /// The page's token, from the page.
    fn token(&self) -> String {
        let (status, page) = self.raw(&format!("GET / HTTP/1.1\r\nHost: {}", self.host()), "");
        assert_eq!(status, 200, "{page}");
        token_in(&page)
    }

    fn get(&self, token: &str, path: &str) -> (u16, Value) {
        let (status, body) = self.raw(
            &format!(
                "GET {path} HTTP/1.1\r\nHost: {}\r\nX-Sceneeval-Token: {token}",
                self.host()
            ),
            "",
        );
        (
            status,
            serde_json::from_str(&body).unwrap_or_else(|e| panic!("{e}: {body}")),
        )
    }

    fn post(&self, token: &str, path: &str, body: &Value) -> (u16, Value) {
        let (status, body) = self.raw(
            &format!(
                "POST {path} HTTP/1.1\r\nHost: {}\r\nX-Sceneeval-Token: {token}\r\nContent-Type: application/json",
                self.host()
            ),
            &body.to_string(),
        );
        (
            status,
            serde_json::from_str(&body).unwrap_or_else(|e| panic!("{e}: {body}")),
        )
    }

    /// Sends SIGINT (Ctrl-C) and returns the rest of standard output after the process ends.
    fn interrupt(self) -> (std::process::ExitStatus, String) {
        self.0.interrupt()
    }
}

fn content(description: &str, counts: &[&str], attrs: &[&str]) -> Value {
    json!({"description": description, "difficulty": "easy", "obj_count": counts, "obj_attr": attrs,
           "oo_rel": [], "oa_rel": []})
}

#[test]
fn foreign_hosts_missing_tokens_and_malformed_requests_are_refused() {
    let (_dir, file) = setup();
    let review = Review::start(&file);
    let token = review.token();
    let host = review.host();
    // DNS rebinding: a name that resolves to 127.0.0.1 is not the address served.
    let (status, body) = review.raw(
        &format!("GET / HTTP/1.1\r\nHost: evil.example:{}", review.port),
        "",
    );
    assert_eq!(status, 403, "{body}");
    assert!(body.contains("the Host header must be 127.0.0.1:"), "{body}");
    let (status, _) = review.raw(
        &format!(
            "GET /api/candidates HTTP/1.1\r\nHost: localhost:{}\r\nX-Sceneeval-Token: {token}",
            review.port
        ),
        "",
    );
    assert_eq!(status, 403);
    // No token, a wrong token, another origin.
    let (status, body) = review.raw(&format!("GET /api/candidates HTTP/1.1\r\nHost: {host}"), "");
    assert_eq!(status, 403);
    assert!(body.contains("X-Sceneeval-Token"), "{body}");
    let accept = json!({"id": "6"}).to_string();
    let (status, _) = review.raw(
        &format!("POST /api/accept HTTP/1.1\r\nHost: {host}\r\nContent-Type: application/json\r\nX-Sceneeval-Token: 0123"),
        &accept,
    );
    assert_eq!(status, 403);
    let (status, _) = review.raw(
        &format!(
            "POST /api/accept HTTP/1.1\r\nHost: {host}\r\nOrigin: http://evil.example\r\nContent-Type: application/json\r\nX-Sceneeval-Token: {token}"
        ),
        &accept,
    );
    assert_eq!(status, 403);
    // A form post (not JSON), malformed JSON, unknown fields, a missing content.
    let (status, _) = review.raw(
        &format!(
            "POST /api/accept HTTP/1.1\r\nHost: {host}\r\nContent-Type: text/plain\r\nX-Sceneeval-Token: {token}"
        ),
        &accept,
    );
    assert_eq!(status, 415);
    let (status, body) = review.raw(
        &format!("POST /api/save HTTP/1.1\r\nHost: {host}\r\nContent-Type: application/json\r\nX-Sceneeval-Token: {token}"),
        "{\"id\": \"6\", \"content\": ",
    );
    assert_eq!(status, 400);
    assert!(body.contains("the body is not a request of /api/save"), "{body}");
    let (status, body) = review.post(&token, "/api/save", &json!({"id": "6", "colour": "red"}));
    assert_eq!(status, 400, "{body}");
    let (status, body) = review.post(&token, "/api/save", &json!({"id": "6"}));
    assert_eq!(
        (status, body["error"].as_str()),
        (400, Some("the request has no \"content\""))
    );
    let (status, _) = review.get(&token, "/api/candidate?id=nope");
    assert_eq!(status, 404);
    let (status, _) = review.get(&token, "/api/candidate");
    assert_eq!(status, 400);
    let (status, _) = review.raw(
        &format!("DELETE /api/candidates HTTP/1.1\r\nHost: {host}\r\nX-Sceneeval-Token: {token}"),
        "",
    );
    assert_eq!(status, 405);
    let (status, _) = review.raw(&format!("GET /etc/passwd HTTP/1.1\r\nHost: {host}"), "");
    assert_eq!(status, 404);
    // Not HTTP at all: the server answers 400 and goes on.
    let mut stream = TcpStream::connect(("127.0.0.1", review.port)).unwrap();
    stream.write_all(b"\x00\x01garbage\r\n\r\n").unwrap();
    let mut buf = String::new();
    let _ = stream.read_to_string(&mut buf);
    // The validator's findings of a hand-made bad row: the attribute before the category.
    let (status, body) = review.post(
        &token,
        "/api/validate",
        &json!({"id": "5", "content": content("A bedroom with a red bed.", &["eq,1,bed"], &["eq,1,red,bed"])}),
    );
    assert_eq!(status, 200, "{body}");
    let findings = body["findings"].as_array().unwrap();
    assert_eq!(findings.len(), 1, "{body}");
    assert_eq!(findings[0]["code"], "attribute-category-swapped");
    assert_eq!(findings[0]["severity"], "error");
    assert_eq!(findings[0]["suggestion"], "eq,1,bed,red");
    // The page's script and the server's client script (which sends the token).
    let (status, script) = review.raw(&format!("GET /app.js HTTP/1.1\r\nHost: {host}"), "");
    assert_eq!(status, 200);
    assert!(script.contains("sceneevalApi("));
    let (status, client) = review.raw(&format!("GET /sceneeval-api.js HTTP/1.1\r\nHost: {host}"), "");
    assert_eq!(status, 200);
    assert!(
        client.contains("\"X-Sceneeval-Token\": SCENEEVAL_TOKEN"),
        "{client}"
    );
    // Still serving after all that.
    assert_eq!(review.token(), token);
}

#[test]
fn decisions_are_written_at_once_and_a_second_review_continues() {
    let (dir, file) = setup();
    let review = Review::start(&file);
    let token = review.token();
    let (status, list) = review.get(&token, "/api/candidates");
    assert_eq!(status, 200);
    let ids: Vec<(&str, &str, u64)> = list["candidates"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            (
                c["id"].as_str().unwrap(),
                c["state"].as_str().unwrap(),
                c["errors"].as_u64().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        ids,
        [("5", "pending", 1), ("6", "pending", 0), ("7", "pending", 0)]
    );
    // Accepting row 5 as it is: refused, it has an error; nothing written.
    let (status, body) = review.post(&token, "/api/accept", &json!({"id": "5"}));
    assert_eq!(status, 409, "{body}");
    assert!(!dir.path().join("mine.accepted.csv").exists());
    // Fixed and accepted; 6 rejected with a reason; 7 (from the rejected file) edited.
    let fixed = content("A bedroom with a red bed.", &["eq,1,bed"], &["eq,1,bed,red"]);
    let (status, body) = review.post(&token, "/api/accept", &json!({"id": "5", "content": fixed}));
    assert_eq!(status, 200, "{body}");
    assert_eq!(body["candidate"]["state"], "accepted");
    let (status, _) = review.post(&token, "/api/reject", &json!({"id": "6", "note": ""}));
    assert_eq!(status, 400);
    let (status, _) = review.post(&token, "/api/reject", &json!({"id": "6", "note": "too plain"}));
    assert_eq!(status, 200);
    let (status, body) = review.post(
        &token,
        "/api/save",
        &json!({"id": "7", "content": content("A study with a desk and a chair.", &["eq,1,desk", "eq,1,chair"], &[])}),
    );
    assert_eq!((status, &body["candidate"]["state"]), (200, &json!("pending")));
    // Each decision is in its file already.
    let accepted = std::fs::read_to_string(dir.path().join("mine.accepted.csv")).unwrap();
    assert_eq!(
        accepted,
        "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n5,easy,A bedroom with a red bed.,\"eq,1,bed\",\"eq,1,bed,red\",,\n"
    );
    let decisions = std::fs::read_to_string(dir.path().join("mine.accepted.csv.rejected.jsonl")).unwrap();
    assert!(
        decisions.contains(r#""id":"6""#) && decisions.contains(r#""reason":"reviewer","note":"too plain""#),
        "{decisions}"
    );
    let rejected = std::fs::read_to_string(dir.path().join("mine.csv.rejected.jsonl")).unwrap();
    assert!(
        rejected.starts_with(r#"{"id":"7","#) && rejected.contains("A study with a desk and a chair."),
        "{rejected}"
    );
    let reviewed = std::fs::read_to_string(&file).unwrap();
    assert!(
        reviewed.contains("eq,1,bed,red"),
        "the edit is saved where the row lives: {reviewed}"
    );
    // The statistics of the accepted rows: Table 1, as `annotations stats` prints it.
    let (status, stats) = review.get(&token, "/api/stats");
    assert_eq!(status, 200);
    let markdown = stats["markdown"].as_str().unwrap();
    assert!(
        markdown.contains("| Easy | 1 | 6.00 | 1.00 | 1.00 | 1.00 | 0.00 | 0.00 |"),
        "{markdown}"
    );

    // Ctrl-C ends the server cleanly: exit status 0, a summary, no temporary file left.
    let (status, rest) = review.interrupt();
    assert!(status.success(), "{status:?}");
    assert!(
        rest.ends_with(&format!(
            "\nstopped: 1 pending, 1 accepted, 1 rejected; accepted rows in {}\n",
            dir.path().join("mine.accepted.csv").display()
        )),
        "{rest}"
    );
    let names = sceneeval_test_support::file_names(dir.path());
    assert_eq!(
        names,
        [
            "mine.accepted.csv",
            "mine.accepted.csv.rejected.jsonl",
            "mine.csv",
            "mine.csv.rejected.jsonl"
        ]
    );

    // A second review continues: the same states.
    let review = Review::start(&file);
    let token = review.token();
    let (_, list) = review.get(&token, "/api/candidates");
    let states: Vec<(&str, &str)> = list["candidates"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| (c["id"].as_str().unwrap(), c["state"].as_str().unwrap()))
        .collect();
    assert_eq!(states, [("5", "accepted"), ("6", "rejected"), ("7", "pending")]);
    let (_, detail) = review.get(&token, "/api/candidate?id=6");
    assert_eq!(detail["candidate"]["reviewer_note"], "too plain");
    // The accepted file is what `check` and `evaluate --annotations` read.
    assert_cmd::Command::cargo_bin("sceneeval")
        .unwrap()
        .args(["annotations", "check"])
        .arg(dir.path().join("mine.accepted.csv"))
        .assert()
        .success();
}

/// The reviewed file keeps its permissions when an edit rewrites it; the files the review
/// makes get the umask's.
#[cfg(unix)]
#[test]
fn a_reviewed_file_keeps_its_mode_and_new_files_get_the_umask_s() {
    use std::os::unix::fs::PermissionsExt;
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    let (dir, file) = setup();
    std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o644)).unwrap();
    let review = Review::start_under_umask(&file, "002");
    let token = review.token();
    let fixed = content("A bedroom with a red bed.", &["eq,1,bed"], &["eq,1,bed,red"]);
    let (status, body) = review.post(&token, "/api/accept", &json!({"id": "5", "content": fixed}));
    assert_eq!(status, 200, "{body}");
    assert!(
        std::fs::read_to_string(&file).unwrap().contains("eq,1,bed,red"),
        "rewritten"
    );
    assert_eq!(mode(&file), 0o644, "the user's file keeps its mode");
    assert_eq!(mode(&dir.path().join("mine.accepted.csv")), 0o664, "umask 002");
}

/// Waits until `check` holds, for at most 20 seconds.
fn wait_for(what: &str, check: impl FnMut() -> bool) {
    common::page::wait_for(what, Duration::from_secs(20), check);
}

/// Clients that misbehave on purpose: none of them stops the server or holds up anyone else.
mod hostile {
    use super::*;

    /// A connection that has sent `sent` and then keeps quiet.
    fn silent(port: u16, sent: &str) -> TcpStream {
        let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
        stream.write_all(sent.as_bytes()).unwrap();
        stream
    }

    /// Whether the server has said nothing on `stream` yet (and not closed it).
    fn still_waiting(stream: &TcpStream) -> bool {
        stream.set_nonblocking(true).unwrap();
        let mut byte = [0u8; 1];
        let quiet = matches!(stream.peek(&mut byte), Err(e) if e.kind() == std::io::ErrorKind::WouldBlock);
        stream.set_nonblocking(false).unwrap();
        quiet
    }

    #[test]
    fn a_huge_declared_body_gets_413_and_the_server_lives() {
        let (_dir, file) = setup();
        let review = Review::start(&file);
        // No token, a foreign Host: the size is refused first, and nothing of the body is read.
        for head in [
            "POST /api/save HTTP/1.1\r\nHost: evil.example\r\n".to_owned(),
            format!("GET / HTTP/1.1\r\nHost: {}\r\n", review.host()),
            "POST /api/save HTTP/1.1\r\n".to_owned(),
        ] {
            // The head only: a body sent and never read would make the close a reset.
            let request = format!("{head}Content-Length: 99999999999999\r\n\r\n");
            let (status, response_head, body) = review.exchange(request.as_bytes());
            assert_eq!(status, 413, "{head}: {body}");
            assert!(body.contains("the body is larger than 1048576 bytes"), "{body}");
            assert!(
                response_head
                    .to_ascii_lowercase()
                    .contains("content-security-policy: default-src 'none'"),
                "{response_head}"
            );
        }
        let token = review.token();
        // Still serving.
        assert_eq!(review.token(), token);
        let (status, _) = review.get(&token, "/api/candidates");
        assert_eq!(status, 200);
    }

    #[test]
    fn a_silent_or_slow_client_does_not_hold_up_the_others() {
        let (_dir, file) = setup();
        let review = Review::start(&file);
        let token = review.token();
        let host = review.host();
        // Declares a body and sends nothing; another sends its headers byte by byte.
        let quiet = silent(
            review.port,
            &format!(
                "POST /api/save HTTP/1.1\r\nHost: {host}\r\nX-Sceneeval-Token: {token}\r\n\
                 Content-Type: application/json\r\nContent-Length: 100000\r\n\r\n"
            ),
        );
        let port = review.port;
        let trickle = std::thread::spawn({
            let host = host.clone();
            move || {
                let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
                for byte in format!("GET /app.css HTTP/1.1\r\nHost: {host}\r\n\r\n").bytes() {
                    stream.write_all(&[byte]).unwrap();
                    std::thread::sleep(Duration::from_millis(40));
                }
                let mut response = String::new();
                stream.read_to_string(&mut response).unwrap();
                response
            }
        });
        // Meanwhile other requests are answered, one after the other, while the silent client
        // still holds its connection without an answer.
        for _ in 0..5 {
            let (status, list) = review.get(&token, "/api/candidates");
            assert_eq!(status, 200, "{list}");
        }
        let (status, _) = review.post(&token, "/api/reject", &json!({"id": "6", "note": "plain"}));
        assert_eq!(status, 200);
        assert!(still_waiting(&quiet), "the silent client was answered or dropped");
        // The slow but complete request is served too.
        let response = trickle.join().unwrap();
        assert!(response.starts_with("HTTP/1.1 200"), "{response}");
        assert!(still_waiting(&quiet));
    }

    #[test]
    fn ctrl_c_stops_the_server_with_a_slow_client_connected() {
        let (dir, file) = setup();
        let mut review = Review::start(&file);
        let host = review.host();
        // Half a request line and a header that never ends; and a body that never comes.
        let half = silent(review.port, &format!("GET / HTTP/1.1\r\nHost: {host}\r\nX-Slow"));
        let token = review.token();
        let body = silent(
            review.port,
            &format!(
                "POST /api/save HTTP/1.1\r\nHost: {host}\r\nX-Sceneeval-Token: {token}\r\n\
                 Content-Type: application/json\r\nContent-Length: 100000\r\n\r\n{{"
            ),
        );
        assert!(still_waiting(&half) && still_waiting(&body));
        review.send_interrupt();
        // The server stops well before the slow clients' 30 s timeouts would drop them.
        let mut status = None;
        wait_for("the server to stop", || {
            status = review.child.try_wait().unwrap();
            status.is_some()
        });
        assert!(status.unwrap().success(), "{status:?}");
        let mut rest = String::new();
        review.stdout.read_to_string(&mut rest).unwrap();
        assert!(
            rest.contains("stopped: 3 pending, 0 accepted, 0 rejected"),
            "{rest}"
        );
        // Both connections are closed, unanswered, and nothing was written.
        for mut stream in [half, body] {
            stream.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
            let mut buf = Vec::new();
            let _ = stream.read_to_end(&mut buf);
            assert!(buf.is_empty(), "{}", String::from_utf8_lossy(&buf));
        }
        assert_eq!(
            sceneeval_test_support::file_names(dir.path()),
            ["mine.csv", "mine.csv.rejected.jsonl"]
        );
    }
}

mod browser {
    use super::*;

    #[test]
    fn an_edit_made_in_the_page_is_saved_to_the_file() {
        let Some(chromium) = sceneeval_test_support::system::chromium() else {
            return;
        };
        let (dir, file) = setup();
        let review = Review::start(&file);
        let profile = tempfile::tempdir().unwrap();
        let (_browser, tab, errors) =
            common::browser::open(chromium, &review.url(), profile.path(), Duration::from_secs(20));
        // The first pending candidate opens: 5, with its swapped attribute reported.
        tab.wait_for_element("#candidates li.current").unwrap();
        let title = tab
            .wait_for_element("#cand-title")
            .unwrap()
            .get_inner_text()
            .unwrap();
        assert_eq!(title, "Candidate 5");
        let findings = tab
            .wait_for_element("#findings li.error")
            .unwrap()
            .get_inner_text()
            .unwrap();
        assert!(findings.contains("attribute-category-swapped"), "{findings}");
        // Swap the two cells back by typing into them.
        let cell = |col: u8| format!("table[data-field=\"obj_attr\"] tbody tr input[data-col=\"{col}\"]");
        for (col, text) in [(2, "bed"), (3, "red")] {
            let input = tab.wait_for_element(&cell(col)).unwrap();
            input
                .call_js_fn("function() { this.value = ''; }", vec![], false)
                .unwrap();
            input.click().unwrap();
            // Input.insertText: the text as one input event in the focused cell.
            tab.send_character(text).unwrap();
        }
        // The findings follow the edit (the server's validator): none left.
        tab.wait_for_element("#findings li.none").unwrap();
        tab.wait_for_element("#accept").unwrap().click().unwrap();
        let accepted = dir.path().join("mine.accepted.csv");
        wait_for("the accepted row", || {
            std::fs::read_to_string(&accepted)
                .is_ok_and(|t| t.contains("5,easy,A bedroom with a red bed.,\"eq,1,bed\",\"eq,1,bed,red\""))
        });
        // The page moved on to the next pending candidate; an edit there is saved with Ctrl+S.
        wait_for("candidate 6", || {
            tab.find_element("#cand-title")
                .and_then(|e| e.get_inner_text())
                .is_ok_and(|t| t == "Candidate 6")
        });
        let description = tab.wait_for_element("#description").unwrap();
        description
            .call_js_fn("function() { this.value = ''; }", vec![], false)
            .unwrap();
        description.click().unwrap();
        tab.send_character("A kitchen with a fridge, a stove and a <script>alert(1)</script> sink.")
            .unwrap();
        tab.press_key_with_modifiers("s", Some(&[headless_chrome::browser::tab::ModifierKey::Ctrl]))
            .unwrap();
        wait_for("the saved edit", || {
            std::fs::read_to_string(&file).is_ok_and(|t| t.contains("<script>alert(1)</script> sink."))
        });
        // The list shows the text as text (no element made of it), and the statistics view.
        wait_for("the list to show the edit", || {
            tab.find_element("#candidates li.current div")
                .and_then(|e| e.get_inner_text())
                .is_ok_and(|t| t.contains("<script>"))
        });
        assert!(tab.find_elements("#candidates script").is_err_or_empty());
        // An edit not saved by hand is saved when another candidate opens: 7, from the
        // rejected file, edited, then 6 opened from the list.
        tab.wait_for_element("#candidates li[data-id=\"7\"]")
            .unwrap()
            .click()
            .unwrap();
        wait_for("candidate 7", || {
            tab.find_element("#cand-title")
                .and_then(|e| e.get_inner_text())
                .is_ok_and(|t| t == "Candidate 7")
        });
        let description = tab.wait_for_element("#description").unwrap();
        description.click().unwrap();
        tab.press_key("End").unwrap();
        tab.send_character(" Autosaved.").unwrap();
        tab.wait_for_element("#candidates li[data-id=\"6\"]")
            .unwrap()
            .click()
            .unwrap();
        let rejected = dir.path().join("mine.csv.rejected.jsonl");
        wait_for("the edit saved on leaving", || {
            std::fs::read_to_string(&rejected).is_ok_and(|t| t.contains("A study with a desk. Autosaved."))
        });
        tab.wait_for_element("#nav-stats").unwrap().click().unwrap();
        wait_for("the statistics", || {
            tab.find_element("#stats-table td")
                .and_then(|e| e.get_inner_text())
                .is_ok_and(|t| t == "Easy")
        });
        let errors = errors.lock().unwrap().clone();
        assert!(errors.is_empty(), "{errors:?}");
    }

    trait EmptyOrErr {
        fn is_err_or_empty(&self) -> bool;
    }

    impl<T, E> EmptyOrErr for Result<Vec<T>, E> {
        fn is_err_or_empty(&self) -> bool {
            self.as_ref().map_or(true, Vec::is_empty)
        }
    }
}
