//! The id pass: each pixel's glTF node and label are those of the surface the image shows
//! there, exactly. Checked against geometry: a pixel whose surface (the position AOV)
//! lies inside a box shows that box's node and label, the floor's elsewhere, and the sky
//! shows NO_NODE and 0; on both paths, with MSAA asked for.

mod common;

use chiaro_render::{FrameOptions, FrameOutput, View};
use chiaro_scene::{CastShadows, RenderPath, Scene, Settings};
use common::*;
use glam::Vec3;

const SIZE: u32 = 128;
const NO_NODE: u32 = u32::MAX;
/// Fewest pixels each box must cover for the check to mean something.
const MIN_PIXELS: usize = 200;

/// A floor (label 0) and two boxes labelled 7 and 9, seen from above and in front, with
/// sky above the horizon.
fn scene() -> Scene {
    let mut scene = floor_scene(6.0, Vec3::ZERO, vec![]);
    look_from(&mut scene, Vec3::new(0.0, 3.0, 6.0), Vec3::new(0.0, 0.5, 0.0));
    add_box(&mut scene, Vec3::new(-1.2, 0.5, 0.0), Vec3::ONE, 0.3, CastShadows::On);
    add_box(&mut scene, Vec3::new(1.2, 0.75, 0.5), Vec3::new(1.0, 1.5, 1.0), -0.4, CastShadows::On);
    let n = scene.instances.len();
    scene.instances[n - 2].label = 7;
    scene.instances[n - 1].label = 9;
    scene
}

fn render(scene: &Scene, path: RenderPath) -> FrameOutput {
    let mut settings = Settings::default();
    settings.render.path = path;
    settings.render.msaa = 4;
    let mut renderer = renderer();
    let view = View::from_camera(scene, 0, SIZE, SIZE);
    let prepared = renderer.prepare(scene).expect("prepare");
    let options = FrameOptions { aovs: true, ids: true, readback: true, ..Default::default() };
    renderer.render(scene, &prepared, &view, &settings, options).expect("render")
}

/// Whether world point `p` lies inside the instance's box, `margin` metres in from its faces.
fn inside(scene: &Scene, instance: usize, p: Vec3, margin: f32) -> bool {
    let local = scene.instances[instance].world_from_local.inverse().transform_point3(p);
    let size = scene.instances[instance].world_from_local.to_scale_rotation_translation().0;
    (local.abs() * size).cmple(size * 0.5 - margin).all()
}

#[test]
fn each_pixel_names_the_node_and_label_it_shows() {
    let scene = scene();
    let boxes = [scene.instances.len() - 2, scene.instances.len() - 1];
    let floor = &scene.instances[0];
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let frame = render(&scene, path);
        let ids = frame.ids.as_ref().expect("ids");
        let aovs = frame.aovs.as_ref().expect("aovs");
        assert_eq!(ids.instance.len(), (SIZE * SIZE) as usize);
        let mut covered = [0usize; 2];
        let (mut sky, mut checked) = (0, 0);
        for i in 0..ids.instance.len() {
            let (node, label) = (ids.instance[i], ids.label[i]);
            let p = Vec3::from_array(aovs.position_ws[i]);
            if !p.is_finite() {
                assert_eq!((node, label), (NO_NODE, 0), "{path:?}: pixel {i} shows no surface");
                sky += 1;
                continue;
            }
            // A surface point on a box lies within 1 cm of that box (positions round); one
            // on the floor lies at y = 0 away from the boxes. Points within 1 cm of both
            // (where a box stands on the floor) are not judged.
            let on_box = boxes.iter().find(|&&b| inside(&scene, b, p, -0.01)).map(|&b| &scene.instances[b]);
            let shown = match on_box {
                Some(b) if p.y > 0.01 => Some(b),
                None if p.y.abs() < 1e-3 => Some(floor),
                _ => None,
            };
            if let Some(shown) = shown {
                assert_eq!(
                    (node, label),
                    (shown.node as u32, shown.label),
                    "{path:?}: pixel {i} at {p} shows {}",
                    shown.name
                );
                checked += 1;
            }
            for (k, &b) in boxes.iter().enumerate() {
                covered[k] += usize::from(node == scene.instances[b].node as u32);
            }
        }
        let surfaces = ids.instance.len() - sky;
        println!("{path:?}: boxes cover {covered:?} pixels, sky {sky}, {checked} of {surfaces} surface pixels checked");
        // Only pixels where a box meets the floor go unjudged.
        assert!(checked * 100 >= surfaces * 95, "{path:?}: {checked} of {surfaces} surface pixels checked");
        assert!(covered.iter().all(|&c| c >= MIN_PIXELS), "{path:?}: boxes cover {covered:?}");
        assert!(sky >= MIN_PIXELS, "{path:?}: sky covers {sky}");
    }
}

#[test]
fn ids_are_not_rendered_unless_asked_for() {
    let scene = scene();
    let mut renderer = renderer();
    let view = View::from_camera(&scene, 0, SIZE, SIZE);
    let prepared = renderer.prepare(&scene).expect("prepare");
    let frame = renderer
        .render(&scene, &prepared, &view, &Settings::default(), FrameOptions { readback: true, ..Default::default() })
        .expect("render");
    assert!(frame.ids.is_none());
    assert!(!frame.graph.passes.contains(&"ids"), "{:?}", frame.graph.passes);
}
