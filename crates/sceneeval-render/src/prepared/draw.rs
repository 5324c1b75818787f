//! Drawing one [`Shot`] of a [`PreparedScene`] into an image: opaque surfaces, then blended
//! ones, with closed meshes seen from outside drawn with their back faces culled.

use std::sync::PoisonError;

use image::RgbaImage;
use sceneeval_geom::{Aabb, Point3, Real};
use sceneeval_io::appearance::AlphaMode;

use super::targets::Targets;
use super::uniforms::{item_data, rotation_normal_matrix, view_uniform};
use super::{HUMAN_COLOR, NEVER_CUT, Owner, PreparedScene, Shot};
use crate::pipeline::{PipelineKey, SAMPLE_COUNTS};
use crate::pixels;
use crate::{NEAR_M, RenderError, RenderSettings};

/// A closed mesh is drawn with back faces culled only when its world box lies this much
/// (metres, plus a thousandth of the box diagonal) beyond the near plane: then the camera is
/// outside it and the near plane cuts nothing open.
const CULL_NEAR_MARGIN_M: Real = 0.01;

impl PreparedScene {
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
        let corners: [Point3; 8] = match owner {
            Owner::Object(i) => self.input.objects[i].world_aabb.corners(),
            Owner::Human => match &shot.human {
                Some(pose) => self.figure_bounds.corners().map(|c| pose * c),
                None => return false,
            },
            Owner::Floor | Owner::Wall(_) => return false,
        };
        let Some(bounds) = Aabb::from_points(&corners) else {
            return false;
        };
        let margin = NEAR_M + CULL_NEAR_MARGIN_M + 1e-3 * bounds.extents().norm();
        let camera = &shot.camera;
        let forward = camera.forward();
        corners
            .iter()
            .all(|c| (c - camera.position).dot(&forward) > margin)
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use sceneeval_io::assets::PlainFolderSource;
    use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state};

    use super::*;
    use crate::{Renderer, View, ViewKind};

    /// Every view of four fixture scenes with closed meshes culled and without: the images
    /// differ only where a back face and a front face of the same mesh meet at a silhouette
    /// and their depths tie (a few pixels); a wrong winding or a culled open mesh would lose
    /// whole faces.
    #[test]
    fn culling_closed_meshes_changes_only_silhouette_ties() {
        let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        let Some(renderer) = sceneeval_test_support::system::available(
            &sceneeval_test_support::system::GPU,
            Renderer::new(),
            crate::RenderError::is_missing_driver,
        ) else {
            return;
        };
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
