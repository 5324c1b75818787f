//! `sceneeval convert holodeck|layoutvlm|idesign|scene-agent INPUT --out DIR [--id-map JSON]
//! [--assets PREFIX=DIR]...`: turn a generator's batch folder into sceneState files (and the
//! assets that travel with them) that `sceneeval evaluate` reads, then print what was
//! converted, what was skipped and why, and the command that evaluates the result.
//!
//! SIGINT (Ctrl-C) or SIGTERM stops the conversion at its next file: its temporary folder is
//! removed and the process exits with status 128 + the signal's number. A second signal ends
//! the process at once; the folder it leaves is removed by the next conversion into the same
//! output.

use std::io::{self, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};

use anyhow::Context;
use sceneeval::convert::{ConvertError, ConvertOptions, Format, IdMap, Report, convert};
use sceneeval::io::assets::AssetSpec;

/// Arguments of `sceneeval convert`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The generator: `holodeck`, `layoutvlm`, `idesign` or `scene-agent` (also `scenesmith`).
    #[arg(value_parser = clap::builder::ValueParser::new(parse_format))]
    pub format: Format,
    /// The generator's batch folder: Holodeck `<name>/<name>.json` folders; LayoutVLM, IDesign
    /// and SceneAgent `scene_NNN` folders.
    pub input: PathBuf,
    /// The folder to write `scene_<ID>.json` (and, for IDesign and SceneAgent, `scene_<ID>/`)
    /// into. It must not exist or be empty; it appears only once every scene is converted.
    #[arg(long, short = 'o', value_name = "DIR")]
    pub out: PathBuf,
    /// Scene keys (the NNN of scene_NNN; a Holodeck scene's position in name order) to
    /// SceneEval-500 ids, as a JSON object (`'{"0": 106, "1": 56}'`) or a file holding one.
    /// Scenes it does not list are skipped.
    #[arg(long = "id-map", value_name = "JSON|FILE")]
    pub id_map: Option<String>,
    /// Asset folders, as for `sceneeval evaluate`: Holodeck needs `objaverse=DIR` (the
    /// Objathor folder) and LayoutVLM `layoutvlm-objaverse=DIR`, because their positions are
    /// box centres and only the meshes say where those are. Repeatable.
    #[arg(long = "assets", value_name = "PREFIX=[LAYOUT:]DIR")]
    pub assets: Vec<String>,
    /// Refuse converted scenes with keys the sceneState format does not have (a SceneAgent
    /// state file is copied with its keys) instead of warning about each.
    #[arg(long)]
    pub strict: bool,
}

fn parse_format(s: &str) -> Result<Format, String> {
    s.parse()
}

/// Runs the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let id_map = args
        .id_map
        .as_deref()
        .map(|text| {
            let text = if text.trim_start().starts_with('{') {
                text.to_owned()
            } else {
                std::fs::read_to_string(text).with_context(|| format!("--id-map: reading {text}"))?
            };
            IdMap::parse(&text).map_err(anyhow::Error::from)
        })
        .transpose()?;
    let assets = args
        .assets
        .iter()
        .map(|s| AssetSpec::parse(s))
        .collect::<Result<Vec<_>, _>>()
        .context("invalid --assets")?;
    let interrupt = Arc::new(AtomicBool::new(false));
    let signal = Arc::new(AtomicU8::new(0));
    interrupt_on_signals(Arc::clone(&interrupt), Arc::clone(&signal))?;
    let mut options = ConvertOptions::default()
        .with_assets(assets)
        .with_strict(args.strict)
        .with_interrupt(interrupt);
    options.id_map = id_map;
    let report = match convert(args.format, &args.input, &args.out, &options) {
        Ok(report) => report,
        Err(ConvertError::Interrupted) => {
            eprintln!(
                "interrupted: nothing was written to {} (the temporary folder is removed)",
                args.out.display()
            );
            return Ok(ExitCode::from(128 + signal.load(Ordering::SeqCst)));
        }
        Err(e) => {
            return Err(anyhow::Error::from(e).context(format!(
                "cannot convert {} ({})",
                args.input.display(),
                args.format
            )));
        }
    };
    let stdout = io::stdout();
    let mut out = stdout.lock();
    print_report(&mut out, &report, &args.assets)?;
    Ok(ExitCode::SUCCESS)
}

fn print_report(out: &mut impl Write, report: &Report, assets: &[String]) -> io::Result<()> {
    writeln!(
        out,
        "converted {} {} scene{} from {} into {}",
        report.scenes.len(),
        report.format,
        if report.scenes.len() == 1 { "" } else { "s" },
        report.input.display(),
        report.out.display()
    )?;
    for s in &report.scenes {
        writeln!(
            out,
            "  {} -> {}: {} object{}, {} room{}{}",
            s.source.file_name().map_or_else(
                || s.source.display().to_string(),
                |n| n.to_string_lossy().into_owned()
            ),
            s.files
                .first()
                .map_or_else(String::new, |f| f.display().to_string()),
            s.objects,
            if s.objects == 1 { "" } else { "s" },
            s.rooms,
            if s.rooms == 1 { "" } else { "s" },
            if s.files.len() > 1 {
                format!(", {} asset files", s.files.len() - 1)
            } else {
                String::new()
            }
        )?;
        for o in &s.skipped_objects {
            writeln!(
                out,
                "    skipped object {:?} ({} {}): {}",
                o.name,
                o.file.display(),
                o.pointer,
                o.reason
            )?;
        }
    }
    if !report.skipped.is_empty() {
        writeln!(
            out,
            "skipped {} scene{}:",
            report.skipped.len(),
            if report.skipped.len() == 1 { "" } else { "s" }
        )?;
        for s in &report.skipped {
            writeln!(out, "  {} (key {}): {}", s.source.display(), s.key, s.reason)?;
        }
    }
    if !report.unused_id_map_keys.is_empty() {
        let keys: Vec<String> = report.unused_id_map_keys.iter().map(u64::to_string).collect();
        writeln!(
            out,
            "--id-map keys with no scene in the input: {}",
            keys.join(", ")
        )?;
    }
    // The command that evaluates the result: the same asset folders, and the output itself
    // for the formats whose assets it holds.
    let mut flags: Vec<String> = assets.iter().map(|a| format!("--assets {a}")).collect();
    if let Some(prefix) = report.format.assets_in_output() {
        flags.push(format!("--assets {prefix}={}", report.out.display()));
    }
    writeln!(
        out,
        "evaluate with: sceneeval evaluate {} {} --out <RESULTS>",
        report.out.display(),
        flags.join(" ")
    )
}

/// What to do about a conversion error that an option fixes, if it is one.
pub fn hint(err: &(dyn std::error::Error + 'static)) -> Option<String> {
    match err.downcast_ref::<ConvertError>()? {
        ConvertError::AssetsNeeded { prefix, .. } => Some(format!(
            "pass --assets {prefix}=DIR with the folder the evaluation will read the assets from"
        )),
        ConvertError::IdMap { .. } => Some("check the JSON given to --id-map".to_owned()),
        _ => None,
    }
}

/// On the first SIGINT or SIGTERM sets `interrupt` (the conversion stops at its next file and
/// removes its temporary folder) and records the signal's number in `signal`; on a second one
/// ends the process at once. A thread waits for the signals (tokio's, on a runtime of its own).
fn interrupt_on_signals(interrupt: Arc<AtomicBool>, signal: Arc<AtomicU8>) -> anyhow::Result<()> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .context("cannot start the signal handler")?;
    let on_signal = move |number: u8| {
        if interrupt.swap(true, Ordering::SeqCst) {
            eprintln!(
                "interrupted again: stopping now (the next conversion into this folder removes what is left)"
            );
            std::process::exit(128 + i32::from(number));
        }
        signal.store(number, Ordering::SeqCst);
    };
    #[cfg(unix)]
    {
        use tokio::signal::unix::{SignalKind, signal as listen};
        // Installed before the conversion starts, so that no signal is missed.
        let mut streams = runtime
            .block_on(async {
                Ok::<_, io::Error>([
                    (2, listen(SignalKind::interrupt())?),
                    (15, listen(SignalKind::terminate())?),
                ])
            })
            .context("cannot install the signal handlers")?;
        std::thread::Builder::new()
            .name("signals".into())
            .spawn(move || {
                runtime.block_on(async move {
                    let [(int, int_stream), (term, term_stream)] = &mut streams;
                    loop {
                        let number = std::future::poll_fn(|cx| {
                            if int_stream.poll_recv(cx).is_ready() {
                                return std::task::Poll::Ready(*int);
                            }
                            if term_stream.poll_recv(cx).is_ready() {
                                return std::task::Poll::Ready(*term);
                            }
                            std::task::Poll::Pending
                        })
                        .await;
                        on_signal(number);
                    }
                });
            })
            .context("cannot start the signal handler")?;
    }
    #[cfg(not(unix))]
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            while runtime.block_on(tokio::signal::ctrl_c()).is_ok() {
                on_signal(2);
            }
        })
        .context("cannot start the signal handler")?;
    Ok(())
}
