//! Measured facts about the light model on the GPU: radiance on a white floor follows the
//! inverse-square and range terms, spot cones light exactly their cone, and nothing beyond
//! a light's range is lit by it.

mod common;

use chiaro_math::brdf::brdf_cos;
use chiaro_math::light::{distance_attenuation, spot_angle_params, spot_attenuation};
use chiaro_scene::{Light, LightKind};
use common::*;
use glam::Vec3;

const EYE: Vec3 = Vec3::new(0.0, 6.0, 0.01);

/// Radiance the light model predicts at `p` on the floor (normal +Y) seen from `EYE`.
fn predicted(light: &Light, p: Vec3, range: f32) -> f32 {
    let v = (EYE - p).normalize();
    match light.kind {
        LightKind::Directional => light.intensity * brdf_cos(Vec3::ONE, 0.0, 1.0, Vec3::Y, v, -light.direction()).x,
        LightKind::Point | LightKind::Spot { .. } => {
            let to_light = light.position() - p;
            let l = to_light.normalize();
            let mut e = light.intensity * distance_attenuation(to_light.length_squared(), range);
            if let LightKind::Spot { inner_cone_rad, outer_cone_rad } = light.kind {
                e *= spot_attenuation(light.direction().dot(-l), spot_angle_params(inner_cone_rad, outer_cone_rad));
            }
            e * brdf_cos(Vec3::ONE, 0.0, 1.0, Vec3::Y, v, l).x
        }
        LightKind::Rect { .. } | LightKind::Disk { .. } => unreachable!("tests/area_lights.rs judges area lights"),
    }
}

#[test]
fn point_light_radiance_follows_inverse_square_within_2_percent() {
    let light = point_light(Vec3::new(0.0, 1.5, 0.0), 20.0, Some(100.0));
    let scene = floor_scene(12.0, EYE, vec![light.clone()]);
    let frame = render(&mut renderer(), &scene, &unlit_settings(), 256);
    let pixels = surface_pixels(&frame);
    assert!(pixels.len() > 20_000, "floor covers {} pixels", pixels.len());

    // Every pixel against the formula.
    let mut worst = 0.0f32;
    for &(_, p, n, radiance) in &pixels {
        assert!((n - Vec3::Y).length() < 1e-3);
        let expected = predicted(&light, p, 100.0);
        worst = worst.max((radiance.x / expected - 1.0).abs());
    }
    assert!(worst < 0.02, "worst relative error {worst}");

    // The ratio at two known distances, as a photometer would measure it.
    let nearest = |target: Vec3| {
        pixels.iter().min_by(|a, b| a.1.distance(target).total_cmp(&b.1.distance(target))).copied().unwrap()
    };
    let (_, p1, _, l1) = nearest(Vec3::new(0.5, 0.0, 0.0));
    let (_, p2, _, l2) = nearest(Vec3::new(3.0, 0.0, 0.0));
    let measured = l1.x / l2.x;
    let expected = predicted(&light, p1, 100.0) / predicted(&light, p2, 100.0);
    assert!(expected > 5.0, "the two points must differ a lot: {expected}");
    assert!((measured / expected - 1.0).abs() < 0.02, "ratio {measured} vs {expected}");
}

#[test]
fn pixels_beyond_a_lights_range_are_exactly_unlit() {
    let range = 3.0;
    let light = point_light(Vec3::new(0.5, 1.0, -0.5), 10.0, Some(range));
    let scene = floor_scene(12.0, EYE, vec![light.clone()]);
    let frame = render(&mut renderer(), &scene, &unlit_settings(), 192);
    let (mut outside, mut inside) = (0, 0);
    for &(_, p, _, radiance) in &surface_pixels(&frame) {
        let d = p.distance(light.position());
        if d >= range {
            outside += 1;
            assert_eq!(radiance, Vec3::ZERO, "lit at distance {d}");
        } else if d < range * 0.9 {
            inside += 1;
            assert!(radiance.x > 0.0, "unlit at distance {d}");
            let expected = predicted(&light, p, range);
            if expected > 1e-3 {
                assert!((radiance.x / expected - 1.0).abs() < 0.02, "{} vs {expected} at {d}", radiance.x);
            }
        }
    }
    assert!(outside > 1000 && inside > 1000, "outside {outside}, inside {inside}");
}

#[test]
fn spot_light_lights_exactly_its_cone() {
    let (inner, outer) = (20f32.to_radians(), 30f32.to_radians());
    let light = Light {
        name: "spot".into(),
        node: 3,
        intensity: 30.0,
        range: Some(50.0),
        ..Light::new(
            LightKind::Spot { inner_cone_rad: inner, outer_cone_rad: outer },
            Vec3::new(0.0, 3.0, 0.0),
            Vec3::NEG_Y,
        )
    };
    let scene = floor_scene(12.0, EYE, vec![light.clone()]);
    let frame = render(&mut renderer(), &scene, &unlit_settings(), 256);
    let margin = 0.3f32.to_radians();
    let (mut in_cone, mut lit) = (0usize, 0usize);
    for &(_, p, _, radiance) in &surface_pixels(&frame) {
        let angle = light.direction().angle_between(p - light.position());
        if angle < outer {
            in_cone += 1;
        }
        if radiance.x > 0.0 {
            lit += 1;
        }
        if angle > outer + margin {
            assert_eq!(radiance, Vec3::ZERO, "lit outside the cone at {} deg", angle.to_degrees());
        } else if angle < outer - margin {
            assert!(radiance.x > 0.0, "dark inside the cone at {} deg", angle.to_degrees());
        }
        if angle < inner {
            let expected = predicted(&light, p, 50.0);
            assert!((radiance.x / expected - 1.0).abs() < 0.02, "{} vs {expected}", radiance.x);
        }
    }
    // The cone on the floor is a disc of radius 3 tan(30 deg) = 1.73 m.
    assert!(in_cone > 2000, "cone covers {in_cone} pixels");
    let ratio = lit as f32 / in_cone as f32;
    assert!((ratio - 1.0).abs() < 0.02, "lit area {lit} vs cone {in_cone}");
}

#[test]
fn directional_light_gives_illuminance_times_brdf() {
    let direction = Vec3::new(0.3, -1.0, 0.2).normalize();
    let sun = Light {
        name: "sun".into(),
        node: 2,
        intensity: 2.0,
        ..Light::new(LightKind::Directional, Vec3::ZERO, direction)
    };
    let scene = floor_scene(12.0, EYE, vec![sun.clone()]);
    let frame = render(&mut renderer(), &scene, &unlit_settings(), 128);
    for &(_, p, _, radiance) in &surface_pixels(&frame) {
        let expected = predicted(&sun, p, 0.0);
        assert!((radiance.x / expected - 1.0).abs() < 0.02, "{} vs {expected}", radiance.x);
    }
}

#[test]
fn lights_over_the_limit_are_dropped_by_importance() {
    let lights: Vec<Light> = (0..70)
        .map(|i| point_light(Vec3::new((i % 10) as f32 - 4.5, 0.5, (i / 10) as f32 - 3.0), 1.0 + i as f32, Some(2.0)))
        .collect();
    let scene = floor_scene(12.0, EYE, lights);
    let mut forward = unlit_settings();
    forward.render.path = chiaro_scene::RenderPath::Forward;
    forward.lights.culling = chiaro_scene::LightCulling::None;
    let frame = render(&mut renderer(), &scene, &forward, 64);
    assert_eq!(frame.local_lights_shaded(), 64);
    assert_eq!(frame.local_lights_dropped(), 6);
    // Culled lists shade them all.
    forward.lights.culling = chiaro_scene::LightCulling::Clustered;
    let frame = render(&mut renderer(), &scene, &forward, 64);
    assert_eq!((frame.local_lights_shaded(), frame.local_lights_dropped()), (70, 0));
    // The deferred path shades them all, or as many as the setting says.
    let mut deferred = unlit_settings();
    deferred.render.path = chiaro_scene::RenderPath::Deferred;
    let frame = render(&mut renderer(), &scene, &deferred, 64);
    assert_eq!((frame.local_lights_shaded(), frame.local_lights_dropped()), (70, 0));
    deferred.lights.max_other_lights = Some(50);
    let frame = render(&mut renderer(), &scene, &deferred, 64);
    assert_eq!((frame.local_lights_shaded(), frame.local_lights_dropped()), (50, 20));
}

#[test]
fn every_pass_that_ran_reports_its_own_gpu_time() {
    let mut renderer = renderer();
    assert!(renderer.ctx.has_timestamps, "the software device offers timestamp queries");
    let scene = chiaro_scene::demo::demo_scene(4);
    let prepared = renderer.prepare(&scene).unwrap();
    let view = chiaro_render::View::from_camera(&scene, 0, 96, 96);
    let options = chiaro_render::FrameOptions { aovs: true, readback: true, ..Default::default() };
    let frame = renderer.render(&scene, &prepared, &view, &chiaro_scene::Settings::default(), options).unwrap();
    let passes: Vec<&str> = frame.timings.gpu_pass_ms.iter().map(|(p, _)| *p).collect();
    assert_eq!(passes, ["shadows", "depth prepass", "forward", "aov", "tonemap"]);
    for (pass, ms) in &frame.timings.gpu_pass_ms {
        assert!(*ms > 0.0 && ms.is_finite(), "{pass} pass timed at {ms} ms");
    }
}
