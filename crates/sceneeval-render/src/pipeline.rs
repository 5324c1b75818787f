//! Compiled render pipelines, bind group layouts, samplers and the formats of the targets.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};

use sceneeval_io::appearance::{Filter, Sampler, Wrap};

/// Colour format of the targets: 8-bit sRGB, so the PNG bytes are gamma-encoded.
pub(crate) const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Depth format (reversed depth: 1 near, 0 far).
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Sample counts a render may use: 1 (no multisampling) or 4.
pub(crate) const SAMPLE_COUNTS: [u32; 2] = [1, 4];
/// Bytes per vertex: position, normal (3 x f32 each), uv (2 x f32), colour (4 x f32).
pub(crate) const VERTEX_STRIDE: u64 = 48;
/// Bytes per item in the storage buffer: a 4x4 matrix and five vec4s.
pub(crate) const ITEM_STRIDE: u64 = 144;
/// Bytes of the per-view uniform: a 4x4 matrix and four vec4s.
pub(crate) const VIEW_UNIFORM_BYTES: u64 = 128;

/// The two pipelines of one sample count: opaque surfaces, then blended ones.
#[derive(Debug)]
pub(crate) struct Passes {
    pub opaque: wgpu::RenderPipeline,
    pub blend: wgpu::RenderPipeline,
}

/// Everything compiled once per [`crate::Renderer`] (pipelines once per sample count).
#[derive(Debug)]
pub(crate) struct Pipelines {
    pub view_layout: wgpu::BindGroupLayout,
    pub material_layout: wgpu::BindGroupLayout,
    shader: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    passes: Mutex<HashMap<u32, Arc<Passes>>>,
    samplers: Mutex<HashMap<Sampler, wgpu::Sampler>>,
}

impl Pipelines {
    pub(crate) fn new(device: &wgpu::Device) -> Pipelines {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("sceneeval shader"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shader.wgsl").into()),
        });
        let view_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("view"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(VIEW_UNIFORM_BYTES),
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(ITEM_STRIDE),
                    },
                    count: None,
                },
            ],
        });
        let material_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("material"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sceneeval"),
            bind_group_layouts: &[Some(&view_layout), Some(&material_layout)],
            immediate_size: 0,
        });
        Pipelines {
            view_layout,
            material_layout,
            shader,
            layout,
            passes: Mutex::new(HashMap::new()),
            samplers: Mutex::new(HashMap::new()),
        }
    }

    /// The pipelines for `samples` samples per pixel, compiled on first use.
    pub(crate) fn passes(&self, device: &wgpu::Device, samples: u32) -> Arc<Passes> {
        let mut map = self.passes.lock().unwrap_or_else(PoisonError::into_inner);
        Arc::clone(map.entry(samples).or_insert_with(|| {
            Arc::new(Passes {
                opaque: self.pipeline(device, "opaque", false, samples),
                blend: self.pipeline(device, "blend", true, samples),
            })
        }))
    }

    fn pipeline(
        &self,
        device: &wgpu::Device,
        label: &str,
        blend: bool,
        samples: u32,
    ) -> wgpu::RenderPipeline {
        let attributes = wgpu::vertex_attr_array![
            0 => Float32x3,
            1 => Float32x3,
            2 => Float32x2,
            3 => Float32x4,
        ];
        let buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: VERTEX_STRIDE,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &attributes,
        })];
        let targets = [Some(wgpu::ColorTargetState {
            format: COLOR_FORMAT,
            // Premultiplied alpha: the shader writes (rgb * a, a).
            blend: blend.then_some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(&self.layout),
            vertex: wgpu::VertexState {
                module: &self.shader,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &buffers,
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                // Assets often have flipped triangles: draw both sides.
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(!blend),
                depth_compare: Some(wgpu::CompareFunction::Greater),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: samples,
                mask: !0,
                alpha_to_coverage_enabled: false,
            },
            fragment: Some(wgpu::FragmentState {
                module: &self.shader,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }

    /// The wgpu sampler for `s`, created once.
    pub(crate) fn sampler(&self, device: &wgpu::Device, s: &Sampler) -> wgpu::Sampler {
        let mut map = self.samplers.lock().unwrap_or_else(PoisonError::into_inner);
        map.entry(*s)
            .or_insert_with(|| {
                let wrap = |w: Wrap| match w {
                    Wrap::Repeat => wgpu::AddressMode::Repeat,
                    Wrap::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
                    Wrap::ClampToEdge => wgpu::AddressMode::ClampToEdge,
                };
                let filter = |f: Filter| match f {
                    Filter::Nearest => wgpu::FilterMode::Nearest,
                    Filter::Linear => wgpu::FilterMode::Linear,
                };
                let (mipmap_filter, lod_max_clamp) = match s.mipmap {
                    Some(Filter::Nearest) => (wgpu::MipmapFilterMode::Nearest, 32.0),
                    Some(Filter::Linear) => (wgpu::MipmapFilterMode::Linear, 32.0),
                    None => (wgpu::MipmapFilterMode::Nearest, 0.0),
                };
                device.create_sampler(&wgpu::SamplerDescriptor {
                    label: Some("material"),
                    address_mode_u: wrap(s.wrap_u),
                    address_mode_v: wrap(s.wrap_v),
                    address_mode_w: wgpu::AddressMode::ClampToEdge,
                    mag_filter: filter(s.magnify),
                    min_filter: filter(s.minify),
                    mipmap_filter,
                    lod_min_clamp: 0.0,
                    lod_max_clamp,
                    compare: None,
                    anisotropy_clamp: 1,
                    border_color: None,
                })
            })
            .clone()
    }
}
