//! Shared set-up for the reference tests: a renderer on whatever adapter is present (the
//! software Vulkan device in CI) and the scenes of chiaro_testkit. No adapter
//! is a failure, never a skip.

#![allow(dead_code, unused_imports)]

pub use chiaro_testkit::*;

use chiaro_compare::{ShadowComparison, compare_shadows};
use chiaro_render::{GpuContext, Renderer, View};
use chiaro_scene::{Scene, Settings};

pub use chiaro_testkit::renderer;

/// Renders `scene` from its first camera at `size` x `size` and compares its shadows
/// with the ray-traced reference.
pub fn compare(scene: &Scene, settings: &Settings, size: u32) -> ShadowComparison {
    let mut renderer = renderer();
    let prepared = renderer.prepare(scene).unwrap();
    let view = View::from_camera(scene, 0, size, size);
    compare_shadows(&mut renderer, scene, &prepared, &view, settings).unwrap()
}
