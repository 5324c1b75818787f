//! CNT: matched objects per annotated category against the ObjCount quantifier.

use sceneeval_annotation::ObjCount;
use sceneeval_scene::Scene;

use super::{FidelityEvaluator, ids, spec_count};
use crate::matching::Matching;
use crate::report::{CntSpec, MetricResult};

impl FidelityEvaluator {
    /// The CNT result: one spec per ObjCount entry, satisfied when the number of objects
    /// matched to its category satisfies its quantifier.
    pub(super) fn cnt(
        &self,
        scene: &Scene,
        m: &Matching,
        counts: &[(String, ObjCount)],
    ) -> MetricResult<CntSpec> {
        let specs = counts
            .iter()
            .map(|(text, c)| {
                let objs = m.objects_of(scene, &c.category);
                let n = objs.len() as u64;
                CntSpec {
                    spec: text.clone(),
                    count: spec_count(&c.count),
                    category: c.category.clone(),
                    objects: ids(scene, &objs),
                    count_in_scene: n,
                    satisfied: c.count.holds(n),
                }
            })
            .collect();
        MetricResult::new(
            specs,
            |s| s.satisfied,
            "No object count requirements to evaluate.",
        )
    }
}
