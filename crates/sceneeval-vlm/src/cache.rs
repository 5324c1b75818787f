//! The response cache: one JSON file per answer, named by a content hash of the request.
//!
//! # Key
//! The key is the blake3 hash of the model name, the model's settings ([`Vlm::settings`]:
//! image detail, sampling temperature and seed, reply token limit; only when not empty), the
//! system prompt, the user text, the bytes of every image (in order), the schema name and the
//! schema (compact JSON), each prefixed with its length so that no two different requests
//! share a byte stream. It is written as 64 hex digits. One cache folder can hold the answers
//! of several models and settings side by side: a request asked again with another detail or
//! temperature is a different key, never a stale answer.
//!
//! # Files
//! The answer to key `k` is `<dir>/<k[0..2]>/<k>.json`, a [`CacheRecord`] (format
//! `sceneeval.vlm-cache/1`): the model, the task, the request in readable form (system prompt,
//! user text, each image's size, dimensions and hash, the schema), the answer (`kind` `json`,
//! `not_json`, `refusal` or `truncated`) and the token usage. Images are stored by hash only.
//!
//! A file is written to a temporary file with a unique name in the same folder and renamed
//! into place ([`sceneeval_files::write_atomic`]), so a reader never sees a partial file and
//! several processes can share one cache: two processes that answer the same request at once
//! both write a complete file, and the last rename wins. Only regular files are read back (a
//! named pipe in the cache folder is an error, not a blocked reader).
//! Only usable answers are cached: [`Cached`] stores an answer when [`crate::Session`] found
//! it usable ([`Vlm::judged`]: at least one question got a valid answer from it). A refusal, a
//! reply cut off at the token limit, a reply that is not JSON or names only categories that were
//! not offered is never stored, so a re-run asks exactly the questions that got no usable
//! answer; errors (timeouts, HTTP failures) are not stored either. Entries of earlier versions
//! holding such answers are passed over (and a cached JSON answer that turns out unusable is
//! removed and asked afresh).

use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use serde::{Deserialize, Serialize};

use crate::{Answer, AnswerContent, ResponseSchema, TokenUsage, Vlm, VlmError, VlmRequest};

/// The `format` value of cache records written by this version.
pub const CACHE_FORMAT: &str = "sceneeval.vlm-cache/1";

/// A cache folder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DiskCache {
    dir: PathBuf,
}

/// One cached answer, as stored in its file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CacheRecord {
    /// Always [`CACHE_FORMAT`].
    pub format: String,
    /// The request's key (the file name without `.json`).
    pub key: String,
    /// The model that answered.
    pub model: String,
    /// The model's settings when it answered ([`Vlm::settings`]); empty for models without.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub settings: String,
    /// The task name.
    pub task: String,
    /// The request.
    pub request: RecordedRequest,
    /// The answer.
    pub answer: AnswerContent,
    /// The tokens the answer used when it was obtained.
    pub usage: TokenUsage,
}

/// A request in readable form.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordedRequest {
    /// The system prompt.
    pub system: String,
    /// The user text.
    pub user_text: String,
    /// The images, by size and hash.
    pub images: Vec<RecordedImage>,
    /// The response schema.
    pub schema: ResponseSchema,
}

/// An image of a recorded request.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct RecordedImage {
    /// Size of the PNG file in bytes.
    pub bytes: usize,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// blake3 hash of the PNG file (64 hex digits).
    pub blake3: String,
}

/// The cache key of `request` asked of `model` with `settings` ([`Vlm::settings`]; see the
/// [module docs](self)). Empty settings add nothing to the hash, so the keys of models without
/// settings are those of earlier versions.
///
/// ```
/// use sceneeval_vlm::cache::cache_key;
/// use sceneeval_vlm::{ResponseSchema, VlmRequest};
/// let mut r = VlmRequest {
///     task: "t".into(), system: "s".into(), user_text: "u".into(), images: vec![],
///     schema: ResponseSchema { name: "t".into(), schema: serde_json::json!({"type": "object"}) },
/// };
/// let k = cache_key("m", "", &r);
/// assert_eq!(k.len(), 64);
/// assert_ne!(k, cache_key("other-model", "", &r));
/// assert_ne!(k, cache_key("m", "detail=high", &r));
/// assert_ne!(cache_key("m", "detail=low", &r), cache_key("m", "detail=high", &r));
/// r.user_text.push(' ');
/// assert_ne!(k, cache_key("m", "", &r));
/// ```
pub fn cache_key(model: &str, settings: &str, request: &VlmRequest) -> String {
    fn field(h: &mut blake3::Hasher, bytes: &[u8]) {
        h.update(&(bytes.len() as u64).to_le_bytes());
        h.update(bytes);
    }
    let mut h = blake3::Hasher::new();
    h.update(b"sceneeval-vlm cache key v1\0");
    field(&mut h, model.as_bytes());
    if !settings.is_empty() {
        // Tagged, so that no model name and settings run together into another model's name.
        h.update(b"settings\0");
        field(&mut h, settings.as_bytes());
    }
    field(&mut h, request.system.as_bytes());
    field(&mut h, request.user_text.as_bytes());
    h.update(&(request.images.len() as u64).to_le_bytes());
    for image in &request.images {
        field(&mut h, image.bytes());
    }
    field(&mut h, request.schema.name.as_bytes());
    field(&mut h, request.schema.schema.to_string().as_bytes());
    h.finalize().to_hex().to_string()
}

impl DiskCache {
    /// A cache in `dir` (created when the first answer is stored).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        DiskCache { dir: dir.into() }
    }

    /// The cache folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The file of key `key`.
    pub fn path_of(&self, key: &str) -> PathBuf {
        self.dir
            .join(key.get(..2).unwrap_or("__"))
            .join(format!("{key}.json"))
    }

    /// The record for `key`, if there is one.
    ///
    /// # Errors
    /// [`VlmError::Io`] when the file exists but cannot be read, [`VlmError::CacheRecord`] when
    /// it is not a record of this format for this key.
    pub fn load(&self, key: &str) -> Result<Option<CacheRecord>, VlmError> {
        let path = self.path_of(key);
        let read = sceneeval_files::open_regular(&path).and_then(|mut file| {
            let mut text = String::new();
            file.read_to_string(&mut text).map(|_| text)
        });
        let text = match read {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(VlmError::io(path, e)),
        };
        let bad = |message: String| VlmError::CacheRecord {
            path: path.clone(),
            message,
        };
        let record: CacheRecord = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
        if record.format != CACHE_FORMAT {
            return Err(bad(format!(
                "format {:?}, expected {CACHE_FORMAT:?}",
                record.format
            )));
        }
        if record.key != key {
            return Err(bad(format!("the record is for key {}", record.key)));
        }
        Ok(Some(record))
    }

    /// Stores a record atomically (a temporary file with a unique name, then a rename:
    /// [`sceneeval_files::write_atomic`]).
    ///
    /// # Errors
    /// [`VlmError::Io`] when the folder or file cannot be written.
    pub fn store(&self, record: &CacheRecord) -> Result<PathBuf, VlmError> {
        let path = self.path_of(&record.key);
        let mut text = serde_json::to_string_pretty(record).map_err(|e| VlmError::CacheRecord {
            path: path.clone(),
            message: e.to_string(),
        })?;
        text.push('\n');
        sceneeval_files::write_atomic(&path, text.as_bytes()).map_err(|e| VlmError::io(&path, e))?;
        Ok(path)
    }

    /// The record of `answer` to `request` asked of `model` with `settings`.
    pub fn record(model: &str, settings: &str, request: &VlmRequest, answer: &Answer) -> CacheRecord {
        CacheRecord {
            format: CACHE_FORMAT.to_owned(),
            key: cache_key(model, settings, request),
            model: model.to_owned(),
            settings: settings.to_owned(),
            task: request.task.clone(),
            request: RecordedRequest {
                system: request.system.clone(),
                user_text: request.user_text.clone(),
                images: request
                    .images
                    .iter()
                    .map(|i| RecordedImage {
                        bytes: i.bytes().len(),
                        width: i.dimensions().0,
                        height: i.dimensions().1,
                        blake3: i.blake3_hex(),
                    })
                    .collect(),
                schema: request.schema.clone(),
            },
            answer: answer.content.clone(),
            usage: answer.usage,
        }
    }
}

/// A [`Vlm`] with a disk cache in front: answers from the cache when it can, otherwise asks
/// the inner model; stores an answer once [`crate::Session`] has found it usable
/// ([`Vlm::judged`]; see the [module docs](self)).
///
/// A cache file that cannot be read as a record is logged as a warning and replaced by a fresh
/// answer (a run never stops for a damaged cache entry); [`Replay`] reports it as an error. An
/// answer that cannot be stored (a full disk, a folder that cannot be written) is used all the
/// same, with one warning per cache (and its clones).
#[derive(Debug, Clone)]
pub struct Cached<V> {
    inner: V,
    cache: DiskCache,
    /// Whether a failed write was reported already.
    warned: Arc<AtomicBool>,
}

impl<V: Vlm> Cached<V> {
    /// `inner` behind the cache in `dir`.
    pub fn new(inner: V, dir: impl Into<PathBuf>) -> Self {
        Cached {
            inner,
            cache: DiskCache::new(dir),
            warned: Arc::new(AtomicBool::new(false)),
        }
    }

    /// The inner model.
    pub fn inner(&self) -> &V {
        &self.inner
    }

    /// The cache.
    pub fn cache(&self) -> &DiskCache {
        &self.cache
    }
}

impl<V: Vlm> Vlm for Cached<V> {
    fn model(&self) -> &str {
        self.inner.model()
    }

    fn settings(&self) -> &str {
        self.inner.settings()
    }

    async fn answer(&self, request: &VlmRequest) -> Result<Answer, VlmError> {
        let key = cache_key(self.model(), self.settings(), request);
        match self.cache.load(&key) {
            Ok(Some(record)) if matches!(record.answer, AnswerContent::Json { .. }) => {
                tracing::debug!(task = %request.task, key = %key, "answer read from the cache");
                return Ok(Answer {
                    content: record.answer,
                    usage: record.usage,
                    from_cache: true,
                });
            }
            Ok(Some(_)) => {
                tracing::debug!(task = %request.task, key = %key, "cached reply not usable (an earlier version stored it); asking again");
            }
            Ok(None) => {}
            Err(e) => tracing::warn!(error = %e, "unusable cache entry; asking the model again"),
        }
        self.inner.answer(request).await
    }

    fn judged(&self, request: &VlmRequest, answer: &Answer, usable: bool) {
        self.inner.judged(request, answer, usable);
        match (usable, answer.from_cache) {
            (true, false) => {
                let record = DiskCache::record(self.model(), self.settings(), request, answer);
                match self.cache.store(&record) {
                    Ok(path) => {
                        tracing::debug!(task = %request.task, path = %path.display(), "answer stored in the cache");
                    }
                    Err(e) if !self.warned.swap(true, Ordering::Relaxed) => {
                        tracing::warn!(error = %e, "the response cache cannot be written; answers are used but not kept");
                    }
                    Err(e) => tracing::debug!(error = %e, "answer not stored in the cache"),
                }
            }
            (false, true) => {
                let path = self
                    .cache
                    .path_of(&cache_key(self.model(), self.settings(), request));
                match std::fs::remove_file(&path) {
                    Ok(()) => {
                        tracing::info!(task = %request.task, path = %path.display(), "unusable cached answer removed")
                    }
                    Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                    Err(e) => {
                        tracing::warn!(path = %path.display(), error = %e, "unusable cached answer not removed")
                    }
                }
            }
            _ => {}
        }
    }
}

/// A [`Vlm`] that answers only from a cache: a request without a cached answer is a
/// [`VlmError::CacheMiss`] naming the request. Reproduces a run without network access.
#[derive(Debug, Clone)]
pub struct Replay {
    cache: DiskCache,
    model: String,
    settings: String,
}

impl Replay {
    /// Answers of `model` (asked without settings) from the cache in `dir`.
    pub fn new(dir: impl Into<PathBuf>, model: impl Into<String>) -> Self {
        Replay {
            cache: DiskCache::new(dir),
            model: model.into(),
            settings: String::new(),
        }
    }

    /// Replays the answers the model gave with `settings` (its [`Vlm::settings`] when the
    /// answers were cached, e.g. `sceneeval_vlm_openai::OpenAiVlm::settings`).
    pub fn with_settings(mut self, settings: impl Into<String>) -> Self {
        self.settings = settings.into();
        self
    }
}

impl Vlm for Replay {
    fn model(&self) -> &str {
        &self.model
    }

    fn settings(&self) -> &str {
        &self.settings
    }

    async fn answer(&self, request: &VlmRequest) -> Result<Answer, VlmError> {
        let key = cache_key(&self.model, &self.settings, request);
        match self.cache.load(&key)? {
            Some(record) => Ok(Answer {
                content: record.answer,
                usage: record.usage,
                from_cache: true,
            }),
            None => {
                let chars: Vec<char> = request.user_text.chars().collect();
                let tail: String = chars[chars.len().saturating_sub(160)..].iter().collect();
                Err(VlmError::CacheMiss {
                    task: request.task.clone(),
                    model: self.model.clone(),
                    key,
                    dir: self.cache.dir().to_path_buf(),
                    text_tail: tail,
                })
            }
        }
    }
}
