//! A scene uploaded to the GPU once (meshes, textures, materials, per-item transforms) and
//! drawn from any number of cameras.
//!
//! One concept per file:
//! - this file: the [`PreparedScene`] and what its views are made of (draw items, their
//!   owners, one [`Shot`] per image) and the flat colours;
//! - `upload`: building a [`PreparedScene`]: meshes with the fewest vertex attributes,
//!   textures with their mipmaps, materials, and one draw item per part;
//! - `draw`: drawing one [`Shot`] into an image, with back faces culled where that is safe;
//! - `targets`: the colour and depth targets and the readback buffer of one image size;
//! - `uniforms`: the per-item and per-view uniforms, in the layout `shader.wgsl` reads.

mod draw;
mod targets;
mod uniforms;
mod upload;

use std::ops::Range;
use std::sync::Mutex;

use sceneeval_geom::{Aabb, Isometry3, Point3};

use crate::human::FigureMesh;
use crate::input::{ObjectInput, SceneInput};
use crate::pipeline::VertexKind;
use crate::{Camera, Renderer};

use targets::Targets;

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
    /// Whether the material masks by alpha (fragments below its cutoff are discarded).
    pub masked: bool,
    /// Whether the item may be drawn with back faces culled when its owner's box lies in
    /// front of the camera: its owner is drawn as one closed, outward-wound mesh
    /// ([`closed_outward`](crate::closed::closed_outward)) that is opaque everywhere, never
    /// cut, and not mirrored.
    pub closed: bool,
}

#[derive(Debug)]
struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    kind: VertexKind,
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
    /// alignment, at least [`ITEM_BYTES`](crate::pipeline::ITEM_BYTES)).
    item_stride: u64,
    /// The human figure's bounds in its own frame.
    figure_bounds: Aabb,
    view_buffer: wgpu::Buffer,
    view_bind_group: wgpu::BindGroup,
    targets: Mutex<Option<Targets>>,
}

impl PreparedScene {
    /// The ids of the scene's objects, in scene order.
    pub fn object_ids(&self) -> impl Iterator<Item = &str> + '_ {
        self.input.objects.iter().map(|o| o.id.as_str())
    }
}

/// World-space points of an object's mesh (for fitting cameras).
pub(crate) fn object_points(object: &ObjectInput) -> impl Iterator<Item = Point3> + '_ {
    object.mesh.vertices().iter().map(|v| object.pose * v)
}
