//! Every scene in the repository's tests/assets loads and renders on the GPU: finite
//! radiance, its lights (unshadowed) reach some of what the camera sees, and the AOVs
//! cover the same pixels.

mod common;

use chiaro_render::{FrameOptions, View};
use chiaro_scene::load_gltf;
use common::*;

#[test]
fn every_test_scene_renders() {
    let mut renderer = renderer();
    let settings = unlit_settings();
    for path in asset_scenes() {
        let mut scene = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
        // This checks that lights reach surfaces; shadows have tests of their own. (In
        // ShadowsSpot an opaque BLEND cone encloses the spot and, dithered at alpha 1,
        // shadows everything, as the reference agrees.)
        for light in &mut scene.lights {
            light.shadow.mode = chiaro_scene::ShadowMode::None;
        }
        let view = if scene.cameras.is_empty() {
            View::framing(&scene, 45f32.to_radians(), 128, 128)
        } else {
            View::from_camera(&scene, 0, 128, 128)
        };
        let prepared = renderer.prepare(&scene).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let frame = renderer
            .render(
                &scene,
                &prepared,
                &view,
                &settings,
                FrameOptions { aovs: true, readback: true, ..Default::default() },
            )
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let surfaces = surface_pixels(&frame);
        assert!(surfaces.len() > 100, "{}: only {} pixels covered", path.display(), surfaces.len());
        assert!(frame.hdr.iter().all(|p| p.iter().all(|c| c.is_finite())), "{}: non-finite radiance", path.display());
        let lit = surfaces.iter().filter(|s| s.3.max_element() > 0.0).count();
        assert!(lit * 100 > surfaces.len(), "{}: only {lit} of {} pixels lit", path.display(), surfaces.len());
    }
}
