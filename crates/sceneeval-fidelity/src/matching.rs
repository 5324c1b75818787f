//! Object matching: which scene objects are instances of which annotated category.
//!
//! Three sources ([`crate::MatchingMethod`]): the VLM (one request per object with its front
//! view, as the reference), the objects' stated labels ([`crate::labels`]), or a file in the
//! reference's `obj_matching_result.json` shape. Whatever the source, the result is a
//! [`Matching`], written per scene as `matching.json` ([`MatchingRecord`]) with its source and
//! a reason per object.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use sceneeval_scene::Scene;
use sceneeval_vlm::tasks::{ObjectDimensions, ObjectMatchingTask};
use sceneeval_vlm::{Outcome, Session, Vlm};

use crate::FidelityError;
use crate::labels::{LabelMatch, match_label};
use crate::views::{ObjectViews, ViewKind};

/// The schema of `matching.json`.
pub const MATCHING_SCHEMA: &str = "sceneeval.matching/1";

/// The file name of a scene's matching in its output folder.
pub const MATCHING_FILE: &str = "matching.json";

/// The file name the reference gives its matching.
pub const REFERENCE_MATCHING_FILE: &str = "obj_matching_result.json";

/// Scene objects assigned to annotated categories, in the reference's
/// `obj_matching_result.json` shape (each object in at most one category).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Matching {
    /// Every annotated category, with the objects matched to it and why.
    pub per_category: BTreeMap<String, BTreeMap<String, String>>,
    /// Objects matched to no category, and why.
    pub not_matched_objs: BTreeMap<String, String>,
    /// What each object actually is (its label, or the VLM's words).
    #[serde(default)]
    pub actual_categories: BTreeMap<String, String>,
}

impl Matching {
    /// The indices (in scene order) of the objects matched to `category`.
    pub fn objects_of(&self, scene: &Scene, category: &str) -> Vec<usize> {
        let Some(objs) = self.per_category.get(category) else {
            return Vec::new();
        };
        let mut idx: Vec<usize> = objs.keys().filter_map(|id| scene.object_index(id)).collect();
        idx.sort_unstable();
        idx
    }

    /// "Matched a/b categories. Matched c/d objects." as the reference reports it.
    pub fn message(&self, objects: usize) -> String {
        let cats = self.per_category.values().filter(|m| !m.is_empty()).count();
        let objs: usize = self.per_category.values().map(BTreeMap::len).sum();
        format!(
            "Matched {cats}/{} categories. Matched {objs}/{objects} objects.",
            self.per_category.len()
        )
    }
}

/// Where a matching came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MatchingSource {
    /// The objects' labels.
    Labels,
    /// The VLM.
    Vlm,
    /// A file.
    File,
}

/// A scene's `matching.json`: the matching, its source, and the objects the VLM did not
/// answer for.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatchingRecord {
    /// Always [`MATCHING_SCHEMA`].
    pub schema: String,
    /// Where the matching came from.
    pub source: MatchingSource,
    /// The file, for [`MatchingSource::File`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<PathBuf>,
    /// The matching.
    #[serde(flatten)]
    pub matching: Matching,
    /// Objects without a valid VLM answer, and why (they are in `not_matched_objs` too).
    #[serde(default)]
    pub unanswered: BTreeMap<String, String>,
}

impl MatchingRecord {
    /// Writes the record as pretty JSON to `path`, atomically: through a temporary file with a
    /// unique name in the same folder, renamed into place ([`sceneeval_files::write_atomic`]),
    /// so that processes writing the same file at once all succeed and leave one whole record.
    ///
    /// # Errors
    /// [`FidelityError::Write`].
    pub fn write(&self, path: &Path) -> Result<(), FidelityError> {
        let write_err = |source| FidelityError::Write {
            path: path.to_owned(),
            source,
        };
        let mut text = serde_json::to_string_pretty(self).map_err(|e| write_err(std::io::Error::other(e)))?;
        text.push('\n');
        sceneeval_files::write_atomic(path, text.as_bytes()).map_err(write_err)
    }
}

fn empty_matching(categories: &[String]) -> Matching {
    Matching {
        per_category: categories.iter().map(|c| (c.clone(), BTreeMap::new())).collect(),
        ..Matching::default()
    }
}

/// Matches by the objects' stated categories (see [`crate::labels`]).
pub fn match_by_labels(scene: &Scene, categories: &[String]) -> MatchingRecord {
    let mut m = empty_matching(categories);
    for o in scene.objects() {
        let id = o.id().as_str().to_owned();
        let Some(label) = o.category() else {
            m.not_matched_objs.insert(
                id,
                "the object states no category (scene file or asset metadata)".into(),
            );
            continue;
        };
        m.actual_categories.insert(id.clone(), label.to_owned());
        match match_label(label, categories) {
            Some((i, how)) => {
                let reason = match how {
                    LabelMatch::Exact => format!("label {label:?} is {:?}", categories[i]),
                    LabelMatch::HeadNoun => {
                        format!("label {label:?} is a kind of {:?} (head noun)", categories[i])
                    }
                };
                if let Some(objs) = m.per_category.get_mut(&categories[i]) {
                    objs.insert(id, reason);
                }
            }
            None => {
                m.not_matched_objs
                    .insert(id, format!("label {label:?} is none of the annotated categories"));
            }
        }
    }
    MatchingRecord {
        schema: MATCHING_SCHEMA.into(),
        source: MatchingSource::Labels,
        file: None,
        matching: m,
        unanswered: BTreeMap::new(),
    }
}

/// Matches with the VLM: one `obj_matching` request per object with its front view (and its
/// dimensions when `size_aware`). An object without a valid answer is not matched and listed
/// in `unanswered`.
///
/// # Errors
/// [`FidelityError::View`] when a view cannot be made, [`FidelityError::Vlm`] when a request
/// gets no answer at all.
pub fn match_by_vlm<V: Vlm>(
    scene: &Scene,
    categories: &[String],
    session: &Session<V>,
    views: &dyn ObjectViews,
    size_aware: bool,
) -> Result<MatchingRecord, FidelityError> {
    let mut m = empty_matching(categories);
    let mut unanswered = BTreeMap::new();
    if !categories.is_empty() {
        for o in scene.objects() {
            let id = o.id().as_str().to_owned();
            let front = views.view(&id, ViewKind::Front)?;
            let mut task = ObjectMatchingTask::new(front, categories.iter().cloned())
                .map_err(|e| vlm_err("obj_matching", e))?;
            if size_aware {
                task = task.with_dimensions(ObjectDimensions {
                    extents_m: o.obb().extents(),
                });
            }
            let answers = pollster::block_on(session.ask(&task)).map_err(|e| vlm_err("obj_matching", e))?;
            match answers.into_single() {
                Some(Outcome::Answered { answer, .. }) => {
                    m.actual_categories
                        .insert(id.clone(), answer.actual_category.clone());
                    match answer.category {
                        Some(c) => {
                            if let Some(objs) = m.per_category.get_mut(&c) {
                                objs.insert(id, answer.reason);
                            }
                        }
                        None => {
                            m.not_matched_objs.insert(id, answer.reason);
                        }
                    }
                }
                Some(Outcome::Unanswered(why)) => {
                    m.not_matched_objs
                        .insert(id.clone(), format!("unanswered: {why}"));
                    unanswered.insert(id, why.to_string());
                }
                None => {
                    unanswered.insert(id.clone(), "no outcome".into());
                    m.not_matched_objs.insert(id, "unanswered: no outcome".into());
                }
            }
        }
    }
    Ok(MatchingRecord {
        schema: MATCHING_SCHEMA.into(),
        source: MatchingSource::Vlm,
        file: None,
        matching: m,
        unanswered,
    })
}

pub(crate) fn vlm_err(task: &str, source: sceneeval_vlm::VlmError) -> FidelityError {
    FidelityError::Vlm {
        task: task.to_owned(),
        source: Box::new(source),
    }
}

/// The matching file of scene `scene_name` under `path`: `path` itself when it is a file,
/// else `<path>/<scene_name>/matching.json` or `<path>/<scene_name>/obj_matching_result.json`.
pub fn matching_file_for(path: &Path, scene_name: &str) -> PathBuf {
    if path.is_dir() {
        let ours = path.join(scene_name).join(MATCHING_FILE);
        if ours.is_file() {
            return ours;
        }
        path.join(scene_name).join(REFERENCE_MATCHING_FILE)
    } else {
        path.to_owned()
    }
}

/// Reads a matching file (the reference's `obj_matching_result.json` or a `matching.json`)
/// and checks it against the scene and the annotated categories: every object id must be in
/// the scene, every category annotated, no object in two categories. Annotated categories the
/// file lacks have no objects.
///
/// # Errors
/// [`FidelityError::MatchingFile`], [`FidelityError::MatchingFormat`].
pub fn read_matching_file(
    path: &Path,
    scene: &Scene,
    categories: &[String],
) -> Result<MatchingRecord, FidelityError> {
    // A regular file only: a named pipe would block the reader.
    let text = sceneeval_files::open_regular(path)
        .and_then(|mut file| {
            let mut text = String::new();
            std::io::Read::read_to_string(&mut file, &mut text).map(|_| text)
        })
        .map_err(|source| FidelityError::MatchingFile {
            path: path.to_owned(),
            source,
        })?;
    let bad = |message: String| FidelityError::MatchingFormat {
        path: path.to_owned(),
        message,
    };
    let given: Matching = serde_json::from_str(&text)
        .map_err(|e| bad(format!("not in the obj_matching_result.json shape: {e}")))?;
    let mut m = empty_matching(categories);
    let mut owner: BTreeMap<&str, &str> = BTreeMap::new();
    for (cat, objs) in &given.per_category {
        let Some(slot) = m.per_category.get_mut(cat) else {
            return Err(bad(format!(
                "/per_category/{cat}: {cat:?} is not an annotated category of this scene"
            )));
        };
        for (id, reason) in objs {
            if scene.object_index(id).is_none() {
                return Err(bad(format!(
                    "/per_category/{cat}/{id}: no object {id:?} in the scene"
                )));
            }
            if let Some(first) = owner.insert(id, cat) {
                return Err(bad(format!(
                    "object {id:?} is matched to both {first:?} and {cat:?}"
                )));
            }
            slot.insert(id.clone(), reason.clone());
        }
    }
    for (id, reason) in &given.not_matched_objs {
        if scene.object_index(id).is_none() {
            return Err(bad(format!(
                "/not_matched_objs/{id}: no object {id:?} in the scene"
            )));
        }
        if owner.contains_key(id.as_str()) {
            return Err(bad(format!("object {id:?} is both matched and not matched")));
        }
        m.not_matched_objs.insert(id.clone(), reason.clone());
    }
    for o in scene.objects() {
        let id = o.id().as_str();
        if !owner.contains_key(id) && !m.not_matched_objs.contains_key(id) {
            m.not_matched_objs
                .insert(id.to_owned(), "not listed in the matching file".into());
        }
    }
    m.actual_categories = given.actual_categories;
    Ok(MatchingRecord {
        schema: MATCHING_SCHEMA.into(),
        source: MatchingSource::File,
        file: Some(path.to_owned()),
        matching: m,
        unanswered: BTreeMap::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(category: &str) -> MatchingRecord {
        let mut matching = Matching::default();
        matching.per_category.insert(
            category.to_owned(),
            (0..500)
                .map(|k| (format!("o{k}"), "its label".to_owned()))
                .collect(),
        );
        MatchingRecord {
            schema: MATCHING_SCHEMA.into(),
            source: MatchingSource::Labels,
            file: None,
            matching,
            unanswered: BTreeMap::new(),
        }
    }

    #[test]
    fn concurrent_writers_of_one_matching_file_never_fail_and_leave_one_whole_record() {
        // Three `evaluate` processes on one --out wrote `matching.json` through the fixed name
        // `matching.json.tmp` and failed each other ("No such file or directory"). Two writers
        // of two different records, 50 times each: all succeed, one whole record remains.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("scene_7").join(MATCHING_FILE);
        let records = [record("bed"), record("sofa")];
        std::thread::scope(|s| {
            for r in &records {
                let path = &path;
                s.spawn(move || {
                    for _ in 0..50 {
                        r.write(path).unwrap();
                    }
                });
            }
        });
        let back: MatchingRecord = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        assert!(back == records[0] || back == records[1]);
        assert_eq!(std::fs::read_dir(path.parent().unwrap()).unwrap().count(), 1);
    }

    #[cfg(unix)]
    #[test]
    fn a_matching_file_that_is_a_pipe_is_refused_without_blocking() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("obj_matching_result.json");
        let status = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(status.success());
        let scene = sceneeval_scene::Scene::builder().build().unwrap();
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let err = read_matching_file(&fifo, &scene, &[]).map(|_| ()).unwrap_err();
            let cause = std::error::Error::source(&err).map(ToString::to_string);
            let _ = tx.send(format!("{err}: {}", cause.unwrap_or_default()));
        });
        let err = rx
            .recv_timeout(std::time::Duration::from_secs(20))
            .expect("blocked on a named pipe");
        assert!(
            err.contains("is a named pipe (FIFO), not a regular file"),
            "{err}"
        );
    }
}
