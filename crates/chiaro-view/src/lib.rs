//! `chiaro view`: a window (winit) with the 3D view and a settings panel (egui on the
//! renderer's own wgpu device). The 3D view is rendered offscreen by the same renderer
//! `chiaro render` uses and copied into the window beside the panel, so a screenshot
//! writes exactly what `chiaro render` writes for the same scene, camera, settings and
//! size, and the window costs little more than the frame itself.
//!
//! In: a `ViewerConfig` (the scene, settings and view the command line chose, and how to
//! read files opened later). The viewer is state (state.rs) and actions (action.rs):
//! panels are functions from the state to actions, and so are keys, drops, reloads and
//! the scripted run; `Viewer::apply` is the one place that changes the state.

mod action;
mod apply;
use chiaro_render::camera_rig as camera;
use chiaro_render::debug_images;
mod frame;
mod gpu;
mod input;
mod light_overlay;
mod light_shapes;
mod loader;
mod navigation;
mod panel;
mod pick;
mod present;
mod reference;
mod save_scene;
mod screenshot;
mod script;
mod state;
mod viewer;

#[cfg(test)]
mod apply_tests;

pub use action::{Action, FrameReport};
pub use camera::Navigation;
pub use panel::controls::{debug_label, parse_debug};
pub use script::Script;
pub use state::{Selection, ViewerState};
pub use viewer::{Viewer, run};

use chiaro_render::{DebugView, View};
use chiaro_scene::{Scene, Settings};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Reads a scene file opened or reloaded in the window (and attaches its bake), on the
/// loader's thread, with the settings in use.
pub type LoadScene = Arc<dyn Fn(&Path, &Settings) -> anyhow::Result<Scene> + Send + Sync>;

/// What the viewer opens with, as plain values.
pub struct ViewerConfig {
    pub scene: Scene,
    /// The file the scene came from (`None`: the demo).
    pub scene_path: Option<PathBuf>,
    /// The settings, with the view's size in render.width and height.
    pub settings: Settings,
    /// `--settings`: where "Save settings" writes back.
    pub settings_file: Option<PathBuf>,
    /// `--msaa`, when given, so that a device's refusal names the flag.
    pub msaa_flag: Option<u32>,
    /// `--camera`: kept while its file is open, for views at a new size.
    pub camera_key: Option<String>,
    /// The view to open with (the chosen camera's, at the view's size).
    pub start_view: View,
    pub debug: Option<DebugView>,
    /// Compare with the reference as soon as the first frame is drawn.
    pub compare_at_start: bool,
    /// `--exit-after-frames` and what to write then.
    pub script: Option<Script>,
    pub load_scene: LoadScene,
    /// `--time`: the moment of the glTF animations to open at (`None`: the rest pose).
    pub time: Option<f32>,
}

impl ViewerConfig {
    /// The viewer of `scene` (the demo, unless `scene_path` is set later) with
    /// `settings` from `start_view`; files opened later are read with no bake.
    pub fn new(scene: Scene, settings: Settings, start_view: View) -> ViewerConfig {
        ViewerConfig {
            scene,
            scene_path: None,
            settings,
            settings_file: None,
            msaa_flag: None,
            camera_key: None,
            start_view,
            debug: None,
            compare_at_start: false,
            script: None,
            load_scene: loader::plain_loader(),
            time: None,
        }
    }
}
