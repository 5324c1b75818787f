//! Pairwise and door checks for loops that move objects ([`crate::LayoutChecks`]): whether
//! two objects collide (with the penetration depth and its gradient for boxes) and whether an
//! object blocks a door's clearance box. Allocation free.

use sceneeval_geom::{Obb, Real};
use sceneeval_relations::grad::{BoxGrad, box_penetration};
use sceneeval_relations::{ObjectGeom, object_distance};
use sceneeval_scene::SceneObject;

/// How two objects meet, as [`crate::LayoutChecks::contact`] sees them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Whether they collide: for two box objects, whether they interpenetrate by more than the
    /// contact tolerance; with a mesh involved, whether their solids meet (surfaces touching
    /// or crossing, or one inside the other).
    pub colliding: bool,
    /// The penetration depth in metres, the length of the shortest translation separating
    /// them: exact for two box objects (0 when apart); `None` with a mesh involved and the
    /// solids meeting (the collision metric's certified depth search allocates; use
    /// [`crate::collision`] for it), `Some(0.0)` when they are apart.
    pub depth: Option<Real>,
    /// The depth's derivatives with respect to each object's box parameters (see
    /// `sceneeval_relations::grad`), for two box objects that interpenetrate; `None`
    /// otherwise.
    pub gradient: Option<(BoxGrad, BoxGrad)>,
}

impl Contact {
    const APART: Contact = Contact {
        colliding: false,
        depth: Some(0.0),
        gradient: None,
    };
}

/// The contact of two scene objects, `tolerance` the contact tolerance for boxes.
pub(crate) fn contact(a: &SceneObject, b: &SceneObject, tolerance: Real) -> Contact {
    if a.box_half_extents().is_some() && b.box_half_extents().is_some() {
        return match box_penetration(a.obb(), b.obb()) {
            None => Contact::APART,
            Some(p) => Contact {
                colliding: p.depth > tolerance,
                depth: Some(p.depth),
                gradient: Some((p.a, p.b)),
            },
        };
    }
    // Boxes apart: the solids inside them are apart.
    if box_penetration(a.obb(), b.obb()).is_none() {
        return Contact::APART;
    }
    let meet = object_distance(&ObjectGeom::from_object(a), &ObjectGeom::from_object(b)) == 0.0;
    Contact {
        colliding: meet,
        depth: if meet { None } else { Some(0.0) },
        gradient: None,
    }
}

/// Whether `object`'s surface enters the clearance box `door` (shrunk as the opening-clearance
/// metric shrinks it): the exact distance from its mesh to the box is 0.
pub(crate) fn enters(object: &SceneObject, door: &Obb) -> bool {
    object.world_aabb().intersects(&door.aabb()) && object.mesh().distance_to_obb(object.pose(), door) == 0.0
}
