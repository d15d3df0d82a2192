//! Screen-space ambient occlusion (`[ambient_occlusion]`) on both paths: it darkens the
//! ambient term by exactly the AO the frame reads back, the environment's light no more
//! than that, and direct light not at all. (Its agreement with the traced AO is
//! chiaro-compare's tests/ambient_occlusion.rs.)

mod common;

use chiaro_render::{FrameOptions, FrameOutput, Renderer, View};
use chiaro_scene::settings::EnvironmentSource;
use chiaro_scene::{CastShadows, Light, LightKind, RenderPath, Scene, Settings};
use common::*;
use glam::Vec3;

const SIZE: u32 = 96;

/// The HDR target holds half floats: 2^-11 relative, doubled for the read-back.
const HDR_TOLERANCE: f32 = 1.0e-3;

/// A unit box on a floor, seen from above and in front.
fn box_on_floor(lights: Vec<Light>) -> Scene {
    let mut scene = floor_scene(10.0, Vec3::ZERO, lights);
    look_from(&mut scene, Vec3::new(0.0, 3.0, 3.0), Vec3::new(0.0, 0.2, 0.0));
    add_box(&mut scene, Vec3::new(0.0, 0.5, 0.0), Vec3::ONE, 0.3, CastShadows::On);
    scene
}

fn render(renderer: &mut Renderer, scene: &Scene, settings: &Settings, ao: bool) -> FrameOutput {
    let mut settings = settings.clone();
    settings.ambient_occlusion.enabled = ao;
    settings.render.msaa = 1;
    let view = View::from_camera(scene, 0, SIZE, SIZE);
    let prepared = renderer.prepare(scene).expect("prepare");
    let options = FrameOptions { readback: true, ambient_occlusion: true, ..Default::default() };
    renderer.render(scene, &prepared, &view, &settings, options).expect("render")
}

fn luminance(p: &[f32; 4]) -> f32 {
    (p[0] + p[1] + p[2]) / 3.0
}

fn settings(path: RenderPath, ambient: f32) -> Settings {
    let mut settings = Settings::default();
    settings.render.path = path;
    settings.render.ambient = [ambient; 3];
    settings
}

#[test]
fn the_ambient_term_is_darkened_by_the_ao_read_back() {
    let scene = box_on_floor(vec![]);
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        // A renderer of its own: the AO this frame shades with must be this frame's, not
        // one an earlier frame left in the buffer.
        let mut renderer = renderer();
        let settings = settings(path, 0.5);
        let on = render(&mut renderer, &scene, &settings, true);
        let off = render(&mut renderer, &scene, &settings, false);
        assert!(off.ambient_occlusion.as_ref().unwrap().iter().all(|&a| a == 1.0), "{path:?}: AO off reads 1");
        let ao = on.ambient_occlusion.as_ref().expect("asked for");
        let occluded = ao.iter().filter(|&&a| a < 0.85).count();
        assert!(occluded > 50, "{path:?}: the box's foot must be occluded ({occluded} pixels)");
        for (i, &a) in ao.iter().enumerate() {
            let (before, after) = (luminance(&off.hdr[i]), luminance(&on.hdr[i]));
            let expected = before * a;
            assert!(
                (after - expected).abs() <= 2.0 * HDR_TOLERANCE * before.max(1e-3),
                "{path:?} pixel {i}: {before} x AO {a} = {expected}, rendered {after}"
            );
        }
    }
}

#[test]
fn direct_light_is_never_darkened() {
    let mut renderer = renderer();
    let sun = Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(0.3, -1.0, 0.4)) };
    let scene = box_on_floor(vec![sun]);
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let settings = settings(path, 0.0);
        let off = render(&mut renderer, &scene, &settings, false);
        let on = render(&mut renderer, &scene, &settings, true);
        assert!(on.ambient_occlusion.as_ref().unwrap().iter().any(|&a| a < 0.85), "{path:?}: nothing occluded");
        for (i, (a, b)) in off.hdr.iter().zip(&on.hdr).enumerate() {
            let (a, b) = (luminance(a), luminance(b));
            assert!((a - b).abs() <= 2.0 * HDR_TOLERANCE * a.max(1e-3), "{path:?} pixel {i}: {a} -> {b}");
        }
    }
}

#[test]
fn environment_light_is_darkened_no_more_than_the_ao() {
    let mut renderer = renderer();
    let scene = box_on_floor(vec![]);
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let mut settings = settings(path, 0.0);
        settings.environment.source = EnvironmentSource::Neutral;
        settings.environment.background = false;
        let off = render(&mut renderer, &scene, &settings, false);
        let on = render(&mut renderer, &scene, &settings, true);
        let ao = on.ambient_occlusion.as_ref().unwrap();
        let mut darkened = 0;
        for (i, &a) in ao.iter().enumerate() {
            let (before, after) = (luminance(&off.hdr[i]), luminance(&on.hdr[i]));
            let slack = 2.0 * HDR_TOLERANCE * before.max(1e-3);
            // Diffuse light x AO, the reflection x a specular occlusion at least the AO.
            assert!(after <= before + slack, "{path:?} pixel {i}: {before} -> {after}");
            assert!(after >= before * a - slack, "{path:?} pixel {i}: {before} x {a} > {after}");
            if a < 0.85 && after < 0.95 * before {
                darkened += 1;
            }
        }
        assert!(darkened > 50, "{path:?}: only {darkened} occluded pixels darkened");
    }
}
