//! The deferred path against the forward path: the same scene, view and settings give the
//! same image (per-pixel relative difference in the HDR radiance), for every light type,
//! with and without shadows.

mod common;

use chiaro_render::FrameOutput;
use chiaro_scene::{Light, LightKind, RenderPath, Scene, Settings};
use common::*;
use glam::Vec3;

/// Share of pixels whose radiance differs by more than `tolerance` relative (with a small
/// absolute floor for near-black pixels), and the worst pixel.
fn disagreement(a: &FrameOutput, b: &FrameOutput, tolerance: f32) -> (f64, usize, f32) {
    let mut over = 0;
    let mut worst = (0, 0.0f32);
    for (i, (p, q)) in a.hdr.iter().zip(&b.hdr).enumerate() {
        let mut d = 0.0f32;
        for c in 0..3 {
            let scale = p[c].abs().max(q[c].abs()).max(1e-3);
            d = d.max((p[c] - q[c]).abs() / scale);
        }
        if d > tolerance {
            over += 1;
        }
        if d > worst.1 {
            worst = (i, d);
        }
    }
    (over as f64 / a.hdr.len() as f64, worst.0, worst.1)
}

fn both_paths(scene: &Scene, settings: &Settings, size: u32) -> (FrameOutput, FrameOutput) {
    let mut r = renderer();
    let mut forward = settings.clone();
    forward.render.path = RenderPath::Forward;
    let mut deferred = settings.clone();
    deferred.render.path = RenderPath::Deferred;
    (render(&mut r, scene, &forward, size), render(&mut r, scene, &deferred, size))
}

#[test]
fn a_spot_light_on_a_floor_agrees() {
    let spot = Light {
        intensity: 30.0,
        range: Some(8.0),
        ..Light::new(
            LightKind::Spot { inner_cone_rad: 0.3, outer_cone_rad: 0.5 },
            Vec3::new(0.5, 2.0, 0.0),
            Vec3::new(0.2, -1.0, 0.1).normalize(),
        )
    };
    let scene = floor_scene(10.0, Vec3::new(0.0, 6.0, 0.01), vec![spot]);
    let (f, d) = both_paths(&scene, &unlit_settings(), 128);
    let (share, worst, value) = disagreement(&f, &d, 0.02);
    println!("share {share} worst {worst} {value} f {:?} d {:?}", f.hdr[worst], d.hdr[worst]);
    let sum = |o: &FrameOutput| o.hdr.iter().map(|p| p[0] as f64).sum::<f64>();
    println!("sums {} {}", sum(&f), sum(&d));
    assert!(share < 0.005);
}

#[test]
fn a_point_light_on_a_floor_agrees() {
    let scene =
        floor_scene(10.0, Vec3::new(0.0, 6.0, 0.01), vec![point_light(Vec3::new(0.5, 1.0, 0.0), 10.0, Some(3.0))]);
    let (f, d) = both_paths(&scene, &unlit_settings(), 128);
    let (share, worst, value) = disagreement(&f, &d, 0.02);
    println!("{}", d.plan);
    println!("share {share} worst {worst} {value} f {:?} d {:?}", f.hdr[worst], d.hdr[worst]);
    let sum = |o: &FrameOutput| o.hdr.iter().map(|p| p[0] as f64).sum::<f64>();
    println!("sums {} {}", sum(&f), sum(&d));
    assert!(share < 0.005);
}
