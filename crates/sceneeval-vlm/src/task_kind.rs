//! [`TaskKind`]: the one list of the tasks a model is asked.

use std::fmt;

use serde::Serialize;

/// The tasks of the reference (with their names in its `prompts.yaml`), the two tasks of the
/// paper's semi-automatic annotation generation, and the endpoint check: the one list of
/// tasks. Each has a prompt template of the same name
/// ([`crate::prompt::Template::Task`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum TaskKind {
    /// `obj_matching`: which annotated category an object belongs to (one call per object).
    ObjMatching,
    /// `obj_attribute`: which instances satisfy an attribute (one call per ObjAttr entry).
    ObjAttribute,
    /// `obj_support_type`: what an object rests on (one call per object).
    ObjSupportType,
    /// `obj_functional_sides`: which sides of each object must stay free (one call per scene).
    ObjFunctionalSides,
    /// `obj_relationship_mapping`: free-text object-object relations onto predicates (one call
    /// per scene).
    ObjRelationshipMapping,
    /// `arch_relationship_mapping`: free-text object-architecture relations onto predicates
    /// (one call per scene).
    ArchRelationshipMapping,
    /// `category_matching_for_semantic_color`: scene categories onto reference categories.
    CategoryMatchingForSemanticColor,
    /// `annotate_description`: the SceneEval-500 annotations of a given scene description (the
    /// paper's annotation generation, appendix "Semi-Automatic Data Generation").
    AnnotateDescription,
    /// `generate_annotated_description`: a new scene description of a difficulty level with its
    /// annotations (the paper's annotation generation).
    GenerateAnnotatedDescription,
    /// `endpoint_check`: the colour of a test image, to check that an endpoint works.
    EndpointCheck,
}

impl TaskKind {
    /// All tasks, in the reference's order, then the annotation tasks, the endpoint check last.
    pub const ALL: [TaskKind; 10] = [
        TaskKind::ObjMatching,
        TaskKind::ObjAttribute,
        TaskKind::ObjSupportType,
        TaskKind::ObjFunctionalSides,
        TaskKind::ObjRelationshipMapping,
        TaskKind::ArchRelationshipMapping,
        TaskKind::CategoryMatchingForSemanticColor,
        TaskKind::AnnotateDescription,
        TaskKind::GenerateAnnotatedDescription,
        TaskKind::EndpointCheck,
    ];

    /// The task's name: its name in the reference (the annotation tasks' are this crate's),
    /// used as the schema name, the template name
    /// and in logs.
    pub const fn name(self) -> &'static str {
        match self {
            TaskKind::ObjMatching => "obj_matching",
            TaskKind::ObjAttribute => "obj_attribute",
            TaskKind::ObjSupportType => "obj_support_type",
            TaskKind::ObjFunctionalSides => "obj_functional_sides",
            TaskKind::ObjRelationshipMapping => "obj_relationship_mapping",
            TaskKind::ArchRelationshipMapping => "arch_relationship_mapping",
            TaskKind::CategoryMatchingForSemanticColor => "category_matching_for_semantic_color",
            TaskKind::AnnotateDescription => "annotate_description",
            TaskKind::GenerateAnnotatedDescription => "generate_annotated_description",
            TaskKind::EndpointCheck => "endpoint_check",
        }
    }
}

impl fmt::Display for TaskKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
