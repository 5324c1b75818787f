//! Compiled render pipelines, bind group layouts, samplers and the formats of the targets.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};

use sceneeval_io::appearance::{Filter, Sampler, Wrap};

/// Format of colour textures: 8-bit sRGB-encoded colour, linear alpha.
pub(crate) const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Format of the colour targets: the same bytes as [`COLOR_FORMAT`] (gamma-encoded, what the
/// PNG stores), written as they are by opaque surfaces, which encode sRGB in the shader once
/// per pixel; a CPU rasteriser would otherwise convert every one of the 4 samples. Blended
/// surfaces and the multisample resolve use a [`COLOR_FORMAT`] view of the same texture, so
/// that they mix in linear light.
pub(crate) const TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Depth format (reversed depth: 1 near, 0 far).
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Sample counts a render may use: 1 (no multisampling) or 4.
pub(crate) const SAMPLE_COUNTS: [u32; 2] = [1, 4];
/// Bytes of one item's data in the uniform buffer: a 4x4 matrix and five vec4s (`Item` in
/// `shader.wgsl`).
pub(crate) const ITEM_BYTES: u64 = 144;
/// Bytes of the per-view uniform: a 4x4 matrix and four vec4s.
pub(crate) const VIEW_UNIFORM_BYTES: u64 = 128;

/// The vertex attributes a mesh is uploaded with, and the shader entry points that draw it.
/// Each kind draws exactly what [`VertexKind::Full`] would draw for such a mesh, with fewer
/// values passed per vertex and interpolated per pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum VertexKind {
    /// Positions only: no normals (flat shading), no texture, white vertex colours.
    Flat,
    /// Positions and normals: no texture, white vertex colours.
    Smooth,
    /// Positions, normals, texture coordinates and vertex colours, and the base colour
    /// texture.
    Full,
}

impl VertexKind {
    /// Every kind.
    pub(crate) const ALL: [VertexKind; 3] = [VertexKind::Flat, VertexKind::Smooth, VertexKind::Full];

    /// 32-bit floats per vertex: position (3), normal (3), uv (2), colour (4).
    pub(crate) const fn floats(self) -> usize {
        match self {
            VertexKind::Flat => 3,
            VertexKind::Smooth => 6,
            VertexKind::Full => 12,
        }
    }

    fn entry_points(self) -> (&'static str, &'static str) {
        match self {
            VertexKind::Flat => ("vs_flat", "fs_flat"),
            VertexKind::Smooth => ("vs_smooth", "fs_smooth"),
            VertexKind::Full => ("vs_full", "fs_full"),
        }
    }
}

/// One pipeline: the vertex kind, whether the surface blends, whether back faces are culled
/// (only for opaque closed meshes, see `closed.rs`), and whether fragments may be discarded
/// (walls cut in top views, alpha-masked materials). Without `discard` the shader has no
/// discard at all, which lets a CPU rasteriser test and write depth in one step before
/// shading.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) struct PipelineKey {
    pub kind: VertexKind,
    pub blend: bool,
    pub cull: bool,
    pub discard: bool,
}

impl PipelineKey {
    /// The pipelines renders use: opaque surfaces culled or not, opaque ones that may discard
    /// (never culled), and blended ones (never culled and never discarding: only objects
    /// blend, and they are not cut). Others are created if ever needed.
    pub(crate) fn all() -> impl Iterator<Item = PipelineKey> {
        VertexKind::ALL.into_iter().flat_map(|kind| {
            [
                (false, false, false),
                (false, true, false),
                (false, false, true),
                (true, false, false),
            ]
            .map(|(blend, cull, discard)| PipelineKey {
                kind,
                blend,
                cull,
                discard,
            })
        })
    }
}

/// Everything compiled once per [`crate::Renderer`] (pipelines once per sample count).
#[derive(Debug)]
pub(crate) struct Pipelines {
    pub view_layout: wgpu::BindGroupLayout,
    pub material_layout: wgpu::BindGroupLayout,
    shader: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    pipelines: Mutex<HashMap<(u32, PipelineKey), Arc<wgpu::RenderPipeline>>>,
    samplers: Mutex<HashMap<Sampler, wgpu::Sampler>>,
}

impl Pipelines {
    pub(crate) fn new(device: &wgpu::Device) -> Pipelines {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("sceneeval shader"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shader.wgsl").into()),
        });
        let uniform = |binding, bytes, dynamic| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: dynamic,
                min_binding_size: wgpu::BufferSize::new(bytes),
            },
            count: None,
        };
        let view_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("view"),
            entries: &[
                uniform(0, VIEW_UNIFORM_BYTES, false),
                // The item drawn: one window of the item buffer per draw call.
                uniform(1, ITEM_BYTES, true),
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
            pipelines: Mutex::new(HashMap::new()),
            samplers: Mutex::new(HashMap::new()),
        }
    }

    /// The pipeline `key` for `samples` samples per pixel, compiled on first use.
    pub(crate) fn pipeline(
        &self,
        device: &wgpu::Device,
        samples: u32,
        key: PipelineKey,
    ) -> Arc<wgpu::RenderPipeline> {
        let mut map = self.pipelines.lock().unwrap_or_else(PoisonError::into_inner);
        Arc::clone(
            map.entry((samples, key))
                .or_insert_with(|| Arc::new(self.create(device, samples, key))),
        )
    }

    fn create(&self, device: &wgpu::Device, samples: u32, key: PipelineKey) -> wgpu::RenderPipeline {
        let attributes = wgpu::vertex_attr_array![
            0 => Float32x3,
            1 => Float32x3,
            2 => Float32x2,
            3 => Float32x4,
        ];
        let used = match key.kind {
            VertexKind::Flat => 1,
            VertexKind::Smooth => 2,
            VertexKind::Full => 4,
        };
        let buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: (key.kind.floats() * 4) as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &attributes[..used],
        })];
        // Opaque surfaces write sRGB-encoded bytes into the target as it is; blended ones go
        // through its sRGB view and blend in linear light (`TARGET_FORMAT`).
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        let constants = [
            ("encode_srgb", flag(!key.blend)),
            ("may_discard", flag(key.discard)),
        ];
        let targets = [Some(wgpu::ColorTargetState {
            format: if key.blend { COLOR_FORMAT } else { TARGET_FORMAT },
            // Premultiplied alpha: the shader writes (rgb * a, a).
            blend: key
                .blend
                .then_some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let (vertex_entry, fragment_entry) = key.kind.entry_points();
        let label = format!(
            "{:?}{}{}{}",
            key.kind,
            if key.blend { " blend" } else { " opaque" },
            if key.cull { " culled" } else { "" },
            if key.discard { " discarding" } else { "" }
        );
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&label),
            layout: Some(&self.layout),
            vertex: wgpu::VertexState {
                module: &self.shader,
                entry_point: Some(vertex_entry),
                compilation_options: Default::default(),
                buffers: &buffers,
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                // Triangles are counter-clockwise seen from outside (glTF's convention).
                front_face: wgpu::FrontFace::Ccw,
                // Assets often have flipped triangles: both sides are drawn, except that a
                // closed mesh seen from outside cannot show its back faces.
                cull_mode: key.cull.then_some(wgpu::Face::Back),
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(!key.blend),
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
                entry_point: Some(fragment_entry),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    ..Default::default()
                },
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
