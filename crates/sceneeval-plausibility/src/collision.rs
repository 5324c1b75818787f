//! Collision (COL): which objects interpenetrate, and how deeply.

use std::sync::OnceLock;

use rayon::prelude::*;
use sceneeval_geom::{Aabb, Point3, Real};
use sceneeval_scene::{ObjectId, Scene, SceneObject};
use serde::{Deserialize, Serialize};

use crate::category::has_word;
use crate::error::check_non_negative;
use crate::solid::Solid;
use crate::{Deadline, PlausibilityError};

/// Parameters of the collision metric.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CollisionParams {
    /// Resting-contact tolerance in metres: a pair whose penetration depth is at most this is
    /// touching, not colliding. Default 0.005, the reference's intent
    /// (`CollisionMetric.move_direction_amount`: it forgives a pair that separates after a
    /// 5 mm push).
    pub contact_tolerance: Real,
    /// Leave flat floor coverings out of the metric (not tested, not counted). Default `false`,
    /// like the original reference; its fork sets it.
    pub exclude_floor_coverings: bool,
    /// Whole words that mark a floor covering in an object's category (or, without a category,
    /// its description). Default `rug`, `carpet`, `mat`, `doormat`.
    pub floor_covering_words: Vec<String>,
    /// Finest spacing in metres of the surface points at which the penetration depth is
    /// evaluated. Default 0.0025 (half the contact tolerance).
    pub depth_sample_spacing: Real,
    /// Most surface points per pair and direction for the depth; the spacing is coarsened
    /// (deterministically) to stay within it. Default 2048.
    pub depth_sample_budget: usize,
}

impl Default for CollisionParams {
    fn default() -> Self {
        CollisionParams {
            contact_tolerance: 0.005,
            exclude_floor_coverings: false,
            floor_covering_words: ["rug", "carpet", "mat", "doormat"].map(String::from).to_vec(),
            depth_sample_spacing: 0.0025,
            depth_sample_budget: 2048,
        }
    }
}

impl CollisionParams {
    pub(crate) fn validate(&self) -> Result<(), PlausibilityError> {
        check_non_negative("collision", "contact_tolerance", self.contact_tolerance, false)?;
        check_non_negative(
            "collision",
            "depth_sample_spacing",
            self.depth_sample_spacing,
            true,
        )?;
        if self.depth_sample_budget == 0 {
            return Err(PlausibilityError::InvalidParameter {
                metric: "collision",
                name: "depth_sample_budget",
                value: 0.0,
                reason: "must be at least 1",
            });
        }
        Ok(())
    }
}

/// How two objects meet.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "type")]
pub enum ContactKind {
    /// Their surfaces touch or cross.
    Surface,
    /// Their surfaces do not meet, but `inner` lies entirely inside the other (the reference
    /// misses this case).
    Nested {
        /// The object inside.
        inner: ObjectId,
    },
}

/// Two objects whose surfaces meet or that are nested: the evidence behind the metric.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairContact {
    /// First object (earlier in scene order).
    pub a: ObjectId,
    /// Second object.
    pub b: ObjectId,
    /// How they meet.
    pub kind: ContactKind,
    /// Penetration depth in metres (see [`collision`]).
    pub depth: Real,
    /// Spacing in metres of the surface points the depth was evaluated at; the true depth is
    /// at most `depth + depth_spacing`.
    pub depth_spacing: Real,
    /// Whether the pair counts as a collision: nested, or deeper than the contact tolerance.
    pub colliding: bool,
}

/// Collision evidence of one object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectCollision {
    /// The object.
    pub id: ObjectId,
    /// Left out as a floor covering.
    pub excluded: bool,
    /// In collision with at least one other object.
    pub in_collision: bool,
    /// The objects it collides with, in scene order.
    pub colliding_with: Vec<ObjectId>,
    /// Its deepest colliding penetration in metres (0 when not in collision).
    pub max_depth: Real,
}

/// The collision metric of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CollisionReport {
    /// One entry per object, in scene order.
    pub objects: Vec<ObjectCollision>,
    /// Every pair whose surfaces meet or that is nested, colliding or resting, in pair order.
    pub contacts: Vec<PairContact>,
    /// Objects tested (all but excluded floor coverings).
    pub num_tested: usize,
    /// Tested objects in collision.
    pub num_in_collision: usize,
    /// Colliding pairs.
    pub num_colliding_pairs: usize,
    /// **COL_ob**: the share of tested objects in collision, in [0, 1]; `None` when no object
    /// was tested.
    pub col_ob: Option<Real>,
    /// **COL_sc**: whether any pair collides.
    pub col_sc: bool,
}

/// Computes the collision metric.
///
/// **Broad phase**: sort-and-sweep of the world AABBs along the axis over which their centres
/// spread most; only overlapping boxes reach the narrow phase, so the cost grows as
/// `n log n + k` for `k` overlapping pairs.
///
/// **Narrow phase**: an exact mesh-mesh surface test ([`sceneeval_geom::Mesh::intersects`]).
/// Pairs whose surfaces do not meet are tested for nesting: one world AABB contains the other
/// and a vertex of the inner mesh is inside the outer one.
///
/// **Penetration depth**: the largest distance from a point of one surface lying inside the
/// other object to the other's surface, over both directions. It is evaluated at the vertices
/// and on a lattice of points (sub-triangle centroids) of the triangles inside the overlap of
/// the two boxes, first with at most 256 points per direction, then, if that does not already
/// exceed the tolerance, with at most [`CollisionParams::depth_sample_budget`] points at
/// spacing [`CollisionParams::depth_sample_spacing`] (coarser if the budget demands). A sampled
/// depth never exceeds the true one, and falls short of it by at most about the reported
/// [`PairContact::depth_spacing`]. For two boxes overlapping face to face by `d` it is `d`;
/// for resting contact it is 0. "Inside" is the pseudo-normal sign test for closed meshes and
/// the generalized winding number for open ones (there at most 256 points, farthest first, are
/// tested). A pair collides when nested or when its depth exceeds
/// [`CollisionParams::contact_tolerance`]; the reference instead pushes one object 5 mm away
/// from the contacts and tests again, which misses nested objects (quirk Q23).
///
/// # Errors
/// [`PlausibilityError::InvalidParameter`] for a negative tolerance or a zero spacing/budget.
pub fn collision(scene: &Scene, params: &CollisionParams) -> Result<CollisionReport, PlausibilityError> {
    collision_with(scene, params, &Deadline::none())
}

/// [`collision`], giving up once `deadline` has passed (checked before each candidate pair).
pub(crate) fn collision_with(
    scene: &Scene,
    params: &CollisionParams,
    deadline: &Deadline,
) -> Result<CollisionReport, PlausibilityError> {
    params.validate()?;
    let objects = scene.objects();
    let excluded: Vec<bool> = objects
        .iter()
        .map(|o| params.exclude_floor_coverings && is_floor_covering(o, &params.floor_covering_words))
        .collect();
    let tested: Vec<usize> = (0..objects.len()).filter(|&i| !excluded[i]).collect();
    let candidates = sweep_and_prune(objects, &tested);
    // Inside-test structures are built once per object, on first use, by whichever thread
    // needs them first; they are pure functions of the object, so results do not depend on it.
    let solids: Vec<OnceLock<Solid<'_>>> = objects.iter().map(|_| OnceLock::new()).collect();
    let solid = |k: usize| solids[k].get_or_init(|| Solid::new(objects[k].mesh(), objects[k].pose()));
    let found: Vec<(usize, usize, PairContact)> = candidates
        .par_iter()
        .filter_map(|&(i, j)| {
            if deadline.expired() {
                return None;
            }
            narrow_phase(objects, i, j, &solid, params).map(|c| (i, j, c))
        })
        .collect();
    deadline.check("collision")?;

    let mut colliding_with: Vec<Vec<usize>> = vec![Vec::new(); objects.len()];
    let mut max_depth = vec![0.0; objects.len()];
    for (i, j, c) in &found {
        if c.colliding {
            colliding_with[*i].push(*j);
            colliding_with[*j].push(*i);
            max_depth[*i] = Real::max(max_depth[*i], c.depth);
            max_depth[*j] = Real::max(max_depth[*j], c.depth);
        }
    }
    let contacts: Vec<PairContact> = found.into_iter().map(|(_, _, c)| c).collect();
    let report_objects: Vec<ObjectCollision> = objects
        .iter()
        .enumerate()
        .map(|(i, o)| {
            let mut with = colliding_with[i].clone();
            with.sort_unstable();
            ObjectCollision {
                id: o.id().clone(),
                excluded: excluded[i],
                in_collision: !with.is_empty(),
                colliding_with: with.iter().map(|&k| objects[k].id().clone()).collect(),
                max_depth: max_depth[i],
            }
        })
        .collect();
    let num_in_collision = report_objects.iter().filter(|o| o.in_collision).count();
    let num_colliding_pairs = contacts.iter().filter(|c| c.colliding).count();
    tracing::debug!(
        objects = objects.len(),
        candidates = candidates.len(),
        contacts = contacts.len(),
        num_colliding_pairs,
        "collision"
    );
    Ok(CollisionReport {
        objects: report_objects,
        contacts,
        num_tested: tested.len(),
        num_in_collision,
        num_colliding_pairs,
        col_ob: (!tested.is_empty()).then(|| num_in_collision as Real / tested.len() as Real),
        col_sc: num_colliding_pairs > 0,
    })
}

/// Whether the object is a flat floor covering by its category (or description).
pub(crate) fn is_floor_covering(o: &SceneObject, words: &[String]) -> bool {
    match o.category() {
        Some(c) => has_word(c, words),
        None => o.description().is_some_and(|d| has_word(d, words)),
    }
}

/// Candidate pairs `(i, j)`, `i < j`, whose world AABBs overlap, in lexicographic order.
pub(crate) fn sweep_and_prune(objects: &[SceneObject], members: &[usize]) -> Vec<(usize, usize)> {
    if members.len() < 2 {
        return Vec::new();
    }
    let axis = (0..3)
        .max_by(|&a, &b| {
            spread(objects, members, a)
                .total_cmp(&spread(objects, members, b))
                .then(b.cmp(&a))
        })
        .unwrap_or(0);
    let mut order: Vec<usize> = members.to_vec();
    order.sort_by(|&a, &b| {
        objects[a].world_aabb().min[axis]
            .total_cmp(&objects[b].world_aabb().min[axis])
            .then(a.cmp(&b))
    });
    let mut active: Vec<usize> = Vec::new();
    let mut pairs = Vec::new();
    for &k in &order {
        let bk = objects[k].world_aabb();
        active.retain(|&a| objects[a].world_aabb().max[axis] >= bk.min[axis]);
        for &a in &active {
            if objects[a].world_aabb().intersects(bk) {
                pairs.push((a.min(k), a.max(k)));
            }
        }
        active.push(k);
    }
    pairs.sort_unstable();
    pairs
}

fn spread(objects: &[SceneObject], members: &[usize], axis: usize) -> Real {
    let (mut lo, mut hi) = (Real::INFINITY, Real::NEG_INFINITY);
    for &i in members {
        let c = objects[i].world_aabb().center()[axis];
        lo = lo.min(c);
        hi = hi.max(c);
    }
    hi - lo
}

fn narrow_phase<'s>(
    objects: &'s [SceneObject],
    i: usize,
    j: usize,
    solid: &(dyn Fn(usize) -> &'s Solid<'s> + Sync),
    params: &CollisionParams,
) -> Option<PairContact> {
    let (a, b) = (&objects[i], &objects[j]);
    let (ba, bb) = (a.world_aabb(), b.world_aabb());
    let contact = |kind, (depth, depth_spacing): (Real, Real), colliding: bool| PairContact {
        a: a.id().clone(),
        b: b.id().clone(),
        kind,
        depth,
        depth_spacing,
        colliding,
    };
    if a.mesh().intersects(a.pose(), b.mesh(), b.pose()) {
        let region = ba.intersection(bb)?;
        // Coarse first: a depth found above the tolerance at a coarse spacing already proves
        // the collision (sampled depths never exceed the true one); only shallow pairs are
        // resampled at the full budget to tell contact from collision.
        let coarse = params.depth_sample_budget.min(COARSE_BUDGET);
        let mut depth = (0.0, 0.0);
        for budget in [coarse, params.depth_sample_budget] {
            let (d1, s1) = depth_into(a, solid(j), bb, &region, params, budget);
            let (d2, s2) = depth_into(b, solid(i), ba, &region, params, budget);
            depth = (d1.max(d2), s1.max(s2));
            if depth.0 > params.contact_tolerance || budget == params.depth_sample_budget {
                break;
            }
        }
        return Some(contact(
            ContactKind::Surface,
            depth,
            depth.0 > params.contact_tolerance,
        ));
    }
    for (inner, outer) in [(i, j), (j, i)] {
        let (oi, oo) = (&objects[inner], &objects[outer]);
        if oo.world_aabb().contains_aabb(oi.world_aabb()) {
            let v = oi.pose() * oi.mesh().vertices()[0];
            if solid(outer).contains(&v) {
                let depth = depth_into(
                    oi,
                    solid(outer),
                    oo.world_aabb(),
                    oi.world_aabb(),
                    params,
                    COARSE_BUDGET,
                );
                return Some(contact(
                    ContactKind::Nested {
                        inner: oi.id().clone(),
                    },
                    depth,
                    true,
                ));
            }
        }
    }
    None
}

/// Surface points per direction of the first, coarse depth pass.
const COARSE_BUDGET: usize = 256;

/// The deepest point of `a`'s surface inside `b`, and the sample spacing used.
fn depth_into(
    a: &SceneObject,
    b: &Solid<'_>,
    b_box: &Aabb,
    region: &Aabb,
    params: &CollisionParams,
    budget: usize,
) -> (Real, Real) {
    let region = region.loosened(1e-9);
    let mesh = a.mesh();
    let world: Vec<Point3> = mesh.vertices().iter().map(|v| a.pose() * v).collect();
    let tris: Vec<[Point3; 3]> = mesh
        .triangles()
        .iter()
        .map(|t| [world[t[0] as usize], world[t[1] as usize], world[t[2] as usize]])
        .filter(|t| Aabb::from_points(t.iter()).is_some_and(|bb| bb.intersects(&region)))
        .collect();
    if tris.is_empty() {
        return (0.0, 0.0);
    }
    let total_area: Real = tris
        .iter()
        .map(|t| (t[1] - t[0]).cross(&(t[2] - t[0])).norm() * 0.5)
        .sum();
    let budget = budget.max(1) as Real;
    // k^2 sub-triangles of spacing s cover about (s^2 / 2) each.
    let spacing = params
        .depth_sample_spacing
        .max((2.0 * total_area / budget).sqrt());
    let mut points: Vec<Point3> = Vec::new();
    for t in &tris {
        points.extend(t.iter().copied());
        let longest = (0..3)
            .map(|i| (t[(i + 1) % 3] - t[i]).norm())
            .fold(0.0, Real::max);
        let k = ((longest / spacing).ceil() as usize).clamp(1, 64);
        lattice(t, k, &mut points);
    }
    points.retain(|p| region.contains_point(p));
    points.sort_by(|p, q| {
        p.x.total_cmp(&q.x)
            .then(p.y.total_cmp(&q.y))
            .then(p.z.total_cmp(&q.z))
    });
    points.dedup();
    let mut depth: Real = 0.0;
    if b.is_closed() {
        // A point inside `b` is no deeper than its distance to the boundary of `b`'s box:
        // visit points by that bound and stop once it cannot beat the depth found.
        let mut by_bound: Vec<(Real, usize)> = points
            .iter()
            .enumerate()
            .map(|(i, p)| (box_depth(b_box, p), i))
            .collect();
        by_bound.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
        for &(bound, i) in &by_bound {
            if bound <= depth {
                break;
            }
            if let (d, Some(true)) = b.query(&points[i])
                && d > depth
            {
                depth = d;
            }
        }
    } else {
        // Open mesh: winding-number tests are costly, so test the farthest points first and
        // stop at the first one inside (it is the deepest), after at most 256 tests.
        let mut by_distance: Vec<(Real, usize)> = points
            .iter()
            .enumerate()
            .map(|(i, p)| (b.query(p).0, i))
            .collect();
        by_distance.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
        for &(d, i) in by_distance.iter().take(256) {
            if d <= depth {
                break;
            }
            if b.contains(&points[i]) {
                depth = d;
                break;
            }
        }
    }
    (depth, spacing)
}

/// Distance from `p` to the boundary of the box (0 outside).
fn box_depth(b: &Aabb, p: &Point3) -> Real {
    (0..3)
        .map(|k| (p[k] - b.min[k]).min(b.max[k] - p[k]))
        .fold(Real::INFINITY, Real::min)
        .max(0.0)
}

/// Appends the centroids of the `k^2` sub-triangles of the `k`-subdivision of `t`.
pub(crate) fn lattice(t: &[Point3; 3], k: usize, out: &mut Vec<Point3>) {
    let (a, e1, e2) = (t[0], t[1] - t[0], t[2] - t[0]);
    let kf = k as Real;
    for i in 0..k {
        for j in 0..k - i {
            let (fi, fj) = (i as Real, j as Real);
            out.push(a + e1 * ((fi + 1.0 / 3.0) / kf) + e2 * ((fj + 1.0 / 3.0) / kf));
            if j + 1 < k - i {
                out.push(a + e1 * ((fi + 2.0 / 3.0) / kf) + e2 * ((fj + 2.0 / 3.0) / kf));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use sceneeval_geom::Vector3;
    use sceneeval_geom::conventions::pose_from_yaw;

    proptest! {
        /// The sweep finds exactly the pairs whose boxes overlap (checked against all pairs).
        #[test]
        fn sweep_matches_brute_force(boxes in proptest::collection::vec(
            (0.0..5.0f64, 0.0..5.0f64, 0.0..2.0f64, 0.05..1.5f64, 0.05..1.5f64, 0.05..1.0f64), 0..24)) {
            let objects: Vec<SceneObject> = boxes
                .iter()
                .enumerate()
                .map(|(k, &(x, y, z, w, d, h))| {
                    SceneObject::new_box(format!("o{k}"), Vector3::new(w, d, h) * 0.5, pose_from_yaw(Point3::new(x, y, z), 0.3 * k as f64))
                        .unwrap()
                })
                .collect();
            let all: Vec<usize> = (0..objects.len()).collect();
            let mut brute = Vec::new();
            for i in 0..objects.len() {
                for j in i + 1..objects.len() {
                    if objects[i].world_aabb().intersects(objects[j].world_aabb()) {
                        brute.push((i, j));
                    }
                }
            }
            prop_assert_eq!(sweep_and_prune(&objects, &all), brute);
        }
    }

    #[test]
    fn lattice_has_k_squared_points_inside() {
        let t = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ];
        for k in 1..6 {
            let mut pts = Vec::new();
            lattice(&t, k, &mut pts);
            assert_eq!(pts.len(), k * k);
            assert!(pts.iter().all(|p| p.x > 0.0 && p.y > 0.0 && p.x + p.y < 1.0));
            // The centroids average to the triangle's centroid.
            let mean = pts
                .iter()
                .fold(sceneeval_geom::Vector3::zeros(), |acc, p| acc + p.coords)
                / (k * k) as f64;
            assert!((mean - sceneeval_geom::Vector3::new(1.0 / 3.0, 1.0 / 3.0, 0.0)).norm() < 1e-12);
        }
    }
}
