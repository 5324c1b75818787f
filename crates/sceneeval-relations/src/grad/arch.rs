//! Gradients of the 10 object-architecture scores with respect to the object (the room is
//! fixed): the kernels of [`crate::arch`] report which element (wall, opening, ceiling
//! triangle, wall pair) their best score comes from and the closest points to it, and the
//! gradient is that element's (at a tie, the first in the kernel's visiting order).

use sceneeval_geom::{ClosestPoints, Real, Vector3};
use sceneeval_scene::Room;

use super::distance::{band_slope, point_grad};
use super::volume::{as_fraction, region_fraction_grad, volume_grad};
use super::{ArchGrad, BoxGrad, for_object};
use crate::arch::{
    Probe, ceiling_distance, corner_of_room_best, element_band_best, in_front_region, over_floor,
    wall_contact_best,
};
use crate::pairwise::{BoxInFrame, FrameBoxJacobian, effective_half};
use crate::params::{DistanceBand, RoomCentre};
use crate::{ArchElement, ObjectGeom, RelationParams};

/// The derivative of a distance whose closest points are `c` (the probed geometry's first)
/// with respect to the probed geometry `x` (yaw about its box centre); 0 when they meet.
fn distance_grad(c: &ClosestPoints, x: &ObjectGeom<'_>) -> BoxGrad {
    match c.points {
        Some((p, q)) => point_grad(x.obb, x.mesh.is_none(), &p, &((p - q) / c.distance)),
        None => BoxGrad::ZERO,
    }
}

/// A band score of a distance and its gradient with respect to the probed geometry.
fn band_grad(band: &DistanceBand, c: &ClosestPoints, x: &ObjectGeom<'_>) -> (Real, BoxGrad) {
    let (score, slope) = band_slope(band, c.distance);
    if slope == 0.0 {
        return (score, BoxGrad::ZERO);
    }
    (score, distance_grad(c, x) * slope)
}

/// An [`ArchGrad`] from derivatives with yaw about the box centre.
fn result(score: Real, d: BoxGrad, target: &ObjectGeom<'_>) -> ArchGrad {
    ArchGrad {
        score,
        target: for_object(d, target),
    }
}

fn element_band(
    target: &ObjectGeom<'_>,
    room: &Room,
    element: ArchElement,
    band: &DistanceBand,
    params: &RelationParams,
) -> ArchGrad {
    let (score, best) = element_band_best(target, room, element, band, params);
    let probe = Probe::new(target, params);
    let (_, d) = band_grad(band, &best.closest, &probe.geom);
    result(score, d, target)
}

/// [`crate::arch::next_to`] and its gradient.
pub fn next_to(
    target: &ObjectGeom<'_>,
    room: &Room,
    element: ArchElement,
    params: &RelationParams,
) -> ArchGrad {
    element_band(target, room, element, &params.arch_next_to, params)
}

/// [`crate::arch::near`] and its gradient.
pub fn near(target: &ObjectGeom<'_>, room: &Room, element: ArchElement, params: &RelationParams) -> ArchGrad {
    element_band(target, room, element, &params.arch_near, params)
}

/// [`crate::arch::across_from`] and its gradient.
pub fn across_from(
    target: &ObjectGeom<'_>,
    room: &Room,
    element: ArchElement,
    params: &RelationParams,
) -> ArchGrad {
    element_band(target, room, element, &params.arch_across_from, params)
}

/// [`crate::arch::far`] and its gradient.
pub fn far(target: &ObjectGeom<'_>, room: &Room, element: ArchElement, params: &RelationParams) -> ArchGrad {
    element_band(target, room, element, &params.arch_far, params)
}

/// A volume and its derivatives, summed over floor triangles.
#[derive(Clone, Copy, Default)]
struct Summed {
    v: Real,
    d: BoxGrad,
}

impl std::ops::AddAssign for Summed {
    fn add_assign(&mut self, o: Summed) {
        self.v += o.v;
        self.d += o.d;
    }
}

/// [`crate::arch::inside_room`] and its gradient: the floor triangles' prisms are fixed, the
/// box moves (volume fractions, see [`crate::grad`]). A box wholly over a convex floor scores 1
/// with a zero gradient.
///
/// ```
/// use sceneeval_relations::{grad, ObjectGeom, RelationParams};
/// use sceneeval_scene::RoomBuilder;
/// use sceneeval_geom::{Obb, Point2, na::{Point3, Vector3}};
/// let room = RoomBuilder::rectangle("r", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0)).build().unwrap();
/// // A 1 m cube centred on the wall line x = 4: half over the floor; moving it by dx toward
/// // the room (-x) brings 1 m^2 x dx more over it: -1 per metre of x.
/// let cube = Obb::from_yaw(Point3::new(4.0, 2.0, 0.5), Vector3::repeat(0.5), 0.0).unwrap();
/// let g = grad::arch::inside_room(&ObjectGeom::from_box(&cube), &room, &RelationParams::default());
/// assert!((g.score - 0.5).abs() < 1e-12);
/// assert!((g.target.center.x + 1.0).abs() < 1e-9 && g.target.center.y.abs() < 1e-9);
/// ```
pub fn inside_room(target: &ObjectGeom<'_>, room: &Room, params: &RelationParams) -> ArchGrad {
    let obb = target.obb;
    let h = effective_half(obb, params);
    let summed = over_floor(obb, &h, room, params, |h, planes| {
        let (v, d, _) = volume_grad(obb, h, planes, params);
        Summed { v, d }
    });
    match summed {
        None => result(1.0, BoxGrad::ZERO, target),
        Some(Summed { v, d }) => {
            let (score, d) = as_fraction(obb, &h, v, &d, params);
            result(score, d, target)
        }
    }
}

/// [`crate::arch::middle_of_room`] and its gradient: through the plan offset from the room's
/// centre and through the standard deviation, which grows with the longer plan side `o` of the
/// box (one-sided where width and depth are equal: the width's, and where the ratio term
/// reaches 0).
pub fn middle_of_room(target: &ObjectGeom<'_>, room: &Room, params: &RelationParams) -> ArchGrad {
    let score = crate::arch::middle_of_room(target, room, params);
    let (rect_centre, dims) = room.floor_rectangle();
    let centre = match params.room_centre {
        RoomCentre::AreaCentroid => room.floor_centroid(),
        RoomCentre::BoundsCentre => rect_centre,
    };
    let c = target.obb.center;
    let (dx, dy) = (c.x - centre.x, c.y - centre.y);
    let r = 0.5 * (dims.x + dims.y);
    let e = target.obb.extents();
    let o = e.x.max(e.y);
    let ratio_open = r > 0.0 && 1.0 - o / r > 0.0;
    let ratio = if r > 0.0 { (1.0 - o / r).max(0.0) } else { 0.0 };
    let base = params.middle_of_room_base_sigma_m;
    let sigma = base * (params.middle_of_room_size_weight * o + params.middle_of_room_ratio_weight * ratio);
    if sigma <= 0.0 {
        return result(score, BoxGrad::ZERO, target);
    }
    let d2 = dx * dx + dy * dy;
    let s2 = sigma * sigma;
    // ds/dsigma = s d^2 / sigma^3; dsigma/do = base (w_size - w_ratio / r while the ratio is open).
    let d_sigma_d_o = base
        * (params.middle_of_room_size_weight
            - if ratio_open {
                params.middle_of_room_ratio_weight / r
            } else {
                0.0
            });
    let d_o = score * d2 / (s2 * sigma) * d_sigma_d_o;
    // o = 2 max(hx, hy): the width's on a tie, as `max` keeps it.
    let half_extents = if e.x >= e.y {
        Vector3::new(2.0 * d_o, 0.0, 0.0)
    } else {
        Vector3::new(0.0, 2.0 * d_o, 0.0)
    };
    let d = BoxGrad {
        center: Vector3::new(dx, dy, 0.0) * (-score / s2),
        half_extents,
        yaw: 0.0,
    };
    result(score, d, target)
}

/// [`crate::arch::corner_of_room`] and its gradient: the product rule over the best pair of
/// walls. Zero outside the `inside_room` gate (where the score jumps to 0).
pub fn corner_of_room(target: &ObjectGeom<'_>, room: &Room, params: &RelationParams) -> ArchGrad {
    let (score, pair) = corner_of_room_best(target, room, params);
    let Some(((si, ci), (sj, cj))) = pair else {
        return result(score, BoxGrad::ZERO, target);
    };
    let probe = Probe::new(target, params);
    let (_, gi) = band_grad(&params.corner_wall, &ci, &probe.geom);
    let (_, gj) = band_grad(&params.corner_wall, &cj, &probe.geom);
    result(score, gi * sj + gj * si, target)
}

/// `on_wall` and `against_wall`: the product rule on (fraction in front of the best wall) x
/// (band score of the distance to it).
fn wall_contact(
    target: &ObjectGeom<'_>,
    room: &Room,
    band: &DistanceBand,
    params: &RelationParams,
) -> ArchGrad {
    let (score, best) = wall_contact_best(target, room, band, params);
    let Some((i, c)) = best else {
        return result(score, BoxGrad::ZERO, target);
    };
    let wall = &room.walls()[i];
    let (origin, region) = in_front_region(wall, params);
    let inframe = BoxInFrame::new(target.obb, &wall.rotation(), &origin, params);
    let (front, d_front, _) =
        region_fraction_grad(&inframe, target.obb, &region, &FrameBoxJacobian::ZERO, params);
    let probe = Probe::new(target, params);
    let (b, d_band) = band_grad(band, &c, &probe.geom);
    result(score, d_front * b + d_band * front, target)
}

/// [`crate::arch::on_wall`] and its gradient.
pub fn on_wall(target: &ObjectGeom<'_>, room: &Room, params: &RelationParams) -> ArchGrad {
    wall_contact(target, room, &params.on_wall, params)
}

/// [`crate::arch::against_wall`] and its gradient.
pub fn against_wall(target: &ObjectGeom<'_>, room: &Room, params: &RelationParams) -> ArchGrad {
    wall_contact(target, room, &params.against_wall, params)
}

/// [`crate::arch::hang_from_ceiling`] and its gradient (for a box under the ceiling, through
/// its top point: the centre's height and the half extents' vertical reach).
pub fn hang_from_ceiling(target: &ObjectGeom<'_>, room: &Room, params: &RelationParams) -> ArchGrad {
    let Some(c) = ceiling_distance(target, room, params) else {
        return result(0.0, BoxGrad::ZERO, target);
    };
    let probe = Probe::new(target, params);
    let (score, d) = band_grad(&params.hang_from_ceiling, &c, &probe.geom);
    result(score, d, target)
}
