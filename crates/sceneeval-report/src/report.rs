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
use crate::html::scene::{Image, SceneLink, ScenePage, scene_page};
use crate::html::topview::Overlay;
use crate::run::{Run, scene_of, summary_columns};
use crate::within::{Inside, inside, is_file_name};

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
    /// records name ([`recorded_assets`]), those inside the run folder or `scenes` only.
    pub assets: Vec<String>,
    /// The folder holding the scene files (`<scene>.json`); `None`: the file each record
    /// names, only when it lies inside the run folder.
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
    pub without_top_view: Vec<(String, NoTopView)>,
}

/// Why a scene page has no top view.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum NoTopView {
    /// No scene folder was given and the record names no scene file (it has no fingerprint).
    NotRecorded,
    /// No scene folder was given and the scene file the record names lies outside the run
    /// folder: it is not read (a record could name any file).
    OutsideRun,
    /// The scene's name is not a file name (`..`, a separator): no path is made of it.
    NotAFileName,
    /// The scene file could not be read.
    Unreadable {
        /// The file.
        path: PathBuf,
        /// Why, with the causes.
        reason: String,
    },
}

impl std::fmt::Display for NoTopView {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NoTopView::NotRecorded => f.write_str(
                "the record names no scene file (it has no fingerprint) and the report was given no scene folder",
            ),
            NoTopView::OutsideRun => f.write_str(
                "the scene file the record names lies outside the run folder and the report was given no scene \
                 folder; the report reads scene files only inside the run folder or the scene folder it is given",
            ),
            NoTopView::NotAFileName => f.write_str("the scene's name is not a file name"),
            NoTopView::Unreadable { path, reason } => write!(f, "reading {} failed: {reason}", path.display()),
        }
    }
}

/// Writes the report of `run` into `out` (created if needed): `index.html` and
/// `scenes/<scene>.html`. Images the run wrote (`<scene>/views/*.png`,
/// `<scene>/diagnostics/*.png`) are linked where they are when `out` lies inside the run
/// folder (the default, `RUN/report`), and copied under `out/files/` otherwise, so the folder
/// works on its own. Each scene's top view is drawn from `options.scenes/<scene>.json`, or
/// without it from the scene file its record names when that lies inside the run folder, read
/// with the default read options through `options.assets` or the asset folders the records
/// name inside the run folder or `options.scenes`; a scene that cannot be read gets a page
/// saying why. Every file is written atomically.
///
/// The report reads only inside the run folder, `options.scenes` and `options.assets`: a path
/// a record names elsewhere is not read (nor quoted), and an image that is a symbolic link out
/// of the run folder is neither linked nor copied (its page says so).
///
/// # Errors
/// [`ReportError::File`] when a folder cannot be created or an image read,
/// [`ReportError::File`] when a file cannot be written, [`ReportError::Assets`] for a bad
/// asset folder specification.
pub fn write_report(run: &Run, out: &Path, options: &ReportOptions) -> Result<Written, ReportError> {
    let pages_dir = out.join(SCENES_DIR);
    std::fs::create_dir_all(&pages_dir).map_err(|e| ReportError::file(&pages_dir, e))?;
    let root = run
        .dir
        .canonicalize()
        .map_err(|e| ReportError::file(&run.dir, e))?;
    let assets = asset_library(run, &root, options)?;
    let inside_run = out.canonicalize().is_ok_and(|o| o.starts_with(&root));
    let metrics = run.metrics();
    let columns: Vec<(&'static str, sceneeval_results::Metric)> = summary_columns()
        .into_iter()
        .filter(|(_, m)| metrics.contains(m))
        .collect();
    // Every scene's page file first: each page links its neighbours in the overview's order.
    let files: Vec<String> = run
        .records
        .iter()
        .map(|r| format!("{}.html", escape::file_name(scene_of(r))))
        .collect();
    let link = |k: usize| SceneLink {
        scene: scene_of(&run.records[k]).to_owned(),
        href: escape::url_segment(&files[k]),
    };
    let mut pages = std::collections::BTreeMap::new();
    let mut without_top_view = Vec::new();
    for (k, record) in run.records.iter().enumerate() {
        let name = scene_of(record);
        let file = &files[k];
        let (loaded, mut remarks) = load(record, &root, options, &assets);
        let images = Images {
            root: &root,
            scene_dir: run.scene_dir(name),
            scene: name,
            out,
            pages_dir: &pages_dir,
            inside_run,
        };
        let views = images.list("views", &mut remarks)?;
        let diagnostics = images.list("diagnostics", &mut remarks)?;
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
            scene: loaded.as_ref().map(SceneInfo::new).map_err(ToString::to_string),
            views,
            diagnostics,
            overlay,
            remarks,
            columns: &columns,
            description: run.description(name),
            previous: k.checked_sub(1).map(link),
            next: (k + 1 < files.len()).then(|| link(k + 1)),
            labels: run.labels(),
        });
        if let Err(why) = loaded {
            without_top_view.push((name.to_owned(), why));
        }
        write_atomic(&pages_dir.join(file), html.as_bytes())?;
        pages.insert(
            name.to_owned(),
            format!("{SCENES_DIR}/{}", escape::url_segment(file)),
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

/// The asset folders of `options` (`--assets`), or without any the folders the run's
/// records name inside `root` (the run folder, canonical) or the scene folder.
fn asset_library(run: &Run, root: &Path, options: &ReportOptions) -> Result<AssetLibrary, ReportError> {
    Ok(if options.assets.is_empty() {
        let scenes = options.scenes.as_deref().and_then(|d| d.canonicalize().ok());
        let within: Vec<&Path> = std::iter::once(root).chain(scenes.as_deref()).collect();
        recorded_assets(&run.records, &within)
    } else {
        AssetLibrary::from_specs(&options.assets).map_err(ReportError::Assets)?
    })
}

/// The scenes of a run read as the report reads them for its top views, one at a time (the
/// judge page, `sceneeval judge`): the scene file from `options.scenes`, or the file a record
/// names only when it lies inside the run folder, with the assets of `options` (or the
/// folders the records name inside the run or scene folder).
#[derive(Debug)]
pub struct RecordedScenes {
    root: PathBuf,
    options: ReportOptions,
    assets: AssetLibrary,
}

impl RecordedScenes {
    /// The scenes of `run` as `options` finds them.
    ///
    /// # Errors
    /// [`ReportError::File`] when the run folder cannot be found, [`ReportError::Assets`] for
    /// a bad asset folder specification.
    pub fn new(run: &Run, options: &ReportOptions) -> Result<RecordedScenes, ReportError> {
        let root = run
            .dir
            .canonicalize()
            .map_err(|e| ReportError::file(&run.dir, e))?;
        let assets = asset_library(run, &root, options)?;
        Ok(RecordedScenes {
            root,
            options: options.clone(),
            assets,
        })
    }

    /// The asset library the scenes are read with.
    #[must_use]
    pub fn assets(&self) -> &AssetLibrary {
        &self.assets
    }

    /// The scene of `record`, and remarks on it (the file changed since the run), or why it
    /// cannot be read.
    ///
    /// # Errors
    /// The [`NoTopView`] reason.
    pub fn read(&self, record: &SceneRecord) -> Result<(Scene, Vec<String>), NoTopView> {
        let (scene, remarks) = load(record, &self.root, &self.options, &self.assets);
        scene.map(|s| (s, remarks))
    }
}

/// A scene's images in the run folder, linked or copied into the report.
struct Images<'a> {
    /// The run folder, canonical.
    root: &'a Path,
    /// The scene's folder in the run, when its name is a file name.
    scene_dir: Option<PathBuf>,
    scene: &'a str,
    out: &'a Path,
    pages_dir: &'a Path,
    /// Whether the report lies inside the run folder (images are linked, not copied).
    inside_run: bool,
}

impl Images<'_> {
    /// The PNG files of `<scene>/<kind>`; a file that leads out of the run folder is left out
    /// with a remark.
    fn list(&self, kind: &str, remarks: &mut Vec<String>) -> Result<Vec<Image>, ReportError> {
        let Some(scene_dir) = &self.scene_dir else {
            return Ok(Vec::new());
        };
        let mut list = Vec::new();
        for path in pngs(&scene_dir.join(kind))? {
            let file_name = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let Inside::Yes(real) = inside(self.root, &path) else {
                remarks.push(format!(
                    "The image {kind}/{file_name} is a symbolic link that leads out of the run folder: not shown."
                ));
                continue;
            };
            let href = if self.inside_run {
                relative_href(self.pages_dir, &path)
            } else {
                None
            };
            let href = match href {
                Some(h) => h,
                None => {
                    let mut bytes = Vec::new();
                    sceneeval_files::open_regular(&real)
                        .and_then(|mut f| std::io::Read::read_to_end(&mut f, &mut bytes))
                        .map_err(|e| ReportError::file(&path, e))?;
                    let folder = escape::file_name(self.scene);
                    write_atomic(
                        &self.out.join(FILES_DIR).join(&folder).join(kind).join(&file_name),
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
    }
}

/// The scene of `record` read from its file, or why it cannot be; and remarks on it. `root` is
/// the run folder (canonical).
fn load(
    record: &SceneRecord,
    root: &Path,
    options: &ReportOptions,
    assets: &AssetLibrary,
) -> (Result<Scene, NoTopView>, Vec<String>) {
    let recorded = record.fingerprint.as_ref().map(|f| &f.scene);
    let name = record.scene.as_str();
    let path = match (&options.scenes, recorded) {
        (Some(_), _) if !is_file_name(name) => return (Err(NoTopView::NotAFileName), Vec::new()),
        (Some(dir), _) => dir.join(format!("{name}.json")),
        (None, Some(f)) => match inside(root, Path::new(&f.path)) {
            Inside::Yes(path) => path,
            // Not followed, not quoted: a record can name any file.
            Inside::No | Inside::Missing => return (Err(NoTopView::OutsideRun), Vec::new()),
        },
        (None, None) => return (Err(NoTopView::NotRecorded), Vec::new()),
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
            Err(NoTopView::Unreadable {
                reason: format!("{:#}", ErrorChain::new(&e)),
                path,
            }),
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
