//! Virtual shadow maps (`[shadows] technique = "virtual"`) against the ray-traced
//! reference on the software device, atlas against virtual: low boxes and a cube on a
//! floor seen from close by under a sun, a point light and a spot; a point light 40 cm
//! from a wall seen up close; and what the pool does when it is too small.

mod common;

use chiaro_compare::LightComparison;
use chiaro_render::{FrameOptions, FrameOutput, Renderer, View};
use chiaro_scene::{Light, LightShadow, RenderPath, Scene, Settings, ShadowTechnique};
use common::*;
use glam::Vec3;

const SIZE: u32 = 192;

fn settings(technique: ShadowTechnique) -> Settings {
    let mut settings = unlit_settings();
    settings.shadows.technique = technique;
    settings
}

/// The light's comparison with the reference at `edge_band_px`.
fn judged(scene: &Scene, settings: &Settings, edge_band_px: usize) -> LightComparison {
    judged_at(scene, settings, edge_band_px, SIZE)
}

/// The cube and low boxes under `light`, at its default normal bias.
fn boxes(light: Light) -> Scene {
    low_boxes(light, LightShadow::default().normal_bias)
}

#[test]
fn every_light_type_agrees_with_the_reference_at_edge_band_one() {
    for light in [sun(), point(), spot()] {
        let name = light.name.clone();
        let scene = boxes(light);
        for band in [3, 1, 0] {
            let atlas = judged(&scene, &settings(ShadowTechnique::Atlas), band);
            let virt = judged(&scene, &settings(ShadowTechnique::Virtual), band);
            eprintln!("{name}, band {band}: atlas {atlas:?}, virtual {virt:?}");
            if band == 1 {
                assert!(virt.compared > 10_000, "{name}: {virt:?}");
                assert!(share(&virt) < 0.001, "{name}: {virt:?}");
            }
        }
    }
}

#[test]
fn a_point_light_beside_a_wall_seen_up_close_agrees_with_the_reference() {
    let mut scene = point_beside_a_wall();
    let (mut atlas_total, mut virtual_total) = (0, 0);
    // From a metre, then from 20 to 50 cm off the boxes' feet, 384 pixels square: the
    // atlas's cube faces spread a texel over several pixels there.
    for (eye, target) in [
        (Vec3::new(0.3, 0.5, -0.6), Vec3::new(0.0, 0.1, -1.8)),
        (Vec3::new(0.25, 0.15, -1.3), Vec3::new(0.1, 0.0, -1.75)),
        (Vec3::new(-0.3, 0.1, -1.2), Vec3::new(-0.5, 0.0, -1.6)),
        (Vec3::new(0.6, 0.25, -1.0), Vec3::new(0.5, 0.0, -1.5)),
    ] {
        look_from(&mut scene, eye, target);
        for band in [3, 1, 0] {
            let atlas = judged_at(&scene, &settings(ShadowTechnique::Atlas), band, 384);
            let virt = judged_at(&scene, &settings(ShadowTechnique::Virtual), band, 384);
            eprintln!("wall from {eye}, band {band}: atlas {atlas:?}, virtual {virt:?}");
            if band == 1 {
                assert!(share(&virt) < 0.001, "from {eye}: {virt:?}");
                atlas_total += disagreeing(&atlas);
                virtual_total += disagreeing(&virt);
            }
        }
    }
    assert!(virtual_total <= atlas_total, "virtual {virtual_total} against atlas {atlas_total} at band 1");
}

fn render(renderer: &mut Renderer, scene: &Scene, settings: &Settings) -> FrameOutput {
    let prepared = renderer.prepare(scene).unwrap();
    let view = View::from_camera(scene, 0, SIZE, SIZE);
    let options = FrameOptions { readback: true, ..Default::default() };
    renderer.render(scene, &prepared, &view, settings, options).unwrap()
}

#[test]
fn a_still_frame_draws_no_page() {
    for light in [sun(), point(), spot()] {
        for path in [RenderPath::Forward, RenderPath::Deferred] {
            let scene = boxes(light.clone());
            let mut renderer = renderer();
            let mut settings = settings(ShadowTechnique::Virtual);
            settings.render.path = path;
            let first = render(&mut renderer, &scene, &settings);
            let second = render(&mut renderer, &scene, &settings);
            let stats = first.virtual_pages().expect("virtual pages");
            eprintln!(
                "{} {path:?}: first {} pages {stats:?}, second {}",
                light.name, first.shadow_tiles, second.shadow_tiles
            );
            assert!(first.shadow_tiles > 0 && stats.requested > 0);
            assert_eq!(second.shadow_tiles, 0);
            assert_eq!(first.hdr, second.hdr);
            // The lit image is shadowed where the atlas's is: the floor behind the cube.
            let atlas = render(&mut renderer, &scene, &{
                let mut s = settings.clone();
                s.shadows.technique = ShadowTechnique::Atlas;
                s
            });
            let dark = |f: &FrameOutput| f.hdr.iter().filter(|p| p[1] < 0.02).count();
            let (v, a) = (dark(&first), dark(&atlas));
            assert!(v > 1000 && (v as f64 - a as f64).abs() < 0.02 * a as f64, "{path:?}: {v} dark pixels, atlas {a}");
        }
    }
}

#[test]
fn a_full_pool_serves_coarser_pages_and_leaves_no_hole() {
    let mut scene = boxes(sun());
    scene.lights.extend([point(), spot()]);
    let size = 512;
    let shadow_aovs = |pool_mb| {
        let mut settings = settings(ShadowTechnique::Virtual);
        settings.shadows.virtual_pool_mb = pool_mb;
        let mut renderer = renderer();
        let prepared = renderer.prepare(&scene).unwrap();
        let view = View::from_camera(&scene, 0, size, size);
        let options = FrameOptions { readback: true, shadow_aovs: true, ..Default::default() };
        renderer.render(&scene, &prepared, &view, &settings, options).unwrap()
    };
    let (roomy, full) = (shadow_aovs(512), shadow_aovs(16));
    let (roomy_pages, full_pages) = (roomy.virtual_pages().unwrap(), full.virtual_pages().unwrap());
    eprintln!("roomy {roomy_pages:?}, full {full_pages:?}");
    assert_eq!(roomy_pages.dropped, 0);
    assert!(full_pages.dropped > 0 && full_pages.resident <= 196, "{full_pages:?}");
    for (light, (a, b)) in roomy.shadow_aovs.iter().zip(&full.shadow_aovs).enumerate() {
        let shadowed = a.iter().filter(|v| **v < 0.5).count();
        // Where the roomy pool's page says shadow, the coarser page the full pool falls
        // back to says so too, but within a coarse texel of its edges.
        let lost = a.iter().zip(b).filter(|(a, b)| **a < 0.5 && **b >= 0.5).count();
        eprintln!("light {light}: {shadowed} shadowed pixels, {lost} lit with the full pool");
        assert!(shadowed > 1000, "light {light}: {shadowed}");
        assert!((lost as f64) < 0.05 * shadowed as f64, "light {light}: {lost} of {shadowed}");
    }
}
