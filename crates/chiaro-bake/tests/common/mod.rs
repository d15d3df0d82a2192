//! What the bake tests that render share: a scene with its bake applied, as `chiaro
//! render` would load it.

use chiaro_bake::{Silent, bake};
use chiaro_scene::{Scene, Settings, baked};
use std::sync::atomic::AtomicBool;

/// `scene` baked with `settings` and the bake applied, in memory.
pub fn baked_scene(scene: &Scene, settings: &Settings) -> Scene {
    let result = bake(scene, settings, &Silent, &AtomicBool::new(false)).unwrap();
    let mut baked_scene = scene.clone();
    baked::apply(&mut baked_scene, result.lighting, &result.layout.placements(scene)).unwrap();
    baked_scene
}
