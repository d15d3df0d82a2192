//! Antialiasing on the deferred path: its G-buffer has one sample, so at its defaults it
//! smooths edges with FXAA, and they come out close to the forward path's 4x MSAA ones,
//! while pixels away from edges keep their shading.

mod common;

use chiaro_render::{FrameOptions, FrameOutput, View};
use chiaro_scene::{DeferredAntialiasing, RenderPath, Settings};
use common::*;

const SIZE: u32 = 96;

fn render(path: RenderPath, msaa: u32, antialiasing: DeferredAntialiasing, aovs: bool) -> FrameOutput {
    let scene = turned_floor_scene();
    let mut settings: Settings = unlit_settings();
    settings.render.path = path;
    settings.render.msaa = msaa;
    settings.render.deferred_antialiasing = antialiasing;
    let mut r = renderer();
    let view = View::from_camera(&scene, 0, SIZE, SIZE);
    let prepared = r.prepare(&scene).expect("prepare");
    r.render(&scene, &prepared, &view, &settings, FrameOptions { readback: true, aovs, ..Default::default() })
        .expect("render")
}

fn green(f: &FrameOutput, x: i32, y: i32) -> f32 {
    let (x, y) = (x.clamp(0, SIZE as i32 - 1), y.clamp(0, SIZE as i32 - 1));
    f.hdr[(y as u32 * SIZE + x as u32) as usize][1]
}

#[test]
fn deferred_edges_are_smoothed_like_the_forward_paths_msaa() {
    let defaults = Settings::default();
    assert_eq!(defaults.render.deferred_antialiasing, DeferredAntialiasing::Fxaa);
    let forward = render(RenderPath::Forward, 4, DeferredAntialiasing::Fxaa, false);
    let deferred = render(RenderPath::Deferred, 4, DeferredAntialiasing::Fxaa, false);
    let aliased = render(RenderPath::Deferred, 4, DeferredAntialiasing::None, false);
    assert!(deferred.graph.passes.contains(&"fxaa"), "{:?}", deferred.graph.passes);
    assert!(!aliased.graph.passes.contains(&"fxaa"));
    let lit = aliased.hdr.iter().map(|p| p[1]).filter(|&v| v > 1e-4).fold(f32::INFINITY, f32::min);
    let (mut edge, mut inside, mut partial, mut partial_aliased, mut partial_msaa) = (0, 0, 0, 0, 0);
    let (mut error, mut error_aliased) = (0.0f64, 0.0f64);
    for y in 0..SIZE as i32 {
        for x in 0..SIZE as i32 {
            let one = green(&aliased, x, y);
            let neighbours = [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (1, 1), (-1, 1), (1, -1)];
            let on_edge = neighbours.iter().any(|&(dx, dy)| (green(&aliased, x + dx, y + dy) > 1e-4) != (one > 1e-4));
            let smoothed = green(&deferred, x, y);
            if !on_edge {
                // Away from edges the filter finds no contrast and leaves the pixel.
                assert!((smoothed - one).abs() <= 1e-3 * one.max(1e-4), "({x}, {y}): {one} vs {smoothed}");
                inside += (one > 1e-4) as usize;
                continue;
            }
            edge += 1;
            let reference = green(&forward, x, y);
            error += (smoothed - reference).abs() as f64;
            error_aliased += (one - reference).abs() as f64;
            let is_partial = |v: f32| v > 0.1 * lit && v < 0.9 * lit;
            partial += is_partial(smoothed) as usize;
            partial_aliased += is_partial(one) as usize;
            partial_msaa += is_partial(reference) as usize;
        }
    }
    let (error, error_aliased) = (error / edge as f64 / lit as f64, error_aliased / edge as f64 / lit as f64);
    println!(
        "{inside} pixels inside, {edge} on edges (either side): partly lit {partial} with FXAA, {partial_aliased} \
         without, {partial_msaa} with forward 4x MSAA; mean difference from forward 4x MSAA {:.1}% of the lit level \
         with FXAA, {:.1}% without",
        error * 100.0,
        error_aliased * 100.0
    );
    assert!(inside > 400 && edge > 100, "{inside} {edge}");
    assert_eq!(partial_aliased, 0, "one sample gives no partial coverage");
    // As many edge pixels take partial values as under MSAA (the others lie wholly on
    // either side of the edge), and they are nearer MSAA's values than one sample's.
    assert!(partial * 5 >= partial_msaa * 4, "{partial} edge pixels smoothed, {partial_msaa} by MSAA");
    assert!(error < 0.5 * error_aliased, "FXAA edges {error} against forward MSAA; aliased {error_aliased}");
}

#[test]
fn fxaa_runs_where_the_forward_path_would_have_msaa() {
    for (msaa, antialiasing, aovs, expected) in [
        (4, DeferredAntialiasing::Fxaa, false, true),
        (1, DeferredAntialiasing::Fxaa, false, false),
        (4, DeferredAntialiasing::None, false, false),
        // AOVs are pixel-exact on both paths: no MSAA, no FXAA.
        (4, DeferredAntialiasing::Fxaa, true, false),
    ] {
        let frame = render(RenderPath::Deferred, msaa, antialiasing, aovs);
        assert_eq!(frame.plan.fxaa, expected, "msaa {msaa}, {antialiasing:?}, aovs {aovs}");
        assert_eq!(frame.graph.passes.contains(&"fxaa"), expected, "{:?}", frame.graph.passes);
    }
    assert!(!render(RenderPath::Forward, 4, DeferredAntialiasing::Fxaa, false).plan.fxaa);
}
