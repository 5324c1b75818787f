//! CNT: matched objects per annotated category against the ObjCount quantifier.

use sceneeval_annotation::{CountRange, ObjCount};
use sceneeval_scene::Scene;

use super::undecided::{Unknown, verdict_over};
use super::{FidelityEvaluator, ids, spec_count};
use crate::matching::Matching;
use crate::report::{CntSpec, MetricResult};

impl FidelityEvaluator {
    /// The CNT result: one spec per ObjCount entry, satisfied when the number of objects
    /// matched to its category satisfies its quantifier. Objects without a matching answer
    /// could add to any count: a spec whose verdict they could change has none.
    pub(super) fn cnt(
        &self,
        scene: &Scene,
        m: &Matching,
        unknown: Unknown<'_>,
        counts: &[(String, ObjCount)],
    ) -> MetricResult<CntSpec> {
        let specs = counts
            .iter()
            .map(|(text, c)| {
                let objs = m.objects_of(scene, &c.category);
                let n = objs.len() as u64;
                // The count is n plus any of the unknown objects.
                let satisfied = verdict_over(&c.count, CountRange::between(n, n + unknown.count()));
                CntSpec {
                    unanswered: satisfied.is_none().then(|| unknown.reason()),
                    ..CntSpec::new(
                        text.as_str(),
                        spec_count(&c.count),
                        c.category.as_str(),
                        ids(scene, &objs),
                        satisfied,
                    )
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
