//! The viewer's side panel: camera controls, the settings (settings_panel), the light
//! list (lights_panel), the debug views, and the frame's timings with a small graph.

use super::camera::Navigation;
use super::lights_panel::LightsState;
use chiaro_render::{DebugView, GpuFrameTimes};
use std::collections::VecDeque;

/// The name of the 3D view's debug view in the panel ("none" for the lit image).
pub fn debug_label(debug: Option<DebugView>) -> String {
    debug.map_or_else(|| "none".into(), DebugView::label)
}

/// Parses the viewer's `--debug`: a debug view's name, or `none`.
pub fn parse_debug(text: &str) -> Result<Option<DebugView>, String> {
    if text == "none" {
        return Ok(None);
    }
    DebugView::parse(text).map(Some).map_err(|e| e.replace("(one of: ", "(one of: none, "))
}

/// The panel's choices: none, then every view, with one shadow AOV per light.
pub fn debug_choices(lights: usize) -> Vec<Option<DebugView>> {
    std::iter::once(None).chain(DebugView::all(lights).into_iter().map(Some)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn debug_views_parse_from_their_names() {
        assert_eq!(parse_debug("none"), Ok(None));
        for d in DebugView::all(0) {
            assert_eq!(parse_debug(d.cli_name().expect("named")), Ok(Some(d)));
        }
        let error = parse_debug("wireframe").unwrap_err();
        assert!(error.contains("'wireframe'") && error.contains("none, cascades, "), "{error}");
    }
}

/// Frames of history the timings graph shows.
pub const GRAPH_FRAMES: usize = 120;

/// One frame's times, for the graph.
#[derive(Clone, Debug, Default)]
pub struct FrameSample {
    pub cpu_ms: f64,
    /// GPU time of each pass of the latest frame whose timestamps came back.
    pub passes: Vec<(&'static str, f64)>,
    pub interval_ms: Option<f64>,
}

/// What the panel shows besides the settings.
#[derive(Default)]
pub struct PanelState {
    pub debug: Option<DebugView>,
    pub navigation: Navigation,
    pub lights: LightsState,
    /// "Save settings" was pressed this frame.
    pub save_requested: bool,
    /// "Save scene" was pressed this frame.
    pub save_scene_requested: bool,
    /// "Compare with the reference" was pressed this frame.
    pub compare_requested: bool,
    /// "Frame selected" was pressed this frame.
    pub frame_requested: bool,
    /// A glTF camera chosen this frame (by index), or "reset view" (`Some(None)`).
    pub camera_request: Option<Option<usize>>,
    /// A file to open, typed into the panel.
    pub open_path: String,
    pub open_requested: bool,
    /// The outcome of the last save, screenshot or load.
    pub status: Option<String>,
    /// The last rejected edit or failed load, shown until the next accepted one.
    pub error: Option<String>,
    /// Milliseconds per pass of the latest finished frame.
    pub gpu: Option<GpuFrameTimes>,
    pub history: VecDeque<FrameSample>,
    pub shadow_tiles: usize,
    pub lights_shaded: usize,
    /// Lines describing the reference comparison (running, done, or stale).
    pub reference_lines: Vec<String>,
}

impl PanelState {
    pub fn record(&mut self, sample: FrameSample) {
        if self.history.len() == GRAPH_FRAMES {
            self.history.pop_front();
        }
        self.history.push_back(sample);
    }
}

pub const HELP: &str = "Mouse: drag in the view to orbit (fly: to look around), wheel to zoom. \
    Keys: V switches orbit and fly; W/A/S/D move and Q/E go down and up when flying (Shift: faster); \
    F frames the selection (click an object, or a light's \"select\"; else the whole scene); R resets the view; C steps through the glTF \
    cameras; P writes a screenshot (chiaro-view.png); Escape quits. Drop a .gltf or .glb on the \
    window to open it; the open scene reloads when its files change. Settings apply to the next frame.";

/// The camera rows: navigation, frame selected, reset view and one button per glTF camera.
pub fn cameras_panel(ui: &mut egui::Ui, cameras: &[String], state: &mut PanelState) {
    ui.horizontal(|ui| {
        for n in [Navigation::Orbit, Navigation::Fly] {
            ui.selectable_value(&mut state.navigation, n, n.name());
        }
        if ui.button("frame selected").clicked() {
            state.frame_requested = true;
        }
    });
    ui.horizontal_wrapped(|ui| {
        if ui.button("reset view").clicked() {
            state.camera_request = Some(None);
        }
        for (i, name) in cameras.iter().enumerate() {
            let label = if name.is_empty() { format!("camera {i}") } else { name.clone() };
            if ui.button(label).clicked() {
                state.camera_request = Some(Some(i));
            }
        }
    });
}

/// The scene row: a path to open (dropping a file on the window does the same).
pub fn open_panel(ui: &mut egui::Ui, state: &mut PanelState, loading: Option<&std::path::Path>) {
    ui.horizontal(|ui| {
        let edit =
            ui.add(egui::TextEdit::singleline(&mut state.open_path).hint_text("scene.gltf").desired_width(180.0));
        let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if ui.button("open").clicked() || enter {
            state.open_requested = !state.open_path.trim().is_empty();
        }
    });
    if let Some(path) = loading {
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label(format!("loading {}", path.display()));
        });
    }
}

/// The debug view choice and the reference comparison.
pub fn debug_panel(ui: &mut egui::Ui, state: &mut PanelState, lights: usize, comparing: bool) {
    egui::ComboBox::from_label("debug view").selected_text(debug_label(state.debug)).show_ui(ui, |ui| {
        for d in debug_choices(lights) {
            ui.selectable_value(&mut state.debug, d, debug_label(d));
        }
    });
    if state.debug == Some(DebugView::Reference) {
        ui.horizontal(|ui| {
            if ui.add_enabled(!comparing, egui::Button::new("compare with the reference")).clicked() {
                state.compare_requested = true;
            }
            if comparing {
                ui.spinner();
            }
        });
        ui.label("red: false shadow, blue: missed shadow");
        for line in &state.reference_lines {
            ui.label(line);
        }
    }
}

/// Timings of the latest frames: numbers, and a graph of each pass's GPU time (stacked)
/// under the whole frame's interval and the CPU time.
pub fn timings_panel(ui: &mut egui::Ui, state: &PanelState) {
    let last = state.history.back().cloned().unwrap_or_default();
    let mut intervals: Vec<f64> = state.history.iter().filter_map(|s| s.interval_ms).collect();
    intervals.sort_by(f64::total_cmp);
    if let Some(median) = intervals.get(intervals.len() / 2) {
        ui.label(format!("frame {median:.1} ms ({:.1} fps), median of the graph", 1000.0 / median));
    }
    ui.colored_label(CPU_COLOR, format!("CPU {:.1} ms to plan and record", last.cpu_ms));
    ui.label(format!("{} lights shaded, {} shadow tiles drawn", state.lights_shaded, state.shadow_tiles));
    if let Some(gpu) = &state.gpu {
        ui.label(format!("GPU {:.1} ms (timestamps)", gpu.total_ms()));
        for (k, (pass, ms)) in gpu.passes.iter().enumerate() {
            ui.colored_label(pass_color(k), format!("  {pass}: {ms:.2} ms"));
        }
    }
    graph(ui, state);
}

const CPU_COLOR: egui::Color32 = egui::Color32::from_rgb(120, 200, 255);
const FRAME_COLOR: egui::Color32 = egui::Color32::from_rgb(220, 220, 220);
const PASS_COLORS: [egui::Color32; 6] = [
    egui::Color32::from_rgb(230, 120, 60),
    egui::Color32::from_rgb(90, 170, 90),
    egui::Color32::from_rgb(200, 170, 60),
    egui::Color32::from_rgb(170, 110, 200),
    egui::Color32::from_rgb(80, 150, 200),
    egui::Color32::from_rgb(200, 90, 120),
];

/// The colour of the frame's `k`th pass in the graph and its legend.
fn pass_color(k: usize) -> egui::Color32 {
    PASS_COLORS[k % PASS_COLORS.len()]
}

fn graph(ui: &mut egui::Ui, state: &PanelState) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(ui.available_width(), 80.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, egui::Color32::from_gray(20));
    let top = state
        .history
        .iter()
        .flat_map(|s| [Some(s.cpu_ms), Some(s.passes.iter().map(|p| p.1).sum()), s.interval_ms])
        .flatten()
        .fold(1.0f64, f64::max);
    let column = rect.width() / GRAPH_FRAMES as f32;
    let x_of = |i: usize| rect.left() + column * i as f32;
    let y_of = |ms: f64| rect.bottom() - rect.height() * (ms / top) as f32;
    for (i, sample) in state.history.iter().enumerate() {
        let mut below = 0.0;
        for (k, (_, ms)) in sample.passes.iter().enumerate() {
            let bar = egui::Rect::from_min_max(
                egui::pos2(x_of(i), y_of(below + ms)),
                egui::pos2(x_of(i) + column.max(1.0), y_of(below)),
            );
            painter.rect_filled(bar, 0.0, pass_color(k));
            below += ms;
        }
    }
    let line = |value: &dyn Fn(&FrameSample) -> Option<f64>, color| {
        let points: Vec<egui::Pos2> = state
            .history
            .iter()
            .enumerate()
            .filter_map(|(i, s)| value(s).map(|ms| egui::pos2(x_of(i) + 0.5 * column, y_of(ms))))
            .collect();
        painter.add(egui::Shape::line(points, egui::Stroke::new(1.0, color)));
    };
    line(&|s| s.interval_ms, FRAME_COLOR);
    line(&|s| Some(s.cpu_ms), CPU_COLOR);
    painter.text(
        rect.left_top() + egui::vec2(4.0, 2.0),
        egui::Align2::LEFT_TOP,
        format!("{top:.0} ms"),
        egui::FontId::monospace(10.0),
        egui::Color32::GRAY,
    );
    ui.horizontal(|ui| {
        ui.colored_label(FRAME_COLOR, "frame interval");
        ui.label("over GPU passes (stacked);");
        ui.colored_label(CPU_COLOR, "CPU");
    });
}
