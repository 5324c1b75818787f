//! `sceneeval report RUN`: the static report of a finished run (`RUN/report/index.html` and a
//! page per scene), made from what the run wrote, without evaluating anything.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use sceneeval::annotation::Annotations;
use sceneeval::report::{DEFAULT_DIR, NoTopView, ReportOptions, Run, Written, write_report};

/// Arguments of `sceneeval report`.
#[derive(Debug, clap::Args)]
#[command(
    after_help = "The report opens from disk in any browser (no server, no network) and prints. Each \
scene's top view is drawn from --scenes DIR/<scene>.json and the asset folders of --assets. The report reads only \
inside the run folder and the folders given: without --scenes it draws a scene only when the scene file its record \
names lies inside the run folder, and without --assets it uses the asset folders the records name only inside the \
run folder or --scenes (a run folder from elsewhere could name any file). A record that cannot be read is listed \
and the others are reported. The folder's layout is described in docs/formats.md."
)]
pub struct Args {
    /// Output folder of `sceneeval evaluate` (holding `<scene>/eval.json`).
    #[arg(value_name = "RUN")]
    pub run: PathBuf,
    /// Folder to write the report into (default: RUN/report). Outside RUN, the images the run
    /// wrote are copied into it.
    #[arg(long, short = 'o', value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Where the scenes' geometry is read from.
    #[command(flatten)]
    pub sources: SceneSources,
    /// The annotation CSV (or JSON) the run used: each scene's difficulty (default: the run's
    /// summary_scenes.csv).
    #[arg(long, value_name = "FILE")]
    pub annotations: Option<PathBuf>,
    /// The run's name in the report (default: the folder's name).
    #[arg(long, value_name = "NAME")]
    pub name: Option<String>,
    /// Label files of people's verdicts on the run's specs (JSON Lines, or CSV when the name
    /// ends in .csv; docs/judge.md): the overview page gets the agreement table of `sceneeval
    /// agreement --reference LABELS RUN` and each scene page marks the specs where the run and
    /// the people's majority disagree.
    #[arg(long, value_name = "LABELS", num_args = 1..)]
    pub labels: Vec<PathBuf>,
}

/// Where a command that draws a run's scenes (`report`, `judge`) reads their files: the
/// options `--assets` and `--scenes`, as `sceneeval::report::ReportOptions` takes them.
#[derive(Debug, Clone, clap::Args)]
pub struct SceneSources {
    /// Asset folder for a model-id prefix, as for `sceneeval evaluate` (`PREFIX=DIR` or
    /// `PREFIX=LAYOUT:DIR`); default: the folders the run's records name, when they lie inside
    /// RUN or --scenes.
    #[arg(long = "assets", value_name = "PREFIX=[LAYOUT:]DIR")]
    pub assets: Vec<String>,
    /// Folder holding the scene files (`<scene>.json`), as given to `sceneeval evaluate`;
    /// default: the file each record names, only when it lies inside RUN.
    #[arg(long, value_name = "DIR")]
    pub scenes: Option<PathBuf>,
}

impl SceneSources {
    /// The options of the report crate.
    pub fn options(&self) -> ReportOptions {
        ReportOptions {
            assets: self.assets.clone(),
            scenes: self.scenes.clone(),
        }
    }
}

/// Runs the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let mut run = open_run(&args.run)?;
    if let Some(name) = &args.name {
        run = run.with_name(name.as_str());
    }
    if let Some(path) = &args.annotations {
        let a = Annotations::read(path).with_context(|| format!("reading annotations {}", path.display()))?;
        run = run.with_annotations(&a);
    }
    if !args.labels.is_empty() {
        run = with_labels(run, &args.labels)?;
    }
    let out = args.out.clone().unwrap_or_else(|| args.run.join(DEFAULT_DIR));
    let written = write_report(&run, &out, &args.sources.options())?;
    tell(&run, &written);
    Ok(ExitCode::SUCCESS)
}

/// Writes the report of the run just evaluated into `OUT/report` (`sceneeval evaluate
/// --report`), with the run's own scene folder, asset folders and annotations.
pub fn after_evaluate(
    out: &Path,
    scenes: &Path,
    assets: &[String],
    annotations: Option<&Path>,
) -> anyhow::Result<()> {
    let mut run = open_run(out)?;
    if let Some(path) = annotations {
        run = run.with_annotations(&Annotations::read(path)?);
    }
    let options = ReportOptions {
        assets: assets.to_vec(),
        scenes: Some(scenes.to_owned()),
    };
    let written = write_report(&run, &out.join(DEFAULT_DIR), &options)?;
    tell(&run, &written);
    Ok(())
}

/// `run` with its agreement with the label files `paths` (the defaults of `sceneeval
/// agreement`: 1000 resamples, its seed), its notes said on standard error.
fn with_labels(run: Run, paths: &[PathBuf]) -> anyhow::Result<Run> {
    use sceneeval::report::agreement::AgreementOptions;
    use sceneeval::report::labels::LabelFile;
    let files = paths
        .iter()
        .map(|p| LabelFile::read(p))
        .collect::<Result<Vec<_>, _>>()?;
    let run = run.with_labels(&files, &AgreementOptions::default())?;
    for note in run.labels().map(|a| a.notes.as_slice()).unwrap_or_default() {
        eprintln!("note: {note}");
    }
    Ok(run)
}

/// Reads a run folder (`sceneeval report`, `sceneeval compare`), saying which records could
/// not be read.
pub fn open_run(dir: &Path) -> anyhow::Result<Run> {
    let run = Run::open(dir)?;
    warn_unreadable(&run);
    Ok(run)
}

/// Warns about each record of `run` that could not be read.
pub fn warn_unreadable(run: &Run) {
    for u in &run.unreadable {
        eprintln!(
            "warning: {} could not be read ({}); scene {} is left out",
            u.path.display(),
            u.reason,
            u.scene
        );
    }
}

/// Says where the report is and which scenes have no top view, and what to pass.
fn tell(run: &Run, written: &Written) {
    eprintln!(
        "report: {} ({} scene pages{})",
        written.index.display(),
        written.pages,
        if run.unreadable.is_empty() {
            String::new()
        } else {
            format!("; {} unreadable records listed", run.unreadable.len())
        }
    );
    for (scene, why) in written.without_top_view.iter().take(5) {
        eprintln!("warning: no top view of {scene}: {why}");
    }
    if written.without_top_view.len() > 5 {
        eprintln!(
            "warning: and {} more scenes without a top view",
            written.without_top_view.len() - 5
        );
    }
    if written
        .without_top_view
        .iter()
        .any(|(_, why)| !matches!(why, NoTopView::NotAFileName))
    {
        eprintln!(
            "hint: give the folder of scene files sceneeval evaluate read (--scenes DIR) and its asset folders \
             (--assets PREFIX=DIR) to draw the top views"
        );
    }
}
