//! Directional shadows against the ray-traced reference on the software device: a box on a
//! floor shadows where the reference says with every filter and cascade count, a lit floor
//! shows no acne down to a 10 degree sun, shadows end at the max distance, and the
//! per-object cast/receive flags do what they say.

mod common;

use chiaro_compare::{
    EDGE_BAND_PX, JudgedLight, PixelVerdict, ShadowComparison, assert_agrees_with_reference, classify_pixels,
};
use chiaro_render::View;
use chiaro_scene::{CastShadows, Light, LightKind, Scene};
use common::*;
use glam::Vec3;

fn sun(elevation_deg: f32, azimuth_deg: f32) -> Light {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    let direction = -Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin());
    Light { name: "sun".into(), node: 7, intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, direction) }
}

/// A floor seen from a three-quarter view, with boxes (position, size, casting) on it.
fn box_scene(light: Light, boxes: &[(Vec3, Vec3, CastShadows)], eye: Vec3) -> Scene {
    let mut scene = floor_scene(40.0, eye, vec![light]);
    look_from(&mut scene, eye, Vec3::new(0.0, 0.5, 0.0));
    for &(position, size, cast) in boxes {
        add_box(&mut scene, position, size, 0.4, cast);
    }
    scene
}

fn verdicts(scene: &Scene, result: &ShadowComparison) -> Vec<PixelVerdict> {
    let positions: Vec<Option<Vec3>> = result.reference.position.clone();
    classify_pixels(&JudgedLight {
        rendered_shadow: &result.rendered[0],
        rendered_position: &positions,
        reference: &result.reference,
        light_index: 0,
        light: &scene.lights[0],
        range: f32::INFINITY,
        edge_band_px: EDGE_BAND_PX,
    })
}

#[test]
fn box_shadow_matches_the_reference_with_every_filter_and_cascade_count() {
    let scene = box_scene(
        sun(40.0, -60.0),
        &[(Vec3::new(0.0, 0.75, 0.0), Vec3::new(2.0, 1.5, 2.0), CastShadows::On)],
        Vec3::new(0.0, 5.0, 7.0),
    );
    for filter in ["pcf2x2", "tent3x3", "tent5x5", "tent7x7"] {
        for cascades in [1, 2, 4] {
            let mut settings = unlit_settings();
            // The scene is 10 m across: a 20 m shadow distance keeps one cascade's texels
            // (and so the wide filters' blur) near the size of the 3-pixel edge band.
            settings.shadows.max_distance = 20.0;
            settings.shadows.directional.filter = filter.into();
            settings.shadows.directional.cascade_count = cascades;
            let result = compare(&scene, &settings, 200);
            let c = &result.reports[0].comparison;
            let shadowed = verdicts(&scene, &result).iter().filter(|v| **v == PixelVerdict::AgreeShadowed).count();
            assert!(shadowed > 300, "{filter}, {cascades} cascades: only {shadowed} shadowed pixels agree");
            assert_agrees_with_reference(&format!("{filter}, {cascades} cascades"), c);
        }
    }
}

#[test]
fn no_acne_on_a_lit_floor_at_grazing_sun_angles() {
    for elevation in [10.0, 20.0, 45.0, 80.0] {
        let scene = box_scene(sun(elevation, 110.0), &[], Vec3::new(0.0, 3.0, 9.0));
        let result = compare(&scene, &unlit_settings(), 160);
        let c = &result.reports[0].comparison;
        assert!(c.compared > 10_000, "{elevation} deg: {} compared", c.compared);
        assert_eq!(c.false_shadow, 0, "{elevation} deg sun: acne on {} of {} floor pixels", c.false_shadow, c.compared);
    }
}

#[test]
fn shadows_fade_out_beyond_the_max_distance() {
    // Boxes marching away from the camera down -Z; shadows reach at most 12 m.
    let boxes: Vec<(Vec3, Vec3, CastShadows)> =
        (0..8).map(|i| (Vec3::new(0.0, 0.5, 2.0 - 3.0 * i as f32), Vec3::ONE, CastShadows::On)).collect();
    let scene = box_scene(sun(40.0, 0.0), &boxes, Vec3::new(0.0, 3.0, 6.0));
    let mut settings = unlit_settings();
    settings.shadows.max_distance = 12.0;
    let result = compare(&scene, &settings, 192);
    let aovs_depth = {
        let mut renderer = renderer();
        let prepared = renderer.prepare(&scene).unwrap();
        let frame = renderer
            .render(
                &scene,
                &prepared,
                &View::from_camera(&scene, 0, 192, 192),
                &settings,
                chiaro_render::FrameOptions { aovs: true, readback: true, ..Default::default() },
            )
            .unwrap();
        frame.aovs.unwrap().depth
    };
    let (mut near_shadowed, mut far_checked) = (0, 0);
    for (i, &depth) in aovs_depth.iter().enumerate() {
        let rendered = result.rendered[0][i];
        let reference = result.reference.visibility[0][i];
        if !depth.is_finite() || !reference.is_finite() {
            continue;
        }
        if depth > 12.0 {
            far_checked += 1;
            assert_eq!(rendered, 1.0, "shadow sampled at depth {depth}");
        } else if depth < 10.0 && reference == 0.0 && result.reports[0].difference[i] != [0, 0, 0, 255] {
            near_shadowed += 1;
            assert!(rendered < 0.5, "shadow lost at depth {depth}: {rendered}");
        }
    }
    assert!(far_checked > 1000 && near_shadowed > 100, "far {far_checked}, near shadowed {near_shadowed}");
}

#[test]
fn cast_and_receive_flags_are_honoured() {
    let boxes = [
        (Vec3::new(-2.0, 0.75, 0.0), Vec3::new(1.0, 1.5, 1.0), CastShadows::Off),
        (Vec3::new(2.0, 0.75, 0.0), Vec3::new(1.0, 1.5, 1.0), CastShadows::ShadowsOnly),
    ];
    let scene = box_scene(sun(60.0, 90.0), &boxes, Vec3::new(0.0, 6.0, 6.0));
    let result = compare(&scene, &unlit_settings(), 160);
    // The reference honours the same flags, so agreement means both are right...
    let c = &result.reports[0].comparison;
    assert_agrees_with_reference("cast and receive flags", c);
    // ...and there is a shadow (from the shadows-only box) but no visible box there.
    let shadowed = result.rendered[0].iter().filter(|v| **v < 0.5).count();
    assert!(shadowed > 100, "the shadows-only box casts: {shadowed}");
    let shadows_only_center = Vec3::new(2.0, 0.75, 0.0);
    let seen_inside =
        result.reference.position.iter().flatten().filter(|p| p.distance(shadows_only_center) < 0.45).count();
    assert_eq!(seen_inside, 0, "shadows-only boxes are invisible");

    // A floor that does not receive shadows reports attenuation 1 everywhere.
    let mut no_receive = scene.clone();
    no_receive.instances[0].receive_shadows = false;
    let result = compare(&no_receive, &unlit_settings(), 96);
    let aov = &result.rendered[0];
    let floor_pixels: Vec<usize> =
        (0..aov.len()).filter(|&i| result.reference.position[i].is_some_and(|p| p.y.abs() < 1e-3)).collect();
    assert!(floor_pixels.len() > 1000);
    assert!(floor_pixels.iter().all(|&i| aov[i] == 1.0));
}

#[test]
fn soft_and_dithered_cascade_transitions_keep_shadows_in_place() {
    // Boxes spread over the first two cascades' boundary (10 m at the default ratios
    // with a 100 m distance, here 4 m with 40 m).
    let boxes: Vec<(Vec3, Vec3, CastShadows)> = (0..5)
        .map(|i| (Vec3::new(-1.0 + 0.5 * i as f32, 0.5, 3.0 - 2.0 * i as f32), Vec3::ONE, CastShadows::On))
        .collect();
    let scene = box_scene(sun(45.0, -70.0), &boxes, Vec3::new(0.0, 3.0, 7.0));
    for blend in [chiaro_scene::CascadeBlend::Soft, chiaro_scene::CascadeBlend::Dither] {
        let mut settings = unlit_settings();
        settings.shadows.max_distance = 40.0;
        settings.shadows.directional.cascade_blend = blend;
        settings.shadows.directional.cascade_fade = 0.3;
        let result = compare(&scene, &settings, 192);
        let c = &result.reports[0].comparison;
        assert!(c.compared > 10_000);
        assert_agrees_with_reference(&format!("{blend:?} cascade blend"), c);
    }
}
