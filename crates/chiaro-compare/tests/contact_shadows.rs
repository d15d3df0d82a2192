//! Screen-space contact shadows (`[shadows] contact`) against the ray-traced reference on
//! the software device: low boxes and a cube on a floor seen from close by, lit in turn by
//! a sun, a point light and a spot. Where a large normal bias lets light leak under the
//! casters' feet (the sun's, a low point light's), contact shadows close the leak; with
//! the default bias they cost no agreement; and the lit image of both paths (the forward
//! one multisampled) darkens where the shadow AOV does.

mod common;

use chiaro_compare::LightComparison;
use chiaro_render::{FrameOptions, FrameOutput, View};
use chiaro_scene::{Light, LightShadow, RenderPath, Scene, Settings};
use common::*;
use glam::Vec3;

const SIZE: u32 = 192;

fn settings(contact: bool) -> Settings {
    let mut settings = unlit_settings();
    settings.shadows.contact = contact;
    settings
}

/// The light's comparison with the reference at `edge_band_px`.
fn judged(scene: &Scene, settings: &Settings, edge_band_px: usize) -> LightComparison {
    judged_at(scene, settings, edge_band_px, SIZE)
}

#[test]
fn contact_shadows_close_the_leak_a_large_normal_bias_opens() {
    for light in [sun(), point(), spot()] {
        let name = light.name.clone();
        let scene = low_boxes(light, 4.0);
        for band in [1, 0] {
            let (off, on) = (judged(&scene, &settings(false), band), judged(&scene, &settings(true), band));
            eprintln!("{name}, band {band}: without {off:?}, with {on:?}");
            if name == "sun" {
                // The leak under the boxes' sunward sides: 66 pixels at band 1, 154 at 0.
                assert!(off.missed_shadow >= 40, "{name}, band {band}: the bias leaks only {off:?}");
                assert!(on.missed_shadow * 3 <= off.missed_shadow, "{name}, band {band}: {off:?} -> {on:?}");
                assert!(disagreeing(&on) < disagreeing(&off), "{name}, band {band}: {off:?} -> {on:?}");
            }
            // At band 0 the pixels a shadow edge crosses count too, where a march's samples
            // and the reference's rays fall either way (spot: 4 -> 5 pixels of 23,125).
            if band == 1 {
                assert!(disagreeing(&on) <= disagreeing(&off), "{name}: {off:?} -> {on:?}");
                assert!(share(&on) < 0.001, "{name}: {on:?}");
            }
        }
    }
}

#[test]
fn contact_shadows_close_the_leak_under_a_low_point_light() {
    // 35 cm above the floor, 70 cm from the 4 cm box, with an 8-texel normal bias: the
    // cube face's texels are coarse at that distance and the bias lets light under it.
    let low = Light { shadow: LightShadow::default(), ..point_light(Vec3::new(0.9, 0.35, 1.3), 20.0, Some(10.0)) };
    let scene = low_boxes(low, 8.0);
    let (off, on) = (judged(&scene, &settings(false), 1), judged(&scene, &settings(true), 1));
    eprintln!("low point, band 1: without {off:?}, with {on:?}");
    assert!(off.missed_shadow >= 15, "the bias leaks only {off:?}");
    assert!(on.missed_shadow * 3 <= off.missed_shadow, "{off:?} -> {on:?}");
    assert!(disagreeing(&on) < disagreeing(&off), "{off:?} -> {on:?}");
}

#[test]
fn with_the_default_bias_contact_shadows_cost_no_agreement() {
    for light in [sun(), point(), spot()] {
        let name = light.name.clone();
        let scene = low_boxes(light, LightShadow::default().normal_bias);
        let (off, on) = (judged(&scene, &settings(false), 1), judged(&scene, &settings(true), 1));
        eprintln!("{name}, band 1: without {off:?}, with {on:?}");
        assert!(disagreeing(&on) <= disagreeing(&off), "{name}: {off:?} -> {on:?}");
        assert!(share(&on) < 0.0005, "{name}: {on:?}");
        // Band 0, for docs/shadows.md: edge pixels fall either way (see above).
        let (off, on) = (judged(&scene, &settings(false), 0), judged(&scene, &settings(true), 0));
        eprintln!("{name}, band 0: without {off:?}, with {on:?}");
    }
}

fn render(scene: &Scene, settings: &Settings, shadow_aovs: bool) -> FrameOutput {
    let mut renderer = renderer();
    let prepared = renderer.prepare(scene).unwrap();
    let view = View::from_camera(scene, 0, SIZE, SIZE);
    let options = FrameOptions { readback: true, shadow_aovs, ..Default::default() };
    renderer.render(scene, &prepared, &view, settings, options).unwrap()
}

/// How many pixels set in `a` have a pixel set in `b` at most one pixel away.
fn near(a: &[bool], b: &[bool]) -> usize {
    let size = SIZE as i32;
    let set = |x: i32, y: i32| (0..size).contains(&x) && (0..size).contains(&y) && b[(y * size + x) as usize];
    (0..a.len() as i32)
        .filter(|&i| a[i as usize])
        .filter(|&i| (-1..=1).any(|dy| (-1..=1).any(|dx| set(i % size + dx, i / size + dy))))
        .count()
}

/// Pixels whose radiance contact shadows more than halve, of `off` and `on`.
fn darkened(off: &FrameOutput, on: &FrameOutput) -> Vec<bool> {
    off.hdr.iter().zip(&on.hdr).map(|(a, b)| b[1] < 0.5 * a[1]).collect()
}

#[test]
fn the_lit_image_of_both_paths_darkens_where_the_shadow_aov_does() {
    let scene = low_boxes(sun(), 4.0);
    let aov = |contact| render(&scene, &settings(contact), true).shadow_aovs.remove(0);
    let (aov_off, aov_on) = (aov(false), aov(true));
    let in_aov: Vec<bool> = aov_off.iter().zip(&aov_on).map(|(a, b)| *b < 0.5 * *a).collect();
    let aov_count = in_aov.iter().filter(|&&d| d).count();
    assert!(aov_count > 40, "contact shadows darken {aov_count} pixels of the shadow AOV");
    for (path, msaa) in [(RenderPath::Forward, 4), (RenderPath::Forward, 1), (RenderPath::Deferred, 1)] {
        let lit = |contact| {
            let mut s = settings(contact);
            s.render.path = path;
            s.render.msaa = msaa;
            render(&scene, &s, false)
        };
        let (off, on) = (lit(false), lit(true));
        assert!(!off.graph.passes.contains(&"contact depth"), "{path:?}: {:?}", off.graph.passes);
        assert!(on.graph.passes.contains(&"contact depth"), "{path:?}: {:?}", on.graph.passes);
        let in_image = darkened(&off, &on);
        let image_count = in_image.iter().filter(|&&d| d).count();
        // Multisampled, the lit pixels on a contact shadow's edge mix samples either side
        // of it: a darkened pixel counts where the other image darkens it or a neighbour.
        let (image_near, aov_near) = (near(&in_image, &in_aov), near(&in_aov, &in_image));
        eprintln!(
            "{path:?}: {image_count} darkened, {aov_count} in the AOV; {image_near} and {aov_near} near the other's"
        );
        assert!(image_near as f64 >= 0.95 * image_count as f64, "{path:?}: {image_near} of {image_count}");
        assert!(aov_near as f64 >= 0.95 * aov_count as f64, "{path:?}: {aov_near} of {aov_count}");
    }
}

#[test]
fn beside_a_wall_a_point_light_keeps_false_contact_shadow_under_a_tenth_of_a_percent() {
    // The light 40 cm from the wall and 60 cm up, boxes between, seen from close by: rays
    // from the wall towards the light pass just behind the boxes' silhouettes, which the
    // depth buffer cannot tell from rays that enter them.
    let mut scene = point_beside_a_wall();
    for (eye, target) in [
        (Vec3::new(0.3, 0.5, -0.6), Vec3::new(0.0, 0.1, -1.8)),
        (Vec3::new(-0.2, 0.3, -1.0), Vec3::new(0.4, 0.05, -1.7)),
    ] {
        look_from(&mut scene, eye, target);
        for band in [3, 1, 0] {
            let (off, on) = (judged(&scene, &settings(false), band), judged(&scene, &settings(true), band));
            eprintln!("wall from {eye}, band {band}: without {off:?}, with {on:?}");
            if band == 1 {
                assert!(share(&on) < 0.001, "from {eye}: {on:?}");
            }
        }
    }
}
