//! The default bake against a converged one (4096 samples a texel, not denoised) on a
//! scene of its own: a floor with boxes standing on it, a wall, a mixed spot light and a
//! baked sun. At the median floor texel and at the median floor texel within 0.3 m of
//! where a box meets the floor (the contact shadows of bounced light, where a blur shows
//! first), the default bake is within 5%, for at most a tenth of the converged bake's rays.

mod common;

use chiaro_bake::convergence::{DARK_SHARE, quantile};
use chiaro_bake::{BakeResult, Silent, bake};
use chiaro_scene::{CastShadows, Light, LightKind, LightMode, Scene, Settings};
use chiaro_testkit::{add_box, floor_scene};
use common::texel_places;
use glam::{Vec2, Vec3, Vec4};
use std::sync::atomic::AtomicBool;

/// The converged bake's samples a texel.
const REFERENCE_SAMPLES: u32 = 4096;
/// Floor texels this close to a box's footprint (metres) are in contact.
const CONTACT_M: f32 = 0.3;
/// The most a texel may be off at the median, in each region.
const MAX_MEDIAN_ERROR: f32 = 0.05;

/// The boxes: centre on the floor (x, z), size.
const BOXES: [(Vec2, Vec3); 3] = [
    (Vec2::new(-1.2, -0.4), Vec3::new(0.9, 0.9, 0.9)),
    (Vec2::new(0.9, -0.9), Vec3::new(0.6, 1.4, 0.6)),
    (Vec2::new(0.4, 1.1), Vec3::new(1.2, 0.5, 0.7)),
];

fn scene() -> Scene {
    let mut spot = Light::new(
        LightKind::Spot { inner_cone_rad: 0.5, outer_cone_rad: 0.8 },
        Vec3::new(0.5, 3.2, 1.6),
        Vec3::new(-0.2, -1.0, -0.45),
    );
    spot.intensity = 80.0;
    spot.range = Some(12.0);
    spot.mode = LightMode::Mixed;
    let mut sun = Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(0.5, -0.7, -0.4));
    sun.intensity = 2.0;
    sun.mode = LightMode::Mixed;
    sun.node = 11;
    let mut scene = floor_scene(6.0, Vec3::new(0.0, 5.0, 4.0), vec![spot, sun]);
    scene.materials[0].base_color = Vec4::new(0.75, 0.75, 0.75, 1.0);
    for (centre, size) in BOXES {
        add_box(&mut scene, Vec3::new(centre.x, size.y / 2.0, centre.y), size, 0.0, CastShadows::On);
    }
    // A wall along the floor's back edge, which bounces the spot's light onto the floor.
    add_box(&mut scene, Vec3::new(0.0, 1.0, -2.9), Vec3::new(6.0, 2.0, 0.2), 0.0, CastShadows::On);
    scene
}

fn settings(samples: Option<u32>, denoise: bool) -> Settings {
    let mut s = Settings::default();
    s.render.ambient = [0.05; 3];
    s.bake.samples = samples;
    s.bake.denoise = denoise;
    s.bake.probe_spacing = 6.0;
    s
}

fn run(scene: &Scene, s: &Settings) -> BakeResult {
    bake(scene, s, &Silent, &AtomicBool::new(false)).unwrap()
}

/// Per atlas, per texel: the world position of the floor (instance 0) it covers.
fn floor_texels(scene: &Scene, result: &BakeResult) -> Vec<Vec<Option<Vec3>>> {
    texel_places(scene, result)
        .into_iter()
        .map(|layer| layer.into_iter().map(|place| place.filter(|&(_, i, _)| i == 0).map(|(_, _, p)| p)).collect())
        .collect()
}

fn light(t: &[f32; 4]) -> f32 {
    t[0] + t[1] + t[2]
}

/// How far `p` on the floor is outside the nearest box's footprint (0 under a box).
fn distance_to_boxes(p: Vec3) -> f32 {
    BOXES
        .iter()
        .map(|(c, s)| {
            let d = (Vec2::new(p.x, p.z) - *c).abs() - Vec2::new(s.x, s.z) / 2.0;
            d.max(Vec2::ZERO).length()
        })
        .fold(f32::INFINITY, f32::min)
}

/// Sorted relative errors against `reference` of the wholly covered, lit floor texels
/// `pick` chooses by position.
fn floor_errors(
    test: &BakeResult,
    reference: &BakeResult,
    places: &[Vec<Option<Vec3>>],
    pick: impl Fn(Vec3) -> bool,
) -> Vec<f32> {
    let all: Vec<f32> = reference.lighting.lightmaps.iter().flat_map(|m| m.texels.iter().map(light)).collect();
    let dark = DARK_SHARE * all.iter().sum::<f32>() / all.len() as f32;
    let mut errors = Vec::new();
    for ((test, reference), places) in test.lighting.lightmaps.iter().zip(&reference.lighting.lightmaps).zip(places) {
        for ((t, r), p) in test.texels.iter().zip(&reference.texels).zip(places) {
            let Some(p) = p else { continue };
            if r[3] >= 0.999 && light(r) > dark && pick(*p) {
                errors.push((light(t) - light(r)).abs() / light(r));
            }
        }
    }
    errors.sort_by(f32::total_cmp);
    errors
}

#[test]
fn the_default_bake_is_within_five_percent_of_a_converged_one_on_open_floor_and_at_contacts() {
    let scene = scene();
    let default = run(&scene, &settings(None, true));
    let samples = Settings::default().bake.texel_samples();
    let reference = run(&scene, &settings(Some(REFERENCE_SAMPLES), false));
    let places = floor_texels(&scene, &reference);
    let open = floor_errors(&default, &reference, &places, |p| distance_to_boxes(p) > CONTACT_M);
    let contact = floor_errors(&default, &reference, &places, |p| {
        (0.0..CONTACT_M).contains(&distance_to_boxes(p)) && distance_to_boxes(p) > 0.0
    });
    let (open_median, contact_median) = (quantile(&open, 0.5), quantile(&contact, 0.5));
    println!(
        "{samples} samples, denoised: {:.2} s, {} rays; converged ({} samples): {:.2} s, {} rays; floor median {:.2}% \
         (p90 {:.2}%) over {} texels, within {CONTACT_M} m of a box median {:.2}% (p90 {:.2}%) over {} texels",
        default.stats.seconds,
        default.stats.rays,
        REFERENCE_SAMPLES,
        reference.stats.seconds,
        reference.stats.rays,
        100.0 * open_median,
        100.0 * quantile(&open, 0.9),
        open.len(),
        100.0 * contact_median,
        100.0 * quantile(&contact, 0.9),
        contact.len()
    );
    assert!(open.len() > 1000 && contact.len() > 100, "{} and {} texels", open.len(), contact.len());
    assert!(open_median < MAX_MEDIAN_ERROR, "open floor: median {open_median}");
    assert!(contact_median < MAX_MEDIAN_ERROR, "contacts: median {contact_median}");
    // The budget, counted in rays rather than seconds (which vary with the machine).
    assert!(
        default.stats.rays * 10 <= reference.stats.rays,
        "{} rays against {}",
        default.stats.rays,
        reference.stats.rays
    );
}
