//! The viewer's side panel: the settings `chiaro render` reads (one `Settings`, edited in
//! place and validated as a file would be), the frame's timings, and the controls.

use chiaro_render::{DebugView, GpuFrameTimes};
use chiaro_scene::{CascadeBlend, Light, LightCulling, RenderPath, Settings, ShadowMode};
use std::collections::HashMap;

/// What the 3D view shows instead of the lit image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Debug {
    #[default]
    None,
    /// Tint by cascade (forward path).
    Cascades,
    /// A deferred-path view.
    View(DebugView),
    /// Both shadow atlases, side by side, instead of the 3D view.
    Atlases,
}

impl Debug {
    fn name(self) -> &'static str {
        match self {
            Debug::None => "none",
            Debug::Cascades => "cascades",
            Debug::View(DebugView::GbufferAlbedo) => "gbuffer-albedo",
            Debug::View(DebugView::GbufferNormal) => "gbuffer-normal",
            Debug::View(DebugView::LightOverdraw) => "light-overdraw",
            Debug::Atlases => "shadow atlases",
        }
    }
}

/// What the panel shows besides the settings.
#[derive(Default)]
pub struct PanelState {
    pub debug: Debug,
    /// Lights switched off, with the intensity they get back when switched on.
    pub switched_off: HashMap<usize, f32>,
    /// "Save settings" was pressed this frame.
    pub save_requested: bool,
    /// A glTF camera chosen this frame (by index), or "reset view" (`Some(None)`).
    pub camera_request: Option<Option<usize>>,
    /// The outcome of the last save.
    pub saved: Option<String>,
    /// The last rejected edit, shown until the next one is accepted.
    pub error: Option<String>,
    /// Milliseconds per pass of the latest finished frame, and its total.
    pub gpu: Option<GpuFrameTimes>,
    pub cpu_frame_ms: f64,
    pub shadow_tiles: usize,
    pub lights_shaded: usize,
}

pub const HELP: &str = "Drag with the left button to orbit, wheel to zoom. Keys: R resets the view, \
    C steps through the glTF cameras, P writes a screenshot (chiaro-view.png). Settings apply to the next frame.";

/// The camera row: "reset view" and one button per glTF camera.
pub fn cameras_panel(ui: &mut egui::Ui, cameras: &[String], state: &mut PanelState) {
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
    ui.heading("View");
    egui::ComboBox::from_label("debug").selected_text(state.debug.name()).show_ui(ui, |ui| {
        let views = [
            Debug::None,
            Debug::Cascades,
            Debug::View(DebugView::GbufferAlbedo),
            Debug::View(DebugView::GbufferNormal),
            Debug::View(DebugView::LightOverdraw),
            Debug::Atlases,
        ];
        for d in views {
            ui.selectable_value(&mut state.debug, d, d.name());
        }
    });
    state.save_requested = ui.button("Save settings").clicked();
    if let Some(saved) = &state.saved {
        ui.label(saved);
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

/// One collapsible row per light: on/off, colour, intensity, range, shadow mode and
/// strength. Returns whether a light changed.
pub fn lights_panel(ui: &mut egui::Ui, lights: &mut [Light], state: &mut PanelState) -> bool {
    let mut changed = false;
    for (i, light) in lights.iter_mut().enumerate() {
        let title = if light.name.is_empty() { format!("light {i}") } else { light.name.clone() };
        egui::CollapsingHeader::new(title).id_salt(("light", i)).show(ui, |ui| {
            let mut on = !state.switched_off.contains_key(&i);
            if ui.checkbox(&mut on, "on").changed() {
                if on {
                    light.intensity = state.switched_off.remove(&i).unwrap_or(1.0);
                } else {
                    state.switched_off.insert(i, light.intensity);
                    light.intensity = 0.0;
                }
                changed = true;
            }
            if on {
                changed |= ui
                    .add(egui::Slider::new(&mut light.intensity, 0.0..=1.0e5).logarithmic(true).text("intensity"))
                    .changed();
            }
            let mut rgb = light.color.to_array();
            if ui.color_edit_button_rgb(&mut rgb).changed() {
                light.color = glam::Vec3::from(rgb);
                changed = true;
            }
            if let Some(range) = light.range.as_mut() {
                changed |= ui.add(egui::Slider::new(range, 0.01..=1000.0).logarithmic(true).text("range")).changed();
            }
            egui::ComboBox::from_id_salt(("shadows", i))
                .selected_text(format!("shadows {:?}", light.shadow.mode).to_lowercase())
                .show_ui(ui, |ui| {
                    for m in [ShadowMode::None, ShadowMode::Hard, ShadowMode::Soft] {
                        changed |=
                            ui.selectable_value(&mut light.shadow.mode, m, format!("{m:?}").to_lowercase()).changed();
                    }
                });
            changed |=
                ui.add(egui::Slider::new(&mut light.shadow.strength, 0.0..=1.0).text("shadow strength")).changed();
            changed |= ui.add(egui::Slider::new(&mut light.shadow.depth_bias, 0.0..=10.0).text("depth bias")).changed();
            changed |=
                ui.add(egui::Slider::new(&mut light.shadow.normal_bias, 0.0..=3.0).text("normal bias")).changed();
        });
    }
    changed
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui_kittest::Harness;
    use egui_kittest::kittest::Queryable;

    #[test]
    fn a_checkbox_in_the_panel_changes_the_settings_and_the_frame_plan() {
        let mut harness = Harness::new_ui_state(
            |ui, (settings, state, changed): &mut (Settings, PanelState, bool)| {
                *changed |= settings_panel(ui, settings, state);
            },
            (Settings::default(), PanelState::default(), false),
        );
        harness.run();
        harness.get_by_label("cache tiles").click();
        harness.run();
        let (settings, _, changed) = harness.state();
        assert!(*changed, "the panel reports the change");
        assert!(!settings.shadows.cache, "the checkbox turned shadow caching off");
        // The frame plan follows the settings.
        let scene = chiaro_scene::demo::demo_scene(4);
        let view = chiaro_render::View::from_camera(&scene, 0, 64, 64);
        let draws =
            chiaro_render::plan::draws::scene_draws(&scene, &chiaro_render::plan::draws::GeometryLayout::of(&scene));
        let mut tiles = chiaro_render::plan::shadows::ShadowAtlasTiles::default();
        let plan = chiaro_render::FramePlan::new(&scene, &draws, &view, settings, &mut tiles, Default::default());
        assert!(!plan.shadow_cache);
    }

    #[test]
    fn camera_buttons_ask_for_their_camera() {
        let cameras = vec!["overview".to_string(), String::new()];
        let mut harness = Harness::new_ui_state(
            |ui, state: &mut PanelState| cameras_panel(ui, &cameras, state),
            PanelState::default(),
        );
        harness.run();
        harness.get_by_label("camera 1").click();
        harness.run();
        assert_eq!(harness.state().camera_request, Some(Some(1)));
        harness.get_by_label("reset view").click();
        harness.run();
        assert_eq!(harness.state().camera_request, Some(None));
    }

    #[test]
    fn an_invalid_edit_is_shown_and_not_applied() {
        let mut settings = Settings::default();
        let mut state = PanelState::default();
        // A count the panel cannot produce, as a stand-in for any invalid edit.
        settings.render.width = 0;
        let before = settings.clone();
        let mut harness = Harness::new_ui_state(
            |ui, (settings, state): &mut (Settings, PanelState)| {
                settings_panel(ui, settings, state);
            },
            (settings, std::mem::take(&mut state)),
        );
        harness.run();
        harness.get_by_label("cache tiles").click();
        harness.run();
        let (settings, state) = harness.state();
        assert_eq!(*settings, before, "rejected");
        assert!(state.error.as_deref().is_some_and(|e| e.contains("render.width")), "{:?}", state.error);
    }
}
