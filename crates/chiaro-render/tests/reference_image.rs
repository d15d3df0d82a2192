//! The demo scene against images kept in the repository, one per render path, with
//! NVIDIA's FLIP metric, which tolerates the small differences between rasterizers but
//! not a changed light. Set CHIARO_UPDATE_REFERENCE=1 to rewrite the images after an
//! intended change. (The two paths' agreement is measured in HDR by deferred_path.rs.)

mod common;

use chiaro_render::{FrameOptions, FrameOutput, View};
use chiaro_scene::demo::{DEMO_LOCAL_LIGHTS, demo_scene};
use chiaro_scene::{RenderPath, Scene, Settings};
use common::{ldr_rgb, mean_flip, renderer};

const SIZE: u32 = 256;
const REFERENCE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/reference/demo_256.png");
const DEFERRED_REFERENCE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/reference/demo_256_deferred.png");
/// Mean FLIP error allowed against the reference.
const MAX_MEAN_FLIP: f32 = 0.005;
/// How far above `MAX_MEAN_FLIP` the control (every spot light moved 2 m) must score:
/// ten times, so that the control decides on any machine, whatever its rasterizer adds
/// (one spot moved 2 m scored between 1.9 and 2.4 times the limit from machine to
/// machine, which tested the machine rather than the metric).
const MOVED_LIGHTS_MARGIN: f32 = 10.0;

fn render_rgb(scene: &Scene) -> Vec<u8> {
    render_path(scene, RenderPath::Forward)
}

fn render_path(scene: &Scene, path: RenderPath) -> Vec<u8> {
    let mut settings = Settings::default();
    settings.render.path = path;
    // The references were rendered with one sample per pixel.
    settings.render.msaa = 1;
    let mut renderer = renderer();
    let view = View::from_camera(scene, 0, SIZE, SIZE);
    let prepared = renderer.prepare(scene).unwrap();
    let frame: FrameOutput = renderer
        .render(scene, &prepared, &view, &settings, FrameOptions { readback: true, ..Default::default() })
        .unwrap();
    ldr_rgb(&frame)
}

fn reference() -> Vec<u8> {
    read_reference(REFERENCE)
}

fn read_reference(path: &str) -> Vec<u8> {
    image::open(path)
        .unwrap_or_else(|e| panic!("{path}: {e} (run with CHIARO_UPDATE_REFERENCE=1 to create it)"))
        .to_rgb8()
        .into_raw()
}

#[test]
fn demo_matches_the_reference_image_on_each_path() {
    for (path, file) in [(RenderPath::Forward, REFERENCE), (RenderPath::Deferred, DEFERRED_REFERENCE)] {
        let rendered = render_path(&demo_scene(DEMO_LOCAL_LIGHTS), path);
        if std::env::var_os("CHIARO_UPDATE_REFERENCE").is_some() {
            image::save_buffer(file, &rendered, SIZE, SIZE, image::ExtendedColorType::Rgb8).unwrap();
        }
        let mean = mean_flip(SIZE, &read_reference(file), &rendered);
        eprintln!("{path:?}: mean FLIP against the reference: {mean}");
        assert!(mean < MAX_MEAN_FLIP, "{path:?}: mean FLIP {mean} against {file}");
    }
}

#[test]
fn the_metric_notices_moved_lights() {
    let mut scene = demo_scene(DEMO_LOCAL_LIGHTS);
    let spots: Vec<_> = scene.lights.iter_mut().filter(|l| l.name.starts_with("spot")).collect();
    assert!(spots.len() >= 3, "the demo's spots");
    for spot in spots {
        spot.world_from_light.w_axis.x += 2.0;
    }
    let mean = mean_flip(SIZE, &reference(), &render_rgb(&scene));
    eprintln!("the spots moved 2 m: mean FLIP {mean}, {:.1} times the limit", mean / MAX_MEAN_FLIP);
    assert!(mean > MOVED_LIGHTS_MARGIN * MAX_MEAN_FLIP, "moving the spot lights scored only {mean}");
}
