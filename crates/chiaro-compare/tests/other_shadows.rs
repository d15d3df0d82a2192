//! Spot and point shadows against the ray-traced reference on the software device: a box
//! between a spot and a wall, a point light in a ring of pillars shadowing every cube
//! face's region, no seams where faces meet, and a caster reaching behind a spot.

mod common;

use chiaro_compare::{
    EDGE_BAND_PX, JudgedLight, PixelVerdict, ShadowComparison, assert_agrees_with_reference, classify_pixels,
};
use chiaro_math::shadow::local::cube_face;
use chiaro_render::ShadowStatus;
use chiaro_scene::{CastShadows, Light, LightKind, LightShadow, Scene, ShadowMode};
use common::*;
use glam::Vec3;

fn spot(position: Vec3, direction: Vec3, outer_deg: f32, range: f32) -> Light {
    let kind =
        LightKind::Spot { inner_cone_rad: (outer_deg * 0.7).to_radians(), outer_cone_rad: outer_deg.to_radians() };
    Light {
        name: "spot".into(),
        node: 50,
        intensity: 40.0,
        range: Some(range),
        ..Light::new(kind, position, direction)
    }
}

fn verdicts(scene: &Scene, result: &ShadowComparison) -> Vec<PixelVerdict> {
    let light = &scene.lights[0];
    let range = light.range.unwrap_or(f32::INFINITY);
    classify_pixels(&JudgedLight {
        rendered_shadow: &result.rendered[0],
        rendered_position: &result.reference.position,
        reference: &result.reference,
        light_index: 0,
        light,
        range,
        edge_band_px: EDGE_BAND_PX,
    })
}

fn assert_agrees(label: &str, result: &ShadowComparison) {
    assert_eq!(result.status[0], ShadowStatus::Mapped, "{label}: no shadow map");
    let c = &result.reports[0].comparison;
    assert!(c.compared > 2000, "{label}: only {} pixels compared", c.compared);
    assert_agrees_with_reference(label, c);
}

#[test]
fn box_between_a_spot_and_a_wall() {
    // The floor stands up as a wall at z = -4, lit by a spot at z = +2 through a box.
    let mut scene = floor_scene(12.0, Vec3::ZERO, vec![spot(Vec3::new(0.0, 1.0, 2.0), Vec3::NEG_Z, 40.0, 15.0)]);
    scene.instances[0].world_from_local = glam::Mat4::from_rotation_translation(
        glam::Quat::from_rotation_x(90f32.to_radians()),
        Vec3::new(0.0, 1.0, -4.0),
    );
    add_box(&mut scene, Vec3::new(0.3, 1.0, -1.0), Vec3::new(0.8, 0.8, 0.8), 0.3, CastShadows::On);
    look_from(&mut scene, Vec3::new(2.5, 2.0, 4.0), Vec3::new(0.0, 1.0, -3.0));
    let result = compare(&scene, &unlit_settings(), 192);
    assert_agrees("spot and wall", &result);
    let shadowed = verdicts(&scene, &result).iter().filter(|v| **v == PixelVerdict::AgreeShadowed).count();
    assert!(shadowed > 300, "the box shadows the wall: {shadowed}");
}

#[test]
fn point_light_in_a_ring_of_pillars_shadows_every_face() {
    let light_position = Vec3::new(0.0, 1.5, 0.0);
    let mut point = point_light(light_position, 20.0, Some(12.0));
    point.shadow = LightShadow::default();
    let mut scene = floor_scene(16.0, Vec3::ZERO, vec![point]);
    // Pillars on the four sides, a slab overhead (its underside faces the light) with a
    // block hanging from it, and a low block on the floor below the light.
    for k in 0..8 {
        let a = k as f32 * std::f32::consts::TAU / 8.0 + 0.2;
        add_box(&mut scene, Vec3::new(2.0 * a.cos(), 1.5, 2.0 * a.sin()), Vec3::new(0.3, 3.0, 0.3), a, CastShadows::On);
    }
    add_box(&mut scene, Vec3::new(0.0, 4.0, 0.0), Vec3::new(8.0, 0.2, 8.0), 0.0, CastShadows::On);
    add_box(&mut scene, Vec3::new(0.4, 3.2, 0.3), Vec3::new(0.4, 0.8, 0.4), 0.0, CastShadows::On);
    add_box(&mut scene, Vec3::new(-0.3, 0.25, 0.4), Vec3::new(0.5, 0.5, 0.5), 0.5, CastShadows::On);
    // Views from inside the ring towards each face's region.
    let mut shadowed_per_face = [0usize; 6];
    for (eye, target) in [
        (Vec3::new(0.3, 1.0, 1.7), Vec3::new(-0.1, 1.3, -2.0)),
        (Vec3::new(1.7, 1.0, -0.3), Vec3::new(-2.0, 1.3, 0.1)),
        (Vec3::new(-1.7, 1.0, 0.3), Vec3::new(2.0, 1.3, -0.1)),
        (Vec3::new(-0.3, 1.0, -1.7), Vec3::new(0.1, 1.3, 2.0)),
        (Vec3::new(0.2, 0.6, 0.9), Vec3::new(0.0, 3.5, 0.0)),
        (Vec3::new(0.8, 2.6, 0.8), Vec3::new(-0.2, 0.0, -0.2)),
    ] {
        look_from(&mut scene, eye, target);
        let result = compare(&scene, &unlit_settings(), 160);
        assert_agrees(&format!("ring from {eye}"), &result);
        for (i, v) in verdicts(&scene, &result).iter().enumerate() {
            if *v == PixelVerdict::AgreeShadowed {
                let p = result.reference.position[i].unwrap();
                shadowed_per_face[cube_face(p - light_position)] += 1;
            }
        }
    }
    for (face, count) in shadowed_per_face.iter().enumerate() {
        assert!(*count > 20, "face {face}: only {count} agreeing shadowed pixels ({shadowed_per_face:?})");
    }
}

#[test]
fn no_seams_where_cube_faces_meet() {
    // A low point light over an open floor: the floor crosses the boundaries between the
    // -Y face and the four side faces, where a seam would show as a line of false shadow.
    let mut scene = floor_scene(16.0, Vec3::ZERO, vec![point_light(Vec3::new(0.2, 0.6, -0.1), 10.0, Some(8.0))]);
    for (eye, target) in [(Vec3::new(0.0, 5.0, 3.0), Vec3::new(0.0, 0.0, -0.5)), (Vec3::new(3.0, 2.0, 3.0), Vec3::ZERO)]
    {
        look_from(&mut scene, eye, target);
        let result = compare(&scene, &unlit_settings(), 192);
        assert_eq!(result.status[0], ShadowStatus::Mapped);
        let c = &result.reports[0].comparison;
        assert!(c.compared > 10_000, "{} compared", c.compared);
        assert_eq!(c.false_shadow, 0, "seams or acne on {} of {} floor pixels", c.false_shadow, c.compared);
    }
}

#[test]
fn caster_partly_behind_a_spot_is_not_distorted() {
    // A long beam passes through the spot's position: half of it lies behind the light.
    // Clamping its depth would smear that half across the tile; clipping leaves the cone's
    // view of the front half exact.
    let mut scene = floor_scene(14.0, Vec3::ZERO, vec![spot(Vec3::new(0.0, 3.0, 0.0), Vec3::NEG_Y, 50.0, 10.0)]);
    add_box(&mut scene, Vec3::new(0.6, 2.6, 0.0), Vec3::new(0.25, 2.0, 0.25), 0.0, CastShadows::On);
    add_box(&mut scene, Vec3::new(-0.8, 1.0, 0.5), Vec3::new(0.6, 0.6, 0.6), 0.0, CastShadows::On);
    look_from(&mut scene, Vec3::new(0.0, 6.0, 5.0), Vec3::ZERO);
    let result = compare(&scene, &unlit_settings(), 192);
    assert_agrees("beam behind the spot", &result);
    let shadowed = verdicts(&scene, &result).iter().filter(|v| **v == PixelVerdict::AgreeShadowed).count();
    assert!(shadowed > 200, "the beam and box shadow the floor: {shadowed}");
}

#[test]
fn lights_that_do_not_fit_get_no_realtime_shadow() {
    // Three points want 18 tiles of 16 (the atlas of Catlike Coding's Custom SRP tutorial
    // "Point and Spot Shadows"): the least important gets none, and says so.
    let lights = (0..3)
        .map(|i| {
            let mut l = point_light(Vec3::new(i as f32 * 2.0 - 2.0, 1.0, 0.0), 10.0 + i as f32, Some(6.0));
            l.node = 60 + i;
            l
        })
        .collect();
    let mut scene = floor_scene(12.0, Vec3::ZERO, lights);
    add_box(&mut scene, Vec3::new(0.0, 0.3, 0.0), Vec3::splat(0.6), 0.0, CastShadows::On);
    look_from(&mut scene, Vec3::new(0.0, 6.0, 4.0), Vec3::ZERO);
    let mut settings = unlit_settings();
    settings.shadows.other.max_tiles = 16;
    let result = compare(&scene, &settings, 96);
    let no_tile = result.status.iter().filter(|s| **s == ShadowStatus::NoTile).count();
    let mapped = result.status.iter().filter(|s| **s == ShadowStatus::Mapped).count();
    assert_eq!((mapped, no_tile), (2, 1), "{:?}", result.status);
    let unmapped = result.status.iter().position(|s| *s == ShadowStatus::NoTile).unwrap();
    assert!(result.rendered[unmapped].iter().filter(|v| v.is_finite()).all(|&v| v == 1.0));
}

#[test]
fn a_light_inside_a_closed_box_stays_inside_with_two_sided_casters() {
    // A point light inside a single-sided box (faces out, as glTF exporters write closed
    // meshes): the light sees only back faces. Two-sided casting (glTF nodes' default)
    // blocks it, as the reference does; the casting of Catlike Coding's Custom SRP
    // tutorials ("on": the ShadowCaster pass culls as the material does) lets it light the
    // floor around the box.
    let mut point = point_light(Vec3::new(0.0, 0.6, 0.0), 20.0, Some(8.0));
    point.shadow = LightShadow::default();
    for (cast, leaks) in [(CastShadows::TwoSided, false), (CastShadows::On, true)] {
        let mut scene = floor_scene(10.0, Vec3::ZERO, vec![point.clone()]);
        add_box(&mut scene, Vec3::new(0.0, 0.6, 0.0), Vec3::new(1.0, 1.0, 1.0), 0.3, cast);
        look_from(&mut scene, Vec3::new(2.5, 2.5, 3.0), Vec3::new(0.0, 0.0, 0.0));
        let result = compare(&scene, &unlit_settings(), 160);
        let c = &result.reports[0].comparison;
        println!(
            "{cast:?}: {:.3}% of {} compared pixels disagree ({} false, {} missed)",
            100.0 * c.disagreement(),
            c.compared,
            c.false_shadow,
            c.missed_shadow
        );
        if leaks {
            assert!(c.missed_shadow > 1000, "the material-faces casting (\"on\") leaks light out of the box: {c:?}");
        } else {
            assert!(c.compared > 1000, "{c:?}");
            assert_agrees_with_reference(&format!("{cast:?}"), c);
        }
    }
}

#[test]
fn a_caster_three_centimetres_from_a_point_light_still_casts() {
    // A thin plate 2.5 to 3.5 cm below the light, wholly inside the old 5 cm near plane:
    // it was clipped away and its shadow on the floor vanished.
    let light_position = Vec3::new(0.0, 1.0, 0.0);
    let mut point = point_light(light_position, 20.0, Some(8.0));
    point.shadow = LightShadow::default();
    let mut scene = floor_scene(10.0, Vec3::ZERO, vec![point]);
    add_box(&mut scene, Vec3::new(0.0, 0.97, 0.0), Vec3::new(0.2, 0.01, 0.2), 0.0, CastShadows::TwoSided);
    look_from(&mut scene, Vec3::new(1.5, 2.5, 2.0), Vec3::new(0.0, 0.0, 0.0));
    let result = compare(&scene, &unlit_settings(), 160);
    let c = &result.reports[0].comparison;
    let shadowed = verdicts(&scene, &result).iter().filter(|v| **v == PixelVerdict::AgreeShadowed).count();
    println!(
        "caster 3 cm from the light: {:.3}% of {} disagree ({} missed), {shadowed} agreeing shadowed pixels",
        100.0 * c.disagreement(),
        c.compared,
        c.missed_shadow
    );
    assert_agrees("caster at 3 cm", &result);
    assert!(shadowed > 1000, "the plate shadows the floor under it: {shadowed}");
}

#[test]
fn a_point_light_close_to_a_wall_casts_no_acne_on_it() {
    // A point light 0.4 m from a wall that meets the floor: both are lit across several
    // cube faces, from head-on to grazing; a small cube beside the light casts the one
    // true shadow. Close to the light a face's texels are millimetres wide and the depths
    // the biases must clear as small: false shadow there is acne.
    let wall_z = -2.0;
    for (light_position, eye, mode) in [
        (Vec3::new(0.1, 1.2, -1.6), Vec3::new(0.8, 1.6, 0.5), ShadowMode::Soft),
        (Vec3::new(0.1, 1.2, -1.6), Vec3::new(-1.5, 0.8, 0.0), ShadowMode::Hard),
        (Vec3::new(0.0, 0.4, -1.6), Vec3::new(0.0, 0.6, -0.4), ShadowMode::Soft),
        (Vec3::new(0.0, 2.0, -1.6), Vec3::new(0.3, 0.5, 0.5), ShadowMode::Hard),
    ] {
        let mut point = point_light(light_position, 4.0, Some(6.0));
        point.shadow = LightShadow { mode, ..LightShadow::default() };
        let mut scene = floor_scene(10.0, Vec3::ZERO, vec![point]);
        let mut wall = scene.instances[0].clone();
        wall.world_from_local = glam::Mat4::from_rotation_translation(
            glam::Quat::from_rotation_x(90f32.to_radians()),
            Vec3::new(0.0, 5.0, wall_z),
        );
        scene.instances.push(wall);
        add_box(&mut scene, light_position + Vec3::new(0.25, -0.1, -0.2), Vec3::splat(0.12), 0.4, CastShadows::On);
        look_from(&mut scene, eye, Vec3::new(light_position.x, light_position.y * 0.5, wall_z));
        let result = compare(&scene, &unlit_settings(), 192);
        let c = &result.reports[0].comparison;
        let shadowed = verdicts(&scene, &result).iter().filter(|v| **v == PixelVerdict::AgreeShadowed).count();
        println!(
            "{mode:?} point light at {light_position}, 0.4 m from a wall, seen from {eye}: {} compared, false \
             shadow {:.3}%, missed {:.3}%, {shadowed} agreeing shadowed pixels",
            c.compared,
            100.0 * c.false_share(),
            100.0 * c.missed_share()
        );
        assert_agrees(&format!("wall from {eye}"), &result);
        assert!(c.false_share() < 0.001, "acne: {:.3}% false shadow", 100.0 * c.false_share());
        assert!(shadowed > 50, "the cube shadows the wall: {shadowed}");
    }
}
