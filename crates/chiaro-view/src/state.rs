//! What the viewer shows and remembers, in small parts: the scene, the settings, the
//! camera (navigation), what the panel shows besides them, the frame statistics and the
//! jobs running on other threads. Panels read it; only `Viewer::apply` changes it.

use crate::ViewerConfig;
use crate::loader::Loader;
use crate::navigation::CameraState;
use crate::pick::Picker;
use crate::reference::{Disagreement, ReferenceJob};
use chiaro_render::{DebugView, FrameOptions, GpuFrameTimes, View};
use chiaro_scene::{Scene, Settings};
use std::collections::{HashMap, VecDeque};
use std::path::PathBuf;

/// Frames of history the timings graph shows.
pub const GRAPH_FRAMES: usize = 120;

/// The open scene and where it came from.
pub struct SceneState {
    pub scene: Scene,
    /// The file the scene came from (`None`: the demo).
    pub path: Option<PathBuf>,
    /// Finds what a click in the view points at.
    pub picker: Picker,
}

impl SceneState {
    /// The window's title for this scene.
    pub fn title(&self) -> String {
        format!("chiaro view: {}", self.path.as_ref().map_or("demo".into(), |p| p.display().to_string()))
    }
}

/// The settings in use and where they are saved.
pub struct SettingsState {
    pub current: Settings,
    /// `--settings`: "Save settings" writes back to it (else chiaro-view.toml).
    pub file: Option<PathBuf>,
    /// `--msaa`, when given: a device that cannot render the count names the flag.
    pub msaa_flag: Option<u32>,
}

impl SettingsState {
    /// Where "Save settings" writes.
    pub fn save_path(&self) -> PathBuf {
        self.file.clone().unwrap_or_else(|| PathBuf::from("chiaro-view.toml"))
    }
}

/// What "frame selected" looks at: a light chosen in the list, or a mesh instance
/// clicked in the view.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Selection {
    Light(usize),
    Object(usize),
}

/// What the light list keeps between frames.
#[derive(Default)]
pub struct LightsState {
    /// Lights switched off, with the intensity they get back when switched on.
    pub switched_off: HashMap<usize, f32>,
    /// What "frame selected" looks at.
    pub selected: Option<Selection>,
    /// Per scene light, the tiles it got this frame, in words.
    pub tiles: Vec<String>,
    /// The view draws no outlines of rect and disk lights.
    pub shapes_hidden: bool,
}

/// What the panel shows besides the settings and the statistics.
#[derive(Default)]
pub struct PanelState {
    pub lights: LightsState,
    /// The outcome of the last save, screenshot or load.
    pub status: Option<String>,
    /// The last rejected edit or failed load, shown until the next accepted one.
    pub error: Option<String>,
    /// Lines describing the reference comparison (running, done, or stale).
    pub reference_lines: Vec<String>,
}

/// Where the animations are: the time shown (`None`: the rest pose) and whether it runs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TimelineState {
    pub time: Option<f32>,
    pub playing: bool,
}

impl TimelineState {
    /// The time after `seconds` more of playing, wrapping at `duration` (the loop of the
    /// longest animation); a zero-length animation stays at 0.
    pub fn advanced(&self, seconds: f32, duration: f32) -> f32 {
        let t = self.time.unwrap_or(0.0) + seconds;
        if duration > 0.0 { t.rem_euclid(duration) } else { 0.0 }
    }
}

/// One frame's times, for the graph.
#[derive(Clone, Debug, Default)]
pub struct FrameSample {
    pub cpu_ms: f64,
    /// GPU time of each pass of the latest frame whose timestamps came back.
    pub passes: Vec<(&'static str, f64)>,
    pub interval_ms: Option<f64>,
}

/// Frames shown and what they cost.
#[derive(Default)]
pub struct FrameStats {
    pub frames: u32,
    /// Wall time between the ends of consecutive frames, ms.
    pub frame_intervals: Vec<f64>,
    /// GPU time of each frame whose timestamps came back, ms.
    pub gpu_frame_ms: Vec<f64>,
    /// Milliseconds per pass of the latest finished frame.
    pub gpu: Option<GpuFrameTimes>,
    pub history: VecDeque<FrameSample>,
    pub shadow_tiles: usize,
    pub lights_shaded: usize,
    /// Frames on which egui drew the panel.
    pub panel_draws: u32,
}

impl FrameStats {
    pub fn record(&mut self, sample: FrameSample) {
        if self.history.len() == GRAPH_FRAMES {
            self.history.pop_front();
        }
        self.history.push_back(sample);
    }

    /// The line a scripted run ends with: frames shown and the median frame time.
    pub fn summary(&self) -> Option<String> {
        let median = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v.get(v.len() / 2).copied()
        };
        let frame = median(self.frame_intervals.clone())?;
        let gpu =
            median(self.gpu_frame_ms.clone()).map_or(String::new(), |g| format!(" (GPU {g:.1} ms by timestamps)"));
        Some(format!(
            "chiaro: {} frames shown (the panel drawn on {}), median {frame:.1} ms a frame{gpu}",
            self.frames, self.panel_draws
        ))
    }
}

/// Work on other threads: scenes being read, the reference being traced.
pub struct Jobs {
    pub loader: Loader,
    pub reference: ReferenceJob,
    /// The last finished comparison.
    pub disagreement: Option<Disagreement>,
}

/// Everything the viewer shows, apart from what lives on the device.
pub struct ViewerState {
    pub scene: SceneState,
    pub settings: SettingsState,
    pub camera: CameraState,
    /// The debug view shown in place of the lit image (`None`: the lit image).
    pub debug: Option<DebugView>,
    pub panel: PanelState,
    pub stats: FrameStats,
    pub jobs: Jobs,
    pub timeline: TimelineState,
}

impl ViewerState {
    pub fn new(config: ViewerConfig) -> ViewerState {
        let ViewerConfig {
            scene, scene_path, settings, settings_file, msaa_flag, camera_key, start_view, time, ..
        } = config;
        let mut loader = Loader::new(config.load_scene);
        loader.watch(&scene);
        ViewerState {
            camera: CameraState::new(start_view, camera_key, &settings),
            scene: SceneState { scene, path: scene_path, picker: Picker::default() },
            settings: SettingsState { current: settings, file: settings_file, msaa_flag },
            debug: config.debug,
            panel: PanelState::default(),
            stats: FrameStats::default(),
            jobs: Jobs { loader, reference: ReferenceJob::default(), disagreement: None },
            timeline: TimelineState { time, playing: false },
        }
    }

    /// The view the camera now shows.
    pub fn current_view(&self) -> View {
        self.camera.current_view(&self.scene.scene)
    }

    /// What the frame renders and reads back for the view shown.
    pub fn frame_options(&self) -> FrameOptions {
        self.debug.map_or_else(FrameOptions::default, DebugView::frame_options)
    }

    /// Whether the last comparison was of another camera than the one shown.
    pub fn comparison_stale(&self) -> bool {
        let shown = self.current_view().world_from_view;
        self.jobs.disagreement.as_ref().is_some_and(|d| d.view.world_from_view != shown)
    }
}
