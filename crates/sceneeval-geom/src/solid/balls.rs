//! Interior balls: a few large balls inside a mesh's solid, seeded at the box's centre and on
//! the inward rays of the largest triangles, then grown away from the surface.

use crate::parry::math::Vector as PVector;
use crate::parry::query::{PointQuery, RayCast};
use crate::{Mesh, Point3, Real};

use super::SolidTables;

/// Triangles whose inward ray seeds an interior ball.
const BALL_SEEDS: usize = 12;
/// Steps a ball takes away from its closest surface point.
const BALL_STEPS: usize = 4;
/// Interior balls kept per mesh.
const MAX_BALLS: usize = 8;

/// A ball inside a mesh's solid, in the mesh frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Ball {
    pub centre: Point3,
    pub radius: Real,
}

/// Balls inside the solid: from the largest triangles, the midpoint of the inward ray to the
/// opposite surface, with its distance to the surface as radius.
pub(super) fn interior_balls(mesh: &Mesh, tables: &SolidTables) -> Vec<Ball> {
    let mut order: Vec<(Real, usize)> = (0..mesh.triangles().len())
        .map(|k| {
            let [a, b, c] = mesh.triangle(k);
            ((b - a).cross(&(c - a)).norm(), k)
        })
        .collect();
    order.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
    let scale = mesh.aabb().extents().norm().max(1e-9);
    let mut balls: Vec<Ball> = Vec::new();
    // The centre of the box is the deepest point of convex, box-like shapes. A point inside
    // is no farther from the surface than from the box's faces: search no farther.
    let bx = mesh.aabb();
    let centre = bx.center();
    let reach = (0..3)
        .map(|k| bx.half_extents()[k])
        .fold(Real::INFINITY, Real::min);
    let class = tables.classify_within(mesh, &centre, reach.max(1e-9) * (1.0 + 1e-9));
    if class.inside && class.exact && class.distance > 0.0 {
        balls.push(grow_ball(mesh, tables, centre, class.distance));
    }
    for &(_, k) in order.iter().take(BALL_SEEDS) {
        let [a, b, c] = mesh.triangle(k);
        let Some(n) = (b - a).cross(&(c - a)).try_normalize(0.0) else {
            continue;
        };
        let g = Point3::from((a.coords + b.coords + c.coords) / 3.0);
        for dir in [-n, n] {
            let start = g + dir * (1e-9 * scale);
            let ray = crate::parry::query::Ray::new(
                PVector::new(start.x, start.y, start.z),
                PVector::new(dir.x, dir.y, dir.z),
            );
            let Some(toi) = mesh.parry_shape().cast_local_ray(&ray, 2.0 * scale, false) else {
                continue;
            };
            // The hit lies half the ray away: the surface is no farther than that.
            let centre = start + dir * (0.5 * toi);
            let class = tables.classify_within(mesh, &centre, 0.5 * toi * (1.0 + 1e-9) + 1e-12);
            if class.inside && class.exact && class.distance > 0.0 {
                balls.push(grow_ball(mesh, tables, centre, class.distance));
                break;
            }
        }
    }
    balls.sort_by(|x, y| {
        y.radius
            .total_cmp(&x.radius)
            .then(x.centre.x.total_cmp(&y.centre.x))
            .then(x.centre.y.total_cmp(&y.centre.y))
            .then(x.centre.z.total_cmp(&y.centre.z))
    });
    // Keep balls whose centres lie outside the balls already kept.
    let mut kept: Vec<Ball> = Vec::new();
    for b in balls {
        if kept.len() < MAX_BALLS && kept.iter().all(|k| (k.centre - b.centre).norm() > k.radius) {
            kept.push(b);
        }
    }
    kept
}

/// A ball inside the solid grown by a few steps away from its closest surface point (every
/// search bounded by a little more than the current radius, so that a ball deep inside a
/// round object stays cheap).
fn grow_ball(mesh: &Mesh, tables: &SolidTables, mut centre: Point3, mut radius: Real) -> Ball {
    for _ in 0..BALL_STEPS {
        let Some(proj) = mesh.parry_shape().project_local_point_with_max_dist(
            PVector::new(centre.x, centre.y, centre.z),
            false,
            radius * (1.0 + 1e-9) + 1e-12,
        ) else {
            break;
        };
        let away = centre - Point3::new(proj.point.x, proj.point.y, proj.point.z);
        let Some(dir) = away.try_normalize(0.0) else {
            break;
        };
        let next = centre + dir * (0.5 * radius);
        // Moving by r/2 away, the surface is at most 1.5 r from the new centre.
        let class = tables.classify_within(mesh, &next, 1.5 * radius * (1.0 + 1e-9));
        if !(class.inside && class.exact && class.distance > radius) {
            break;
        }
        centre = next;
        radius = class.distance;
    }
    Ball { centre, radius }
}
