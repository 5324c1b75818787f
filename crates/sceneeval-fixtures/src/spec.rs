//! Scenes as plain data: rooms, object placements in object-frame terms, and the intended
//! flaws. [`crate::build`] turns a [`SceneSpec`] into a `Scene`; [`crate::expected`] derives
//! the expected answers from the spec and the built scene.
//!
//! A placement gives the world position of the object's **bottom centre** (the origin of every
//! fixture asset, see [`crate::assets`]) and its yaw about +z (yaw 0: front = world -y;
//! yaw 90 degrees: front = +x). Scale is per object-frame axis (width x, depth y, height z)
//! and scales about the bottom centre.

use sceneeval_scene::{RoomBuilder, SupportType};

/// What an object is made of.
#[derive(Debug, Clone, PartialEq)]
pub enum Model {
    /// A fixture asset, by asset id (model id `fixture.<id>`).
    Asset(&'static str),
    /// A plain box without any asset (a sceneState `box` entry).
    Box {
        /// Full size in the object frame: width x, depth y, height z (metres).
        size: [f64; 3],
        /// Category.
        category: &'static str,
        /// Description.
        description: &'static str,
    },
}

/// What holds an object up, by construction.
#[derive(Debug, Clone, PartialEq)]
pub enum Support {
    /// Stands on its room's floor.
    Floor,
    /// Stands on top of another object (by key).
    On(String),
    /// Hangs on a wall (by wall id), its back touching the wall's inner face.
    Wall(String),
    /// Hangs from the ceiling, its top touching it.
    Ceiling,
    /// Touches nothing below it (a deliberate flaw).
    Nothing,
}

impl Support {
    /// The support type this support gives (written as the scene object's `supportType` and in
    /// `expected.json`; an unsupported object keeps the type it should have had).
    pub fn support_type(&self, intended: SupportType) -> SupportType {
        match self {
            Support::Floor => SupportType::Ground,
            Support::On(_) => SupportType::Object,
            Support::Wall(_) => SupportType::Wall,
            Support::Ceiling => SupportType::Ceiling,
            Support::Nothing => intended,
        }
    }
}

/// One object of a scene spec.
#[derive(Debug, Clone, PartialEq)]
pub struct Placement {
    /// Short unique name within the scene (e.g. `nightstand_left`), used by flaws and
    /// supports; the object id in the file is `idx<index>_<modelId>`.
    pub key: String,
    /// Asset or box.
    pub model: Model,
    /// World position of the bottom centre (metres).
    pub position: [f64; 3],
    /// Rotation about +z in degrees (0: front = world -y).
    pub yaw_deg: f64,
    /// Scale along the object-frame axes (width, depth, height).
    pub scale: [f64; 3],
    /// What holds it up.
    pub support: Support,
    /// For [`Support::Nothing`]: the support type it should have had.
    pub intended_support: SupportType,
    /// Whether its support holds it: false when it touches its support but its centre of
    /// mass is not over the contacts (it would tip over).
    pub held: bool,
}

impl Placement {
    /// An asset standing on the floor at `position` (bottom centre) turned by `yaw_deg`.
    pub fn asset(key: &str, asset: &'static str, position: [f64; 3], yaw_deg: f64) -> Placement {
        Placement {
            key: key.to_owned(),
            model: Model::Asset(asset),
            position,
            yaw_deg,
            scale: [1.0; 3],
            support: Support::Floor,
            intended_support: SupportType::Ground,
            held: true,
        }
    }

    /// A box object standing on the floor at `position` (bottom centre).
    pub fn boxed(
        key: &str,
        category: &'static str,
        description: &'static str,
        size: [f64; 3],
        position: [f64; 3],
        yaw_deg: f64,
    ) -> Placement {
        Placement {
            key: key.to_owned(),
            model: Model::Box {
                size,
                category,
                description,
            },
            position,
            yaw_deg,
            scale: [1.0; 3],
            support: Support::Floor,
            intended_support: SupportType::Ground,
            held: true,
        }
    }

    /// Marks the object as standing on the object `key`.
    pub fn on(mut self, key: &str) -> Placement {
        self.support = Support::On(key.to_owned());
        self
    }

    /// Marks the object as hanging on the wall `wall_id`.
    pub fn on_wall(mut self, wall_id: &str) -> Placement {
        self.support = Support::Wall(wall_id.to_owned());
        self
    }

    /// Marks the object as hanging from the ceiling.
    pub fn from_ceiling(mut self) -> Placement {
        self.support = Support::Ceiling;
        self
    }

    /// Marks the object as supported by nothing although it should stand on `intended`
    /// (ground or object).
    pub fn unsupported(mut self, intended: SupportType) -> Placement {
        self.support = Support::Nothing;
        self.intended_support = intended;
        self
    }

    /// Marks the object as touching its support without being held by it: its centre of mass
    /// is not over its contacts.
    pub fn tipping(mut self) -> Placement {
        self.held = false;
        self
    }

    /// Scales the object along its object-frame axes (width, depth, height).
    pub fn scaled(mut self, scale: [f64; 3]) -> Placement {
        self.scale = scale;
        self
    }

    /// The model id written to the scene file, if any.
    pub fn model_id(&self) -> Option<String> {
        match &self.model {
            Model::Asset(id) => Some(format!("{}.{id}", crate::ASSET_PREFIX)),
            Model::Box { .. } => None,
        }
    }
}

/// A deliberate flaw of a scene, in terms of placement keys.
#[derive(Debug, Clone, PartialEq)]
pub enum Flaw {
    /// Two objects interpenetrate.
    Collision {
        /// First object key.
        a: String,
        /// Second object key.
        b: String,
    },
    /// An object hovers above the floor.
    Floating {
        /// Object key.
        object: String,
    },
    /// An object sticks out through a wall.
    OutOfBounds {
        /// Object key.
        object: String,
        /// The wall it crosses.
        wall: String,
    },
    /// A door is blocked by an object standing in front of it on the room side.
    BlockedDoor {
        /// The door's opening id.
        door: String,
        /// Object key.
        by: String,
    },
    /// An object lies entirely inside another's volume.
    Inside {
        /// The enclosed object.
        inner: String,
        /// The enclosing object.
        outer: String,
    },
}

/// One fixture scene as data.
#[derive(Debug, Clone)]
pub struct SceneSpec {
    /// Scene number `N` (file `scene_<N>.json`, annotation ID).
    pub number: u32,
    /// Short title (e.g. `tidy bedroom`).
    pub title: &'static str,
    /// One sentence describing the scene, as an annotation description would.
    pub description: &'static str,
    /// Rooms.
    pub rooms: Vec<RoomBuilder>,
    /// Objects, in file order.
    pub objects: Vec<Placement>,
    /// Deliberate flaws (empty for a clean scene).
    pub flaws: Vec<Flaw>,
    /// Whether the free floor is one connected region from which every door can be reached
    /// (`None`: no claim).
    pub navigable: Option<bool>,
}

impl SceneSpec {
    /// The placement with this key.
    pub fn placement(&self, key: &str) -> Option<&Placement> {
        self.objects.iter().find(|p| p.key == key)
    }

    /// The index (file order) of the placement with this key.
    pub fn index_of(&self, key: &str) -> Option<usize> {
        self.objects.iter().position(|p| p.key == key)
    }

    /// The scene's name, `scene_<N>`.
    pub fn name(&self) -> String {
        format!("scene_{}", self.number)
    }
}
