//! The static report of a run: `index.html` and one page per scene, opened from disk with no
//! server and no network.

use std::path::{Path, PathBuf};

use sceneeval_files::ErrorChain;
use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state};
use sceneeval_results::{FileDigest, SceneRecord};
use sceneeval_scene::Scene;
use sceneeval_scene::inspect::SceneInfo;

use crate::ReportError;
use crate::assets::recorded_assets;
use crate::escape;
use crate::html::overview::overview;
use crate::html::relative_href;
use crate::html::scene::{Image, ScenePage, scene_page};
use crate::html::topview::Overlay;
use crate::run::{Run, summary_columns};

/// The report's folder inside a run folder when none is given (`RUN/report`).
pub const DEFAULT_DIR: &str = "report";
/// The overview page.
pub const INDEX: &str = "index.html";
/// The folder of the scene pages (`scenes/<scene>.html`).
pub const SCENES_DIR: &str = "scenes";
/// The folder images are copied into when the report is not inside its run folder.
pub const FILES_DIR: &str = "files";

/// Where the report finds a scene's geometry for its top view.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ReportOptions {
    /// Asset folders as `--assets` takes them (`PREFIX=[LAYOUT:]DIR`); empty: the folders the
    /// records name ([`recorded_assets`]).
    pub assets: Vec<String>,
    /// The folder holding the scene files (`<scene>.json`); `None`: the file each record names.
    pub scenes: Option<PathBuf>,
}

/// What [`write_report`] wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Written {
    /// The overview page.
    pub index: PathBuf,
    /// Scene pages written.
    pub pages: usize,
    /// Scenes whose top view could not be drawn, and why.
    pub without_top_view: Vec<(String, String)>,
}

/// Writes the report of `run` into `out` (created if needed): `index.html` and
/// `scenes/<scene>.html`. Images the run wrote (`<scene>/views/*.png`,
/// `<scene>/diagnostics/*.png`) are linked where they are when `out` lies inside the run
/// folder (the default, `RUN/report`), and copied under `out/files/` otherwise, so the folder
/// works on its own. Each scene's top view is drawn from the scene file its record names (or
/// `options.scenes`), read with the default read options through `options.assets` or the
/// asset folders the records name; a scene that cannot be read gets a page saying why. Every
/// file is written atomically.
///
/// # Errors
/// [`ReportError::File`] when a folder cannot be created or an image read,
/// [`ReportError::File`] when a file cannot be written, [`ReportError::Assets`] for a bad
/// `--assets` specification.
pub fn write_report(run: &Run, out: &Path, options: &ReportOptions) -> Result<Written, ReportError> {
    let pages_dir = out.join(SCENES_DIR);
    std::fs::create_dir_all(&pages_dir).map_err(|e| ReportError::file(&pages_dir, e))?;
    let assets = if options.assets.is_empty() {
        recorded_assets(&run.records)
    } else {
        AssetLibrary::from_specs(&options.assets).map_err(ReportError::Assets)?
    };
    let inside = match (out.canonicalize(), run.dir.canonicalize()) {
        (Ok(o), Ok(r)) => o.starts_with(r),
        _ => false,
    };
    let metrics = run.metrics();
    let columns: Vec<(&'static str, sceneeval_results::Metric)> = summary_columns()
        .into_iter()
        .filter(|(_, m)| metrics.contains(m))
        .collect();
    let mut pages = std::collections::BTreeMap::new();
    let mut without_top_view = Vec::new();
    for record in &run.records {
        let name = record.scene.as_str();
        let file = format!("{}.html", escape::file_name(name));
        let (loaded, remarks) = load(record, options, &assets);
        if let Err(why) = &loaded {
            without_top_view.push((name.to_owned(), why.clone()));
        }
        let scene_dir = run.dir.join(name);
        let images = |kind: &str| -> Result<Vec<Image>, ReportError> {
            let mut list = Vec::new();
            for path in pngs(&scene_dir.join(kind))? {
                let file_name = path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default();
                let href = if inside {
                    relative_href(&pages_dir, &path)
                } else {
                    None
                };
                let href = match href {
                    Some(h) => h,
                    None => {
                        let bytes = std::fs::read(&path).map_err(|e| ReportError::file(&path, e))?;
                        let folder = escape::file_name(name);
                        write_atomic(
                            &out.join(FILES_DIR).join(&folder).join(kind).join(&file_name),
                            &bytes,
                        )?;
                        format!(
                            "../{FILES_DIR}/{folder}/{kind}/{}",
                            escape::url_segment(&file_name)
                        )
                    }
                };
                list.push(Image {
                    name: file_name,
                    href,
                });
            }
            Ok(list)
        };
        let views = images("views")?;
        let diagnostics = images("diagnostics")?;
        let overlay = match (
            record.report().and_then(|r| r.navigability.as_ref()),
            diagnostics.iter().find(|i| i.name == "navigability.png"),
        ) {
            (Some(nav), Some(img)) => Some(Overlay {
                href: img.href.clone(),
                grid: nav.grid,
            }),
            _ => None,
        };
        let html = scene_page(&ScenePage {
            run: &run.name,
            record,
            difficulty: run.difficulty(name),
            scene: loaded.as_ref().map(SceneInfo::new).map_err(Clone::clone),
            views,
            diagnostics,
            overlay,
            remarks,
            columns: &columns,
        });
        write_atomic(&pages_dir.join(&file), html.as_bytes())?;
        pages.insert(
            name.to_owned(),
            format!("{SCENES_DIR}/{}", escape::url_segment(&file)),
        );
    }
    let index = out.join(INDEX);
    write_atomic(&index, overview(run, &columns, &pages).as_bytes())?;
    Ok(Written {
        index,
        pages: pages.len(),
        without_top_view,
    })
}

/// The scene of `record` read from its file, or why it cannot be; and remarks on it.
fn load(
    record: &SceneRecord,
    options: &ReportOptions,
    assets: &AssetLibrary,
) -> (Result<Scene, String>, Vec<String>) {
    let recorded = record.fingerprint.as_ref().map(|f| &f.scene);
    let path = match (&options.scenes, recorded) {
        (Some(dir), _) => dir.join(format!("{}.json", record.scene)),
        (None, Some(f)) => PathBuf::from(&f.path),
        (None, None) => {
            return (
                Err("the record names no scene file (it has no fingerprint); pass --scenes DIR".to_owned()),
                Vec::new(),
            );
        }
    };
    let mut remarks = Vec::new();
    match read_scene_state(&path, assets, &ReadOptions::default()) {
        Ok(scene) => {
            if let Some(old) = recorded.and_then(|f| f.blake3.as_deref())
                && FileDigest::of(&path).blake3.as_deref() != Some(old)
            {
                remarks.push(format!(
                    "The scene file {} changed since the run evaluated it: the top view shows the file as it is now.",
                    path.display()
                ));
            }
            (Ok(scene), remarks)
        }
        Err(e) => (
            Err(format!(
                "reading {} failed: {:#}. The record names the scene file and its asset files as the run read them \
                 (relative paths are relative to the folder sceneeval evaluate ran in): write the report from that \
                 folder, or pass --scenes DIR and --assets PREFIX=DIR.",
                path.display(),
                ErrorChain::new(&e)
            )),
            remarks,
        ),
    }
}

/// Writes `bytes` to `path` atomically, the error naming the file.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    sceneeval_files::write_atomic(path, bytes).map_err(|e| ReportError::file(path, e))
}

/// The PNG files of `dir` in name order; none when it does not exist.
fn pngs(dir: &Path) -> Result<Vec<PathBuf>, ReportError> {
    if !dir.is_dir() {
        return Ok(Vec::new());
    }
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| ReportError::file(dir, e))? {
        let path = entry.map_err(|e| ReportError::file(dir, e))?.path();
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) && path.is_file() {
            out.push(path);
        }
    }
    out.sort();
    Ok(out)
}
