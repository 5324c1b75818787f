//! `sceneeval render SCENE.json --assets PREFIX=DIR ... --out DIR [--views front,size,surroundings,top]
//! [--objects ID,...] [--render-size PX]`: render the reference's views of a scene as PNG files
//! (`front_<id>.png`, `size_<id>.png`, `surroundings_<id>.png`, `top.png`) and print each
//! file's path.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressStyle};
use sceneeval::render::{RenderSettings, Renderer, View, ViewKind, write_png};

/// Arguments of `sceneeval render`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The sceneState JSON file.
    pub scene: PathBuf,
    /// Asset folder for a model-id prefix, as `PREFIX=DIR` (layout chosen from the prefix) or
    /// `PREFIX=LAYOUT:DIR` with LAYOUT one of 3d-future, objathor, hssd, layoutvlm, idesign,
    /// scene-agent, plain. Repeat for several prefixes.
    #[arg(long = "assets", value_name = "PREFIX=[LAYOUT:]DIR")]
    pub assets: Vec<String>,
    /// Output folder (created if missing).
    #[arg(long, short = 'o', value_name = "DIR")]
    pub out: PathBuf,
    /// Which views to render (comma-separated): front, size, surroundings, top.
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "VIEW,...",
        default_value = "front,size,surroundings,top"
    )]
    pub views: Vec<ViewKind>,
    /// Render the per-object views of these objects only (comma-separated ids as `sceneeval
    /// inspect` prints them). Default: every object.
    #[arg(long, value_delimiter = ',', value_name = "ID,...")]
    pub objects: Option<Vec<String>>,
    /// Image width and height in pixels (the same option as `evaluate`'s and `settle`'s;
    /// `--size` is its old spelling).
    #[arg(long, alias = "size", value_name = "PX", default_value_t = RenderSettings::DEFAULT_SIZE)]
    pub render_size: u32,
    /// Refuse a scene file with keys the sceneState format does not have (a misspelt key is
    /// read as absent) instead of warning about each.
    #[arg(long)]
    pub strict: bool,
}

/// Runs the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    if args.render_size == 0 {
        bail!("--render-size must be at least 1");
    }
    let (library, scene) = crate::inspect::load_scene(&args.scene, &args.assets, args.strict)?;
    let ids: Vec<String> = match args.objects {
        Some(ids) => {
            let unknown: Vec<&str> = ids
                .iter()
                .filter(|id| scene.object(id).is_none())
                .map(String::as_str)
                .collect();
            if !unknown.is_empty() {
                bail!(
                    "the scene has no object {} (its objects: {})",
                    unknown.join(", "),
                    scene
                        .objects()
                        .iter()
                        .map(|o| o.id().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                );
            }
            ids
        }
        None => scene.objects().iter().map(|o| o.id().to_string()).collect(),
    };
    let views = View::standard(&args.views, ids.iter().map(String::as_str));
    if views.is_empty() {
        bail!("nothing to render: no objects and no top view");
    }
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;

    let renderer = Renderer::new().context("cannot start the renderer")?;
    tracing::info!(adapter = %renderer.gpu().adapter().name, "rendering");
    let prepared = renderer
        .prepare(&scene, &library)
        .with_context(|| format!("cannot prepare {} for rendering", args.scene.display()))?;
    let settings = RenderSettings::square(args.render_size);

    let progress = ProgressBar::new(views.len() as u64);
    if let Ok(style) = ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} images {msg}") {
        progress.set_style(style.progress_chars("=> "));
    }
    for (view, image) in prepared.render_all(&views, &settings) {
        let name = view.file_name();
        let image = image.with_context(|| format!("rendering {name}"))?;
        let path = args.out.join(&name);
        write_png(&image, &path)?;
        progress.suspend(|| crate::print_stdout(&format!("{}\n", path.display())))?;
        progress.inc(1);
    }
    progress.finish_and_clear();
    let n = views.len();
    eprintln!(
        "{n} image{} written to {}",
        if n == 1 { "" } else { "s" },
        args.out.display()
    );
    Ok(ExitCode::SUCCESS)
}
