//! The panel under egui_kittest (egui's headless harness, drawn with wgpu on lavapipe):
//! edits reach the settings, the frame plan and the rendered view; invalid edits are
//! refused; every documented settings key has its widget; snapshots of the panel.

use super::controls::cameras_panel;
use super::lights::lights_panel;
use super::settings::settings_panel;
use crate::action::Action;
use crate::camera::Navigation;
use crate::state::{FrameSample, FrameStats, GRAPH_FRAMES};
use crate::{Viewer, ViewerConfig};
use chiaro_render::plan::draws::{GeometryLayout, scene_draws};
use chiaro_render::plan::shadows::ShadowAtlasTiles;
use chiaro_render::{FrameOptions, FramePlan, GpuContext, Renderer, View};
use chiaro_scene::{Scene, Settings};
use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

/// A viewer (no window) of `scene` with `settings`.
fn viewer(scene: Scene, settings: Settings) -> Viewer {
    let view = View::from_camera(&scene, 0, 64, 64);
    Viewer::new(ViewerConfig::new(scene, settings, view))
}

/// The settings panel over a viewer: what it asks for is applied as the window applies it.
fn settings_harness<'a>(settings: Settings) -> Harness<'a, Viewer> {
    let viewer = viewer(chiaro_scene::demo::demo_scene(0), settings);
    Harness::builder().with_size(egui::vec2(360.0, 800.0)).wgpu().build_ui_state(
        |ui, viewer: &mut Viewer| {
            let actions = settings_panel(ui, &viewer.state.settings.current, Default::default());
            viewer.apply_all(actions);
        },
        viewer,
    )
}

/// The settings a harness's viewer kept, and the error it shows.
fn kept(harness: &Harness<'_, Viewer>) -> (Settings, Option<String>) {
    let state = &harness.state().state;
    (state.settings.current.clone(), state.panel.error.clone())
}

/// The light list over a viewer of `scene`; `drawn`: rendered with wgpu, for snapshots.
fn lights_harness<'a>(scene: Scene, size: egui::Vec2, tiles: Vec<String>, drawn: bool) -> Harness<'a, Viewer> {
    let mut viewer = viewer(scene, Settings::default());
    viewer.state.panel.lights.tiles = tiles;
    let builder = Harness::builder().with_size(size);
    let builder = if drawn { builder.wgpu() } else { builder };
    builder.build_ui_state(
        |ui, viewer: &mut Viewer| {
            let state = &viewer.state;
            let actions = lights_panel(ui, &state.scene.scene.lights, &state.panel.lights);
            viewer.apply_all(actions);
        },
        viewer,
    )
}

fn plan(scene: &Scene, settings: &Settings) -> FramePlan {
    let view = View::from_camera(scene, 0, 64, 64);
    let draws = scene_draws(scene, &GeometryLayout::of(scene));
    FramePlan::new(scene, &draws, &view, settings, &ShadowAtlasTiles::default(), Default::default())
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
    let (after, error) = kept(&harness);
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
    crate::save_scene::save_settings(&path, &after).unwrap();
    let saved = chiaro_io::scenes::load_settings(Some(&path)).unwrap();
    assert_eq!(rendered_view(&scene, &saved), shown_after);
    harness.snapshot("settings_panel_after_edit");
}

#[test]
fn drawing_a_light_does_not_clamp_what_the_file_set() {
    let mut sun = chiaro_scene::Light::new(chiaro_scene::LightKind::Directional, glam::Vec3::ZERO, glam::Vec3::NEG_Y);
    sun.intensity = 120_000.0;
    sun.shadow.depth_bias = 25.0;
    let scene = Scene { lights: vec![sun], ..chiaro_scene::demo::demo_scene(0) };
    let mut harness = lights_harness(scene, egui::vec2(330.0, 300.0), Vec::new(), false);
    harness.get_all_by_label_contains("(directional)").next().expect("the sun's row").click();
    harness.run();
    assert!(harness.query_by_role_and_label(Role::Slider, "depth bias").is_some(), "the row is open");
    let lights = &harness.state().state.scene.scene.lights;
    assert_eq!(lights[0].intensity, 120_000.0);
    assert_eq!(lights[0].shadow.depth_bias, 25.0);
}

#[test]
fn the_light_list_names_the_tiles_each_light_got() {
    let scene = chiaro_scene::demo::demo_scene_with_shadows(4, 1, 1);
    let tiles = super::lights::tiles_by_light(&plan(&scene, &Settings::default()), scene.lights.len());
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
    let (kept, error) = kept(&harness);
    assert_eq!(kept, settings, "refused");
    assert!(error.as_deref().is_some_and(|e| e.contains("shadows.directional.filter")), "{error:?}");
}

#[test]
fn moving_a_cascade_split_keeps_the_splits_in_order() {
    let mut harness = settings_harness(Settings::default());
    harness.get_by_role_and_label(Role::Slider, "cascade 1 ends at").set_value_accesskit(0.6);
    harness.run();
    let (settings, error) = kept(&harness);
    assert_eq!(error, None);
    let ratios = settings.shadows.directional.cascade_ratios.clone().expect("set");
    assert_eq!(ratios[0], 0.6);
    assert!(ratios.windows(2).all(|w| w[0] < w[1]) && ratios[2] < 1.0, "{ratios:?}");
}

#[test]
fn camera_buttons_ask_for_their_camera() {
    let cameras = vec!["overview".to_string(), String::new()];
    // Every action the buttons asked for, in order.
    let mut harness = Harness::new_ui_state(
        |ui, asked: &mut Vec<Action>| asked.extend(cameras_panel(ui, &cameras, Navigation::Orbit)),
        Vec::new(),
    );
    harness.get_by_label("camera 1").click();
    harness.run();
    assert!(matches!(harness.state().last(), Some(Action::SelectCamera(1))), "{:?}", harness.state());
    harness.get_by_label("reset view").click();
    harness.run();
    assert!(matches!(harness.state().last(), Some(Action::ResetView)), "{:?}", harness.state());
    harness.get_by_label("frame selected").click();
    harness.run();
    assert!(matches!(harness.state().last(), Some(Action::FrameSelected)), "{:?}", harness.state());
}

#[test]
fn an_area_lights_row_edits_its_size_in_nits_and_metres() {
    let mut rect = chiaro_scene::Light::new(
        chiaro_scene::LightKind::Rect { width: 1.0, height: 0.5 },
        glam::Vec3::new(0.0, 3.0, 0.0),
        glam::Vec3::NEG_Y,
    );
    rect.name = "panel".into();
    rect.intensity = 500.0;
    rect.shadow.mode = chiaro_scene::ShadowMode::Pcss;
    let scene = Scene { lights: vec![rect], ..chiaro_scene::demo::demo_scene(0) };
    let mut harness = lights_harness(scene, egui::vec2(330.0, 400.0), Vec::new(), false);
    harness.get_all_by_label_contains("(rect)").next().expect("the rect's row").click();
    harness.run();
    assert!(harness.query_by_role_and_label(Role::Slider, "intensity (nits)").is_some());
    assert!(
        harness.query_by_role_and_label(Role::Slider, "light radius (m)").is_none(),
        "its shape sizes its penumbra"
    );
    harness.get_by_role_and_label(Role::Slider, "width (m)").set_value_accesskit(2.0);
    harness.run();
    harness.get_by_role_and_label(Role::Slider, "height (m)").set_value_accesskit(0.25);
    harness.run();
    let light = &harness.state().state.scene.scene.lights[0];
    assert_eq!(light.kind, chiaro_scene::LightKind::Rect { width: 2.0, height: 0.25 });
    assert_eq!(light.intensity, 500.0);
}

#[test]
fn the_side_panel_switches_the_area_lights_outlines_off_and_on() {
    let rect = chiaro_scene::Light::new(
        chiaro_scene::LightKind::Rect { width: 1.0, height: 0.5 },
        glam::Vec3::new(0.0, 3.0, 0.0),
        glam::Vec3::NEG_Y,
    );
    let label = "draw rect and disk lights' outlines";
    let plain = viewer(chiaro_scene::demo::demo_scene(0), Settings::default());
    let mut harness = Harness::builder().with_size(egui::vec2(360.0, 6000.0)).build_ui_state(
        |ui, viewer: &mut Viewer| {
            let actions = super::side_panel(ui, &viewer.state);
            viewer.apply_all(actions);
        },
        plain,
    );
    harness.run();
    assert!(harness.query_by_label(label).is_none(), "no area light, no switch");
    let scene = Scene { lights: vec![rect], ..chiaro_scene::demo::demo_scene(0) };
    harness.state_mut().state.scene.scene = scene;
    harness.run();
    assert!(!harness.state().state.panel.lights.shapes_hidden, "drawn by default");
    harness.get_by_label(label).click();
    harness.run();
    assert!(harness.state().state.panel.lights.shapes_hidden);
    harness.get_by_label(label).click();
    harness.run();
    assert!(!harness.state().state.panel.lights.shapes_hidden);
}

#[test]
fn the_light_list_edits_the_scene_lights() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets/ShadowsSpot/glTF/shadows-spot.gltf");
    let scene = chiaro_scene::load_gltf(std::path::Path::new(path)).unwrap();
    let spot = scene.lights.iter().position(|l| matches!(l.kind, chiaro_scene::LightKind::Spot { .. })).unwrap();
    let tiles = vec!["1 point/spot tiles (0), 2048 texels".into()];
    let mut harness = lights_harness(scene.clone(), egui::vec2(330.0, 290.0), tiles, true);
    harness.get_all_by_label_contains("(spot)").next().expect("a spot row").click();
    harness.run();
    harness.get_by_role_and_label(Role::Slider, "outer cone (deg)").set_value_accesskit(20.0);
    harness.run();
    harness.get_by_role_and_label(Role::Slider, "near plane (m)").set_value_accesskit(0.5);
    harness.run();
    harness.get_by_label("on").click();
    harness.run();
    let state = &harness.state().state;
    let light = &state.scene.scene.lights[spot];
    let chiaro_scene::LightKind::Spot { inner_cone_rad, outer_cone_rad } = light.kind else { unreachable!() };
    assert!((outer_cone_rad.to_degrees() - 20.0).abs() < 1e-3);
    assert!(inner_cone_rad < outer_cone_rad, "the inner cone gave way");
    assert_eq!(light.shadow.near_plane, 0.5);
    assert_eq!(light.intensity, 0.0, "switched off");
    assert_eq!(state.panel.lights.switched_off.get(&spot), Some(&scene.lights[spot].intensity));
    assert!(harness.query_by_label_contains("this frame: 1 point/spot tiles").is_some());
    harness.snapshot("light_list_spot");
}

#[test]
fn the_timings_graph_stacks_each_pass_under_the_frame_interval() {
    let mut state = FrameStats::default();
    for i in 0..GRAPH_FRAMES {
        let wobble = (i % 7) as f64;
        state.record(FrameSample {
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
        .build_ui_state(|ui, stats: &mut FrameStats| super::timings::timings_panel(ui, stats), state);
    assert!(harness.query_by_label_contains("forward: 10.00 ms").is_some());
    assert!(harness.query_by_label_contains("frame 19.0 ms").is_some(), "the median interval");
    harness.run();
    harness.snapshot("timings_graph");
}

#[test]
fn the_whole_panel_changes_the_viewer_only_through_actions() {
    let scene = chiaro_scene::demo::demo_scene_with_shadows(4, 1, 1);
    let mut harness = Harness::builder().with_size(egui::vec2(340.0, 2400.0)).build_ui_state(
        |ui, viewer: &mut Viewer| {
            let actions = super::side_panel(ui, &viewer.state);
            viewer.apply_all(actions);
        },
        viewer(scene, Settings::default()),
    );
    harness.get_by_label("Save scene").click();
    harness.run();
    let status = harness.state().state.panel.status.clone();
    assert_eq!(status.as_deref(), Some("not saved: the demo scene has no file"));

    harness.get_by_role_and_label(Role::ComboBox, "debug view").click();
    harness.run();
    // An early item: the list scrolls, and a click lands only on what it shows.
    harness.get_by_role_and_label(Role::Button, "cascades").click();
    harness.run();
    assert_eq!(harness.state().state.debug, Some(chiaro_render::DebugView::Cascades));

    harness.get_by_label("fly").click();
    harness.run();
    assert_eq!(harness.state().state.camera.navigation, Navigation::Fly);
}
