//! The window's egui layout: the side panel (a function from the viewer's state to the
//! actions its widgets ask for) and the central area where the 3D view or a debug view's
//! images sit. Widgets keep only their own passing state (a path being typed, a header
//! open); every change to the viewer goes out as an `Action`.

pub mod controls;
pub mod lights;
pub mod settings;
#[cfg(test)]
mod tests;
pub mod timeline;
pub mod timings;

use crate::action::Action;
use crate::gpu::PANEL_WIDTH;
use crate::state::{Selection, ViewerState};
use chiaro_render::DebugView;

/// What the central area shows, and how.
pub struct ViewArea {
    /// The 3D view's size in physical pixels.
    pub size_px: (u32, u32),
    /// The 3D view itself (else the debug images).
    pub show_view: bool,
    /// The compositor copies the view into the window: egui only leaves room for it.
    pub composed: bool,
    pub view_texture: egui::TextureId,
    /// The debug view's images and their sizes.
    pub images: Vec<(egui::TextureId, egui::Vec2)>,
}

/// One run of egui over the window.
pub struct PanelRun {
    pub output: egui::FullOutput,
    pub actions: Vec<Action>,
    /// Where the 3D view sits: its top-left corner and where the panel cuts it, in
    /// physical pixels (when it is shown).
    pub view_pixels: Option<([u32; 2], [u32; 2])>,
}

/// Runs egui over the side panel and the central area.
pub fn run(ctx: &egui::Context, input: egui::RawInput, state: &ViewerState, area: &ViewArea) -> PanelRun {
    let ppp = ctx.pixels_per_point();
    let mut actions = Vec::new();
    let mut view_rect = None;
    let mut central = egui::Rect::NOTHING;
    let output = ctx.run_ui(input, |ui| {
        // egui's separator line lands inside the panel, across its text.
        egui::Panel::right("settings").exact_size(PANEL_WIDTH).resizable(false).show_separator_line(false).show(
            ui,
            |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| actions.extend(side_panel(ui, state)));
            },
        );
        egui::CentralPanel::no_frame().show(ui, |ui| {
            central = ui.max_rect();
            view_rect = view_area(ui, state.debug, area, ppp);
        });
    });
    let pixel = |v: f32| (v * ppp).round().max(0.0) as u32;
    let view_pixels = view_rect
        .map(|rect: egui::Rect| ([pixel(rect.min.x), pixel(rect.min.y)], [pixel(central.max.x), pixel(central.max.y)]));
    PanelRun { output, actions, view_pixels }
}

/// The side panel's sections, top to bottom.
pub fn side_panel(ui: &mut egui::Ui, state: &ViewerState) -> Vec<Action> {
    let scene = &state.scene.scene;
    let mut actions = Vec::new();
    ui.heading("Scene");
    actions.extend(controls::open_panel(ui, state.jobs.loader.loading()));
    ui.heading("Camera");
    let camera_names: Vec<String> = scene.cameras.iter().map(|c| c.name.clone()).collect();
    actions.extend(controls::cameras_panel(ui, &camera_names, state.camera.navigation));
    ui.label(selected_line(state));
    if let Some(duration) = scene.animation_duration() {
        ui.heading("Animation");
        actions.extend(timeline::timeline_panel(ui, &state.timeline, duration));
    }
    ui.heading("View");
    actions.extend(controls::debug_panel(ui, state));
    if state.comparison_stale() && state.debug == Some(DebugView::Reference) {
        ui.colored_label(egui::Color32::YELLOW, "the camera moved since: compare again");
    }
    ui.separator();
    ui.heading("Frame");
    timings::timings_panel(ui, &state.stats);
    ui.separator();
    ui.horizontal(|ui| {
        if ui.button("Save settings").clicked() {
            actions.push(Action::SaveSettings);
        }
        let save_scene =
            ui.button("Save scene").on_hover_text("the glTF with the lights as edited and this view as a camera");
        if save_scene.clicked() {
            actions.push(Action::SaveScene);
        }
    });
    if let Some(status) = &state.panel.status {
        ui.label(status);
    }
    if let Some(e) = &state.panel.error {
        ui.colored_label(egui::Color32::LIGHT_RED, e);
    }
    let choices = settings::SceneChoices {
        own_environment: state.scene.scene.environment.as_ref().map(|own| own.label.as_str()),
        variants: &state.scene.scene.variants.names,
    };
    actions.extend(settings::settings_panel(ui, &state.settings.current, choices));
    ui.separator();
    ui.heading("Lights");
    if scene.lights.iter().any(chiaro_scene::Light::is_area) {
        let mut shown = !state.panel.lights.shapes_hidden;
        if ui.checkbox(&mut shown, "draw rect and disk lights' outlines").changed() {
            actions.push(Action::ShowLightShapes(shown));
        }
    }
    actions.extend(lights::lights_panel(ui, &scene.lights, &state.panel.lights));
    ui.separator();
    ui.label(controls::HELP);
    actions
}

/// What is selected, in words.
fn selected_line(state: &ViewerState) -> String {
    let scene = &state.scene.scene;
    match state.panel.lights.selected {
        Some(Selection::Object(i)) if i < scene.instances.len() => {
            let instance = &scene.instances[i];
            format!("selected: {} (node {})", instance.name, instance.node)
        }
        Some(Selection::Light(i)) if i < scene.lights.len() => format!("selected: light {}", scene.lights[i].name),
        _ => "selected: nothing (click an object)".to_string(),
    }
}

/// The central area: room for the 3D view (or the view itself, where nothing composes
/// the window), or the debug view's images. Returns where the view is, in points.
fn view_area(ui: &mut egui::Ui, debug: Option<DebugView>, area: &ViewArea, ppp: f32) -> Option<egui::Rect> {
    let (w, h) = area.size_px;
    let view_size = egui::vec2(w as f32 / ppp, h as f32 / ppp);
    if area.show_view {
        return Some(if area.composed {
            ui.allocate_exact_size(view_size, egui::Sense::hover()).0
        } else {
            ui.image(egui::load::SizedTexture::new(area.view_texture, view_size)).rect
        });
    }
    ui.horizontal(|ui| {
        for &(id, size) in &area.images {
            // Atlases side by side; any other image at the view's size.
            let shown = if debug == Some(DebugView::ShadowAtlases) {
                let side = (view_size.x / 2.0).min(view_size.y);
                egui::vec2(side, side)
            } else {
                size * (view_size.x / size.x.max(1.0))
            };
            ui.image(egui::load::SizedTexture::new(id, shown));
        }
    });
    if area.images.is_empty() {
        ui.label(match debug {
            Some(DebugView::ShadowAtlases) => "No light casts a shadow.",
            Some(DebugView::Clusters) => "No clusters: lights.culling is not clustered on this path.",
            Some(DebugView::VirtualPages) => "No virtual shadow maps: shadows.technique is not \"virtual\".",
            _ => "Nothing to show yet.",
        });
    }
    None
}
