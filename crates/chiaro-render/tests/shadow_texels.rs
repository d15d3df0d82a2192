//! Shadow texels per pixel (`FrameOutput::shadow_texels_per_pixel`, `bench --json`'s
//! `shadow_texel_ratio_*`): a step of one pixel against the texels of the map that shaded
//! it. Overhead, orthographic, it is the pixel's size over the cascade texel's; it halves
//! when the image doubles; and it is missing where no map is sampled.

mod common;

use chiaro_math::shadow::AtlasLayout;
use chiaro_math::shadow::bias::cascade_texel_size_ws;
use chiaro_render::{FrameOptions, FrameOutput, View};
use chiaro_scene::{Light, LightKind, Scene, Settings};
use common::*;
use glam::Vec3;

fn render_shadow_aovs(scene: &Scene, settings: &Settings, size: u32) -> FrameOutput {
    let mut renderer = renderer();
    let prepared = renderer.prepare(scene).expect("prepare");
    let view = View::from_camera(scene, 0, size, size);
    renderer
        .render(scene, &prepared, &view, settings, FrameOptions { shadow_aovs: true, ..Default::default() })
        .expect("render")
}

fn finite(values: &[f32]) -> Vec<f32> {
    let mut v: Vec<f32> = values.iter().copied().filter(|r| r.is_finite()).collect();
    v.sort_by(f32::total_cmp);
    v
}

#[test]
fn overhead_it_is_the_pixel_over_the_cascade_texel() {
    let sun = Light { name: "sun".into(), ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::NEG_Y) };
    let mut scene = floor_scene(20.0, Vec3::new(0.0, 10.0, 0.0), vec![sun]);
    let ymag = 2.0;
    make_orthographic(&mut scene, ymag, 50.0);
    let mut settings = unlit_settings();
    settings.shadows.directional.cascade_count = 1;
    let size = 64;
    let out = render_shadow_aovs(&scene, &settings, size);
    let radius = out.plan.shadows.cascade_spheres[0].radius;
    let tile = AtlasLayout::for_tiles(settings.shadows.directional.atlas_size, 1).tile_size();
    let expected = (2.0 * ymag / size as f32) / cascade_texel_size_ws(radius, tile);
    let ratios = finite(&out.shadow_texels_per_pixel[0]);
    assert_eq!(ratios.len(), (size * size) as usize, "the floor fills the view");
    for r in [ratios[0], ratios[ratios.len() - 1]] {
        assert!((r / expected - 1.0).abs() < 0.01, "{r} texels per pixel, expected {expected}");
    }
    assert_eq!(out.shadow_texel_ratio_percentiles().map(|p| (p[1] / expected - 1.0).abs() < 0.01), Some(true));
}

#[test]
fn it_halves_when_the_image_doubles_and_is_missing_without_a_map() {
    let mut scene =
        floor_scene(20.0, Vec3::new(3.0, 2.5, 3.0), vec![point_light(Vec3::new(0.5, 1.5, 0.0), 20.0, Some(10.0))]);
    scene.lights[0].shadow = chiaro_scene::LightShadow::default();
    add_box(&mut scene, Vec3::new(0.0, 0.3, 0.0), Vec3::splat(0.6), 0.3, chiaro_scene::CastShadows::On);
    let settings = unlit_settings();
    let median = |size| {
        let out = render_shadow_aovs(&scene, &settings, size);
        out.shadow_texel_ratio_percentiles().expect("the point light's map is sampled")[1]
    };
    let (small, large) = (median(64), median(128));
    assert!((small / large - 2.0).abs() < 0.1, "64 px: {small}, 128 px: {large}");
    // Without shadows no map is sampled: no ratio anywhere.
    scene.lights[0].shadow.mode = chiaro_scene::ShadowMode::None;
    let out = render_shadow_aovs(&scene, &settings, 64);
    assert!(out.shadow_texels_per_pixel[0].iter().all(|r| r.is_nan()));
    assert_eq!(out.shadow_texel_ratio_percentiles(), None);
}
