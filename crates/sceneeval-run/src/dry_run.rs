//! What a run would ask the VLM, without asking: [`DryRun`], made by
//! [`crate::PreparedRun::dry_run`] (`sceneeval evaluate --dry-run`, `evaluate(dry_run=True)`).
//!
//! A dry run goes through the same scenes, reuse decisions and per-scene pipeline as the run,
//! rendering the same object views (so that each request, and therefore its cache key, is the
//! one the run would send), but computes no geometry metric, writes nothing and sends nothing:
//! its model ([`DryRunModel`]) answers each request from the response cache when it can, and
//! otherwise counts it, with its estimated input tokens, as one the run would send, and
//! answers it with a refusal ("not sent"), so that the pipeline goes on without it.
//!
//! Attribute questions depend on the matching. In a scene whose matching requests the cache
//! answers, the attribute requests are the run's own. In a scene with a matching request to
//! send, they cannot be known: the dry run counts one attribute request per ObjAttr entry of
//! the scene's annotation row (one per entry is the most the run sends: none when no object
//! matches the entry's category), each with as many instances as the entry's quantity (at
//! least one; two views each, of the run's render size).

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::future::Future;
use std::path::PathBuf;
use std::sync::Arc;

use serde::Serialize;

use sceneeval_annotation::AnnotationRow;
use sceneeval_vlm::cache::{DiskCache, cache_key};
use sceneeval_vlm::tasks::{AttributeTask, InstanceViews};
use sceneeval_vlm::{
    Answer, AnswerContent, PngImage, Session, TaskKind, TokenUsage, Vlm, VlmError, VlmRequest,
};

/// What one task would cost over the scenes a run would evaluate.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct TaskCost {
    /// The task (`obj_matching`, ... [`TaskKind::name`]).
    pub task: String,
    /// Requests the run would make (answered from the cache or sent); re-asks of invalid
    /// answers (at most one per request) are not counted.
    pub requests: u64,
    /// Of those, answered by the response cache.
    pub cached: u64,
    /// Of those to send, how many are estimated rather than known (attribute requests of
    /// scenes whose matching is not cached).
    pub estimated: u64,
    /// Estimated input tokens of the requests to send
    /// (`sceneeval_vlm_openai::OpenAiVlm::estimate_tokens`).
    pub prompt_tokens: u64,
}

impl TaskCost {
    /// Requests the run would send.
    pub fn to_send(&self) -> u64 {
        self.requests - self.cached
    }

    fn add(&mut self, other: &TaskCost) {
        self.requests += other.requests;
        self.cached += other.cached;
        self.estimated += other.estimated;
        self.prompt_tokens += other.prompt_tokens;
    }
}

/// What a run would ask the VLM ([`crate::PreparedRun::dry_run`]).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct DryRun {
    /// The scenes of the run.
    pub scenes: usize,
    /// Scenes whose earlier result would be kept (nothing asked).
    pub reused: usize,
    /// Scenes the run would evaluate.
    pub evaluated: usize,
    /// Scenes whose attribute requests are estimated (a matching request to send).
    pub attributes_estimated: usize,
    /// Scenes that could not be read or gone through, with why (the run would record them as
    /// failed).
    pub failed: Vec<(String, String)>,
    /// Per task with at least one request, in the reference's task order.
    pub tasks: Vec<TaskCost>,
    /// Whether a VLM is configured (without one nothing is asked).
    pub vlm: bool,
}

impl DryRun {
    /// The tasks' sums (task `total`).
    pub fn total(&self) -> TaskCost {
        let mut total = TaskCost {
            task: "total".to_owned(),
            ..TaskCost::default()
        };
        for t in &self.tasks {
            total.add(t);
        }
        total
    }

    /// Adds one scene's costs.
    pub(crate) fn add_scene(&mut self, scene: &SceneTally) {
        for (kind, cost) in &scene.tasks {
            match self.tasks.iter_mut().find(|t| t.task == kind.name()) {
                Some(t) => t.add(cost),
                None => {
                    let mut t = cost.clone();
                    t.task = kind.name().to_owned();
                    self.tasks.push(t);
                }
            }
        }
        let order = |name: &str| TaskKind::ALL.iter().position(|k| k.name() == name);
        self.tasks.sort_by_key(|t| order(&t.task));
    }
}

/// One scene's requests, as the dry run's model sees them.
#[derive(Debug, Default)]
pub(crate) struct SceneTally {
    tasks: BTreeMap<TaskKind, TaskCost>,
    matching_to_send: bool,
}

thread_local! {
    static TALLY: RefCell<Option<SceneTally>> = const { RefCell::new(None) };
}

impl SceneTally {
    /// Starts counting the requests asked on this thread.
    pub(crate) fn start() {
        TALLY.with(|t| *t.borrow_mut() = Some(SceneTally::default()));
    }

    /// The requests asked on this thread since [`SceneTally::start`].
    pub(crate) fn finish() -> SceneTally {
        TALLY.with(|t| t.borrow_mut().take()).unwrap_or_default()
    }

    fn record(kind: TaskKind, cached: bool, tokens: u64) {
        TALLY.with(|t| {
            if let Some(tally) = t.borrow_mut().as_mut() {
                let cost = tally.tasks.entry(kind).or_default();
                cost.requests += 1;
                if cached {
                    cost.cached += 1;
                } else {
                    cost.prompt_tokens += tokens;
                    tally.matching_to_send |= kind == TaskKind::ObjMatching;
                }
            }
        });
    }

    /// Whether some matching request of the scene would be sent.
    pub(crate) fn matching_to_send(&self) -> bool {
        self.matching_to_send
    }
}

/// The model a dry run asks (see the module docs).
#[derive(Clone)]
pub(crate) struct DryRunModel {
    model: String,
    settings: String,
    cache: DiskCache,
    estimate: Arc<dyn Fn(&VlmRequest) -> u64 + Send + Sync>,
    /// A blank view of the run's render size, for the estimated attribute requests.
    blank: Option<PngImage>,
}

impl std::fmt::Debug for DryRunModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DryRunModel")
            .field("model", &self.model)
            .field("settings", &self.settings)
            .field("cache", &self.cache)
            .finish_non_exhaustive()
    }
}

/// The text of the refusal a dry run answers requests to send with.
const NOT_SENT: &str = "dry run: not sent";

impl DryRunModel {
    /// The model `model` with `settings` (the run's client's), answering from the cache in
    /// `cache`; `estimate` gives a request's tokens; views are `render_size` pixels square.
    #[cfg_attr(not(feature = "openai"), allow(dead_code))] // Made only with the HTTP client.
    pub(crate) fn new(
        model: &str,
        settings: &str,
        cache: impl Into<PathBuf>,
        estimate: impl Fn(&VlmRequest) -> u64 + Send + Sync + 'static,
        render_size: u32,
    ) -> Self {
        let side = render_size as usize;
        let blank =
            sceneeval_vlm::encode_rgb_png(render_size, render_size, &vec![255u8; side * side * 3]).ok();
        DryRunModel {
            model: model.to_owned(),
            settings: settings.to_owned(),
            cache: DiskCache::new(cache),
            estimate: Arc::new(estimate),
            blank,
        }
    }

    /// The scene's attribute requests as the dry run estimates them (see the module docs):
    /// one per ObjAttr entry of `row`.
    pub(crate) fn estimate_attributes(&self, row: &AnnotationRow) -> TaskCost {
        let mut cost = TaskCost::default();
        let Some(blank) = &self.blank else { return cost };
        let session = Session::new(self);
        for entry in row.obj_attrs() {
            let instances = entry.count.quantity.clamp(1, 64) as usize;
            let views = vec![
                InstanceViews {
                    front: blank.clone(),
                    size: blank.clone(),
                };
                instances
            ];
            let request = AttributeTask::new(entry.category.clone(), [entry.attribute.clone()], views)
                .and_then(|task| session.request(&task));
            if let Ok(request) = request {
                cost.requests += 1;
                cost.estimated += 1;
                cost.prompt_tokens += (self.estimate)(&request);
            }
        }
        cost
    }

    /// A scene's tally with its attribute requests estimated when its matching is not cached.
    pub(crate) fn settle(&self, mut tally: SceneTally, row: Option<&AnnotationRow>) -> (SceneTally, bool) {
        let estimated = tally.matching_to_send();
        if estimated {
            tally.tasks.remove(&TaskKind::ObjAttribute);
            if let Some(row) = row {
                let cost = self.estimate_attributes(row);
                if cost.requests > 0 {
                    tally.tasks.insert(TaskKind::ObjAttribute, cost);
                }
            }
        }
        (tally, estimated)
    }
}

impl Vlm for DryRunModel {
    fn model(&self) -> &str {
        &self.model
    }

    fn settings(&self) -> &str {
        &self.settings
    }

    fn answer(&self, request: &VlmRequest) -> impl Future<Output = Result<Answer, VlmError>> + Send {
        let kind = TaskKind::ALL
            .into_iter()
            .find(|k| k.name() == request.task)
            .unwrap_or(TaskKind::EndpointCheck);
        let key = cache_key(&self.model, &self.settings, request);
        let answer = match self.cache.load(&key) {
            Ok(Some(record)) => {
                SceneTally::record(kind, true, 0);
                Answer {
                    content: record.answer,
                    usage: record.usage,
                    from_cache: true,
                }
            }
            _ => {
                SceneTally::record(kind, false, (self.estimate)(request));
                Answer {
                    content: AnswerContent::Refusal {
                        text: NOT_SENT.to_owned(),
                    },
                    usage: TokenUsage::default(),
                    from_cache: false,
                }
            }
        };
        std::future::ready(Ok(answer))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_annotation::Annotations;
    use sceneeval_vlm::check::EndpointCheck;

    fn row() -> AnnotationRow {
        let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
                   1,easy,A room.,\"eq,2,chair\",\"eq,2,chair,wooden; eq,1,bed,double\",,\n";
        Annotations::from_csv_str(csv).unwrap().get("1").unwrap().clone()
    }

    #[test]
    fn cached_requests_are_answered_and_others_counted_with_their_tokens() {
        let dir = tempfile::tempdir().unwrap();
        // 10 tokens per request, whatever it is.
        let model = DryRunModel::new("m", "detail=low", dir.path(), |_| 10, 16);
        let session = Session::new(&model);
        let check = EndpointCheck::new();
        // Cached beforehand: the check's request with an answer.
        let request = session.request(&check).unwrap();
        let answer = Answer::new(
            AnswerContent::Json {
                value: serde_json::json!({"colour": "red", "reason": "r"}),
            },
            TokenUsage::default(),
        );
        model
            .cache
            .store(&DiskCache::record("m", "detail=low", &request, &answer))
            .unwrap();
        SceneTally::start();
        let cached = pollster::block_on(session.ask(&check)).unwrap();
        assert!(cached.into_single().unwrap().is_answered());
        // Another model's cache key: not cached, counted as to send, refused.
        let other = DryRunModel::new("m2", "detail=low", dir.path(), |_| 10, 16);
        let sent = pollster::block_on(Session::new(&other).ask(&check)).unwrap();
        assert!(!sent.into_single().unwrap().is_answered());
        let tally = SceneTally::finish();
        let mut run = DryRun::default();
        run.add_scene(&tally);
        assert_eq!(
            run.tasks,
            vec![TaskCost {
                task: "endpoint_check".into(),
                requests: 2,
                cached: 1,
                estimated: 0,
                prompt_tokens: 10,
            }]
        );
        assert_eq!(run.total().to_send(), 1);
    }

    #[test]
    fn attributes_are_estimated_per_objattr_entry_when_matching_is_to_send() {
        let dir = tempfile::tempdir().unwrap();
        // Tokens: the number of images times 100, so that the instances show.
        let model = DryRunModel::new("m", "", dir.path(), |r| 100 * r.images.len() as u64, 16);
        let mut tally = SceneTally::default();
        tally.tasks.insert(
            TaskKind::ObjAttribute,
            TaskCost {
                requests: 5,
                ..TaskCost::default()
            },
        );
        // Matching cached: the attribute requests seen are kept.
        let (kept, estimated) = model.settle(tally, Some(&row()));
        assert!(!estimated);
        assert_eq!(kept.tasks[&TaskKind::ObjAttribute].requests, 5);
        // A matching request to send: one per entry; chairs x 2 (4 images), bed x 1 (2).
        let mut tally = kept;
        tally.matching_to_send = true;
        let (settled, estimated) = model.settle(tally, Some(&row()));
        assert!(estimated);
        assert_eq!(
            settled.tasks[&TaskKind::ObjAttribute],
            TaskCost {
                task: String::new(),
                requests: 2,
                cached: 0,
                estimated: 2,
                prompt_tokens: 400 + 200,
            }
        );
    }
}
