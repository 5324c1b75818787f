//! The two tasks of the paper's semi-automatic annotation generation (appendix
//! "Semi-Automatic Data Generation"): `annotate_description` (the annotations of a given scene
//! description) and `generate_annotated_description` (a new description of a difficulty level
//! with its annotations).
//!
//! Both send the paper's system prompt word for word ([`Template::AnnotationSystem`]) and a
//! user message made of the paper's instructions, the in-context examples (one JSON object per
//! line, in the answer's own form) and the scene-specific part last. The answer is one
//! [`AnnotatedDescription`]: `description`, `difficulty` and the four entry lists as strings
//! (`"eq,2,nightstand"`, `"eq,1,left,0,bed,nightstand"`).
//!
//! This crate knows the annotation schema only as text: the caller gives the check of an
//! answer's entries ([`EntryChecker`]; the facade's runs `sceneeval-annotation`'s validator),
//! and every problem it names makes the answer invalid, so [`crate::Session::ask`] asks once
//! more with the problems quoted. Every answer the model gave is kept
//! ([`AnnotationTask::answers`]), so that a caller can keep a rejected candidate with its
//! problems.

use std::fmt;
use std::sync::{Arc, Mutex, PoisonError};

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::TaskKind;
use crate::names::name_list;
use crate::prompt::Template;
use crate::task::{Single, Task, Validation};

/// A difficulty level of SceneEval-500 as the model writes it (the annotation crate's
/// `Difficulty` without its free-text case).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AnnotationLevel {
    /// At most four objects, all large furniture.
    Easy,
    /// Five to eight objects, at most three small.
    Medium,
    /// Nine objects or more.
    Hard,
}

impl AnnotationLevel {
    /// The three levels, easiest first.
    pub const ALL: [AnnotationLevel; 3] = [
        AnnotationLevel::Easy,
        AnnotationLevel::Medium,
        AnnotationLevel::Hard,
    ];

    /// `easy`, `medium` or `hard`.
    pub const fn name(self) -> &'static str {
        match self {
            AnnotationLevel::Easy => "easy",
            AnnotationLevel::Medium => "medium",
            AnnotationLevel::Hard => "hard",
        }
    }
}

impl fmt::Display for AnnotationLevel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for AnnotationLevel {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        AnnotationLevel::ALL
            .into_iter()
            .find(|l| l.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| format!("{s:?} is not a difficulty level (easy, medium or hard)"))
    }
}

name_list!(
    /// `difficulty` values: the three levels.
    LevelName => AnnotationLevel::ALL.iter().map(|l| l.name()).collect()
);

/// A scene description with its annotations, as the model writes it (the answer of both
/// annotation tasks) and as the in-context examples are shown. The four lists hold entries in
/// the SceneEval-500 schema, one string each.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
pub struct AnnotatedDescription {
    /// The scene description.
    pub description: String,
    /// Its difficulty level: `easy`, `medium` or `hard` (the schema lists them; a validated
    /// answer has one of them, in lower case).
    #[schemars(with = "LevelName")]
    pub difficulty: String,
    /// `ObjCount` entries: `q,n,category`.
    pub obj_count: Vec<String>,
    /// `ObjAttr` entries: `q,n,category,attribute`.
    pub obj_attr: Vec<String>,
    /// `OORel` entries: `q,n,relationship,anchor_index,ref_0,ref_1,...`.
    pub oo_rel: Vec<String>,
    /// `OARel` entries: `q,n,relationship,object,arch`.
    pub oa_rel: Vec<String>,
}

/// The check of an answer's entries: the problems found, in words (none: the answer is
/// valid). The facade's parses the entries and runs the annotation validator.
pub type EntryChecker = dyn Fn(&AnnotatedDescription) -> Vec<String> + Send + Sync;

/// What the task asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Mode {
    /// The annotations of this description (`annotate_description`).
    Annotate { description: String },
    /// A new description with its annotations (`generate_annotated_description`), following the
    /// user's instructions.
    Generate { instruction: String },
}

/// One of the two annotation tasks (see the module docs): built with
/// [`AnnotationTask::annotate`] or [`AnnotationTask::generate`], then given examples and the
/// entry check.
///
/// ```
/// use sceneeval_vlm::tasks::{AnnotationLevel, AnnotationTask};
/// use sceneeval_vlm::{AnswerContent, Scripted, Session};
/// use serde_json::json;
///
/// let vlm = Scripted::queue("m", [AnswerContent::Json { value: json!({
///     "description": "A bedroom with a bed.", "difficulty": "easy",
///     "obj_count": ["eq,1,bed"], "obj_attr": [], "oo_rel": [], "oa_rel": []}) }]);
/// let task = AnnotationTask::annotate("A bedroom with a bed.", Some(AnnotationLevel::Easy));
/// let session = Session::new(&vlm);
/// let row = pollster::block_on(session.ask(&task)).unwrap().into_single().unwrap().into_result().unwrap();
/// assert_eq!(row.obj_count, ["eq,1,bed"]);
/// // The paper's system prompt, word for word.
/// assert!(vlm.requests()[0].system.starts_with("You are tasked to generate annotations for scenes"));
/// ```
#[derive(Clone)]
pub struct AnnotationTask {
    mode: Mode,
    difficulty: Option<AnnotationLevel>,
    examples: Vec<AnnotatedDescription>,
    checker: Option<Arc<EntryChecker>>,
    answers: Arc<Mutex<Vec<AnnotatedDescription>>>,
}

impl fmt::Debug for AnnotationTask {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("AnnotationTask")
            .field("mode", &self.mode)
            .field("difficulty", &self.difficulty)
            .field("examples", &self.examples.len())
            .field("checker", &self.checker.is_some())
            .finish()
    }
}

impl AnnotationTask {
    /// The annotations of `description`, of the given difficulty (`None`: the model chooses
    /// it by the paper's rules). The answer must copy the description; the validated answer
    /// holds `description` exactly as given.
    pub fn annotate(description: impl Into<String>, difficulty: Option<AnnotationLevel>) -> Self {
        AnnotationTask::new(
            Mode::Annotate {
                description: description.into(),
            },
            difficulty,
        )
    }

    /// A new scene description of `difficulty` with its annotations; `instruction` is the
    /// user's instructions of the paper's prompt (empty: none), for example the descriptions
    /// to move away from.
    pub fn generate(difficulty: AnnotationLevel, instruction: impl Into<String>) -> Self {
        AnnotationTask::new(
            Mode::Generate {
                instruction: instruction.into(),
            },
            Some(difficulty),
        )
    }

    fn new(mode: Mode, difficulty: Option<AnnotationLevel>) -> Self {
        AnnotationTask {
            mode,
            difficulty,
            examples: Vec::new(),
            checker: None,
            answers: Arc::default(),
        }
    }

    /// Shows `examples` in the prompt as in-context examples, in this order.
    pub fn with_examples(mut self, examples: Vec<AnnotatedDescription>) -> Self {
        self.examples = examples;
        self
    }

    /// Checks every answer's entries with `checker`: each problem it names makes the answer
    /// invalid (asked again once, with the problems quoted).
    pub fn with_checker(mut self, checker: Arc<EntryChecker>) -> Self {
        self.checker = Some(checker);
        self
    }

    /// The in-context examples.
    pub fn examples(&self) -> &[AnnotatedDescription] {
        &self.examples
    }

    /// Every answer the model gave to this task (and its clones) that followed the schema, in
    /// order, valid or not: the last one is the candidate to keep when the task stays
    /// unanswered.
    pub fn answers(&self) -> Vec<AnnotatedDescription> {
        self.answers
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone()
    }

    /// The in-context examples as the prompt shows them: one compact JSON object per line,
    /// `(none)` without examples.
    fn example_lines(&self) -> String {
        if self.examples.is_empty() {
            return "(none)".to_owned();
        }
        let lines: Vec<String> = self
            .examples
            .iter()
            .map(|e| serde_json::to_string(e).unwrap_or_default())
            .collect();
        lines.join("\n")
    }
}

/// Text compared with runs of whitespace made one space, trimmed.
fn collapse_spaces(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

impl Task for AnnotationTask {
    type Response = AnnotatedDescription;
    type Key = Single;
    type Item = AnnotatedDescription;

    fn kind(&self) -> TaskKind {
        match self.mode {
            Mode::Annotate { .. } => TaskKind::AnnotateDescription,
            Mode::Generate { .. } => TaskKind::GenerateAnnotatedDescription,
        }
    }

    fn system_template(&self) -> Template {
        Template::AnnotationSystem
    }

    fn placeholders(&self) -> Vec<(&'static str, String)> {
        let mut values = vec![
            ("NUM_EXAMPLES", self.examples.len().to_string()),
            ("IN_CONTEXT_EXAMPLES", self.example_lines()),
        ];
        match &self.mode {
            Mode::Annotate { description } => {
                let difficulty = self.difficulty.map_or_else(
                    || "not given; choose it by the difficulty levels above".to_owned(),
                    |d| d.name().to_owned(),
                );
                values.push(("DIFFICULTY", difficulty));
                values.push(("SCENE_DESCRIPTION", description.clone()));
            }
            Mode::Generate { instruction } => {
                let instruction = if instruction.trim().is_empty() {
                    "(none)".to_owned()
                } else {
                    instruction.clone()
                };
                values.push(("INSTRUCTION", instruction));
                let difficulty = self.difficulty.unwrap_or(AnnotationLevel::Easy);
                values.push(("DIFFICULTY", difficulty.name().to_owned()));
            }
        }
        values
    }

    fn keys(&self) -> Vec<Single> {
        vec![Single]
    }

    fn validate(&self, mut r: AnnotatedDescription, out: &mut Validation<Single, AnnotatedDescription>) {
        self.answers
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(r.clone());
        let mut problems = Vec::new();
        match (r.difficulty.parse::<AnnotationLevel>(), self.difficulty) {
            (Err(e), _) => problems.push(format!("difficulty: {e}")),
            (Ok(level), Some(wanted)) if level != wanted => problems.push(format!(
                "difficulty is {:?}, but a {wanted} description was asked for",
                level.name()
            )),
            (Ok(level), _) => r.difficulty = level.name().to_owned(),
        }
        match &self.mode {
            Mode::Annotate { description } => {
                if collapse_spaces(&r.description) != collapse_spaces(description) {
                    problems.push(
                        "description is not the given scene description; copy it word for word".to_owned(),
                    );
                }
                // The row keeps the user's text exactly.
                r.description.clone_from(description);
            }
            Mode::Generate { .. } => {
                if r.description.trim().is_empty() {
                    problems.push("description is empty".to_owned());
                } else if !r.description.is_ascii() {
                    problems.push(
                        "description has characters that are not ASCII; use only ASCII characters".to_owned(),
                    );
                }
                r.description = r.description.trim().to_owned();
            }
        }
        if let Some(check) = &self.checker {
            problems.extend(check(&r));
        }
        if problems.is_empty() {
            out.answer(Single, r);
        } else {
            for p in problems {
                out.problem(Single, p);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prompt::Prompts;
    use crate::schema::{check_strict, strict_schema_for};
    use crate::{AnswerContent, Scripted, Session, UnansweredKind};
    use serde_json::json;

    fn example() -> AnnotatedDescription {
        AnnotatedDescription {
            description: "A bedroom with a bed and a wardrobe.".into(),
            difficulty: "easy".into(),
            obj_count: vec!["eq,1,bed".into(), "eq,1,wardrobe".into()],
            obj_attr: vec![],
            oo_rel: vec![],
            oa_rel: vec![],
        }
    }

    #[test]
    fn the_schema_is_strict_with_the_six_fields() {
        let s = strict_schema_for::<AnnotatedDescription>("generate_annotated_description").unwrap();
        check_strict(&s.schema).unwrap();
        assert_eq!(
            s.schema["required"],
            json!([
                "description",
                "difficulty",
                "obj_count",
                "obj_attr",
                "oo_rel",
                "oa_rel"
            ])
        );
        assert_eq!(s.schema["additionalProperties"], false);
        assert_eq!(
            s.schema["properties"]["difficulty"]["enum"],
            json!(["easy", "medium", "hard"])
        );
        assert_eq!(s.schema["properties"]["oo_rel"]["items"]["type"], "string");
    }

    #[test]
    fn the_prompt_has_the_papers_system_prompt_and_the_examples() {
        let task = AnnotationTask::generate(AnnotationLevel::Medium, "Move away from: \"A den.\"")
            .with_examples(vec![example()]);
        let request = Session::new(Scripted::queue("m", [])).request(&task).unwrap();
        let paper = Prompts::builtin().text(Template::AnnotationSystem).to_owned();
        assert_eq!(request.system, paper);
        for line in [
            "You are tasked to generate annotations for scenes given a text description of the scene.",
            "    - Fix the anchor index to be 0 and instead re-arrange the obj_references as needed",
            "  - You do not need to specify something is on the floor as it is expected and adding one for each object is redundant",
        ] {
            assert!(paper.lines().any(|l| l == line), "{line}");
        }
        assert!(
            request
                .user_text
                .contains("Here are 1 manually annotated examples")
        );
        assert!(request.user_text.contains(
            r#"{"description":"A bedroom with a bed and a wardrobe.","difficulty":"easy","obj_count":["eq,1,bed","eq,1,wardrobe"],"obj_attr":[],"oo_rel":[],"oa_rel":[]}"#
        ));
        assert!(request.user_text.contains("Move away from: \"A den.\""));
        assert!(
            request
                .user_text
                .ends_with("generate a medium scene description and its annotations.")
        );
        assert_eq!(request.task, "generate_annotated_description");

        let task = AnnotationTask::annotate("A den with a sofa.", None);
        let request = Session::new(Scripted::queue("m", [])).request(&task).unwrap();
        assert!(
            request
                .user_text
                .contains("Here are 0 manually annotated examples")
        );
        assert!(request.user_text.contains("(none)"));
        assert!(request.user_text.contains("not given; choose it"));
        assert!(
            request.user_text.ends_with(
                "--- Begin scene description ---\nA den with a sofa.\n--- End scene description ---"
            )
        );
    }

    #[test]
    fn an_answer_with_problems_is_asked_again_then_unanswered_with_both() {
        let answer = json!({"description": "A bedroom with a bed.", "difficulty": "easy",
            "obj_count": [], "obj_attr": ["eq,1,red,bed"], "oo_rel": [], "oa_rel": []});
        let vlm = Scripted::queue(
            "m",
            [
                AnswerContent::Json {
                    value: answer.clone(),
                },
                AnswerContent::Json { value: answer },
            ],
        );
        let checker: Arc<EntryChecker> = Arc::new(|a: &AnnotatedDescription| {
            a.obj_attr
                .iter()
                .filter(|e| e.contains("red,bed"))
                .map(|e| format!("ObjAttr {e:?}: attribute and category swapped"))
                .collect()
        });
        let task = AnnotationTask::generate(AnnotationLevel::Easy, "").with_checker(checker);
        let session = Session::new(&vlm);
        let outcome = pollster::block_on(session.ask(&task))
            .unwrap()
            .into_single()
            .unwrap();
        let why = outcome.into_result().unwrap_err();
        assert_eq!(why.kind, UnansweredKind::Invalid);
        assert!(
            why.reason.contains("attribute and category swapped"),
            "{}",
            why.reason
        );
        assert!(
            vlm.requests()[1]
                .user_text
                .contains("- the answer: ObjAttr \"eq,1,red,bed\": attribute and category swapped")
        );
        // Both answers are kept; the last is the candidate.
        assert_eq!(task.answers().len(), 2);
        assert_eq!(task.answers()[1].obj_attr, ["eq,1,red,bed"]);
    }

    #[test]
    fn annotate_keeps_the_users_description_and_difficulty() {
        let task = AnnotationTask::annotate("A  den with\na sofa.", Some(AnnotationLevel::Easy));
        let mut v = Validation::new();
        let mut answer = example();
        answer.description = "A den with a sofa.".into();
        task.validate(answer.clone(), &mut v);
        assert_eq!(v.item(&Single).unwrap().description, "A  den with\na sofa.");

        let mut v = Validation::new();
        answer.description = "A den with a red sofa.".into();
        answer.difficulty = "hard".into();
        task.validate(answer, &mut v);
        let problems = v.problems_for(&Single);
        assert_eq!(problems.len(), 2, "{problems:?}");
        assert!(problems[0].contains("\"hard\"") && problems[1].contains("word for word"));
    }

    #[test]
    fn generated_descriptions_are_ascii_and_not_empty() {
        let task = AnnotationTask::generate(AnnotationLevel::Easy, "");
        for (text, problem) in [(" ", "empty"), ("A caf\u{e9} with a table.", "ASCII")] {
            let mut v = Validation::new();
            let mut answer = example();
            answer.description = text.into();
            task.validate(answer, &mut v);
            assert!(v.problems_for(&Single)[0].contains(problem));
        }
        assert_eq!("Hard".parse::<AnnotationLevel>(), Ok(AnnotationLevel::Hard));
        assert!("expert".parse::<AnnotationLevel>().is_err());
    }
}
