//! The panel under egui_kittest (egui's headless harness, drawn with wgpu on lavapipe):
//! edits reach the settings, the frame plan and the rendered view; invalid edits are
//! refused; every documented settings key has its widget; snapshots of the panel.

use super::lights_panel::{LightsState, lights_panel};
use super::panel::{PanelState, cameras_panel};
use super::settings_panel::settings_panel;
use chiaro_render::plan::draws::{GeometryLayout, scene_draws};
use chiaro_render::plan::shadows::ShadowAtlasTiles;
use chiaro_render::{FrameOptions, FramePlan, GpuContext, Renderer, View};
use chiaro_scene::{Scene, Settings};
use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

/// The settings panel over a settings value, keeping valid edits and the last error.
fn settings_harness<'a>(settings: Settings) -> Harness<'a, (Settings, Option<String>)> {
    Harness::builder().with_size(egui::vec2(360.0, 800.0)).wgpu().build_ui_state(
        |ui, (settings, error): &mut (Settings, Option<String>)| match settings_panel(ui, settings) {
            Some(Ok(edited)) => {
                *settings = edited;
                *error = None;
            }
            Some(Err(e)) => *error = Some(e),
            None => {}
        },
        (settings, None),
    )
}

fn plan(scene: &Scene, settings: &Settings) -> FramePlan {
    let view = View::from_camera(scene, 0, 64, 64);
    let draws = scene_draws(scene, &GeometryLayout::of(scene));
    FramePlan::new(scene, &draws, &view, settings, &mut ShadowAtlasTiles::default(), Default::default())
}

/// The view `chiaro view` shows (and `--screenshot` writes), tone-mapped RGBA8.
fn rendered_view(scene: &Scene, settings: &Settings) -> Vec<u8> {
    let mut renderer = Renderer::new(GpuContext::new().expect("a device")).expect("a renderer");
    let prepared = renderer.prepare(scene).unwrap();
    let view = View::from_camera(scene, 0, 96, 64);
    let options = FrameOptions { readback: true, ..Default::default() };
    renderer.render(scene, &prepared, &view, settings, options).unwrap().ldr
}

/// Every `section.key` of the settings file documented in docs/settings.md.
fn documented_keys() -> Vec<String> {
    let doc = include_str!("../../../../docs/settings.md");
    let block = doc.split("```toml").nth(1).and_then(|b| b.split("```").next()).expect("a toml block");
    let mut section = String::new();
    let mut keys = Vec::new();
    for line in block.lines() {
        let line = line.trim_start_matches('#').trim();
        if let Some(name) = line.strip_prefix('[').and_then(|l| l.split(']').next()) {
            section = name.to_string();
        } else if let Some((key, _)) = line.split_once(" = ")
            && !key.contains(' ')
            && !key.is_empty()
        {
            keys.push(format!("{section}.{key}"));
        }
    }
    keys
}

#[test]
fn every_documented_settings_key_has_a_widget_labelled_with_it() {
    let keys = documented_keys();
    assert!(keys.len() >= 30, "the doc's keys were read: {keys:?}");
    let harness = settings_harness(Settings::default());
    let missing: Vec<&String> =
        keys.iter().filter(|k| harness.query_all_by_label_contains(k).next().is_none()).collect();
    assert!(missing.is_empty(), "no widget for {missing:?}");
}

#[test]
fn a_panel_edit_changes_the_frame_plan_and_the_rendered_view() {
    let scene = chiaro_scene::demo::demo_scene(4);
    let before = Settings::default();
    let mut harness = settings_harness(before.clone());
    harness.get_by_role_and_label(Role::Slider, "shadows.directional.cascade_count").set_value_accesskit(2.0);
    harness.run();
    harness.get_by_role_and_label(Role::Slider, "render.exposure_ev100").set_value_accesskit(-1.0);
    harness.run();
    let (after, error) = harness.state().clone();
    assert_eq!(error, None);
    assert_eq!(after.shadows.directional.cascade_count, 2);
    assert_eq!(after.render.exposure_ev100, -1.0);
    assert_eq!(plan(&scene, &before).shadows.cascade_spheres.len(), 4);
    assert_eq!(plan(&scene, &after).shadows.cascade_spheres.len(), 2, "the plan follows the panel");

    let (shown_before, shown_after) = (rendered_view(&scene, &before), rendered_view(&scene, &after));
    let brighter = shown_before.iter().zip(&shown_after).filter(|(b, a)| a > b).count();
    assert!(brighter > shown_after.len() / 8, "one stop more exposure brightens the view: {brighter} channels");
    // What "Save settings" writes renders the same view headless.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("viewer.toml");
    super::save_settings(&path, &after).unwrap();
    let saved = crate::scene_source::load_settings(Some(&path)).unwrap();
    assert_eq!(rendered_view(&scene, &saved), shown_after);
    harness.snapshot("settings_panel_after_edit");
}

#[test]
fn drawing_a_light_does_not_clamp_what_the_file_set() {
    let mut sun = chiaro_scene::Light::new(chiaro_scene::LightKind::Directional, glam::Vec3::ZERO, glam::Vec3::NEG_Y);
    sun.intensity = 120_000.0;
    sun.shadow.depth_bias = 25.0;
    let mut harness = Harness::builder().with_size(egui::vec2(330.0, 300.0)).build_ui_state(
        |ui, (lights, state): &mut (Vec<chiaro_scene::Light>, LightsState)| {
            lights_panel(ui, lights, state);
        },
        (vec![sun], LightsState::default()),
    );
    harness.get_all_by_label_contains("(directional)").next().expect("the sun's row").click();
    harness.run();
    assert!(harness.query_by_role_and_label(Role::Slider, "depth bias").is_some(), "the row is open");
    let (lights, _) = harness.state();
    assert_eq!(lights[0].intensity, 120_000.0);
    assert_eq!(lights[0].shadow.depth_bias, 25.0);
}

#[test]
fn the_light_list_names_the_tiles_each_light_got() {
    let scene = chiaro_scene::demo::demo_scene_with_shadows(4, 1, 1);
    let tiles = super::lights_panel::tiles_by_light(&plan(&scene, &Settings::default()), scene.lights.len());
    assert_eq!(tiles.len(), scene.lights.len());
    let sun = scene.lights.iter().position(|l| l.kind == chiaro_scene::LightKind::Directional).unwrap();
    assert!(tiles[sun].starts_with("4 directional tiles (0, 1, 2, 3)"), "{}", tiles[sun]);
    let point = scene.lights.iter().position(|l| l.kind == chiaro_scene::LightKind::Point && l.shadow.casts()).unwrap();
    assert!(tiles[point].starts_with("6 point/spot tiles"), "{}", tiles[point]);
    let unshadowed = scene.lights.iter().position(|l| !l.shadow.casts()).unwrap();
    assert_eq!(tiles[unshadowed], "no atlas tiles this frame");
}

#[test]
fn an_invalid_edit_is_reported_and_not_kept() {
    let mut settings = Settings::default();
    // A value the panel's widgets cannot produce, standing in for any invalid edit.
    settings.shadows.directional.filter = "bilinear".into();
    let mut harness = settings_harness(settings.clone());
    harness.get_by_label("shadows.cache").click();
    harness.run();
    let (kept, error) = harness.state();
    assert_eq!(*kept, settings, "refused");
    assert!(error.as_deref().is_some_and(|e| e.contains("shadows.directional.filter")), "{error:?}");
}

#[test]
fn moving_a_cascade_split_keeps_the_splits_in_order() {
    let mut harness = settings_harness(Settings::default());
    harness.get_by_role_and_label(Role::Slider, "cascade 1 ends at").set_value_accesskit(0.6);
    harness.run();
    let (settings, error) = harness.state();
    assert_eq!(*error, None);
    let ratios = settings.shadows.directional.cascade_ratios.clone().expect("set");
    assert_eq!(ratios[0], 0.6);
    assert!(ratios.windows(2).all(|w| w[0] < w[1]) && ratios[2] < 1.0, "{ratios:?}");
}

#[test]
fn camera_buttons_ask_for_their_camera() {
    let cameras = vec!["overview".to_string(), String::new()];
    let mut harness =
        Harness::new_ui_state(|ui, state: &mut PanelState| cameras_panel(ui, &cameras, state), PanelState::default());
    harness.get_by_label("camera 1").click();
    harness.run();
    assert_eq!(harness.state().camera_request, Some(Some(1)));
    harness.get_by_label("reset view").click();
    harness.run();
    assert_eq!(harness.state().camera_request, Some(None));
    harness.get_by_label("frame selected").click();
    harness.run();
    assert!(harness.state().frame_requested);
}

#[test]
fn the_light_list_edits_the_scene_lights() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/assets/ShadowsSpot/glTF/shadows-spot.gltf");
    let scene = chiaro_scene::load_gltf(std::path::Path::new(path)).unwrap();
    let spot = scene.lights.iter().position(|l| matches!(l.kind, chiaro_scene::LightKind::Spot { .. })).unwrap();
    let mut harness = Harness::builder().with_size(egui::vec2(330.0, 290.0)).wgpu().build_ui_state(
        |ui, (lights, state): &mut (Vec<chiaro_scene::Light>, LightsState)| {
            lights_panel(ui, lights, state);
        },
        (
            scene.lights.clone(),
            LightsState { tiles: vec!["1 point/spot tiles (0), 2048 texels".into()], ..Default::default() },
        ),
    );
    harness.get_all_by_label_contains("(spot)").next().expect("a spot row").click();
    harness.run();
    harness.get_by_role_and_label(Role::Slider, "outer cone (deg)").set_value_accesskit(20.0);
    harness.run();
    harness.get_by_role_and_label(Role::Slider, "near plane (m)").set_value_accesskit(0.5);
    harness.run();
    harness.get_by_label("on").click();
    harness.run();
    let (lights, state) = harness.state();
    let light = &lights[spot];
    let chiaro_scene::LightKind::Spot { inner_cone_rad, outer_cone_rad } = light.kind else { unreachable!() };
    assert!((outer_cone_rad.to_degrees() - 20.0).abs() < 1e-3);
    assert!(inner_cone_rad < outer_cone_rad, "the inner cone gave way");
    assert_eq!(light.shadow.near_plane, 0.5);
    assert_eq!(light.intensity, 0.0, "switched off");
    assert_eq!(state.switched_off.get(&spot), Some(&scene.lights[spot].intensity));
    assert!(harness.query_by_label_contains("this frame: 1 point/spot tiles").is_some());
    harness.snapshot("light_list_spot");
}

#[test]
fn the_timings_graph_stacks_each_pass_under_the_frame_interval() {
    let mut state = PanelState::default();
    for i in 0..super::panel::GRAPH_FRAMES {
        let wobble = (i % 7) as f64;
        state.record(super::panel::FrameSample {
            cpu_ms: 1.0,
            passes: vec![("shadows", 2.0 + wobble), ("forward", 10.0), ("tonemap", 1.0)],
            interval_ms: Some(16.0 + wobble),
        });
    }
    state.gpu = Some(chiaro_render::GpuFrameTimes {
        frame: 7,
        passes: vec![("shadows", 2.0), ("forward", 10.0), ("tonemap", 1.0)],
    });
    let mut harness = Harness::builder()
        .with_size(egui::vec2(330.0, 260.0))
        .wgpu()
        .build_ui_state(|ui, state: &mut PanelState| super::panel::timings_panel(ui, state), state);
    assert!(harness.query_by_label_contains("forward: 10.00 ms").is_some());
    assert!(harness.query_by_label_contains("frame 19.0 ms").is_some(), "the median interval");
    harness.run();
    harness.snapshot("timings_graph");
}
