//! Every change the viewer makes to what it shows, as a value. The panel, the keys and
//! mouse, dropped files, file reloads, finished jobs and the scripted
//! `--exit-after-frames` run all produce these; `Viewer::apply` (apply.rs) is the one
//! place that carries them out.

use crate::camera::{FlyInput, Navigation};
use crate::loader::Loaded;
use crate::reference::Disagreement;
use crate::state::{FrameSample, Selection};
use chiaro_render::{DebugView, GpuFrameTimes};
use chiaro_scene::{Light, Settings};
use std::path::PathBuf;

#[derive(Debug)]
pub enum Action {
    /// Use these settings, if they validate as a file would and the device renders them;
    /// else the error is shown and they are not kept.
    SetSettings(Box<Settings>),
    /// Replace scene light `index` (as the light list edited it).
    EditLight { index: usize, light: Box<Light> },
    /// Switch scene light `index` off (keeping its intensity) or back on.
    SwitchLight { index: usize, on: bool },
    /// What "frame selected" looks at.
    Select(Option<Selection>),
    /// Draw the outlines of rect and disk lights over the view, or not.
    ShowLightShapes(bool),
    /// Pose the scene at this time of its animations (`None`: the rest pose).
    SetTime(Option<f32>),
    /// Run the animations in real time (looping), or stop them where they are.
    Play(bool),
    /// Show this debug view in place of the lit image (`None`: the lit image).
    SetDebugView(Option<DebugView>),

    /// Orbit about the target, or fly.
    SetNavigation(Navigation),
    /// Look through glTF camera `index`.
    SelectCamera(usize),
    /// The glTF camera after the one in use.
    NextCamera,
    /// Back to the view the window opened with.
    ResetView,
    /// Look at the selection, or the whole scene.
    FrameSelected,
    /// A mouse drag in the view, in pixels.
    Drag { dx: f32, dy: f32 },
    /// Mouse wheel steps (positive: closer).
    Zoom(f32),
    /// Fly by `input` (camera axes) for `seconds`.
    Fly { input: FlyInput, fast: bool, seconds: f32 },
    /// A click in the 3D view at these pixels from its top-left corner.
    Pick { x: f32, y: f32 },

    /// Read this scene file on another thread and show it when it loads.
    Open(PathBuf),
    /// Read the open scene's file again (it changed), keeping the camera.
    Reload,
    /// A scene the loader finished reading (or failed to).
    SceneLoaded(Box<Loaded>),
    /// Write the settings to the `--settings` file (or chiaro-view.toml).
    SaveSettings,
    /// Write the glTF with the lights as edited and this view as a camera.
    SaveScene,
    /// Write the 3D view as `chiaro render` would. `fatal`: a failure ends the viewer
    /// with its error (a scripted run) rather than being shown in the panel.
    Screenshot { path: PathBuf, fatal: bool },
    /// Write the whole window as the last frame composed it; a failure ends the viewer.
    ScreenshotWindow(PathBuf),
    /// Trace the reference for the current camera and judge the frame against it.
    Compare,
    /// A comparison finished (or its thread died).
    ComparisonDone(Result<Box<Disagreement>, String>),

    /// What a rendered frame tells the panel.
    FrameRendered(Box<FrameReport>),
    /// The renderer refused the frame (shown, not fatal: the panel can undo the cause).
    FrameFailed(String),
    /// A frame reached the window, `interval_ms` after the one before.
    FrameShown { interval_ms: Option<f64> },
    /// Draw the panel again (something it shows, or egui, changed).
    RefreshPanel,
    /// Close the window; `report`: print the frames shown and their median time first.
    Quit { report: bool },
}

/// What a frame tells the panel.
#[derive(Debug)]
pub struct FrameReport {
    pub shadow_tiles: usize,
    pub lights_shaded: usize,
    /// Per scene light, its atlas tiles in words.
    pub tiles: Vec<String>,
    /// Frames whose GPU timestamps came back since the last report.
    pub gpu_times: Vec<GpuFrameTimes>,
    pub sample: FrameSample,
}
