//! The wgpu device: one per process by default ([`Gpu::shared`]), or the caller's own.

use std::sync::{Arc, Mutex, PoisonError};

use crate::RenderError;

/// What is known about the adapter behind a [`Gpu`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AdapterSummary {
    /// The adapter's name (`llvmpipe (LLVM 15.0.6, 256 bits)` for Mesa's software driver).
    pub name: String,
    /// The backend (`Vulkan`, ...).
    pub backend: String,
    /// Discrete GPU, integrated GPU, CPU, ...
    pub device_type: String,
    /// Driver name and version, when the driver reports them.
    pub driver: String,
}

impl From<&wgpu::AdapterInfo> for AdapterSummary {
    fn from(info: &wgpu::AdapterInfo) -> Self {
        AdapterSummary {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
            driver: format!("{} {}", info.driver, info.driver_info).trim().to_owned(),
        }
    }
}

/// A wgpu device and its queue. Cheap to clone (the handles are reference counted).
#[derive(Debug, Clone)]
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: Arc<AdapterSummary>,
}

static SHARED: Mutex<Option<Gpu>> = Mutex::new(None);

impl Gpu {
    /// Opens a new device on the best adapter of the enabled backends: Vulkan unless the
    /// environment variable `WGPU_BACKEND` names others. A hardware GPU is preferred; Mesa's
    /// software driver (lavapipe) works too.
    ///
    /// Most callers want [`Gpu::shared`], which opens one device per process.
    ///
    /// # Driver noise on headless machines
    /// With Mesa's Vulkan drivers installed and `XDG_RUNTIME_DIR` unset (a container, CI, a
    /// service), opening the device prints `error: XDG_RUNTIME_DIR is invalid or not set in the
    /// environment.` to standard error; rendering works all the same. It comes from Mesa's
    /// implicit layer `VK_LAYER_MESA_device_select`: because wgpu enables the
    /// `VK_KHR_wayland_surface` instance extension whenever the driver offers it (wgpu 30 has no
    /// option to leave window-system extensions out), the layer calls libwayland's
    /// `wl_display_connect` while it orders the adapters, and libwayland prints that line when
    /// it finds no runtime folder. This crate cannot keep it out without `unsafe` (creating the
    /// Vulkan instance itself without those extensions, or redirecting file descriptor 2), which
    /// the workspace forbids, nor set the variables below for its own process (also `unsafe`
    /// since edition 2024). Set one of them in the environment instead: `NODEVICE_SELECT=1`
    /// turns the layer off (the Vulkan loader honours it; the adapter is chosen by wgpu
    /// anyway), or `XDG_RUNTIME_DIR` naming a folder of one's own.
    ///
    /// # Errors
    /// [`RenderError::NoAdapter`] (with the packages to install) when there is no adapter,
    /// [`RenderError::NoDevice`] when it cannot create a device.
    pub fn new() -> Result<Gpu, RenderError> {
        let backends = wgpu::Backends::VULKAN.with_env();
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = backends;
        desc.flags = wgpu::InstanceFlags::empty().with_env();
        let instance = wgpu::Instance::new(desc);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            ..Default::default()
        }))
        .map_err(|e| RenderError::NoAdapter {
            backends: format!("{backends:?}"),
            reason: e.to_string(),
        })?;
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("sceneeval-render"),
            required_features: wgpu::Features::empty(),
            required_limits: wgpu::Limits::default().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|source| RenderError::NoDevice {
            adapter: info.name.clone(),
            source,
        })?;
        // Errors of our own operations are caught by error scopes; anything else (from a
        // dropped resource, say) is logged instead of wgpu's default panic.
        device.on_uncaptured_error(Arc::new(|e: wgpu::Error| {
            tracing::error!(error = %e, "uncaptured GPU error");
        }));
        let adapter = AdapterSummary::from(&info);
        tracing::info!(adapter = %adapter.name, backend = %adapter.backend, kind = %adapter.device_type, "GPU device opened");
        Ok(Gpu {
            device,
            queue,
            adapter: Arc::new(adapter),
        })
    }

    /// The process-wide device, opened on first use (see [`Gpu::new`]) and shared by every
    /// later caller. A failure is not remembered: the next call tries again.
    ///
    /// # Errors
    /// As [`Gpu::new`].
    pub fn shared() -> Result<Gpu, RenderError> {
        let mut slot = SHARED.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(gpu) = slot.as_ref() {
            return Ok(gpu.clone());
        }
        let gpu = Gpu::new()?;
        *slot = Some(gpu.clone());
        Ok(gpu)
    }

    /// Wraps a device and queue the caller already has (an application that renders
    /// elsewhere too). The device needs no optional feature; default limits suffice.
    pub fn from_device(device: wgpu::Device, queue: wgpu::Queue) -> Gpu {
        let adapter = AdapterSummary::from(&device.adapter_info());
        Gpu {
            device,
            queue,
            adapter: Arc::new(adapter),
        }
    }

    /// The device.
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue.
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// The adapter the device runs on.
    pub fn adapter(&self) -> &AdapterSummary {
        &self.adapter
    }

    /// Runs `f` with validation and out-of-memory errors captured, turning them into
    /// [`RenderError::Gpu`] for `operation`.
    pub(crate) fn checked<T>(
        &self,
        operation: impl FnOnce() -> String,
        f: impl FnOnce() -> Result<T, RenderError>,
    ) -> Result<T, RenderError> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let result = f();
        let validation = pollster::block_on(validation.pop());
        let oom = pollster::block_on(oom.pop());
        match validation.or(oom) {
            Some(e) => Err(RenderError::Gpu {
                operation: operation(),
                message: e.to_string(),
            }),
            None => result,
        }
    }
}
