//! Bakes rendered: a baked light with no bounces renders like the same light in realtime,
//! and its baked shadows agree with the ray-traced reference; dynamic objects take their
//! light from the probes. On the software device, like every GPU test.

mod common;

use chiaro_compare::assert_agrees_with_reference;
use chiaro_math::light::{distance_attenuation, spot_angle_params, spot_attenuation};
use chiaro_render::{FrameOptions, FrameOutput, Renderer, View};
use chiaro_scene::{CastShadows, Light, LightKind, LightMode, RenderPath, Scene, Settings, ShadowMode};
use chiaro_testkit::{add_box, floor_scene, renderer};
use common::baked_scene;
use glam::Vec3;

fn render(renderer: &mut Renderer, scene: &Scene, settings: &Settings, size: u32) -> FrameOutput {
    let view = View::from_camera(scene, 0, size, size);
    let prepared = renderer.prepare(scene).expect("prepare");
    renderer
        .render(scene, &prepared, &view, settings, FrameOptions { aovs: true, readback: true, ..Default::default() })
        .expect("render")
}

fn settings(path: RenderPath) -> Settings {
    let mut s = Settings::default();
    s.render.ambient = [0.0; 3];
    s.render.path = path;
    s.bake.samples = Some(64);
    s.bake.bounces = 0;
    s.bake.texels_per_metre = 16.0;
    s.bake.probe_samples = Some(64);
    s
}

fn spot(mode: LightMode, shadows: ShadowMode) -> Light {
    let mut light = Light::new(
        LightKind::Spot { inner_cone_rad: 0.5, outer_cone_rad: 0.9 },
        Vec3::new(0.4, 2.5, -0.3),
        Vec3::new(-0.1, -1.0, 0.15),
    );
    light.intensity = 30.0;
    light.range = Some(9.0);
    light.mode = mode;
    light.shadow.mode = shadows;
    light
}

/// The realtime model's irradiance at a surface point: what the bake must reproduce.
fn model_irradiance(light: &Light, p: Vec3, n: Vec3) -> f32 {
    let to_light = light.position() - p;
    let l = to_light.normalize();
    let LightKind::Spot { inner_cone_rad, outer_cone_rad } = light.kind else { unreachable!() };
    let cone = spot_attenuation(light.direction().dot(-l), spot_angle_params(inner_cone_rad, outer_cone_rad));
    light.intensity * distance_attenuation(to_light.length_squared(), light.range.unwrap()) * cone * n.dot(l).max(0.0)
}

#[test]
fn a_baked_light_without_bounces_renders_like_the_realtime_light() {
    let mut gpu = renderer();
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let s = settings(path);
        let realtime = floor_scene(8.0, Vec3::new(0.0, 5.0, 4.0), vec![spot(LightMode::Realtime, ShadowMode::None)]);
        let mut to_bake = realtime.clone();
        to_bake.lights[0].mode = LightMode::Baked;
        let baked = baked_scene(&to_bake, &s);
        let (a, b) = (render(&mut gpu, &realtime, &s, 128), render(&mut gpu, &baked, &s, 128));
        assert_eq!(b.local_lights_shaded(), 0, "the baked light is not shaded in realtime");
        let aovs = b.aovs.as_ref().unwrap();
        let peak = a.hdr.iter().map(|p| p[0]).fold(0.0, f32::max);
        let (mut lit, mut close, mut irradiance_close, mut worst, mut worst_irradiance) = (0, 0, 0, 0.0f32, 0.0f32);
        for i in 0..a.hdr.len() {
            if !aovs.position_ws[i][0].is_finite() || a.hdr[i][0] < peak * 0.05 {
                continue;
            }
            lit += 1;
            let relative = (b.hdr[i][0] - a.hdr[i][0]).abs() / a.hdr[i][0];
            worst = worst.max(relative);
            close += (relative < 0.05) as usize;
            let expected = model_irradiance(&realtime.lights[0], Vec3::from(aovs.position_ws[i]), Vec3::Y);
            let irradiance_error = (aovs.baked_irradiance[i][0] - expected).abs() / expected;
            worst_irradiance = worst_irradiance.max(irradiance_error);
            irradiance_close += (irradiance_error < 0.02) as usize;
        }
        let (close, irradiance_close) = (close as f32 / lit as f32, irradiance_close as f32 / lit as f32);
        println!(
            "{path:?}: {lit} lit pixels; radiance within 5% of realtime: {:.2}% (worst {:.1}%); lightmap irradiance \
             within 2% of the model: {:.2}% (worst {:.1}%)",
            close * 100.0,
            worst * 100.0,
            irradiance_close * 100.0,
            worst_irradiance * 100.0
        );
        assert!(lit > 2000, "{lit}");
        // Realtime adds a rough specular lobe that baked light has not: a few %.
        assert!(close > 0.99, "{close}");
        assert!(irradiance_close > 0.99, "{irradiance_close}");
    }
}

/// The baked shadow of the one baked light, per pixel: baked irradiance over what the
/// model gives unshadowed there (NaN where the light gives almost nothing, not judged).
fn baked_shadow(frame: &FrameOutput, light: &Light) -> (Vec<f32>, Vec<Option<Vec3>>) {
    let aovs = frame.aovs.as_ref().unwrap();
    let mut shadow = Vec::new();
    let mut positions = Vec::new();
    for i in 0..aovs.position_ws.len() {
        let p = Vec3::from(aovs.position_ws[i]);
        if !p.is_finite() {
            shadow.push(f32::NAN);
            positions.push(None);
            continue;
        }
        let unshadowed = model_irradiance(light, p, Vec3::from(aovs.normal_ws[i]));
        shadow.push(if unshadowed > 0.05 { aovs.baked_irradiance[i][0] / unshadowed } else { f32::NAN });
        positions.push(Some(p));
    }
    (shadow, positions)
}

#[test]
fn baked_shadows_agree_with_the_traced_reference() {
    let mut gpu = renderer();
    let s = Settings {
        bake: chiaro_scene::settings::BakeSettings { texels_per_metre: 32.0, ..settings(RenderPath::Deferred).bake },
        ..settings(RenderPath::Deferred)
    };
    // Low and to the side, so the boxes cast long shadows.
    let mut light = spot(LightMode::Baked, ShadowMode::Hard);
    light.world_from_light = chiaro_math::rigid::looking_along(Vec3::new(2.0, 1.6, -0.3), Vec3::new(-2.3, -1.6, 0.4));
    let mut scene = floor_scene(8.0, Vec3::new(0.0, 5.0, 4.0), vec![light]);
    add_box(&mut scene, Vec3::new(0.3, 0.4, 0.2), Vec3::new(0.6, 0.8, 0.5), 0.4, CastShadows::On);
    add_box(&mut scene, Vec3::new(-0.6, 0.25, -0.5), Vec3::new(0.3, 0.5, 0.9), -0.3, CastShadows::On);
    let baked = baked_scene(&scene, &s);
    let size = 160;
    let frame = render(&mut gpu, &baked, &s, size);
    let light = &scene.lights[0];
    let (shadow, positions) = baked_shadow(&frame, light);
    let view = View::from_camera(&scene, 0, size, size);
    let camera = chiaro_trace::PixelCamera { clip_from_world: view.clip_from_world(), width: size, height: size };
    let range = light.range.unwrap();
    let reference = chiaro_trace::trace_shadow_reference(&scene, &camera, &[range]);
    let comparison = chiaro_compare::compare_light(&chiaro_compare::JudgedLight {
        rendered_shadow: &shadow,
        rendered_position: &positions,
        reference: &reference,
        light_index: 0,
        light,
        range,
        edge_band_px: chiaro_compare::EDGE_BAND_PX,
    });
    let shadowed = shadow.iter().filter(|&&v| v < 0.5).count();
    println!(
        "baked spot shadow: {} pixels compared, {} shadowed, disagreement {:.3}% (false {:.3}%, missed {:.3}%)",
        comparison.compared,
        shadowed,
        comparison.disagreement() * 100.0,
        comparison.false_share() * 100.0,
        comparison.missed_share() * 100.0
    );
    assert!(comparison.compared > 5000, "{comparison:?}");
    assert!(shadowed > 300, "the boxes shadow the floor: {shadowed} pixels");
    assert_agrees_with_reference("baked spot shadow", &comparison);
}

#[test]
fn dynamic_objects_take_baked_light_from_the_probes() {
    // A box lit by a baked spot: static, it reads its lightmap; dynamic, the probes. Both
    // must give its lit top about the light's irradiance there (the probes' L2 lobe and
    // trilinear blend cost some accuracy, so within 10%), and the floor stays lightmapped.
    let mut gpu = renderer();
    let mut s = settings(RenderPath::Deferred);
    s.bake.probe_spacing = 0.5;
    s.bake.probe_samples = Some(128);
    let mut scene = floor_scene(8.0, Vec3::new(0.0, 5.0, 4.0), vec![spot(LightMode::Baked, ShadowMode::None)]);
    add_box(&mut scene, Vec3::new(0.2, 0.5, -0.1), Vec3::splat(1.0), 0.0, CastShadows::Off);
    scene.instances[1].is_static = false;
    let baked = baked_scene(&scene, &s);
    assert!(baked.instances[0].lightmap.is_some() && baked.instances[1].lightmap.is_none());
    let frame = render(&mut gpu, &baked, &s, 128);
    let aovs = frame.aovs.as_ref().unwrap();
    let light = &scene.lights[0];
    let (mut top, mut close, mut error_sum) = (0, 0, 0.0);
    for i in 0..aovs.position_ws.len() {
        let p = Vec3::from(aovs.position_ws[i]);
        if !(p.is_finite() && (p.y - 1.0).abs() < 1e-3) {
            continue;
        }
        top += 1;
        let expected = model_irradiance(light, p, Vec3::Y);
        let error = (aovs.baked_irradiance[i][0] - expected).abs() / expected;
        error_sum += error;
        close += (error < 0.1) as usize;
    }
    println!(
        "probe-lit box top: {close} of {top} pixels within 10% of the light's irradiance, mean error {:.1}%",
        error_sum / top as f32 * 100.0
    );
    assert!(top > 150, "{top}");
    assert!(close as f32 > top as f32 * 0.95, "{close} of {top}");
}

#[test]
fn mixed_lights_stay_realtime_and_bake_only_their_bounces() {
    let mut gpu = renderer();
    let mut s = settings(RenderPath::Deferred);
    let mut scene = floor_scene(8.0, Vec3::new(0.0, 5.0, 4.0), vec![spot(LightMode::Mixed, ShadowMode::Soft)]);
    add_box(&mut scene, Vec3::new(0.3, 0.4, 0.2), Vec3::new(0.6, 0.8, 0.5), 0.4, CastShadows::On);
    let without = render(&mut gpu, &scene, &s, 96);
    // No bounces: the mixed light bakes nothing, and renders as before.
    let direct_only = baked_scene(&scene, &s);
    let frame = render(&mut gpu, &direct_only, &s, 96);
    assert_eq!(frame.local_lights_shaded(), 1, "the mixed light is shaded in realtime");
    let baked_max = frame.aovs.as_ref().unwrap().baked_irradiance.iter().map(|e| e[0]).fold(0.0, f32::max);
    assert_eq!(baked_max, 0.0, "no direct light of a mixed light in the lightmap");
    for (a, b) in without.hdr.iter().zip(&frame.hdr) {
        assert!((a[0] - b[0]).abs() <= a[0] * 1e-3 + 1e-6, "{a:?} vs {b:?}");
    }
    // Two bounces: light reflected by the floor and the box reaches the lightmaps.
    s.bake.bounces = 2;
    let bounced = baked_scene(&scene, &s);
    let frame = render(&mut gpu, &bounced, &s, 96);
    assert_eq!(frame.local_lights_shaded(), 1);
    let lit = frame.aovs.as_ref().unwrap().baked_irradiance.iter().filter(|e| e[0] > 0.0).count();
    let brighter = without.hdr.iter().zip(&frame.hdr).filter(|(a, b)| b[0] > a[0] * 1.001 + 1e-6).count();
    println!("mixed spot, two bounces: {lit} pixels read baked indirect light, {brighter} got brighter");
    assert!(lit > 1000 && brighter > 1000, "{lit} {brighter}");
}

/// Per pixel, the diffuse light realtime shading gives the floor: the frame with a white
/// floor less the frame with a black one (a dielectric's specular lobe does not depend on
/// its base colour, so only the diffuse term is left).
fn realtime_diffuse(gpu: &mut Renderer, scene: &Scene, s: &Settings, size: u32) -> Vec<f32> {
    let mut black = scene.clone();
    black.materials[0].base_color = glam::Vec4::new(0.0, 0.0, 0.0, 1.0);
    let (white, black) = (render(gpu, scene, s, size), render(gpu, &black, s, size));
    white.hdr.iter().zip(&black.hdr).map(|(w, b)| w[0] - b[0]).collect()
}

#[test]
fn baked_direct_light_equals_realtime_diffuse_light_per_light_type() {
    // A light switched from realtime to baked (no bounces) must not change the floor: the
    // same range window, cone and the same share of light given to the diffuse lobe.
    let mut gpu = renderer();
    let mut s = settings(RenderPath::Forward);
    s.bake.texels_per_metre = 32.0;
    s.bake.samples = Some(16);
    let mut point = chiaro_testkit::point_light(Vec3::new(0.3, 1.2, -0.2), 20.0, Some(3.5));
    point.shadow.mode = ShadowMode::None;
    let mut sun = Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(-0.3, -1.0, 0.2));
    sun.intensity = 3.0;
    sun.shadow.mode = ShadowMode::None;
    let size = 128;
    for (name, light) in [("spot", spot(LightMode::Realtime, ShadowMode::None)), ("point", point), ("sun", sun)] {
        let realtime = floor_scene(8.0, Vec3::new(0.0, 5.0, 4.0), vec![light]);
        let expected = realtime_diffuse(&mut gpu, &realtime, &s, size);
        let mut to_bake = realtime.clone();
        to_bake.lights[0].mode = LightMode::Baked;
        let baked = render(&mut gpu, &baked_scene(&to_bake, &s), &s, size);
        assert!(baked.plan.lights.is_empty(), "{name} is not shaded in realtime");
        let peak = expected.iter().copied().fold(0.0, f32::max);
        // The dim rim too: everything above 2% of the brightest pixel.
        let mut errors: Vec<f32> = expected
            .iter()
            .zip(&baked.hdr)
            .filter(|(e, _)| **e > peak * 0.005)
            .map(|(e, b)| (b[0] - e).abs() / e)
            .collect();
        errors.sort_by(f32::total_cmp);
        let at = |q: f32| errors[((errors.len() - 1) as f32 * q) as usize];
        let signed: f32 =
            expected.iter().zip(&baked.hdr).filter(|(e, _)| **e > peak * 0.005).map(|(e, b)| b[0] - e).sum::<f32>()
                / expected.iter().filter(|e| **e > peak * 0.005).sum::<f32>();
        println!(
            "{name}: {} pixels; baked against realtime diffuse: median {:.2}%, p95 {:.2}%, worst {:.2}%, \
             overall {:+.2}%",
            errors.len(),
            at(0.5) * 100.0,
            at(0.95) * 100.0,
            at(1.0) * 100.0,
            signed * 100.0
        );
        assert!(errors.len() > 2500, "{name}: {} lit pixels", errors.len());
        assert!(at(0.5) < 0.01, "{name}: median {}", at(0.5));
        assert!(at(0.95) < 0.03, "{name}: p95 {}", at(0.95));
    }
}

#[test]
fn a_box_on_a_floor_under_the_baked_sky_gets_the_traced_sky_light() {
    use chiaro_scene::environment::EnvironmentLight;
    use chiaro_scene::settings::{EnvironmentMode, EnvironmentSource};
    // The sun sets the sky's direction and brightness; realtime, so the bake holds only
    // the sky.
    let mut sun = Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(-0.4, -0.8, -0.3));
    sun.intensity = 5.0;
    let mut scene = floor_scene(8.0, Vec3::new(0.0, 5.0, 4.0), vec![sun]);
    add_box(&mut scene, Vec3::new(0.0, 0.5, 0.0), Vec3::ONE, 0.3, CastShadows::On);
    let mut s = settings(RenderPath::Forward);
    s.environment.source = EnvironmentSource::Sky;
    s.environment.mode = EnvironmentMode::Baked;
    s.bake.samples = Some(256);
    s.bake.texels_per_metre = 8.0;
    let baked = baked_scene(&scene, &s);
    let mut gpu = renderer();
    let frame = render(&mut gpu, &baked, &s, 128);
    let aovs = frame.aovs.as_ref().unwrap();

    let sky = EnvironmentLight::from_settings(&s.environment, &scene).unwrap().unwrap();
    let bvh = chiaro_trace::SceneBvh::build(&scene);
    let luminance = |e: Vec3| chiaro_math::tonemap::luminance(e);
    let open_floor =
        luminance(chiaro_trace::environment_irradiance(&bvh, &sky, Vec3::new(3.5, 0.0, 3.5), Vec3::Y, 32, 7));
    let (mut ratios, mut shaded) = (Vec::new(), Vec::new());
    for i in (0..aovs.position_ws.len()).step_by(2) {
        let p = Vec3::from(aovs.position_ws[i]);
        if !(p.y.abs() < 1e-3 && p.x.abs() < 3.5 && p.z.abs() < 3.5) {
            continue;
        }
        let traced = luminance(chiaro_trace::environment_irradiance(&bvh, &sky, p, Vec3::Y, 24, i as u64));
        let ratio = luminance(Vec3::from(aovs.baked_irradiance[i])) / traced;
        ratios.push(ratio);
        // Where the box hides a tenth of the sky or more.
        if traced < 0.9 * open_floor {
            shaded.push(ratio);
        }
    }
    ratios.sort_by(f32::total_cmp);
    shaded.sort_by(f32::total_cmp);
    let shaded_median = shaded[shaded.len() / 2];
    let (median, p10, p90) = (ratios[ratios.len() / 2], ratios[ratios.len() / 10], ratios[ratios.len() * 9 / 10]);
    println!(
        "baked sky on the floor against the traced sky: {} pixels, baked / traced median {median:.4}, 10th \
         percentile {p10:.4}, 90th {p90:.4}; the {} pixels the box darkens: median {shaded_median:.4}; open floor \
         {open_floor:.2} lux",
        ratios.len(),
        shaded.len()
    );
    assert!(ratios.len() > 1_000 && shaded.len() > 100, "{} {}", ratios.len(), shaded.len());
    assert!((median - 1.0).abs() < 0.03, "median {median}");
    assert!((shaded_median - 1.0).abs() < 0.03, "median by the box {shaded_median}");

    // `compare` judges the same: the environment as a light, against the traced one.
    let view = View::from_camera(&baked, 0, 96, 96);
    let prepared = gpu.prepare(&baked).unwrap();
    let result = chiaro_compare::compare_shadows(&mut gpu, &baked, &prepared, &view, &s).unwrap();
    let Some(chiaro_compare::EnvironmentReport::Compared { pixels, median, .. }) = result.environment else {
        panic!("{:?}", result.environment);
    };
    println!("compare: baked / traced sky over {pixels} pixels, median {median:.4}");
    assert!(pixels > 300 && (median - 1.0).abs() < 0.03, "{pixels} {median}");
    s.environment.mode = EnvironmentMode::Realtime;
    let result = chiaro_compare::compare_shadows(&mut gpu, &baked, &prepared, &view, &s).unwrap();
    assert!(
        matches!(result.environment, Some(chiaro_compare::EnvironmentReport::NotCompared(why)) if why.starts_with("realtime"))
    );
}
