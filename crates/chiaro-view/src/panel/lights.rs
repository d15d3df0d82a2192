//! The light list: one collapsible row per glTF light with everything its extras and
//! KHR_lights_punctual set, editable live (each row edits a copy and asks for it,
//! `EditLight`), and the atlas tiles it got this frame.

use crate::action::Action;
use crate::state::{LightsState, Selection};
use chiaro_render::FramePlan;
use chiaro_render::plan::shadows::ShadowAtlas;
use chiaro_scene::{Light, LightKind, LightMode, ShadowMode};
use egui::{ComboBox, Slider, Ui};

/// Sliders only limit what is dragged: drawing one must not clamp a light the file set
/// outside its range (a 120,000 lux sun), or the view would stop matching `chiaro render`.
const EDITS_ONLY: egui::SliderClamping = egui::SliderClamping::Edits;

/// Describes each scene light's atlas tiles in `plan`.
pub fn tiles_by_light(plan: &FramePlan, light_count: usize) -> Vec<String> {
    let mut per_light: Vec<Vec<(ShadowAtlas, u32, u32)>> = vec![Vec::new(); light_count];
    for tile in &plan.shadows.tiles {
        if let Some(list) = per_light.get_mut(tile.light.index()) {
            list.push((tile.atlas, tile.tile, tile.viewport.2));
        }
    }
    per_light
        .into_iter()
        .map(|tiles| {
            let Some(&(atlas, _, size)) = tiles.first() else { return "no atlas tiles this frame".to_string() };
            let atlas = match atlas {
                ShadowAtlas::Directional => "directional",
                ShadowAtlas::Local => "point/spot",
            };
            let indices: Vec<String> = tiles.iter().map(|t| t.1.to_string()).collect();
            let sizes = if tiles.iter().all(|t| t.2 == size) { format!("{size}") } else { "mixed".into() };
            format!("{} {atlas} tiles ({}), {sizes} texels", tiles.len(), indices.join(", "))
        })
        .collect()
}

/// Draws the list; returns what its rows ask for.
pub fn lights_panel(ui: &mut Ui, lights: &[Light], state: &LightsState) -> Vec<Action> {
    let mut actions = Vec::new();
    for (i, light) in lights.iter().enumerate() {
        let kind = light.kind.name();
        let name = if light.name.is_empty() { format!("light {i}") } else { light.name.clone() };
        egui::CollapsingHeader::new(format!("{name} ({kind})")).id_salt(("light", i)).show(ui, |ui| {
            let mut edited = light.clone();
            let mut changed = false;
            ui.horizontal(|ui| {
                actions.extend(switch_and_select(ui, i, state));
                let mut rgb = edited.color.to_array();
                if ui.color_edit_button_rgb(&mut rgb).changed() {
                    edited.color = glam::Vec3::from(rgb);
                    changed = true;
                }
            });
            changed |= light_rows(ui, i, &mut edited, state);
            if changed {
                actions.push(Action::EditLight { index: i, light: Box::new(edited) });
            }
        });
    }
    actions
}

/// The row's on/off switch and "select" (for "frame selected").
fn switch_and_select(ui: &mut Ui, i: usize, state: &LightsState) -> Vec<Action> {
    let mut actions = Vec::new();
    let mut on = !state.switched_off.contains_key(&i);
    if ui.checkbox(&mut on, "on").changed() {
        actions.push(Action::SwitchLight { index: i, on });
    }
    let selected = state.selected == Some(Selection::Light(i));
    if ui.selectable_label(selected, "select").clicked() {
        actions.push(Action::Select(if selected { None } else { Some(Selection::Light(i)) }));
    }
    actions
}

/// A rect's width and height or a disk's diameter, metres; whether one changed.
fn area_rows(ui: &mut Ui, kind: &mut LightKind) -> bool {
    let size = |ui: &mut Ui, value: &mut f32, label: &str| {
        ui.add(Slider::new(value, 0.01..=20.0).logarithmic(true).text(label).clamping(EDITS_ONLY)).changed()
    };
    match kind {
        LightKind::Rect { width, height } => size(ui, width, "width (m)") | size(ui, height, "height (m)"),
        LightKind::Disk { diameter } => size(ui, diameter, "diameter (m)"),
        _ => false,
    }
}

/// The light's values below its first row as widgets, editing `light`; returns whether
/// one changed.
fn light_rows(ui: &mut Ui, i: usize, light: &mut Light, state: &LightsState) -> bool {
    let mut changed = false;
    if !state.switched_off.contains_key(&i) {
        let unit = match light.kind {
            LightKind::Directional => "intensity (lux)",
            LightKind::Rect { .. } | LightKind::Disk { .. } => "intensity (nits)",
            _ => "intensity (cd)",
        };
        changed |= ui
            .add(Slider::new(&mut light.intensity, 0.0..=1.0e5).logarithmic(true).text(unit).clamping(EDITS_ONLY))
            .changed();
    }
    if light.kind != LightKind::Directional {
        let mut has_range = light.range.is_some();
        ui.horizontal(|ui| {
            if ui.checkbox(&mut has_range, "range").changed() {
                light.range = has_range.then_some(10.0);
                changed = true;
            }
            match light.range.as_mut() {
                Some(range) => {
                    changed |= ui
                        .add(Slider::new(range, 0.01..=1000.0).logarithmic(true).text("m").clamping(EDITS_ONLY))
                        .changed()
                }
                None => {
                    ui.weak("from intensity");
                }
            }
        });
    }
    if let LightKind::Spot { inner_cone_rad, outer_cone_rad } = &mut light.kind {
        let (mut inner, mut outer) = (inner_cone_rad.to_degrees(), outer_cone_rad.to_degrees());
        let inner_changed = ui.add(Slider::new(&mut inner, 0.0..=89.9).text("inner cone (deg)")).changed();
        let outer_changed = ui.add(Slider::new(&mut outer, 0.1..=90.0).text("outer cone (deg)")).changed();
        if inner_changed || outer_changed {
            // glTF: 0 <= inner < outer <= 90 degrees; the other end gives way.
            if inner_changed {
                outer = outer.max(inner + 0.1);
            } else {
                inner = inner.min(outer - 0.1);
            }
            *inner_cone_rad = inner.to_radians();
            *outer_cone_rad = outer.min(90.0).to_radians();
            changed = true;
        }
    }
    changed |= area_rows(ui, &mut light.kind);
    let is_area = light.is_area();
    let shadow = &mut light.shadow;
    ComboBox::new(("shadows", i), "shadows").selected_text(shadow.mode.name()).show_ui(ui, |ui| {
        for m in [ShadowMode::None, ShadowMode::Hard, ShadowMode::Soft, ShadowMode::Pcss] {
            changed |= ui.selectable_value(&mut shadow.mode, m, m.name()).changed();
        }
    });
    // An area light's penumbra comes from its shape.
    if shadow.mode == ShadowMode::Pcss && !is_area {
        changed |= match light.kind {
            LightKind::Directional => ui.add(
                Slider::new(&mut shadow.angular_diameter_deg, 0.0..=10.0)
                    .text("angular diameter (deg)")
                    .clamping(EDITS_ONLY),
            ),
            _ => ui.add(Slider::new(&mut shadow.light_radius, 0.0..=1.0).text("light radius (m)").clamping(EDITS_ONLY)),
        }
        .changed();
    }
    changed |=
        ui.add(Slider::new(&mut shadow.strength, 0.0..=1.0).text("shadow strength").clamping(EDITS_ONLY)).changed();
    changed |=
        ui.add(Slider::new(&mut shadow.depth_bias, 0.0..=10.0).text("depth bias").clamping(EDITS_ONLY)).changed();
    changed |=
        ui.add(Slider::new(&mut shadow.normal_bias, 0.0..=3.0).text("normal bias").clamping(EDITS_ONLY)).changed();
    changed |=
        ui.add(Slider::new(&mut shadow.near_plane, 0.0..=10.0).text("near plane (m)").clamping(EDITS_ONLY)).changed();
    ComboBox::new(("mode", i), "mode").selected_text(light.mode.name()).show_ui(ui, |ui| {
        for m in [LightMode::Realtime, LightMode::Mixed, LightMode::Baked] {
            changed |= ui.selectable_value(&mut light.mode, m, m.name()).changed();
        }
    });
    if light.mode != LightMode::Realtime {
        ui.weak("baked light comes from the last chiaro bake");
    }
    if let Some(tiles) = state.tiles.get(i) {
        ui.label(format!("this frame: {tiles}"));
    }
    changed
}
