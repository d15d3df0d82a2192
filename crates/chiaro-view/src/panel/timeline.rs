//! The animation row, shown when the scene has glTF animations: play or pause, a slider to
//! scrub through the longest animation's length, and a button back to the rest pose.

use crate::action::Action;
use crate::state::TimelineState;

/// The timeline's widgets for animations `duration` seconds long.
pub fn timeline_panel(ui: &mut egui::Ui, timeline: &TimelineState, duration: f32) -> Vec<Action> {
    let mut actions = Vec::new();
    ui.horizontal(|ui| {
        let label = if timeline.playing { "pause" } else { "play" };
        if ui.button(label).clicked() {
            actions.push(Action::Play(!timeline.playing));
            if !timeline.playing && timeline.time.is_none() {
                actions.push(Action::SetTime(Some(0.0)));
            }
        }
        let rest = ui.add_enabled(timeline.time.is_some(), egui::Button::new("rest pose"));
        if rest.on_hover_text("the file's own node transforms").clicked() {
            actions.push(Action::Play(false));
            actions.push(Action::SetTime(None));
        }
    });
    let mut time = timeline.time.unwrap_or(0.0);
    let slider = egui::Slider::new(&mut time, 0.0..=duration.max(0.0)).text("time (s)").max_decimals(3);
    if ui.add(slider).changed() {
        actions.push(Action::SetTime(Some(time)));
    }
    if timeline.time.is_none() {
        ui.label("showing the rest pose");
    }
    actions
}
