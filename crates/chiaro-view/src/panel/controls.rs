//! The panel's small sections: the scene to open, the camera buttons, the debug view
//! choice and the reference comparison; each returns the actions its widgets ask for.
//! Also the debug views' names, as `--debug` parses them.

use crate::action::Action;
use crate::camera::Navigation;
use crate::state::ViewerState;
use chiaro_render::DebugView;
use std::path::{Path, PathBuf};

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

pub const HELP: &str = "Mouse: drag in the view to orbit (fly: to look around), wheel to zoom. \
    Keys: V switches orbit and fly; W/A/S/D move and Q/E go down and up when flying (Shift: faster); \
    F frames the selection (click an object, or a light's \"select\"; else the whole scene); R resets the view; C steps through the glTF \
    cameras; P writes a screenshot (chiaro-view.png); Escape quits. Drop a .gltf or .glb on the \
    window to open it; the open scene reloads when its files change. Settings apply to the next frame.";

/// The camera rows: navigation, frame selected, reset view and one button per glTF camera.
pub fn cameras_panel(ui: &mut egui::Ui, cameras: &[String], navigation: Navigation) -> Vec<Action> {
    let mut actions = Vec::new();
    ui.horizontal(|ui| {
        for n in [Navigation::Orbit, Navigation::Fly] {
            if ui.selectable_label(navigation == n, n.name()).clicked() && navigation != n {
                actions.push(Action::SetNavigation(n));
            }
        }
        if ui.button("frame selected").clicked() {
            actions.push(Action::FrameSelected);
        }
    });
    ui.horizontal_wrapped(|ui| {
        if ui.button("reset view").clicked() {
            actions.push(Action::ResetView);
        }
        for (i, name) in cameras.iter().enumerate() {
            let label = if name.is_empty() { format!("camera {i}") } else { name.clone() };
            if ui.button(label).clicked() {
                actions.push(Action::SelectCamera(i));
            }
        }
    });
    actions
}

/// The scene row: a path to open (dropping a file on the window does the same). The path
/// being typed is the field's own, kept in egui's memory.
pub fn open_panel(ui: &mut egui::Ui, loading: Option<&Path>) -> Option<Action> {
    let mut open = None;
    ui.horizontal(|ui| {
        let id = egui::Id::unique("open path");
        let mut path = ui.data_mut(|d| d.get_temp::<String>(id)).unwrap_or_default();
        let edit = ui.add(egui::TextEdit::singleline(&mut path).hint_text("scene.gltf").desired_width(180.0));
        let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if (ui.button("open").clicked() || enter) && !path.trim().is_empty() {
            open = Some(Action::Open(PathBuf::from(path.trim())));
        }
        ui.data_mut(|d| d.insert_temp(id, path));
    });
    if let Some(path) = loading {
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label(format!("loading {}", path.display()));
        });
    }
    open
}

/// The debug view choice and the reference comparison.
pub fn debug_panel(ui: &mut egui::Ui, state: &ViewerState) -> Vec<Action> {
    let mut actions = Vec::new();
    let (debug, comparing) = (state.debug, state.jobs.reference.running());
    egui::ComboBox::from_label("debug view").selected_text(debug_label(debug)).show_ui(ui, |ui| {
        for d in debug_choices(state.scene.scene.lights.len()) {
            if ui.selectable_label(debug == d, debug_label(d)).clicked() && debug != d {
                actions.push(Action::SetDebugView(d));
            }
        }
    });
    if debug == Some(DebugView::Reference) {
        ui.horizontal(|ui| {
            if ui.add_enabled(!comparing, egui::Button::new("compare with the reference")).clicked() {
                actions.push(Action::Compare);
            }
            if comparing {
                ui.spinner();
            }
        });
        ui.label("red: false shadow, blue: missed shadow");
        for line in &state.panel.reference_lines {
            ui.label(line);
        }
    }
    actions
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
