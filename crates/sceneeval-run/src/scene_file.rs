//! The scene files of a run: [`SceneFile`] (a scene's identity, its [`SceneName`], made once
//! where scene files are found, and its file); [`find_scenes`] lists a folder's scene files.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};

use sceneeval_results::{RECORD_FILE, SceneName, TIMING_FILE};

use sceneeval_annotation::Annotations;
use sceneeval_eval::RequestField;

use crate::RunError;

/// A scene file found by [`find_scenes`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneFile {
    /// The scene's name and id (`scene_12`, `12`).
    pub name: SceneName,
    /// The file.
    pub path: PathBuf,
}

impl SceneFile {
    /// The scene's folder under `out_dir` (`<out_dir>/scene_12`).
    pub fn out_dir(&self, out_dir: &Path) -> PathBuf {
        out_dir.join(self.name.as_str())
    }

    /// Where this scene's record goes under `out_dir`.
    pub fn record_path(&self, out_dir: &Path) -> PathBuf {
        self.out_dir(out_dir).join(RECORD_FILE)
    }

    /// Where this scene's timing file goes under `out_dir`.
    pub fn timing_path(&self, out_dir: &Path) -> PathBuf {
        self.out_dir(out_dir).join(TIMING_FILE)
    }

    /// The benchmark id's number, by which scene files are ordered (files found by
    /// [`find_scenes`] always have one).
    fn number(&self) -> u64 {
        self.name.number().unwrap_or(u64::MAX)
    }
}

/// A file of the scene folder that looks like a scene file but is not evaluated.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SkippedFile {
    /// The file.
    pub path: PathBuf,
    /// Why it is skipped.
    pub reason: String,
}

/// The scene files of a folder and the near misses that were skipped.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SceneSet {
    /// The `scene_<ID>.json` files, ordered by ID.
    pub scenes: Vec<SceneFile>,
    /// Entries whose name starts with `scene_` and ends with `.json` (in any case) that are
    /// not regular files of the form `scene_<digits>.json` (or whose name is not valid UTF-8).
    pub skipped: Vec<SkippedFile>,
}

/// The `scene_<ID>.json` files of a folder (not recursive), `<ID>` one or more ASCII digits
/// and `.json` lower case (as the reference names them), ordered by ID. Entries that look like
/// scene files but are not regular files of that form (`scene_1.JSON`, `scene_x.json`,
/// `scene_state_template.json`, a name that is not UTF-8, a folder or a FIFO named
/// `scene_7.json`) are listed as skipped, so that the caller can warn.
///
/// # Errors
/// [`RunError::File`] when the folder cannot be read; [`RunError::DuplicateSceneId`] when
/// two files have the same ID (`scene_1.json` and `scene_01.json`), before any work is done.
pub fn find_scenes(dir: &Path) -> Result<SceneSet, RunError> {
    let file_err = |source| RunError::file(dir, source);
    let mut set = SceneSet::default();
    for entry in std::fs::read_dir(dir).map_err(file_err)? {
        let path = entry.map_err(file_err)?.path();
        let Some(file_name) = path.file_name() else {
            continue;
        };
        let looks_like_scene = {
            let lossy = file_name.to_string_lossy().to_ascii_lowercase();
            lossy.starts_with("scene_") && lossy.ends_with(".json")
        };
        if !looks_like_scene {
            continue;
        }
        let reason = match std::fs::metadata(&path) {
            Err(e) => Some(format!("cannot be read: {e}")),
            Ok(m) if m.is_dir() => Some("a folder, not a file".to_owned()),
            Ok(m) if !m.is_file() => Some("not a regular file (a FIFO, socket or device)".to_owned()),
            Ok(_) => scene_name_of(file_name).err().map(str::to_owned),
        };
        match reason {
            Some(reason) => set.skipped.push(SkippedFile { path, reason }),
            None => {
                let Ok(name) = scene_name_of(file_name) else {
                    continue;
                };
                set.scenes.push(SceneFile { name, path });
            }
        }
    }
    set.scenes
        .sort_by(|a, b| a.number().cmp(&b.number()).then_with(|| a.name.cmp(&b.name)));
    set.skipped.sort_by(|a, b| a.path.cmp(&b.path));
    for pair in set.scenes.windows(2) {
        if pair[0].number() == pair[1].number() {
            return Err(RunError::DuplicateSceneId {
                id: pair[0].number(),
                first: pair[0].path.clone(),
                second: pair[1].path.clone(),
            });
        }
    }
    Ok(set)
}

/// The name of `scene_<digits>.json`, or why the file name is not one.
fn scene_name_of(file_name: &OsStr) -> Result<SceneName, &'static str> {
    let Some(name) = file_name.to_str() else {
        return Err("the file name is not valid UTF-8");
    };
    let Some(stem) = name.strip_suffix(".json") else {
        return Err("scene files end in lower-case .json");
    };
    let digits = stem.strip_prefix("scene_").unwrap_or("");
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return Err("not of the form scene_<ID>.json with a numeric ID");
    }
    let name = SceneName::new(stem);
    if name.number().is_none() {
        return Err("the ID is too large");
    }
    Ok(name)
}

/// The most findings [`check_annotation_rows`]'s error lists (it counts the rest).
const MAX_LISTED_FINDINGS: usize = 20;

/// Validates the annotation rows the run's `scenes` use, as the whole file's validation
/// reports them ([`Annotations::validate_rows`]), so that a bad row stops the run before
/// its first scene rather than failing scene after scene. A plan with text-fidelity metrics
/// reads every cell of a row; any other reads only the ID and the difficulty (the summary's
/// groups), so only findings about those count.
///
/// # Errors
/// [`RunError::Eval`] with a request error on [`RequestField::Annotations`] listing the rows'
/// errors; warnings are logged.
pub(crate) fn check_annotation_rows(
    annotations: &Annotations,
    scenes: &[SceneFile],
    fidelity: bool,
) -> Result<(), RunError> {
    use sceneeval_annotation::{Field, Severity};
    let used: std::collections::BTreeSet<usize> = scenes
        .iter()
        .filter_map(|s| s.name.annotation_row(annotations))
        .filter_map(|row| annotations.rows.iter().position(|r| std::ptr::eq(r, row)))
        .collect();
    let findings: Vec<_> = annotations
        .validate_rows(&used)
        .into_iter()
        .filter(|f| fidelity || matches!(f.field, Field::Id | Field::Difficulty))
        .collect();
    let (errors, warnings): (Vec<_>, Vec<_>) = findings.iter().partition(|f| f.severity == Severity::Error);
    for w in &warnings {
        tracing::debug!("annotation row: {w}");
    }
    if !warnings.is_empty() {
        tracing::warn!(
            rows = used.len(),
            warnings = warnings.len(),
            "the annotation rows this run uses have {} warning(s) (probably wrong, still evaluable)",
            warnings.len()
        );
    }
    if errors.is_empty() {
        return Ok(());
    }
    let rows: std::collections::BTreeSet<usize> = errors.iter().map(|f| f.row_index).collect();
    let mut message = format!(
        "{} of the {} rows this run uses {} {} error(s); nothing was evaluated:",
        rows.len(),
        used.len(),
        if rows.len() == 1 { "has" } else { "have" },
        errors.len()
    );
    for f in errors.iter().take(MAX_LISTED_FINDINGS) {
        message.push_str(&format!("\n  {f}"));
    }
    if errors.len() > MAX_LISTED_FINDINGS {
        message.push_str(&format!("\n  and {} more", errors.len() - MAX_LISTED_FINDINGS));
    }
    Err(RunError::request(RequestField::Annotations, message))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_scene_files_in_numeric_order() {
        let dir = tempfile::tempdir().unwrap();
        for name in [
            "scene_10.json",
            "scene_2.json",
            "scene_x.json",
            "notes.json",
            "scene_1.txt",
            "scene_3.JSON",
            "scene_state_template.json",
        ] {
            std::fs::write(dir.path().join(name), "{}").unwrap();
        }
        std::fs::create_dir(dir.path().join("scene_4.json")).unwrap();
        let set = find_scenes(dir.path()).unwrap();
        let names: Vec<(&str, Option<u64>)> = set
            .scenes
            .iter()
            .map(|s| (s.name.as_str(), s.name.number()))
            .collect();
        assert_eq!(names, vec![("scene_2", Some(2)), ("scene_10", Some(10))]);
        let skipped: Vec<String> = set
            .skipped
            .iter()
            .map(|s| s.path.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            skipped,
            vec![
                "scene_3.JSON",
                "scene_4.json",
                "scene_state_template.json",
                "scene_x.json"
            ]
        );
        assert!(set.skipped[0].reason.contains("lower-case .json"));
        assert!(set.skipped[1].reason.contains("a folder"));
        assert!(matches!(
            find_scenes(&dir.path().join("missing")),
            Err(RunError::File { .. })
        ));
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_named_like_a_scene_is_skipped_with_a_reason() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("scene_7.json");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            eprintln!("skipped: mkfifo is not available");
            return;
        }
        std::fs::write(dir.path().join("scene_1.json"), "{}").unwrap();
        let set = find_scenes(dir.path()).unwrap();
        assert_eq!(set.scenes.len(), 1);
        assert_eq!(set.skipped.len(), 1);
        assert!(
            set.skipped[0].reason.contains("not a regular file"),
            "{:?}",
            set.skipped
        );
    }

    #[test]
    fn duplicate_ids_are_an_error_before_any_work() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["scene_1.json", "scene_01.json", "scene_2.json"] {
            std::fs::write(dir.path().join(name), "{}").unwrap();
        }
        let err = find_scenes(dir.path()).unwrap_err();
        assert!(matches!(err, RunError::DuplicateSceneId { id: 1, .. }), "{err}");
        let text = err.to_string();
        assert!(
            text.contains("scene_01.json") && text.contains("scene_1.json") && text.contains("same id 1"),
            "{text}"
        );
    }

    #[cfg(unix)]
    #[test]
    fn names_that_are_not_utf8_are_reported() {
        use std::os::unix::ffi::OsStrExt;
        let dir = tempfile::tempdir().unwrap();
        let name = OsStr::from_bytes(b"scene_\xff1.json");
        std::fs::write(dir.path().join(name), "{}").unwrap();
        let set = find_scenes(dir.path()).unwrap();
        assert!(set.scenes.is_empty());
        assert_eq!(set.skipped.len(), 1);
        assert!(set.skipped[0].reason.contains("not valid UTF-8"));
    }
}
