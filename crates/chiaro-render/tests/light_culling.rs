//! Light culling on the GPU: with no limit reached, clustered, per-object and no culling
//! give the same image; a thousand lights under clustered culling add up to the sum of
//! renders of fifty lights at a time without culling (also with lights far smaller than
//! their depth slices); more than 32 shadowed lights in one cluster (the shader marks them
//! 32 at a time) shade as without culling; per-object lists keep the most important
//! lights of each object.

mod common;

use chiaro_render::plan::FramePlan;
use chiaro_render::plan::draws::{GeometryLayout, scene_draws};
use chiaro_render::plan::shadows::ShadowAtlasTiles;
use chiaro_render::{FrameOptions, FrameOutput, Renderer, View};
use chiaro_scene::{
    CastShadows, ColorSpace, Cookie, Image, LightCulling, LightKind, RenderPath, Scene, Settings, ShadowMode, load_gltf,
};
use common::*;
use glam::{Vec2, Vec3};

const SIZE: u32 = 128;

/// An opaque linear RGB8 image of `width` x `height` texels from `rgb(x, y)`.
fn rgb_image(width: u32, height: u32, rgb: impl Fn(u32, u32) -> [u8; 3]) -> Image {
    let rgba8 = (0..height).flat_map(|y| (0..width).map(move |x| (x, y))).flat_map(|(x, y)| {
        let [r, g, b] = rgb(x, y);
        [r, g, b, 255]
    });
    Image {
        name: "cookie".into(),
        width,
        height,
        rgba8: rgba8.collect(),
        file_mips: Vec::new(),
        basis_source: None,
        color_space: ColorSpace::Linear,
    }
}

fn render_hdr(renderer: &mut Renderer, scene: &Scene, settings: &Settings) -> FrameOutput {
    let view = if scene.cameras.is_empty() {
        View::framing(scene, 45f32.to_radians(), SIZE, SIZE)
    } else {
        View::from_camera(scene, 0, SIZE, SIZE)
    };
    let prepared = renderer.prepare(scene).expect("prepare");
    renderer
        .render(scene, &prepared, &view, settings, FrameOptions { readback: true, ..Default::default() })
        .expect("render")
}

fn forward(culling: LightCulling) -> Settings {
    let mut s = unlit_settings();
    s.render.path = RenderPath::Forward;
    s.lights.culling = culling;
    s
}

/// Largest difference between two HDR images relative to the brighter of each pixel's
/// channels, ignoring values under `floor`.
fn worst_relative_difference(a: &FrameOutput, b: &FrameOutput, floor: f32) -> f32 {
    a.hdr
        .iter()
        .zip(&b.hdr)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c], q[c])))
        .filter(|(x, y)| x.max(*y) > floor)
        .map(|(x, y)| (x - y).abs() / x.max(y))
        .fold(0.0, f32::max)
}

/// A floor with boxes and seven lights: shadowed and unshadowed points, a shadowed spot.
fn boxes_scene() -> Scene {
    let mut lights = Vec::new();
    for (i, p) in
        [(-3.0, 1.0, -2.0), (2.5, 1.5, 1.0), (0.0, 0.8, 3.0), (-2.0, 2.0, 2.5), (3.0, 0.6, -3.0), (0.5, 1.2, 0.0)]
            .into_iter()
            .enumerate()
    {
        let mut l = point_light(Vec3::from(p), 4.0 + i as f32, Some(4.0 + i as f32 * 0.5));
        if i % 2 == 1 {
            l.shadow.mode = ShadowMode::None;
        }
        lights.push(l);
    }
    let spot = chiaro_scene::Light {
        name: "spot".into(),
        node: 11,
        intensity: 30.0,
        range: Some(9.0),
        ..chiaro_scene::Light::new(
            LightKind::Spot { inner_cone_rad: 0.3, outer_cone_rad: 0.5 },
            Vec3::new(1.0, 4.0, -1.0),
            Vec3::new(-0.2, -1.0, 0.1).normalize(),
        )
    };
    lights.push(spot);
    let mut scene = floor_scene(12.0, Vec3::new(0.0, 7.0, 6.0), lights);
    for (i, p) in [(-1.5, -1.0), (1.0, 1.5), (2.0, -2.0), (-2.5, 1.5)].into_iter().enumerate() {
        add_box(&mut scene, Vec3::new(p.0, 0.5, p.1), Vec3::new(0.8, 1.0, 0.6), i as f32 * 0.4, CastShadows::On);
    }
    scene
}

#[test]
fn the_three_culling_modes_give_the_same_image() {
    let mut r = renderer();
    let lamp = asset_scenes().into_iter().find(|p| p.ends_with("LightsPunctualLamp.gltf")).expect("the lamp scene");
    let scenes = [("boxes", boxes_scene()), ("LightsPunctualLamp", load_gltf(&lamp).expect("lamp"))];
    for (name, scene) in scenes {
        let none = render_hdr(&mut r, &scene, &forward(LightCulling::None));
        let lit = none.hdr.iter().filter(|p| p[0].max(p[1]).max(p[2]) > 1e-3).count();
        assert!(lit * 10 > none.hdr.len(), "{name}: only {lit} pixels lit");
        for culling in [LightCulling::Clustered, LightCulling::PerObject] {
            let culled = render_hdr(&mut r, &scene, &forward(culling));
            assert_eq!(culled.plan.culling, culling);
            assert_eq!(culled.local_lights_shaded(), none.local_lights_shaded());
            // Only the order of the sums differs; half floats hold the results.
            let worst = worst_relative_difference(&none, &culled, 1e-3);
            println!("{name} {culling:?}: worst relative difference {worst:e}");
            assert!(worst < 2e-3, "{name}: {culling:?} differs from no culling by {worst}");
        }
    }
}

/// Forty shadowed spots on a ring, all aimed at the middle of a floor with a box: the
/// clusters there list more shadowed lights than the shader marks at once (32), so its
/// second chunk of shadowed entries is shaded too.
fn ring_of_shadowed_spots() -> Scene {
    let lights = (0..40)
        .map(|i| {
            let angle = i as f32 / 40.0 * std::f32::consts::TAU;
            let position = Vec3::new(3.0 * angle.cos(), 3.0, 3.0 * angle.sin());
            chiaro_scene::Light {
                name: format!("spot {i}"),
                node: 20 + i,
                intensity: 2.0,
                range: Some(8.0),
                ..chiaro_scene::Light::new(
                    LightKind::Spot { inner_cone_rad: 0.4, outer_cone_rad: 0.6 },
                    position,
                    (Vec3::ZERO - position).normalize(),
                )
            }
        })
        .collect();
    let mut scene = floor_scene(8.0, Vec3::new(0.0, 6.0, 4.0), lights);
    add_box(&mut scene, Vec3::new(0.0, 0.4, 0.0), Vec3::new(0.6, 0.8, 0.6), 0.3, CastShadows::On);
    scene
}

#[test]
fn more_than_32_shadowed_lights_in_a_cluster_shade_as_without_culling() {
    let mut r = renderer();
    let scene = ring_of_shadowed_spots();
    let none = render_hdr(&mut r, &scene, &forward(LightCulling::None));
    let clustered = render_hdr(&mut r, &scene, &forward(LightCulling::Clustered));
    let lists = &clustered.plan.culled.lists;
    let most = (0..lists.len()).map(|k| lists.shadowed(k)).max().unwrap_or(0);
    assert!(most > 32, "a cluster lists {most} shadowed lights: the test needs more than 32");
    assert_eq!(clustered.local_lights_shaded(), 40);
    let worst = worst_relative_difference(&none, &clustered, 1e-3);
    assert!(worst < 2e-3, "clustered differs from no culling by {worst}");
}

/// A floor with boxes under `count` small coloured point lights, none casting shadows,
/// spread over the floor, and two shadowed spots.
/// `count` point lights over a floor with boxes (and two shadowed spots); `scale` sizes the
/// point lights' ranges and heights.
fn many_lights_scene(count: usize, scale: f32) -> Scene {
    let mut lights = Vec::new();
    for k in 0..2 {
        lights.push(chiaro_scene::Light {
            name: format!("spot {k}"),
            node: 11 + k,
            intensity: 40.0,
            range: Some(10.0),
            ..chiaro_scene::Light::new(
                LightKind::Spot { inner_cone_rad: 0.4, outer_cone_rad: 0.6 },
                Vec3::new(k as f32 * 4.0 - 2.0, 5.0, 0.0),
                Vec3::new(0.1, -1.0, 0.0).normalize(),
            )
        });
    }
    // A low-discrepancy spread (golden-ratio steps across, even steps down), so every
    // run places them alike.
    let phi = 0.618_034f32;
    for i in 0..count {
        let u = (i as f32 * phi).fract();
        let v = (i as f32 + 0.5) / count as f32;
        let position = Vec3::new(u * 18.0 - 9.0, (0.2 + (i % 7) as f32 * 0.2) * scale, v * 18.0 - 9.0);
        let mut l = point_light(position, 2.0 + (i % 5) as f32, Some((1.5 + (i % 4) as f32 * 0.5) * scale));
        if i % 9 == 4 {
            // Unshadowed spots among the points, tilted and of several cones: read from
            // the texel table, their kind follows from their cone.
            let down = Vec3::new((i % 5) as f32 * 0.2 - 0.4, -1.0, (i % 3) as f32 * 0.2 - 0.2).normalize();
            let outer = 0.5 + (i % 4) as f32 * 0.15;
            let kind = LightKind::Spot { inner_cone_rad: outer * 0.6, outer_cone_rad: outer };
            let spot = chiaro_scene::Light::new(kind, position + Vec3::Y * scale, down);
            l = chiaro_scene::Light { intensity: l.intensity * 4.0, range: l.range, ..spot };
        }
        l.color = Vec3::new(0.3 + 0.7 * u, 0.3 + 0.7 * v, 1.0 - 0.6 * u);
        l.shadow.mode = ShadowMode::None;
        lights.push(l);
    }
    // An unshadowed spot and point with cookies: from the table, their cookie records are
    // read, and the spot's kind picks the 2D cookie.
    let cone = LightKind::Spot { inner_cone_rad: 0.4, outer_cone_rad: 0.7 };
    let cookie_spot = chiaro_scene::Light::new(cone, Vec3::new(2.0, 3.0, 1.0), Vec3::new(0.2, -1.0, 0.1).normalize());
    let cookie_point = point_light(Vec3::new(-3.0, 1.5, -2.0), 10.0, Some(4.0));
    for (image, light) in [cookie_spot, cookie_point].into_iter().enumerate() {
        let cookie = Some(Cookie { image, size_m: Vec2::ONE });
        let shadow = chiaro_scene::LightShadow { mode: ShadowMode::None, ..light.shadow };
        lights.push(chiaro_scene::Light { intensity: 30.0, range: Some(6.0), cookie, shadow, ..light });
    }
    let mut scene = floor_scene(20.0, Vec3::new(0.0, 14.0, 6.0), lights);
    // A spot cookie (stripes) and a point cookie (six faces of a gradient).
    scene.images.push(rgb_image(8, 8, |x, y| [((x % 4) * 60 + 40) as u8, ((y % 2) * 150 + 80) as u8, 200]));
    scene.images.push(rgb_image(48, 8, |x, y| [(x * 5) as u8, (y * 30 + 20) as u8, 120]));
    for (i, p) in [(-4.0, -3.0), (3.0, 3.5), (5.0, -4.0), (-5.0, 4.0), (0.0, 0.0)].into_iter().enumerate() {
        add_box(&mut scene, Vec3::new(p.0, 0.75, p.1), Vec3::new(1.2, 1.5, 0.9), i as f32 * 0.5, CastShadows::On);
    }
    scene
}

#[test]
fn a_thousand_clustered_lights_add_up_to_fifty_at_a_time_without_culling() {
    let scene = many_lights_scene(1000, 1.0);
    let (all, lit) = clustered_equals_the_sum_of_groups(&scene);
    assert!(all.local_lights_shaded() > 990, "{} lights shaded", all.local_lights_shaded());
    assert!(lit > all.hdr.len(), "most pixels are lit ({lit} channels)");
}

#[test]
fn lights_small_for_their_depth_add_up_too() {
    // Ranges of 15 to 30 cm seen from 15 m, in slices metres deep.
    let scene = many_lights_scene(600, 0.1);
    let (all, lit) = clustered_equals_the_sum_of_groups(&scene);
    assert!(all.local_lights_shaded() > 590, "{} lights shaded", all.local_lights_shaded());
    assert!(lit > all.hdr.len() / 8, "the small lights light the floor ({lit} channels)");
}

/// Renders `scene` under clustered culling and checks it against the sum of renders of
/// its lights fifty at a time without culling; returns the clustered frame and how many
/// channels are lit.
fn clustered_equals_the_sum_of_groups(scene: &Scene) -> (FrameOutput, usize) {
    let mut r = renderer();
    let mut settings = forward(LightCulling::Clustered);
    settings.render.msaa = 1;
    let all = render_hdr(&mut r, scene, &settings);
    // Every light in view is shaded.
    assert_eq!(all.local_lights_dropped(), 0);
    assert!(all.plan.lights_in_table(), "hundreds of lights are read from their texel table");
    // The sum of renders of groups of 50 lights, with no culling; the two shadowed spots
    // share the first group, so their shadow tiles are laid out as in the full frame.
    let mut sum = vec![[0.0f32; 3]; all.hdr.len()];
    let mut group_settings = forward(LightCulling::None);
    group_settings.render.msaa = 1;
    for group in scene.lights.chunks(50) {
        let mut part = scene.clone();
        part.lights = group.to_vec();
        let frame = render_hdr(&mut r, &part, &group_settings);
        assert_eq!(frame.local_lights_dropped(), 0);
        for (s, p) in sum.iter_mut().zip(&frame.hdr) {
            for c in 0..3 {
                s[c] += p[c];
            }
        }
    }
    let mut worst = 0.0f32;
    let mut lit = 0;
    for (p, s) in all.hdr.iter().zip(&sum) {
        for c in 0..3 {
            let scale = p[c].max(s[c]);
            if scale > 1e-3 {
                lit += 1;
                worst = worst.max((p[c] - s[c]).abs() / scale);
            }
        }
    }
    println!("{} lights: {lit} lit channels, worst relative difference {worst:e}", scene.lights.len());
    // Each group's half floats round by 2^-11 of its part; their sum stays within 0.3%.
    assert!(worst < 3e-3, "clustered render differs from the sum of groups by {worst}");
    (all, lit)
}

#[test]
fn per_object_lists_keep_each_objects_most_important_lights() {
    // Twelve lights around one box, all in range: its list holds the eight brightest.
    let lights: Vec<_> = (0..12)
        .map(|i| {
            let angle = i as f32 * std::f32::consts::TAU / 12.0;
            let mut l = point_light(Vec3::new(angle.cos() * 2.0, 1.0, angle.sin() * 2.0), 1.0 + i as f32, Some(6.0));
            l.shadow.mode = ShadowMode::None;
            l
        })
        .collect();
    let mut scene = floor_scene(4.0, Vec3::new(0.0, 6.0, 4.0), lights);
    add_box(&mut scene, Vec3::new(0.0, 0.5, 0.0), Vec3::ONE, 0.0, CastShadows::On);
    let view = View::from_camera(&scene, 0, 64, 64);
    let plan = FramePlan::new(
        &scene,
        &scene_draws(&scene, &GeometryLayout::of(&scene)),
        &view,
        &forward(LightCulling::PerObject),
        &ShadowAtlasTiles::default(),
        Default::default(),
    );
    let lists = &plan.culled.lists;
    assert_eq!(lists.len(), 2, "one list per object: the floor and the box");
    for k in 0..2 {
        let list = lists.list(k);
        assert_eq!(list.len(), 8, "object {k} keeps eight of twelve lights");
        // Every index names one of the frame's point lights.
        let mut scene_ids: Vec<u32> = list.iter().map(|&i| plan.lights[i as usize].id.0).collect();
        scene_ids.sort();
        assert_eq!(scene_ids, (4..12).collect::<Vec<u32>>(), "object {k}: the eight brightest");
    }
}
