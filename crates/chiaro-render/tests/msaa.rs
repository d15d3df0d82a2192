//! MSAA on the forward path: with four samples the edges of a lit floor against the
//! black background take partial coverage, resolved before tone mapping, while pixels
//! inside the floor are shaded exactly as with one sample.

mod common;

use chiaro_render::{FrameOptions, FrameOutput, View};
use chiaro_scene::{RenderPath, Settings};
use common::*;

const SIZE: u32 = 96;

fn render_msaa(msaa: u32) -> FrameOutput {
    let scene = turned_floor_scene();
    let mut settings: Settings = unlit_settings();
    settings.render.path = RenderPath::Forward;
    settings.render.msaa = msaa;
    let mut r = renderer();
    let view = View::from_camera(&scene, 0, SIZE, SIZE);
    let prepared = r.prepare(&scene).expect("prepare");
    let frame = r
        .render(&scene, &prepared, &view, &settings, FrameOptions { readback: true, ..Default::default() })
        .expect("render");
    assert_eq!(frame.plan.msaa, msaa);
    frame
}

#[test]
fn four_samples_soften_edges_and_leave_the_inside_alone() {
    let single = render_msaa(1);
    let multi = render_msaa(4);
    let value = |f: &FrameOutput, x: i32, y: i32| -> f32 {
        let (x, y) = (x.clamp(0, SIZE as i32 - 1), y.clamp(0, SIZE as i32 - 1));
        f.hdr[(y as u32 * SIZE + x as u32) as usize][1]
    };
    let lit: Vec<f32> = single.hdr.iter().map(|p| p[1]).filter(|&v| v > 1e-4).collect();
    assert!(lit.len() > 500, "the floor covers {} pixels", lit.len());
    let darkest_lit = lit.iter().copied().fold(f32::INFINITY, f32::min);
    let mut inside = 0;
    let mut partial = 0;
    for y in 0..SIZE as i32 {
        for x in 0..SIZE as i32 {
            let one = value(&single, x, y);
            let four = value(&multi, x, y);
            let neighbours = [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (1, 1), (-1, 1), (1, -1)];
            let on_edge = neighbours.iter().any(|&(dx, dy)| (value(&single, x + dx, y + dy) > 1e-4) != (one > 1e-4));
            if !on_edge {
                // Fully covered or fully empty: the same shading as one sample.
                assert!((one - four).abs() <= 2e-3 * one.max(1e-4), "({x}, {y}): {one} vs {four}");
                inside += (one > 1e-4) as usize;
            } else if four > 0.1 * darkest_lit && four < 0.9 * darkest_lit {
                partial += 1;
            }
        }
    }
    println!("{inside} pixels inside the floor, {partial} edge pixels partly covered");
    assert!(inside > 400);
    assert!(partial >= 20, "only {partial} edge pixels resolved to partial coverage");
    // One sample never gives partial values: the floor is lit evenly enough.
    assert!(single.hdr.iter().all(|p| p[1] <= 1e-4 || p[1] >= 0.9 * darkest_lit));
}
