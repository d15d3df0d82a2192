//! Shared set-up for the GPU tests: a renderer on whatever adapter is present (the
//! software Vulkan device in CI), the scenes of chiaro_testkit, and a frame
//! with its AOVs. No adapter is a failure, never a skip.

#![allow(dead_code, unused_imports)]

pub use chiaro_testkit::*;

use chiaro_render::{FrameOptions, FrameOutput, GpuContext, Renderer, View};
use chiaro_scene::{Scene, Settings};
use glam::Vec3;
use std::path::PathBuf;

pub use chiaro_testkit::{renderer, srgb_encode};

pub fn render(renderer: &mut Renderer, scene: &Scene, settings: &Settings, size: u32) -> FrameOutput {
    let view = View::from_camera(scene, 0, size, size);
    let prepared = renderer.prepare(scene).expect("prepare");
    renderer
        .render(scene, &prepared, &view, settings, FrameOptions { aovs: true, readback: true, ..Default::default() })
        .expect("render")
}

/// A small sunlit floor turned so that its edges cross pixels at every angle, against
/// the black background: what the antialiasing tests look at.
pub fn turned_floor_scene() -> Scene {
    let sun = chiaro_scene::Light {
        name: "sun".into(),
        node: 2,
        intensity: 3.0,
        ..chiaro_scene::Light::new(chiaro_scene::LightKind::Directional, Vec3::ZERO, Vec3::NEG_Y)
    };
    let mut scene = floor_scene(3.0, Vec3::new(1.0, 5.0, 2.0), vec![sun]);
    scene.instances[0].world_from_local = glam::Mat4::from_rotation_y(0.37);
    scene
}

/// The frame's LDR image as RGB8, alpha dropped, as FLIP compares it.
pub fn ldr_rgb(frame: &FrameOutput) -> Vec<u8> {
    frame.ldr.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect()
}

/// NVIDIA FLIP's mean error between two `size` x `size` RGB8 images.
pub fn mean_flip(size: u32, reference: &[u8], test: &[u8]) -> f32 {
    let error = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(size, size, reference),
        nv_flip::FlipImageRgb8::with_data(size, size, test),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    nv_flip::FlipPool::from_image(&error).mean()
}

/// Covered pixels: (index, world position, normal, rendered radiance).
pub fn surface_pixels(frame: &FrameOutput) -> Vec<(usize, Vec3, Vec3, Vec3)> {
    let aovs = frame.aovs.as_ref().expect("aovs");
    (0..frame.hdr.len())
        .filter(|&i| aovs.position_ws[i][0].is_finite())
        .map(|i| {
            let h = frame.hdr[i];
            (i, Vec3::from(aovs.position_ws[i]), Vec3::from(aovs.normal_ws[i]), Vec3::new(h[0], h[1], h[2]))
        })
        .collect()
}

/// Every glTF scene in the repository's tests/assets.
pub fn asset_scenes() -> Vec<PathBuf> {
    let root = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets"));
    let mut scenes = Vec::new();
    let mut stack = vec![root.clone()];
    while let Some(dir) = stack.pop() {
        let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        for entry in entries {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "gltf" || e == "glb") {
                scenes.push(path);
            }
        }
    }
    scenes.sort();
    assert!(scenes.len() >= 6, "expected the six test scenes under {}, found {scenes:?}", root.display());
    scenes
}
