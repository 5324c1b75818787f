//! OAR: object-architecture relationships. Each spec's relationship is mapped onto a
//! predicate against its first known architecture reference (the lexicon, or the VLM with the
//! reference's prompt) and evaluated for every object matched to its category; the satisfied
//! objects are counted against its quantifier.

use sceneeval_annotation::{ArchRef, CountRange, OaRel};
use sceneeval_relations::{Relation, RelationError};
use sceneeval_scene::Scene;
use sceneeval_scene::label::{Synset, normalise};
use sceneeval_vlm::tasks::{ArchRelationSpec, ArchRelationTask};
use sceneeval_vlm::{Outcome, Vlm};

use super::mapping::{self, info};
use super::undecided::{Unknown, verdict_over};
use super::{FidelityEvaluator, Resources, spec_count};
use crate::lexicon::{Lookup, map_arch};
use crate::matching::{Matching, vlm_err, with_note};
use crate::report::{
    ArchCandidate, MappingSource, MappingStatus, MetricResult, OarSpec, RelationMappingInfo,
};
use crate::{FidelityError, RelationMapping};

/// How one OARel spec's relationship maps onto a predicate, known before the matching: from
/// the lexicon, or from the VLM (asked for every spec whose word the lexicon does not know).
pub(super) struct OarMapping {
    info: RelationMappingInfo,
    relation: Option<Relation>,
    /// The floors the VLM restricted the relation to; `None` for the lexicon's mappings (the
    /// room types among the architecture references decide).
    floors: Option<Vec<String>>,
}

impl FidelityEvaluator {
    /// The mapping of every OARel spec: the lexicon's (against the spec's first known
    /// architecture element, with [`RelationMapping::Lexicon`]), and the VLM's for the others,
    /// in one request (not asked when the scene has no floor to offer). Asked while the
    /// objects are being matched, as [`Self::oor_mappings`].
    ///
    /// # Errors
    /// [`FidelityError::Vlm`] when the request gets no answer at all.
    pub(super) async fn oar_mappings<V: Vlm>(
        &self,
        rels: &[(String, OaRel)],
        floor_ids: &[String],
        res: &Resources<'_, V>,
    ) -> Result<Vec<OarMapping>, FidelityError> {
        let mut mappings: Vec<OarMapping> = Vec::with_capacity(rels.len());
        let mut ask: Vec<ArchRelationSpec> = Vec::new();
        for (k, (_, r)) in rels.iter().enumerate() {
            let arch_references: Vec<String> = r.arch.iter().map(|a| a.as_str().to_owned()).collect();
            let lookup = match self.params.relation_mapping {
                RelationMapping::Lexicon => match r.arch.iter().find_map(ArchRef::element) {
                    Some(c) => map_arch(&r.relationship, c),
                    None => Lookup::Unmapped {
                        reason: format!("no known architecture element among {arch_references:?}"),
                    },
                },
                RelationMapping::Vlm => Lookup::Unknown,
            };
            let mut p = OarMapping {
                info: info(MappingStatus::Unmapped, MappingSource::None, ""),
                relation: None,
                floors: None,
            };
            match lookup {
                Lookup::Mapped { mapping, word } => {
                    p.info = mapping::by_lexicon(word, &[mapping]);
                    p.relation = Some(mapping);
                }
                Lookup::Unmapped { reason } => {
                    p.info = info(MappingStatus::Unmapped, MappingSource::Lexicon, &reason);
                }
                Lookup::Unknown => {
                    let asked = res.session.is_some() && !floor_ids.is_empty();
                    if asked {
                        ask.push(ArchRelationSpec {
                            key: k.to_string(),
                            relationship: r.relationship.clone(),
                            object: r.object.to_string(),
                            architecture: arch_references,
                        });
                    }
                    p.info = mapping::not_in_lexicon(&r.relationship, asked);
                }
            }
            mappings.push(p);
        }
        if let (Some(session), false) = (res.session, ask.is_empty()) {
            let task = ArchRelationTask::new(ask, floor_ids.iter().cloned())
                .map_err(|e| vlm_err("arch_relationship_mapping", e))?;
            let answers = session
                .ask(&task)
                .await
                .map_err(|e| vlm_err("arch_relationship_mapping", e))?;
            for (key, outcome) in answers.outcomes {
                let Some(p) = key.parse::<usize>().ok().and_then(|k| mappings.get_mut(k)) else {
                    continue;
                };
                match outcome {
                    Outcome::Answered { answer, note, .. } => {
                        let reason = with_note(answer.reason, note);
                        match answer.relation {
                            Some(r) => {
                                p.info = mapping::by_vlm(&[r], reason);
                                p.floors = Some(answer.floors);
                                p.relation = Some(r);
                            }
                            None => p.info = info(MappingStatus::Unmapped, MappingSource::Vlm, &reason),
                        }
                    }
                    Outcome::Unanswered(why) => p.info = mapping::unanswered(&why),
                }
            }
        }
        Ok(mappings)
    }

    /// The OAR result: each OARel spec's relationship mapped onto a predicate (`mappings`,
    /// from [`Self::oar_mappings`]), evaluated for every matched object, the satisfied objects
    /// counted against its quantifier. A spec without a verdict: its mapping is unanswered, or
    /// objects without a matching answer could change it (each could be one more candidate).
    ///
    /// # Errors
    /// A predicate that cannot be evaluated (other than for a scene without the architecture,
    /// which counts as unsatisfied with a warning).
    pub(super) fn oar(
        &self,
        scene: &Scene,
        m: &Matching,
        unknown: Unknown<'_>,
        rels: &[(String, OaRel)],
        mappings: Vec<OarMapping>,
        warnings: &mut Vec<String>,
    ) -> Result<MetricResult<OarSpec>, FidelityError> {
        let u = unknown.count();
        let mut out = Vec::with_capacity(rels.len());
        for ((text, r), p) in rels.iter().zip(mappings) {
            let objects = m.objects_of(scene, &r.object.category);
            let present = !objects.is_empty();
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
                unanswered: None,
                satisfied: None,
            };
            if !present {
                spec.satisfied = match (u, p.relation) {
                    (0, _) => Some(self.absent_verdict(&r.count)),
                    // The unknown objects could be of the category: up to `u` candidates.
                    (u, Some(_)) => {
                        self.absent_or_present(&r.count, verdict_over(&r.count, CountRange::between(0, u)))
                    }
                    (_, None) => self.absent_or_present(&r.count, self.unmapped_verdict(&p.info)),
                };
                if spec.satisfied.is_none() {
                    spec.unanswered = Some(unknown.reason());
                }
                out.push(spec);
                continue;
            }
            spec.mapping = p.info;
            let Some(rel) = p.relation else {
                spec.satisfied = self.unmapped_verdict(&spec.mapping);
                if spec.satisfied.is_none() {
                    spec.unanswered = Some(mapping::unanswered_reason(&spec.mapping));
                }
                out.push(spec);
                continue;
            };
            spec.floors = match p.floors {
                Some(floors) => floors,
                None => room_floors(scene, &r.arch, warnings, text),
            };
            let floors: Vec<&str> = spec.floors.iter().map(String::as_str).collect();
            for i in objects {
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
            let c = spec.count_satisfied;
            spec.satisfied = verdict_over(&r.count, CountRange::between(c, c + u));
            if spec.satisfied.is_none() {
                spec.unanswered = Some(unknown.reason());
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
