//! ATR: the VLM's verdicts on each matched instance's attributes (from its front and size
//! views); not judged without a VLM.

use sceneeval_annotation::{AnnotationRow, CountSpec, Entry, EntryProblem, Quantifier};
use sceneeval_scene::Scene;
use sceneeval_vlm::tasks::{AttributeKey, AttributeTask, InstanceViews};
use sceneeval_vlm::{Outcome, Vlm};

use super::{FidelityEvaluator, Resources, ids, malformed, spec_count};
use crate::FidelityError;
use crate::matching::{Matching, vlm_err};
use crate::report::{AtrSpec, AttributeAssessment, MetricResult};
use crate::views::ViewKind;

/// Why ATR is not judged without a VLM.
const NO_VLM_ATR: &str = "not judged: no VLM configured (attributes cannot be judged from labels)";

/// One ObjAttr entry: its text, count, category and attributes (several allowed, Q6).
pub(super) struct AttrSpecIn {
    text: String,
    count: CountSpec,
    category: String,
    attributes: Vec<String>,
}

impl FidelityEvaluator {
    /// ObjAttr entries, several attributes allowed (Q6: `q,n,category,attr_1,attr_2,...`).
    pub(super) fn attr_entries(&self, row: &AnnotationRow) -> Result<Vec<AttrSpecIn>, FidelityError> {
        let mut out: Vec<AttrSpecIn> = Vec::new();
        for e in &row.obj_attr {
            let spec = match e {
                Entry::Parsed(a) => AttrSpecIn {
                    text: a.to_string(),
                    count: a.count,
                    category: a.category.clone(),
                    attributes: vec![a.attribute.clone()],
                },
                Entry::Malformed(m) => {
                    let parts: Vec<&str> = m.text().split(',').map(str::trim).collect();
                    let only_field_count = m
                        .problems()
                        .iter()
                        .all(|p| matches!(p, EntryProblem::WrongFieldCount { .. }));
                    let q = parts.first().and_then(|q| q.parse::<Quantifier>().ok());
                    let n = parts.get(1).and_then(|n| n.parse::<u64>().ok());
                    match (only_field_count && parts.len() > 4, q, n) {
                        (true, Some(q), Some(n)) if parts[2..].iter().all(|p| !p.is_empty()) => AttrSpecIn {
                            text: parts.join(","),
                            count: CountSpec::new(q, n),
                            category: parts[2].to_owned(),
                            attributes: parts[3..].iter().map(|s| (*s).to_owned()).collect(),
                        },
                        _ => return Err(malformed(row, "ObjAttr", m.text(), m.problems())),
                    }
                }
            };
            if !self.params.keep_duplicate_specs && out.iter().any(|s| s.text == spec.text) {
                continue;
            }
            out.push(spec);
        }
        Ok(out)
    }

    /// The ATR result: per ObjAttr spec, the instances the VLM finds having every attribute,
    /// against the quantifier.
    pub(super) fn atr<V: Vlm>(
        &self,
        scene: &Scene,
        m: &Matching,
        attrs: &[AttrSpecIn],
        res: &Resources<'_, V>,
    ) -> Result<MetricResult<AtrSpec>, FidelityError> {
        let mut specs = Vec::new();
        let judged = res.session.is_some() && res.views.is_some();
        for a in attrs {
            let objs = m.objects_of(scene, &a.category);
            let mut spec = AtrSpec {
                spec: a.text.clone(),
                count: spec_count(&a.count),
                category: a.category.clone(),
                attributes: a.attributes.clone(),
                objects: ids(scene, &objs),
                count_satisfied: None,
                assessments: Vec::new(),
                unanswered: None,
                note: None,
                satisfied: None,
            };
            if objs.is_empty() {
                if self.params.presence_gate_respects_quantifier {
                    spec.count_satisfied = Some(0);
                    spec.satisfied = Some(a.count.holds(0));
                    spec.note =
                        Some("no object of the category: decided by the quantifier on a count of 0".into());
                } else {
                    spec.satisfied = Some(false);
                    spec.note =
                        Some("no object of the category: unsatisfied (reference presence gate, Q5)".into());
                }
                specs.push(spec);
                continue;
            }
            let (Some(session), Some(views)) = (res.session, res.views) else {
                specs.push(spec);
                continue;
            };
            let mut instances = Vec::with_capacity(objs.len());
            for &i in &objs {
                let id = scene.objects()[i].id().as_str();
                instances.push(InstanceViews {
                    front: views.view(id, ViewKind::Front)?,
                    size: views.view(id, ViewKind::Size)?,
                });
            }
            let task = AttributeTask::new(a.category.clone(), a.attributes.clone(), instances)
                .map_err(|e| vlm_err("obj_attribute", e))?;
            let answers = pollster::block_on(session.ask(&task)).map_err(|e| vlm_err("obj_attribute", e))?;
            let mut count = 0u64;
            let mut problems = Vec::new();
            for (k, &i) in objs.iter().enumerate() {
                let id = scene.objects()[i].id().as_str().to_owned();
                let mut all = true;
                for attr in &a.attributes {
                    let key = AttributeKey {
                        instance: k,
                        attribute: attr.clone(),
                    };
                    let (sat, reason) = match answers.get(&key) {
                        Some(Outcome::Answered { answer, .. }) => {
                            (Some(answer.satisfied), answer.reason.clone())
                        }
                        Some(Outcome::Unanswered(why)) => {
                            problems.push(format!("{id}/{attr}: {why}"));
                            (None, format!("unanswered: {why}"))
                        }
                        None => {
                            problems.push(format!("{id}/{attr}: not asked"));
                            (None, "unanswered".into())
                        }
                    };
                    all &= sat == Some(true);
                    spec.assessments.push(AttributeAssessment {
                        object: id.clone(),
                        attribute: attr.clone(),
                        satisfied: sat,
                        reason,
                    });
                }
                count += u64::from(all);
            }
            if !problems.is_empty() {
                spec.unanswered = Some(problems.join("; "));
            }
            spec.count_satisfied = Some(count);
            spec.satisfied = Some(a.count.holds(count));
            specs.push(spec);
        }
        Ok(if judged || specs.is_empty() {
            MetricResult::new(
                specs,
                |s| s.satisfied == Some(true),
                "No object attribute requirements to evaluate.",
            )
        } else {
            MetricResult::not_judged(specs, NO_VLM_ATR)
        })
    }
}
