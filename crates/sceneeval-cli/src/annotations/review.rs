//! `sceneeval annotations review FILE`: the paper's review step as a local web page. The
//! candidates, their states and the files every decision is written to are the facade's
//! (`sceneeval::annotate::review::ReviewStore`); the server is the command line's local page
//! server (`crate::server`: 127.0.0.1 only, Host, token and Origin checks, JSON bodies with a
//! size limit, strict security headers, hostile clients and Ctrl-C); this module is the page
//! (`review/body.html`, `review/app.js`, `review/app.css`, shipped in the binary) and its API:
//!
//! | route | request | response |
//! |---|---|---|
//! | `GET /api/candidates` | none | the file names and every candidate's summary |
//! | `GET /api/candidate?id=ID` | the ID | the candidate with the validator's findings |
//! | `GET /api/stats` | none | Table 1 of the accepted rows (Markdown and numbers) |
//! | `POST /api/validate` | `{id, content}` | the validator's findings of `content` |
//! | `POST /api/save` | `{id, content}` | the edit written; the candidate |
//! | `POST /api/accept` | `{id, content?}` | the (edited) candidate accepted; the candidate |
//! | `POST /api/reject` | `{id, content?, note}` | the candidate rejected with the note; the candidate |
//!
//! The page builds its DOM with `textContent` and form values only (descriptions are untrusted
//! text). Bad input never panics: a malformed request is answered with a status and a message.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::anyhow;
use sceneeval::ErrorChain;
use sceneeval::annotate::GenerateError;
use sceneeval::annotate::review::{
    Candidate, CandidateSource, ReviewError, ReviewState, ReviewStore, findings,
};
use sceneeval::annotation::{Finding, Severity};
use sceneeval::vlm::tasks::AnnotatedDescription;
use serde::{Deserialize, Serialize};
use serde_json::json;

use crate::server::{Api, ApiError, Asset, Listener, NoParams, Page};

/// The page (its head is the page server's, [`Page::html`]); its script and style sheet.
const PAGE: Page = Page {
    title: "sceneeval: review annotations",
    body: include_str!("review/body.html"),
};
const ASSETS: [Asset; 2] =
    Asset::page_files(include_bytes!("review/app.js"), include_bytes!("review/app.css"));

/// Arguments of `sceneeval annotations review`.
#[derive(Debug, clap::Args)]
pub struct ReviewArgs {
    /// The annotation file to review (typically the `--out` of `generate`); the candidates of
    /// FILE.rejected.jsonl are reviewed too.
    pub file: PathBuf,
    /// Where accepted rows go (default: FILE with `.accepted` before the extension); rejected
    /// ones go to OUT.rejected.jsonl with the reviewer's reason. (`--accepted` is its old
    /// name.)
    #[arg(long, short = 'o', alias = "accepted", value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// The port on 127.0.0.1 (0: a random free port).
    #[arg(long, default_value_t = 0, value_name = "P")]
    pub port: u16,
    /// Do not open the page in the default browser; only print its URL.
    #[arg(long)]
    pub no_open: bool,
}

fn api_error(e: ReviewError) -> ApiError {
    let status = match &e {
        ReviewError::UnknownId(_) => 404,
        ReviewError::HasErrors { .. } => 409,
        ReviewError::NoReason | ReviewError::SameFile(_) => 400,
        ReviewError::File(GenerateError::Unwritable { .. }) => 422,
        _ => 500,
    };
    ApiError::new(status, format!("{:#}", ErrorChain::new(&e)))
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

/// The query of `GET /api/candidate`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Id {
    id: String,
}

/// A line of the candidate list.
#[derive(Debug, Serialize)]
struct Summary {
    id: String,
    state: ReviewState,
    from_rejected: bool,
    difficulty: String,
    description: String,
    errors: usize,
    warnings: usize,
}

/// A candidate with the validator's findings.
#[derive(Debug, Serialize)]
struct Detail {
    candidate: Candidate,
    findings: Vec<Finding>,
}

fn count(findings: &[Finding], severity: Severity) -> usize {
    findings.iter().filter(|f| f.severity == severity).count()
}

/// The review's routes.
fn api() -> Api<ReviewStore> {
    Api::new()
        .get("candidates", |store: &mut ReviewStore, _: NoParams| Ok(list(store)))
        .get("candidate", |store: &mut ReviewStore, q: Id| detail(store, &q.id))
        .get("stats", |store: &mut ReviewStore, _: NoParams| {
            let stats = store.stats();
            Ok(json!({ "markdown": stats.to_markdown(), "stats": stats, "rows": store.accepted().rows.len() }))
        })
        .post("validate", |_: &mut ReviewStore, d: Decision| {
            let content = d.content.ok_or_else(no_content)?;
            Ok(json!({ "findings": findings(&content, &d.id) }))
        })
        .post("save", |store: &mut ReviewStore, d: Decision| {
            store
                .edit(&d.id, d.content.ok_or_else(no_content)?)
                .map_err(api_error)?;
            detail(store, &d.id)
        })
        .post("accept", |store: &mut ReviewStore, d: Decision| {
            store.accept(&d.id, d.content).map_err(api_error)?;
            detail(store, &d.id)
        })
        .post("reject", |store: &mut ReviewStore, d: Decision| {
            store
                .reject(&d.id, d.content, d.note.as_deref().unwrap_or_default())
                .map_err(api_error)?;
            detail(store, &d.id)
        })
}

fn list(store: &ReviewStore) -> serde_json::Value {
    let candidates: Vec<Summary> = store
        .candidates()
        .iter()
        .map(|c| {
            let f = findings(&c.content, &c.id);
            Summary {
                id: c.id.clone(),
                state: c.state,
                from_rejected: matches!(c.source, CandidateSource::Rejected { .. }),
                difficulty: c.content.difficulty.clone(),
                description: c.content.description.clone(),
                errors: count(&f, Severity::Error),
                warnings: count(&f, Severity::Warning),
            }
        })
        .collect();
    json!({
        "file": store.file(),
        "accepted_file": store.accepted_file(),
        "candidates": candidates,
    })
}

fn detail(store: &ReviewStore, id: &str) -> Result<Detail, ApiError> {
    let c = store
        .candidate(id)
        .ok_or_else(|| api_error(ReviewError::UnknownId(id.to_owned())))?;
    Ok(Detail {
        findings: findings(&c.content, &c.id),
        candidate: c.clone(),
    })
}

/// A request to validate or save that carries no text.
fn no_content() -> ApiError {
    ApiError::bad_request("the request has no \"content\"")
}

/// Runs `annotations review`: serves the page until Ctrl-C, then prints where the decisions
/// are.
pub fn review(args: ReviewArgs) -> anyhow::Result<ExitCode> {
    let store = ReviewStore::open(&args.file, args.out.as_deref())
        .map_err(|e| anyhow!("{:#}", ErrorChain::new(&e)))?;
    let listener = Listener::bind(args.port)?;
    let url = listener.url();
    crate::print_stdout(&format!(
        "Review of {} ({} candidates; accepted rows go to {}): {url}\nCtrl-C stops; every decision is saved at once.\n",
        store.file().display(),
        store.candidates().len(),
        store.accepted_file().display()
    ))?;
    let store = listener.serve_page(&PAGE, &ASSETS, api(), store, args.no_open)?;
    let states = store.candidates().iter().fold([0usize; 3], |mut n, c| {
        n[c.state as usize] += 1;
        n
    });
    crate::print_stdout(&format!(
        "stopped: {} pending, {} accepted, {} rejected; accepted rows in {}\n",
        states[0],
        states[1],
        states[2],
        store.accepted_file().display()
    ))?;
    Ok(ExitCode::SUCCESS)
}
