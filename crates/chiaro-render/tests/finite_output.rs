//! No valid scene gives a non-finite value: cameras at, inside and just outside each light
//! type (a flashlight at the eye, a bulb a centimetre away), lights touching a surface,
//! grazing views, on every path (forward with and without MSAA, deferred with FXAA and
//! with the 8-bit light buffer), with hard, soft and contact-hardening shadows, cookies,
//! the environment, and every AOV. Where the view and light directions coincide, rounding
//! takes their cosines past 1, and a power or square root of what follows was NaN.

mod common;

use chiaro_render::{FrameOptions, FrameOutput, Renderer, View};
use chiaro_scene::settings::{DeferredAntialiasing, EnvironmentSource, LightBuffer};
use chiaro_scene::{
    CastShadows, ColorSpace, Cookie, Image, Light, LightKind, Material, RenderPath, Scene, Settings, ShadowMode,
};
use chiaro_testkit::{add_box, floor_scene, look_from};
use common::renderer;
use glam::{Vec3, Vec4};

const WIDTH: u32 = 40;
const HEIGHT: u32 = 30;

/// The eye, looking at the middle of the floor from the side.
const TARGET: Vec3 = Vec3::new(0.0, 0.0, 0.0);

/// A light of `kind` at `position`, shining at the floor's middle, bright enough that a
/// centimetre away it passes what a half float holds.
fn light(kind: LightKind, position: Vec3, shadows: ShadowMode, cookie: bool) -> Light {
    let direction = (TARGET - position).try_normalize().unwrap_or(Vec3::NEG_Y);
    let mut light = Light::new(kind, position, direction);
    light.name = format!("{} light", kind.name());
    light.node = 20;
    light.intensity = if kind == LightKind::Directional { 5.0 } else { 200.0 };
    light.range = (kind != LightKind::Directional).then_some(6.0);
    light.shadow.mode = shadows;
    light.cookie = cookie.then_some(Cookie { image: 0, size_m: glam::Vec2::splat(1.5) });
    light
}

fn spot() -> LightKind {
    LightKind::Spot { inner_cone_rad: 0.3, outer_cone_rad: 0.6 }
}

/// A floor with a shiny box and a mirror-smooth metal box, `light` in it, seen from `eye`.
fn scene(light: Light, eye: Vec3) -> Scene {
    let mut scene = floor_scene(8.0, eye, vec![light]);
    add_box(&mut scene, Vec3::new(-1.0, 0.5, 0.5), Vec3::new(1.0, 1.0, 1.0), 0.4, CastShadows::On);
    add_box(&mut scene, Vec3::new(1.2, 0.4, -0.6), Vec3::new(0.8, 0.8, 0.8), -0.2, CastShadows::On);
    scene.materials.truncate(1);
    scene.materials[0].roughness = 0.5;
    scene.materials.push(Material {
        name: "mirror".into(),
        base_color: Vec4::new(0.9, 0.9, 0.9, 1.0),
        metallic: 1.0,
        roughness: 0.0,
        ..Material::default()
    });
    for mesh in &mut scene.meshes[1..] {
        for primitive in &mut mesh.primitives {
            primitive.material = Some(1);
        }
    }
    // Six 2 x 2 faces side by side, so that it serves a point light's cube too.
    let rgba8 = (0..12 * 2).flat_map(|t: u32| [(t * 37 % 256) as u8, (t * 91 % 256) as u8, (t * 13 % 256) as u8, 255]);
    scene.images.push(Image {
        name: "cookie".into(),
        width: 12,
        height: 2,
        rgba8: rgba8.collect(),
        file_mips: Vec::new(),
        basis_source: None,
        color_space: ColorSpace::Linear,
    });
    if eye.distance(TARGET) > 1e-3 {
        look_from(&mut scene, eye, TARGET);
    }
    scene
}

/// Where the camera stands for a light at `at`: exactly there, a centimetre and a
/// millimetre beside it, half a metre off (inside its range), just outside its range.
fn eyes(at: Vec3) -> Vec<Vec3> {
    let side = Vec3::new(0.6, 0.3, 0.74).normalize();
    vec![at, at + 0.01 * side, at + 0.001 * side, at + 0.5 * side, at + 6.01 * side]
}

/// The render variants: path, MSAA, light buffer, FXAA.
fn variants() -> Vec<(&'static str, Settings)> {
    let base = {
        let mut s = Settings::default();
        s.render.width = WIDTH;
        s.render.height = HEIGHT;
        s
    };
    let with = |f: &dyn Fn(&mut Settings)| {
        let mut s = base.clone();
        f(&mut s);
        s
    };
    vec![
        ("forward, 1 sample", with(&|s| s.render.msaa = 1)),
        ("forward, 4x MSAA", with(&|s| s.render.msaa = 4)),
        (
            "deferred, FXAA",
            with(&|s| {
                s.render.path = RenderPath::Deferred;
                s.render.msaa = 4;
                s.render.deferred_antialiasing = DeferredAntialiasing::Fxaa;
            }),
        ),
        (
            "deferred, 8-bit light buffer",
            with(&|s| {
                s.render.path = RenderPath::Deferred;
                s.render.light_buffer = LightBuffer::LdrExp2;
            }),
        ),
    ]
}

/// The first non-finite value in the frame's outputs, described.
fn first_non_finite(frame: &FrameOutput) -> Option<String> {
    if let Some(i) = frame.hdr.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        return Some(format!("HDR pixel {i} is {:?}", frame.hdr[i]));
    }
    let aovs = frame.aovs.as_ref().expect("AOVs");
    // The sky's AOVs are NaN and infinite by definition; every covered pixel's are finite.
    let covered: Vec<usize> = (0..aovs.depth.len()).filter(|&i| aovs.depth[i].is_finite()).collect();
    if covered.is_empty() {
        return Some("no pixel shows a surface".into());
    }
    for &i in &covered {
        let values = [aovs.position_ws[i], aovs.normal_ws[i]];
        if values.iter().flatten().any(|c| !c.is_finite()) {
            return Some(format!("AOV pixel {i}: position {:?}, normal {:?}", values[0], values[1]));
        }
        if let Some(e) = aovs.baked_irradiance.get(i).filter(|e| e.iter().any(|c| !c.is_finite())) {
            return Some(format!("baked irradiance at pixel {i} is {e:?}"));
        }
        for (light, layer) in frame.shadow_aovs.iter().enumerate() {
            if !layer[i].is_finite() {
                return Some(format!("shadow AOV of light {light} at pixel {i} is {}", layer[i]));
            }
        }
    }
    None
}

fn render(renderer: &mut Renderer, scene: &Scene, settings: &Settings) -> FrameOutput {
    let view = View::from_camera(scene, 0, WIDTH, HEIGHT);
    let prepared = renderer.prepare(scene).expect("prepare");
    let options = FrameOptions { readback: true, aovs: true, shadow_aovs: true, ids: true, ..Default::default() };
    renderer.render(scene, &prepared, &view, settings, options).expect("render")
}

#[test]
fn no_output_holds_a_non_finite_value_with_the_camera_at_in_or_beside_a_light() {
    let mut renderer = renderer();
    let mut failures = Vec::new();
    let mut frames = 0;
    let point_at = Vec3::new(0.3, 1.2, 2.0);
    let lights: Vec<(LightKind, Vec3)> = vec![
        (LightKind::Point, point_at),
        (spot(), point_at),
        // A spot and a point touching the floor, and one a millimetre above it.
        (spot(), Vec3::new(0.2, 0.0, 0.1)),
        (LightKind::Point, Vec3::new(-0.3, 0.001, 0.2)),
        (LightKind::Directional, Vec3::new(0.0, 3.0, 3.0)),
    ];
    for (k, &(kind, at)) in lights.iter().enumerate() {
        for (e, eye) in eyes(at).into_iter().enumerate() {
            // Each placement takes every variant once, with shadows and cookies varied
            // between placements so that every mode meets every path.
            let shadows = [ShadowMode::Hard, ShadowMode::Soft, ShadowMode::Pcss][(k + e) % 3];
            let cookie = (k + e) % 2 == 0;
            let scene = scene(light(kind, at, shadows, cookie), eye);
            for (name, mut settings) in variants() {
                if (k + e) % 2 == 1 {
                    settings.environment.source = EnvironmentSource::Neutral;
                }
                let frame = render(&mut renderer, &scene, &settings);
                frames += 1;
                if let Some(problem) = first_non_finite(&frame) {
                    failures.push(format!(
                        "{} at {at}, eye {eye} ({shadows:?} shadows, cookie {cookie}, environment {}), {name}: {problem}",
                        kind.name(),
                        settings.environment.source.name()
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{} of {frames} frames:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn grazing_views_and_lights_stay_finite() {
    let mut renderer = renderer();
    let mut failures = Vec::new();
    // The eye a millimetre above the floor, looking along it; lights along the floor too.
    let eye = Vec3::new(0.0, 0.001, 3.9);
    let lights = [
        light(LightKind::Directional, Vec3::new(0.0, 0.002, 5.0), ShadowMode::Pcss, true),
        light(spot(), Vec3::new(0.0, 0.002, 3.95), ShadowMode::Soft, false),
        light(LightKind::Point, Vec3::new(0.5, 0.0005, 3.0), ShadowMode::Pcss, true),
    ];
    for light in lights {
        let kind = light.kind.name();
        let mut scene = scene(light, eye);
        look_from(&mut scene, eye, Vec3::new(0.0, 0.001, -4.0));
        for (name, mut settings) in variants() {
            settings.environment.source = EnvironmentSource::Sky;
            let frame = render(&mut renderer, &scene, &settings);
            if let Some(problem) = first_non_finite(&frame) {
                failures.push(format!("{kind}, {name}: {problem}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
