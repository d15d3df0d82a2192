//! Shared set-up for the reference tests: a renderer on whatever adapter is present (the
//! software Vulkan device in CI) and the scenes of chiaro_testkit. No adapter
//! is a failure, never a skip.

#![allow(dead_code, unused_imports)]

pub use chiaro_testkit::*;

use chiaro_compare::{CompareOptions, LightComparison, ShadowComparison, compare_shadows, compare_shadows_with};
use chiaro_render::{GpuContext, Renderer, View};
use chiaro_scene::{CastShadows, Light, LightKind, LightShadow};
use chiaro_scene::{Scene, Settings};
use glam::Vec3;

pub use chiaro_testkit::renderer;

/// Renders `scene` from its first camera at `size` x `size` and compares its shadows
/// with the ray-traced reference.
pub fn compare(scene: &Scene, settings: &Settings, size: u32) -> ShadowComparison {
    let mut renderer = renderer();
    let prepared = renderer.prepare(scene).unwrap();
    let view = View::from_camera(scene, 0, size, size);
    compare_shadows(&mut renderer, scene, &prepared, &view, settings).unwrap()
}

// The close-up scenes of the contact and virtual shadow tests: a sun, a point light and a
// spot over a cube and low boxes, and a point light beside a wall.

/// A sun 30 degrees up.
pub fn sun() -> Light {
    let (e, a) = (30f32.to_radians(), -50f32.to_radians());
    let direction = -Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin());
    Light { name: "sun".into(), node: 7, intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, direction) }
}

/// A point light 1 m up beside the boxes.
pub fn point() -> Light {
    Light { shadow: LightShadow::default(), ..point_light(Vec3::new(1.2, 1.0, 1.0), 20.0, Some(10.0)) }
}

/// A spot from the point light's place, at the boxes.
pub fn spot() -> Light {
    let cone = LightKind::Spot { inner_cone_rad: 0.6, outer_cone_rad: 0.9 };
    let position = Vec3::new(1.2, 1.0, 1.0);
    let direction = (Vec3::new(0.5, 0.0, 0.7) - position).normalize();
    Light { name: "spot".into(), intensity: 20.0, range: Some(10.0), ..Light::new(cone, position, direction) }
}

/// A 1 m cube and boxes 4 and 8 cm tall on a floor, seen from 2 m, lit by `light` with
/// `normal_bias` (texels).
pub fn low_boxes(light: Light, normal_bias: f32) -> Scene {
    let mut scene = floor_scene(40.0, Vec3::ZERO, vec![light]);
    scene.lights[0].shadow.normal_bias = normal_bias;
    add_box(&mut scene, Vec3::new(0.0, 0.5, 0.0), Vec3::new(1.0, 1.0, 1.0), 0.4, CastShadows::On);
    add_box(&mut scene, Vec3::new(0.9, 0.02, 0.6), Vec3::new(0.3, 0.04, 0.2), 0.2, CastShadows::On);
    add_box(&mut scene, Vec3::new(0.2, 0.04, 1.0), Vec3::new(0.15, 0.08, 0.4), -0.3, CastShadows::On);
    look_from(&mut scene, Vec3::new(1.6, 0.6, 1.8), Vec3::new(0.3, 0.0, 0.4));
    scene
}

/// A point light 40 cm from a wall and 60 cm up, boxes at the wall's foot.
pub fn point_beside_a_wall() -> Scene {
    let point = Light { shadow: LightShadow::default(), ..point_light(Vec3::new(0.0, 0.6, -1.6), 10.0, Some(8.0)) };
    let mut scene = floor_scene(16.0, Vec3::ZERO, vec![point]);
    let mut wall = scene.instances[0].clone();
    wall.world_from_local = glam::Mat4::from_rotation_translation(
        glam::Quat::from_rotation_x(90f32.to_radians()),
        Vec3::new(0.0, 0.0, -2.0),
    );
    scene.instances.push(wall);
    for (x, side) in [(-0.6, 0.3), (0.5, 0.4), (0.1, 0.2)] {
        add_box(&mut scene, Vec3::new(x, side / 2.0, -1.75 + side / 2.0), Vec3::splat(side), 0.3, CastShadows::On);
    }
    scene
}

/// The first light's comparison with the reference at `edge_band_px` on a `size` x
/// `size` image.
pub fn judged_at(scene: &Scene, settings: &Settings, edge_band_px: usize, size: u32) -> LightComparison {
    let mut renderer = renderer();
    let prepared = renderer.prepare(scene).unwrap();
    let view = View::from_camera(scene, 0, size, size);
    let options = CompareOptions { edge_band_px };
    let result = compare_shadows_with(&mut renderer, scene, &prepared, &view, settings, options).unwrap();
    result.reports[0].comparison
}

/// False and missed shadow pixels.
pub fn disagreeing(c: &LightComparison) -> usize {
    c.false_shadow + c.missed_shadow
}

/// Disagreeing pixels' share of those compared.
pub fn share(c: &LightComparison) -> f64 {
    disagreeing(c) as f64 / c.compared.max(1) as f64
}
