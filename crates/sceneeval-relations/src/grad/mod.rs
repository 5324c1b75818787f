//! Gradients of the 23 scores with respect to the objects' box parameters, for optimisers.
//!
//! Every kernel here returns the score **bit for bit** as the kernel of the same name in the
//! crate root or in [`crate::arch`] computes it, together with its derivatives with respect to
//! the parameters of the target and of the anchor ([`BoxGrad`]): the box's centre `(x, y, z)`,
//! its half extents `(x, y, z)` and its yaw. Dispatch by [`Relation`](crate::Relation) is in
//! [`pair`], [`surround`] and [`arch_rooms`].
//!
//! # Parameters
//! - **Centre**: a translation of the object in world coordinates (metres).
//! - **Half extents**: the box's half sizes along its own axes (metres). For an object with a
//!   mesh they are not free (the box is the mesh's bounds): the derivative is reported as 0.
//! - **Yaw**: a rotation about the world vertical through the object's origin (radians,
//!   counter-clockwise seen from above): the box's centre for a box object, the pose's
//!   translation for an object with a mesh (so that, with the centre, the gradient is the one
//!   with respect to the pose `(x, y, z, yaw)`). For a tilted box this is still a turn about
//!   the world vertical, applied on the left of its rotation.
//! - Object-architecture relations differentiate with respect to the object only: the room is
//!   fixed.
//!
//! The order of [`BoxGrad::to_array`] is `(cx, cy, cz, hx, hy, hz, yaw)`.
//!
//! # Exact where differentiable, and what happens at kinks
//! The derivatives are analytic, not finite differences: the volume fractions from the areas
//! and first moments of the clipped polyhedron's faces (Reynolds' transport theorem), the
//! distances from the closest points of the two solids (the envelope theorem), `face_to` from
//! the areas, centroids and edges of the clipped cross-section pieces, the centroid-based
//! scores by the chain rule. Each is the derivative of the very function the score computes
//! wherever that function is differentiable.
//!
//! Scores are piecewise smooth. Where two pieces meet (a *kink*), each kernel returns the
//! derivative of the piece its score computation takes: a one-sided derivative, never an
//! average, except where a row below says 0. Where the score is flat (a volume fraction of 0
//! or 1 with the box clear of every plane, a distance inside a band's range, overlapping
//! objects whose distance is 0) the derivative is 0. Where the score jumps (it is not
//! continuous there) no derivative exists and the one of the side computed is returned. Per
//! predicate:
//!
//! | predicate | kinks: one-sided there (the branch the score takes) | jumps | zero gradient |
//! |---|---|---|---|
//! | volume fractions (`inside_of`, `outside_of`, `side_of`, `side_region`, `long_short_side_of`, `on_top`, `inside_room`) | a corner or edge of the target box crossing a region plane; a half extent at the flat-box floor (`min_half_extent_m`: the derivative from above); `long_short_side_of`: the two sides' fractions equal (the first of the pair: the right or back side) | `long_short_side_of`: the anchor's width and depth changing order, or becoming equal (score 0) | wholly inside or outside the region; a half extent below the flat-box floor |
//! | `middle_of` | none | none | — |
//! | distance bands (`next_to`, `near`, `across_from`, `far`) | two closest-point pairs at different places equally near (the pair found) | none | inside the band's range, at its ends too; touching, overlapping or nested objects (distance 0) |
//! | `surround` | a distance or angle deviation reaching its clip at 1; two targets at the same plan angle (the first); the reference variant's median changing targets | a target crossing the anchor's vertical (its plan angle) | fewer than three targets; a deviation of exactly 0 (where its absolute value turns: 0, the mean of the two sides) |
//! | `face_to` | a corner of the cross-section or of a face's projection crossing an edge | a line of the cross-section starting or ceasing to hit the anchor; for a mesh anchor, a ray of the grid doing so | no line hits (score 0); at angle 0 (the maximum: 0); beyond the 30-degree clip |
//! | object-architecture distance bands (`next_to(wall)`, ...) | as the distance bands; two elements scoring the same (the first the kernel visits) | none | as the distance bands |
//! | `middle_of_room` | the object's longer plan side switching between width and depth (the width's); the size-ratio term reaching its floor 0 | none | — |
//! | `corner_of_room` | the best pair of walls changing | `inside_room` crossing its 0.5 gate | outside the gate |
//! | `on_wall`, `against_wall` | the best wall changing; the in-front fraction's kinks | none | not in front of any wall |
//! | `hang_from_ceiling` | as the distance bands | none | as the distance bands |
//! | [`box_penetration`] | two candidate axes giving the same depth (the first) | none | — |
//!
//! `face_to` against a mesh anchor averages a fixed grid of rays: between the jumps where a ray
//! starts or stops hitting, its derivative is that of the hit points on the triangles the rays
//! hit (exact for the grid).
//!
//! `tests/gradients.rs` compares every derivative with central finite differences over
//! thousands of random configurations per family (and keeps the kinks above out of the
//! comparison by detecting them), and holds hand-computed gradients for each family.
//!
//! # Cost
//! Score and gradient together cost at most 2.5 times the score alone for every predicate in
//! the benchmark configurations (`docs/performance.md`, section Gradients: instruction counts;
//! 1.0-1.1x for the distance relations, 1.2-1.7x for the volume fractions, 2.4x for `face_to`
//! where lines hit a box): the derivatives reuse the clip, the closest points or the pieces
//! the score computes. No kernel allocates.

pub mod arch;
mod centroid;
mod dispatch;
mod distance;
mod face_to;
mod penetration;
mod volume;

use std::ops::{Add, AddAssign, Mul, Neg, Sub};

use sceneeval_geom::{Point3, Real, Vector3};

use crate::ObjectGeom;

pub use centroid::{middle_of, surround};
pub use dispatch::{arch_rooms, pair};
pub use distance::{across_from, far, near, next_to};
pub use face_to::face_to;
pub use penetration::{Penetration, box_penetration};
pub use volume::{inside_of, long_short_side_of, on_top, outside_of, side_of, side_region};

/// The derivative of a score with respect to one object's box parameters (see the
/// [module docs](self) for what each parameter moves).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BoxGrad {
    /// With respect to the centre (per metre along world x, y, z).
    pub center: Vector3,
    /// With respect to the half extents (per metre along the box's own x, y, z); 0 for an
    /// object with a mesh.
    pub half_extents: Vector3,
    /// With respect to a turn about the world vertical through the object's origin (per
    /// radian).
    pub yaw: Real,
}

impl BoxGrad {
    /// No dependence on any parameter.
    pub const ZERO: BoxGrad = BoxGrad {
        center: Vector3::new(0.0, 0.0, 0.0),
        half_extents: Vector3::new(0.0, 0.0, 0.0),
        yaw: 0.0,
    };

    /// The seven derivatives in the order `(cx, cy, cz, hx, hy, hz, yaw)`.
    ///
    /// ```
    /// use sceneeval_relations::grad::BoxGrad;
    /// use sceneeval_geom::Vector3;
    /// let g = BoxGrad { center: Vector3::new(1.0, 2.0, 3.0), half_extents: Vector3::new(4.0, 5.0, 6.0), yaw: 7.0 };
    /// assert_eq!(g.to_array(), [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
    /// assert_eq!(BoxGrad::from_array(g.to_array()), g);
    /// ```
    pub fn to_array(&self) -> [Real; 7] {
        let (c, h) = (self.center, self.half_extents);
        [c.x, c.y, c.z, h.x, h.y, h.z, self.yaw]
    }

    /// The inverse of [`BoxGrad::to_array`].
    pub fn from_array(a: [Real; 7]) -> Self {
        BoxGrad {
            center: Vector3::new(a[0], a[1], a[2]),
            half_extents: Vector3::new(a[3], a[4], a[5]),
            yaw: a[6],
        }
    }
}

impl Add for BoxGrad {
    type Output = BoxGrad;
    fn add(self, o: BoxGrad) -> BoxGrad {
        BoxGrad {
            center: self.center + o.center,
            half_extents: self.half_extents + o.half_extents,
            yaw: self.yaw + o.yaw,
        }
    }
}

impl AddAssign for BoxGrad {
    fn add_assign(&mut self, o: BoxGrad) {
        *self = *self + o;
    }
}

impl Sub for BoxGrad {
    type Output = BoxGrad;
    fn sub(self, o: BoxGrad) -> BoxGrad {
        self + (-o)
    }
}

impl Neg for BoxGrad {
    type Output = BoxGrad;
    fn neg(self) -> BoxGrad {
        self * -1.0
    }
}

impl Mul<Real> for BoxGrad {
    type Output = BoxGrad;
    fn mul(self, k: Real) -> BoxGrad {
        BoxGrad {
            center: self.center * k,
            half_extents: self.half_extents * k,
            yaw: self.yaw * k,
        }
    }
}

/// A two-object score and its derivatives with respect to both objects.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PairGrad {
    /// The score, bit for bit the kernel's.
    pub score: Real,
    /// With respect to the target (the object being located).
    pub target: BoxGrad,
    /// With respect to the anchor.
    pub anchor: BoxGrad,
}

/// An object-architecture score and its derivatives with respect to the object (the room is
/// fixed).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ArchGrad {
    /// The score, bit for bit the kernel's.
    pub score: Real,
    /// With respect to the object.
    pub target: BoxGrad,
}

/// A score's derivatives computed with yaw about the box centre, turned into the object's
/// parameters: for an object with a mesh, yaw about the pose's origin (the box centre moves
/// on a circle about it) and no half extents.
#[inline]
pub(crate) fn for_object(g: BoxGrad, o: &ObjectGeom<'_>) -> BoxGrad {
    match o.mesh {
        None => g,
        Some((_, pose)) => {
            let lever = o.obb.center.coords - pose.translation.vector;
            BoxGrad {
                center: g.center,
                half_extents: Vector3::zeros(),
                yaw: g.yaw + g.center.dot(&Vector3::z().cross(&lever)),
            }
        }
    }
}

/// The anchor's centre and yaw derivatives of a score that depends on the two objects'
/// relative pose only (every object-object score does: moving or turning both together about
/// the vertical changes nothing), from the target's; `anchor_half` is the anchor's half-extent
/// derivative, computed separately. Yaws about the box centres.
#[inline]
pub(crate) fn anchor_by_invariance(
    target: &BoxGrad,
    target_centre: &Point3,
    anchor_centre: &Point3,
    anchor_half: Vector3,
) -> BoxGrad {
    let lever = target_centre - anchor_centre;
    BoxGrad {
        center: -target.center,
        half_extents: anchor_half,
        yaw: -target.yaw - target.center.dot(&Vector3::z().cross(&lever)),
    }
}

/// A [`PairGrad`] from derivatives computed with yaws about the box centres (the anchor's
/// centre and yaw from the invariance), turned into each object's parameters.
pub(crate) fn pair_result(
    score: Real,
    target_box: BoxGrad,
    anchor_half: Vector3,
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
) -> PairGrad {
    let anchor_box = anchor_by_invariance(&target_box, &target.obb.center, &anchor.obb.center, anchor_half);
    PairGrad {
        score,
        target: for_object(target_box, target),
        anchor: for_object(anchor_box, anchor),
    }
}
