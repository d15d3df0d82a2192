//! Shadows seen through an orthographic camera against the ray-traced reference, which
//! casts parallel primary rays from the same projection: cascades fitted to the view's
//! box slices, and a point light's cube tiles sized by the coverage parallel rays give.

mod common;

use chiaro_compare::{
    EDGE_BAND_PX, JudgedLight, PixelVerdict, ShadowComparison, assert_agrees_with_reference, classify_pixels,
};
use chiaro_render::{ShadowStatus, View};
use chiaro_scene::{CastShadows, Light, LightKind, LightShadow, Scene};
use common::*;
use glam::Vec3;

/// Boxes on a floor under `light`, seen by an orthographic camera 10 m high from above
/// and in front.
fn boxes_from_above(light: Light) -> Scene {
    let eye = Vec3::new(4.0, 9.0, 10.0);
    let mut scene = floor_scene(30.0, eye, vec![light]);
    look_from(&mut scene, eye, Vec3::new(0.0, 0.5, 0.0));
    make_orthographic(&mut scene, 5.0, 40.0);
    for (k, position) in
        [Vec3::new(-2.0, 0.75, 0.0), Vec3::new(1.5, 0.5, -1.5), Vec3::new(0.5, 1.0, 2.5)].into_iter().enumerate()
    {
        add_box(&mut scene, position, Vec3::new(1.0, 2.0 * position.y, 1.0), 0.3 * k as f32, CastShadows::On);
    }
    scene
}

fn agreeing_shadowed(scene: &Scene, result: &ShadowComparison) -> usize {
    let light = &scene.lights[0];
    let verdicts = classify_pixels(&JudgedLight {
        rendered_shadow: &result.rendered[0],
        rendered_position: &result.reference.position,
        reference: &result.reference,
        light_index: 0,
        light,
        range: light.range.unwrap_or(f32::INFINITY),
        edge_band_px: EDGE_BAND_PX,
    });
    verdicts.iter().filter(|v| **v == PixelVerdict::AgreeShadowed).count()
}

#[test]
fn directional_cascades_follow_an_orthographic_view() {
    let sun = Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(0.6, -1.0, 0.8)) };
    let scene = boxes_from_above(sun);
    assert!(View::from_camera(&scene, 0, 8, 8).is_orthographic());
    for cascades in [1, 4] {
        let mut settings = unlit_settings();
        settings.shadows.max_distance = 30.0;
        settings.shadows.directional.cascade_count = cascades;
        let result = compare(&scene, &settings, 192);
        let c = &result.reports[0].comparison;
        assert!(c.compared > 20_000, "{cascades} cascades: only {} pixels compared", c.compared);
        let shadowed = agreeing_shadowed(&scene, &result);
        eprintln!(
            "{cascades}: {} compared, {} false, {} missed, {shadowed} agree shadowed",
            c.compared, c.false_shadow, c.missed_shadow
        );
        assert!(shadowed > 500, "{cascades} cascades: only {shadowed} shadowed pixels agree");
        assert_agrees_with_reference(&format!("orthographic, {cascades} cascades"), c);
    }
}

#[test]
fn point_light_shadows_through_an_orthographic_view() {
    let mut point = point_light(Vec3::new(0.0, 3.0, 0.5), 30.0, Some(15.0));
    point.shadow = LightShadow::default();
    let scene = boxes_from_above(point);
    let result = compare(&scene, &unlit_settings(), 192);
    assert_eq!(result.status[0], ShadowStatus::Mapped);
    let c = &result.reports[0].comparison;
    assert!(c.compared > 20_000, "only {} pixels compared", c.compared);
    let shadowed = agreeing_shadowed(&scene, &result);
    assert!(shadowed > 500, "only {shadowed} shadowed pixels agree");
    assert_agrees_with_reference("orthographic, point light", c);
}
