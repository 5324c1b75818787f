//! OOR: object-object relationships. Each spec's relationship is mapped onto predicates (the
//! lexicon, or the VLM with the reference's prompt); its candidate groups (an anchor and
//! combinations of the other objects, per category) are scored, and the satisfied groups are
//! counted against its quantifier.

use std::collections::BTreeMap;

use sceneeval_annotation::{OoRel, binomial};
use sceneeval_relations::{Relation, RelationKind};
use sceneeval_scene::Scene;
use sceneeval_vlm::tasks::{ObjectRelationSpec, ObjectRelationTask};
use sceneeval_vlm::{Outcome, Vlm};

use super::mapping::{self, info};
use super::{FidelityEvaluator, Resources, ids, spec_count};
use crate::lexicon::{Lookup, map_object};
use crate::matching::{Matching, vlm_err};
use crate::report::{
    CandidateGroup, MappingSource, MappingStatus, MetricResult, OorSpec, Participants, PredicateResult,
    RelationMappingInfo,
};
use crate::{FidelityError, RelationMapping};

/// At most this many candidate groups per OOR spec are recorded with their scores in the
/// report (all are evaluated, up to the cap).
pub const MAX_RECORDED_GROUPS: usize = 64;

impl FidelityEvaluator {
    /// The OOR result: each OORel spec's relationship mapped onto predicates (lexicon or VLM),
    /// its candidate groups scored, the satisfied groups counted against its quantifier.
    pub(super) fn oor<V: Vlm>(
        &self,
        scene: &Scene,
        m: &Matching,
        rels: &[(String, OoRel)],
        res: &Resources<'_, V>,
        warnings: &mut Vec<String>,
    ) -> Result<MetricResult<OorSpec>, FidelityError> {
        // Presence gate and lexicon first; collect what the VLM must map.
        struct Pending {
            participants: Option<Participants>,
            relations: Vec<Relation>,
            info: RelationMappingInfo,
            present: bool,
        }
        let mut pending: Vec<Pending> = Vec::new();
        let mut ask: Vec<ObjectRelationSpec> = Vec::new();
        for (k, (_, r)) in rels.iter().enumerate() {
            let mut mentions: BTreeMap<&str, usize> = BTreeMap::new();
            for o in &r.refs {
                *mentions.entry(o.category.as_str()).or_default() += 1;
            }
            let present = mentions.iter().all(|(c, n)| m.objects_of(scene, c).len() >= *n);
            let lexical = lexicon_participants(r);
            let mut p = Pending {
                participants: None,
                relations: Vec::new(),
                info: info(
                    MappingStatus::NotNeeded,
                    MappingSource::None,
                    "an object of the relation is absent",
                ),
                present,
            };
            if present {
                let use_lexicon = self.params.relation_mapping == RelationMapping::Lexicon;
                let lookup = if use_lexicon {
                    map_object(&r.relationship)
                } else {
                    Lookup::Unknown
                };
                match lookup {
                    Lookup::Mapped { mapping, word } => {
                        p.participants = Some(lexical);
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
            }
            pending.push(p);
        }
        if let (Some(session), false) = (res.session, ask.is_empty()) {
            let task = ObjectRelationTask::new(ask).map_err(|e| vlm_err("obj_relationship_mapping", e))?;
            let answers =
                pollster::block_on(session.ask(&task)).map_err(|e| vlm_err("obj_relationship_mapping", e))?;
            for (key, outcome) in answers.outcomes {
                let Some(p) = key.parse::<usize>().ok().and_then(|k| pending.get_mut(k)) else {
                    continue;
                };
                match outcome {
                    Outcome::Answered { answer, .. } => {
                        p.participants = Some(Participants {
                            anchor: answer.anchor_object.clone(),
                            others: answer.other_objects.clone(),
                        });
                        match answer.relations {
                            Some(rs) if !rs.is_empty() => {
                                p.info = mapping::by_vlm(&rs, answer.reason);
                                p.relations = rs;
                            }
                            _ => p.info = info(MappingStatus::Unmapped, MappingSource::Vlm, &answer.reason),
                        }
                    }
                    Outcome::Unanswered(why) => p.info = mapping::unanswered(&why),
                }
            }
        }
        let mut specs = Vec::new();
        for ((text, r), p) in rels.iter().zip(pending) {
            let mut spec = OorSpec {
                spec: text.clone(),
                count: spec_count(&r.count),
                relationship: r.relationship.clone(),
                anchor_index: r.anchor.map_or(-1, |a| a as i64),
                obj_references: r.refs.iter().map(ToString::to_string).collect(),
                all_objects_present: p.present,
                participants: p.participants.clone(),
                mapping: p.info,
                num_candidate_groups: 0,
                groups_evaluated: 0,
                groups: Vec::new(),
                count_satisfied: 0,
                satisfied: false,
            };
            if !p.present {
                spec.satisfied = self.absent_verdict(&r.count);
            } else if spec.mapping.status != MappingStatus::Mapped {
                spec.satisfied = self.unmapped_verdict(&spec.mapping);
            } else if let Some(parts) = &p.participants {
                self.groups(scene, m, parts, &p.relations, &mut spec, warnings)?;
                spec.satisfied = r.count.holds(spec.count_satisfied);
            }
            specs.push(spec);
        }
        let mut result = MetricResult::new(
            specs,
            |s| s.satisfied,
            "No object-object relationship specs to evaluate.",
        );
        if result.total > 0 && result.specs.iter().all(|s| !s.all_objects_present) {
            result.message = format!(
                "No object-object relationship specs have all objects present in the scene. {}",
                result.message
            );
        }
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
