//! The uniforms the shader reads: 36 floats per draw item and 32 per view, in the layout of
//! `shader.wgsl`.

use sceneeval_geom::na::Matrix4;
use sceneeval_geom::{Isometry3, Matrix3, Real, Vector3};
use sceneeval_io::appearance::AlphaMode;

use super::Shot;
use crate::RenderSettings;

/// The 36 floats of one item: `world_from_local`, the normal matrix's columns, the base
/// colour and the parameters (see `shader.wgsl`).
pub(super) fn item_data(
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

pub(super) fn rotation_normal_matrix(pose: &Isometry3) -> Matrix3 {
    *pose.rotation.to_rotation_matrix().matrix()
}

/// The per-view uniform: clip matrix, camera position, light directions, options.
pub(super) fn view_uniform(shot: &Shot, settings: &RenderSettings) -> [f32; 32] {
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
