//! A bounding-volume hierarchy over boxes (parry's [`Bvh`]): the metrics ask it which objects
//! (or floor pieces) a region can touch instead of testing every one, so a query costs about
//! `log n` box tests plus the candidates found.

use std::sync::atomic::{AtomicU64, Ordering};

use sceneeval_geom::parry::bounding_volume::{Aabb as PAabb, BoundingVolume};
use sceneeval_geom::parry::math::Vector as PVector;
use sceneeval_geom::parry::partitioning::{Bvh, BvhBuildStrategy, TraversalAction};
use sceneeval_geom::{Aabb, Point2, Real};
use serde::{Deserialize, Serialize};

/// The work of the spatial-index queries of a metric ([`crate::support_with_work`],
/// [`crate::accessibility_with_work`]): what bounds its cost, deterministic unlike times.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct IndexWork {
    /// Boxes tested against a query region (index nodes and leaves).
    pub box_tests: u64,
    /// Candidates returned (items whose box meets a query region).
    pub candidates: u64,
}

/// Counters shared by the threads of one metric.
#[derive(Debug, Default)]
pub(crate) struct WorkCounter {
    box_tests: AtomicU64,
    candidates: AtomicU64,
}

impl WorkCounter {
    /// The totals.
    pub fn total(&self) -> IndexWork {
        IndexWork {
            box_tests: self.box_tests.load(Ordering::Relaxed),
            candidates: self.candidates.load(Ordering::Relaxed),
        }
    }
}

/// A hierarchy over items' boxes, queried by box.
pub(crate) struct BoxIndex {
    bvh: Bvh,
    len: usize,
}

fn to_parry(b: &Aabb) -> PAabb {
    PAabb::new(
        PVector::new(b.min.x, b.min.y, b.min.z),
        PVector::new(b.max.x, b.max.y, b.max.z),
    )
}

/// A flat 3-D box standing for a 2-D rectangle `(min, max)`.
pub(crate) fn flat(b: &(Point2, Point2)) -> Aabb {
    Aabb {
        min: sceneeval_geom::Point3::new(b.0.x, b.0.y, 0.0),
        max: sceneeval_geom::Point3::new(b.1.x, b.1.y, 0.0),
    }
}

impl BoxIndex {
    /// The index over `boxes` (item `i` is `boxes[i]`).
    pub fn new(boxes: &[Aabb]) -> Self {
        let leaves: Vec<PAabb> = boxes.iter().map(to_parry).collect();
        BoxIndex {
            bvh: Bvh::from_leaves(BvhBuildStrategy::Binned, &leaves),
            len: boxes.len(),
        }
    }

    /// The items whose boxes meet `region` (closed boxes), in increasing order.
    pub fn query(&self, region: &Aabb, work: &WorkCounter) -> Vec<usize> {
        let mut out = Vec::new();
        if self.len == 0 {
            return out;
        }
        let q = to_parry(region);
        let mut tests: u64 = 0;
        self.bvh.traverse(|node| {
            tests += 1;
            if !node.aabb().intersects(&q) {
                return TraversalAction::Prune;
            }
            if let Some(leaf) = node.leaf_data() {
                out.push(leaf as usize);
            }
            TraversalAction::Continue
        });
        out.sort_unstable();
        work.box_tests.fetch_add(tests, Ordering::Relaxed);
        work.candidates.fetch_add(out.len() as u64, Ordering::Relaxed);
        out
    }

    /// [`BoxIndex::query`] with a 2-D rectangle `(min, max)` against flat boxes.
    pub fn query_flat(&self, region: &(Point2, Point2), work: &WorkCounter) -> Vec<usize> {
        self.query(&flat(region), work)
    }
}

/// Grows a rectangle by `margin` on every side.
pub(crate) fn grown(b: &(Point2, Point2), margin: Real) -> (Point2, Point2) {
    let m = sceneeval_geom::Vector2::repeat(margin);
    (b.0 - m, b.1 + m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::Point3;

    #[test]
    fn finds_exactly_the_overlapping_boxes_with_few_tests() {
        // A 40 x 40 grid of unit boxes spaced 2 m apart.
        let boxes: Vec<Aabb> = (0..1600)
            .map(|k| {
                let (x, y) = (f64::from(k % 40) * 2.0, f64::from(k / 40) * 2.0);
                Aabb::new(Point3::new(x, y, 0.0), Point3::new(x + 1.0, y + 1.0, 1.0))
            })
            .collect();
        let index = BoxIndex::new(&boxes);
        let work = WorkCounter::default();
        let region = Aabb::new(Point3::new(3.5, 3.5, 0.5), Point3::new(6.5, 4.5, 0.6));
        let found = index.query(&region, &work);
        let brute: Vec<usize> = (0..boxes.len())
            .filter(|&i| boxes[i].intersects(&region))
            .collect();
        assert_eq!(found, brute);
        // Boxes x in [4, 5] and [6, 7] of row y in [4, 5]: items 2 * 40 + 2 and + 3.
        assert_eq!(found, vec![82, 83]);
        let w = work.total();
        assert_eq!(w.candidates, 2);
        assert!(w.box_tests < 100, "{w:?}");
        assert!(BoxIndex::new(&[]).query(&region, &work).is_empty());
    }
}
