//! Gradients of the scores of box centres: `middle_of` and `surround`.

use sceneeval_geom::{Real, Vector3};

use super::{BoxGrad, PairGrad, for_object, pair_result};
use crate::pairwise::{surround_core, with_scratch};
use crate::{ObjectGeom, RelationError, RelationParams};

/// [`crate::middle_of`] and its gradient: `-s / sigma^2` times the plan offset between the
/// centres (no kink).
///
/// ```
/// use sceneeval_relations::{grad, ObjectGeom, RelationParams};
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// let bed = Obb::from_yaw(Point3::new(1.0, 2.0, 0.3), Vector3::new(0.8, 1.0, 0.3), 0.0).unwrap();
/// // 0.25 m off along x: s = exp(-0.5), ds/dx = -s * 0.25 / 0.25^2 = -4 s.
/// let pillow = Obb::from_yaw(Point3::new(1.25, 2.0, 0.7), Vector3::new(0.3, 0.2, 0.1), 0.0).unwrap();
/// let g = grad::middle_of(&ObjectGeom::from_box(&pillow), &ObjectGeom::from_box(&bed), &RelationParams::default());
/// let s = (-0.5f64).exp();
/// assert!((g.target.center.x + 4.0 * s).abs() < 1e-12);
/// assert_eq!(g.target.center.z, 0.0);
/// ```
pub fn middle_of(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> PairGrad {
    let score = crate::middle_of(target, anchor, params);
    let d = target.obb.center - anchor.obb.center;
    let s2 = params.middle_of_sigma_m * params.middle_of_sigma_m;
    let d_target = BoxGrad {
        center: Vector3::new(d.x, d.y, 0.0) * (-score / s2),
        ..BoxGrad::ZERO
    };
    pair_result(score, d_target, Vector3::zeros(), target, anchor)
}

/// [`crate::surround`] and its gradient: the derivatives with respect to each target into
/// `d_targets` (one per target), and the score with its derivatives with respect to the
/// anchor. The score depends on the centres only, so the half extents' derivatives are 0 and
/// a box's own yaw changes nothing; the anchor's follow from moving or turning everything
/// together. Fewer than three targets score 0 with a zero gradient.
///
/// # Errors
/// [`RelationError::LengthMismatch`] when `d_targets` does not have one entry per target,
/// [`RelationError::TooManyTargets`] as [`crate::score`] for the reference variant.
///
/// ```
/// use sceneeval_relations::{grad::{self, BoxGrad}, ObjectGeom, RelationParams};
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// let table = Obb::from_yaw(Point3::new(0.0, 0.0, 0.4), Vector3::repeat(0.5), 0.0).unwrap();
/// let chair = |x: f64, y: f64| Obb::from_yaw(Point3::new(x, y, 0.4), Vector3::repeat(0.25), 0.0).unwrap();
/// let chairs = [chair(1.0, 0.0), chair(0.0, 1.0), chair(-1.0, 0.0), chair(0.0, -1.0)];
/// let targets: Vec<ObjectGeom> = chairs.iter().map(ObjectGeom::from_box).collect();
/// let mut d = [BoxGrad::ZERO; 4];
/// let (score, anchor) = grad::surround(&targets, &ObjectGeom::from_box(&table), &RelationParams::default(), &mut d).unwrap();
/// // Evenly spread: the score is 1 and at its maximum.
/// assert_eq!(score, 1.0);
/// assert!(d.iter().all(|g| g.center.norm() < 1e-12) && anchor.center.norm() < 1e-12);
/// ```
pub fn surround(
    targets: &[ObjectGeom<'_>],
    anchor: &ObjectGeom<'_>,
    params: &RelationParams,
    d_targets: &mut [BoxGrad],
) -> Result<(Real, BoxGrad), RelationError> {
    let n = targets.len();
    crate::dispatch::surround_limit(n, params)?;
    if d_targets.len() != n {
        return Err(RelationError::LengthMismatch {
            what: "d_targets",
            got: d_targets.len(),
            expected: n,
        });
    }
    let b = &anchor.obb.center;
    let (score, anchor_box) = with_scratch(n, |centres: &mut [Vector3]| {
        let score = surround_core(n, |i| targets[i].obb.center, b, params, Some(&mut *centres));
        let mut anchor_box = BoxGrad::ZERO;
        for (k, (g, t)) in centres.iter().zip(targets).enumerate() {
            // Zero when fewer than three targets (the core leaves the buffer untouched).
            let g = if n < 3 { Vector3::zeros() } else { *g };
            let lever = t.obb.center - b;
            anchor_box.center -= g;
            anchor_box.yaw -= g.dot(&Vector3::z().cross(&lever));
            d_targets[k] = for_object(
                BoxGrad {
                    center: g,
                    ..BoxGrad::ZERO
                },
                t,
            );
        }
        (score, anchor_box)
    });
    Ok((score, for_object(anchor_box, anchor)))
}
