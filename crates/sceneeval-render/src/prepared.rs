//! A scene uploaded to the GPU once (meshes, textures, materials, per-item transforms) and
//! drawn from any number of cameras.

use std::collections::HashMap;
use std::ops::Range;
use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use image::RgbaImage;
use sceneeval_geom::na::Matrix4;
use sceneeval_geom::{Aabb, Isometry3, Matrix3, Mesh, Point3, Real, Vector3};
use sceneeval_io::AssetLibrary;
use sceneeval_io::appearance::{AlphaMode, Appearance, Texture, TextureBinding};

use crate::closed::closed_outward;
use crate::human::{FigureMesh, human_figure};
use crate::input::{ObjectInput, SceneInput};
use crate::pipeline::{
    COLOR_FORMAT, DEPTH_FORMAT, ITEM_BYTES, PipelineKey, SAMPLE_COUNTS, TARGET_FORMAT, VIEW_UNIFORM_BYTES,
    VertexKind,
};
use crate::pixels;
use crate::{Camera, NEAR_M, RenderError, RenderSettings, Renderer};

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

/// A closed mesh is drawn with back faces culled only when its world box lies this much
/// (metres, plus a thousandth of the box diagonal) beyond the near plane: then the camera is
/// outside it and the near plane cuts nothing open.
const CULL_NEAR_MARGIN_M: Real = 0.01;

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
    /// Whether the material masks by alpha (fragments below its cutoff are discarded).
    pub masked: bool,
    /// Whether the item may be drawn with back faces culled when its owner's box lies in
    /// front of the camera: its owner is drawn as one closed, outward-wound mesh
    /// ([`closed_outward`]) that is opaque everywhere, never cut, and not mirrored.
    pub closed: bool,
}

#[derive(Debug)]
struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    kind: VertexKind,
}

/// Colour and depth targets and the readback buffer for one image size.
#[derive(Debug)]
struct Targets {
    width: u32,
    height: u32,
    samples: u32,
    /// The colour target drawn into ([`TARGET_FORMAT`]; multisampled, or `resolve` itself
    /// with one sample): opaque surfaces write sRGB-encoded bytes through this view...
    encoded: wgpu::TextureView,
    /// ... and blended surfaces blend in linear light through this [`COLOR_FORMAT`] view.
    linear: wgpu::TextureView,
    /// The single-sample image that is read back.
    resolve: wgpu::Texture,
    /// With multisampling, `resolve`'s [`COLOR_FORMAT`] view, into which the samples are
    /// averaged in linear light; `None` with one sample.
    resolve_linear: Option<wgpu::TextureView>,
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
    /// Whether closed meshes in front of the camera are drawn with back faces culled (the
    /// image is the same either way up to depth ties at silhouettes; see
    /// [`DrawItem::closed`]).
    pub cull_closed: bool,
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
    /// Bytes between consecutive items in `item_buffer` (the device's uniform offset
    /// alignment, at least [`ITEM_BYTES`]).
    item_stride: u64,
    /// The human figure's bounds in its own frame.
    figure_bounds: Aabb,
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
    mesh_by_key: HashMap<MeshKey, (usize, bool)>,
    materials: Vec<wgpu::BindGroup>,
    material_by_key: HashMap<(usize, sceneeval_io::appearance::Sampler), usize>,
    items: Vec<DrawItem>,
    item_data: Vec<[f32; 36]>,
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
                self.human_item as u64 * self.item_stride,
                bytemuck::cast_slice(&item),
            );
        }
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
        // Opaque surfaces, then blended ones in a second pass through the linear view, which
        // also resolves the samples (in linear light); each in item order.
        for blend in [false, true] {
            let resolving = blend && targets.resolve_linear.is_some();
            if blend && !resolving && !shot.items.iter().any(|&i| self.items[i].blend) {
                break;
            }
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: if blend { &targets.linear } else { &targets.encoded },
                    depth_slice: None,
                    resolve_target: if blend {
                        targets.resolve_linear.as_ref()
                    } else {
                        None
                    },
                    ops: wgpu::Operations {
                        load: if blend {
                            wgpu::LoadOp::Load
                        } else {
                            wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT)
                        },
                        // Multisampled, the samples are resolved into `resolve` and discarded;
                        // with one sample `resolve` is the target.
                        store: if resolving {
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
                        load: if blend {
                            wgpu::LoadOp::Load
                        } else {
                            wgpu::LoadOp::Clear(0.0)
                        },
                        store: if blend {
                            wgpu::StoreOp::Discard
                        } else {
                            wgpu::StoreOp::Store
                        },
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let pipelines = self.renderer.pipelines();
            let mut bound_pipeline = None;
            let mut bound_mesh = None;
            let mut bound_material = None;
            for &i in &shot.items {
                let item = &self.items[i];
                if item.blend != blend {
                    continue;
                }
                let mesh = &self.meshes[item.mesh];
                let cut = shot.cut_walls && matches!(item.owner, Owner::Wall(_));
                let key = PipelineKey {
                    kind: mesh.kind,
                    blend,
                    cull: item.closed && shot.cull_closed && self.in_front(item.owner, shot),
                    discard: cut || item.masked,
                };
                if bound_pipeline != Some(key) {
                    pass.set_pipeline(&pipelines.pipeline(device, targets.samples, key));
                    bound_pipeline = Some(key);
                }
                if bound_mesh != Some(item.mesh) {
                    pass.set_vertex_buffer(0, mesh.vertices.slice(..));
                    pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                    bound_mesh = Some(item.mesh);
                }
                if bound_material != Some(item.material) {
                    pass.set_bind_group(1, &self.materials[item.material], &[]);
                    bound_material = Some(item.material);
                }
                // The item's window of the item buffer (fits in u32: checked at upload).
                let offset = (i as u64 * self.item_stride) as u32;
                pass.set_bind_group(0, &self.view_bind_group, &[offset]);
                pass.draw_indexed(item.first_index..item.first_index + item.index_count, 0, 0..1);
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

    /// Whether the world box of what `owner` draws lies entirely beyond the near plane of
    /// `shot`'s camera (with [`CULL_NEAR_MARGIN_M`]), so that the camera sees a closed mesh
    /// of it from outside and uncut. Only objects and the human are ever culled.
    fn in_front(&self, owner: Owner, shot: &Shot) -> bool {
        let corners: Vec<Point3> = match owner {
            Owner::Object(i) => {
                let b = &self.input.objects[i].world_aabb;
                box_corners(b.min, b.max).collect()
            }
            Owner::Human => match &shot.human {
                Some(pose) => box_corners(self.figure_bounds.min, self.figure_bounds.max)
                    .map(|c| pose * c)
                    .collect(),
                None => return false,
            },
            Owner::Floor | Owner::Wall(_) => return false,
        };
        let Some((lo, hi)) = bounds_of(&corners) else {
            return false;
        };
        let margin = NEAR_M + CULL_NEAR_MARGIN_M + 1e-3 * (hi - lo).norm();
        let camera = &shot.camera;
        let forward = camera.forward();
        corners
            .iter()
            .all(|c| (c - camera.position).dot(&forward) > margin)
    }
}

/// The 8 corners of the box `[lo, hi]`.
fn box_corners(lo: Point3, hi: Point3) -> impl Iterator<Item = Point3> {
    (0..8).map(move |k| {
        Point3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The componentwise minimum and maximum of `points`.
fn bounds_of(points: &[Point3]) -> Option<(Point3, Point3)> {
    let first = *points.first()?;
    Some(
        points
            .iter()
            .fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p))),
    )
}

/// The appearance an object is drawn with, if it shows an asset whose look can be loaded and
/// agrees with its geometry; `None` draws its geometry mesh in [`BOX_COLOR`].
fn object_appearance(object: &ObjectInput, assets: &AssetLibrary) -> Option<Arc<Appearance>> {
    if object.is_box {
        return None;
    }
    let model_id = object.model_id.as_deref()?;
    let look = match assets.appearance_facing(model_id, object.asset_front.as_ref()) {
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

    /// The GPU mesh of `key` (uploaded on first use) and whether it is closed and wound
    /// outward; `closed` is asked only on first use (`None`: not needed, taken as open).
    fn mesh(
        &mut self,
        key: MeshKey,
        kind: VertexKind,
        vertices: &[f32],
        indices: &[u32],
        closed: impl FnOnce() -> Option<bool>,
    ) -> (usize, bool) {
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
            kind,
        };
        self.meshes.push(mesh);
        let m = (self.meshes.len() - 1, closed().unwrap_or(false));
        self.mesh_by_key.insert(key, m);
        m
    }

    fn push_item(&mut self, item: DrawItem, data: [f32; 36]) {
        self.items.push(item);
        self.item_data.push(data);
    }

    /// One item per part of an asset's render mesh, placed by the object's pose and scale.
    fn appearance_items(&mut self, i: usize, object: &ObjectInput, look: &Arc<Appearance>) {
        let mesh = &look.mesh;
        let kind = render_mesh_kind(look);
        let mut vertices = Vec::with_capacity(mesh.positions.len() * kind.floats());
        for k in 0..mesh.positions.len() {
            vertices.extend_from_slice(&mesh.positions[k]);
            if kind != VertexKind::Flat {
                vertices.extend_from_slice(&mesh.normals[k]);
            }
            if kind == VertexKind::Full {
                vertices.extend_from_slice(&mesh.uvs[k]);
                vertices.extend_from_slice(&mesh.colors[k]);
            }
        }
        let (gpu_mesh, closed) = self.mesh(
            MeshKey::Appearance(Arc::as_ptr(look) as usize),
            kind,
            &vertices,
            &mesh.indices,
            || Some(closed_outward(&mesh.positions, &mesh.indices)),
        );
        let s = object.scale;
        let world = object.pose.to_homogeneous() * Matrix4::new_nonuniform_scaling(&s);
        let rotation = object.pose.rotation.to_rotation_matrix();
        let normal = rotation.matrix() * Matrix3::from_diagonal(&s.map(|v| 1.0 / v));
        let closed = closed && cullable_appearance(look, &s);
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
                    masked: matches!(material.alpha_mode, AlphaMode::Mask { .. }),
                    closed,
                },
                data,
            );
        }
    }

    /// One item drawing a geometry mesh (flat shaded) in a flat colour. Only objects' meshes
    /// may be culled (floors are open and walls are cut).
    fn geometry_item(
        &mut self,
        owner: Owner,
        mesh: &Arc<Mesh>,
        world: &Matrix4<Real>,
        color: [f32; 4],
        cut_base: f32,
    ) {
        let positions: Vec<[f32; 3]> = mesh
            .vertices()
            .iter()
            .map(|v| [v.x as f32, v.y as f32, v.z as f32])
            .collect();
        let vertices: Vec<f32> = positions.iter().flatten().copied().collect();
        let indices: Vec<u32> = mesh.triangles().iter().flatten().copied().collect();
        let cullable = matches!(owner, Owner::Object(_)) && cut_base == NEVER_CUT;
        let (gpu_mesh, closed) = self.mesh(
            MeshKey::Geometry(Arc::as_ptr(mesh) as usize),
            VertexKind::Flat,
            &vertices,
            &indices,
            || cullable.then(|| closed_outward(&positions, &indices)),
        );
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
                masked: false,
                closed: closed && cullable && normal.determinant() > 0.0,
            },
            data,
        );
    }

    fn human_item(&mut self, figure: &FigureMesh) {
        let positions: Vec<[f32; 3]> = figure.positions.iter().map(|p| p.map(|v| v as f32)).collect();
        let mut vertices = Vec::with_capacity(figure.positions.len() * VertexKind::Smooth.floats());
        for (p, n) in positions.iter().zip(&figure.normals) {
            vertices.extend_from_slice(p);
            vertices.extend(n.iter().map(|&v| v as f32));
        }
        let (gpu_mesh, closed) = self.mesh(
            MeshKey::Human,
            VertexKind::Smooth,
            &vertices,
            &figure.indices,
            // The figure is the same in every scene: check it once.
            || {
                static CLOSED: OnceLock<bool> = OnceLock::new();
                Some(*CLOSED.get_or_init(|| closed_outward(&positions, &figure.indices)))
            },
        );
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
                masked: false,
                closed,
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
        // Each item in its own window, at the device's uniform offset alignment.
        let align = u64::from(device.limits().min_uniform_buffer_offset_alignment).max(1);
        let item_stride = ITEM_BYTES.div_ceil(align) * align;
        let floats = (item_stride / 4) as usize;
        let mut contents = vec![0.0f32; floats * self.item_data.len()];
        for (k, data) in self.item_data.iter().enumerate() {
            contents[k * floats..k * floats + data.len()].copy_from_slice(data);
        }
        // Dynamic offsets are 32-bit.
        if contents.len() as u64 * 4 > u64::from(u32::MAX) {
            return Err(RenderError::Gpu {
                operation: "uploading the scene".into(),
                message: format!("{} draw items do not fit in one item buffer", self.items.len()),
            });
        }
        let item_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("items"),
            contents: bytemuck::cast_slice(&contents),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
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
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &item_buffer,
                        offset: 0,
                        size: wgpu::BufferSize::new(ITEM_BYTES),
                    }),
                },
            ],
        });
        let figure_points: Vec<Point3> = figure
            .positions
            .iter()
            .map(|p| Point3::new(p[0], p[1], p[2]))
            .collect();
        let (lo, hi) = bounds_of(&figure_points).unwrap_or((Point3::origin(), Point3::origin()));
        let figure_bounds = Aabb::new(lo, hi);
        tracing::debug!(
            items = self.items.len(),
            closed = self.items.iter().filter(|item| item.closed).count(),
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
            item_stride,
            figure_bounds,
            view_buffer,
            view_bind_group,
            targets: Mutex::new(None),
        })
    }
}

/// The fewest vertex attributes that draw `look` exactly: texture coordinates and vertex
/// colours only when a part has a texture or a vertex colour is not white, normals only when
/// the file gives some.
fn render_mesh_kind(look: &Appearance) -> VertexKind {
    let mesh = &look.mesh;
    let textured = mesh.parts.iter().any(|part| {
        look.materials
            .get(part.material)
            .is_some_and(|m| m.base_color_texture.is_some())
    });
    if textured || mesh.colors.iter().any(|c| *c != [1.0; 4]) {
        VertexKind::Full
    } else if mesh.normals.iter().any(|n| *n != [0.0; 3]) {
        VertexKind::Smooth
    } else {
        VertexKind::Flat
    }
}

/// Whether an object showing `look` at `scale` hides the back faces of its mesh, if the mesh
/// is closed and wound outward: every part is drawn and opaque (no blending, no alpha mask),
/// and the scale does not mirror the mesh (which would turn its outside faces clockwise).
fn cullable_appearance(look: &Appearance, scale: &Vector3) -> bool {
    let opaque = look.mesh.parts.iter().all(|part| {
        look.materials
            .get(part.material)
            .is_some_and(|m| m.alpha_mode == AlphaMode::Opaque)
    });
    opaque && scale.x * scale.y * scale.z > 0.0
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

#[cfg(test)]
mod tests {
    use std::path::Path;

    use sceneeval_io::appearance::{Material, MeshPart, RenderMesh, Sampler, Texture, TextureBinding};
    use sceneeval_io::assets::PlainFolderSource;
    use sceneeval_io::{ReadOptions, read_scene_state};

    use super::*;
    use crate::{View, ViewKind};

    /// A one-triangle look with two parts (materials 0 and 1, both opaque white).
    fn look() -> Appearance {
        Appearance {
            model_id: "test.tri".into(),
            path: "tri.glb".into(),
            mesh: RenderMesh {
                positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                normals: vec![[0.0; 3]; 3],
                uvs: vec![[0.0; 2]; 3],
                colors: vec![[1.0; 4]; 3],
                indices: vec![0, 1, 2, 0, 1, 2],
                parts: vec![
                    MeshPart {
                        first_index: 0,
                        index_count: 3,
                        material: 0,
                    },
                    MeshPart {
                        first_index: 3,
                        index_count: 3,
                        material: 1,
                    },
                ],
            },
            materials: vec![Material::gltf_default(), Material::gltf_default()],
        }
    }

    #[test]
    fn meshes_get_the_fewest_attributes_that_draw_them() {
        let mut l = look();
        // No normals, texture or vertex colour: positions only.
        assert_eq!(render_mesh_kind(&l), VertexKind::Flat);
        l.mesh.normals[1] = [0.0, 0.0, 1.0];
        assert_eq!(render_mesh_kind(&l), VertexKind::Smooth);
        // One vertex colour that is not white needs the full set.
        let mut coloured = l.clone();
        coloured.mesh.colors[2] = [1.0, 0.5, 1.0, 1.0];
        assert_eq!(render_mesh_kind(&coloured), VertexKind::Full);
        // So does a texture on any part's material.
        l.materials[1].base_color_texture = Some(TextureBinding {
            texture: Arc::new(Texture {
                label: "t".into(),
                width: 1,
                height: 1,
                pixels: vec![255; 4],
            }),
            sampler: Sampler::default(),
        });
        assert_eq!(render_mesh_kind(&l), VertexKind::Full);
    }

    #[test]
    fn only_opaque_unmirrored_looks_hide_back_faces() {
        let one = Vector3::repeat(1.0);
        assert!(cullable_appearance(&look(), &one));
        // Mirrored along one axis: the outside turns clockwise. Along two it does not.
        assert!(!cullable_appearance(&look(), &Vector3::new(-1.0, 1.0, 1.0)));
        assert!(cullable_appearance(&look(), &Vector3::new(-1.0, -1.0, 1.0)));
        for mode in [AlphaMode::Blend, AlphaMode::Mask { cutoff: 0.5 }] {
            let mut l = look();
            l.materials[1].alpha_mode = mode;
            assert!(!cullable_appearance(&l, &one), "{mode:?}");
        }
        // A part whose material is missing is not drawn: the mesh has a hole.
        let mut l = look();
        l.materials.pop();
        assert!(!cullable_appearance(&l, &one));
    }

    /// Every view of four fixture scenes with closed meshes culled and without: the images
    /// differ only where a back face and a front face of the same mesh meet at a silhouette
    /// and their depths tie (a few pixels); a wrong winding or a culled open mesh would lose
    /// whole faces.
    #[test]
    fn culling_closed_meshes_changes_only_silhouette_ties() {
        let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        let renderer = Renderer::new().unwrap();
        let settings = RenderSettings::square(128);
        let limit = 128 * 128 / 200;
        let (mut views, mut culled_views) = (0, 0);
        for n in [0, 4, 9, 11] {
            let assets =
                AssetLibrary::new().with_source("fixture", PlainFolderSource::new(fixtures.join("assets")));
            let path = fixtures.join(format!("scenes/scene_{n}.json"));
            let scene = read_scene_state(&path, &assets, &ReadOptions::default()).unwrap();
            let prepared = renderer.prepare(&scene, &assets).unwrap();
            let ids: Vec<&str> = prepared.object_ids().collect();
            for view in View::standard(&ViewKind::ALL, ids) {
                views += 1;
                let mut shot = prepared.shot(&view, &settings).unwrap();
                if shot
                    .items
                    .iter()
                    .any(|&i| prepared.items[i].closed && prepared.in_front(prepared.items[i].owner, &shot))
                {
                    culled_views += 1;
                }
                let culled = prepared.draw(&shot, &settings, "culled").unwrap();
                shot.cull_closed = false;
                let both_sides = prepared.draw(&shot, &settings, "both sides").unwrap();
                let differing = culled
                    .pixels()
                    .zip(both_sides.pixels())
                    .filter(|(a, b)| a != b)
                    .count();
                assert!(differing <= limit, "scene {n} {view}: {differing} pixels differ");
            }
        }
        // 33 objects with 3 views each, and 4 top views. All but 4 cull something: the front
        // views of the sofa, bookshelf and chair (assets that are not closed) and the chair's
        // surroundings view; size views cull the human figure.
        assert_eq!((views, culled_views), (33 * 3 + 4, 99));
    }
}
