//! `sceneeval judge RUN --annotator NAME --out LABELS`: a person judges a run's fidelity specs
//! in the browser, one at a time, and every verdict is appended to a label file at once
//! (`docs/judge.md`, "Judge"). The items, their order and the sample are the report crate's
//! (`sceneeval::report::judge`); the label file is written by its locked, durable writer
//! (`sceneeval::report::label_writer`); the server is the command line's local page server
//! (`crate::server`); this module is the page (`judge/body.html`, `judge/app.js`,
//! `judge/app.css`, shipped in the binary) and its API:
//!
//! | route | request | response |
//! |---|---|---|
//! | `GET /api/items` | none | the items (spec, words, objects, this annotator's verdict; the run's verdict only with `--show-verdicts`), the scenes' descriptions, progress |
//! | `GET /api/topview?item=K` | item number | the scene's top view with the spec's objects outlined (SVG) |
//! | `GET /api/view?item=K&object=ID&kind=front\|size` | item, object, view | the object view the VLM is shown (PNG): the run's file when it kept it, else rendered |
//! | `POST /api/verdict` | `{item, satisfied}` | the verdict appended to LABELS; progress |
//!
//! Blind by default: the run's verdicts are not in any response unless `--show-verdicts`. The
//! page builds its DOM with `textContent` only, and shows images from `blob:` URLs.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use sceneeval::ErrorChain;
use sceneeval::annotation::Annotations;
use sceneeval::fidelity::{FidelityMetric, ObjectViews, RenderedViews, ViewKind};
use sceneeval::inspect::SceneInfo;
use sceneeval::render::{RenderSettings, Renderer, View};
use sceneeval::report::judge::{ItemFilter, JudgeItem, items};
use sceneeval::report::label_writer::LabelWriter;
use sceneeval::report::labels::Label;
use sceneeval::report::{RecordedScenes, Run, outlined_top_view};
use sceneeval::scene::Scene;
use serde::{Deserialize, Serialize};

use crate::server::{Api, ApiError, Asset, Listener, NoParams, Page, Raw};

/// The page (its head is the page server's, [`Page::html`]); its script and style sheet.
const PAGE: Page = Page {
    title: "sceneeval: judge the fidelity specs",
    body: include_str!("judge/body.html"),
};
const ASSETS: [Asset; 2] = Asset::page_files(include_bytes!("judge/app.js"), include_bytes!("judge/app.css"));

/// The seed of `--sample` unless `--seed` is given.
pub const DEFAULT_SEED: u64 = 0;

/// Arguments of `sceneeval judge`.
#[derive(Debug, clap::Args)]
#[command(
    after_help = "The page walks you through the run's fidelity specs (CNT, ATR, OOR, OAR of every scene's eval.json), \
scene by scene: the scene's description (from --annotations, the annotation file the run used), the spec in words, \
the top view with the objects the spec names outlined, and the object views the VLM saw (the run's views/ files, or \
rendered from the scene and --assets when the run did not keep them). Answer with the buttons or the keys y \
(satisfied), n (not satisfied), u (can't tell); b goes back, s skips. Every verdict is appended to LABELS at once and \
synced to disk; LABELS is locked while the page runs (a second judge on it is refused). Run it again with the same \
--annotator and --out to continue at the first spec you have not judged. The run's own verdicts are not shown \
unless --show-verdicts. --sample N --seed S judges the specs of N scenes drawn reproducibly (docs/judge.md). \
Ctrl-C stops."
)]
pub struct Args {
    /// Output folder of `sceneeval evaluate` with the text-fidelity metrics.
    #[arg(value_name = "RUN")]
    pub run: PathBuf,
    /// Your name, written with every verdict.
    #[arg(long, value_name = "NAME")]
    pub annotator: String,
    /// The label file (JSON Lines) verdicts are appended to; created when missing.
    #[arg(long, short = 'o', value_name = "LABELS")]
    pub out: PathBuf,
    /// Where the scenes' geometry is read from (the top views and the views rendered).
    #[command(flatten)]
    pub sources: crate::report::SceneSources,
    /// The annotation CSV (or JSON) the run used: each scene's description.
    #[arg(long, value_name = "FILE")]
    pub annotations: Option<PathBuf>,
    /// Judge the specs of N scenes drawn with --seed (all scenes when N is at least their
    /// number).
    #[arg(long, value_name = "N")]
    pub sample: Option<usize>,
    /// The seed of --sample (the same seed draws the same scenes).
    #[arg(long, value_name = "S", default_value_t = DEFAULT_SEED, requires = "sample")]
    pub seed: u64,
    /// Only these metrics' specs (comma-separated: cnt, atr, oor, oar).
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = parse_metric)]
    pub metrics: Vec<FidelityMetric>,
    /// The port on 127.0.0.1 (0: a random free port).
    #[arg(long, default_value_t = 0, value_name = "P")]
    pub port: u16,
    /// Do not open the page in the default browser; only print its URL.
    #[arg(long)]
    pub no_open: bool,
    /// Show the run's own verdict of each spec (for reviewing disagreements; not blind).
    #[arg(long)]
    pub show_verdicts: bool,
}

fn parse_metric(s: &str) -> Result<FidelityMetric, String> {
    s.parse()
}

/// The page's state: the items, the writer, the scenes and the views made so far.
struct Judge {
    run: Run,
    items: Vec<JudgeItem>,
    descriptions: BTreeMap<String, String>,
    writer: LabelWriter,
    show_verdicts: bool,
    scenes: RecordedScenes,
    /// The last scene read (scene name, the scene or why not), so that the items of a scene
    /// read it once.
    scene: Option<(String, Result<Scene, String>)>,
    /// The renderer, started on the first view that is not in the run folder.
    renderer: Option<Result<Renderer, String>>,
    /// The views of the last scene rendered.
    views: Option<(String, RenderedViews)>,
}

/// An item as the page gets it.
#[derive(Debug, Serialize)]
struct PageItem<'a> {
    scene: &'a str,
    metric: &'static str,
    index: usize,
    spec: &'a str,
    words: &'a str,
    objects: &'a [String],
    /// This annotator's verdict: absent when not judged yet.
    #[serde(skip_serializing_if = "Option::is_none")]
    verdict: Option<Option<bool>>,
    /// The run's verdict, only with `--show-verdicts`: `satisfied`, `not satisfied` or
    /// `undecided`.
    #[serde(skip_serializing_if = "Option::is_none")]
    run_verdict: Option<&'static str>,
}

/// The query of `GET /api/topview`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ItemQuery {
    item: String,
}

/// The query of `GET /api/view`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ViewQuery {
    item: String,
    object: String,
    kind: String,
}

/// The body of `POST /api/verdict`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Verdict {
    item: usize,
    satisfied: Option<bool>,
}

/// What `POST /api/verdict` answers.
#[derive(Debug, Serialize)]
struct Progress {
    judged: usize,
    total: usize,
}

impl Judge {
    fn judged(&self) -> usize {
        self.items
            .iter()
            .filter(|i| self.writer.judged().contains_key(&i.item))
            .count()
    }

    fn item(&self, k: &str) -> Result<&JudgeItem, ApiError> {
        k.parse::<usize>()
            .ok()
            .and_then(|k| self.items.get(k))
            .ok_or_else(|| {
                ApiError::not_found(format!(
                    "no item {k:?} (0 to {})",
                    self.items.len().saturating_sub(1)
                ))
            })
    }

    fn list(&self) -> serde_json::Value {
        let items: Vec<PageItem<'_>> = self
            .items
            .iter()
            .map(|i| PageItem {
                scene: &i.item.scene,
                metric: i.item.metric.name(),
                index: i.item.index,
                spec: &i.spec,
                words: &i.words,
                objects: &i.objects,
                verdict: self.writer.judged().get(&i.item).map(|l| l.satisfied),
                run_verdict: self.show_verdicts.then_some(match i.run_verdict {
                    Some(true) => "satisfied",
                    Some(false) => "not satisfied",
                    None => "undecided",
                }),
            })
            .collect();
        serde_json::json!({
            "run": self.run.name,
            "annotator": self.writer.annotator(),
            "out": self.writer.path(),
            "show_verdicts": self.show_verdicts,
            "descriptions": self.descriptions,
            "judged": self.judged(),
            "total": self.items.len(),
            "items": items,
        })
    }

    fn verdict(&mut self, v: Verdict) -> Result<Progress, ApiError> {
        let item = self
            .items
            .get(v.item)
            .ok_or_else(|| ApiError::not_found(format!("no item {}", v.item)))?;
        let label = Label {
            scene: item.item.scene.clone(),
            metric: item.item.metric,
            index: item.item.index,
            spec: item.spec.clone(),
            satisfied: v.satisfied,
            annotator: self.writer.annotator().to_owned(),
        };
        self.writer.append(label).map_err(|e| {
            ApiError::new(
                500,
                format!("the verdict was not saved: {:#}", ErrorChain::new(&e)),
            )
        })?;
        Ok(Progress {
            judged: self.judged(),
            total: self.items.len(),
        })
    }

    /// The scene `name`, read once for all its items.
    fn scene(&mut self, name: &str) -> Result<&Scene, ApiError> {
        if self.scene.as_ref().is_none_or(|(n, _)| n != name) {
            self.views = None;
            let read = match self.run.record(name) {
                None => Err(format!("the run has no scene {name}")),
                Some(record) => self
                    .scenes
                    .read(record)
                    .map(|(scene, remarks)| {
                        for r in remarks {
                            tracing::warn!(scene = name, "{r}");
                        }
                        scene
                    })
                    .map_err(|why| format!("{why} (give --scenes DIR and --assets PREFIX=DIR)")),
            };
            self.scene = Some((name.to_owned(), read));
        }
        match &self.scene {
            Some((_, Ok(scene))) => Ok(scene),
            Some((_, Err(why))) => Err(ApiError::new(422, format!("no scene {name} to draw: {why}"))),
            None => Err(ApiError::new(500, "no scene")),
        }
    }

    fn topview(&mut self, q: &ItemQuery) -> Result<Raw, ApiError> {
        let item = self.item(&q.item)?.clone();
        let scene = self.scene(&item.item.scene)?;
        let named: Vec<&str> = item.objects.iter().map(String::as_str).collect();
        let svg = outlined_top_view(&SceneInfo::new(scene), &named);
        Ok(Raw {
            content_type: "image/svg+xml",
            bytes: svg.into_bytes(),
        })
    }

    fn view(&mut self, q: &ViewQuery) -> Result<Raw, ApiError> {
        let item = self.item(&q.item)?.clone();
        if !item.objects.contains(&q.object) {
            return Err(ApiError::not_found(format!(
                "item {} names no object {:?}",
                q.item, q.object
            )));
        }
        let (kind, view) = match q.kind.as_str() {
            "front" => (ViewKind::Front, View::Front(q.object.clone())),
            "size" => (ViewKind::Size, View::Size(q.object.clone())),
            other => {
                return Err(ApiError::bad_request(format!(
                    "no view {other:?} (front or size)"
                )));
            }
        };
        if let Some(bytes) = self.kept_view(&item.item.scene, &view.file_name()) {
            return Ok(Raw {
                content_type: "image/png",
                bytes,
            });
        }
        let scene_name = item.item.scene.clone();
        self.scene(&scene_name)?;
        if self.views.as_ref().is_none_or(|(n, _)| *n != scene_name) {
            let renderer = self
                .renderer
                .get_or_insert_with(|| Renderer::new().map_err(|e| format!("{:#}", ErrorChain::new(&e))));
            let renderer = renderer
                .as_ref()
                .map_err(|e| ApiError::new(503, format!("cannot start the renderer: {e}")))?;
            let Some((_, Ok(scene))) = &self.scene else {
                return Err(ApiError::new(500, "no scene"));
            };
            let views = RenderedViews::new(
                renderer,
                scene,
                self.scenes.assets(),
                RenderSettings::square(RenderSettings::DEFAULT_SIZE),
                None,
            )
            .map_err(|e| ApiError::new(422, format!("{:#}", ErrorChain::new(&e))))?;
            self.views = Some((scene_name, views));
        }
        let Some((_, views)) = &self.views else {
            return Err(ApiError::new(500, "no views"));
        };
        let png = views
            .view(&q.object, kind)
            .map_err(|e| ApiError::new(422, format!("{:#}", ErrorChain::new(&e))))?;
        Ok(Raw {
            content_type: "image/png",
            bytes: png.bytes().to_vec(),
        })
    }

    /// The view `file` the run kept in `<scene>/views/`, when it is a regular file inside the
    /// run folder (a symbolic link out of it is not followed).
    fn kept_view(&self, scene: &str, file: &str) -> Option<Vec<u8>> {
        let path = self.run.scene_dir(scene)?.join("views").join(file);
        let root = self.run.dir.canonicalize().ok()?;
        let real = path.canonicalize().ok()?;
        if !real.starts_with(&root) {
            tracing::warn!(path = %path.display(), "a view that leads out of the run folder: not read");
            return None;
        }
        let mut bytes = Vec::new();
        sceneeval::files::open_regular(&real)
            .and_then(|mut f| std::io::Read::read_to_end(&mut f, &mut bytes))
            .ok()?;
        Some(bytes)
    }
}

/// The judge page's routes.
fn api() -> Api<Judge> {
    Api::new()
        .get("items", |j: &mut Judge, _: NoParams| Ok(j.list()))
        .get_raw("topview", |j: &mut Judge, q: ItemQuery| j.topview(&q))
        .get_raw("view", |j: &mut Judge, q: ViewQuery| j.view(&q))
        .post("verdict", Judge::verdict)
}

/// The descriptions of the run's scenes from their rows in `annotations`, found as the run
/// found them.
fn descriptions(run: &Run, annotations: Option<&Path>) -> anyhow::Result<BTreeMap<String, String>> {
    let Some(path) = annotations else {
        return Ok(BTreeMap::new());
    };
    let a = Annotations::read(path).with_context(|| format!("reading annotations {}", path.display()))?;
    Ok(run
        .records
        .iter()
        .filter_map(|r| {
            let row = r.scene.annotation_row(&a)?;
            Some((r.scene.as_str().to_owned(), row.description.clone()))
        })
        .collect())
}

/// Runs `sceneeval judge`: serves the page until Ctrl-C, then says how many verdicts were
/// written.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let run = crate::report::open_run(&args.run)?;
    let filter = ItemFilter {
        metrics: args.metrics.clone(),
        sample: args.sample.map(|n| (n, args.seed)),
    };
    let items = items(&run, &filter);
    if items.is_empty() {
        anyhow::bail!(
            "{} has no text-fidelity specs to judge{} (evaluate with annotations and a plan with cnt, atr, oor or oar)",
            args.run.display(),
            if args.metrics.is_empty() {
                ""
            } else {
                " of the metrics given"
            }
        );
    }
    let descriptions = descriptions(&run, args.annotations.as_deref())?;
    let writer = LabelWriter::open(&args.out, &args.annotator)?;
    let scenes = RecordedScenes::new(&run, &args.sources.options())?;
    let listener = Listener::bind(args.port)?;
    let url = listener.url();
    let state = Judge {
        run,
        items,
        descriptions,
        writer,
        show_verdicts: args.show_verdicts,
        scenes,
        scene: None,
        renderer: None,
        views: None,
    };
    crate::print_stdout(&format!(
        "Judging {} ({} specs, {} judged by {}; verdicts go to {}): {url}\nCtrl-C stops; every verdict is saved at once.\n",
        args.run.display(),
        state.items.len(),
        state.judged(),
        args.annotator,
        args.out.display()
    ))?;
    let state = listener.serve_page(&PAGE, &ASSETS, api(), state, args.no_open)?;
    crate::print_stdout(&format!(
        "stopped: {} of {} specs judged by {}; {} verdicts written to {} this session\n",
        state.judged(),
        state.items.len(),
        state.writer.annotator(),
        state.writer.appended(),
        state.writer.path().display()
    ))?;
    Ok(ExitCode::SUCCESS)
}
