//! Building a [`PreparedScene`]: every mesh, texture and material uploaded once (meshes with
//! the fewest vertex attributes that draw them), one draw item per part of an object's look,
//! and the item buffer.

use std::collections::HashMap;
use std::ops::Range;
use std::sync::{Arc, Mutex, OnceLock};

use sceneeval_geom::na::Matrix4;
use sceneeval_geom::{Aabb, Matrix3, Mesh, Point3, Real, Vector3};
use sceneeval_io::AssetLibrary;
use sceneeval_io::appearance::{AlphaMode, Appearance, Texture, TextureBinding};

use super::uniforms::item_data;
use super::{
    BOX_COLOR, DrawItem, FLOOR_COLOR, GpuMesh, HUMAN_COLOR, NEVER_CUT, Owner, PreparedScene, WALL_COLOR,
};
use crate::closed::closed_outward;
use crate::human::{FigureMesh, human_figure};
use crate::input::{ObjectInput, SceneInput};
use crate::pipeline::{COLOR_FORMAT, ITEM_BYTES, VIEW_UNIFORM_BYTES, VertexKind};
use crate::pixels;
use crate::{RenderError, Renderer};

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
        let figure_bounds =
            Aabb::from_points(&figure_points).unwrap_or(Aabb::new(Point3::origin(), Point3::origin()));
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

#[cfg(test)]
mod tests {
    use sceneeval_io::appearance::{Material, MeshPart, RenderMesh, Sampler, Texture, TextureBinding};

    use super::*;

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
}
