//! The local page server: one module for every page the command line serves to the user's
//! browser on 127.0.0.1 (`sceneeval annotations review` and `sceneeval judge`). A page brings
//! its HTML, its static files, its state and its API, a list of typed
//! routes ([`Api`]: a handler takes the page's state and a request type deserialized from the
//! query or the JSON body, and returns a response type serialized as JSON, or bytes of their
//! own type such as an image, [`Raw`]); this module does the rest, the same way for every page:
//!
//! - **Only 127.0.0.1**: the listener is bound to the loopback address only, on a random free
//!   port unless one is given ([`Listener::bind`]).
//! - **Host check**: a request whose `Host` header is not `127.0.0.1:PORT` is refused (403), so
//!   a DNS name rebound to 127.0.0.1 (DNS rebinding) cannot reach the API.
//! - **Per-run token**: 128 bits from the operating system's generator, put into the page
//!   (`<meta name="sceneeval-token" content="{{TOKEN}}">`, [`TOKEN_SLOT`]) and required on every
//!   `/api/` request in the [`TOKEN_HEADER`] header (compared in constant time); only the page
//!   this run served has it. The page's script sends its requests through `sceneevalApi`
//!   ([`CLIENT_SCRIPT`], served at `/sceneeval-api.js`), which adds it.
//! - **Origin check**: an `/api/` request with an `Origin` other than the page's is refused.
//! - **JSON bodies with a size limit**: a POST must be `application/json` (which a cross-site
//!   form cannot send) of at most [`Limits::max_body`] bytes; a request that declares more is
//!   answered 413 before anything else is looked at, and nothing of its body is read; a
//!   chunked body is read up to one byte past the limit.
//! - **Strict headers**: every response has a Content-Security-Policy that allows no inline
//!   script, nothing from another origin (images also from `blob:` URLs, which the page makes
//!   of what it fetched with its token) and no framing, `nosniff`, `no-referrer`,
//!   `Cache-Control: no-store`, and same-origin resource and opener policies.
//! - **Hostile clients cannot stop it**: each connection is served on its own task, so a slow
//!   or silent client does not hold up the others; headers must arrive within
//!   [`Limits::header_timeout`], a body within [`Limits::body_timeout`], and a connection lives
//!   at most [`Limits::connection_timeout`] (one request per connection); at most
//!   [`Limits::max_connections`] are open at once. A malformed request is answered with a
//!   status and a JSON `{"error": ...}`; nothing a client sends ends the server.
//! - **Ctrl-C** (SIGINT) stops it at once: no new connection is accepted, requests being
//!   handled get [`SHUTDOWN_GRACE`] to finish (a decision being written completes), and slow
//!   clients are dropped.
//!
//! The HTTP/1.1 server is hyper's (on tokio, with one current-thread runtime per server):
//! handlers run on tokio's blocking threads under a lock of the page's state, one at a time,
//! so a page's state needs no synchronisation of its own.

mod api;
mod http;

use std::net::{Ipv4Addr, SocketAddr, TcpListener};
use std::time::Duration;

use anyhow::{Context, anyhow};

pub use api::{Api, ApiError, NoParams, Raw};

/// The placeholder of the page's HTML that the per-run token replaces.
pub const TOKEN_SLOT: &str = "{{TOKEN}}";

/// The header of every `/api/` request that carries the per-run token.
pub const TOKEN_HEADER: &str = "X-Sceneeval-Token";

/// The page server's client script, served to every page at `/sceneeval-api.js`:
/// `sceneevalApi(method, path, body, options)` sends a request with the page's token (the
/// page loads it before its own script).
pub const CLIENT_SCRIPT: Asset = Asset {
    path: "/sceneeval-api.js",
    content_type: "text/javascript; charset=utf-8",
    body: include_bytes!("client.js"),
};

/// How long requests being handled may take to finish after Ctrl-C.
pub const SHUTDOWN_GRACE: Duration = Duration::from_secs(2);

/// A page's HTML: its title and its `<body>` element; [`Page::html`] writes the document
/// around them, the same head for every page (the token's slot, the style sheet, the client
/// script and the page's script, at the paths [`Asset::page_files`] and [`CLIENT_SCRIPT`]
/// serve).
#[derive(Debug, Clone, Copy)]
pub struct Page {
    /// The document's title (trusted text, written as it is).
    pub title: &'static str,
    /// The `<body>...</body>` element, with its line end.
    pub body: &'static str,
}

impl Page {
    /// The whole document: the doctype, the head, the body.
    pub fn html(&self) -> String {
        format!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
             <meta name=\"sceneeval-token\" content=\"{TOKEN_SLOT}\">\n<title>{}</title>\n\
             <link rel=\"stylesheet\" href=\"/app.css\">\n<script src=\"{}\" defer></script>\n\
             <script src=\"/app.js\" defer></script>\n</head>\n{}</html>\n",
            self.title, CLIENT_SCRIPT.path, self.body
        )
    }
}

/// A static file of a page (`/app.js`, `/app.css`).
#[derive(Debug, Clone, Copy)]
pub struct Asset {
    /// Its path, from the root (`/app.js`).
    pub path: &'static str,
    /// Its `Content-Type`.
    pub content_type: &'static str,
    /// Its bytes.
    pub body: &'static [u8],
}

impl Asset {
    /// A page's script and style sheet, served at `/app.js` and `/app.css` (every page's
    /// HTML loads them from there).
    pub const fn page_files(script: &'static [u8], style: &'static [u8]) -> [Asset; 2] {
        [
            Asset {
                path: "/app.js",
                content_type: "text/javascript; charset=utf-8",
                body: script,
            },
            Asset {
                path: "/app.css",
                content_type: "text/css; charset=utf-8",
                body: style,
            },
        ]
    }
}

/// What the server holds a client to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// The largest request body, in bytes.
    pub max_body: usize,
    /// The time a client has to send a request's headers.
    pub header_timeout: Duration,
    /// The time a client has to send a request's body.
    pub body_timeout: Duration,
    /// The longest a connection is kept open, whatever it does.
    pub connection_timeout: Duration,
    /// The most connections open at once; more wait in the operating system's queue.
    pub max_connections: usize,
}

impl Default for Limits {
    /// 1 MiB bodies (a page's request is a few kilobytes), 30 s for headers and for a body,
    /// 120 s per connection, 64 connections.
    fn default() -> Self {
        Limits {
            max_body: 1 << 20,
            header_timeout: Duration::from_secs(30),
            body_timeout: Duration::from_secs(30),
            connection_timeout: Duration::from_secs(120),
            max_connections: 64,
        }
    }
}

/// A page: its HTML (with [`TOKEN_SLOT`] where the token goes), its static files, its API and
/// the limits it is served with.
pub struct Site<S> {
    /// The HTML served at `/` and `/index.html`.
    pub html: String,
    /// The static files.
    pub assets: Vec<Asset>,
    /// The routes under `/api/`.
    pub api: Api<S>,
    /// The limits.
    pub limits: Limits,
}

impl<S> std::fmt::Debug for Site<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Site")
            .field("assets", &self.assets)
            .field("api", &self.api)
            .field("limits", &self.limits)
            .finish_non_exhaustive()
    }
}

/// A port on 127.0.0.1, bound and ready to serve a page; Ctrl-C is caught from the moment it
/// is bound.
#[derive(Debug)]
pub struct Listener {
    listener: TcpListener,
    addr: SocketAddr,
    runtime: http::Runtime,
}

impl Listener {
    /// Binds 127.0.0.1:`port` (0: a random free port) and starts catching Ctrl-C (which then
    /// stops [`Listener::serve`], or ends nothing before it is called).
    ///
    /// # Errors
    /// When the port cannot be bound (in use, not allowed), or the runtime or the Ctrl-C
    /// handler cannot start.
    pub fn bind(port: u16) -> anyhow::Result<Listener> {
        let runtime = http::Runtime::new()?;
        let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, port))
            .with_context(|| format!("cannot listen on 127.0.0.1:{port}"))?;
        let addr = listener.local_addr().context("the listener has no address")?;
        if !addr.ip().is_loopback() {
            return Err(anyhow!("refusing to serve on {addr}: only 127.0.0.1"));
        }
        Ok(Listener {
            listener,
            addr,
            runtime,
        })
    }

    /// The page's URL, `http://127.0.0.1:PORT/`.
    pub fn url(&self) -> String {
        format!("http://127.0.0.1:{}/", self.addr.port())
    }

    /// A page's whole session: opens the page in the user's browser unless `no_open`, then
    /// serves `page` with its `assets` and `api` under the default [`Limits`] until Ctrl-C,
    /// and returns the state.
    ///
    /// # Errors
    /// As [`Listener::serve`].
    pub fn serve_page<S: Send + 'static>(
        self,
        page: &Page,
        assets: &[Asset],
        api: Api<S>,
        state: S,
        no_open: bool,
    ) -> anyhow::Result<S> {
        if !no_open {
            open_in_browser(&self.url());
        }
        let site = Site {
            html: page.html(),
            assets: assets.to_vec(),
            api,
            limits: Limits::default(),
        };
        self.serve(site, state)
    }

    /// Serves `site` with `state` until Ctrl-C, then returns the state.
    ///
    /// # Errors
    /// When no token can be drawn or the listener cannot be set up.
    pub fn serve<S: Send + 'static>(self, site: Site<S>, state: S) -> anyhow::Result<S> {
        http::serve(
            self.runtime,
            self.listener,
            self.addr.port(),
            site,
            state,
            new_token()?,
        )
    }
}

/// 128 bits from the operating system's generator, as hex.
fn new_token() -> anyhow::Result<String> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes).map_err(|e| anyhow!("no random bytes for the page's token: {e}"))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// Opens `url` in the default browser, without waiting; a failure is only logged.
pub fn open_in_browser(url: &str) {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every page's document is this head (written out by hand) around the page's body: the
    /// token's slot, the style sheet, the client script and the page's script.
    #[test]
    fn a_page_is_the_one_head_around_its_body() {
        let page = Page {
            title: "sceneeval: a page",
            body: "<body>\n<p>x</p>\n</body>\n",
        };
        assert_eq!(
            page.html(),
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
             <meta name=\"sceneeval-token\" content=\"{{TOKEN}}\">\n<title>sceneeval: a page</title>\n\
             <link rel=\"stylesheet\" href=\"/app.css\">\n<script src=\"/sceneeval-api.js\" defer></script>\n\
             <script src=\"/app.js\" defer></script>\n</head>\n<body>\n<p>x</p>\n</body>\n</html>\n"
        );
    }
}
