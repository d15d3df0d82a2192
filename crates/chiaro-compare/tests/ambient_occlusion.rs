//! Screen-space ambient occlusion (`[ambient_occlusion]`) against the ray-traced
//! reference (chiaro-trace's occlusion, 256 stratified cosine-weighted rays a pixel) on
//! the software device: a sphere on a floor, a corner, thin poles and boxes, on both
//! render paths, at the default quality (and the high one, forward).

mod common;

use chiaro_compare::OcclusionReport;
use chiaro_scene::{AoQuality, CastShadows, RenderPath, Scene, Settings, shapes};
use common::*;
use glam::{Mat4, Vec3};

const SIZE: u32 = 256;

fn ao_settings(path: RenderPath, quality: AoQuality) -> Settings {
    let mut settings = Settings::default();
    settings.render.path = path;
    settings.ambient_occlusion.enabled = true;
    settings.ambient_occlusion.quality = quality;
    settings
}

fn white() -> chiaro_scene::Material {
    chiaro_scene::Material { name: "white".into(), roughness: 1.0, ..Default::default() }
}

/// A 0.5 m sphere resting on a floor, seen from above and aside.
fn sphere_on_floor() -> Scene {
    let mut scene = floor_scene(20.0, Vec3::ZERO, vec![]);
    let at = Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0));
    add_mesh(&mut scene, "sphere", shapes::sphere(0.5, 48, 24), white(), at, CastShadows::On);
    look_from(&mut scene, Vec3::new(1.6, 1.4, 1.8), Vec3::new(0.0, 0.2, 0.0));
    scene
}

/// Two walls and the floor meeting in a corner, seen from inside it.
fn corner() -> Scene {
    let mut scene = floor_scene(20.0, Vec3::ZERO, vec![]);
    add_box(&mut scene, Vec3::new(0.0, 1.0, -0.1), Vec3::new(4.0, 2.0, 0.2), 0.0, CastShadows::On);
    add_box(&mut scene, Vec3::new(-0.1, 1.0, 0.0), Vec3::new(0.2, 2.0, 4.0), 0.0, CastShadows::On);
    look_from(&mut scene, Vec3::new(2.2, 1.5, 2.2), Vec3::new(0.0, 0.3, 0.0));
    scene
}

/// Poles 4 cm thick standing on a floor in front of a wall 1 m behind them.
fn thin_poles() -> Scene {
    let mut scene = floor_scene(20.0, Vec3::ZERO, vec![]);
    for k in 0..4 {
        let x = -0.9 + 0.6 * k as f32;
        add_box(&mut scene, Vec3::new(x, 0.75, 0.0), Vec3::new(0.04, 1.5, 0.04), 0.3, CastShadows::On);
    }
    add_box(&mut scene, Vec3::new(0.0, 1.0, -1.0), Vec3::new(4.0, 2.0, 0.2), 0.0, CastShadows::On);
    look_from(&mut scene, Vec3::new(0.4, 1.2, 2.4), Vec3::new(0.0, 0.5, -0.3));
    scene
}

fn report(scene: &Scene, settings: &Settings) -> OcclusionReport {
    let comparison = compare(scene, settings, SIZE);
    comparison.occlusion.expect("ambient occlusion is on")
}

fn scenes() -> Vec<(&'static str, Scene)> {
    vec![
        ("sphere on a floor", sphere_on_floor()),
        ("corner", corner()),
        ("thin poles", thin_poles()),
        ("boxes", low_boxes(sun(), 1.0)),
    ]
}

#[test]
fn ambient_occlusion_matches_the_traced_reference_on_both_paths() {
    let mut failures = Vec::new();
    let runs = [
        (RenderPath::Forward, AoQuality::Medium),
        (RenderPath::Deferred, AoQuality::Medium),
        (RenderPath::Forward, AoQuality::High),
    ];
    for (path, quality) in runs {
        for (name, scene) in scenes() {
            let r = report(&scene, &ao_settings(path, quality));
            eprintln!(
                "{path:?} {quality:?} {name}: mean {:.4} over {}, occluded {:.4} over {}, p95 {:.4}, signed {:+.4}",
                r.mean_error, r.surfaces, r.mean_error_occluded, r.occluded, r.p95_error, r.mean_signed_error
            );
            assert!(r.occluded > 200, "{name}: the scene must have occluded pixels: {r:?}");
            // The issue asks for 0.03 and 0.06. Occluded pixels are held to 0.05: measured
            // 0.030-0.047 since the denoise fits a plane through its texels and the upsample
            // follows its slope, 0.034-0.054 when both took means, which smeared creases
            // outwards (docs/ambient-occlusion.md).
            if r.mean_error >= 0.03 || r.mean_error_occluded >= 0.05 {
                failures.push(format!(
                    "{path:?} {quality:?} {name}: mean {} over surfaces, {} where occluded",
                    r.mean_error, r.mean_error_occluded
                ));
            }
        }
    }
    assert!(failures.is_empty(), "AO error above 0.03 over surfaces or 0.05 where occluded: {failures:#?}");
}

#[test]
fn an_open_floor_is_not_occluded() {
    // A plane's own samples lie on its hemisphere's edge: none may darken it (a sample off
    // its slice's line did, by up to 5 % at grazing angles).
    let mut scene = floor_scene(20.0, Vec3::ZERO, vec![]);
    look_from(&mut scene, Vec3::new(1.6, 1.4, 1.8), Vec3::new(0.0, 0.2, 0.0));
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let comparison = compare(&scene, &ao_settings(path, AoQuality::Medium), SIZE);
        let r = comparison.occlusion.expect("ambient occlusion is on");
        assert!(r.surfaces > 10_000, "{r:?}");
        assert!(r.mean_error < 0.002 && r.p95_error < 0.005, "{path:?}: {r:?}");
    }
}
