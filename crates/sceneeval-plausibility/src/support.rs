//! Support (SUP): whether each object rests on, hangs on or hangs from something.

use std::collections::HashSet;

use rayon::prelude::*;
use sceneeval_geom::{Aabb, Isometry3, Mesh, Point2, Point3, Ray, Real, Vector3};
use sceneeval_scene::{ObjectId, Scene, SceneObject};
use serde::{Deserialize, Serialize};

use crate::error::{check_non_negative, check_range};
use crate::index::{BoxIndex, IndexWork, WorkCounter};
use crate::plane::{area, convex_contains, convex_hull};
use crate::sources::{SupportType, SupportTypeSource};
use crate::{Deadline, PlausibilityError};

/// Parameters of the support metric (reference yaml `SupportMetric`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SupportParams {
    /// Rays start this far behind the object's surface, against the support direction, in
    /// metres (reference `epsilon`, 0.005). Range: finite, `>= 0`.
    pub lift_m: Real,
    /// A hit counts as a contact when it is at most this far from the ray's start, in metres
    /// (reference `support_distance_threshold`, 0.01). With the lift, a supporting surface from
    /// 5 mm inside to 5 mm beyond the object's extreme is accepted. Range: finite, `> 0`.
    pub contact_distance_m: Real,
    /// Vertices within this distance of the object's extreme along the support direction are
    /// ray origins, in metres (reference: numpy `isclose` with `atol` 0.01). Range: finite,
    /// `>= 0`.
    pub extreme_band_m: Real,
    /// Faces among the extreme ones whose normal has `|n . g|` above this also get ray origins
    /// on a lattice (reference `normal_facing_threshold`, 0.9). Range: `[0, 1]`.
    pub normal_facing_threshold: Real,
    /// Lattice density on those faces, points per square metre (reference
    /// `num_samples_per_square_meter`, 256; the reference samples at random, we use sub-triangle
    /// centroids). Range: finite, `>= 0` (the points are bounded by `max_face_samples`).
    pub samples_per_m2: Real,
    /// Most lattice points per object; the density is lowered to stay within it (reference
    /// `max_total_num_samples`, 1e5, per object here). Default 4096. Range: 0 (extreme
    /// vertices only) to [`SupportParams::MAX_FACE_SAMPLES`].
    pub max_face_samples: usize,
}

impl Default for SupportParams {
    fn default() -> Self {
        SupportParams {
            lift_m: 0.005,
            contact_distance_m: 0.01,
            extreme_band_m: 0.01,
            normal_facing_threshold: 0.9,
            samples_per_m2: 256.0,
            max_face_samples: 4096,
        }
    }
}

impl SupportParams {
    /// The largest `max_face_samples` (2^20 = 1,048,576 ray origins per object, 24 MB).
    pub const MAX_FACE_SAMPLES: usize = 1 << 20;

    pub(crate) fn validate(&self) -> Result<(), PlausibilityError> {
        check_non_negative("support", "lift_m", self.lift_m, false)?;
        check_non_negative("support", "contact_distance_m", self.contact_distance_m, true)?;
        check_non_negative("support", "extreme_band_m", self.extreme_band_m, false)?;
        check_range(
            "support",
            "normal_facing_threshold",
            self.normal_facing_threshold,
            [0.0, 1.0],
            "must lie in [0, 1]",
        )?;
        check_non_negative("support", "samples_per_m2", self.samples_per_m2, false)?;
        check_range(
            "support",
            "max_face_samples",
            self.max_face_samples as f64,
            [0.0, Self::MAX_FACE_SAMPLES as f64],
            "must lie in [0, 1048576]",
        )
    }
}

/// What a support ray hit.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "type", content = "id")]
pub enum Supporter {
    /// Another object.
    Object(ObjectId),
    /// The floor of a room (room id).
    Floor(String),
    /// A wall (wall id).
    Wall(String),
    /// The ceiling of a room (room id).
    Ceiling(String),
}

/// Support evidence of one object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectSupport {
    /// The object.
    pub id: ObjectId,
    /// The support type checked.
    pub support_type: SupportType,
    /// The source that gave the type, `None` when no source knew it and `ground` was assumed.
    pub type_source: Option<String>,
    /// The support direction `g` (unit, world).
    pub gravity: Vector3,
    /// Number of rays cast (extreme vertices plus face lattice points).
    pub num_ray_origins: usize,
    /// Number of rays that found a contact.
    pub num_contacts: usize,
    /// What the contacts touched, sorted.
    pub supporters: Vec<Supporter>,
    /// Smallest gap between the object's surface and a supporter along `g`, in metres
    /// (negative when sunk in), if any contact.
    pub min_gap: Option<Real>,
    /// Area of the contacts' convex hull in the plane across `g`, square metres.
    pub contact_hull_area: Real,
    /// The centre of mass used: the area-weighted centroid of the surface (as the reference).
    pub centre_of_mass: Point3,
    /// Whether the object is supported.
    pub supported: bool,
}

/// The support metric of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SupportReport {
    /// One entry per object, in scene order.
    pub objects: Vec<ObjectSupport>,
    /// Supported objects.
    pub num_supported: usize,
    /// Objects whose type no source knew (checked as `ground`).
    pub num_unknown_type: usize,
    /// **SUP**: share of supported objects, `None` for a scene without objects.
    pub sup: Option<Real>,
}

/// One thing rays can hit.
struct Target<'a> {
    mesh: &'a Mesh,
    pose: Isometry3,
    aabb: Aabb,
    what: Supporter,
    object: Option<usize>,
}

/// Computes the support metric.
///
/// Per object, the support direction `g` follows its type: `ground` and `object` `-z`,
/// `ceiling` `+z`, `wall` the object's back (`R * (0, 1, 0)`, the negated front). Rays are cast
/// along `g` from the vertices within [`SupportParams::extreme_band_m`] of the object's extreme
/// along `g` (measured along `g` itself, so rotated wall objects work, unlike the reference's
/// dominant-axis test, quirk Q11) and from a fixed lattice on the extreme faces facing along
/// `g`, each started [`SupportParams::lift_m`] behind the surface. They are tested against every
/// other object and every floor, wall and ceiling whose box can be reached; a hit within
/// [`SupportParams::contact_distance_m`] is a contact.
///
/// `wall` and `ceiling` objects are supported by any contact. `ground` and `object` objects
/// are supported when their centre of mass (the area-weighted surface centroid, as the
/// reference), projected along `g`, lies in the closed convex hull of the contacts, which must
/// have positive area (three non-collinear contacts at least). Many rays form the hull, so a
/// single ray slipping through a shared edge cannot decide the outcome.
///
/// The targets rays may hit are found with a bounding-volume hierarchy over their boxes, so
/// the metric grows as `n log n` in the number of objects.
///
/// # Errors
/// [`PlausibilityError::InvalidParameter`] for negative or non-finite parameters.
pub fn support(
    scene: &Scene,
    params: &SupportParams,
    types: &dyn SupportTypeSource,
) -> Result<SupportReport, PlausibilityError> {
    support_with(scene, params, types, &Deadline::none()).map(|(report, _)| report)
}

/// [`support`] and the work of its spatial-index queries (boxes tested, candidate targets),
/// for tests and profiling.
///
/// # Errors
/// As [`support`].
pub fn support_with_work(
    scene: &Scene,
    params: &SupportParams,
    types: &dyn SupportTypeSource,
) -> Result<(SupportReport, IndexWork), PlausibilityError> {
    support_with(scene, params, types, &Deadline::none())
}

/// [`support_with_work`], giving up once `deadline` has passed (checked before each object).
pub(crate) fn support_with(
    scene: &Scene,
    params: &SupportParams,
    types: &dyn SupportTypeSource,
    deadline: &Deadline,
) -> Result<(SupportReport, IndexWork), PlausibilityError> {
    params.validate()?;
    let mut targets: Vec<Target<'_>> = Vec::new();
    for (k, o) in scene.objects().iter().enumerate() {
        targets.push(Target {
            mesh: o.mesh(),
            pose: *o.pose(),
            aabb: *o.world_aabb(),
            what: Supporter::Object(o.id().clone()),
            object: Some(k),
        });
    }
    for room in scene.rooms() {
        let rid = room.id().to_string();
        targets.push(arch_target(room.floor_mesh(), Supporter::Floor(rid.clone())));
        // A wall whose openings cover it whole has no solid to support anything.
        for (w, mesh) in room.walls().iter().filter_map(|w| Some((w, w.mesh()?))) {
            targets.push(arch_target(mesh, Supporter::Wall(w.id().to_owned())));
        }
        if let Some(c) = room.ceiling_mesh() {
            targets.push(arch_target(c, Supporter::Ceiling(rid)));
        }
    }
    let index = BoxIndex::new(&targets.iter().map(|t| t.aabb).collect::<Vec<_>>());
    let work = WorkCounter::default();
    let objects: Vec<ObjectSupport> = scene
        .objects()
        .par_iter()
        .enumerate()
        .map(|(k, o)| {
            deadline.check("support")?;
            let answer = types.support_type(scene, o);
            let (support_type, type_source) = match answer {
                Some(a) => (a.value, Some(a.source)),
                None => (SupportType::Ground, None),
            };
            Ok(check_object(
                k,
                o,
                support_type,
                type_source,
                &targets,
                &index,
                &work,
                params,
            ))
        })
        .collect::<Result<_, PlausibilityError>>()?;
    let num_supported = objects.iter().filter(|o| o.supported).count();
    let num_unknown_type = objects.iter().filter(|o| o.type_source.is_none()).count();
    if num_unknown_type > 0 {
        tracing::debug!(num_unknown_type, "support types unknown, checked as ground");
    }
    let report = SupportReport {
        sup: (!objects.is_empty()).then(|| num_supported as Real / objects.len() as Real),
        objects,
        num_supported,
        num_unknown_type,
    };
    Ok((report, work.total()))
}

fn arch_target(mesh: &Mesh, what: Supporter) -> Target<'_> {
    let pose = Isometry3::identity();
    Target {
        mesh,
        aabb: mesh.world_aabb(&pose),
        pose,
        what,
        object: None,
    }
}

/// The support direction of an object of this type.
pub(crate) fn gravity(support_type: SupportType, object: &SceneObject) -> Vector3 {
    match support_type {
        SupportType::Ground | SupportType::Object => -Vector3::z(),
        SupportType::Ceiling => Vector3::z(),
        SupportType::Wall => object.pose().rotation * Vector3::y(),
    }
}

#[allow(clippy::too_many_arguments)]
fn check_object(
    own: usize,
    o: &SceneObject,
    support_type: SupportType,
    type_source: Option<String>,
    targets: &[Target<'_>],
    index: &BoxIndex,
    work: &WorkCounter,
    params: &SupportParams,
) -> ObjectSupport {
    let g = gravity(support_type, o);
    let world: Vec<Point3> = o.mesh().vertices().iter().map(|v| o.pose() * v).collect();
    let centre_of_mass = surface_centroid(o.mesh(), &world);
    let origins = ray_origins(o, &world, &g, params);
    let starts: Vec<Point3> = origins.iter().map(|p| p - g * params.lift_m).collect();
    let reach = params.contact_distance_m;
    let corridor = Aabb::from_points(starts.iter()).map(|b| {
        b.including(&(b.min + g * reach))
            .including(&(b.max + g * reach))
            .loosened(1e-9)
    });
    let candidates: Vec<&Target<'_>> = match corridor {
        Some(c) => index
            .query(&c, work)
            .into_iter()
            .map(|k| &targets[k])
            .filter(|t| t.object != Some(own))
            .collect(),
        None => Vec::new(),
    };
    let mut contacts: Vec<Point3> = Vec::new();
    let mut supporters: HashSet<&Supporter> = HashSet::new();
    let mut min_toi: Option<Real> = None;
    for s in &starts {
        let ray = Ray::new(*s, g);
        let mut best: Option<Real> = None;
        for t in &candidates {
            if let Some(hit) = t.mesh.cast_ray(&t.pose, &ray, reach) {
                supporters.insert(&t.what);
                best = Some(best.map_or(hit.toi, |b: Real| b.min(hit.toi)));
            }
        }
        if let Some(toi) = best {
            contacts.push(ray.point_at(toi));
            min_toi = Some(min_toi.map_or(toi, |m: Real| m.min(toi)));
        }
    }
    let (u, v) = plane_basis(&g);
    let project = |p: &Point3| Point2::new(p.coords.dot(&u), p.coords.dot(&v));
    let hull = convex_hull(&contacts.iter().map(project).collect::<Vec<_>>());
    let hull_area = if hull.len() >= 3 { area(&hull) } else { 0.0 };
    let supported = match support_type {
        SupportType::Wall | SupportType::Ceiling => !contacts.is_empty(),
        SupportType::Ground | SupportType::Object => {
            hull_area > 1e-12 && convex_contains(&hull, &project(&centre_of_mass), 1e-9)
        }
    };
    let mut supporters: Vec<Supporter> = supporters.into_iter().cloned().collect();
    supporters.sort();
    ObjectSupport {
        id: o.id().clone(),
        support_type,
        type_source,
        gravity: g,
        num_ray_origins: origins.len(),
        num_contacts: contacts.len(),
        supporters,
        min_gap: min_toi.map(|t| t - params.lift_m),
        contact_hull_area: hull_area,
        centre_of_mass,
        supported,
    }
}

/// An orthonormal basis `(u, v)` of the plane across `g` (deterministic).
pub(crate) fn plane_basis(g: &Vector3) -> (Vector3, Vector3) {
    let helper = if g.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let u = g.cross(&helper).normalize();
    let v = g.cross(&u);
    (u, v)
}

/// The area-weighted centroid of a mesh's surface (world vertices given).
pub(crate) fn surface_centroid(mesh: &Mesh, world: &[Point3]) -> Point3 {
    let mut acc = Vector3::zeros();
    let mut total = 0.0;
    for t in mesh.triangles() {
        let (a, b, c) = (world[t[0] as usize], world[t[1] as usize], world[t[2] as usize]);
        let w = (b - a).cross(&(c - a)).norm() * 0.5;
        acc += (a.coords + b.coords + c.coords) * (w / 3.0);
        total += w;
    }
    if total > 0.0 {
        Point3::from(acc / total)
    } else {
        world.first().copied().unwrap_or(Point3::origin())
    }
}

/// The ray origins of one object: extreme vertices (deduplicated by position) then lattice
/// points on the extreme faces facing along `g`.
fn ray_origins(o: &SceneObject, world: &[Point3], g: &Vector3, params: &SupportParams) -> Vec<Point3> {
    let along: Vec<Real> = world.iter().map(|p| p.coords.dot(g)).collect();
    let extreme = along.iter().copied().fold(Real::NEG_INFINITY, Real::max);
    let in_band: Vec<bool> = along
        .iter()
        .map(|&a| a >= extreme - params.extreme_band_m)
        .collect();
    let mut seen: HashSet<[u64; 3]> = HashSet::new();
    let mut origins: Vec<Point3> = Vec::new();
    for (p, _) in world.iter().zip(&in_band).filter(|(_, b)| **b) {
        if seen.insert([p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]) {
            origins.push(*p);
        }
    }
    let faces: Vec<([Point3; 3], Real)> = o
        .mesh()
        .triangles()
        .iter()
        .filter(|t| t.iter().all(|&i| in_band[i as usize]))
        .filter_map(|t| {
            let tri = [world[t[0] as usize], world[t[1] as usize], world[t[2] as usize]];
            let n = (tri[1] - tri[0]).cross(&(tri[2] - tri[0]));
            let a = n.norm();
            (a > 0.0 && (n.dot(g) / a).abs() > params.normal_facing_threshold).then_some((tri, a * 0.5))
        })
        .collect();
    // Faces holding at least one point at this density get a k x k lattice (k^2 close to
    // area x density); smaller faces share points: a running sum of area x density emits a
    // face's centroid each time it passes an integer, so tiny faces are sampled in proportion
    // to their area too. Without `out` the points are only counted: the density is lowered
    // to fit the budget *before* any point is stored (1.2 million coincident faces of half a
    // square metre would otherwise materialise 173 million points, 4 GB, first).
    let lattice_at = |density: Real, mut out: Option<&mut Vec<Point3>>| -> usize {
        let mut count = 0usize;
        let mut carry = 0.0;
        for (tri, a) in &faces {
            let expected = a * density;
            let k = if expected >= 1.0 {
                (expected.sqrt().ceil() as usize).min(64)
            } else {
                let before = carry;
                carry += expected;
                usize::from(carry.floor() > before.floor())
            };
            if k > 0 {
                count += k * k;
                if let Some(out) = out.as_deref_mut() {
                    lattice(tri, k, out);
                }
            }
        }
        count
    };
    let mut density = params.samples_per_m2;
    let full = lattice_at(density, None);
    if full > params.max_face_samples {
        density *= params.max_face_samples as Real / full as Real;
    }
    let mut lattice_points = Vec::new();
    lattice_at(density, Some(&mut lattice_points));
    // Many tiny faces can still exceed the budget at one point each: keep an even subset.
    let keep = params.max_face_samples.max(1);
    if lattice_points.len() > keep {
        let step = lattice_points.len().div_ceil(keep);
        lattice_points = lattice_points.into_iter().step_by(step).collect();
    }
    origins.extend(lattice_points);
    origins
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
            let mean = pts.iter().fold(Vector3::zeros(), |acc, p| acc + p.coords) / (k * k) as f64;
            assert!((mean - Vector3::new(1.0 / 3.0, 1.0 / 3.0, 0.0)).norm() < 1e-12);
        }
    }
}
