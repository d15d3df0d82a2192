//! Every key of settings.toml (docs/settings.md) as a widget labelled with its key. The
//! panel edits a copy and asks for it (`SetSettings`); the viewer keeps it only when it
//! validates as a file would, so that what "Save settings" writes renders the same image
//! headless.

use crate::action::Action;
use chiaro_scene::settings::{AoQuality, BakeQuality, EnvironmentMode, EnvironmentSource};
use chiaro_scene::{
    CascadeBlend, DeferredAntialiasing, LightBuffer, LightCulling, MixedMode, RenderPath, Settings, ShadowTechnique,
    ToneMapping,
};
use egui::{ComboBox, DragValue, Slider, Ui};

const FILTERS: [&str; 4] = ["pcf2x2", "tent3x3", "tent5x5", "tent7x7"];
const ATLAS_SIZES: [u32; 6] = [256, 512, 1024, 2048, 4096, 8192];
/// Default far ends of the cascades, x max_distance (docs/settings.md).
const DEFAULT_RATIOS: [f32; 3] = [0.1, 0.25, 0.5];

/// What the open file offers the settings to choose from.
#[derive(Clone, Copy, Default)]
pub struct SceneChoices<'a> {
    /// The file's EXT_lights_image_based light, if it has one.
    pub own_environment: Option<&'a str>,
    /// Its KHR_materials_variants variants.
    pub variants: &'a [String],
}

/// Draws the settings; asks for the edited settings when they changed.
pub fn settings_panel(ui: &mut Ui, settings: &Settings, choices: SceneChoices<'_>) -> Option<Action> {
    let own_environment = choices.own_environment;
    let mut edited = settings.clone();
    // Narrow sliders leave room for the keys' long names.
    ui.spacing_mut().slider_width = 100.0;
    render_section(ui, &mut edited);
    lights_section(ui, &mut edited);
    shadows_section(ui, &mut edited);
    environment_section(ui, &mut edited, own_environment);
    ambient_occlusion_section(ui, &mut edited);
    lighting_and_bake_section(ui, &mut edited);
    scene_section(ui, &mut edited, choices.variants);
    // Cascade ratios must match the count; unset, the defaults for it apply.
    if edited.shadows.directional.cascade_count != settings.shadows.directional.cascade_count {
        edited.shadows.directional.cascade_ratios = None;
    }
    (edited != *settings).then(|| Action::SetSettings(Box::new(edited)))
}

fn drag_row<N: egui::emath::Numeric>(ui: &mut Ui, key: &str, value: &mut N, range: std::ops::RangeInclusive<N>) {
    ui.horizontal(|ui| {
        let label = ui.label(key);
        ui.add(DragValue::new(value).range(range)).labelled_by(label.id);
    });
}

fn rgb_row(ui: &mut Ui, key: &str, rgb: &mut [f32; 3]) {
    ui.horizontal(|ui| {
        let label = ui.label(key);
        for c in rgb.iter_mut() {
            ui.add(DragValue::new(c).range(0.0..=1.0e6).speed(0.001).max_decimals(4)).labelled_by(label.id);
        }
    });
}

fn combo<T: PartialEq + Copy>(ui: &mut Ui, key: &str, value: &mut T, options: &[(T, &str)]) {
    let current = options.iter().find(|(v, _)| v == value).map_or("?", |(_, name)| name);
    ComboBox::from_label(key).selected_text(current).show_ui(ui, |ui| {
        for (v, name) in options {
            ui.selectable_value(value, *v, *name);
        }
    });
}

fn filter_combo(ui: &mut Ui, key: &str, filter: &mut String) {
    ComboBox::from_label(key).selected_text(filter.clone()).show_ui(ui, |ui| {
        for f in FILTERS {
            ui.selectable_value(filter, f.to_string(), f);
        }
    });
}

fn atlas_combo(ui: &mut Ui, key: &str, size: &mut u32) {
    let options: Vec<(u32, String)> = ATLAS_SIZES.iter().map(|s| (*s, s.to_string())).collect();
    ComboBox::from_label(key).selected_text(size.to_string()).show_ui(ui, |ui| {
        for (s, name) in &options {
            ui.selectable_value(size, *s, name);
        }
    });
}

fn render_section(ui: &mut Ui, s: &mut Settings) {
    ui.heading("[render]");
    let r = &mut s.render;
    drag_row(ui, "render.width", &mut r.width, 1..=16384);
    drag_row(ui, "render.height", &mut r.height, 1..=16384);
    ui.add(Slider::new(&mut r.exposure_ev100, -30.0..=30.0).text("render.exposure_ev100"));
    rgb_row(ui, "render.ambient", &mut r.ambient);
    rgb_row(ui, "render.background", &mut r.background);
    combo(ui, "render.path", &mut r.path, &[(RenderPath::Forward, "forward"), (RenderPath::Deferred, "deferred")]);
    combo(
        ui,
        "render.light_buffer",
        &mut r.light_buffer,
        &[(LightBuffer::Hdr, "hdr"), (LightBuffer::LdrExp2, "ldr-exp2")],
    );
    combo(ui, "render.msaa", &mut r.msaa, &[(1, "1"), (2, "2"), (4, "4"), (8, "8")]);
    combo(
        ui,
        "render.deferred_antialiasing",
        &mut r.deferred_antialiasing,
        &[(DeferredAntialiasing::Fxaa, "fxaa"), (DeferredAntialiasing::None, "none")],
    );
    combo(
        ui,
        "render.tone_mapping",
        &mut r.tone_mapping,
        &[
            (ToneMapping::PbrNeutral, "pbr-neutral"),
            (ToneMapping::Aces, "aces"),
            (ToneMapping::Agx, "agx"),
            (ToneMapping::Linear, "linear"),
        ],
    );
}

fn lights_section(ui: &mut Ui, s: &mut Settings) {
    ui.heading("[lights]");
    let l = &mut s.lights;
    ui.horizontal(|ui| {
        let mut limited = l.max_other_lights.is_some();
        let label = ui.label("lights.max_other_lights");
        if ui.checkbox(&mut limited, "").labelled_by(label.id).changed() {
            l.max_other_lights = limited.then_some(64);
        }
        if let Some(max) = l.max_other_lights.as_mut() {
            ui.add(DragValue::new(max).range(1..=4096)).labelled_by(label.id);
        } else {
            ui.weak("unset: as many as fit");
        }
    });
    ui.add(Slider::new(&mut l.range_threshold_lux, 1e-6..=1e6).logarithmic(true).text("lights.range_threshold_lux"));
    combo(
        ui,
        "lights.culling",
        &mut l.culling,
        &[
            (LightCulling::Clustered, "clustered"),
            (LightCulling::PerObject, "per-object"),
            (LightCulling::None, "none"),
        ],
    );
    ui.heading("[camera]");
    ui.add(Slider::new(&mut s.camera.auto_yfov_deg, 1.0..=179.0).text("camera.auto_yfov_deg"));
}

fn shadows_section(ui: &mut Ui, s: &mut Settings) {
    ui.heading("[shadows]");
    let sh = &mut s.shadows;
    ui.add(Slider::new(&mut sh.max_distance, 0.1..=10000.0).logarithmic(true).text("shadows.max_distance"));
    ui.add(Slider::new(&mut sh.distance_fade, 0.001..=1.0).text("shadows.distance_fade"));
    ui.checkbox(&mut sh.cache, "shadows.cache");
    ui.add(Slider::new(&mut sh.pcss_blocker_samples, 4..=64).text("shadows.pcss_blocker_samples"));
    ui.add(Slider::new(&mut sh.pcss_filter_samples, 4..=64).text("shadows.pcss_filter_samples"));
    ui.checkbox(&mut sh.contact, "shadows.contact");
    ui.add_enabled_ui(sh.contact, |ui| {
        ui.add(Slider::new(&mut sh.contact_length, 0.001..=10.0).logarithmic(true).text("shadows.contact_length"));
        ui.add(Slider::new(&mut sh.contact_steps, 1..=64).text("shadows.contact_steps"));
        let thickness = Slider::new(&mut sh.contact_thickness, 0.001..=10.0).logarithmic(true);
        ui.add(thickness.text("shadows.contact_thickness"));
    });
    combo(
        ui,
        "shadows.technique",
        &mut sh.technique,
        &[(ShadowTechnique::Atlas, "atlas"), (ShadowTechnique::Virtual, "virtual")],
    );
    ui.add_enabled_ui(sh.technique == ShadowTechnique::Virtual, |ui| {
        let pool = Slider::new(&mut sh.virtual_pool_mb, 16..=2048).logarithmic(true);
        ui.add(pool.text("shadows.virtual_pool_mb"));
    });
    ui.heading("[shadows.directional]");
    let d = &mut sh.directional;
    atlas_combo(ui, "shadows.directional.atlas_size", &mut d.atlas_size);
    filter_combo(ui, "shadows.directional.filter", &mut d.filter);
    ui.add(Slider::new(&mut d.cascade_count, 1..=4).text("shadows.directional.cascade_count"));
    cascade_ratios(ui, d.cascade_count, &mut d.cascade_ratios);
    ui.add(Slider::new(&mut d.cascade_fade, 0.001..=1.0).text("shadows.directional.cascade_fade"));
    combo(
        ui,
        "shadows.directional.cascade_blend",
        &mut d.cascade_blend,
        &[(CascadeBlend::Hard, "hard"), (CascadeBlend::Soft, "soft"), (CascadeBlend::Dither, "dither")],
    );
    ui.heading("[shadows.other]");
    let o = &mut sh.other;
    atlas_combo(ui, "shadows.other.atlas_size", &mut o.atlas_size);
    filter_combo(ui, "shadows.other.filter", &mut o.filter);
    ui.add(Slider::new(&mut o.max_tiles, 1..=64).text("shadows.other.max_tiles"));
}

/// One slider per cascade split. Moving one keeps the others in increasing order by
/// pushing its neighbours, so that the edit stays valid.
fn cascade_ratios(ui: &mut Ui, count: u32, ratios: &mut Option<Vec<f32>>) {
    let splits = count.saturating_sub(1) as usize;
    ui.label("shadows.directional.cascade_ratios");
    if splits == 0 {
        ui.weak("  (one cascade: no splits)");
        return;
    }
    let mut values = ratios.clone().unwrap_or_else(|| DEFAULT_RATIOS[..splits].to_vec());
    let mut moved = None;
    for (i, v) in values.iter_mut().enumerate() {
        let slider = Slider::new(v, 0.001..=0.999).logarithmic(true).text(format!("cascade {} ends at", i + 1));
        if ui.add(slider).changed() {
            moved = Some(i);
        }
    }
    if let Some(i) = moved {
        const GAP: f32 = 1e-3;
        for k in (0..i).rev() {
            values[k] = values[k].min(values[k + 1] - GAP);
        }
        for k in i + 1..values.len() {
            values[k] = values[k].max(values[k - 1] + GAP);
        }
        *ratios = Some(values);
    }
    if ratios.is_some() && ui.small_button("default splits").clicked() {
        *ratios = None;
    }
}

/// `[scene]`: the material variant, from the file's list (none: its default materials).
fn scene_section(ui: &mut Ui, s: &mut Settings, variants: &[String]) {
    ui.heading("[scene]");
    let shown = s.scene.variant.clone().unwrap_or_else(|| "(default materials)".into());
    ComboBox::from_label("scene.variant").selected_text(shown).show_ui(ui, |ui| {
        ui.selectable_value(&mut s.scene.variant, None, "(default materials)");
        for name in variants {
            ui.selectable_value(&mut s.scene.variant, Some(name.clone()), name.as_str());
        }
    });
}

/// The environment: a source (an image is dropped on the window or named in the file),
/// its intensity, turn, background and mode.
fn environment_section(ui: &mut Ui, s: &mut Settings, own_environment: Option<&str>) {
    ui.heading("[environment]");
    let e = &mut s.environment;
    let mut sources =
        vec![EnvironmentSource::None, EnvironmentSource::Ambient, EnvironmentSource::Neutral, EnvironmentSource::Sky];
    if let EnvironmentSource::File(_) = &e.source {
        sources.push(e.source.clone());
    }
    ComboBox::from_label("environment.source").selected_text(e.source.name()).show_ui(ui, |ui| {
        for source in sources {
            let name = source.name();
            ui.selectable_value(&mut e.source, source, name);
        }
    });
    if let (EnvironmentSource::None, Some(own)) = (&e.source, own_environment) {
        ui.label(format!("(none: the file's own, {own})"));
    }
    ui.label("(drop an .hdr or .exr on the window to use it)");
    ui.add(Slider::new(&mut e.intensity, 0.0..=1.0e6).logarithmic(true).text("environment.intensity"));
    ui.add(Slider::new(&mut e.rotation_deg, -180.0..=180.0).text("environment.rotation_deg"));
    ui.checkbox(&mut e.background, "environment.background");
    combo(
        ui,
        "environment.mode",
        &mut e.mode,
        &[(EnvironmentMode::Realtime, "realtime"), (EnvironmentMode::Baked, "baked")],
    );
}

/// Screen-space ambient occlusion: on or off, its radius, quality, intensity and thickness.
fn ambient_occlusion_section(ui: &mut Ui, s: &mut Settings) {
    ui.heading("[ambient_occlusion]");
    let a = &mut s.ambient_occlusion;
    ui.checkbox(&mut a.enabled, "ambient_occlusion.enabled");
    ui.add(Slider::new(&mut a.radius, 0.01..=100.0).logarithmic(true).text("ambient_occlusion.radius"));
    combo(ui, "ambient_occlusion.quality", &mut a.quality, &AoQuality::ALL.map(|q| (q, q.name())));
    ui.add(Slider::new(&mut a.intensity, 0.0..=8.0).text("ambient_occlusion.intensity"));
    ui.add(Slider::new(&mut a.thickness, 0.001..=100.0).logarithmic(true).text("ambient_occlusion.thickness"));
}

fn lighting_and_bake_section(ui: &mut Ui, s: &mut Settings) {
    ui.heading("[lighting]");
    combo(
        ui,
        "lighting.mixed_mode",
        &mut s.lighting.mixed_mode,
        &[
            (MixedMode::DistanceShadowmask, "distance-shadowmask"),
            (MixedMode::Shadowmask, "shadowmask"),
            (MixedMode::BakedIndirect, "baked-indirect"),
        ],
    );
    egui::CollapsingHeader::new("[bake] (chiaro bake reads these)").default_open(true).show(ui, |ui| {
        let b = &mut s.bake;
        combo(ui, "bake.quality", &mut b.quality, &BakeQuality::ALL.map(|q| (q, q.name())));
        ui.checkbox(&mut b.denoise, "bake.denoise");
        let mut samples = b.texel_samples();
        drag_row(ui, "bake.samples", &mut samples, 1..=65536);
        if samples != b.texel_samples() {
            b.samples = Some(samples);
        }
        drag_row(ui, "bake.bounces", &mut b.bounces, 0..=64);
        drag_row(ui, "bake.texels_per_metre", &mut b.texels_per_metre, 0.01..=1000.0);
        drag_row(ui, "bake.seed", &mut b.seed, 0..=u64::MAX);
        drag_row(ui, "bake.probe_spacing", &mut b.probe_spacing, 0.05..=1000.0);
        let mut probe_samples = b.probe_samples();
        drag_row(ui, "bake.probe_samples", &mut probe_samples, 1..=65536);
        if probe_samples != b.probe_samples() {
            b.probe_samples = Some(probe_samples);
        }
    });
}
