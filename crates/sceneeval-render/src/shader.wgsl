// Three pairs of entry points sharing one lighting function. Each mesh is uploaded with the
// fewest vertex attributes that draw it exactly (see `pipeline.rs`, `VertexKind`), because on
// a CPU rasteriser every attribute passed from the vertex to the fragment stage costs per
// triangle and per pixel:
// - `vs_flat`/`fs_flat`: positions only; flat normals, the item's colour.
// - `vs_smooth`/`fs_smooth`: positions and normals; the item's colour.
// - `vs_full`/`fs_full`: positions, normals, texture coordinates and vertex colours, and the
//   base colour texture.
// Per-item transforms and colours come from a uniform buffer bound at a dynamic offset per
// draw; two-sided diffuse lighting from a fixed white rig; premultiplied-alpha output,
// sRGB-encoded here for opaque surfaces (`encode_srgb`) and by the target's sRGB view for
// blended ones.

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
@group(0) @binding(1) var<uniform> item: Item;
@group(1) @binding(0) var base_texture: texture_2d<f32>;
@group(1) @binding(1) var base_sampler: sampler;

// True for opaque surfaces, which are drawn into an Rgba8Unorm view of the colour target:
// the shader encodes sRGB once per pixel instead of the rasteriser once per sample. Blended
// surfaces output linear light into the target's sRGB view, which blends in linear light.
override encode_srgb: bool = false;

// False for surfaces that are never cut or alpha-masked: their pipelines contain no discard,
// so the rasteriser can test and write depth before shading in one step.
override may_discard: bool = true;

// Sky and ground brightness of the hemisphere light, key and fill strengths. A surface facing
// the key light gets at most about 1.0: white stays white, colours keep their hue.
const SKY: f32 = 0.42;
const GROUND: f32 = 0.24;
const KEY: f32 = 0.5;
const FILL: f32 = 0.16;

fn world_position(position: vec3<f32>) -> vec4<f32> {
    return item.world_from_local * vec4<f32>(position, 1.0);
}

fn world_normal(normal: vec3<f32>) -> vec3<f32> {
    return mat3x3<f32>(item.normal_x.xyz, item.normal_y.xyz, item.normal_z.xyz) * normal;
}

// The triangle's normal from the screen-space derivatives of the world position (call in
// uniform control flow).
fn flat_normal(world: vec3<f32>) -> vec3<f32> {
    let geometric = cross(dpdx(world), dpdy(world));
    let g_len = length(geometric);
    return select(vec3<f32>(0.0, 0.0, 1.0), geometric / max(g_len, 1e-30), g_len > 0.0);
}

// The interpolated normal where there is one, else the flat normal.
fn surface_normal(world: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
    let flat_n = flat_normal(world);
    let n_len = length(normal);
    return select(flat_n, normal / max(n_len, 1e-30), n_len > 1e-6);
}

// Lights `base` (linear RGBA) on a surface at `world` with unit normal `normal`, discards cut
// and masked fragments, and returns premultiplied RGBA.
fn shade(world: vec3<f32>, normal: vec3<f32>, base: vec4<f32>) -> vec4<f32> {
    // No back-face culling of open meshes (assets often have flipped triangles): light the
    // side we see.
    let to_camera = view.camera.xyz - world;
    let n = select(normal, -normal, dot(normal, to_camera) < 0.0);

    let hemisphere = mix(GROUND, SKY, 0.5 + 0.5 * n.z);
    let light = hemisphere + KEY * max(dot(n, view.key.xyz), 0.0) + FILL * max(dot(n, view.fill.xyz), 0.0);
    let rgb = min(base.rgb * light, vec3<f32>(1.0));
    let alpha = select(1.0, clamp(base.a, 0.0, 1.0), item.params.z > 0.5);

    let cut = view.options.x > 0.5 && world.z > item.params.x + view.options.y;
    let masked = item.params.y >= 0.0 && base.a < item.params.y;
    if (may_discard && (cut || masked)) {
        discard;
    }
    let premultiplied = rgb * alpha;
    return vec4<f32>(select(premultiplied, srgb_encode(premultiplied), encode_srgb), alpha);
}

// Linear light in [0, 1] to the sRGB transfer curve (IEC 61966-2-1).
fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let curve = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(curve, 12.92 * c, c <= vec3<f32>(0.0031308));
}

struct FlatOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
};

@vertex
fn vs_flat(@location(0) position: vec3<f32>) -> FlatOut {
    let world = world_position(position);
    var out: FlatOut;
    out.clip = view.clip_from_world * world;
    out.world = world.xyz;
    return out;
}

@fragment
fn fs_flat(in: FlatOut) -> @location(0) vec4<f32> {
    return shade(in.world, flat_normal(in.world), item.base_color);
}

struct SmoothOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

@vertex
fn vs_smooth(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> SmoothOut {
    let world = world_position(position);
    var out: SmoothOut;
    out.clip = view.clip_from_world * world;
    out.world = world.xyz;
    out.normal = world_normal(normal);
    return out;
}

@fragment
fn fs_smooth(in: SmoothOut) -> @location(0) vec4<f32> {
    return shade(in.world, surface_normal(in.world, in.normal), item.base_color);
}

struct FullIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) color: vec4<f32>,
};

struct FullOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) color: vec4<f32>,
};

@vertex
fn vs_full(v: FullIn) -> FullOut {
    let world = world_position(v.position);
    var out: FullOut;
    out.clip = view.clip_from_world * world;
    out.world = world.xyz;
    out.normal = world_normal(v.normal);
    out.uv = v.uv;
    out.color = v.color;
    return out;
}

@fragment
fn fs_full(in: FullOut) -> @location(0) vec4<f32> {
    // Everything that needs derivatives first, while control flow is uniform.
    let texel = textureSample(base_texture, base_sampler, in.uv);
    let n = surface_normal(in.world, in.normal);
    return shade(in.world, n, item.base_color * in.color * texel);
}
