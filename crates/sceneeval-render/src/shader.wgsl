// One shader for everything: per-item transforms and colours from a storage buffer, an
// optional sRGB base colour texture, vertex colours, two-sided diffuse lighting from a fixed
// white rig, premultiplied-alpha output.

struct ViewData {
    clip_from_world: mat4x4<f32>,
    // xyz: camera position (world).
    camera: vec4<f32>,
    // xyz: unit direction towards the key light (world).
    key: vec4<f32>,
    // xyz: unit direction towards the fill light (world).
    fill: vec4<f32>,
    // x: 1 when walls are cut; y: the cut height above an item's base (metres).
    options: vec4<f32>,
};

struct Item {
    world_from_local: mat4x4<f32>,
    // Columns of the normal matrix (inverse transpose of the linear part).
    normal_x: vec4<f32>,
    normal_y: vec4<f32>,
    normal_z: vec4<f32>,
    // Linear RGBA base colour factor.
    base_color: vec4<f32>,
    // x: base z for cutting (walls; 1e30 for everything else); y: alpha cutoff (< 0: none);
    // z: 1 when alpha blends, 0 when the surface is opaque.
    params: vec4<f32>,
};

@group(0) @binding(0) var<uniform> view: ViewData;
@group(0) @binding(1) var<storage, read> items: array<Item>;
@group(1) @binding(0) var base_texture: texture_2d<f32>;
@group(1) @binding(1) var base_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) color: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) color: vec4<f32>,
    @location(4) @interpolate(flat) item: u32,
};

@vertex
fn vs_main(v: VertexIn, @builtin(instance_index) item_index: u32) -> VertexOut {
    let item = items[item_index];
    let world = item.world_from_local * vec4<f32>(v.position, 1.0);
    let normal_matrix = mat3x3<f32>(item.normal_x.xyz, item.normal_y.xyz, item.normal_z.xyz);
    var out: VertexOut;
    out.clip = view.clip_from_world * world;
    out.world = world.xyz;
    out.normal = normal_matrix * v.normal;
    out.uv = v.uv;
    out.color = v.color;
    out.item = item_index;
    return out;
}

// Sky and ground brightness of the hemisphere light, key and fill strengths. A surface facing
// the key light gets at most about 1.0: white stays white, colours keep their hue.
const SKY: f32 = 0.42;
const GROUND: f32 = 0.24;
const KEY: f32 = 0.5;
const FILL: f32 = 0.16;

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let item = items[in.item];
    // Everything that needs derivatives first, while control flow is uniform.
    let texel = textureSample(base_texture, base_sampler, in.uv);
    let geometric = cross(dpdx(in.world), dpdy(in.world));

    let g_len = length(geometric);
    let flat_normal = select(vec3<f32>(0.0, 0.0, 1.0), geometric / max(g_len, 1e-30), g_len > 0.0);
    let n_len = length(in.normal);
    var n = select(flat_normal, in.normal / max(n_len, 1e-30), n_len > 1e-6);
    // No back-face culling (assets often have flipped triangles): light the side we see.
    let to_camera = view.camera.xyz - in.world;
    n = select(n, -n, dot(n, to_camera) < 0.0);

    let hemisphere = mix(GROUND, SKY, 0.5 + 0.5 * n.z);
    let light = hemisphere + KEY * max(dot(n, view.key.xyz), 0.0) + FILL * max(dot(n, view.fill.xyz), 0.0);
    let base = item.base_color * in.color * texel;
    let rgb = min(base.rgb * light, vec3<f32>(1.0));
    let alpha = select(1.0, clamp(base.a, 0.0, 1.0), item.params.z > 0.5);

    let cut = view.options.x > 0.5 && in.world.z > item.params.x + view.options.y;
    let masked = item.params.y >= 0.0 && base.a < item.params.y;
    if (cut || masked) {
        discard;
    }
    return vec4<f32>(rgb * alpha, alpha);
}
