//! `sceneeval summarize OUT_DIR...`: the summary tables of one or more output folders, e.g.
//! the shards of a cluster run (`sceneeval evaluate --shard K/N`), merged as if one machine
//! had evaluated every scene.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};
use sceneeval::annotation::Annotations;
use sceneeval::{RECORD_FILE, SceneRecord, Summary};

/// Arguments of `sceneeval summarize`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Output folders of `sceneeval evaluate` (each holding `<scene>/eval.json`).
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// The annotation CSV (or JSON) the runs used: adds the rows per difficulty.
    #[arg(long, value_name = "FILE")]
    pub annotations: Option<PathBuf>,
    /// Write `summary.csv`, `summary.md` and `summary_scenes.csv` (one row per scene) into
    /// this folder (else only print the table).
    #[arg(long, short = 'o', value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// Runs the subcommand. A scene found in two folders is an error (shards do not overlap);
/// records of different plans are an error too (their numbers are not comparable).
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let mut records: BTreeMap<String, (PathBuf, SceneRecord)> = BTreeMap::new();
    for dir in &args.dirs {
        let entries = std::fs::read_dir(dir).with_context(|| format!("reading {}", dir.display()))?;
        for entry in entries {
            let path = entry?.path().join(RECORD_FILE);
            if !path.is_file() {
                continue;
            }
            let record = SceneRecord::read(&path)?;
            if let Some((first, _)) = records.get(record.scene.as_str()) {
                bail!(
                    "scene {} is in both {} and {}; shards must not overlap",
                    record.scene,
                    first.display(),
                    path.display()
                );
            }
            records.insert(record.scene.to_string(), (path, record));
        }
    }
    if records.is_empty() {
        bail!("no <scene>/{RECORD_FILE} in the folders given");
    }
    let mut plans: BTreeMap<&str, &PathBuf> = BTreeMap::new();
    for (path, r) in records.values() {
        if let Some(f) = &r.fingerprint {
            plans.entry(f.plan.as_str()).or_insert(path);
        }
    }
    if plans.len() > 1 {
        let which: Vec<String> = plans.values().map(|p| p.display().to_string()).collect();
        bail!(
            "the records come from {} different plans (e.g. {})",
            plans.len(),
            which.join(", ")
        );
    }
    let annotations = args
        .annotations
        .as_deref()
        .map(|p| Annotations::read(p).with_context(|| format!("reading annotations {}", p.display())))
        .transpose()?;
    let list: Vec<&SceneRecord> = records.values().map(|(_, r)| r).collect();
    let summary = Summary::from_records(list, annotations.as_ref());
    let markdown = summary.to_markdown();
    if let Some(out) = &args.out {
        std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
        summary.write_to(out)?;
    }
    crate::print_stdout(&markdown)?;
    eprintln!("{} scenes from {} folder(s)", records.len(), args.dirs.len());
    Ok(ExitCode::SUCCESS)
}
