//! [`FidelityEvaluator`]: CNT, ATR, OOR and OAR of one scene against its annotation row.

use std::collections::BTreeMap;

use sceneeval_annotation::{AnnotationRow, ArchRef, CountSpec, Entry, EntryKind, EntryProblem, Quantifier};
use sceneeval_relations::{Relation, RelationKind, RelationParams, SceneRelations};
use sceneeval_scene::Scene;
use sceneeval_vlm::tasks::{
    ArchRelationSpec, ArchRelationTask, AttributeKey, AttributeTask, InstanceViews, ObjectRelationSpec,
    ObjectRelationTask,
};
use sceneeval_vlm::{Outcome, Session, Vlm};

use crate::labels::normalise;
use crate::lexicon::{ElementClass, Lookup, map_arch, map_object};
use crate::matching::{Matching, MatchingRecord, match_by_labels, match_by_vlm, read_matching_file, vlm_err};
use crate::report::*;
use crate::views::{ObjectViews, ViewKind};
use crate::{FidelityError, FidelityMetric, FidelityParams, MatchingMethod, RelationMapping};

/// At most this many candidate groups per OOR spec are recorded with their scores in the
/// report (all are evaluated, up to the cap).
pub const MAX_RECORDED_GROUPS: usize = 64;

/// What a scene's evaluation may use besides the scene and its row: the VLM session, the
/// object views, and the matching file when the plan reads one.
pub struct Resources<'a, V> {
    /// The VLM, when configured.
    pub session: Option<&'a Session<V>>,
    /// The object views, when a renderer (or another source) is available.
    pub views: Option<&'a dyn ObjectViews>,
    /// The scene's name, to find its file when matching from a folder.
    pub scene_name: &'a str,
}

impl<V> std::fmt::Debug for Resources<'_, V> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Resources")
            .field("vlm", &self.session.is_some())
            .field("views", &self.views.is_some())
            .field("scene_name", &self.scene_name)
            .finish()
    }
}

/// A scene's fidelity report and the matching it used (to write as `matching.json`).
#[derive(Debug, Clone)]
pub struct FidelityOutcome {
    /// The report.
    pub report: FidelityReport,
    /// The matching.
    pub matching: MatchingRecord,
}

/// Runs the fidelity metrics with one set of parameters.
#[derive(Debug, Clone)]
pub struct FidelityEvaluator {
    params: FidelityParams,
    relations: SceneRelations,
}

const NO_VLM_ATR: &str = "not judged: no VLM configured (attributes cannot be judged from labels)";

struct AttrSpecIn {
    text: String,
    count: CountSpec,
    category: String,
    attributes: Vec<String>,
}

impl FidelityEvaluator {
    /// An evaluator with these parameters and predicate parameters.
    ///
    /// # Errors
    /// [`FidelityError::InvalidParameter`] for invalid parameters (either kind).
    pub fn new(params: FidelityParams, relations: RelationParams) -> Result<Self, FidelityError> {
        params.validate()?;
        let relations = SceneRelations::new(relations).map_err(|e| FidelityError::InvalidParameter {
            name: "relations",
            message: e.to_string(),
        })?;
        Ok(FidelityEvaluator { params, relations })
    }

    /// The parameters.
    pub fn params(&self) -> &FidelityParams {
        &self.params
    }

    /// Evaluates `metrics` on `scene` against `row`.
    ///
    /// # Errors
    /// A malformed entry ([`FidelityError::MalformedEntry`]), a matching source that is not
    /// available or fails ([`FidelityError::Unavailable`], [`FidelityError::MatchingFile`],
    /// [`FidelityError::MatchingFormat`]), a view that cannot be made, a VLM request without
    /// any answer, a predicate error.
    pub fn evaluate<V: Vlm>(
        &self,
        scene: &Scene,
        row: &AnnotationRow,
        metrics: &[FidelityMetric],
        res: &Resources<'_, V>,
    ) -> Result<FidelityOutcome, FidelityError> {
        let counts = self.entries(row, &row.obj_count, |c| c.clone())?;
        let attrs = self.attr_entries(row)?;
        let oo = self.entries(row, &row.oo_rel, |r| r.clone())?;
        let oa = self.entries(row, &row.oa_rel, |r| r.clone())?;
        let mut categories: Vec<String> = Vec::new();
        for (_, c) in &counts {
            if !categories.contains(&c.category) {
                categories.push(c.category.clone());
            }
        }
        let matching = match &self.params.matching {
            MatchingMethod::Labels => match_by_labels(scene, &categories),
            MatchingMethod::Vlm => {
                let (Some(session), Some(views)) = (res.session, res.views) else {
                    return Err(FidelityError::Unavailable {
                        what: "matching by VLM".into(),
                        needs: "a VLM and object views",
                    });
                };
                match_by_vlm(
                    scene,
                    &categories,
                    session,
                    views,
                    self.params.size_aware_matching,
                )?
            }
            MatchingMethod::File { path } => {
                let file = crate::matching::matching_file_for(path, res.scene_name);
                read_matching_file(&file, scene, &categories)?
            }
        };
        let m = &matching.matching;
        let mut warnings = Vec::new();
        let runs = |x| metrics.contains(&x);
        let cnt = runs(FidelityMetric::Cnt).then(|| self.cnt(scene, m, &counts));
        let atr = if runs(FidelityMetric::Atr) {
            Some(self.atr(scene, m, &attrs, res)?)
        } else {
            None
        };
        let oor = if runs(FidelityMetric::Oor) {
            Some(self.oor(scene, m, &oo, res, &mut warnings)?)
        } else {
            None
        };
        let oar = if runs(FidelityMetric::Oar) {
            Some(self.oar(scene, m, &oa, res, &mut warnings)?)
        } else {
            None
        };
        let summary = FidelitySummary {
            cnt: cnt.as_ref().and_then(|r| r.score),
            atr: atr.as_ref().and_then(|r| r.score),
            oor: oor.as_ref().and_then(|r| r.score),
            oar: oar.as_ref().and_then(|r| r.score),
        };
        let report = FidelityReport {
            matching: MatchingSummary {
                source: matching.source,
                message: m.message(scene.objects().len()),
                unanswered: matching.unanswered.len(),
            },
            relation_mapping: self.params.relation_mapping,
            cnt,
            atr,
            oor,
            oar,
            summary,
            vlm_usage: res.session.map(|s| s.usage().into()),
            views_rendered: res.views.map_or(0, |v| v.made()),
            warnings,
        };
        Ok(FidelityOutcome { report, matching })
    }

    /// The parsed entries of a field with their text (duplicates collapsed unless kept).
    fn entries<T: EntryKind, U>(
        &self,
        row: &AnnotationRow,
        entries: &[Entry<T>],
        f: impl Fn(&T) -> U,
    ) -> Result<Vec<(String, U)>, FidelityError> {
        let mut out: Vec<(String, U)> = Vec::new();
        for e in entries {
            match e {
                Entry::Parsed(v) => {
                    let text = v.to_string();
                    if !self.params.keep_duplicate_specs && out.iter().any(|(t, _)| *t == text) {
                        continue;
                    }
                    out.push((text, f(v)));
                }
                Entry::Malformed(m) => return Err(malformed(row, T::FIELD.as_str(), m.text(), m.problems())),
            }
        }
        Ok(out)
    }

    /// ObjAttr entries, several attributes allowed (Q6: `q,n,category,attr_1,attr_2,...`).
    fn attr_entries(&self, row: &AnnotationRow) -> Result<Vec<AttrSpecIn>, FidelityError> {
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

    fn cnt(
        &self,
        scene: &Scene,
        m: &Matching,
        counts: &[(String, sceneeval_annotation::ObjCount)],
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

    fn atr<V: Vlm>(
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

    fn oor<V: Vlm>(
        &self,
        scene: &Scene,
        m: &Matching,
        rels: &[(String, sceneeval_annotation::OoRel)],
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
                        p.info = RelationMappingInfo {
                            status: MappingStatus::Mapped,
                            source: MappingSource::Lexicon,
                            word: Some(word.to_owned()),
                            relations: mapping.iter().map(ToString::to_string).collect(),
                            reason: format!("lexicon word {word:?}"),
                        };
                        p.relations = mapping;
                    }
                    Lookup::Unmapped { reason } => {
                        p.info = info(MappingStatus::Unmapped, MappingSource::Lexicon, &reason);
                    }
                    Lookup::Unknown => {
                        if res.session.is_some() {
                            ask.push(ObjectRelationSpec {
                                key: k.to_string(),
                                relationship: r.relationship.clone(),
                                objects: r.refs.iter().map(ToString::to_string).collect(),
                                anchor_index: r.anchor,
                            });
                            p.info = info(MappingStatus::Unanswered, MappingSource::Vlm, "asked");
                        } else {
                            p.info = info(
                                MappingStatus::Unmapped,
                                MappingSource::None,
                                &format!(
                                    "{:?} is not in the lexicon and no VLM is configured",
                                    r.relationship
                                ),
                            );
                        }
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
                                p.info = RelationMappingInfo {
                                    status: MappingStatus::Mapped,
                                    source: MappingSource::Vlm,
                                    word: None,
                                    relations: rs.iter().map(ToString::to_string).collect(),
                                    reason: answer.reason,
                                };
                                p.relations = rs;
                            }
                            _ => p.info = info(MappingStatus::Unmapped, MappingSource::Vlm, &answer.reason),
                        }
                    }
                    Outcome::Unanswered(why) => {
                        p.info = info(MappingStatus::Unanswered, MappingSource::Vlm, &why.to_string());
                    }
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
                spec.satisfied = self.params.presence_gate_respects_quantifier && r.count.holds(0);
            } else if spec.mapping.status != MappingStatus::Mapped {
                spec.satisfied =
                    spec.mapping.status == MappingStatus::Unmapped && self.params.unmapped_is_satisfied;
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
                prod = prod.saturating_mul(binomial(n as u64, *k as u64));
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

    fn oar<V: Vlm>(
        &self,
        scene: &Scene,
        m: &Matching,
        rels: &[(String, sceneeval_annotation::OaRel)],
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
                    let class = r.arch.iter().find_map(ElementClass::of);
                    match class {
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
                        spec.mapping = RelationMappingInfo {
                            status: MappingStatus::Mapped,
                            source: MappingSource::Lexicon,
                            word: Some(word.to_owned()),
                            relations: vec![mapping.to_string()],
                            reason: format!("lexicon word {word:?}"),
                        };
                        spec.floors = room_floors(scene, &r.arch, warnings, text);
                        relation = Some(mapping);
                    }
                    Lookup::Unmapped { reason } => {
                        spec.mapping = info(MappingStatus::Unmapped, MappingSource::Lexicon, &reason);
                    }
                    Lookup::Unknown => {
                        if res.session.is_some() && !floor_ids.is_empty() {
                            ask.push(ArchRelationSpec {
                                key: k.to_string(),
                                relationship: r.relationship.clone(),
                                object: r.object.to_string(),
                                architecture: spec.arch_references.clone(),
                            });
                            spec.mapping = info(MappingStatus::Unanswered, MappingSource::Vlm, "asked");
                        } else {
                            spec.mapping = info(
                                MappingStatus::Unmapped,
                                MappingSource::None,
                                &format!(
                                    "{:?} is not in the lexicon and no VLM is configured",
                                    r.relationship
                                ),
                            );
                        }
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
                            spec.mapping = RelationMappingInfo {
                                status: MappingStatus::Mapped,
                                source: MappingSource::Vlm,
                                word: None,
                                relations: vec![r.to_string()],
                                reason: answer.reason,
                            };
                            spec.floors = answer.floors;
                            *relation = Some(r);
                        }
                        None => {
                            spec.mapping = info(MappingStatus::Unmapped, MappingSource::Vlm, &answer.reason)
                        }
                    },
                    Outcome::Unanswered(why) => {
                        spec.mapping = info(MappingStatus::Unanswered, MappingSource::Vlm, &why.to_string());
                    }
                }
            }
        }
        let mut out = Vec::with_capacity(specs.len());
        for ((_, r), (mut spec, relation)) in rels.iter().zip(specs) {
            if !spec.obj_present {
                spec.satisfied = self.params.presence_gate_respects_quantifier && r.count.holds(0);
            } else if let Some(rel) = relation {
                let floors: Vec<&str> = spec.floors.iter().map(String::as_str).collect();
                for i in m.objects_of(scene, &r.object.category) {
                    let id = scene.objects()[i].id().as_str().to_owned();
                    let (score, holds) = match self.relations.arch(scene, rel, i, &floors) {
                        Ok(e) => (e.score, e.holds),
                        Err(e @ sceneeval_relations::RelationError::NoArchitecture { .. }) => {
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
                spec.satisfied =
                    spec.mapping.status == MappingStatus::Unmapped && self.params.unmapped_is_satisfied;
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
            let t = normalise(t);
            let hits: Vec<String> = scene
                .rooms()
                .iter()
                .filter(|r| normalise(r.id().as_str()).contains(&t) || normalise(r.floor_id()).contains(&t))
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

/// The lexicon's participants: the anchor reference (index, or the first) and the other
/// references grouped by category in order of appearance, each reference one object.
fn lexicon_participants(r: &sceneeval_annotation::OoRel) -> Participants {
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

fn info(status: MappingStatus, source: MappingSource, reason: &str) -> RelationMappingInfo {
    RelationMappingInfo {
        status,
        source,
        word: None,
        relations: Vec::new(),
        reason: reason.to_owned(),
    }
}

fn spec_count(c: &CountSpec) -> SpecCount {
    SpecCount {
        quantifier: c.quantifier.as_str().to_owned(),
        quantity: c.quantity,
    }
}

fn ids(scene: &Scene, idx: &[usize]) -> Vec<String> {
    idx.iter()
        .map(|&i| scene.objects()[i].id().as_str().to_owned())
        .collect()
}

fn malformed(
    row: &AnnotationRow,
    field: &'static str,
    text: &str,
    problems: &[EntryProblem],
) -> FidelityError {
    FidelityError::MalformedEntry {
        row: row.id.clone(),
        field,
        entry: text.to_owned(),
        problems: problems
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("; "),
    }
}

/// `n choose k`, saturating at `u64::MAX`.
pub fn binomial(n: u64, k: u64) -> u64 {
    if k > n {
        return 0;
    }
    let k = k.min(n - k);
    let mut r: u128 = 1;
    for i in 0..k {
        r = r * u128::from(n - i) / u128::from(i + 1);
        if r > u128::from(u64::MAX) {
            return u64::MAX;
        }
    }
    r as u64
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
    fn binomials_and_combinations() {
        assert_eq!(binomial(4, 3), 4);
        assert_eq!(binomial(6, 6), 1);
        assert_eq!(binomial(3, 5), 0);
        assert_eq!(binomial(200, 100), u64::MAX);
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
