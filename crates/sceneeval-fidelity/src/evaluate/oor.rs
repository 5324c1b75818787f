//! OOR: object-object relationships. Each spec's relationship is mapped onto predicates (the
//! lexicon, or the VLM with the reference's prompt); its candidate groups (an anchor and
//! combinations of the other objects, per category) are scored, and the satisfied groups are
//! counted against its quantifier.

use std::collections::BTreeMap;

use sceneeval_annotation::{CountRange, OoRel, binomial};
use sceneeval_relations::{Relation, RelationKind};
use sceneeval_scene::Scene;
use sceneeval_vlm::tasks::{ObjectRelationSpec, ObjectRelationTask};
use sceneeval_vlm::{Outcome, Vlm};

use super::mapping::{self, info};
use super::undecided::{Unknown, verdict_over};
use super::{FidelityEvaluator, Resources, ids, spec_count};
use crate::lexicon::{Lookup, map_object};
use crate::matching::{Matching, vlm_err, with_note};
use crate::report::{
    CandidateGroup, MappingSource, MappingStatus, MetricResult, OorSpec, Participants, PredicateResult,
    RelationMappingInfo,
};
use crate::{FidelityError, RelationMapping};

/// At most this many candidate groups per OOR spec are recorded with their scores in the
/// report (all are evaluated, up to the cap).
pub const MAX_RECORDED_GROUPS: usize = 64;

/// How one OORel spec's relationship maps onto predicates, known before the matching: from the
/// lexicon, or from the VLM (asked for every spec whose word the lexicon does not know).
pub(super) struct OorMapping {
    participants: Option<Participants>,
    relations: Vec<Relation>,
    info: RelationMappingInfo,
}

impl FidelityEvaluator {
    /// The mapping of every OORel spec: the lexicon's (with [`RelationMapping::Lexicon`]), and
    /// the VLM's for the others, in one request. The mappings need only the annotation row, so
    /// they are asked while the objects are being matched (the reference asks only for the
    /// specs whose objects are present, once the matching is known).
    ///
    /// # Errors
    /// [`FidelityError::Vlm`] when the request gets no answer at all.
    pub(super) async fn oor_mappings<V: Vlm>(
        &self,
        rels: &[(String, OoRel)],
        res: &Resources<'_, V>,
    ) -> Result<Vec<OorMapping>, FidelityError> {
        let mut mappings: Vec<OorMapping> = Vec::with_capacity(rels.len());
        let mut ask: Vec<ObjectRelationSpec> = Vec::new();
        for (k, (_, r)) in rels.iter().enumerate() {
            let lookup = match self.params.relation_mapping {
                RelationMapping::Lexicon => map_object(&r.relationship),
                RelationMapping::Vlm => Lookup::Unknown,
            };
            let mut p = OorMapping {
                participants: None,
                relations: Vec::new(),
                info: info(MappingStatus::Unmapped, MappingSource::None, ""),
            };
            match lookup {
                Lookup::Mapped { mapping, word } => {
                    p.participants = Some(lexicon_participants(r));
                    p.info = mapping::by_lexicon(word, &mapping);
                    p.relations = mapping;
                }
                Lookup::Unmapped { reason } => {
                    p.info = info(MappingStatus::Unmapped, MappingSource::Lexicon, &reason);
                }
                Lookup::Unknown => {
                    let asked = res.session.is_some();
                    if asked {
                        ask.push(ObjectRelationSpec {
                            key: k.to_string(),
                            relationship: r.relationship.clone(),
                            objects: r.refs.iter().map(ToString::to_string).collect(),
                            anchor_index: r.anchor,
                        });
                    }
                    p.info = mapping::not_in_lexicon(&r.relationship, asked);
                }
            }
            mappings.push(p);
        }
        if let (Some(session), false) = (res.session, ask.is_empty()) {
            let task = ObjectRelationTask::new(ask).map_err(|e| vlm_err("obj_relationship_mapping", e))?;
            let answers = session
                .ask(&task)
                .await
                .map_err(|e| vlm_err("obj_relationship_mapping", e))?;
            for (key, outcome) in answers.outcomes {
                let Some(p) = key.parse::<usize>().ok().and_then(|k| mappings.get_mut(k)) else {
                    continue;
                };
                match outcome {
                    Outcome::Answered { answer, note, .. } => {
                        p.participants = Some(Participants {
                            anchor: answer.anchor_object.clone(),
                            others: answer.other_objects.clone(),
                        });
                        let reason = with_note(answer.reason, note);
                        match answer.relations {
                            Some(rs) if !rs.is_empty() => {
                                p.info = mapping::by_vlm(&rs, reason);
                                p.relations = rs;
                            }
                            _ => p.info = info(MappingStatus::Unmapped, MappingSource::Vlm, &reason),
                        }
                    }
                    Outcome::Unanswered(why) => p.info = mapping::unanswered(&why),
                }
            }
        }
        Ok(mappings)
    }

    /// The OOR result: each OORel spec's relationship mapped onto predicates (`mappings`,
    /// from [`Self::oor_mappings`]), its candidate groups scored, the satisfied groups counted
    /// against its quantifier. A spec without a verdict: its mapping is unanswered, or objects
    /// without a matching answer could change it (more objects only add groups).
    ///
    /// # Errors
    /// A predicate that cannot be evaluated.
    pub(super) fn oor(
        &self,
        scene: &Scene,
        m: &Matching,
        unknown: Unknown<'_>,
        rels: &[(String, OoRel)],
        mappings: Vec<OorMapping>,
        warnings: &mut Vec<String>,
    ) -> Result<MetricResult<OorSpec>, FidelityError> {
        let mut specs = Vec::new();
        for ((text, r), p) in rels.iter().zip(mappings) {
            let mut mentions: BTreeMap<&str, usize> = BTreeMap::new();
            for o in &r.refs {
                *mentions.entry(o.category.as_str()).or_default() += 1;
            }
            let missing: usize = mentions
                .iter()
                .map(|(c, n)| n.saturating_sub(m.objects_of(scene, c).len()))
                .sum();
            let present = missing == 0;
            let mut spec = OorSpec {
                spec: text.clone(),
                count: spec_count(&r.count),
                relationship: r.relationship.clone(),
                anchor_index: r.anchor.map_or(-1, |a| a as i64),
                obj_references: r.refs.iter().map(ToString::to_string).collect(),
                all_objects_present: present,
                participants: None,
                mapping: info(
                    MappingStatus::NotNeeded,
                    MappingSource::None,
                    "an object of the relation is absent",
                ),
                num_candidate_groups: 0,
                groups_evaluated: 0,
                groups: Vec::new(),
                count_satisfied: 0,
                unanswered: None,
                satisfied: None,
            };
            // With objects without a matching answer, more groups may exist: the count of
            // satisfied groups can only grow.
            let more = if unknown.count() > 0 { None } else { Some(0) };
            if !present {
                spec.satisfied = if (missing as u64) <= unknown.count() {
                    // The unknown objects could make the spec present.
                    let when_present = match p.info.status {
                        MappingStatus::Mapped => verdict_over(&r.count, CountRange::ANY),
                        _ => self.unmapped_verdict(&p.info),
                    };
                    self.absent_or_present(&r.count, when_present)
                } else {
                    Some(self.absent_verdict(&r.count))
                };
                if spec.satisfied.is_none() {
                    spec.unanswered = Some(unknown.reason());
                }
                specs.push(spec);
                continue;
            }
            spec.participants = p.participants.clone();
            spec.mapping = p.info;
            if spec.mapping.status != MappingStatus::Mapped {
                spec.satisfied = self.unmapped_verdict(&spec.mapping);
                if spec.satisfied.is_none() {
                    spec.unanswered = Some(mapping::unanswered_reason(&spec.mapping));
                }
            } else if let Some(parts) = &p.participants {
                self.groups(scene, m, parts, &p.relations, &mut spec, warnings)?;
                let c = spec.count_satisfied;
                spec.satisfied = verdict_over(
                    &r.count,
                    CountRange {
                        min: c,
                        max: more.map(|x| c + x),
                    },
                );
                if spec.satisfied.is_none() {
                    spec.unanswered = Some(unknown.reason());
                }
            }
            specs.push(spec);
        }
        let mut result = MetricResult::new(
            specs,
            |s| s.satisfied,
            "No object-object relationship specs to evaluate.",
        );
        result.note_absent_objects();
        Ok(result)
    }

    /// Enumerates and evaluates the candidate groups of a mapped OOR spec.
    fn groups(
        &self,
        scene: &Scene,
        m: &Matching,
        parts: &Participants,
        relations: &[Relation],
        spec: &mut OorSpec,
        warnings: &mut Vec<String>,
    ) -> Result<(), FidelityError> {
        let anchors = m.objects_of(scene, &parts.anchor);
        let pools: Vec<(Vec<usize>, usize)> = parts
            .others
            .iter()
            .map(|(c, k)| (m.objects_of(scene, c), *k))
            .collect();
        let exclude = !self.params.anchor_may_be_target;
        // Total groups: sum over anchors of the product of binomials (saturating).
        let mut total: u64 = 0;
        for &a in &anchors {
            let mut prod: u64 = 1;
            for (pool, k) in &pools {
                let n = pool.iter().filter(|&&o| !(exclude && o == a)).count();
                prod = prod.saturating_mul(choices(n, *k));
            }
            total = total.saturating_add(prod);
        }
        spec.num_candidate_groups = total;
        let cap = self.params.max_candidate_groups;
        if total > cap {
            let w = format!(
                "OOR spec {:?}: {total} candidate groups, only the first {cap} evaluated (max_candidate_groups)",
                spec.spec
            );
            tracing::warn!("{w}");
            warnings.push(w);
        }
        let mut evaluated = 0u64;
        let mut satisfied = 0u64;
        'anchors: for &a in &anchors {
            let lists: Vec<(Vec<usize>, usize)> = pools
                .iter()
                .map(|(pool, k)| {
                    (
                        pool.iter().copied().filter(|&o| !(exclude && o == a)).collect(),
                        *k,
                    )
                })
                .collect();
            // Odometer over the combinations of each category.
            let mut combos: Vec<Vec<usize>> = Vec::with_capacity(lists.len());
            for (pool, k) in &lists {
                if *k > pool.len() {
                    continue 'anchors;
                }
                combos.push((0..*k).collect());
            }
            loop {
                if evaluated >= cap {
                    break 'anchors;
                }
                let others: Vec<usize> = lists
                    .iter()
                    .zip(&combos)
                    .flat_map(|((pool, _), c)| c.iter().map(move |&i| pool[i]))
                    .collect();
                let group = self.evaluate_group(scene, a, &others, relations, &spec.spec)?;
                evaluated += 1;
                satisfied += u64::from(group.satisfied);
                if spec.groups.len() < MAX_RECORDED_GROUPS {
                    spec.groups.push(group);
                }
                // Advance the last category's combination first (itertools.product order).
                let mut j = combos.len();
                loop {
                    if j == 0 {
                        continue 'anchors;
                    }
                    j -= 1;
                    if next_combination(&mut combos[j], lists[j].0.len()) {
                        break;
                    }
                    combos[j] = (0..lists[j].1).collect();
                }
            }
        }
        spec.groups_evaluated = evaluated;
        spec.count_satisfied = satisfied;
        Ok(())
    }

    fn evaluate_group(
        &self,
        scene: &Scene,
        anchor: usize,
        others: &[usize],
        relations: &[Relation],
        spec: &str,
    ) -> Result<CandidateGroup, FidelityError> {
        let mut results = Vec::with_capacity(relations.len());
        for &r in relations {
            let e = match r.kind() {
                RelationKind::MultiTarget => self.relations.surround(scene, others, anchor),
                _ => self.relations.pair(scene, r, others[0], anchor),
            }
            .map_err(|source| FidelityError::Relation {
                spec: spec.to_owned(),
                relation: r.to_string(),
                source,
            })?;
            results.push(PredicateResult {
                relation: r.to_string(),
                score: e.score,
                holds: e.holds,
            });
        }
        Ok(CandidateGroup {
            anchor: scene.objects()[anchor].id().as_str().to_owned(),
            others: ids(scene, others),
            satisfied: results.iter().all(|x| x.holds),
            results,
        })
    }
}

/// The lexicon's participants: the anchor reference (index, or the first) and the other
/// references grouped by category in order of appearance, each reference one object.
fn lexicon_participants(r: &OoRel) -> Participants {
    let a = r.anchor.unwrap_or(0).min(r.refs.len().saturating_sub(1));
    let anchor = r.refs.get(a).map(|o| o.category.clone()).unwrap_or_default();
    let mut others: Vec<(String, usize)> = Vec::new();
    for (i, o) in r.refs.iter().enumerate() {
        if i == a {
            continue;
        }
        match others.iter_mut().find(|(c, _)| *c == o.category) {
            Some((_, n)) => *n += 1,
            None => others.push((o.category.clone(), 1)),
        }
    }
    Participants { anchor, others }
}

/// `n choose k` as a count of groups, saturating at `u64::MAX` like the sums and products
/// of the counts.
fn choices(n: usize, k: usize) -> u64 {
    u64::try_from(binomial(n as u64, k as u64)).unwrap_or(u64::MAX)
}

/// Advances `c` (a strictly increasing k-subset of `0..n`) to the next in lexicographic
/// order; false when it was the last.
fn next_combination(c: &mut [usize], n: usize) -> bool {
    let k = c.len();
    let mut i = k;
    while i > 0 {
        i -= 1;
        if c[i] < n - k + i {
            c[i] += 1;
            for j in i + 1..k {
                c[j] = c[j - 1] + 1;
            }
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn choices_and_combinations() {
        assert_eq!(choices(4, 3), 4);
        assert_eq!(choices(6, 6), 1);
        assert_eq!(choices(3, 5), 0);
        // C(200, 100) ~ 9.05e58 does not fit.
        assert_eq!(choices(200, 100), u64::MAX);
        // C(67, 33) = 14226520737620288370 fits; C(68, 34) = 28453041475240576740 does not.
        assert_eq!(choices(67, 33), 14_226_520_737_620_288_370);
        assert_eq!(choices(68, 34), u64::MAX);
        let mut c = vec![0, 1];
        let mut all = vec![c.clone()];
        while next_combination(&mut c, 4) {
            all.push(c.clone());
        }
        // itertools.combinations(range(4), 2)
        assert_eq!(
            all,
            vec![
                vec![0, 1],
                vec![0, 2],
                vec![0, 3],
                vec![1, 2],
                vec![1, 3],
                vec![2, 3]
            ]
        );
    }
}
