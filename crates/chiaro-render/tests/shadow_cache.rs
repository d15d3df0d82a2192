//! Shadow caching: a still scene draws its shadow tiles once; a moving light draws only
//! its own tiles again, a moving object only the tiles it casts into; and a cached frame
//! is the same image as a frame drawn from scratch.

mod common;

use chiaro_render::plan::shadows::ShadowAtlas;
use chiaro_render::{FrameOptions, FrameOutput, Renderer, View};
use chiaro_scene::{CastShadows, Light, LightKind, Scene, Settings};
use common::*;
use glam::{Mat4, Vec3};

fn scene() -> Scene {
    let sun = Light { intensity: 2.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(-0.4, -1.0, -0.3)) };
    let spot = Light {
        intensity: 30.0,
        range: Some(6.0),
        node: 21,
        ..Light::new(
            LightKind::Spot { inner_cone_rad: 0.4, outer_cone_rad: 0.6 },
            Vec3::new(-2.0, 3.0, 0.0),
            Vec3::new(0.2, -1.0, 0.0),
        )
    };
    let mut point = point_light(Vec3::new(2.0, 1.5, 0.0), 15.0, Some(3.0));
    point.shadow = Default::default();
    let mut scene = floor_scene(16.0, Vec3::new(0.0, 8.0, 6.0), vec![sun, spot, point]);
    add_box(&mut scene, Vec3::new(-2.0, 0.5, 0.0), Vec3::splat(1.0), 0.2, CastShadows::On);
    add_box(&mut scene, Vec3::new(2.0, 0.4, 0.5), Vec3::splat(0.8), 0.5, CastShadows::On);
    // Far from the spot and the point: it casts into the cascades alone.
    add_box(&mut scene, Vec3::new(4.0, 0.5, -7.0), Vec3::splat(1.0), 0.0, CastShadows::On);
    scene
}

fn frame(renderer: &mut Renderer, scene: &Scene, settings: &Settings) -> FrameOutput {
    let view = View::from_camera(scene, 0, 128, 128);
    let prepared = renderer.prepare(scene).unwrap();
    renderer.render(scene, &prepared, &view, settings, FrameOptions { readback: true, ..Default::default() }).unwrap()
}

/// The atlas and light (scene index) of each tile the frame drew, as its plan says.
fn redrawn(frame: &FrameOutput) -> Vec<(ShadowAtlas, u32)> {
    frame.plan.shadows.redrawn_tiles().map(|(_, t)| (t.atlas, t.light.0)).collect()
}

fn assert_same_image(a: &FrameOutput, b: &FrameOutput, what: &str) {
    let worst = a.hdr.iter().zip(&b.hdr).map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs())).fold(0.0, f32::max);
    assert!(worst <= 1e-6, "{what}: cached frame differs from a fresh one by {worst}");
}

#[test]
fn a_still_scene_draws_its_shadows_once() {
    let s = unlit_settings();
    let scene = scene();
    let mut gpu = renderer();
    let first = frame(&mut gpu, &scene, &s);
    let second = frame(&mut gpu, &scene, &s);
    let third = frame(&mut gpu, &scene, &s);
    println!("still scene: {} tiles, then {} and {}", first.shadow_tiles, second.shadow_tiles, third.shadow_tiles);
    assert_eq!(first.shadow_tiles, 4 + 1 + 6, "four cascades, a spot, a point");
    assert_eq!((second.shadow_tiles, third.shadow_tiles), (0, 0));
    assert_same_image(&first, &third, "still scene");

    let mut uncached = s.clone();
    uncached.shadows.cache = false;
    let again = frame(&mut gpu, &scene, &uncached);
    assert_eq!(again.shadow_tiles, 11, "without the cache every tile is drawn");
    assert_same_image(&first, &again, "cache off");
}

#[test]
fn a_moving_light_draws_only_its_own_tiles() {
    let s = unlit_settings();
    let mut scene = scene();
    let mut gpu = renderer();
    frame(&mut gpu, &scene, &s);
    scene.lights[1].world_from_light =
        chiaro_math::rigid::looking_along(Vec3::new(-2.2, 3.0, 0.3), Vec3::new(0.25, -1.0, -0.1));
    let moved = frame(&mut gpu, &scene, &s);
    println!("spot moved: {} tiles drawn", moved.shadow_tiles);
    assert_eq!(moved.shadow_tiles, 1, "the spot's tile alone");
    assert_eq!(redrawn(&moved), [(ShadowAtlas::Local, 1)], "the spot (light 1) is the one drawn again");
    assert_same_image(&moved, &frame(&mut renderer(), &scene, &s), "moved spot");
}

#[test]
fn a_moving_object_draws_only_the_tiles_it_casts_into() {
    let s = unlit_settings();
    let mut scene = scene();
    let mut gpu = renderer();
    frame(&mut gpu, &scene, &s);
    // The far box moves a little: it lies in no spot or point range, so only cascades
    // that hold it are drawn again.
    scene.instances[3].world_from_local = Mat4::from_translation(Vec3::new(4.3, 0.5, -7.0));
    let moved = frame(&mut gpu, &scene, &s);
    println!("far box moved: {} tiles drawn", moved.shadow_tiles);
    assert!(moved.shadow_tiles >= 1 && moved.shadow_tiles <= 4, "{} tiles", moved.shadow_tiles);
    let tiles = redrawn(&moved);
    assert_eq!(tiles.len(), moved.shadow_tiles, "the plan's redraws are the tiles drawn");
    assert!(tiles.iter().all(|&(atlas, light)| atlas == ShadowAtlas::Directional && light == 0), "{tiles:?}");
    assert_same_image(&moved, &frame(&mut renderer(), &scene, &s), "moved box");
    // The box by the point light moves: the point's faces it reaches are drawn again.
    scene.instances[2].world_from_local = Mat4::from_translation(Vec3::new(2.1, 0.4, 0.6));
    let moved = frame(&mut gpu, &scene, &s);
    println!("near box moved: {} tiles drawn", moved.shadow_tiles);
    assert!(moved.shadow_tiles > 1 && moved.shadow_tiles < 11, "{} tiles", moved.shadow_tiles);
    let tiles = redrawn(&moved);
    println!("near box moved: tiles drawn {tiles:?}");
    let point_faces = tiles.iter().filter(|&&(atlas, _)| atlas == ShadowAtlas::Local).count();
    assert!(
        tiles.iter().all(|&(atlas, light)| atlas == ShadowAtlas::Directional || light == 2),
        "only the point light's (light 2) faces among the point and spot tiles: {tiles:?}"
    );
    assert!((1..6).contains(&point_faces), "the faces the box reaches, not all six: {tiles:?}");
    assert_same_image(&moved, &frame(&mut renderer(), &scene, &s), "moved near box");
}

#[test]
fn forgetting_history_keeps_the_tiles_a_new_renderer_would_draw() {
    let s = unlit_settings();
    let scene = scene();
    let mut gpu = renderer();
    let first = frame(&mut gpu, &scene, &s);
    // Another job between, with its lights in another order and a box moved: its tiles
    // overwrite some of the first scene's.
    let mut other = scene.clone();
    other.lights.swap(1, 2);
    let moved = other.instances.iter().position(|i| i.world_from_local.w_axis.x == -2.0).unwrap();
    other.instances[moved].world_from_local *= Mat4::from_translation(Vec3::new(0.5, 0.0, 0.3));
    gpu.forget_history();
    frame(&mut gpu, &other, &s);
    gpu.forget_history();
    let again = frame(&mut gpu, &scene, &s);
    gpu.forget_history();
    let still = frame(&mut gpu, &scene, &s);
    let fresh = frame(&mut renderer(), &scene, &s);
    println!("after forgetting: {} tiles, then {}", again.shadow_tiles, still.shadow_tiles);
    assert!(again.shadow_tiles > 0, "the tiles the other job overwrote are drawn again");
    assert_same_image(&again, &fresh, "after another scene");
    assert_same_image(&still, &fresh, "the same job twice");
    assert_eq!(still.shadow_tiles, 0, "the same job again draws no tile: the cache outlives the history");
    assert_eq!(first.hdr, fresh.hdr);
}
