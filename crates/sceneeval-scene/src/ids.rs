use std::borrow::Borrow;
use std::fmt;

macro_rules! string_id {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
        #[cfg_attr(feature = "serde", serde(transparent))]
        pub struct $name(String);

        impl $name {
            /// The id from any string.
            pub fn new(id: impl Into<String>) -> Self {
                $name(id.into())
            }

            /// The id as a string slice.
            #[inline]
            pub fn as_str(&self) -> &str {
                &self.0
            }

            /// The id as an owned string.
            #[inline]
            pub fn into_string(self) -> String {
                self.0
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(&self.0)
            }
        }

        impl From<&str> for $name {
            fn from(s: &str) -> Self {
                $name(s.to_owned())
            }
        }

        impl From<&String> for $name {
            fn from(s: &String) -> Self {
                $name(s.clone())
            }
        }

        impl From<String> for $name {
            fn from(s: String) -> Self {
                $name(s)
            }
        }

        impl Borrow<str> for $name {
            fn borrow(&self) -> &str {
                &self.0
            }
        }

        impl AsRef<str> for $name {
            fn as_ref(&self) -> &str {
                &self.0
            }
        }
    };
}

string_id!(
    /// A scene object's stable id. Scenes read from sceneState files use the reference's
    /// naming, `idx<index>_<modelId>`, so results can be compared with the reference's outputs.
    ObjectId
);

string_id!(
    /// A room's id (the sceneState `roomId`).
    RoomId
);

string_id!(
    /// An object's category as the scene states it (e.g. `nightstand`, or a synset such as
    /// `bed.n.01`): a type of its own, so that an object id and a category can never be
    /// passed in each other's place.
    Category
);

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    #[test]
    fn ids_behave_like_strings() {
        let id = ObjectId::from("idx0_3dfModel.abc");
        assert_eq!(id.as_str(), "idx0_3dfModel.abc");
        assert_eq!(id.to_string(), "idx0_3dfModel.abc");
        let mut map = HashMap::new();
        map.insert(id.clone(), 1);
        assert_eq!(
            map.get("idx0_3dfModel.abc"),
            Some(&1),
            "lookup by &str through Borrow"
        );
        assert_eq!(RoomId::new(String::from("r")), RoomId::from("r"));
    }
}
