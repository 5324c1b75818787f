//! Headless renders of SceneEval scenes with wgpu: the pictures the paper's fidelity metrics
//! show a vision-language model, and the top-down views people look at.
//!
//! | view | file | shows |
//! |---|---|---|
//! | [`View::Front`] | `front_<id>.png` | the object alone, camera facing its front, 30 degrees down |
//! | [`View::Size`] | `size_<id>.png` | the object beside a 170 cm human figure, 10 degrees down |
//! | [`View::Surroundings`] | `surroundings_<id>.png` | the object with what stands on and around it, blockers hidden |
//! | [`View::Top`] | `top.png` | the whole scene from above, walls cut so the interior shows |
//! | [`View::TopOf`] | | the top view with only some objects, e.g. a relation's candidates |
//!
//! The semantics are the reference's (Blender, reference-notes section 9): a 35 mm lens on a
//! 36 mm sensor, the object's own Euler angles with the X angle replaced by 60 (front,
//! surroundings) or 80 (size) degrees, Blender's "camera to selected" fit, the same rules
//! for what the surroundings view hides; doors and windows are holes in the walls.
//!
//! # Rendering
//! One wgpu device per process ([`Gpu::shared`]; or the caller's own, [`Gpu::from_device`]),
//! Vulkan, working on a GPU or on a CPU through Mesa's software driver (lavapipe). A
//! [`Renderer`] compiles the pipelines once; [`Renderer::prepare`] uploads a scene once (each
//! asset's meshes and textures once, shared by its objects) and [`PreparedScene::render`]
//! draws any number of views from it. Images are 512 x 512 by default ([`RenderSettings`]),
//! RGBA with a transparent background, 4x multisampled (1x on request), depth-tested, with both
//! sides of every triangle drawn (assets often have flipped triangles) and sRGB output. One
//! exception does not change what is seen: a closed, consistently wound, opaque mesh seen from
//! outside cannot show its back faces, so they are culled, which on a CPU rasteriser saves up
//! to half of its cost (only a depth tie where a back and a front face meet at a silhouette
//! can come out the other way, a pixel or two per view).
//!
//! # Colour
//! Base colour factors and vertex colours are linear, colour textures sRGB, the output
//! sRGB-encoded (by the shader for opaque surfaces, once per pixel; blending and the
//! multisample resolve happen in linear light). The light is white and diffuse only (a hemisphere light plus a key and a fill
//! light fixed relative to the camera), nothing is tone-mapped, and a surface facing the key
//! light receives about full light: a red sofa stays red, a white wall white. Objects without
//! an asset (boxes) are drawn in [`BOX_COLOR`], floors in [`FLOOR_COLOR`], walls in
//! [`WALL_COLOR`], the human in [`HUMAN_COLOR`].
//!
//! # Determinism
//! A view is a pure function of the scene: draw order, cameras and CPU-side pixel work
//! (mipmaps, alpha) are fixed, so the same scene gives byte-identical images on the same
//! driver.
//!
//! # Example
//! ```
//! use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
//! use sceneeval_io::AssetLibrary;
//! use sceneeval_render::{RenderSettings, Renderer, View};
//! use sceneeval_scene::{Category, RoomBuilder, Scene};
//!
//! let scene = Scene::builder()
//!     .room_builder(RoomBuilder::rectangle("r", Point2::new(0.0, 0.0), Point2::new(4.0, 3.0)))
//!     .add_box("desk", Category::new("desk"), Vector3::new(0.6, 0.3, 0.375),
//!              pose_from_yaw(Point3::new(2.0, 2.6, 0.375), 0.0))
//!     .build()
//!     .unwrap();
//! # // Without a graphics driver this example is skipped (unless SCENEEVAL_REQUIRE_GPU is set).
//! # use sceneeval_test_support::system::{GPU, available};
//! # if available(&GPU, sceneeval_render::Gpu::shared(), sceneeval_render::RenderError::is_missing_driver).is_none() {
//! #     return;
//! # }
//! let renderer = Renderer::new().unwrap();
//! let prepared = renderer.prepare(&scene, &AssetLibrary::new()).unwrap();
//! let settings = RenderSettings::square(64);
//! let front = prepared.render(&View::Front("desk".into()), &settings).unwrap();
//! assert_eq!(front.dimensions(), (64, 64));
//! // The desk fills the frame's centre; the corners are transparent background.
//! assert_eq!(front.get_pixel(32, 32).0[3], 255);
//! assert_eq!(front.get_pixel(0, 0).0[3], 0);
//! assert_eq!(View::Front("desk".into()).file_name(), "front_desk.png");
//! ```

mod camera;
mod closed;
mod error;
mod gpu;
mod human;
mod input;
mod pipeline;
mod pixels;
mod prepared;
mod views;

use std::path::Path;
use std::sync::Arc;

use image::RgbaImage;
use sceneeval_io::AssetLibrary;
use sceneeval_scene::Scene;

pub use camera::{Camera, LENS_MM, NEAR_M, SENSOR_MM};
pub use error::RenderError;
pub use gpu::{AdapterSummary, Gpu};
pub use human::HUMAN_HEIGHT_M;
pub use pixels::padded_row_bytes;
pub use prepared::{BOX_COLOR, FLOOR_COLOR, HUMAN_COLOR, PreparedScene, WALL_COLOR};
pub use views::{
    FRONT_TILT_DEG, HUMAN_GAP_M, SIZE_TILT_DEG, SURROUNDINGS_BACK_OFF, SURROUNDINGS_GAP_M,
    SURROUNDINGS_MIN_UP, SURROUNDINGS_WALL_RAYS, View, ViewKind,
};

/// Image size, antialiasing and the top view's wall cut.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Width in pixels (any size from 1 to the device's limit, 8192 or more).
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Samples per pixel: 4 (multisampled edges, the default) or 1 (aliased edges; two to
    /// three times faster on Mesa's software driver, see `docs/performance.md`).
    pub samples: u32,
    /// Top views draw walls only up to this height above their base (metres), so that the
    /// rooms' interiors show.
    pub wall_cut_height: f64,
}

impl RenderSettings {
    /// The default image side: [`sceneeval_scene::DEFAULT_VIEW_SIZE`] (the reference's 512
    /// pixels).
    pub const DEFAULT_SIZE: u32 = sceneeval_scene::DEFAULT_VIEW_SIZE;
    /// The default samples per pixel (4x multisampling).
    pub const DEFAULT_SAMPLES: u32 = 4;
    /// The default wall cut of top views: 1.2 m, the height at which floor plans cut walls.
    pub const DEFAULT_WALL_CUT_M: f64 = 1.2;

    /// Square images of `size x size` pixels, 4x multisampling, default wall cut.
    pub fn square(size: u32) -> Self {
        RenderSettings {
            width: size,
            height: size,
            samples: Self::DEFAULT_SAMPLES,
            wall_cut_height: Self::DEFAULT_WALL_CUT_M,
        }
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings::square(Self::DEFAULT_SIZE)
    }
}

/// A GPU device with the compiled pipelines. Cheap to clone; keep one for many scenes.
#[derive(Debug, Clone)]
pub struct Renderer {
    inner: Arc<RendererInner>,
}

#[derive(Debug)]
struct RendererInner {
    gpu: Gpu,
    pipelines: pipeline::Pipelines,
}

impl Renderer {
    /// A renderer on the process-wide device ([`Gpu::shared`]).
    ///
    /// # Errors
    /// [`RenderError::NoAdapter`] (naming the packages to install) or
    /// [`RenderError::NoDevice`] when no device can be opened; [`RenderError::Gpu`] when the
    /// shaders do not compile on it.
    pub fn new() -> Result<Renderer, RenderError> {
        Renderer::with_gpu(Gpu::shared()?)
    }

    /// A renderer on a given device.
    ///
    /// # Errors
    /// [`RenderError::Gpu`] when the shaders do not compile on the device.
    pub fn with_gpu(gpu: Gpu) -> Result<Renderer, RenderError> {
        let pipelines = gpu.checked(
            || "compiling the shaders".to_owned(),
            || {
                let pipelines = pipeline::Pipelines::new(gpu.device());
                // Create the default pipelines now, so that their errors surface here.
                for key in pipeline::PipelineKey::all() {
                    pipelines.pipeline(gpu.device(), RenderSettings::DEFAULT_SAMPLES, key);
                }
                Ok(pipelines)
            },
        )?;
        Ok(Renderer {
            inner: Arc::new(RendererInner { gpu, pipelines }),
        })
    }

    /// The device.
    pub fn gpu(&self) -> &Gpu {
        &self.inner.gpu
    }

    pub(crate) fn pipelines(&self) -> &pipeline::Pipelines {
        &self.inner.pipelines
    }

    /// Uploads `scene`, loading each asset's appearance (materials and textures) through
    /// `assets` on first use. Objects whose appearance cannot be loaded are drawn in grey with
    /// a logged warning.
    ///
    /// # Errors
    /// [`RenderError::Gpu`] when the GPU runs out of memory or rejects an upload.
    pub fn prepare(&self, scene: &Scene, assets: &AssetLibrary) -> Result<PreparedScene, RenderError> {
        PreparedScene::new(self, input::SceneInput::from_scene(scene), assets)
    }
}

impl PreparedScene {
    /// Renders `view` at `settings`: RGBA, straight alpha, sRGB colour, transparent
    /// background.
    ///
    /// # Errors
    /// [`RenderError::UnknownObject`] for an id the scene does not have,
    /// [`RenderError::EmptyView`] when there is nothing to frame, [`RenderError::BadSize`],
    /// [`RenderError::BadCamera`], [`RenderError::Gpu`] and [`RenderError::Readback`].
    pub fn render(&self, view: &View, settings: &RenderSettings) -> Result<RgbaImage, RenderError> {
        let shot = self.shot(view, settings)?;
        self.draw(&shot, settings, &view.file_name())
    }

    /// The camera `view` would use at `settings`, e.g. to find where a world point appears
    /// in its image ([`Camera::project`]).
    ///
    /// # Errors
    /// As [`PreparedScene::render`], without the GPU errors.
    pub fn camera(&self, view: &View, settings: &RenderSettings) -> Result<Camera, RenderError> {
        Ok(self.shot(view, settings)?.camera)
    }

    /// Renders `views` one after another, lazily (each item is rendered when the iterator
    /// reaches it).
    pub fn render_all<'a>(
        &'a self,
        views: &'a [View],
        settings: &'a RenderSettings,
    ) -> impl Iterator<Item = (&'a View, Result<RgbaImage, RenderError>)> + 'a {
        views.iter().map(move |v| (v, self.render(v, settings)))
    }
}

/// Writes `image` as a PNG file (deterministic: the same pixels give the same bytes),
/// atomically: encoded in memory, then written through a unique temporary file in the same
/// folder and renamed over `path` ([`sceneeval_files::write_atomic`]), so that a full disk or
/// a crash never leaves an empty or partial image and two writers of one file never fail.
///
/// # Errors
/// [`RenderError::WritePng`] when the image cannot be encoded or the file written.
pub fn write_png(image: &RgbaImage, path: &Path) -> Result<(), RenderError> {
    let failed = |source| RenderError::WritePng {
        path: path.to_owned(),
        source,
    };
    let mut bytes = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
        .map_err(failed)?;
    sceneeval_files::write_atomic(path, &bytes).map_err(|e| failed(image::ImageError::IoError(e)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn concurrent_png_writers_never_fail_and_leave_one_whole_image() {
        // Two writers replace one file 40 times each with a 256 x 256 image of their colour.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("front_bed.png");
        let images =
            [[200, 30, 30, 255], [30, 30, 200, 255]].map(|c| RgbaImage::from_pixel(256, 256, image::Rgba(c)));
        std::thread::scope(|s| {
            for img in &images {
                let path = &path;
                s.spawn(move || {
                    for _ in 0..40 {
                        write_png(img, path).unwrap();
                    }
                });
            }
        });
        let read = image::open(&path).unwrap().to_rgba8();
        assert!(read == images[0] || read == images[1]);
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1, "no temporary file left");
        // A folder that cannot be made is an error naming the file.
        std::fs::write(dir.path().join("file"), "x").unwrap();
        let err = write_png(&images[0], &dir.path().join("file/top.png")).unwrap_err();
        assert!(err.to_string().contains("top.png: cannot write PNG"), "{err}");
    }
}
