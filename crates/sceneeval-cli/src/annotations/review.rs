//! `sceneeval annotations review FILE`: the paper's review step as a local web page. The
//! candidates, their states and the files every decision is written to are the facade's
//! (`sceneeval::annotate::review::ReviewStore`); this module is the HTTP server and the page
//! (`review/page.html`, `review/app.js`, `review/app.css`, shipped in the binary).
//!
//! The server listens on 127.0.0.1 only, on a random free port by default, prints the URL and
//! handles one request at a time on the main thread (`tiny_http`). Security, since any page
//! the user opens in the same browser can send requests to 127.0.0.1:
//! - a request whose `Host` header is not `127.0.0.1:PORT` is refused (403), so a DNS name
//!   rebound to 127.0.0.1 cannot reach the API;
//! - every `/api/` request needs the per-run token (`X-Review-Token`, 128 random bits) that
//!   only the page served here carries, a request with an `Origin` other than the page's is
//!   refused, and a request that changes state must be `application/json` (which a cross-site
//!   form cannot send);
//! - the page builds its DOM with `textContent` and form values only (descriptions are
//!   untrusted text) under a Content-Security-Policy that allows no inline script and nothing
//!   from another origin.
//!
//! Bad input never panics: a malformed request is answered 400 with a message.

use std::io::Read;
use std::net::Ipv4Addr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context, anyhow};
use sceneeval::ErrorChain;
use sceneeval::annotate::GenerateError;
use sceneeval::annotate::review::{
    Candidate, CandidateSource, ReviewError, ReviewState, ReviewStore, findings,
};
use sceneeval::annotation::{Finding, Severity};
use sceneeval::vlm::tasks::AnnotatedDescription;
use serde::{Deserialize, Serialize};
use serde_json::json;
use tiny_http::{Header, Method, Request, Response, Server};

/// The page, its script and its style sheet.
const PAGE: &str = include_str!("review/page.html");
const SCRIPT: &str = include_str!("review/app.js");
const STYLE: &str = include_str!("review/app.css");

/// The page's placeholder for the token.
const TOKEN_SLOT: &str = "{{TOKEN}}";

/// The largest request body read (a candidate is a few kilobytes).
const MAX_BODY: u64 = 1 << 20;

/// The header that carries the token.
const TOKEN_HEADER: &str = "X-Review-Token";

/// Arguments of `sceneeval annotations review`.
#[derive(Debug, clap::Args)]
pub struct ReviewArgs {
    /// The annotation file to review (typically the `--out` of `generate`); the candidates of
    /// FILE.rejected.jsonl are reviewed too.
    pub file: PathBuf,
    /// Where accepted rows go (default: FILE with `.accepted` before the extension); rejected
    /// ones go to ACCEPTED.rejected.jsonl with the reviewer's reason.
    #[arg(long, value_name = "OUT")]
    pub accepted: Option<PathBuf>,
    /// The port on 127.0.0.1 (0: a random free port).
    #[arg(long, default_value_t = 0, value_name = "P")]
    pub port: u16,
    /// Do not open the page in the default browser; only print its URL.
    #[arg(long)]
    pub no_open: bool,
}

/// An HTTP error: status and message.
#[derive(Debug)]
struct HttpError {
    status: u16,
    message: String,
}

fn http_error(status: u16, message: impl Into<String>) -> HttpError {
    HttpError {
        status,
        message: message.into(),
    }
}

impl From<ReviewError> for HttpError {
    fn from(e: ReviewError) -> Self {
        let status = match &e {
            ReviewError::UnknownId(_) => 404,
            ReviewError::HasErrors { .. } => 409,
            ReviewError::NoReason | ReviewError::SameFile(_) => 400,
            ReviewError::File(GenerateError::Unwritable { .. }) => 422,
            _ => 500,
        };
        http_error(status, format!("{:#}", ErrorChain::new(&e)))
    }
}

/// A body of the API: the candidate's ID, its text when the request carries one, the reason
/// of a rejection.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Decision {
    id: String,
    #[serde(default)]
    content: Option<AnnotatedDescription>,
    #[serde(default)]
    note: Option<String>,
}

/// A line of the candidate list.
#[derive(Debug, Serialize)]
struct Summary<'a> {
    id: &'a str,
    state: ReviewState,
    from_rejected: bool,
    difficulty: &'a str,
    description: &'a str,
    errors: usize,
    warnings: usize,
}

/// A candidate with the validator's findings.
#[derive(Debug, Serialize)]
struct Detail<'a> {
    candidate: &'a Candidate,
    findings: Vec<Finding>,
}

fn count(findings: &[Finding], severity: Severity) -> usize {
    findings.iter().filter(|f| f.severity == severity).count()
}

/// The server's state: the store, the token, the expected `Host` and `Origin`.
struct App {
    store: ReviewStore,
    token: String,
    host: String,
    origin: String,
}

/// 128 bits from the operating system's generator, as hex.
fn new_token() -> anyhow::Result<String> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes).map_err(|e| anyhow!("no random bytes for the page's token: {e}"))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// Compares without stopping at the first difference.
fn same_secret(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

fn header_value<'r>(request: &'r Request, name: &str) -> Option<&'r str> {
    request
        .headers()
        .iter()
        .find(|h| h.field.as_str().as_str().eq_ignore_ascii_case(name))
        .map(|h| h.value.as_str())
}

fn header(name: &str, value: &str) -> Option<Header> {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).ok()
}

type Reply = Response<std::io::Cursor<Vec<u8>>>;

fn reply(status: u16, content_type: &str, body: Vec<u8>) -> Reply {
    let mut response = Response::from_data(body).with_status_code(status);
    for (name, value) in [
        ("Content-Type", content_type),
        ("Cache-Control", "no-store"),
        ("X-Content-Type-Options", "nosniff"),
        ("Referrer-Policy", "no-referrer"),
        (
            "Content-Security-Policy",
            "default-src 'none'; script-src 'self'; style-src 'self'; connect-src 'self'; \
             base-uri 'none'; form-action 'none'; frame-ancestors 'none'",
        ),
    ] {
        if let Some(h) = header(name, value) {
            response.add_header(h);
        }
    }
    response
}

fn json_reply(value: &impl Serialize) -> Result<Reply, HttpError> {
    let body = serde_json::to_vec(value).map_err(|e| http_error(500, format!("cannot write JSON: {e}")))?;
    Ok(reply(200, "application/json", body))
}

impl App {
    fn handle(&mut self, mut request: Request) {
        let response = match self.route(&mut request) {
            Ok(r) => r,
            Err(e) => {
                tracing::info!(status = e.status, message = %e.message, url = %request.url(), "request refused");
                let body = serde_json::to_vec(&json!({ "error": e.message })).unwrap_or_default();
                reply(e.status, "application/json", body)
            }
        };
        if let Err(e) = request.respond(response) {
            tracing::debug!(error = %e, "the response could not be sent");
        }
    }

    fn route(&mut self, request: &mut Request) -> Result<Reply, HttpError> {
        // DNS rebinding: only the address the page was served from.
        if header_value(request, "Host") != Some(self.host.as_str()) {
            return Err(http_error(
                403,
                format!(
                    "the Host header must be {} (the address this review serves)",
                    self.host
                ),
            ));
        }
        let url = request.url().to_owned();
        let (path, query) = url.split_once('?').unwrap_or((&url, ""));
        let method = request.method().clone();
        if !path.starts_with("/api/") {
            if method != Method::Get && method != Method::Head {
                return Err(http_error(405, format!("{method} is not allowed on {path}")));
            }
            return match path {
                "/" | "/index.html" => Ok(reply(
                    200,
                    "text/html; charset=utf-8",
                    PAGE.replace(TOKEN_SLOT, &self.token).into_bytes(),
                )),
                "/app.js" => Ok(reply(200, "text/javascript; charset=utf-8", SCRIPT.into())),
                "/app.css" => Ok(reply(200, "text/css; charset=utf-8", STYLE.into())),
                _ => Err(http_error(404, format!("no page {path}"))),
            };
        }
        // Another page of the browser must not read or post decisions.
        if header_value(request, "Origin").is_some_and(|o| o != self.origin) {
            return Err(http_error(403, "requests from another origin are refused"));
        }
        if !header_value(request, TOKEN_HEADER).is_some_and(|t| same_secret(t.trim(), &self.token)) {
            return Err(http_error(
                403,
                format!("missing or wrong {TOKEN_HEADER} header (the token of the page this review served)"),
            ));
        }
        match (method, path) {
            (Method::Get, "/api/candidates") => self.list(),
            (Method::Get, "/api/candidate") => {
                let id = query_id(query)?;
                self.detail(&id)
            }
            (Method::Get, "/api/stats") => {
                let stats = self.store.stats();
                json_reply(
                    &json!({ "markdown": stats.to_markdown(), "stats": stats, "rows": self.store.accepted().rows.len() }),
                )
            }
            (Method::Post, "/api/validate") => {
                let body = read_json(request)?;
                let content = body.content.ok_or_else(no_content)?;
                json_reply(&json!({ "findings": findings(&content, &body.id) }))
            }
            (Method::Post, "/api/save") => {
                let body = read_json(request)?;
                self.store.edit(&body.id, body.content.ok_or_else(no_content)?)?;
                self.detail(&body.id)
            }
            (Method::Post, "/api/accept") => {
                let body = read_json(request)?;
                self.store.accept(&body.id, body.content)?;
                self.detail(&body.id)
            }
            (Method::Post, "/api/reject") => {
                let body = read_json(request)?;
                self.store
                    .reject(&body.id, body.content, body.note.as_deref().unwrap_or_default())?;
                self.detail(&body.id)
            }
            (Method::Get | Method::Post, _) => Err(http_error(404, format!("no API endpoint {path}"))),
            (method, _) => Err(http_error(405, format!("{method} is not allowed on {path}"))),
        }
    }

    fn list(&self) -> Result<Reply, HttpError> {
        let candidates: Vec<Summary<'_>> = self
            .store
            .candidates()
            .iter()
            .map(|c| {
                let f = findings(&c.content, &c.id);
                Summary {
                    id: &c.id,
                    state: c.state,
                    from_rejected: matches!(c.source, CandidateSource::Rejected { .. }),
                    difficulty: &c.content.difficulty,
                    description: &c.content.description,
                    errors: count(&f, Severity::Error),
                    warnings: count(&f, Severity::Warning),
                }
            })
            .collect();
        json_reply(&json!({
            "file": self.store.file(),
            "accepted_file": self.store.accepted_file(),
            "candidates": candidates,
        }))
    }

    fn detail(&self, id: &str) -> Result<Reply, HttpError> {
        let c = self
            .store
            .candidate(id)
            .ok_or_else(|| HttpError::from(ReviewError::UnknownId(id.to_owned())))?;
        json_reply(&Detail {
            candidate: c,
            findings: findings(&c.content, &c.id),
        })
    }
}

/// A request to validate or save that carries no text.
fn no_content() -> HttpError {
    http_error(400, "the request has no \"content\"")
}

/// The `id` of a query string (`id=...`, percent-encoded).
fn query_id(query: &str) -> Result<String, HttpError> {
    let value = query
        .split('&')
        .find_map(|kv| kv.strip_prefix("id="))
        .ok_or_else(|| http_error(400, "the query needs id=ID"))?;
    urlencoding::decode(&value.replace('+', " "))
        .map(|v| v.into_owned())
        .map_err(|e| http_error(400, format!("the id is not UTF-8: {e}")))
}

/// The request's JSON body: `application/json`, at most [`MAX_BODY`] bytes.
fn read_json(request: &mut Request) -> Result<Decision, HttpError> {
    let is_json = header_value(request, "Content-Type").is_some_and(|t| {
        t.split(';')
            .next()
            .is_some_and(|m| m.trim().eq_ignore_ascii_case("application/json"))
    });
    if !is_json {
        return Err(http_error(415, "the body must be application/json"));
    }
    // Refused before reading when the length is declared, after reading at most one byte more
    // than the limit when it is not (chunked).
    let too_large = || http_error(413, format!("the body is larger than {MAX_BODY} bytes"));
    if request.body_length().is_some_and(|n| n as u64 > MAX_BODY) {
        return Err(too_large());
    }
    let mut body = Vec::new();
    request
        .as_reader()
        .take(MAX_BODY + 1)
        .read_to_end(&mut body)
        .map_err(|e| http_error(400, format!("cannot read the body: {e}")))?;
    if body.len() as u64 > MAX_BODY {
        return Err(too_large());
    }
    serde_json::from_slice(&body).map_err(|e| http_error(400, format!("the body is not a decision: {e}")))
}

/// Opens `url` in the default browser, without waiting; a failure is only logged.
fn open_in_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        "xdg-open"
    };
    match std::process::Command::new(opener)
        .arg(url)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
    {
        Ok(_) => tracing::info!(opener, "page opened"),
        Err(e) => tracing::warn!(opener, error = %e, "cannot open a browser; open the printed URL"),
    }
}

/// Ends the server's loop on Ctrl-C: a thread waits for the signal (tokio's, on a runtime of
/// its own), sets `stop` and unblocks the server, which finishes the request in hand first.
fn stop_on_ctrl_c(server: Arc<Server>, stop: Arc<AtomicBool>) -> anyhow::Result<()> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .context("cannot start the Ctrl-C handler")?;
    std::thread::Builder::new()
        .name("ctrl-c".into())
        .spawn(move || {
            if runtime.block_on(tokio::signal::ctrl_c()).is_ok() {
                stop.store(true, Ordering::SeqCst);
                server.unblock();
            }
        })
        .context("cannot start the Ctrl-C handler")?;
    Ok(())
}

/// Runs `annotations review`: serves the page until Ctrl-C, then prints where the decisions
/// are.
pub fn review(args: ReviewArgs) -> anyhow::Result<ExitCode> {
    let store = ReviewStore::open(&args.file, args.accepted.as_deref())
        .map_err(|e| anyhow!("{:#}", ErrorChain::new(&e)))?;
    let server = Server::http((Ipv4Addr::LOCALHOST, args.port))
        .map_err(|e| anyhow!("cannot listen on 127.0.0.1:{}: {e}", args.port))?;
    let addr = server
        .server_addr()
        .to_ip()
        .ok_or_else(|| anyhow!("the server did not listen on an IP address"))?;
    if !addr.ip().is_loopback() {
        return Err(anyhow!("refusing to serve the review on {addr}: only 127.0.0.1"));
    }
    let host = format!("127.0.0.1:{}", addr.port());
    let url = format!("http://{host}/");
    let server = Arc::new(server);
    let stop = Arc::new(AtomicBool::new(false));
    stop_on_ctrl_c(Arc::clone(&server), Arc::clone(&stop))?;
    crate::print_stdout(&format!(
        "Review of {} ({} candidates; accepted rows go to {}): {url}\nCtrl-C stops; every decision is saved at once.\n",
        store.file().display(),
        store.candidates().len(),
        store.accepted_file().display()
    ))?;
    if !args.no_open {
        open_in_browser(&url);
    }
    let mut app = App {
        store,
        token: new_token()?,
        origin: format!("http://{host}"),
        host,
    };
    loop {
        match server.recv() {
            Ok(request) => app.handle(request),
            Err(_) if stop.load(Ordering::SeqCst) => break,
            Err(e) => tracing::warn!(error = %e, "a connection failed"),
        }
    }
    let states = app.store.candidates().iter().fold([0usize; 3], |mut n, c| {
        n[c.state as usize] += 1;
        n
    });
    crate::print_stdout(&format!(
        "stopped: {} pending, {} accepted, {} rejected; accepted rows in {}\n",
        states[0],
        states[1],
        states[2],
        app.store.accepted_file().display()
    ))?;
    Ok(ExitCode::SUCCESS)
}
