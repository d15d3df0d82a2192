//! The one place the viewer's state changes: each `Action` carried out, whoever gave it
//! (the panel, a key, a drop, a reload, a finished job or the scripted run). Work that
//! needs the device (a screenshot, a comparison, preparing a new scene) is done here too
//! when the window is open; without one, such actions report that or do nothing.

use crate::action::{Action, FrameReport};
use crate::loader::Loaded;
use crate::reference::{Disagreement, ReferenceJob};
use crate::save_scene;
use crate::viewer::Viewer;
use chiaro_render::{AovView, DebugView};
use chiaro_scene::settings::EnvironmentSource;
use chiaro_scene::{Light, Settings};
use std::path::PathBuf;

/// How a frame the renderer refused is reported in the panel.
pub const FRAME_FAILED: &str = "frame not rendered";

impl Viewer {
    /// Carries out `action`.
    pub fn apply(&mut self, action: Action) {
        // Moving the camera leaves the panel as it is; everything else shows in it.
        let redraws_panel = !matches!(
            action,
            Action::Drag { .. }
                | Action::Zoom(_)
                | Action::Fly { .. }
                | Action::FrameRendered(_)
                | Action::FrameFailed(_)
                | Action::FrameShown { .. }
        );
        match action {
            Action::SetSettings(settings) => self.set_settings(*settings),
            Action::EditLight { index, light } => self.edit_light(index, *light),
            Action::SwitchLight { index, on } => self.switch_light(index, on),
            Action::Select(selection) => self.state.panel.lights.selected = selection,
            Action::ShowLightShapes(shown) => self.state.panel.lights.shapes_hidden = !shown,
            Action::SetDebugView(debug) => self.state.debug = debug,
            Action::SetTime(time) => self.set_time(time),
            Action::Play(playing) => {
                self.state.timeline.playing = playing && self.state.scene.scene.animation_duration().is_some();
            }
            action @ (Action::SetNavigation(_)
            | Action::SelectCamera(_)
            | Action::NextCamera
            | Action::ResetView
            | Action::FrameSelected
            | Action::Drag { .. }
            | Action::Zoom(_)
            | Action::Fly { .. }
            | Action::Pick { .. }) => self.move_camera(action),
            Action::Open(path) => self.state.jobs.loader.open(path, &self.state.settings.current, false),
            Action::Reload => {
                if let Some(path) = self.state.scene.path.clone() {
                    self.state.jobs.loader.open(path, &self.state.settings.current, true);
                }
            }
            Action::SceneLoaded(loaded) => self.show_scene(*loaded),
            Action::SaveSettings => self.save_settings(),
            Action::SaveScene => self.save_scene(),
            Action::Screenshot { path, fatal } => self.write_screenshot(path, fatal),
            Action::ScreenshotWindow(path) => {
                if let Err(e) = self.screenshot_window(&path) {
                    self.fail_with(e);
                }
            }
            Action::Compare => self.start_comparison(),
            Action::ComparisonDone(Ok(done)) => self.show_disagreement(*done),
            Action::ComparisonDone(Err(e)) => self.state.panel.reference_lines = vec![e],
            Action::FrameRendered(report) => self.take_report(*report),
            Action::FrameFailed(message) => {
                if self.state.panel.error.as_ref() != Some(&message) {
                    self.state.panel.error = Some(message);
                    self.panel.dirty = true;
                }
            }
            Action::FrameShown { interval_ms } => self.frame_shown(interval_ms),
            Action::RefreshPanel => {}
            Action::Quit { report } => {
                if report && let Some(line) = self.state.stats.summary() {
                    eprintln!("{line}");
                }
                self.quit = true;
            }
        }
        self.panel.dirty |= redraws_panel;
    }

    /// Ends the viewer with `error` (the first one, if several come).
    pub(crate) fn fail_with(&mut self, error: anyhow::Error) {
        self.failure.get_or_insert(error);
        self.quit = true;
    }

    /// Keeps `settings` if they validate and the device renders them; else shows why not.
    fn set_settings(&mut self, settings: Settings) {
        let checked = settings.validate().map_err(|e| e.to_string()).and_then(|()| match &self.gpu {
            Some(gpu) => {
                let msaa_flag = self.state.settings.msaa_flag;
                chiaro_io::device::check_msaa(&gpu.renderer.ctx, &settings, msaa_flag, None)
                    .map_err(|e| format!("{e:#}"))
            }
            None => Ok(()),
        });
        // A newly named environment image is checked from its header before it is kept.
        let checked = checked.and_then(|()| match &settings.environment.source {
            EnvironmentSource::File(path)
                if settings.environment.source != self.state.settings.current.environment.source =>
            {
                chiaro_scene::environment::check_image(path).map(|_| ()).map_err(|e| e.to_string())
            }
            _ => Ok(()),
        });
        if let Err(e) = checked {
            self.state.panel.error = Some(e);
            return;
        }
        if settings.scene.variant != self.state.settings.current.scene.variant
            && let Err(e) = self.select_variant(settings.scene.variant.as_deref())
        {
            self.state.panel.error = Some(e);
            return;
        }
        self.state.settings.current = settings;
        self.state.panel.error = None;
        self.follow_view_size();
    }

    /// Follows render.width and height (a new view texture and window size) and
    /// camera.auto_yfov_deg.
    fn follow_view_size(&mut self) {
        let state = &mut self.state;
        match state.camera.follow_settings(&state.scene.scene, &state.settings.current) {
            Ok(false) => {}
            Ok(true) => {
                let (w, h) = state.camera.view_size();
                if let Some(gpu) = &mut self.gpu {
                    gpu.fit_view(w, h);
                }
            }
            Err(e) => state.panel.error = Some(format!("{e:#}")),
        }
    }

    fn edit_light(&mut self, index: usize, light: Light) {
        if let Some(slot) = self.state.scene.scene.lights.get_mut(index) {
            *slot = light;
        }
    }

    fn switch_light(&mut self, index: usize, on: bool) {
        let Some(light) = self.state.scene.scene.lights.get_mut(index) else { return };
        let switched_off = &mut self.state.panel.lights.switched_off;
        if on {
            light.intensity = switched_off.remove(&index).unwrap_or(1.0);
        } else if let std::collections::hash_map::Entry::Vacant(off) = switched_off.entry(index) {
            off.insert(light.intensity);
            light.intensity = 0.0;
        }
    }

    /// Poses the scene at `time` and uploads it again (posed meshes are new geometry; the
    /// shadow cache redraws the tiles whose casters moved).
    /// Gives the scene the materials of variant `name` (None: the file's) and uploads it
    /// again.
    fn select_variant(&mut self, name: Option<&str>) -> Result<(), String> {
        let scene = &mut self.state.scene.scene;
        scene.select_variant(name).map_err(|e| format!("scene.variant: {e}"))?;
        if let Some(gpu) = self.gpu.as_mut() {
            gpu.prepared = gpu.renderer.prepare(scene).map_err(|e| format!("scene.variant: {e}"))?;
        }
        Ok(())
    }

    fn set_time(&mut self, time: Option<f32>) {
        let state = &mut self.state;
        if let Err(e) = state.scene.scene.pose(time) {
            state.panel.error = Some(format!("time: {e}"));
            return;
        }
        state.timeline.time = time;
        state.scene.picker.reset();
        if let Some(gpu) = self.gpu.as_mut() {
            match gpu.renderer.prepare(&state.scene.scene) {
                Ok(prepared) => gpu.prepared = prepared,
                Err(e) => state.panel.error = Some(format!("time: {e}")),
            }
        }
    }

    fn move_camera(&mut self, action: Action) {
        let (camera, scene) = (&mut self.state.camera, &self.state.scene.scene);
        match action {
            Action::SetNavigation(navigation) => camera.navigation = navigation,
            Action::SelectCamera(index) => camera.use_camera(scene, Some(index)),
            Action::NextCamera => {
                if let Some(next) = camera.next_camera(scene) {
                    camera.use_camera(scene, Some(next));
                }
            }
            Action::ResetView => camera.use_camera(scene, None),
            Action::FrameSelected => camera.frame_selected(scene, self.state.panel.lights.selected),
            Action::Drag { dx, dy } => {
                let navigation = camera.navigation;
                camera.rig(scene).drag(navigation, dx, dy);
            }
            Action::Zoom(steps) => camera.rig(scene).zoom(steps),
            Action::Fly { input, fast, seconds } => camera.fly(scene, input, fast, seconds),
            Action::Pick { x, y } => {
                let view = camera.current_view(scene);
                let picked = self.state.scene.picker.pick(scene, &view, x, y);
                self.state.panel.lights.selected = picked.map(crate::state::Selection::Object);
            }
            _ => debug_assert!(false, "not a camera action"),
        }
    }

    /// A scene read by the loader: shown if it loads, else its error in the panel.
    fn show_scene(&mut self, loaded: Loaded) {
        let mut scene = match loaded.scene {
            Ok(scene) => scene,
            Err(e) => {
                self.state.panel.error = Some(format!("{e:#}"));
                return;
            }
        };
        // A new scene opens at the time shown; it runs on only if it has animations.
        scene.pose(self.state.timeline.time).expect("the timeline holds finite times");
        self.state.timeline.playing &= scene.animation_duration().is_some();
        let Some(gpu) = self.gpu.as_mut() else { return };
        let prepared = match gpu.renderer.prepare(&scene) {
            Ok(p) => p,
            Err(e) => {
                self.state.panel.error = Some(format!("{}: {e}", loaded.path.display()));
                return;
            }
        };
        gpu.prepared = prepared;
        gpu.debug_textures.clear();
        let state = &mut self.state;
        let old = std::mem::replace(&mut state.scene.scene, scene);
        state.scene.picker.reset();
        // The light list shows the file's lights as they now are.
        state.panel.lights = Default::default();
        // A comparison under way was of the old scene.
        state.jobs.reference = ReferenceJob::default();
        state.panel.reference_lines.clear();
        if !loaded.reload {
            // --camera named a camera of the first file.
            state.camera.camera_key = None;
        }
        state.jobs.loader.watch(&state.scene.scene);
        state.jobs.disagreement = None;
        state.panel.error = None;
        let status = format!("{} {}", if loaded.reload { "reloaded" } else { "opened" }, loaded.path.display());
        eprintln!("chiaro: {status}");
        state.panel.status = Some(status);
        let lights = state.scene.scene.lights.len();
        if matches!(state.debug, Some(DebugView::Aov(AovView::Shadow(i))) if i >= lights) {
            state.debug = None;
        }
        let keep_camera = loaded.reload && old.cameras.len() == state.scene.scene.cameras.len();
        state.scene.path = Some(loaded.path);
        gpu.window.set_title(&state.scene.title());
        if !keep_camera && let Err(e) = state.camera.open_scene(&state.scene.scene, &state.settings.current) {
            state.panel.error = Some(format!("{e:#}"));
        }
    }

    fn save_settings(&mut self) {
        let path = self.state.settings.save_path();
        self.state.panel.status = Some(match save_scene::save_settings(&path, &self.state.settings.current) {
            Ok(()) => format!("saved {}", path.display()),
            Err(e) => format!("not saved: {e:#}"),
        });
    }

    fn save_scene(&mut self) {
        let state = &self.state;
        let status = match &state.scene.path {
            None => "not saved: the demo scene has no file".to_string(),
            Some(source) => {
                let target = save_scene::saved_path(source);
                match save_scene::save_scene(source, &state.scene.scene, &state.current_view(), &target) {
                    Ok(()) => format!(
                        "saved {}: chiaro render it with --camera \"{}\"",
                        target.display(),
                        save_scene::VIEW_CAMERA
                    ),
                    Err(e) => format!("not saved: {e:#}"),
                }
            }
        };
        self.state.panel.status = Some(status);
    }

    fn write_screenshot(&mut self, path: PathBuf, fatal: bool) {
        match self.screenshot(&path) {
            Ok(()) if !fatal => self.state.panel.status = Some(format!("wrote {}", path.display())),
            Ok(()) => {}
            Err(e) if fatal => self.fail_with(e),
            Err(e) => self.state.panel.status = Some(format!("no screenshot: {e:#}")),
        }
    }

    /// Renders the frame of the current camera and compares it with the reference on
    /// another thread.
    fn start_comparison(&mut self) {
        let view = self.state.current_view();
        let Some(gpu) = self.gpu.as_mut() else { return };
        let state = &mut self.state;
        let (scene, settings) = (&state.scene.scene, &state.settings.current);
        match chiaro_compare::render_shadows(&mut gpu.renderer, scene, &gpu.prepared, &view, settings) {
            Ok(rendered) => {
                state.jobs.reference.start(scene, view, settings, rendered);
                state.panel.reference_lines = vec!["tracing the reference for this camera...".into()];
            }
            Err(e) => state.panel.error = Some(format!("comparison: {e}")),
        }
    }

    /// A finished comparison: its lines in the panel, its image in the view.
    fn show_disagreement(&mut self, done: Disagreement) {
        let mut lines = done.lines.clone();
        lines.push(format!("traced in {:.1} s", done.seconds));
        self.state.panel.reference_lines = lines;
        self.state.jobs.disagreement = Some(done);
        if let Some(gpu) = self.gpu.as_mut() {
            gpu.debug_textures.clear();
        }
    }

    /// What a frame told: the panel's numbers, and a refused frame's error cleared.
    fn take_report(&mut self, report: FrameReport) {
        let state = &mut self.state;
        if state.panel.error.as_deref().is_some_and(|e| e.starts_with(FRAME_FAILED)) {
            state.panel.error = None;
            self.panel.dirty = true;
        }
        let stats = &mut state.stats;
        stats.shadow_tiles = report.shadow_tiles;
        stats.lights_shaded = report.lights_shaded;
        state.panel.lights.tiles = report.tiles;
        stats.gpu_frame_ms.extend(report.gpu_times.iter().map(|t| t.total_ms()));
        if let Some(latest) = report.gpu_times.into_iter().last() {
            stats.gpu = Some(latest);
        }
        let passes = stats.gpu.as_ref().map(|g| g.passes.clone()).unwrap_or_default();
        stats.record(crate::state::FrameSample { passes, ..report.sample });
    }

    fn frame_shown(&mut self, interval_ms: Option<f64>) {
        let stats = &mut self.state.stats;
        stats.frames += 1;
        if let Some(ms) = interval_ms {
            stats.frame_intervals.push(ms);
        }
        if let Some(sample) = stats.history.back_mut() {
            sample.interval_ms = interval_ms;
        }
    }
}
