//! The server itself: hyper's HTTP/1.1 on a current-thread tokio runtime, the accept loop (one
//! task per connection, a bounded number of them, Ctrl-C), and the checks every request goes
//! through before a page's handler sees it.

use std::convert::Infallible;
use std::sync::{Arc, Mutex, PoisonError};

use anyhow::Context;
use bytes::Bytes;
use http_body_util::{BodyExt, Full, LengthLimitError, Limited};
use hyper::body::{Body, Incoming};
use hyper::header::{CONTENT_TYPE, HOST, HeaderName, HeaderValue, ORIGIN};
use hyper::http::request::Parts;
use hyper::{Request, Response, StatusCode};
use hyper_util::rt::{TokioIo, TokioTimer};
use tokio::net::TcpStream;
use tokio::sync::{OwnedSemaphorePermit, Semaphore};
use tokio::task::JoinSet;

use super::api::{Input, Method};
use super::{Api, ApiError, Asset, CLIENT_SCRIPT, Limits, SHUTDOWN_GRACE, Site, TOKEN_HEADER, TOKEN_SLOT};

/// The headers of every response.
const SECURITY_HEADERS: [(&str, &str); 6] = [
    ("cache-control", "no-store"),
    ("x-content-type-options", "nosniff"),
    ("referrer-policy", "no-referrer"),
    ("cross-origin-resource-policy", "same-origin"),
    ("cross-origin-opener-policy", "same-origin"),
    (
        "content-security-policy",
        "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' blob:; connect-src 'self'; \
         base-uri 'none'; form-action 'none'; frame-ancestors 'none'",
    ),
];

/// Everything a connection's task needs: the page, its state and what requests must carry.
pub(super) struct Shared<S> {
    /// The page's HTML with the token in place.
    html: String,
    assets: Vec<Asset>,
    api: Api<S>,
    limits: Limits,
    /// The page's state; `None` once the server has stopped and returned it.
    state: Mutex<Option<S>>,
    token: String,
    /// `127.0.0.1:PORT`.
    host: String,
    /// `http://127.0.0.1:PORT`.
    origin: String,
}

/// What a request that passed the checks asks for.
#[derive(Debug, PartialEq, Eq)]
enum Target {
    /// A static file: its type and bytes.
    Static(&'static str, Bytes),
    /// Nothing, on purpose (the browser's `/favicon.ico`: a page has no icon, and a 404 would
    /// be an error in the browser's console).
    NoContent,
    /// An API route with its query string.
    Api {
        method: Method,
        name: String,
        query: String,
    },
}

impl<S> Shared<S> {
    pub(super) fn new(site: Site<S>, state: S, port: u16, token: String) -> Self {
        let host = format!("127.0.0.1:{port}");
        Shared {
            html: site.html.replace(TOKEN_SLOT, &token),
            assets: site.assets.into_iter().chain([CLIENT_SCRIPT]).collect(),
            api: site.api,
            limits: site.limits,
            state: Mutex::new(Some(state)),
            token,
            origin: format!("http://{host}"),
            host,
        }
    }

    /// The checks of a request's head (`declared`: the body length it declares, 0 when it
    /// declares none), in this order: the body's size (413, before anything else, so nothing
    /// of an oversized body is ever read), the `Host` (403), then for `/api/` the `Origin`
    /// (403), the token (403), the method and, for a POST, the content type (415); for
    /// anything else GET or HEAD of the page or a static file.
    fn check(&self, head: &Parts, declared: u64) -> Result<Target, ApiError> {
        let max = self.limits.max_body;
        if declared > max as u64 {
            return Err(ApiError::new(413, format!("the body is larger than {max} bytes")));
        }
        let header = |name: HeaderName| head.headers.get(name).and_then(|v| v.to_str().ok());
        // DNS rebinding: only the address the page was served from.
        if header(HOST) != Some(self.host.as_str()) {
            return Err(ApiError::new(
                403,
                format!(
                    "the Host header must be {} (the address this page is served on)",
                    self.host
                ),
            ));
        }
        let path = head.uri.path();
        let Some(name) = path.strip_prefix("/api/") else {
            if head.method != hyper::Method::GET && head.method != hyper::Method::HEAD {
                return Err(ApiError::new(
                    405,
                    format!("{} is not allowed on {path}", head.method),
                ));
            }
            if path == "/favicon.ico" {
                return Ok(Target::NoContent);
            }
            if path == "/" || path == "/index.html" {
                return Ok(Target::Static(
                    "text/html; charset=utf-8",
                    Bytes::from(self.html.clone()),
                ));
            }
            return match self.assets.iter().find(|a| a.path == path) {
                Some(a) => Ok(Target::Static(a.content_type, Bytes::from_static(a.body))),
                None => Err(ApiError::not_found(format!("no page {path}"))),
            };
        };
        // Another page of the browser must not read or change anything.
        if header(ORIGIN).is_some_and(|o| o != self.origin) {
            return Err(ApiError::new(403, "requests from another origin are refused"));
        }
        let token = head.headers.get(TOKEN_HEADER).and_then(|v| v.to_str().ok());
        if !token.is_some_and(|t| same_secret(t.trim(), &self.token)) {
            return Err(ApiError::new(
                403,
                format!("missing or wrong {TOKEN_HEADER} header (the token of the page this server served)"),
            ));
        }
        let method = match head.method {
            hyper::Method::GET => Method::Get,
            hyper::Method::POST => {
                let is_json = header(CONTENT_TYPE).is_some_and(|t| {
                    t.split(';')
                        .next()
                        .is_some_and(|m| m.trim().eq_ignore_ascii_case("application/json"))
                });
                if !is_json {
                    return Err(ApiError::new(415, "the body must be application/json"));
                }
                Method::Post
            }
            ref other => return Err(ApiError::new(405, format!("{other} is not allowed on {path}"))),
        };
        Ok(Target::Api {
            method,
            name: name.to_owned(),
            query: head.uri.query().unwrap_or_default().to_owned(),
        })
    }

    /// The state back from a stopped server (waiting for a handler still running).
    fn take_state(&self) -> Option<S> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner).take()
    }
}

/// Compares without stopping at the first difference.
fn same_secret(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// The server's runtime and its Ctrl-C, made when the port is bound (before the URL is
/// printed, so that a Ctrl-C right after it is caught).
pub(super) struct Runtime {
    runtime: tokio::runtime::Runtime,
    interrupt: Interrupt,
}

impl std::fmt::Debug for Runtime {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Runtime").finish_non_exhaustive()
    }
}

impl Runtime {
    /// A current-thread runtime, and SIGINT caught from now on.
    pub(super) fn new() -> anyhow::Result<Self> {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .context("cannot start the page server's runtime")?;
        let interrupt = {
            let _context = runtime.enter();
            Interrupt::new().context("cannot catch Ctrl-C")?
        };
        Ok(Runtime { runtime, interrupt })
    }
}

/// Serves until Ctrl-C, then returns the page's state.
pub(super) fn serve<S: Send + 'static>(
    Runtime { runtime, interrupt }: Runtime,
    listener: std::net::TcpListener,
    port: u16,
    site: Site<S>,
    state: S,
    token: String,
) -> anyhow::Result<S> {
    let shared = Arc::new(Shared::new(site, state, port, token));
    let result = runtime.block_on(accept_loop(listener, interrupt, Arc::clone(&shared)));
    // Connections still open are dropped; a handler still running gets the grace to finish.
    runtime.shutdown_timeout(SHUTDOWN_GRACE);
    result?;
    shared
        .take_state()
        .context("the page's state was lost (a handler failed)")
}

/// Accepts connections until Ctrl-C, each served on its own task.
async fn accept_loop<S: Send + 'static>(
    listener: std::net::TcpListener,
    mut interrupt: Interrupt,
    shared: Arc<Shared<S>>,
) -> anyhow::Result<()> {
    listener
        .set_nonblocking(true)
        .context("cannot set up the listener")?;
    let listener = tokio::net::TcpListener::from_std(listener).context("cannot set up the listener")?;
    let slots = Arc::new(Semaphore::new(shared.limits.max_connections));
    let mut connections = JoinSet::new();
    loop {
        // A free slot first: past the limit, connections wait in the operating system's queue.
        let permit = tokio::select! {
            () = interrupt.recv() => break,
            permit = Arc::clone(&slots).acquire_owned() => permit.context("the connection limit closed")?,
        };
        let stream = tokio::select! {
            () = interrupt.recv() => break,
            accepted = listener.accept() => match accepted {
                Ok((stream, _)) => stream,
                Err(e) => {
                    // Out of file descriptors and the like: wait a moment rather than spin.
                    tracing::warn!(error = %e, "a connection could not be accepted");
                    tokio::time::sleep(std::time::Duration::from_millis(50)).await;
                    continue;
                }
            },
        };
        while connections.try_join_next().is_some() {}
        connections.spawn(connection(stream, Arc::clone(&shared), permit));
    }
    tracing::info!(open = connections.len(), "Ctrl-C: the page server stops");
    connections.abort_all();
    Ok(())
}

/// Serves one connection: one request (no keep-alive), its headers within the header timeout,
/// the whole connection within the connection timeout.
async fn connection<S: Send + 'static>(
    stream: TcpStream,
    shared: Arc<Shared<S>>,
    _slot: OwnedSemaphorePermit,
) {
    let limits = shared.limits;
    let service = hyper::service::service_fn(move |request| respond(Arc::clone(&shared), request));
    let mut builder = hyper::server::conn::http1::Builder::new();
    builder
        .timer(TokioTimer::new())
        .header_read_timeout(limits.header_timeout)
        .max_header_size(64 * 1024)
        .keep_alive(false);
    let served = builder.serve_connection(TokioIo::new(stream), service);
    match tokio::time::timeout(limits.connection_timeout, served).await {
        Ok(Ok(())) => {}
        Ok(Err(e)) => tracing::debug!(error = %e, "a connection ended early"),
        Err(_) => tracing::info!("a connection was closed: open longer than the limit"),
    }
}

/// The response to one request: what the page asked for, or the refusal as JSON.
async fn respond<S: Send + 'static>(
    shared: Arc<Shared<S>>,
    request: Request<Incoming>,
) -> Result<Response<Full<Bytes>>, Infallible> {
    let path = request.uri().path().to_owned();
    Ok(match handle(&shared, request).await {
        Ok(None) => response(204, "text/plain; charset=utf-8", Bytes::new()),
        Ok(Some((content_type, body))) => response(200, content_type, body),
        Err(e) => {
            tracing::info!(status = e.status, message = %e.message, %path, "request refused");
            let body = serde_json::to_vec(&serde_json::json!({ "error": e.message })).unwrap_or_default();
            response(e.status, "application/json", Bytes::from(body))
        }
    })
}

/// The type and bytes of the answer to `request` (`None`: no content), or the refusal.
async fn handle<S: Send + 'static>(
    shared: &Arc<Shared<S>>,
    request: Request<Incoming>,
) -> Result<Option<(&'static str, Bytes)>, ApiError> {
    let (head, body) = request.into_parts();
    let target = shared.check(&head, body.size_hint().lower())?;
    let (method, name, query) = match target {
        Target::NoContent => return Ok(None),
        Target::Static(content_type, bytes) => return Ok(Some((content_type, bytes))),
        Target::Api { method, name, query } => (method, name, query),
    };
    let body = match method {
        Method::Post => Some(read_body(body, &shared.limits).await?),
        Method::Get => None,
    };
    let shared = Arc::clone(shared);
    // File writes and validation off the connections' thread, one request at a time.
    let reply = tokio::task::spawn_blocking(move || {
        let mut guard = shared.state.lock().unwrap_or_else(PoisonError::into_inner);
        let Some(state) = guard.as_mut() else {
            return Err(ApiError::new(503, "the server is stopping"));
        };
        let input = match &body {
            Some(b) => Input::Body(b),
            None => Input::Query(&query),
        };
        shared.api.call(state, method, &name, input)
    })
    .await
    .map_err(|e| ApiError::new(500, format!("the request's handler failed: {e}")))??;
    Ok(Some((reply.0, Bytes::from(reply.1))))
}

/// A request's body: at most `limits.max_body` bytes (413 past it), arrived within
/// `limits.body_timeout` (408 otherwise).
async fn read_body(body: Incoming, limits: &Limits) -> Result<Bytes, ApiError> {
    let collected =
        tokio::time::timeout(limits.body_timeout, Limited::new(body, limits.max_body).collect()).await;
    match collected {
        Ok(Ok(c)) => Ok(c.to_bytes()),
        Ok(Err(e)) if e.is::<LengthLimitError>() => Err(ApiError::new(
            413,
            format!("the body is larger than {} bytes", limits.max_body),
        )),
        Ok(Err(e)) => Err(ApiError::bad_request(format!("cannot read the body: {e}"))),
        Err(_) => Err(ApiError::new(
            408,
            format!(
                "the body did not arrive within {} s",
                limits.body_timeout.as_secs()
            ),
        )),
    }
}

fn response(status: u16, content_type: &'static str, body: Bytes) -> Response<Full<Bytes>> {
    let mut response = Response::new(Full::new(body));
    *response.status_mut() = StatusCode::from_u16(status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR);
    let headers = response.headers_mut();
    headers.insert(CONTENT_TYPE, HeaderValue::from_static(content_type));
    for (name, value) in SECURITY_HEADERS {
        headers.insert(name, HeaderValue::from_static(value));
    }
    response
}

/// Ctrl-C: SIGINT on Unix, caught from the moment this is made.
struct Interrupt {
    #[cfg(unix)]
    signal: tokio::signal::unix::Signal,
}

impl Interrupt {
    #[cfg(unix)]
    fn new() -> std::io::Result<Self> {
        use tokio::signal::unix::{SignalKind, signal};
        Ok(Interrupt {
            signal: signal(SignalKind::interrupt())?,
        })
    }

    #[cfg(not(unix))]
    fn new() -> std::io::Result<Self> {
        Ok(Interrupt {})
    }

    /// Waits for Ctrl-C.
    async fn recv(&mut self) {
        #[cfg(unix)]
        {
            self.signal.recv().await;
        }
        #[cfg(not(unix))]
        {
            let _ = tokio::signal::ctrl_c().await;
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::panic)]

    use super::*;
    use crate::server::NoParams;

    const PAGE: &str = "<meta name=\"sceneeval-token\" content=\"{{TOKEN}}\">";
    const TOKEN: &str = "00112233445566778899aabbccddeeff";

    fn shared() -> Shared<u32> {
        let site = Site {
            html: PAGE.to_owned(),
            assets: vec![Asset {
                path: "/app.js",
                content_type: "text/javascript; charset=utf-8",
                body: b"1;",
            }],
            api: Api::new().get("n", |s: &mut u32, _: NoParams| Ok(*s)),
            limits: Limits::default(),
        };
        Shared::new(site, 7, 4321, TOKEN.to_owned())
    }

    fn head(method: &str, uri: &str, headers: &[(&str, &str)]) -> Parts {
        let mut b = Request::builder().method(method).uri(uri);
        for (k, v) in headers {
            b = b.header(*k, *v);
        }
        b.body(()).unwrap().into_parts().0
    }

    const HOST_OK: (&str, &str) = ("host", "127.0.0.1:4321");
    const TOKEN_OK: (&str, &str) = (TOKEN_HEADER, TOKEN);

    fn status(s: &Shared<u32>, h: &Parts, declared: u64) -> u16 {
        s.check(h, declared).map_or_else(|e| e.status, |_| 200)
    }

    #[test]
    fn an_oversized_body_is_refused_before_anything_else() {
        let s = shared();
        // No Host, no token: still 413, the body's size is looked at first.
        let h = head("POST", "/api/n", &[]);
        assert_eq!(status(&s, &h, 99_999_999_999_999), 413);
        assert_eq!(status(&s, &h, 1 << 20), 403);
    }

    #[test]
    fn the_page_and_its_files_need_the_host_only() {
        let s = shared();
        let page = s.check(&head("GET", "/", &[HOST_OK]), 0).unwrap();
        let Target::Static(kind, body) = page else {
            panic!()
        };
        assert_eq!(kind, "text/html; charset=utf-8");
        assert_eq!(
            body,
            format!("<meta name=\"sceneeval-token\" content=\"{TOKEN}\">")
        );
        assert!(matches!(
            s.check(&head("HEAD", "/app.js", &[HOST_OK]), 0),
            Ok(Target::Static(_, _))
        ));
        for (h, want) in [
            (head("GET", "/", &[("host", "localhost:4321")]), 403),
            (head("GET", "/", &[("host", "evil.example:4321")]), 403),
            (head("GET", "/", &[]), 403),
            (head("POST", "/", &[HOST_OK]), 405),
            (head("GET", "/etc/passwd", &[HOST_OK]), 404),
            (head("GET", "/api", &[HOST_OK]), 404),
        ] {
            assert_eq!(status(&s, &h, 0), want, "{h:?}");
        }
    }

    #[test]
    fn the_api_needs_the_token_the_origin_and_json() {
        let s = shared();
        let json = ("content-type", "application/json; charset=utf-8");
        let origin = ("origin", "http://127.0.0.1:4321");
        assert_eq!(
            s.check(&head("GET", "/api/n?x=1", &[HOST_OK, TOKEN_OK, origin]), 0)
                .unwrap(),
            Target::Api {
                method: Method::Get,
                name: "n".into(),
                query: "x=1".into()
            }
        );
        for (h, want) in [
            (head("GET", "/api/n", &[HOST_OK]), 403),
            (head("GET", "/api/n", &[HOST_OK, (TOKEN_HEADER, "0011")]), 403),
            (
                head("GET", "/api/n", &[HOST_OK, (TOKEN_HEADER, &TOKEN.to_uppercase())]),
                403,
            ),
            (
                head(
                    "GET",
                    "/api/n",
                    &[HOST_OK, TOKEN_OK, ("origin", "http://evil.example")],
                ),
                403,
            ),
            (head("POST", "/api/n", &[HOST_OK, TOKEN_OK]), 415),
            (
                head(
                    "POST",
                    "/api/n",
                    &[HOST_OK, TOKEN_OK, ("content-type", "text/plain")],
                ),
                415,
            ),
            (head("POST", "/api/n", &[HOST_OK, TOKEN_OK, json]), 200),
            (head("DELETE", "/api/n", &[HOST_OK, TOKEN_OK]), 405),
        ] {
            assert_eq!(status(&s, &h, 10), want, "{h:?}");
        }
    }

    #[test]
    fn responses_carry_the_security_headers() {
        let r = response(404, "application/json", Bytes::new());
        assert_eq!(r.status(), 404);
        let csp = r
            .headers()
            .get("content-security-policy")
            .unwrap()
            .to_str()
            .unwrap();
        assert!(csp.contains("script-src 'self';") && csp.contains("frame-ancestors 'none'"));
        assert!(csp.contains("img-src 'self' blob:;") && csp.starts_with("default-src 'none';"));
        assert_eq!(r.headers().get("x-content-type-options").unwrap(), "nosniff");
        assert_eq!(r.headers().get("content-type").unwrap(), "application/json");
    }

    #[test]
    fn the_client_script_is_served_and_sends_the_token_header() {
        let s = shared();
        let Ok(Target::Static(kind, body)) = s.check(&head("GET", "/sceneeval-api.js", &[HOST_OK]), 0) else {
            panic!("not served")
        };
        assert_eq!(kind, "text/javascript; charset=utf-8");
        let script = std::str::from_utf8(&body).unwrap();
        assert!(
            script.contains(&format!("\"{TOKEN_HEADER}\": SCENEEVAL_TOKEN")),
            "{script}"
        );
        assert!(script.contains("meta[name=\"sceneeval-token\"]"));
        // Images of a route of bytes are fetched with the token too, shown through blob: URLs
        // (which the policy allows for images only).
        assert!(script.contains("async function sceneevalBlobUrl(path)"));
        assert!(script.matches("\"X-Sceneeval-Token\": SCENEEVAL_TOKEN").count() == 2);
    }

    #[test]
    fn secrets_compare_whole() {
        assert!(same_secret("abc", "abc"));
        assert!(!same_secret("abc", "abd"));
        assert!(!same_secret("abc", "ab"));
    }
}
