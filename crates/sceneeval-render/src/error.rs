use std::path::PathBuf;

use thiserror::Error;

/// Everything that can go wrong preparing or rendering a scene.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum RenderError {
    /// No graphics adapter could be opened (no GPU driver and no software driver installed,
    /// or the backend chosen by `WGPU_BACKEND` is not available).
    #[error(
        "no graphics adapter found for backends {backends} ({reason}). Rendering needs a Vulkan \
         driver: on a machine without a GPU install Mesa's software driver (Debian/Ubuntu: \
         `apt-get install mesa-vulkan-drivers libvulkan1`); the environment variable \
         WGPU_BACKEND (e.g. `vulkan`) chooses the backend"
    )]
    NoAdapter {
        /// The backends that were tried.
        backends: String,
        /// What wgpu reported.
        reason: String,
    },
    /// The adapter refused to create a device.
    #[error("the graphics adapter {adapter:?} could not create a device")]
    NoDevice {
        /// The adapter's name.
        adapter: String,
        /// wgpu's error.
        #[source]
        source: wgpu::RequestDeviceError,
    },
    /// The GPU reported a validation or out-of-memory error during an operation.
    #[error("GPU error while {operation}: {message}")]
    Gpu {
        /// What was being done (`uploading the scene`, `rendering front_idx0_x.png`, ...).
        operation: String,
        /// wgpu's message.
        message: String,
    },
    /// Reading a rendered image back from the GPU failed.
    #[error("reading back {view} failed: {message}")]
    Readback {
        /// The view's file name.
        view: String,
        /// What went wrong.
        message: String,
    },
    /// The requested image size is zero or larger than the device allows.
    #[error("image size {width} x {height} is not supported (1 to {max} pixels per side)")]
    BadSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// The device's largest texture side.
        max: u32,
    },
    /// The requested number of samples per pixel is not supported.
    #[error("{samples} samples per pixel are not supported (1 or 4)")]
    BadSamples {
        /// Requested samples per pixel.
        samples: u32,
    },
    /// A view names an object the scene does not have.
    #[error("the scene has no object {id:?}")]
    UnknownObject {
        /// The id asked for.
        id: String,
    },
    /// A view shows nothing that a camera could be fitted to.
    #[error("{view}: nothing to show (no geometry in view)")]
    EmptyView {
        /// The view's file name.
        view: String,
    },
    /// A camera is not usable (non-finite position or rotation, zero lens or sensor).
    #[error("invalid camera: {reason}")]
    BadCamera {
        /// What is wrong with it.
        reason: String,
    },
    /// Writing a PNG failed.
    #[error("{}: cannot write PNG", .path.display())]
    WritePng {
        /// The file.
        path: PathBuf,
        /// The encoder's or file system's error.
        #[source]
        source: image::ImageError,
    },
}

impl RenderError {
    /// Whether this is the error of a machine without a graphics driver
    /// ([`RenderError::NoAdapter`]): what tests that need a renderer skip on (with
    /// `sceneeval_test_support::system::available`), unlike every other error.
    pub fn is_missing_driver(&self) -> bool {
        matches!(self, RenderError::NoAdapter { .. })
    }
}
