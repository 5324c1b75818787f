//! The state of one query stream: declared objects and rooms, the prepared rooms written in
//! place, the relations already parsed, the asset library; and answering a query against them.

use std::borrow::Cow;
use std::collections::HashMap;
use std::sync::Arc;

use sceneeval_geom::{Obb, Real};
use sceneeval_io::AssetLibrary;
use sceneeval_relations::{ObjectGeom, Operands, Relation, RelationParams, Targets};
use sceneeval_scene::{Room, RoomSpec, SceneObject};

use super::{ObjectSpec, Operand, Query, RelateError, RoomCache, RoomOperand, error_path};

/// An object ready for the predicates: a solid box, or a mesh asset placed in the world.
#[derive(Debug, Clone)]
enum Object {
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

impl Declared {
    /// `an object` or `a room`; `None` for a failed declaration.
    fn kind(&self) -> Option<&'static str> {
        match self {
            Declared::Object(_) => Some("an object"),
            Declared::Room(_) => Some("a room"),
            Declared::Failed { .. } => None,
        }
    }
}

/// How many parsed relations a session keeps (23 relations, some with several arguments).
const RELATIONS_KEPT: usize = 48;

/// A relation's name, side and arch as written in a query.
#[derive(Debug, PartialEq)]
struct RelationText {
    name: String,
    side: Option<String>,
    arch: Option<String>,
}

/// The state of one stream of relation queries, and the one place such a query is answered:
/// `sceneeval relate` keeps one per run; the Python package keeps one for the process (its
/// prepared rooms).
///
/// - **Declared names**: [`Session::declare_object`] and [`Session::declare_room`] give a
///   name to an object or a room written in place; later queries name it instead of writing
///   it. A name keeps its kind (object or room) for the whole session; a failed declaration
///   makes the name unusable until it is declared again.
/// - **Prepared rooms**: a room written in place is prepared once per distinct JSON text and
///   kept in a [`RoomCache`] (the most recently used, up to its capacity); a declared room
///   stays as long as its name.
/// - **Answers**: [`Session::score`] resolves a [`Query`]'s operands (names borrowed, objects
///   written in place built, asset objects loaded through the session's `AssetLibrary`) and
///   scores it through the one dispatcher, [`sceneeval_relations::score`].
///
/// ```
/// use std::borrow::Cow;
/// use sceneeval_io::AssetLibrary;
/// use sceneeval_relate::{BoxSpec, ObjectSpec, Operand, Query, Session};
/// use sceneeval_relations::RelationParams;
///
/// let mut session = Session::new(RelationParams::default(), AssetLibrary::new(), 8);
/// let table = Operand::Inline(Box::new(ObjectSpec::Box(BoxSpec::from_yaw([0.0, 0.0, 0.5], [0.5; 3], 0.0))));
/// session.declare_object("table", &table, 1).unwrap();
/// let lamp = Operand::Inline(Box::new(ObjectSpec::Box(BoxSpec::from_yaw([0.0, 0.0, 1.1], [0.1; 3], 0.0))));
/// let by_name = Operand::Name(Cow::Borrowed("table"));
/// let query = Query { relation: "on_top", target: Some(&lamp), anchor: Some(&by_name), ..Query::default() };
/// // The lamp rests on the table's top face (z = 1.0): all of it is above, score 1.
/// assert_eq!(session.score(&query).unwrap(), 1.0);
/// let lost = Operand::Name(Cow::Borrowed("chair"));
/// let query = Query { relation: "near", target: Some(&lost), anchor: Some(&by_name), ..Query::default() };
/// assert_eq!(session.score(&query).unwrap_err().to_string(), "target: no object named \"chair\" has been declared");
/// ```
#[derive(Debug)]
pub struct Session {
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

impl Session {
    /// A session scoring with `params`, loading assets from `assets`, keeping at most
    /// `room_cache` rooms written in place prepared.
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

    /// The parameters queries are scored with.
    pub fn params(&self) -> &RelationParams {
        &self.params
    }

    /// Whether `score` means the relation holds.
    pub fn holds(&self, score: Real) -> bool {
        self.params.holds(score)
    }

    /// Rooms prepared so far (declared or written in place).
    pub fn rooms_built(&self) -> usize {
        self.rooms.built()
    }

    /// Declares `name` as `object` (written in place); `line` is the number the declaration is
    /// known by in later errors (`relate`: its line). On failure the name becomes unusable.
    ///
    /// # Errors
    /// [`RelateError::Declaration`] wrapping why the object is not one (an invalid box, an
    /// asset that cannot be loaded, a name instead of an object), or
    /// [`RelateError::Redeclared`] when `name` is a room.
    pub fn declare_object(
        &mut self,
        name: &str,
        object: &Operand<'_>,
        line: usize,
    ) -> Result<(), RelateError> {
        let result = match object {
            Operand::Inline(spec) => self.build(spec, name),
            Operand::Name(_) => Err(RelateError::DeclaredByName {
                operand: "object",
                kind: "an object",
            }),
        };
        self.settle(name, result.map(Declared::Object), line)
    }

    /// Declares `name` as `room` (written in place), as [`Session::declare_object`] does.
    ///
    /// # Errors
    /// As [`Session::declare_object`].
    pub fn declare_room(
        &mut self,
        name: &str,
        room: &RoomOperand<'_>,
        line: usize,
    ) -> Result<(), RelateError> {
        let result = match room {
            RoomOperand::Inline(text) => self.inline_room(text.get()),
            RoomOperand::Name(_) => Err(RelateError::DeclaredByName {
                operand: "room",
                kind: "a room",
            }),
        };
        self.settle(name, result.map(Declared::Room), line)
    }

    /// Records the result of declaring `name`: a name keeps its kind (object or room) for the
    /// whole session; declaring it again with the same kind replaces it.
    fn settle(
        &mut self,
        name: &str,
        result: Result<Declared, RelateError>,
        line: usize,
    ) -> Result<(), RelateError> {
        if let (Ok(new), Some(old)) = (&result, self.names.get(name))
            && let (Some(new_kind), Some(old_kind)) = (new.kind(), old.kind())
            && new_kind != old_kind
        {
            return Err(RelateError::Redeclared {
                name: name.to_owned(),
                old: old_kind,
                new: new_kind,
            });
        }
        match result {
            Ok(declared) => {
                self.names.insert(name.to_owned(), declared);
                Ok(())
            }
            Err(e) => {
                self.names.insert(name.to_owned(), Declared::Failed { line });
                Err(RelateError::Declaration {
                    name: name.to_owned(),
                    source: Box::new(e),
                })
            }
        }
    }

    /// The object written as `spec`; `what` names it in errors.
    fn build(&self, spec: &ObjectSpec, what: &str) -> Result<Object, RelateError> {
        match spec {
            ObjectSpec::Box(b) => Ok(Object::Box(b.to_obb(what)?)),
            ObjectSpec::Asset(a) => {
                let pose = a.pose(what)?;
                let scale = a.scale(what)?;
                self.assets
                    .object(what, &a.asset, pose, scale)
                    .map(|o| Object::Mesh(Arc::new(o)))
                    .map_err(|source| RelateError::Asset {
                        what: what.to_owned(),
                        source: Box::new(source),
                    })
            }
        }
    }

    /// The object an operand stands for: built when written in place, borrowed when declared.
    fn object(&self, operand: &Operand<'_>, what: &str) -> Result<Cow<'_, Object>, RelateError> {
        match operand {
            Operand::Inline(spec) => self.build(spec, what).map(Cow::Owned),
            Operand::Name(name) => match self.names.get(name.as_ref()) {
                Some(Declared::Object(object)) => Ok(Cow::Borrowed(object)),
                Some(Declared::Room(_)) => Err(RelateError::OtherKind {
                    what: what.to_owned(),
                    name: name.to_string(),
                    is: "a room",
                    expected: "an object",
                }),
                Some(Declared::Failed { line }) => Err(RelateError::Unusable {
                    what: what.to_owned(),
                    name: name.to_string(),
                    line: *line,
                }),
                None => Err(RelateError::Undeclared {
                    what: what.to_owned(),
                    kind: "object",
                    name: name.to_string(),
                }),
            },
        }
    }

    /// The room kept under `key`, else the room `build` makes, kept under `key` with the
    /// session's rooms written in place (a failure is not kept). Front ends that read rooms
    /// their own way (the Python package, from dicts) keep them here by their JSON text.
    ///
    /// # Errors
    /// The error of `build`.
    pub fn room_with<E>(
        &mut self,
        key: &str,
        build: impl FnOnce() -> Result<Room, E>,
    ) -> Result<Arc<Room>, E> {
        self.rooms.get_or_build(key, build)
    }

    /// The room written in place as `text` (a JSON object), prepared on first use and kept
    /// under its text.
    fn inline_room(&mut self, text: &str) -> Result<Arc<Room>, RelateError> {
        self.rooms.get_or_build(text, || {
            let spec: RoomSpec = serde_json::from_str(text).map_err(|source| RelateError::InvalidRoom {
                path: error_path::<RoomSpec>(text).unwrap_or_default(),
                source,
            })?;
            Ok(spec.build()?)
        })
    }

    /// The declared room a name stands for (borrowed: no reference count is touched per
    /// query).
    fn declared_room(&self, name: &str) -> Result<&Room, RelateError> {
        match self.names.get(name) {
            Some(Declared::Room(room)) => Ok(room),
            Some(Declared::Object(_)) => Err(RelateError::OtherKind {
                what: "room".to_owned(),
                name: name.to_owned(),
                is: "an object",
                expected: "a room",
            }),
            Some(Declared::Failed { line }) => Err(RelateError::Unusable {
                what: "room".to_owned(),
                name: name.to_owned(),
                line: *line,
            }),
            None => Err(RelateError::Undeclared {
                what: "room".to_owned(),
                kind: "room",
                name: name.to_owned(),
            }),
        }
    }

    /// The relation named by `name` with its `side` or `arch` argument (see
    /// [`Relation::from_fields`]), parsed once per distinct spelling.
    ///
    /// # Errors
    /// The error of [`Relation::from_fields`].
    #[inline]
    pub fn relation(
        &mut self,
        name: &str,
        side: Option<&str>,
        arch: Option<&str>,
    ) -> Result<Relation, RelateError> {
        if let Some((_, relation)) = self
            .relations
            .iter()
            .find(|(t, _)| t.name == name && t.side.as_deref() == side && t.arch.as_deref() == arch)
        {
            return Ok(*relation);
        }
        let relation = Relation::from_fields(name, side, arch)?;
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

    /// The score of `query`: its relation, then its room (prepared on first use when written
    /// in place), then its objects, scored with the session's parameters.
    ///
    /// # Errors
    /// The first of: the relation's error, the room's (not a room, an undeclared or unusable
    /// name), an object's (an invalid box, an asset that cannot be loaded, an undeclared or
    /// unusable name), and the dispatcher's (operands the relation's kind does not use or
    /// lacks, too many targets).
    pub fn score(&mut self, query: &Query<'_>) -> Result<Real, RelateError> {
        let relation = self.relation(query.relation, query.side, query.arch)?;
        let inline_room = match query.room {
            Some(RoomOperand::Inline(text)) => Some(self.inline_room(text.get())?),
            _ => None,
        };
        // The rest only reads the session: declared rooms and objects are borrowed, not copied.
        let session = &*self;
        let room = match query.room {
            Some(RoomOperand::Name(name)) => Some(session.declared_room(name)?),
            _ => inline_room.as_deref(),
        };
        let target = query.target.map(|o| session.object(o, "target")).transpose()?;
        let anchor = query.anchor.map(|o| session.object(o, "anchor")).transpose()?;
        let targets = query
            .targets
            .map(|ts| {
                ts.iter()
                    .enumerate()
                    .map(|(i, o)| session.object(o, &format!("targets[{i}]")))
                    .collect::<Result<Vec<_>, _>>()
            })
            .transpose()?;
        let views: Option<Vec<ObjectGeom<'_>>> =
            targets.as_ref().map(|ts| ts.iter().map(|t| t.geom()).collect());
        let operands = Operands {
            target: target.as_ref().map(|t| t.geom()),
            anchor: anchor.as_ref().map(|a| a.geom()),
            targets: views.as_deref().map(Targets::Objects),
            rooms: room.map(std::slice::from_ref),
        };
        Ok(sceneeval_relations::score(relation, &operands, &self.params)?)
    }
}
