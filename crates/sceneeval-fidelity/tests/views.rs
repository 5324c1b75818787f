//! Rendered views written to a folder (feature `render`): written atomically, so two runs
//! writing the same view at once never fail and leave one whole image. Needs a Vulkan driver;
//! skipped without one unless `SCENEEVAL_REQUIRE_GPU=1`.

#![cfg(feature = "render")]
#![allow(clippy::unwrap_used)]

use sceneeval_fidelity::{ObjectViews, RenderedViews, ViewKind};
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Point2, Point3, Vector3};
use sceneeval_io::AssetLibrary;
use sceneeval_render::{RenderError, RenderSettings, Renderer};
use sceneeval_scene::{Category, RoomBuilder, Scene};
use sceneeval_test_support::system::{GPU, available};

/// A room with one desk of half-width `w`.
fn desk_scene(w: f64) -> Scene {
    Scene::builder()
        .room_builder(RoomBuilder::rectangle(
            "r",
            Point2::new(0.0, 0.0),
            Point2::new(4.0, 3.0),
        ))
        .add_box(
            "desk",
            Category::new("desk"),
            Vector3::new(w, 0.3, 0.375),
            pose_from_yaw(Point3::new(2.0, 1.5, 0.375), 0.0),
        )
        .build()
        .unwrap()
}

#[test]
fn two_runs_writing_one_view_never_fail_and_leave_one_whole_image() {
    let Some(renderer) = available(&GPU, Renderer::new(), RenderError::is_missing_driver) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let views = dir.path().join("views");
    let scenes = [desk_scene(0.6), desk_scene(0.3)];
    let images: Vec<Vec<u8>> = std::thread::scope(|s| {
        let handles: Vec<_> = scenes
            .iter()
            .map(|scene| {
                let (renderer, views) = (&renderer, &views);
                s.spawn(move || {
                    let mut bytes = Vec::new();
                    for _ in 0..10 {
                        let made = RenderedViews::new(
                            renderer,
                            scene,
                            &AssetLibrary::new(),
                            RenderSettings::square(32),
                            Some(views.clone()),
                        )
                        .unwrap();
                        bytes = made.view("desk", ViewKind::Front).unwrap().bytes().to_vec();
                    }
                    bytes
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert_ne!(images[0], images[1], "the two desks look different");
    let written = std::fs::read(views.join("front_desk.png")).unwrap();
    assert!(written == images[0] || written == images[1]);
    assert_eq!(
        std::fs::read_dir(&views).unwrap().count(),
        1,
        "no temporary file left"
    );
}
