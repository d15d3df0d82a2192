//! Coloured shadows of surfaces that let light through (KHR_materials_transmission and
//! diffuse transmission) against the ray-traced reference on the software device: a red
//! glass pane above a floor tints its shadow for a sun, a spot and a point light, on both
//! paths; the shadow's visibility (the mean of its channels) agrees with the traced one,
//! and each channel of the floor's light under the pane is the pane's transmittance of
//! the light beside it. An opaque pane of the same colour still casts a black shadow; a
//! closed glass box tints once when single-sided (its back faces cast nothing, as the
//! camera sees it), even when it casts two-sided, and twice when double-sided; a
//! single-sided pane tints towards its front only (mirrored too); tints are drawn again
//! on frames that keep their depth tiles; a box standing on the glass is not tinted.

mod common;

use chiaro_compare::assert_agrees_with_reference;
use chiaro_render::{FrameOptions, ShadowStatus, View};
use chiaro_scene::{CastShadows, Light, LightKind, Material, RenderPath, Scene, Settings, shapes};
use common::*;
use glam::{Mat4, Vec3, Vec4};

/// The pane's colour: one crossing lets through 0.96 (Fresnel at ior 1.5) of it.
const RED_GLASS: Vec3 = Vec3::new(0.9, 0.35, 0.1);

/// Light reaching the floor under a 2 m pane at 1 m, as seen from below its edge
/// (the camera under the pane's height sees the floor, not the pane).
fn pane_scene(light: Light, transmission: f32) -> Scene {
    let mut scene = floor_scene(12.0, Vec3::ZERO, vec![light]);
    look_from(&mut scene, Vec3::new(0.0, 0.6, 3.0), Vec3::new(0.0, 0.0, -0.3));
    let mut material =
        Material { name: "red glass".into(), base_color: RED_GLASS.extend(1.0), metallic: 0.0, ..Material::default() };
    material.double_sided = true;
    material.layers.transmission = transmission;
    let at = Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0));
    add_mesh(&mut scene, "pane", shapes::plane(2.0, 1), material, at, CastShadows::TwoSided);
    scene
}

fn lights() -> Vec<(&'static str, Light)> {
    let sun = Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(0.05, -1.0, 0.02)) };
    let kind = LightKind::Spot { inner_cone_rad: 0.7, outer_cone_rad: 0.9 };
    let spot = Light { intensity: 40.0, range: Some(20.0), ..Light::new(kind, Vec3::new(0.0, 4.0, 0.0), Vec3::NEG_Y) };
    let point = point_light(Vec3::new(0.0, 4.0, 0.0), 40.0, Some(20.0));
    vec![("sun", sun), ("spot", spot), ("point", point)]
}

fn settings(path: RenderPath) -> Settings {
    let mut s = unlit_settings();
    s.render.path = path;
    s
}

/// Floor pixels whose light crosses the pane, well inside its shadow: for the sun the
/// shadow is the pane's footprint (moved 0.05 m); from 4 m up, a 2 m pane at 1 m throws
/// a 2.67 m one.
fn under_pane(name: &str, p: Vec3) -> bool {
    let half = if name == "sun" { 0.8 } else { 1.15 };
    p.y.abs() < 1e-3 && p.x.abs() < half && p.z.abs() < half
}

/// Floor pixels beside the shadow, lit directly, at the same distance from a local light.
fn beside_pane(name: &str, p: Vec3) -> bool {
    let reach = if name == "sun" { 1.2..2.5 } else { 1.6..2.5 };
    p.y.abs() < 1e-3 && p.x.abs() < 0.8 && reach.contains(&p.z.abs())
}

#[test]
fn a_glass_pane_tints_its_shadow_as_the_reference_traces_it() {
    let through = RED_GLASS * 0.96;
    let mean_through = (through.x + through.y + through.z) / 3.0;
    for (name, light) in lights() {
        let scene = pane_scene(light, 1.0);
        for path in [RenderPath::Forward, RenderPath::Deferred] {
            let label = format!("{name}, {path:?}");
            let result = compare(&scene, &settings(path), 192);
            assert_eq!(result.status[0], ShadowStatus::Mapped, "{label}");
            let behind: Vec<f32> = (0..result.rendered[0].len())
                .filter(|&i| result.reference.position[i].is_some_and(|p| under_pane(name, p)))
                .map(|i| result.rendered[0][i])
                .collect();
            assert!(behind.len() > 500, "{label}: {} floor pixels under the pane", behind.len());
            let mean = behind.iter().sum::<f32>() / behind.len() as f32;
            println!(
                "{label}: shadow term under the pane {mean:.4} (expected {mean_through:.4}) over {} pixels",
                behind.len()
            );
            assert!((mean - mean_through).abs() < 0.02, "{label}: shadow term {mean}, expected {mean_through}");
            let c = &result.reports[0].comparison;
            assert!(c.compared > 4000, "{label}: only {} compared", c.compared);
            assert_agrees_with_reference(&label, c);
        }
    }
}

/// The rendered radiance of the floor under the pane over that beside it, per channel
/// (means over the pixels of each), from a frame of `scene`.
fn floor_ratio(name: &str, scene: &Scene, path: RenderPath) -> Vec3 {
    floor_ratio_after(name, scene, path, 1)
}

/// `floor_ratio` of the last of `frames` frames of one renderer (later frames keep the
/// first one's depth tiles in the shadow cache).
fn floor_ratio_after(name: &str, scene: &Scene, path: RenderPath, frames: u32) -> Vec3 {
    let mut renderer = renderer();
    let prepared = renderer.prepare(scene).unwrap();
    let view = View::from_camera(scene, 0, 192, 192);
    let options = FrameOptions { aovs: true, readback: true, ..Default::default() };
    let mut frame = renderer.render(scene, &prepared, &view, &settings(path), options).unwrap();
    for _ in 1..frames {
        frame = renderer.render(scene, &prepared, &view, &settings(path), options).unwrap();
        assert_eq!(frame.shadow_tiles, 0, "{name}: a still frame draws no depth tile");
    }
    let aovs = frame.aovs.as_ref().unwrap();
    let mean = |keep: &dyn Fn(Vec3) -> bool| {
        let (sum, n) = (0..frame.hdr.len())
            .filter(|&i| aovs.position_ws[i][0].is_finite() && keep(Vec3::from(aovs.position_ws[i])))
            .map(|i| {
                let h = frame.hdr[i];
                // Irradiance falls off with distance and angle from a local light: divide
                // it out so that pixels under and beside the pane compare.
                Vec3::new(h[0], h[1], h[2]) / lambert_irradiance(scene, Vec3::from(aovs.position_ws[i]))
            })
            .fold((Vec3::ZERO, 0), |(s, n), v| (s + v, n + 1));
        assert!(n > 200, "{name}: {n} pixels");
        sum / n as f32
    };
    mean(&|p| under_pane(name, p)) / mean(&|p| beside_pane(name, p))
}

/// Relative irradiance on the floor at `p` from the scene's one light (no shadow, no
/// cone), to compare pixels at different places: cos / d^2 for a local light, 1 for a sun.
fn lambert_irradiance(scene: &Scene, p: Vec3) -> f32 {
    let light = &scene.lights[0];
    if light.kind == LightKind::Directional {
        return 1.0;
    }
    let to_light = light.position() - p;
    to_light.normalize().y / to_light.length_squared()
}

#[test]
fn the_floor_under_a_glass_pane_takes_its_colour() {
    let through = RED_GLASS * 0.96;
    for (name, light) in lights() {
        let glass = pane_scene(light.clone(), 1.0);
        for path in [RenderPath::Forward, RenderPath::Deferred] {
            let ratio = floor_ratio(name, &glass, path);
            println!("{name}, {path:?}: floor under / beside the pane {ratio:.4} (expected {through:.4})");
            assert!((ratio - through).abs().max_element() < 0.03, "{name}, {path:?}: {ratio}, expected {through}");
        }
        // The same pane, opaque: an ordinary black shadow.
        let opaque = pane_scene(light, 0.0);
        let ratio = floor_ratio(name, &opaque, RenderPath::Forward);
        assert!(ratio.max_element() < 0.02, "{name}: an opaque pane lets {ratio} through");
    }
}

#[test]
fn diffuse_transmission_tints_the_shadow_in_its_own_colour() {
    let sun = Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::NEG_Y) };
    let mut leaf = pane_scene(sun, 0.0);
    let layers = &mut leaf.materials[1].layers;
    layers.diffuse_transmission = 0.5;
    layers.diffuse_transmission_color = Vec3::new(0.3, 1.0, 0.2);
    leaf.materials[1].base_color = Vec4::new(0.2, 0.6, 0.1, 1.0);
    let expected = Vec3::new(0.3, 1.0, 0.2) * 0.5 * 0.96;
    let ratio = floor_ratio("sun", &leaf, RenderPath::Forward);
    println!("leaf: floor under / beside {ratio:.4} (expected {expected:.4})");
    assert!((ratio - expected).abs().max_element() < 0.03, "{ratio}, expected {expected}");
}

#[test]
fn a_single_sided_glass_box_tints_once_a_double_sided_one_twice() {
    let through = RED_GLASS * 0.96;
    // Casting two-sided (glTF's default) does not make a single-sided material tint twice.
    for (double_sided, cast, crossings) in
        [(false, CastShadows::On, 1), (false, CastShadows::TwoSided, 1), (true, CastShadows::On, 2)]
    {
        let sun = Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::NEG_Y) };
        let mut scene = floor_scene(12.0, Vec3::ZERO, vec![sun]);
        look_from(&mut scene, Vec3::new(0.0, 0.5, 3.0), Vec3::new(0.0, 0.0, -0.3));
        let mut material = Material {
            name: "red glass".into(),
            base_color: RED_GLASS.extend(1.0),
            metallic: 0.0,
            double_sided,
            ..Material::default()
        };
        material.layers.transmission = 1.0;
        let at = Mat4::from_translation(Vec3::new(0.0, 1.5, 0.0));
        add_mesh(&mut scene, "glass box", shapes::cuboid(Vec3::splat(1.6)), material, at, cast);
        let label = format!("double-sided {double_sided}, casting {cast:?}");
        let result = compare(&scene, &settings(RenderPath::Forward), 192);
        let under: Vec<f32> = (0..result.rendered[0].len())
            .filter(|&i| {
                result.reference.position[i].is_some_and(|p| p.y.abs() < 1e-3 && p.x.abs() < 0.65 && p.z.abs() < 0.65)
            })
            .map(|i| result.rendered[0][i])
            .collect();
        assert!(under.len() > 300, "{label}: {} pixels under the box", under.len());
        let mean = under.iter().sum::<f32>() / under.len() as f32;
        let tint = through.powf(crossings as f32);
        let expected = (tint.x + tint.y + tint.z) / 3.0;
        println!("{label}: shadow term under the box {mean:.4} (expected {expected:.4}) over {} pixels", under.len());
        assert!((mean - expected).abs() < 0.02, "{label}: {mean}, expected {expected}");
        assert_agrees_with_reference(&label, &result.reports[0].comparison);
    }
}

#[test]
fn tints_are_drawn_again_on_frames_that_keep_their_depth_tiles() {
    let through = RED_GLASS * 0.96;
    let sun = Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(0.05, -1.0, 0.02)) };
    let ratio = floor_ratio_after("sun", &pane_scene(sun, 1.0), RenderPath::Forward, 3);
    assert!((ratio - through).abs().max_element() < 0.03, "third frame: {ratio}, expected {through}");
}

#[test]
fn a_single_sided_pane_tints_only_towards_its_front() {
    let through = RED_GLASS * 0.96;
    let mean_through = (through.x + through.y + through.z) / 3.0;
    // Facing up (the light meets its front), mirrored (its winding turned, its front
    // still up), and upside down (the light meets its back: no shadow at all).
    let cases = [
        ("up", Mat4::IDENTITY, mean_through),
        ("mirrored", Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)), mean_through),
        ("upside down", Mat4::from_rotation_x(std::f32::consts::PI), 1.0),
    ];
    for (label, turn, expected) in cases {
        let sun = Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::NEG_Y) };
        let mut scene = pane_scene(sun, 1.0);
        scene.materials[1].double_sided = false;
        let pane = scene.instances.len() - 1;
        scene.instances[pane].world_from_local *= turn;
        let result = compare(&scene, &settings(RenderPath::Forward), 192);
        let under: Vec<f32> = (0..result.rendered[0].len())
            .filter(|&i| result.reference.position[i].is_some_and(|p| under_pane("sun", p)))
            .map(|i| result.rendered[0][i])
            .collect();
        let mean = under.iter().sum::<f32>() / under.len() as f32;
        println!("{label}: shadow term under the pane {mean:.4} (expected {expected:.4})");
        assert!((mean - expected).abs() < 0.02, "{label}: {mean}, expected {expected}");
        assert_agrees_with_reference(label, &result.reports[0].comparison);
    }
}

#[test]
fn what_lies_between_the_light_and_the_glass_is_not_tinted() {
    // A white box standing on the pane, seen from above: its top is lit by the whole
    // sun, like the floor beside the pane, in every channel.
    let sun = Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(0.05, -1.0, 0.02)) };
    let mut scene = pane_scene(sun, 1.0);
    add_box(&mut scene, Vec3::new(0.2, 1.15, 0.1), Vec3::new(0.5, 0.3, 0.5), 0.0, CastShadows::On);
    look_from(&mut scene, Vec3::new(0.0, 6.0, 2.5), Vec3::new(0.0, 0.5, 0.0));
    let mut renderer = renderer();
    let prepared = renderer.prepare(&scene).unwrap();
    let view = View::from_camera(&scene, 0, 192, 192);
    let options = FrameOptions { aovs: true, readback: true, ..Default::default() };
    let frame = renderer.render(&scene, &prepared, &view, &settings(RenderPath::Forward), options).unwrap();
    let aovs = frame.aovs.as_ref().unwrap();
    let mean = |keep: &dyn Fn(Vec3) -> bool| {
        let (sum, n) = (0..frame.hdr.len())
            .filter(|&i| aovs.position_ws[i][0].is_finite() && keep(Vec3::from(aovs.position_ws[i])))
            .map(|i| Vec3::new(frame.hdr[i][0], frame.hdr[i][1], frame.hdr[i][2]))
            .fold((Vec3::ZERO, 0), |(s, n), v| (s + v, n + 1));
        assert!(n > 50, "{n} pixels");
        sum / n as f32
    };
    let top = mean(&|p| (p.y - 1.3).abs() < 1e-3 && (p.x - 0.2).abs() < 0.2 && (p.z - 0.1).abs() < 0.2);
    let floor = mean(&|p| p.y.abs() < 1e-3 && p.x.abs() < 1.0 && (1.3..2.5).contains(&p.z));
    let ratio = top / floor;
    println!("box top over the floor beside the pane: {ratio:.4}");
    assert!((ratio - Vec3::ONE).abs().max_element() < 0.03, "the box top is tinted: {ratio}");
}
