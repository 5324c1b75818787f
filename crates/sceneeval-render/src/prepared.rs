//! A scene uploaded to the GPU once (meshes, textures, materials, per-item transforms) and
//! drawn from any number of cameras.

use std::collections::HashMap;
use std::ops::Range;
use std::sync::{Arc, Mutex, PoisonError};

use image::RgbaImage;
use sceneeval_geom::na::Matrix4;
use sceneeval_geom::{Isometry3, Matrix3, Mesh, Point3, Real, Vector3};
use sceneeval_io::AssetLibrary;
use sceneeval_io::appearance::{AlphaMode, Appearance, Texture, TextureBinding};

use crate::human::{FigureMesh, human_figure};
use crate::input::{ObjectInput, SceneInput};
use crate::pipeline::{COLOR_FORMAT, DEPTH_FORMAT, ITEM_STRIDE, SAMPLE_COUNTS, VIEW_UNIFORM_BYTES};
use crate::pixels;
use crate::{Camera, RenderError, RenderSettings, Renderer};

/// Linear base colour of box objects (no asset): a light, neutral grey.
pub const BOX_COLOR: [f32; 4] = [0.70, 0.69, 0.66, 1.0];
/// Linear base colour of floors: a light warm grey.
pub const FLOOR_COLOR: [f32; 4] = [0.46, 0.42, 0.37, 1.0];
/// Linear base colour of walls: off-white.
pub const WALL_COLOR: [f32; 4] = [0.80, 0.80, 0.78, 1.0];
/// Linear base colour of the human figure: a light neutral grey.
pub const HUMAN_COLOR: [f32; 4] = [0.55, 0.55, 0.55, 1.0];

/// `params.x` of items that are never cut.
const NEVER_CUT: f32 = 1e30;

/// What an item belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Owner {
    Object(usize),
    Floor,
    Wall(usize),
    Human,
}

/// One draw call: a range of a mesh's indices with one material.
#[derive(Debug, Clone)]
pub(crate) struct DrawItem {
    pub owner: Owner,
    pub mesh: usize,
    pub first_index: u32,
    pub index_count: u32,
    pub material: usize,
    pub blend: bool,
}

#[derive(Debug)]
struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
}

/// Colour and depth targets and the readback buffer for one image size.
#[derive(Debug)]
struct Targets {
    width: u32,
    height: u32,
    samples: u32,
    /// The multisampled colour target (resolved into `resolve`); `None` with one sample,
    /// when `resolve` is drawn into directly.
    msaa: Option<wgpu::TextureView>,
    resolve: wgpu::Texture,
    resolve_view: wgpu::TextureView,
    depth: wgpu::TextureView,
    readback: wgpu::Buffer,
    padded_row: u32,
}

/// What one image shows: the camera, the items drawn, where the human stands, whether
/// walls are cut.
#[derive(Debug, Clone)]
pub(crate) struct Shot {
    pub camera: Camera,
    pub items: Vec<usize>,
    pub human: Option<Isometry3>,
    pub cut_walls: bool,
}

/// A scene uploaded to the GPU, ready to render any [`crate::View`]. Made by
/// [`Renderer::prepare`]; every asset's meshes and textures are uploaded once and shared by
/// all views. Rendering takes `&self` and may be called from several threads (renders are
/// serialised).
#[derive(Debug)]
pub struct PreparedScene {
    pub(crate) renderer: Renderer,
    pub(crate) input: SceneInput,
    pub(crate) items: Vec<DrawItem>,
    pub(crate) object_items: Vec<Range<usize>>,
    pub(crate) human_item: usize,
    pub(crate) figure: FigureMesh,
    meshes: Vec<GpuMesh>,
    materials: Vec<wgpu::BindGroup>,
    item_buffer: wgpu::Buffer,
    view_buffer: wgpu::Buffer,
    view_bind_group: wgpu::BindGroup,
    targets: Mutex<Option<Targets>>,
}

/// Identifies a mesh uploaded once: an asset's render mesh or a geometry mesh (by the address
/// of its shared allocation), or the human figure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum MeshKey {
    Appearance(usize),
    Geometry(usize),
    Human,
}

/// Collects meshes, materials and items while a scene is uploaded.
struct Upload<'a> {
    renderer: &'a Renderer,
    meshes: Vec<GpuMesh>,
    mesh_by_key: HashMap<MeshKey, usize>,
    materials: Vec<wgpu::BindGroup>,
    material_by_key: HashMap<(usize, sceneeval_io::appearance::Sampler), usize>,
    items: Vec<DrawItem>,
    item_data: Vec<f32>,
}

impl PreparedScene {
    pub(crate) fn new(
        renderer: &Renderer,
        input: SceneInput,
        assets: &AssetLibrary,
    ) -> Result<PreparedScene, RenderError> {
        let gpu = renderer.gpu();
        gpu.checked(
            || "uploading the scene".to_owned(),
            || {
                let mut up = Upload::new(renderer);
                let mut object_items = Vec::with_capacity(input.objects.len());
                for (i, object) in input.objects.iter().enumerate() {
                    let start = up.items.len();
                    match object_appearance(object, assets) {
                        Some(look) => up.appearance_items(i, object, &look),
                        None => up.geometry_item(
                            Owner::Object(i),
                            &object.mesh,
                            &object.pose.to_homogeneous(),
                            BOX_COLOR,
                            NEVER_CUT,
                        ),
                    }
                    object_items.push(start..up.items.len());
                }
                for floor in &input.floors {
                    up.geometry_item(Owner::Floor, floor, &Matrix4::identity(), FLOOR_COLOR, NEVER_CUT);
                }
                for (w, wall) in input.walls.iter().enumerate() {
                    up.geometry_item(
                        Owner::Wall(w),
                        &wall.mesh,
                        &Matrix4::identity(),
                        WALL_COLOR,
                        wall.base_z as f32,
                    );
                }
                let figure = human_figure();
                let human_item = up.items.len();
                up.human_item(&figure);
                up.finish(input, object_items, human_item, figure)
            },
        )
    }

    /// The ids of the scene's objects, in scene order.
    pub fn object_ids(&self) -> impl Iterator<Item = &str> + '_ {
        self.input.objects.iter().map(|o| o.id.as_str())
    }

    /// Draws `shot` into a `settings.width x settings.height` RGBA image (transparent
    /// background, straight alpha, sRGB colour).
    pub(crate) fn draw(
        &self,
        shot: &Shot,
        settings: &RenderSettings,
        label: &str,
    ) -> Result<RgbaImage, RenderError> {
        let gpu = self.renderer.gpu();
        let (width, height) = (settings.width, settings.height);
        let max = gpu.device().limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(RenderError::BadSize { width, height, max });
        }
        if !SAMPLE_COUNTS.contains(&settings.samples) {
            return Err(RenderError::BadSamples {
                samples: settings.samples,
            });
        }
        shot.camera.check()?;
        let mut guard = self.targets.lock().unwrap_or_else(PoisonError::into_inner);
        gpu.checked(
            || format!("rendering {label}"),
            || {
                let targets = match guard.take() {
                    Some(t) if (t.width, t.height, t.samples) == (width, height, settings.samples) => t,
                    _ => Targets::new(gpu.device(), width, height, settings.samples),
                };
                let result = self.draw_into(&targets, shot, settings, label);
                *guard = Some(targets);
                result
            },
        )
    }

    fn draw_into(
        &self,
        targets: &Targets,
        shot: &Shot,
        settings: &RenderSettings,
        label: &str,
    ) -> Result<RgbaImage, RenderError> {
        let gpu = self.renderer.gpu();
        let (device, queue) = (gpu.device(), gpu.queue());
        queue.write_buffer(
            &self.view_buffer,
            0,
            bytemuck::cast_slice(&view_uniform(shot, settings)),
        );
        if let Some(pose) = &shot.human {
            let item = item_data(
                &pose.to_homogeneous(),
                &rotation_normal_matrix(pose),
                HUMAN_COLOR,
                NEVER_CUT,
                AlphaMode::Opaque,
            );
            queue.write_buffer(
                &self.item_buffer,
                self.human_item as u64 * ITEM_STRIDE,
                bytemuck::cast_slice(&item),
            );
        }
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(label),
                // With multisampling the samples are resolved into `resolve` and discarded;
                // without, `resolve` is drawn into directly.
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: targets.msaa.as_ref().unwrap_or(&targets.resolve_view),
                    depth_slice: None,
                    resolve_target: targets.msaa.as_ref().map(|_| &targets.resolve_view),
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: if targets.msaa.is_some() {
                            wgpu::StoreOp::Discard
                        } else {
                            wgpu::StoreOp::Store
                        },
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &targets.depth,
                    depth_ops: Some(wgpu::Operations {
                        // Reversed depth: 0 is infinitely far.
                        load: wgpu::LoadOp::Clear(0.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.view_bind_group, &[]);
            let passes = self.renderer.pipelines().passes(device, targets.samples);
            for (pipeline, blend) in [(&passes.opaque, false), (&passes.blend, true)] {
                pass.set_pipeline(pipeline);
                let mut bound_mesh = None;
                let mut bound_material = None;
                for &i in &shot.items {
                    let item = &self.items[i];
                    if item.blend != blend {
                        continue;
                    }
                    if bound_mesh != Some(item.mesh) {
                        let mesh = &self.meshes[item.mesh];
                        pass.set_vertex_buffer(0, mesh.vertices.slice(..));
                        pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                        bound_mesh = Some(item.mesh);
                    }
                    if bound_material != Some(item.material) {
                        pass.set_bind_group(1, &self.materials[item.material], &[]);
                        bound_material = Some(item.material);
                    }
                    let index = i as u32;
                    pass.draw_indexed(
                        item.first_index..item.first_index + item.index_count,
                        0,
                        index..index + 1,
                    );
                }
            }
        }
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &targets.resolve,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &targets.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(targets.padded_row),
                    rows_per_image: Some(targets.height),
                },
            },
            wgpu::Extent3d {
                width: targets.width,
                height: targets.height,
                depth_or_array_layers: 1,
            },
        );
        queue.submit([encoder.finish()]);
        let pixels = pixels::read_padded(
            device,
            &targets.readback,
            targets.width,
            targets.height,
            targets.padded_row,
            label,
        )?;
        let mut image = RgbaImage::from_raw(targets.width, targets.height, pixels).ok_or_else(|| {
            RenderError::Readback {
                view: label.to_owned(),
                message: "the image buffer has the wrong size".into(),
            }
        })?;
        pixels::unpremultiply(&mut image);
        Ok(image)
    }
}

/// The appearance an object is drawn with, if it shows an asset whose look can be loaded and
/// agrees with its geometry; `None` draws its geometry mesh in [`BOX_COLOR`].
fn object_appearance(object: &ObjectInput, assets: &AssetLibrary) -> Option<Arc<Appearance>> {
    if object.is_box {
        return None;
    }
    let model_id = object.model_id.as_deref()?;
    let look = match assets.appearance(model_id) {
        Ok(look) => look,
        Err(e) => {
            tracing::warn!(object = %object.id, model_id, error = %e, "appearance not loaded; drawing the geometry in grey");
            return None;
        }
    };
    // The render mesh, scaled, must cover the object's own mesh (the same vertices): a scene
    // built in code may give an object another mesh than its model id's.
    let (lo, hi) = look.mesh.bounds()?;
    let aabb = object.mesh.aabb();
    let tolerance = 1e-4 * (1.0 + aabb.extents().norm());
    let agrees = (0..3).all(|k| {
        let (a, b) = (
            Real::from(lo[k]) * object.scale[k],
            Real::from(hi[k]) * object.scale[k],
        );
        (a.min(b) - aabb.min[k]).abs() <= tolerance && (a.max(b) - aabb.max[k]).abs() <= tolerance
    });
    if agrees {
        Some(look)
    } else {
        tracing::warn!(object = %object.id, model_id, "the asset's look does not match the object's mesh; drawing the geometry in grey");
        None
    }
}

impl<'a> Upload<'a> {
    fn new(renderer: &'a Renderer) -> Self {
        let mut up = Upload {
            renderer,
            meshes: Vec::new(),
            mesh_by_key: HashMap::new(),
            materials: Vec::new(),
            material_by_key: HashMap::new(),
            items: Vec::new(),
            item_data: Vec::new(),
        };
        // Material 0: a white texel, for everything without a texture.
        let white = Texture {
            label: "white".into(),
            width: 1,
            height: 1,
            pixels: vec![255; 4],
        };
        let view = upload_texture(renderer.gpu(), &white);
        let bind_group = up.bind_group(&view, &sceneeval_io::appearance::Sampler::default());
        up.materials.push(bind_group);
        up
    }

    fn bind_group(
        &self,
        view: &wgpu::TextureView,
        sampler: &sceneeval_io::appearance::Sampler,
    ) -> wgpu::BindGroup {
        let device = self.renderer.gpu().device();
        let sampler = self.renderer.pipelines().sampler(device, sampler);
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("material"),
            layout: &self.renderer.pipelines().material_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&sampler),
                },
            ],
        })
    }

    /// The material slot of a texture binding (uploaded once per texture and sampler).
    fn texture_material(&mut self, binding: &TextureBinding) -> usize {
        let key = (Arc::as_ptr(&binding.texture) as usize, binding.sampler);
        if let Some(&m) = self.material_by_key.get(&key) {
            return m;
        }
        let view = upload_texture(self.renderer.gpu(), &binding.texture);
        let bind_group = self.bind_group(&view, &binding.sampler);
        self.materials.push(bind_group);
        let m = self.materials.len() - 1;
        self.material_by_key.insert(key, m);
        m
    }

    fn mesh(&mut self, key: MeshKey, vertices: &[f32], indices: &[u32]) -> usize {
        if let Some(&m) = self.mesh_by_key.get(&key) {
            return m;
        }
        use wgpu::util::DeviceExt;
        let device = self.renderer.gpu().device();
        let mesh = GpuMesh {
            vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("vertices"),
                contents: bytemuck::cast_slice(vertices),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("indices"),
                contents: bytemuck::cast_slice(indices),
                usage: wgpu::BufferUsages::INDEX,
            }),
        };
        self.meshes.push(mesh);
        let m = self.meshes.len() - 1;
        self.mesh_by_key.insert(key, m);
        m
    }

    fn push_item(&mut self, item: DrawItem, data: [f32; 36]) {
        self.items.push(item);
        self.item_data.extend_from_slice(&data);
    }

    /// One item per part of an asset's render mesh, placed by the object's pose and scale.
    fn appearance_items(&mut self, i: usize, object: &ObjectInput, look: &Arc<Appearance>) {
        let mesh = &look.mesh;
        let mut vertices = Vec::with_capacity(mesh.positions.len() * 12);
        for k in 0..mesh.positions.len() {
            vertices.extend_from_slice(&mesh.positions[k]);
            vertices.extend_from_slice(&mesh.normals[k]);
            vertices.extend_from_slice(&mesh.uvs[k]);
            vertices.extend_from_slice(&mesh.colors[k]);
        }
        let gpu_mesh = self.mesh(
            MeshKey::Appearance(Arc::as_ptr(look) as usize),
            &vertices,
            &mesh.indices,
        );
        let s = object.scale;
        let world = object.pose.to_homogeneous() * Matrix4::new_nonuniform_scaling(&s);
        let rotation = object.pose.rotation.to_rotation_matrix();
        let normal = rotation.matrix() * Matrix3::from_diagonal(&s.map(|v| 1.0 / v));
        for part in &mesh.parts {
            let Some(material) = look.materials.get(part.material) else {
                continue;
            };
            let slot = match &material.base_color_texture {
                Some(binding) => self.texture_material(binding),
                None => 0,
            };
            let data = item_data(
                &world,
                &normal,
                material.base_color,
                NEVER_CUT,
                material.alpha_mode,
            );
            self.push_item(
                DrawItem {
                    owner: Owner::Object(i),
                    mesh: gpu_mesh,
                    first_index: part.first_index,
                    index_count: part.index_count,
                    material: slot,
                    blend: material.alpha_mode == AlphaMode::Blend,
                },
                data,
            );
        }
    }

    /// One item drawing a geometry mesh (normals left to the shader) in a flat colour.
    fn geometry_item(
        &mut self,
        owner: Owner,
        mesh: &Arc<Mesh>,
        world: &Matrix4<Real>,
        color: [f32; 4],
        cut_base: f32,
    ) {
        let mut vertices = Vec::with_capacity(mesh.vertices().len() * 12);
        for v in mesh.vertices() {
            // Position; no normal (the shader shades flat) and no texture coordinates; white.
            vertices.extend_from_slice(&[v.x as f32, v.y as f32, v.z as f32]);
            vertices.extend_from_slice(&[0.0; 5]);
            vertices.extend_from_slice(&[1.0; 4]);
        }
        let indices: Vec<u32> = mesh.triangles().iter().flatten().copied().collect();
        let gpu_mesh = self.mesh(MeshKey::Geometry(Arc::as_ptr(mesh) as usize), &vertices, &indices);
        let normal = world.fixed_view::<3, 3>(0, 0).into_owned();
        let data = item_data(world, &normal, color, cut_base, AlphaMode::Opaque);
        self.push_item(
            DrawItem {
                owner,
                mesh: gpu_mesh,
                first_index: 0,
                index_count: indices.len() as u32,
                material: 0,
                blend: false,
            },
            data,
        );
    }

    fn human_item(&mut self, figure: &FigureMesh) {
        let mut vertices = Vec::with_capacity(figure.positions.len() * 12);
        for (p, n) in figure.positions.iter().zip(&figure.normals) {
            vertices.extend(p.iter().chain(n).map(|&v| v as f32));
            vertices.extend_from_slice(&[0.0, 0.0, 1.0, 1.0, 1.0, 1.0]);
        }
        let gpu_mesh = self.mesh(MeshKey::Human, &vertices, &figure.indices);
        let data = item_data(
            &Matrix4::identity(),
            &Matrix3::identity(),
            HUMAN_COLOR,
            NEVER_CUT,
            AlphaMode::Opaque,
        );
        self.push_item(
            DrawItem {
                owner: Owner::Human,
                mesh: gpu_mesh,
                first_index: 0,
                index_count: figure.indices.len() as u32,
                material: 0,
                blend: false,
            },
            data,
        );
    }

    fn finish(
        self,
        input: SceneInput,
        object_items: Vec<Range<usize>>,
        human_item: usize,
        figure: FigureMesh,
    ) -> Result<PreparedScene, RenderError> {
        use wgpu::util::DeviceExt;
        let renderer = self.renderer.clone();
        let device = renderer.gpu().device();
        let item_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("items"),
            contents: bytemuck::cast_slice(&self.item_data),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let view_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("view"),
            size: VIEW_UNIFORM_BYTES,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let view_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("view"),
            layout: &renderer.pipelines().view_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: view_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: item_buffer.as_entire_binding(),
                },
            ],
        });
        tracing::debug!(
            items = self.items.len(),
            meshes = self.meshes.len(),
            materials = self.materials.len(),
            "scene uploaded"
        );
        Ok(PreparedScene {
            renderer,
            input,
            items: self.items,
            object_items,
            human_item,
            figure,
            meshes: self.meshes,
            materials: self.materials,
            item_buffer,
            view_buffer,
            view_bind_group,
            targets: Mutex::new(None),
        })
    }
}

/// The 36 floats of one item: `world_from_local`, the normal matrix's columns, the base
/// colour and the parameters (see `shader.wgsl`).
fn item_data(
    world: &Matrix4<Real>,
    normal: &Matrix3,
    color: [f32; 4],
    cut_base: f32,
    alpha: AlphaMode,
) -> [f32; 36] {
    let mut d = [0.0f32; 36];
    for (k, v) in world.iter().enumerate() {
        d[k] = *v as f32;
    }
    for c in 0..3 {
        for r in 0..3 {
            d[16 + 4 * c + r] = normal[(r, c)] as f32;
        }
    }
    d[28..32].copy_from_slice(&color);
    let (cutoff, blend) = match alpha {
        AlphaMode::Opaque => (-1.0, 0.0),
        AlphaMode::Mask { cutoff } => (cutoff, 0.0),
        AlphaMode::Blend => (-1.0, 1.0),
    };
    d[32..36].copy_from_slice(&[cut_base, cutoff, blend, 0.0]);
    d
}

fn rotation_normal_matrix(pose: &Isometry3) -> Matrix3 {
    *pose.rotation.to_rotation_matrix().matrix()
}

/// The per-view uniform: clip matrix, camera position, light directions, options.
fn view_uniform(shot: &Shot, settings: &RenderSettings) -> [f32; 32] {
    let cam = &shot.camera;
    let clip = cam.clip_from_world(settings.width, settings.height);
    let (r, u, b) = (cam.right(), cam.up(), -cam.forward());
    // Key light from the upper left in front of the subject, a weaker fill from the right.
    let key = (-0.45 * r + 0.7 * u + 0.55 * b).normalize();
    let fill = (0.7 * r + 0.1 * u + 0.7 * b).normalize();
    let mut d = [0.0f32; 32];
    for (k, v) in clip.iter().enumerate() {
        d[k] = *v as f32;
    }
    let p = cam.position;
    d[16..20].copy_from_slice(&[p.x as f32, p.y as f32, p.z as f32, 1.0]);
    d[20..24].copy_from_slice(&vec4(&key));
    d[24..28].copy_from_slice(&vec4(&fill));
    let cut = if shot.cut_walls { 1.0 } else { 0.0 };
    d[28..32].copy_from_slice(&[cut, settings.wall_cut_height as f32, 0.0, 0.0]);
    d
}

fn vec4(v: &Vector3) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, 0.0]
}

impl Targets {
    fn new(device: &wgpu::Device, width: u32, height: u32, samples: u32) -> Targets {
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let texture = |label: &str, format, samples, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let msaa = (samples > 1).then(|| {
            texture(
                "colour (msaa)",
                COLOR_FORMAT,
                samples,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
            .create_view(&Default::default())
        });
        let resolve = texture(
            "colour",
            COLOR_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let depth = texture(
            "depth",
            DEPTH_FORMAT,
            samples,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
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
            msaa,
            resolve_view: resolve.create_view(&Default::default()),
            resolve,
            depth: depth.create_view(&Default::default()),
            readback,
            padded_row,
        }
    }
}

/// Uploads a texture with a full mipmap chain (box-filtered in linear light on the CPU, so
/// the result does not depend on the driver).
fn upload_texture(gpu: &crate::Gpu, texture: &Texture) -> wgpu::TextureView {
    let levels = pixels::mip_chain(texture.width, texture.height, &texture.pixels);
    let tex = gpu.device().create_texture(&wgpu::TextureDescriptor {
        label: Some(&texture.label),
        size: wgpu::Extent3d {
            width: texture.width,
            height: texture.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels.len() as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: COLOR_FORMAT,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (level, (w, h, pixels)) in levels.iter().enumerate() {
        gpu.queue().write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &tex,
                mip_level: level as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            pixels,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * w),
                rows_per_image: Some(*h),
            },
            wgpu::Extent3d {
                width: *w,
                height: *h,
                depth_or_array_layers: 1,
            },
        );
    }
    tex.create_view(&Default::default())
}

/// World-space points of an object's mesh (for fitting cameras).
pub(crate) fn object_points(object: &ObjectInput) -> impl Iterator<Item = Point3> + '_ {
    object.mesh.vertices().iter().map(|v| object.pose * v)
}
