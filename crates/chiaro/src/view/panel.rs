//! The viewer's side panel: the settings `chiaro render` reads (one `Settings`, edited in
//! place and validated as a file would be), the frame's timings, and the controls.

use chiaro_render::GpuFrameTimes;
use chiaro_scene::{CascadeBlend, LightCulling, RenderPath, Settings};

/// What the panel shows besides the settings.
#[derive(Default)]
pub struct PanelState {
    /// The last rejected edit, shown until the next one is accepted.
    pub error: Option<String>,
    /// Milliseconds per pass of the latest finished frame, and its total.
    pub gpu: Option<GpuFrameTimes>,
    pub cpu_frame_ms: f64,
    pub shadow_tiles: usize,
    pub lights_shaded: usize,
}

pub const HELP: &str = "Drag with the left button to orbit, wheel to zoom. Settings apply to the next frame.";

const FILTERS: [&str; 4] = ["pcf2x2", "tent3x3", "tent5x5", "tent7x7"];

/// Draws the panel; returns whether the settings changed (and are valid).
pub fn settings_panel(ui: &mut egui::Ui, settings: &mut Settings, state: &mut PanelState) -> bool {
    let before = settings.clone();
    let mut edited = settings.clone();
    ui.heading("Render");
    egui::ComboBox::from_label("path").selected_text(format!("{:?}", edited.render.path).to_lowercase()).show_ui(
        ui,
        |ui| {
            ui.selectable_value(&mut edited.render.path, RenderPath::Forward, "forward");
            ui.selectable_value(&mut edited.render.path, RenderPath::Deferred, "deferred");
        },
    );
    egui::ComboBox::from_label("msaa").selected_text(edited.render.msaa.to_string()).show_ui(ui, |ui| {
        for n in [1, 2, 4, 8] {
            ui.selectable_value(&mut edited.render.msaa, n, n.to_string());
        }
    });
    ui.add(egui::Slider::new(&mut edited.render.exposure_ev100, -10.0..=20.0).text("exposure EV100"));
    ui.heading("Lights");
    egui::ComboBox::from_label("culling").selected_text(culling_name(edited.lights.culling)).show_ui(ui, |ui| {
        for c in [LightCulling::Clustered, LightCulling::PerObject, LightCulling::None] {
            ui.selectable_value(&mut edited.lights.culling, c, culling_name(c));
        }
    });
    ui.heading("Shadows");
    ui.add(egui::Slider::new(&mut edited.shadows.max_distance, 1.0..=500.0).logarithmic(true).text("max distance"));
    ui.add(egui::Slider::new(&mut edited.shadows.distance_fade, 0.001..=1.0).text("distance fade"));
    ui.checkbox(&mut edited.shadows.cache, "cache tiles");
    let d = &mut edited.shadows.directional;
    ui.add(egui::Slider::new(&mut d.cascade_count, 1..=4).text("cascades"));
    ui.add(egui::Slider::new(&mut d.cascade_fade, 0.001..=1.0).text("cascade fade"));
    egui::ComboBox::from_label("cascade blend").selected_text(format!("{:?}", d.cascade_blend).to_lowercase()).show_ui(
        ui,
        |ui| {
            for b in [CascadeBlend::Hard, CascadeBlend::Soft, CascadeBlend::Dither] {
                ui.selectable_value(&mut d.cascade_blend, b, format!("{b:?}").to_lowercase());
            }
        },
    );
    filter_combo(ui, "directional filter", &mut d.filter);
    filter_combo(ui, "point/spot filter", &mut edited.shadows.other.filter);
    // Cascade ratios must match the count; unset, the defaults for it apply.
    if edited.shadows.directional.cascade_count != before.shadows.directional.cascade_count {
        edited.shadows.directional.cascade_ratios = None;
    }

    let changed = edited != before;
    if changed {
        match edited.validate() {
            Ok(()) => {
                *settings = edited;
                state.error = None;
            }
            Err(e) => state.error = Some(e),
        }
    }
    if let Some(e) = &state.error {
        ui.colored_label(egui::Color32::LIGHT_RED, e);
    }
    ui.separator();
    ui.heading("Frame");
    ui.label(format!("CPU frame {:.1} ms", state.cpu_frame_ms));
    ui.label(format!("{} lights shaded, {} shadow tiles drawn", state.lights_shaded, state.shadow_tiles));
    if let Some(gpu) = &state.gpu {
        ui.label(format!("GPU {:.1} ms", gpu.total_ms()));
        for (pass, ms) in &gpu.passes {
            ui.label(format!("  {pass}: {ms:.2} ms"));
        }
    }
    ui.separator();
    ui.label(HELP);
    changed && state.error.is_none()
}

fn culling_name(c: LightCulling) -> &'static str {
    match c {
        LightCulling::Clustered => "clustered",
        LightCulling::PerObject => "per-object",
        LightCulling::None => "none",
    }
}

fn filter_combo(ui: &mut egui::Ui, label: &str, filter: &mut String) {
    egui::ComboBox::from_label(label).selected_text(filter.clone()).show_ui(ui, |ui| {
        for f in FILTERS {
            ui.selectable_value(filter, f.to_string(), f);
        }
    });
}
