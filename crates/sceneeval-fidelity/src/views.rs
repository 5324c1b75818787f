//! Object views shown to the VLM: the front view (matching, attributes), the size view
//! (attributes) and the surroundings view (support types).

use std::collections::HashMap;
use std::sync::Mutex;

use sceneeval_vlm::PngImage;

use crate::FidelityError;

/// Which view of an object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ViewKind {
    /// The object alone, facing its front.
    Front,
    /// The object beside a 170 cm human figure.
    Size,
    /// The object with what stands on and around it.
    Surroundings,
}

impl ViewKind {
    /// `front`, `size` or `surroundings`.
    pub const fn name(self) -> &'static str {
        match self {
            ViewKind::Front => "front",
            ViewKind::Size => "size",
            ViewKind::Surroundings => "surroundings",
        }
    }
}

/// Makes the views of a scene's objects. Implementations should make each view once and
/// return it again when asked again ([`MemoViews`] adds that to any function).
pub trait ObjectViews: Send + Sync {
    /// The `kind` view of the object with id `object`, as PNG.
    ///
    /// # Errors
    /// [`FidelityError::View`] when it cannot be made.
    fn view(&self, object: &str, kind: ViewKind) -> Result<PngImage, FidelityError>;

    /// How many views were made so far (not counting repeats served from memory).
    fn made(&self) -> u64;
}

type MakeView = dyn Fn(&str, ViewKind) -> Result<PngImage, FidelityError> + Send + Sync;

/// Views made by a function, each once: later requests for the same object and kind are
/// served from memory, so every metric of a scene shares one render per object and view.
pub struct MemoViews {
    make: Box<MakeView>,
    memo: Mutex<HashMap<(String, ViewKind), PngImage>>,
}

impl std::fmt::Debug for MemoViews {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MemoViews").field("made", &self.made()).finish()
    }
}

impl MemoViews {
    /// Views made by `make`, memoised.
    pub fn new(
        make: impl Fn(&str, ViewKind) -> Result<PngImage, FidelityError> + Send + Sync + 'static,
    ) -> Self {
        MemoViews {
            make: Box::new(make),
            memo: Mutex::new(HashMap::new()),
        }
    }
}

impl ObjectViews for MemoViews {
    fn view(&self, object: &str, kind: ViewKind) -> Result<PngImage, FidelityError> {
        let key = (object.to_owned(), kind);
        if let Some(v) = self.memo.lock().ok().and_then(|m| m.get(&key).cloned()) {
            return Ok(v);
        }
        let v = (self.make)(object, kind)?;
        if let Ok(mut m) = self.memo.lock() {
            m.insert(key, v.clone());
        }
        Ok(v)
    }

    fn made(&self) -> u64 {
        self.memo.lock().map_or(0, |m| m.len() as u64)
    }
}

#[cfg(feature = "render")]
mod rendered {
    use std::path::PathBuf;
    use std::sync::Mutex;

    use sceneeval_io::AssetLibrary;
    use sceneeval_render::{PreparedScene, RenderSettings, Renderer, View};
    use sceneeval_scene::Scene;
    use sceneeval_vlm::{PngImage, encode_rgb_png};

    use super::{MemoViews, ObjectViews, ViewKind};
    use crate::FidelityError;

    /// Views rendered with `sceneeval-render` (feature `render`), each once per object and
    /// kind, optionally also written as `<dir>/<kind>_<id>.png` (atomically, through a unique
    /// temporary file; a view that cannot be written is logged and still used).
    #[derive(Debug)]
    pub struct RenderedViews {
        memo: MemoViews,
    }

    impl RenderedViews {
        /// Prepares `scene` for rendering with `renderer` at `settings`; `dir`, when given,
        /// receives every view made as a PNG file.
        ///
        /// # Errors
        /// [`FidelityError::View`] when the scene cannot be prepared.
        pub fn new(
            renderer: &Renderer,
            scene: &Scene,
            assets: &AssetLibrary,
            settings: RenderSettings,
            dir: Option<PathBuf>,
        ) -> Result<Self, FidelityError> {
            let prepared = renderer.prepare(scene, assets).map_err(|e| FidelityError::View {
                object: "(scene)".into(),
                view: "any",
                source: Box::new(e),
            })?;
            let prepared: Mutex<PreparedScene> = Mutex::new(prepared);
            let memo = MemoViews::new(move |id, kind| {
                let view = match kind {
                    ViewKind::Front => View::Front(id.into()),
                    ViewKind::Size => View::Size(id.into()),
                    ViewKind::Surroundings => View::Surroundings(id.into()),
                };
                let err = |e: Box<dyn std::error::Error + Send + Sync>| FidelityError::View {
                    object: id.to_owned(),
                    view: kind.name(),
                    source: e,
                };
                let image = {
                    let p = prepared
                        .lock()
                        .map_err(|_| err("the renderer's lock is poisoned".into()))?;
                    p.render(&view, &settings).map_err(|e| err(Box::new(e)))?
                };
                let (w, h) = image.dimensions();
                // Transparent background onto white, as the model sees a photo-like picture.
                let mut rgb = Vec::with_capacity(3 * w as usize * h as usize);
                for p in image.pixels() {
                    let a = u32::from(p.0[3]);
                    for c in &p.0[..3] {
                        rgb.push(((u32::from(*c) * a + 255 * (255 - a) + 127) / 255) as u8);
                    }
                }
                let png = encode_rgb_png(w, h, &rgb).map_err(|e| err(Box::new(e)))?;
                if let Some(dir) = &dir {
                    let path = dir.join(view.file_name());
                    // Atomic: a full disk leaves no empty image behind.
                    if let Err(e) = sceneeval_files::write_atomic(&path, png.bytes()) {
                        tracing::warn!(path = %path.display(), error = %e, "view not written");
                    }
                }
                Ok::<PngImage, FidelityError>(png)
            });
            Ok(RenderedViews { memo })
        }
    }

    impl ObjectViews for RenderedViews {
        fn view(&self, object: &str, kind: ViewKind) -> Result<PngImage, FidelityError> {
            self.memo.view(object, kind)
        }

        fn made(&self) -> u64 {
            self.memo.made()
        }
    }
}

#[cfg(feature = "render")]
pub use rendered::RenderedViews;

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicU64, Ordering};

    #[test]
    fn each_view_is_made_once() {
        let calls = Arc::new(AtomicU64::new(0));
        let c = calls.clone();
        let views = MemoViews::new(move |_, _| {
            c.fetch_add(1, Ordering::Relaxed);
            Ok(sceneeval_vlm::check::test_image())
        });
        for _ in 0..3 {
            views.view("a", ViewKind::Front).unwrap();
            views.view("a", ViewKind::Size).unwrap();
        }
        assert_eq!(calls.load(Ordering::Relaxed), 2);
        assert_eq!(views.made(), 2);
    }
}
