//! The state of one `relate` stream: declared objects and rooms, the cache of prepared
//! rooms (`sceneeval::relations::spec::RoomCache`, shared with the Python package), the asset
//! library, and scoring one parsed line against them.

use std::borrow::Cow;
use std::collections::HashMap;
use std::sync::Arc;

use sceneeval::geom::{Obb, Real};
use sceneeval::io::AssetLibrary;
use sceneeval::relations::spec::{
    GeomOperands, ObjectSpec, RoomCache, RoomSpec, relation_from_spec, score_geoms,
};
use sceneeval::relations::{ObjectGeom, Relation, RelationParams};
use sceneeval::scene::{Room, SceneObject};

use super::line::{Line, Operand, RoomOperand};

/// An object ready for the predicates: a solid box, or a mesh asset placed in the world.
#[derive(Debug, Clone)]
pub(crate) enum Object {
    /// A solid box.
    Box(Obb),
    /// A mesh asset (`Arc`: declared objects are shared without copying).
    Mesh(Arc<SceneObject>),
}

impl Object {
    fn geom(&self) -> ObjectGeom<'_> {
        match self {
            Object::Box(obb) => ObjectGeom::from_box(obb),
            Object::Mesh(object) => ObjectGeom::from_object(object),
        }
    }
}

/// What a declared name stands for.
#[derive(Debug)]
enum Declared {
    Object(Object),
    Room(Arc<Room>),
    /// The latest declaration of the name, on this line, failed: the name is unusable until
    /// declared again (an earlier declaration is not silently used instead).
    Failed {
        line: usize,
    },
}

/// What a line produced.
#[derive(Debug, PartialEq)]
pub(crate) enum Outcome {
    /// A query's score.
    Score(Real),
    /// A declaration's name.
    Declared(String),
}

/// One stream's state.
pub(crate) struct Session {
    params: RelationParams,
    assets: AssetLibrary,
    /// Declared names (looked up twice per query: foldhash, randomly seeded, instead of
    /// SipHash, which cost about a twentieth of a query).
    names: HashMap<String, Declared, foldhash::fast::RandomState>,
    rooms: RoomCache,
    /// Relations parsed recently, with their name, side and arch as written (at most
    /// [`RELATIONS_KEPT`], replaced in turn): streams repeat a few relations, and parsing one
    /// lower-cases and matches names.
    relations: Vec<(RelationText, Relation)>,
    /// The next entry of `relations` to replace once it is full.
    relations_next: usize,
}

/// How many parsed relations a session keeps (23 relations, some with several arguments).
const RELATIONS_KEPT: usize = 48;

/// A relation's name, side and arch as written on a line.
#[derive(Debug, PartialEq)]
struct RelationText {
    name: String,
    side: Option<String>,
    arch: Option<String>,
}

impl Session {
    /// A session scoring with `params`, loading assets from `assets`, keeping at most
    /// `room_cache` inline rooms prepared.
    pub fn new(params: RelationParams, assets: AssetLibrary, room_cache: usize) -> Self {
        Session {
            params,
            assets,
            names: HashMap::default(),
            rooms: RoomCache::new(room_cache),
            relations: Vec::new(),
            relations_next: 0,
        }
    }

    /// Whether `score` means the relation holds.
    pub fn holds(&self, score: Real) -> bool {
        self.params.holds(score)
    }

    /// Rooms prepared so far (declared or inline).
    #[cfg(test)]
    pub fn rooms_built(&self) -> usize {
        self.rooms.built()
    }

    /// Declares `name` as `object`; on failure the name becomes unusable (see
    /// [`Declared::Failed`]).
    pub fn declare_object(
        &mut self,
        name: &str,
        object: &Operand<'_>,
        line: usize,
    ) -> Result<Outcome, String> {
        let result = match object {
            Operand::Inline(spec) => self.build(spec, name),
            Operand::Name(_) => {
                Err("a declaration's \"object\" must be an object written in place, not a name".to_owned())
            }
        };
        self.settle(name, result.map(Declared::Object), line)
    }

    /// Declares `name` as `room`.
    pub fn declare_room(
        &mut self,
        name: &str,
        room: &RoomOperand<'_>,
        line: usize,
    ) -> Result<Outcome, String> {
        let result = match room {
            RoomOperand::Inline(text) => self.inline_room(text.get()),
            RoomOperand::Name(_) => {
                Err("a declaration's \"room\" must be a room written in place, not a name".to_owned())
            }
        };
        self.settle(name, result.map(Declared::Room), line)
    }

    /// Records the result of declaring `name`: a name keeps its kind (object or room) for the
    /// whole stream; declaring it again with the same kind replaces it.
    fn settle(
        &mut self,
        name: &str,
        result: Result<Declared, String>,
        line: usize,
    ) -> Result<Outcome, String> {
        let kind = |d: &Declared| match d {
            Declared::Object(_) => Some("an object"),
            Declared::Room(_) => Some("a room"),
            Declared::Failed { .. } => None,
        };
        if let (Ok(new), Some(old)) = (&result, self.names.get(name))
            && let (Some(new_kind), Some(old_kind)) = (kind(new), kind(old))
            && new_kind != old_kind
        {
            return Err(format!(
                "{name:?} is declared as {old_kind}; a name cannot be declared again as {new_kind}"
            ));
        }
        match result {
            Ok(declared) => {
                self.names.insert(name.to_owned(), declared);
                Ok(Outcome::Declared(name.to_owned()))
            }
            Err(e) => {
                self.names.insert(name.to_owned(), Declared::Failed { line });
                Err(format!("declaration of {name:?}: {e}"))
            }
        }
    }

    /// The object written as `spec`; `what` names it in errors.
    fn build(&self, spec: &ObjectSpec, what: &str) -> Result<Object, String> {
        match spec {
            ObjectSpec::Box(b) => b.to_obb(what).map(Object::Box).map_err(|e| e.to_string()),
            ObjectSpec::Asset(a) => {
                let pose = a.pose(what).map_err(|e| e.to_string())?;
                let scale = a.scale(what).map_err(|e| e.to_string())?;
                self.assets
                    .object(what, &a.asset, pose, scale)
                    .map(|o| Object::Mesh(Arc::new(o)))
                    .map_err(|e| format!("{what}: {}", with_causes(&e)))
            }
        }
    }

    /// The object an operand stands for: built when written in place, borrowed when declared.
    fn object(&self, operand: &Operand<'_>, what: &str) -> Result<Cow<'_, Object>, String> {
        match operand {
            Operand::Inline(spec) => self.build(spec, what).map(Cow::Owned),
            Operand::Name(name) => match self.names.get(name.as_ref()) {
                Some(Declared::Object(object)) => Ok(Cow::Borrowed(object)),
                Some(Declared::Room(_)) => Err(format!("{what}: {name:?} is a room, not an object")),
                Some(Declared::Failed { line }) => Err(format!(
                    "{what}: {name:?} is unusable: its declaration on line {line} failed"
                )),
                None => Err(format!("{what}: no object named {name:?} has been declared")),
            },
        }
    }

    /// The room written in place as `text` (a JSON object), prepared on first use and kept
    /// in the session's [`RoomCache`] under its text.
    fn inline_room(&mut self, text: &str) -> Result<Arc<Room>, String> {
        self.rooms.get_or_build(text, || {
            let spec: RoomSpec = serde_json::from_str(text).map_err(|e| format!("invalid room: {e}"))?;
            spec.build().map_err(|e| e.to_string())
        })
    }

    /// The declared room a name stands for (borrowed: no reference count is touched per
    /// query).
    fn declared_room(&self, name: &str) -> Result<&Room, String> {
        match self.names.get(name) {
            Some(Declared::Room(room)) => Ok(room),
            Some(Declared::Object(_)) => Err(format!("room: {name:?} is an object, not a room")),
            Some(Declared::Failed { line }) => Err(format!(
                "room: {name:?} is unusable: its declaration on line {line} failed"
            )),
            None => Err(format!("room: no room named {name:?} has been declared")),
        }
    }

    /// The relation of a query line.
    fn relation(&mut self, line: &Line<'_>) -> Result<Relation, String> {
        let name = line.relation.as_ref().map_or("", |t| t.0.as_ref());
        let side = line.side.as_ref().map(|t| t.0.as_ref());
        let arch = line.arch.as_ref().map(|t| t.0.as_ref());
        if let Some((_, relation)) = self
            .relations
            .iter()
            .find(|(t, _)| t.name == name && t.side.as_deref() == side && t.arch.as_deref() == arch)
        {
            return Ok(*relation);
        }
        let relation = relation_from_spec(name, side, arch).map_err(|e| e.to_string())?;
        let text = RelationText {
            name: name.to_owned(),
            side: side.map(str::to_owned),
            arch: arch.map(str::to_owned),
        };
        if self.relations.len() < RELATIONS_KEPT {
            self.relations.push((text, relation));
        } else {
            self.relations[self.relations_next] = (text, relation);
            self.relations_next = (self.relations_next + 1) % RELATIONS_KEPT;
        }
        Ok(relation)
    }

    /// The score of a query line.
    pub fn score(&mut self, line: &Line<'_>) -> Result<Outcome, String> {
        let relation = self.relation(line)?;
        let inline_room = match &line.room {
            Some(RoomOperand::Inline(text)) => Some(self.inline_room(text.get())?),
            _ => None,
        };
        // The rest only reads the session: declared rooms and objects are borrowed, not copied.
        let session = &*self;
        let room = match &line.room {
            Some(RoomOperand::Name(name)) => Some(session.declared_room(name)?),
            _ => inline_room.as_deref(),
        };
        let target = line
            .target
            .as_ref()
            .map(|o| session.object(o, "target"))
            .transpose()?;
        let anchor = line
            .anchor
            .as_ref()
            .map(|o| session.object(o, "anchor"))
            .transpose()?;
        let targets = line
            .targets
            .as_ref()
            .map(|ts| {
                ts.iter()
                    .enumerate()
                    .map(|(i, o)| session.object(o, &format!("targets[{i}]")))
                    .collect::<Result<Vec<_>, String>>()
            })
            .transpose()?;
        let views: Option<Vec<ObjectGeom<'_>>> =
            targets.as_ref().map(|ts| ts.iter().map(|t| t.geom()).collect());
        score_geoms(
            relation,
            &GeomOperands {
                target: target.as_ref().map(|t| t.geom()),
                anchor: anchor.as_ref().map(|a| a.geom()),
                targets: views.as_deref(),
                room,
            },
            &self.params,
        )
        .map(Outcome::Score)
        .map_err(|e| e.to_string())
    }
}

/// An error and its causes, joined by `: `.
fn with_causes(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        text.push_str(": ");
        text.push_str(&cause.to_string());
        source = cause.source();
    }
    text
}
