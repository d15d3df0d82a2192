//! Shadow masks rendered: with every light mixed and the shadow distance at 0.1 m, the
//! shadows come from the mask alone and must agree with the ray-traced reference; across
//! the shadow distance the mixed term has no seam; LightsPunctualLamp's lights without
//! atlas tiles keep baked shadows.

mod common;

use chiaro_compare::{assert_agrees_with_reference, compare_shadows};
use chiaro_render::{FrameOptions, Renderer, ShadowStatus, View};
use chiaro_scene::{CastShadows, Light, LightKind, LightMode, MixedMode, Scene, Settings};
use chiaro_testkit::{add_box, floor_scene, renderer};
use common::baked_scene;
use glam::Vec3;

fn mask_settings() -> Settings {
    let mut s = Settings::default();
    s.render.ambient = [0.0; 3];
    s.bake.samples = Some(16);
    s.bake.bounces = 0;
    s.bake.texels_per_metre = 40.0;
    s.bake.probe_samples = Some(16);
    s.bake.probe_spacing = 4.0;
    s.lighting.mixed_mode = MixedMode::DistanceShadowmask;
    // Every shadow from the mask.
    s.shadows.max_distance = 0.1;
    s
}

fn mixed(mut light: Light, node: usize) -> Light {
    light.mode = LightMode::Mixed;
    light.node = node;
    light.intensity = if light.kind == LightKind::Directional { 2.0 } else { 25.0 };
    light.range = (light.kind != LightKind::Directional).then_some(9.0);
    light
}

fn spot() -> Light {
    let kind = LightKind::Spot { inner_cone_rad: 0.5, outer_cone_rad: 0.75 };
    mixed(Light::new(kind, Vec3::new(1.8, 2.2, 1.2), Vec3::new(-0.8, -1.0, -0.5)), 20)
}

fn point() -> Light {
    mixed(Light::new(LightKind::Point, Vec3::new(-0.9, 1.3, 0.9), Vec3::NEG_Y), 21)
}

fn sun() -> Light {
    mixed(Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(0.5, -1.0, -0.35)), 22)
}

fn boxes(lights: Vec<Light>) -> Scene {
    let mut scene = floor_scene(6.0, Vec3::new(0.0, 4.5, 3.5), lights);
    add_box(&mut scene, Vec3::new(0.3, 0.4, 0.1), Vec3::new(0.6, 0.8, 0.5), 0.4, CastShadows::On);
    add_box(&mut scene, Vec3::new(-0.7, 0.25, -0.6), Vec3::new(0.35, 0.5, 0.9), -0.3, CastShadows::On);
    add_box(&mut scene, Vec3::new(0.9, 0.6, -1.0), Vec3::new(0.3, 1.2, 0.3), 0.1, CastShadows::On);
    scene
}

#[test]
fn mask_shadows_agree_with_the_traced_reference() {
    let mut gpu = renderer();
    let s = mask_settings();
    for (label, lights) in [
        ("spot", vec![spot()]),
        ("point", vec![point()]),
        ("sun", vec![sun()]),
        ("spot, point and sun", vec![spot(), point(), sun()]),
    ] {
        let scene = baked_scene(&boxes(lights), &s);
        let view = View::from_camera(&scene, 0, 160, 160);
        let prepared = gpu.prepare(&scene).unwrap();
        let result = compare_shadows(&mut gpu, &scene, &prepared, &view, &s).unwrap();
        for report in &result.reports {
            let c = &report.comparison;
            let light = &scene.lights[report.light];
            println!(
                "{label}: {} channel {:?}: {} compared, {:.3}% disagree ({:.3}% false, {:.3}% missed)",
                light.name,
                scene.baked.as_ref().unwrap().channel(report.light),
                c.compared,
                100.0 * c.disagreement(),
                100.0 * c.false_share(),
                100.0 * c.missed_share()
            );
            assert!(scene.baked.as_ref().unwrap().channel(report.light).is_some(), "{label}: no channel");
            assert_eq!(result.status[report.light], ShadowStatus::Mapped, "{label}");
            assert!(c.compared > 3000, "{label}: {c:?}");
            assert_agrees_with_reference(label, c);
        }
    }
}

/// The shadow term of light 0 and the view depth along pixel column `x`, from the top.
fn shadow_column(gpu: &mut Renderer, scene: &Scene, s: &Settings, x: u32) -> Vec<(f32, f32)> {
    let size = 160;
    let view = View::from_camera(scene, 0, size, size);
    let prepared = gpu.prepare(scene).unwrap();
    let options = FrameOptions { aovs: true, shadow_aovs: true, readback: true, ..Default::default() };
    let frame = gpu.render(scene, &prepared, &view, s, options).unwrap();
    let depth = &frame.aovs.as_ref().unwrap().depth;
    (0..size).map(|y| (frame.shadow_aovs[0][(y * size + x) as usize], depth[(y * size + x) as usize])).collect()
}

fn largest_jump(line: &[f32]) -> f32 {
    line.windows(2).map(|w| (w[1] - w[0]).abs()).fold(0.0, f32::max)
}

/// A long thin bar above the floor, off to the side along the view direction, whose
/// shadow the sun throws onto the floor straight ahead of the camera; baked in `mode`
/// with the shadow distance at 9 m (fade band 6.3 to 9 m).
fn bar_scene(is_static: bool, mode: MixedMode) -> (Scene, Settings) {
    let mut light = sun();
    light.world_from_light = chiaro_math::rigid::looking_along(Vec3::ZERO, Vec3::new(-0.5, -1.0, 0.0));
    let mut scene = floor_scene(40.0, Vec3::ZERO, vec![light]);
    scene.cameras[0].world_from_view =
        glam::Mat4::look_at_rh(Vec3::new(0.0, 2.5, 3.0), Vec3::new(0.0, 0.0, -8.0), Vec3::Y).inverse();
    add_box(&mut scene, Vec3::new(1.0, 2.0, -8.5), Vec3::new(0.4, 0.1, 13.0), 0.0, CastShadows::On);
    scene.instances[1].is_static = is_static;
    let mut s = mask_settings();
    s.bake.texels_per_metre = 16.0;
    s.shadows.max_distance = 9.0;
    s.shadows.distance_fade = 0.3;
    s.lighting.mixed_mode = mode;
    (baked_scene(&scene, &s), s)
}

/// The centre column's shadow term from 5.5 to 12 m, far pixels first.
fn centre_line(gpu: &mut Renderer, scene: &Scene, s: &Settings) -> Vec<f32> {
    shadow_column(gpu, scene, s, 80)
        .into_iter()
        .filter(|(_, depth)| (5.5..12.0).contains(depth))
        .map(|(shadow, _)| shadow)
        .collect()
}

#[test]
fn mixed_modes_choose_where_shadows_come_from() {
    let mut gpu = renderer();
    // (static caster, mode, expected far end (past 9 m), expected near end (before 6.3 m))
    for (is_static, mode, far, near) in [
        (true, MixedMode::Shadowmask, 0.0, 0.0),
        (false, MixedMode::Shadowmask, 1.0, 0.0),
        (true, MixedMode::BakedIndirect, 1.0, 0.0),
        (false, MixedMode::BakedIndirect, 1.0, 0.0),
        (true, MixedMode::DistanceShadowmask, 0.0, 0.0),
        (false, MixedMode::DistanceShadowmask, 1.0, 0.0),
    ] {
        let (scene, s) = bar_scene(is_static, mode);
        let has_mask = !scene.baked.as_ref().unwrap().shadow_masks.is_empty();
        assert_eq!(has_mask, mode != MixedMode::BakedIndirect, "{mode:?} bakes a mask");
        let line = centre_line(&mut gpu, &scene, &s);
        let (first, last) = (line[0], line[line.len() - 1]);
        println!("{} bar, {mode:?}: far {first:.2}, near {last:.2}", if is_static { "static" } else { "dynamic" });
        assert!((first - far).abs() < 0.02 && (last - near).abs() < 0.02, "{is_static} {mode:?}: {line:?}");
        // A bake with masks rendered as baked-indirect: its masks are not used.
        if is_static && mode == MixedMode::DistanceShadowmask {
            let mut indirect = s.clone();
            indirect.lighting.mixed_mode = MixedMode::BakedIndirect;
            let line = centre_line(&mut gpu, &scene, &indirect);
            assert!((line[0] - 1.0).abs() < 0.02, "masks ignored in baked-indirect: {line:?}");
        }
    }
}

#[test]
fn no_seam_where_realtime_shadows_hand_over_to_the_mask() {
    // The centre column runs along the bar's shadow across the fade band. Dynamic, the
    // bar is missing from the mask and its realtime shadow fades out; static, both hold
    // its shadow.
    let mut gpu = renderer();
    for is_static in [false, true] {
        let (baked, s) = bar_scene(is_static, MixedMode::DistanceShadowmask);
        let mut realtime_only = s.clone();
        realtime_only.shadows.max_distance = 1000.0;
        let mut mask_only = s.clone();
        mask_only.shadows.max_distance = 0.1;
        let columns: Vec<Vec<f32>> =
            [&s, &realtime_only, &mask_only].iter().map(|settings| centre_line(&mut gpu, &baked, settings)).collect();
        let [mixed, realtime, mask] = [&columns[0], &columns[1], &columns[2]];
        let (j_mixed, j_realtime, j_mask) = (largest_jump(mixed), largest_jump(realtime), largest_jump(mask));
        let name = if is_static { "static bar" } else { "dynamic bar" };
        println!(
            "{name}: {} pixels; largest jump between neighbours: mixed {j_mixed:.3}, realtime only {j_realtime:.3}, \
             mask only {j_mask:.3}",
            mixed.len()
        );
        println!("  mixed {mixed:.2?}\n  realtime {realtime:.2?}\n  mask {mask:.2?}");
        assert!(mixed.len() > 20, "{name}: {} pixels", mixed.len());
        // Far pixels come first (rows from the top): the far end is the mask's, the near
        // end the realtime shadow's.
        assert!(
            (mixed[0] - mask[0]).abs() < 0.02 && (mixed[mixed.len() - 1] - realtime[realtime.len() - 1]).abs() < 0.02
        );
        // A hard switch would jump by the whole difference (1 for the dynamic bar).
        assert!(j_mixed <= j_realtime.max(j_mask) + 0.15, "{name}: a seam of {j_mixed}");
        if !is_static {
            let between = mixed.iter().filter(|&&v| v > 0.2 && v < 0.8).count();
            assert!(between >= 3, "the column crosses the fade band: {between} pixels in it");
        }
    }
}

#[test]
fn lights_without_atlas_tiles_keep_their_mask_shadows_in_the_lamp() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/assets/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf");
    let mut scene = chiaro_scene::load_gltf(&path).unwrap();
    for light in &mut scene.lights {
        light.mode = LightMode::Mixed;
    }
    let mut s = Settings::default();
    // The 16 tiles of Catlike Coding's Custom SRP tutorial "Point and Spot Shadows": two
    // of the five points fit (the default 64 holds all).
    s.shadows.other.max_tiles = 16;
    s.bake.samples = Some(16);
    s.bake.bounces = 1;
    s.bake.texels_per_metre = 128.0;
    s.bake.probe_samples = Some(16);
    let scene = baked_scene(&scene, &s);
    let mut gpu = renderer();
    let view = View::framing(&scene, s.camera.auto_yfov_deg.to_radians(), 256, 256);
    let prepared = gpu.prepare(&scene).unwrap();
    let result = compare_shadows(&mut gpu, &scene, &prepared, &view, &s).unwrap();
    let baked = scene.baked.as_ref().unwrap();
    let mut mask_only = 0;
    for report in &result.reports {
        let (light, c) = (&scene.lights[report.light], &report.comparison);
        let status = result.status[report.light];
        println!(
            "{} (node {}): {status:?}, channel {:?}, {} compared, {:.3}% disagree",
            light.name,
            light.node,
            baked.channel(report.light),
            c.compared,
            100.0 * c.disagreement()
        );
        match status {
            ShadowStatus::MaskOnly => {
                mask_only += 1;
                assert!(c.compared > 100, "{}: {c:?}", light.name);
                assert_agrees_with_reference(&light.name, c);
            }
            ShadowStatus::Mapped => assert_agrees_with_reference(&light.name, c),
            // Five lights overlap: Unity's rule bakes the least important fully.
            ShadowStatus::Baked => assert!(baked.demoted.contains(&report.light)),
            other => panic!("{}: {other:?}", light.name),
        }
    }
    assert!(mask_only >= 2, "{mask_only} lights shadowed by the mask alone");
    assert_eq!(baked.demoted.len(), 1);
}
