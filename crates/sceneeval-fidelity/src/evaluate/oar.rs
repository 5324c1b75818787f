//! OAR: object-architecture relationships. Each spec's relationship is mapped onto a
//! predicate against its first known architecture reference (the lexicon, or the VLM with the
//! reference's prompt) and evaluated for every object matched to its category; the satisfied
//! objects are counted against its quantifier.

use sceneeval_annotation::{ArchRef, OaRel};
use sceneeval_relations::{Relation, RelationError};
use sceneeval_scene::Scene;
use sceneeval_scene::label::{Synset, normalise};
use sceneeval_vlm::tasks::{ArchRelationSpec, ArchRelationTask};
use sceneeval_vlm::{Outcome, Vlm};

use super::mapping::{self, info};
use super::{FidelityEvaluator, Resources, spec_count};
use crate::lexicon::{Lookup, map_arch};
use crate::matching::{Matching, vlm_err};
use crate::report::{ArchCandidate, MappingSource, MappingStatus, MetricResult, OarSpec};
use crate::{FidelityError, RelationMapping};

impl FidelityEvaluator {
    /// The OAR result: each OARel spec's relationship mapped onto a predicate (lexicon or
    /// VLM), evaluated for every matched object, the satisfied objects counted against its
    /// quantifier.
    pub(super) fn oar<V: Vlm>(
        &self,
        scene: &Scene,
        m: &Matching,
        rels: &[(String, OaRel)],
        res: &Resources<'_, V>,
        warnings: &mut Vec<String>,
    ) -> Result<MetricResult<OarSpec>, FidelityError> {
        let floor_ids: Vec<String> = scene.rooms().iter().map(|r| r.floor_id().to_owned()).collect();
        let mut specs: Vec<(OarSpec, Option<Relation>)> = Vec::new();
        let mut ask: Vec<ArchRelationSpec> = Vec::new();
        for (k, (text, r)) in rels.iter().enumerate() {
            let present = !m.objects_of(scene, &r.object.category).is_empty();
            let mut spec = OarSpec {
                spec: text.clone(),
                count: spec_count(&r.count),
                relationship: r.relationship.clone(),
                obj_reference: r.object.to_string(),
                arch_references: r.arch.iter().map(|a| a.as_str().to_owned()).collect(),
                obj_present: present,
                mapping: info(
                    MappingStatus::NotNeeded,
                    MappingSource::None,
                    "the object is absent",
                ),
                floors: Vec::new(),
                candidates: Vec::new(),
                count_satisfied: 0,
                satisfied: false,
            };
            let mut relation = None;
            if present {
                let lookup = if self.params.relation_mapping == RelationMapping::Lexicon {
                    match r.arch.iter().find_map(ArchRef::element) {
                        Some(c) => map_arch(&r.relationship, c),
                        None => Lookup::Unmapped {
                            reason: format!("no known architecture element among {:?}", spec.arch_references),
                        },
                    }
                } else {
                    Lookup::Unknown
                };
                match lookup {
                    Lookup::Mapped { mapping, word } => {
                        spec.mapping = mapping::by_lexicon(word, &[mapping]);
                        spec.floors = room_floors(scene, &r.arch, warnings, text);
                        relation = Some(mapping);
                    }
                    Lookup::Unmapped { reason } => {
                        spec.mapping = info(MappingStatus::Unmapped, MappingSource::Lexicon, &reason);
                    }
                    Lookup::Unknown => {
                        let asked = res.session.is_some() && !floor_ids.is_empty();
                        if asked {
                            ask.push(ArchRelationSpec {
                                key: k.to_string(),
                                relationship: r.relationship.clone(),
                                object: r.object.to_string(),
                                architecture: spec.arch_references.clone(),
                            });
                        }
                        spec.mapping = mapping::not_in_lexicon(&r.relationship, asked);
                    }
                }
            }
            specs.push((spec, relation));
        }
        if let (Some(session), false) = (res.session, ask.is_empty()) {
            let task = ArchRelationTask::new(ask, floor_ids.clone())
                .map_err(|e| vlm_err("arch_relationship_mapping", e))?;
            let answers = pollster::block_on(session.ask(&task))
                .map_err(|e| vlm_err("arch_relationship_mapping", e))?;
            for (key, outcome) in answers.outcomes {
                let Some((spec, relation)) = key.parse::<usize>().ok().and_then(|k| specs.get_mut(k)) else {
                    continue;
                };
                match outcome {
                    Outcome::Answered { answer, .. } => match answer.relation {
                        Some(r) => {
                            spec.mapping = mapping::by_vlm(&[r], answer.reason);
                            spec.floors = answer.floors;
                            *relation = Some(r);
                        }
                        None => {
                            spec.mapping = info(MappingStatus::Unmapped, MappingSource::Vlm, &answer.reason)
                        }
                    },
                    Outcome::Unanswered(why) => spec.mapping = mapping::unanswered(&why),
                }
            }
        }
        let mut out = Vec::with_capacity(specs.len());
        for ((_, r), (mut spec, relation)) in rels.iter().zip(specs) {
            if !spec.obj_present {
                spec.satisfied = self.absent_verdict(&r.count);
            } else if let Some(rel) = relation {
                let floors: Vec<&str> = spec.floors.iter().map(String::as_str).collect();
                for i in m.objects_of(scene, &r.object.category) {
                    let id = scene.objects()[i].id().as_str().to_owned();
                    let (score, holds) = match self.relations.arch(scene, rel, i, &floors) {
                        Ok(e) => (e.score, e.holds),
                        Err(e @ RelationError::NoArchitecture { .. }) => {
                            warnings.push(format!("OAR spec {:?}: {e}; counted as unsatisfied", spec.spec));
                            (0.0, false)
                        }
                        Err(source) => {
                            return Err(FidelityError::Relation {
                                spec: spec.spec.clone(),
                                relation: rel.to_string(),
                                source,
                            });
                        }
                    };
                    spec.count_satisfied += u64::from(holds);
                    spec.candidates.push(ArchCandidate {
                        object: id,
                        score,
                        holds,
                    });
                }
                spec.satisfied = r.count.holds(spec.count_satisfied);
            } else {
                spec.satisfied = self.unmapped_verdict(&spec.mapping);
            }
            out.push(spec);
        }
        Ok(MetricResult::new(
            out,
            |s| s.satisfied,
            "No object-architecture relationship specs to evaluate.",
        ))
    }
}

/// The floors a relation with these architecture references is restricted to: the rooms whose
/// id contains a referenced room type (`bedroom`); none for plain elements.
fn room_floors(scene: &Scene, arch: &[ArchRef], warnings: &mut Vec<String>, spec: &str) -> Vec<String> {
    let mut out = Vec::new();
    for a in arch {
        if let ArchRef::RoomType(t) = a {
            let t = normalise(t, Synset::Keep);
            let hits: Vec<String> = scene
                .rooms()
                .iter()
                .filter(|r| {
                    normalise(r.id().as_str(), Synset::Keep).contains(&t)
                        || normalise(r.floor_id(), Synset::Keep).contains(&t)
                })
                .map(|r| r.floor_id().to_owned())
                .collect();
            if hits.is_empty() {
                warnings.push(format!(
                    "OAR spec {spec:?}: no room id contains {t:?}; every room is considered"
                ));
            }
            out.extend(hits);
        }
    }
    out.dedup();
    out
}
