//! The colour and depth targets and the readback buffer of one image size, kept by a
//! [`PreparedScene`](super::PreparedScene) between renders of that size.

use crate::pipeline::{COLOR_FORMAT, DEPTH_FORMAT, TARGET_FORMAT};
use crate::pixels;

/// Colour and depth targets and the readback buffer for one image size.
#[derive(Debug)]
pub(super) struct Targets {
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) samples: u32,
    /// The colour target drawn into ([`TARGET_FORMAT`]; multisampled, or `resolve` itself
    /// with one sample): opaque surfaces write sRGB-encoded bytes through this view...
    pub(super) encoded: wgpu::TextureView,
    /// ... and blended surfaces blend in linear light through this [`COLOR_FORMAT`] view.
    pub(super) linear: wgpu::TextureView,
    /// The single-sample image that is read back.
    pub(super) resolve: wgpu::Texture,
    /// With multisampling, `resolve`'s [`COLOR_FORMAT`] view, into which the samples are
    /// averaged in linear light; `None` with one sample.
    pub(super) resolve_linear: Option<wgpu::TextureView>,
    pub(super) depth: wgpu::TextureView,
    pub(super) readback: wgpu::Buffer,
    pub(super) padded_row: u32,
}

impl Targets {
    pub(super) fn new(device: &wgpu::Device, width: u32, height: u32, samples: u32) -> Targets {
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let texture = |label: &str, format, samples, usage, view_formats: &[wgpu::TextureFormat]| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats,
            })
        };
        let linear_view = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                format: Some(COLOR_FORMAT),
                ..Default::default()
            })
        };
        let resolve = texture(
            "colour",
            TARGET_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            &[COLOR_FORMAT],
        );
        let (encoded, linear, resolve_linear) = if samples > 1 {
            let msaa = texture(
                "colour (msaa)",
                TARGET_FORMAT,
                samples,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
                &[COLOR_FORMAT],
            );
            (
                msaa.create_view(&Default::default()),
                linear_view(&msaa),
                Some(linear_view(&resolve)),
            )
        } else {
            (
                resolve.create_view(&Default::default()),
                linear_view(&resolve),
                None,
            )
        };
        let depth = texture(
            "depth",
            DEPTH_FORMAT,
            samples,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
            &[],
        );
        let padded_row = pixels::padded_row_bytes(width);
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(padded_row) * u64::from(height),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Targets {
            width,
            height,
            samples,
            encoded,
            linear,
            resolve,
            resolve_linear,
            depth: depth.create_view(&Default::default()),
            readback,
            padded_row,
        }
    }
}
