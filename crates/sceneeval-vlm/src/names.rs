//! Schema-only name lists: the wire fields are strings (so an unexpected value gets a clear
//! validation message rather than a parse error), and their schemas carry these lists as
//! `enum`s so that schema-constrained decoding only produces valid names. Each list is taken
//! from the vocabulary's own crate, so there is one list per concept; a task's own list
//! (the endpoint check's colours, the architecture element types in the prompt's order) is
//! declared with [`name_list!`] beside its task.

use sceneeval_geom::Side;
use sceneeval_relations::{LongShort, OBJECT_ARCH_NAMES, OBJECT_OBJECT_NAMES};
use sceneeval_scene::SupportType;

/// Declares a unit type whose JSON Schema is a string `enum` of the given names.
macro_rules! name_list {
    ($(#[$doc:meta])* $name:ident => $names:expr) => {
        $(#[$doc])*
        pub(crate) struct $name;

        impl ::schemars::JsonSchema for $name {
            fn schema_name() -> ::std::borrow::Cow<'static, str> {
                stringify!($name).into()
            }

            fn inline_schema() -> bool {
                true
            }

            fn json_schema(_: &mut ::schemars::SchemaGenerator) -> ::schemars::Schema {
                let names: Vec<&str> = $names;
                ::schemars::json_schema!({"type": "string", "enum": names})
            }
        }
    };
}
pub(crate) use name_list;

name_list!(
    /// `support_type` values.
    SupportTypeName => SupportType::ALL.iter().map(|t| t.name()).collect()
);
name_list!(
    /// `functional_sides` values: the horizontal sides.
    HorizontalSideName => Side::HORIZONTAL.iter().map(|s| s.name()).collect()
);
name_list!(
    /// `relationship_types` values: the 13 object-object predicates.
    ObjectRelationName => OBJECT_OBJECT_NAMES.to_vec()
);
name_list!(
    /// `sides` values: a side of `side_of`/`side_region`, or `long`/`short`.
    SideArgumentName => Side::ALL
        .iter()
        .map(|s| s.name())
        .chain([LongShort::Long.name(), LongShort::Short.name()])
        .collect()
);
name_list!(
    /// `relationship_type` values: the 10 object-architecture predicates.
    ArchRelationName => OBJECT_ARCH_NAMES.to_vec()
);
