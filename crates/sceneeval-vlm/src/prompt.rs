//! Prompt templates: the built-in ones (shipped in the crate, the reference's prompts in
//! substance and layout) and user overrides read from files.
//!
//! A template is plain text with placeholders written `<NAME>` (upper case, digits and `_`),
//! as in the reference's `vlm/prompts.yaml`. Each template has a fixed set of placeholders,
//! every one of which it must use (otherwise a scene-specific part would silently be left out
//! of the prompt); [`Template::placeholders`] lists them. Filling is a single pass, so a value
//! that itself contains `<NAME>` is inserted verbatim.
//!
//! To change a prompt, copy the built-in file from the crate's `prompts/` folder into a folder
//! of your own, edit it, and load the folder with [`Prompts::with_overrides_from_dir`]: every
//! `<template>.txt` file there replaces the built-in template of that name. Because prompts are
//! part of every cache key, changed prompts are answered afresh rather than from the cache.

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::{TaskKind, VlmError};

/// One prompt template: the system prompt, the user message of each task ([`TaskKind`], the
/// one list of tasks; the template has the task's name), the size-aware variant of object
/// matching, the re-ask note, and the system prompt of the annotation tasks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[non_exhaustive]
pub enum Template {
    /// The system prompt of every task.
    System,
    /// The user message of a task (`obj_matching`, `obj_attribute`, ...).
    Task(TaskKind),
    /// Object matching with the object's dimensions (the SceneSmith fork's size-aware variant
    /// of [`TaskKind::ObjMatching`]'s template).
    ObjMatchingSized,
    /// Appended to a task's text when an invalid answer is asked again.
    Reask,
    /// The system prompt of the annotation tasks ([`TaskKind::AnnotateDescription`],
    /// [`TaskKind::GenerateAnnotatedDescription`]): the paper's, word for word (appendix
    /// "Semi-Automatic Data Generation", "System Prompt").
    AnnotationSystem,
}

impl Template {
    /// All templates: the system prompt, each task's (the size-aware matching variant after
    /// object matching), the re-ask note, the annotation tasks' system prompt.
    pub const ALL: [Template; TaskKind::ALL.len() + 4] = {
        let mut all = [Template::System; TaskKind::ALL.len() + 4];
        let mut next = 1;
        let mut i = 0;
        while i < TaskKind::ALL.len() {
            all[next] = Template::Task(TaskKind::ALL[i]);
            next += 1;
            if matches!(TaskKind::ALL[i], TaskKind::ObjMatching) {
                all[next] = Template::ObjMatchingSized;
                next += 1;
            }
            i += 1;
        }
        all[next] = Template::Reask;
        all[next + 1] = Template::AnnotationSystem;
        all
    };

    /// The position of the template in [`Template::ALL`].
    const fn index(self) -> usize {
        match self {
            Template::System => 0,
            // Task `i` of TaskKind::ALL, shifted past the sized variant after ObjMatching.
            Template::Task(kind) => {
                let i = kind as usize;
                if i > TaskKind::ObjMatching as usize {
                    i + 2
                } else {
                    i + 1
                }
            }
            Template::ObjMatchingSized => TaskKind::ObjMatching as usize + 2,
            Template::Reask => Template::ALL.len() - 2,
            Template::AnnotationSystem => Template::ALL.len() - 1,
        }
    }

    /// The template's name, which is also the stem of its file (`obj_matching.txt`); a task's
    /// template has the task's name (its name in the reference's `prompts.yaml`).
    pub const fn name(self) -> &'static str {
        match self {
            Template::System => "system",
            Template::Task(kind) => kind.name(),
            Template::ObjMatchingSized => "obj_matching_sized",
            Template::Reask => "reask",
            Template::AnnotationSystem => "annotation_system",
        }
    }

    /// The placeholders the template must contain, and no others.
    pub const fn placeholders(self) -> &'static [&'static str] {
        match self {
            Template::System | Template::AnnotationSystem => &[],
            Template::Reask => &["PROBLEMS", "PREVIOUS_ANSWER"],
            Template::ObjMatchingSized => &["OBJECT_DIMENSIONS", "TARGET_CATEGORIES"],
            Template::Task(kind) => match kind {
                TaskKind::ObjSupportType | TaskKind::EndpointCheck => &[],
                TaskKind::ObjMatching => &["TARGET_CATEGORIES"],
                TaskKind::ObjAttribute => &["OBJ_ATTRIBUTES", "OBJ_COUNT", "OBJ_CATEGORY"],
                TaskKind::ObjFunctionalSides => &["OBJ_INFO"],
                TaskKind::ObjRelationshipMapping => &["RELATIONSHIPS"],
                TaskKind::ArchRelationshipMapping => &["RELATIONSHIPS", "FLOOR_IDS"],
                TaskKind::CategoryMatchingForSemanticColor => &["REFERENCE_CATEGORIES", "INPUT_CATEGORIES"],
                TaskKind::AnnotateDescription => &[
                    "NUM_EXAMPLES",
                    "IN_CONTEXT_EXAMPLES",
                    "DIFFICULTY",
                    "SCENE_DESCRIPTION",
                ],
                TaskKind::GenerateAnnotatedDescription => {
                    &["NUM_EXAMPLES", "IN_CONTEXT_EXAMPLES", "INSTRUCTION", "DIFFICULTY"]
                }
            },
        }
    }

    /// The built-in text (the files in the crate's `prompts/` folder).
    pub const fn builtin(self) -> &'static str {
        match self {
            Template::System => include_str!("../prompts/system.txt"),
            Template::ObjMatchingSized => include_str!("../prompts/obj_matching_sized.txt"),
            Template::Reask => include_str!("../prompts/reask.txt"),
            Template::AnnotationSystem => include_str!("../prompts/annotation_system.txt"),
            Template::Task(kind) => match kind {
                TaskKind::ObjMatching => include_str!("../prompts/obj_matching.txt"),
                TaskKind::ObjAttribute => include_str!("../prompts/obj_attribute.txt"),
                TaskKind::ObjSupportType => include_str!("../prompts/obj_support_type.txt"),
                TaskKind::ObjFunctionalSides => include_str!("../prompts/obj_functional_sides.txt"),
                TaskKind::ObjRelationshipMapping => include_str!("../prompts/obj_relationship_mapping.txt"),
                TaskKind::ArchRelationshipMapping => include_str!("../prompts/arch_relationship_mapping.txt"),
                TaskKind::CategoryMatchingForSemanticColor => {
                    include_str!("../prompts/category_matching_for_semantic_color.txt")
                }
                TaskKind::AnnotateDescription => include_str!("../prompts/annotate_description.txt"),
                TaskKind::GenerateAnnotatedDescription => {
                    include_str!("../prompts/generate_annotated_description.txt")
                }
                TaskKind::EndpointCheck => include_str!("../prompts/endpoint_check.txt"),
            },
        }
    }

    /// The template with this name.
    pub fn from_name(name: &str) -> Option<Template> {
        Template::ALL.into_iter().find(|t| t.name() == name)
    }
}

impl fmt::Display for Template {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The set of prompt templates a [`crate::Session`] uses.
///
/// ```
/// use sceneeval_vlm::prompt::{Prompts, Template};
/// use sceneeval_vlm::TaskKind;
/// let prompts = Prompts::builtin();
/// let matching = Template::Task(TaskKind::ObjMatching);
/// let text = prompts.fill(matching, &[("TARGET_CATEGORIES", "[\"bed\"]")]).unwrap();
/// assert!(text.ends_with("[\"bed\"]"), "the scene-specific part comes last");
/// assert!(prompts.with_override(matching, "no placeholder").is_err());
/// ```
#[derive(Debug, Clone)]
pub struct Prompts {
    texts: Vec<Arc<str>>,
    sources: Vec<Option<PathBuf>>,
}

impl Default for Prompts {
    fn default() -> Self {
        Prompts::builtin()
    }
}

impl Prompts {
    /// The built-in templates.
    pub fn builtin() -> Self {
        Prompts {
            texts: Template::ALL
                .iter()
                .map(|t| Arc::from(t.builtin().trim_end()))
                .collect(),
            sources: vec![None; Template::ALL.len()],
        }
    }

    /// The built-in templates with those of `dir` in their place: each file
    /// `<template name>.txt` replaces one template. Other files are ignored, except `.txt` files
    /// whose stem is not a template name, which are an error (most likely a misspelt name).
    ///
    /// # Errors
    /// [`VlmError::Io`] when the folder or a file cannot be read, [`VlmError::Prompt`] for an
    /// unknown template name or a template with missing or unknown placeholders.
    pub fn with_overrides_from_dir(self, dir: impl AsRef<Path>) -> Result<Self, VlmError> {
        let dir = dir.as_ref();
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .map_err(|e| VlmError::io(dir, e))?
            .map(|e| e.map(|e| e.path()).map_err(|err| VlmError::io(dir, err)))
            .collect::<Result<_, _>>()?;
        entries.sort();
        let mut prompts = self;
        for path in entries {
            if path.extension().and_then(|e| e.to_str()) != Some("txt") {
                continue;
            }
            let stem = path
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or_default()
                .to_owned();
            let Some(template) = Template::from_name(&stem) else {
                let names: Vec<&str> = Template::ALL.iter().map(|t| t.name()).collect();
                return Err(VlmError::Prompt {
                    template: stem,
                    path: Some(path),
                    message: format!("not a template name; expected one of {}", names.join(", ")),
                });
            };
            let text = std::fs::read_to_string(&path).map_err(|e| VlmError::io(&path, e))?;
            check_placeholders(template, &text).map_err(|message| VlmError::Prompt {
                template: stem.clone(),
                path: Some(path.clone()),
                message,
            })?;
            tracing::info!(template = %template, path = %path.display(), "prompt template overridden");
            prompts.texts[template.index()] = Arc::from(text.trim_end());
            prompts.sources[template.index()] = Some(path);
        }
        Ok(prompts)
    }

    /// These templates with `template` replaced by `text`.
    ///
    /// # Errors
    /// [`VlmError::Prompt`] when `text` lacks one of the template's placeholders or has an
    /// unknown one.
    pub fn with_override(&self, template: Template, text: &str) -> Result<Self, VlmError> {
        check_placeholders(template, text).map_err(|message| VlmError::Prompt {
            template: template.name().to_owned(),
            path: None,
            message,
        })?;
        let mut prompts = self.clone();
        prompts.texts[template.index()] = Arc::from(text.trim_end());
        prompts.sources[template.index()] = None;
        Ok(prompts)
    }

    /// The text of a template (trailing whitespace removed).
    pub fn text(&self, template: Template) -> &str {
        &self.texts[template.index()]
    }

    /// The file a template was read from, if it was overridden from a folder.
    pub fn source(&self, template: Template) -> Option<&Path> {
        self.sources[template.index()].as_deref()
    }

    /// The template with its placeholders replaced by `values` (`(name, value)` pairs, names
    /// without the angle brackets).
    ///
    /// # Errors
    /// [`VlmError::Prompt`] when `values` misses one of the template's placeholders.
    pub fn fill(&self, template: Template, values: &[(&str, &str)]) -> Result<String, VlmError> {
        let text = self.text(template);
        let mut out = String::with_capacity(text.len() + values.iter().map(|(_, v)| v.len()).sum::<usize>());
        let mut rest = text;
        while let Some((before, name, after)) = next_placeholder(rest) {
            out.push_str(before);
            match values.iter().find(|(n, _)| *n == name) {
                Some((_, value)) => out.push_str(value),
                None => {
                    return Err(VlmError::Prompt {
                        template: template.name().to_owned(),
                        path: self.source(template).map(Path::to_path_buf),
                        message: format!("no value for placeholder <{name}>"),
                    });
                }
            }
            rest = after;
        }
        out.push_str(rest);
        Ok(out)
    }
}

/// Splits `text` at its first placeholder: (text before, name, text after).
fn next_placeholder(text: &str) -> Option<(&str, &str, &str)> {
    let mut from = 0;
    while let Some(open) = text[from..].find('<').map(|i| i + from) {
        let tail = &text[open + 1..];
        let len = tail
            .bytes()
            .take_while(|b| b.is_ascii_uppercase() || b.is_ascii_digit() || *b == b'_')
            .count();
        if len > 0 && tail.as_bytes()[0].is_ascii_uppercase() && tail.as_bytes().get(len) == Some(&b'>') {
            return Some((&text[..open], &tail[..len], &tail[len + 1..]));
        }
        from = open + 1;
    }
    None
}

/// Every placeholder of `template` is used and no other one appears.
fn check_placeholders(template: Template, text: &str) -> Result<(), String> {
    let expected = template.placeholders();
    let mut found = Vec::new();
    let mut rest = text;
    while let Some((_, name, after)) = next_placeholder(rest) {
        if !expected.contains(&name) {
            let list = if expected.is_empty() {
                "none".to_owned()
            } else {
                expected
                    .iter()
                    .map(|p| format!("<{p}>"))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return Err(format!(
                "unknown placeholder <{name}>; this template takes {list}"
            ));
        }
        found.push(name);
        rest = after;
    }
    if let Some(missing) = expected.iter().find(|p| !found.contains(p)) {
        return Err(format!("placeholder <{missing}> is missing"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_templates_use_exactly_their_placeholders() {
        for t in Template::ALL {
            check_placeholders(t, t.builtin()).unwrap_or_else(|e| panic!("{t}: {e}"));
            assert_eq!(Template::from_name(t.name()), Some(t));
        }
    }

    #[test]
    fn every_task_has_its_template_in_order() {
        let names: Vec<&str> = Template::ALL.iter().map(|t| t.name()).collect();
        assert_eq!(
            names,
            [
                "system",
                "obj_matching",
                "obj_matching_sized",
                "obj_attribute",
                "obj_support_type",
                "obj_functional_sides",
                "obj_relationship_mapping",
                "arch_relationship_mapping",
                "category_matching_for_semantic_color",
                "annotate_description",
                "generate_annotated_description",
                "endpoint_check",
                "reask",
                "annotation_system"
            ]
        );
        for (i, t) in Template::ALL.into_iter().enumerate() {
            assert_eq!(t.index(), i, "{t}");
        }
        for kind in TaskKind::ALL {
            assert_eq!(Template::Task(kind).name(), kind.name());
        }
    }

    #[test]
    fn scene_specific_part_comes_last() {
        // Every placeholder sits in the last fifth of its template, after the instructions
        // and examples (the reference's layout), except in the re-ask note.
        for t in Template::ALL {
            let text = Prompts::builtin().text(t).to_owned();
            if let Some((before, _, _)) = next_placeholder(&text).filter(|_| t != Template::Reask) {
                assert!(before.len() * 5 >= text.len() * 4, "{t}: placeholder too early");
            }
        }
    }

    #[test]
    fn fill_is_single_pass() {
        let p = Prompts::builtin()
            .with_override(
                Template::Task(TaskKind::CategoryMatchingForSemanticColor),
                "A <REFERENCE_CATEGORIES> B <INPUT_CATEGORIES>",
            )
            .unwrap();
        let text = p
            .fill(
                Template::Task(TaskKind::CategoryMatchingForSemanticColor),
                &[
                    ("REFERENCE_CATEGORIES", "<INPUT_CATEGORIES>"),
                    ("INPUT_CATEGORIES", "x"),
                ],
            )
            .unwrap();
        assert_eq!(text, "A <INPUT_CATEGORIES> B x");
        let err = p
            .fill(Template::Task(TaskKind::CategoryMatchingForSemanticColor), &[])
            .unwrap_err();
        assert!(err.to_string().contains("<REFERENCE_CATEGORIES>"), "{err}");
    }

    #[test]
    fn placeholder_scanner_ignores_other_angle_brackets() {
        assert_eq!(
            next_placeholder("a < b <c> <Dd> <E_1> z"),
            Some(("a < b <c> <Dd> ", "E_1", " z"))
        );
        assert_eq!(next_placeholder("<_X> <1A>"), None);
    }

    #[test]
    fn overrides_from_a_folder() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("obj_matching.txt"),
            "Pick one of <TARGET_CATEGORIES>\n",
        )
        .unwrap();
        std::fs::write(dir.path().join("notes.md"), "ignored").unwrap();
        let p = Prompts::builtin().with_overrides_from_dir(dir.path()).unwrap();
        assert_eq!(
            p.text(Template::Task(TaskKind::ObjMatching)),
            "Pick one of <TARGET_CATEGORIES>"
        );
        assert!(p.source(Template::Task(TaskKind::ObjMatching)).is_some());
        assert_eq!(p.text(Template::System), Template::System.builtin().trim_end());

        std::fs::write(dir.path().join("obj_matchin.txt"), "typo").unwrap();
        let err = Prompts::builtin()
            .with_overrides_from_dir(dir.path())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("obj_matchin") && err.contains("obj_matching_sized"),
            "{err}"
        );

        let dir2 = tempfile::tempdir().unwrap();
        std::fs::write(
            dir2.path().join("obj_attribute.txt"),
            "<OBJ_ATTRIBUTES> <OBJ_COUNT>",
        )
        .unwrap();
        let err = Prompts::builtin()
            .with_overrides_from_dir(dir2.path())
            .unwrap_err()
            .to_string();
        assert!(err.contains("<OBJ_CATEGORY> is missing"), "{err}");
    }
}
