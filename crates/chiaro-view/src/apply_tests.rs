//! `Viewer::apply` without a window: each action changes the state as it should, and what
//! needs a window or is refused says so where the user looks.

use crate::action::Action;
use crate::camera::Navigation;
use crate::loader::Loaded;
use crate::state::Selection;
use crate::{Viewer, ViewerConfig};
use chiaro_render::{AovView, DebugView, FrameOptions, View};
use chiaro_scene::{LightKind, Scene, Settings};
use std::path::{Path, PathBuf};

fn asset(name: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets")).join(name)
}

fn viewer_of(scene: Scene, path: Option<PathBuf>) -> Viewer {
    let view = View::from_camera(&scene, 0, 64, 48);
    let mut settings = Settings::default();
    (settings.render.width, settings.render.height) = (64, 48);
    Viewer::new(ViewerConfig { scene_path: path, ..ViewerConfig::new(scene, settings, view) })
}

fn demo_viewer() -> Viewer {
    viewer_of(chiaro_scene::demo::demo_scene_with_shadows(4, 1, 1), None)
}

/// The spot scene (it has a glTF camera), from its file.
fn spot_viewer() -> Viewer {
    let path = asset("ShadowsSpot/glTF/shadows-spot.gltf");
    viewer_of(chiaro_scene::load_gltf(&path).unwrap(), Some(path))
}

#[test]
fn an_invalid_setting_is_refused_and_reported() {
    let mut viewer = demo_viewer();
    let before = viewer.state.settings.current.clone();
    let mut invalid = before.clone();
    invalid.shadows.directional.filter = "bilinear".into();
    viewer.apply(Action::SetSettings(Box::new(invalid)));
    assert_eq!(viewer.state.settings.current, before, "not kept");
    let error = viewer.state.panel.error.clone().unwrap_or_default();
    assert!(error.contains("shadows.directional.filter"), "{error}");
    assert!(viewer.panel.dirty, "the panel shows the error");

    let mut valid = before.clone();
    valid.shadows.max_distance = 42.0;
    viewer.apply(Action::SetSettings(Box::new(valid.clone())));
    assert_eq!(viewer.state.settings.current, valid);
    assert_eq!(viewer.state.panel.error, None, "an accepted edit clears the error");
}

/// The panel's `scene.variant` gives the scene its variant's materials; a name the scene
/// lacks is refused and shown.
#[test]
fn the_variant_setting_switches_the_scenes_materials() {
    let mut scene = chiaro_scene::demo::demo_scene(0);
    let default_material = scene.meshes[0].primitives[0].material;
    scene.variants = chiaro_scene::MaterialVariants {
        names: vec!["Blue".into()],
        mappings: vec![chiaro_scene::VariantMapping {
            mesh: 0,
            primitive: 0,
            default_material,
            materials: vec![(0, scene.materials.len())],
        }],
        selected: None,
    };
    let mut viewer = viewer_of(scene, None);
    let mut blue = viewer.state.settings.current.clone();
    blue.scene.variant = Some("Blue".into());
    viewer.apply(Action::SetSettings(Box::new(blue.clone())));
    assert_eq!(viewer.state.panel.error, None);
    assert_eq!(viewer.state.settings.current, blue);
    let material = |viewer: &Viewer| viewer.state.scene.scene.meshes[0].primitives[0].material;
    assert_eq!(material(&viewer), Some(viewer.state.scene.scene.materials.len()));
    let mut red = blue.clone();
    red.scene.variant = Some("Red".into());
    viewer.apply(Action::SetSettings(Box::new(red)));
    assert_eq!(viewer.state.settings.current, blue, "not kept");
    let error = viewer.state.panel.error.clone().unwrap_or_default();
    assert!(error.contains("scene.variant: no material variant 'Red'; the scene has: Blue"), "{error}");
    let mut plain = blue;
    plain.scene.variant = None;
    viewer.apply(Action::SetSettings(Box::new(plain)));
    assert_eq!(material(&viewer), default_material);
}

#[test]
fn a_new_view_size_in_the_settings_resizes_the_view() {
    let mut viewer = demo_viewer();
    let mut settings = viewer.state.settings.current.clone();
    settings.render.width = 100;
    settings.render.height = 50;
    viewer.apply(Action::SetSettings(Box::new(settings)));
    assert_eq!(viewer.state.camera.view_size(), (100, 50));
    let view = viewer.state.current_view();
    assert_eq!((view.width, view.height), (100, 50));
}

#[test]
fn editing_and_switching_a_light_change_the_scene_light() {
    let mut viewer = demo_viewer();
    let spot = viewer.state.scene.scene.lights.iter().position(|l| matches!(l.kind, LightKind::Spot { .. })).unwrap();
    let mut light = viewer.state.scene.scene.lights[spot].clone();
    light.intensity = 123.0;
    light.color = glam::Vec3::new(1.0, 0.5, 0.25);
    viewer.apply(Action::EditLight { index: spot, light: Box::new(light) });
    let edited = &viewer.state.scene.scene.lights[spot];
    assert_eq!((edited.intensity, edited.color), (123.0, glam::Vec3::new(1.0, 0.5, 0.25)));

    viewer.apply(Action::SwitchLight { index: spot, on: false });
    assert_eq!(viewer.state.scene.scene.lights[spot].intensity, 0.0);
    viewer.apply(Action::SwitchLight { index: spot, on: true });
    assert_eq!(viewer.state.scene.scene.lights[spot].intensity, 123.0, "switched on, it gets its intensity back");
    // A light that is not there is left alone.
    viewer.apply(Action::SwitchLight { index: 999, on: false });
    assert!(viewer.state.panel.lights.switched_off.is_empty());
}

#[test]
fn the_debug_view_decides_the_frame_options() {
    let mut viewer = demo_viewer();
    let options = |v: &Viewer| format!("{:?}", v.state.frame_options());
    assert_eq!(options(&viewer), format!("{:?}", FrameOptions::default()));
    for debug in [DebugView::Clusters, DebugView::Aov(AovView::Depth), DebugView::ShadowAtlases, DebugView::Cascades] {
        viewer.apply(Action::SetDebugView(Some(debug)));
        assert_eq!(viewer.state.debug, Some(debug));
        assert_eq!(options(&viewer), format!("{:?}", debug.frame_options()), "{debug:?}");
    }
    assert!(viewer.state.frame_options().aovs || viewer.state.debug == Some(DebugView::Cascades));
    viewer.apply(Action::SetDebugView(None));
    assert_eq!(options(&viewer), format!("{:?}", FrameOptions::default()));
}

#[test]
fn camera_actions_move_the_view_and_reset_brings_it_back() {
    let mut viewer = spot_viewer();
    let opening = viewer.state.current_view().world_from_view;
    viewer.apply(Action::Drag { dx: 120.0, dy: 10.0 });
    assert_ne!(viewer.state.current_view().world_from_view, opening, "a drag orbits");
    viewer.apply(Action::Zoom(2.0));
    viewer.apply(Action::ResetView);
    assert_eq!(viewer.state.current_view().world_from_view, opening);

    viewer.apply(Action::NextCamera);
    assert_eq!(viewer.state.camera.camera, Some(0));
    viewer.apply(Action::SelectCamera(0));
    assert_eq!(
        viewer.state.current_view().world_from_view,
        View::from_camera(&viewer.state.scene.scene, 0, 64, 48).world_from_view
    );

    viewer.apply(Action::SetNavigation(Navigation::Fly));
    let eye = viewer.state.current_view().eye();
    let forward = crate::camera::FlyInput::new(0.0, 0.0, -1.0);
    viewer.apply(Action::Fly { input: forward, fast: false, seconds: 0.1 });
    assert!(viewer.state.current_view().eye().distance(eye) > 0.0, "the keys fly");
}

#[test]
fn frame_selected_looks_at_the_selected_light() {
    let mut viewer = demo_viewer();
    let scene = &viewer.state.scene.scene;
    let spot = scene.lights.iter().position(|l| matches!(l.kind, LightKind::Spot { .. })).unwrap();
    let at = scene.lights[spot].position();
    viewer.apply(Action::Select(Some(Selection::Light(spot))));
    viewer.apply(Action::FrameSelected);
    let rig = viewer.state.camera.rig.expect("the camera moved");
    assert!(rig.target.distance(at) < 1e-4, "{} vs {at}", rig.target);
}

#[test]
fn a_click_selects_what_it_points_at() {
    let mut viewer = demo_viewer();
    // The sky in the demo view's top-left corner, then something at its centre.
    viewer.apply(Action::Pick { x: 0.0, y: 0.0 });
    assert_eq!(viewer.state.panel.lights.selected, None);
    let (w, h) = viewer.state.camera.view_size();
    viewer.apply(Action::Pick { x: w as f32 / 2.0, y: h as f32 * 0.75 });
    assert!(matches!(viewer.state.panel.lights.selected, Some(Selection::Object(_))));
}

#[test]
fn without_a_window_a_screenshot_says_why_and_a_scripted_one_ends_the_run() {
    let mut viewer = demo_viewer();
    viewer.apply(Action::Screenshot { path: "never.png".into(), fatal: false });
    assert_eq!(viewer.state.panel.status.as_deref(), Some("no screenshot: no frame was rendered"));
    assert!(viewer.failure.is_none() && !viewer.quit);
    viewer.apply_all([Action::Screenshot { path: "never.png".into(), fatal: true }, Action::Quit { report: true }]);
    assert_eq!(viewer.failure.as_ref().map(|e| e.to_string()).as_deref(), Some("no frame was rendered"));
    assert!(viewer.quit);
    assert!(!Path::new("never.png").exists());
}

#[test]
fn saving_writes_the_settings_and_refuses_the_demo_scene() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("tuned.toml");
    let mut viewer = demo_viewer();
    viewer.state.settings.file = Some(file.clone());
    viewer.state.settings.current.shadows.max_distance = 17.0;
    viewer.apply(Action::SaveSettings);
    assert_eq!(viewer.state.panel.status, Some(format!("saved {}", file.display())));
    let saved = chiaro_io::scenes::load_settings(Some(&file)).unwrap();
    assert_eq!(saved, viewer.state.settings.current);
    viewer.apply(Action::SaveScene);
    assert_eq!(viewer.state.panel.status.as_deref(), Some("not saved: the demo scene has no file"));
}

#[test]
fn a_scene_that_failed_to_load_is_reported_and_the_old_one_stays() {
    let mut viewer = spot_viewer();
    let lights = viewer.state.scene.scene.lights.len();
    let failed = Loaded { path: "broken.gltf".into(), reload: false, scene: Err(anyhow::anyhow!("broken.gltf: bad")) };
    viewer.apply(Action::SceneLoaded(Box::new(failed)));
    assert_eq!(viewer.state.panel.error.as_deref(), Some("broken.gltf: bad"));
    assert_eq!(viewer.state.scene.scene.lights.len(), lights);

    viewer.apply(Action::Open(asset("ShadowsDirectional/glTF/shadows-directional.gltf")));
    assert!(viewer.state.jobs.loader.loading().is_some(), "read on the loader's thread");
}

#[test]
fn frames_shown_are_counted_for_the_summary() {
    let mut viewer = demo_viewer();
    assert_eq!(viewer.state.stats.summary(), None);
    viewer.apply(Action::FrameShown { interval_ms: None });
    viewer.apply(Action::FrameShown { interval_ms: Some(10.0) });
    viewer.apply(Action::FrameShown { interval_ms: Some(30.0) });
    assert_eq!(viewer.state.stats.frames, 3);
    let summary = viewer.state.stats.summary().unwrap();
    assert!(summary.starts_with("chiaro: 3 frames shown") && summary.contains("median 30.0 ms"), "{summary}");
    viewer.apply(Action::Quit { report: false });
    assert!(viewer.quit && viewer.failure.is_none());
}

#[test]
fn the_timeline_poses_the_scene_and_the_rest_pose_returns() {
    // The spot scene's animations move its spot light and a cone.
    let mut viewer = spot_viewer();
    let duration = viewer.state.scene.scene.animation_duration().expect("the spot scene is animated");
    let rest = viewer.state.scene.scene.lights[0].world_from_light;
    viewer.apply(Action::SetTime(Some(duration * 0.5)));
    assert_eq!(viewer.state.timeline.time, Some(duration * 0.5));
    let moved = viewer.state.scene.scene.lights[0].world_from_light;
    assert!(!moved.abs_diff_eq(rest, 1e-4), "the animated light moved");
    let mut posed = chiaro_scene::load_gltf(&asset("ShadowsSpot/glTF/shadows-spot.gltf")).unwrap();
    posed.pose(Some(duration * 0.5)).unwrap();
    assert_eq!(posed.lights[0].world_from_light, moved, "as the file posed at that time");

    viewer.apply(Action::Play(true));
    assert!(viewer.state.timeline.playing);
    viewer.apply(Action::SetTime(None));
    assert_eq!(viewer.state.scene.scene.lights[0].world_from_light, rest);
    viewer.apply(Action::SetTime(Some(f32::NAN)));
    assert!(viewer.state.panel.error.as_deref().is_some_and(|e| e.starts_with("time: ")));
    assert_eq!(viewer.state.timeline.time, None, "a refused time is not kept");

    // A scene without animations does not play, and playing wraps at the duration.
    let mut still = demo_viewer();
    still.apply(Action::Play(true));
    assert!(!still.state.timeline.playing);
    let timeline = crate::state::TimelineState { time: Some(3.5), playing: true };
    assert!((timeline.advanced(1.0, 4.0) - 0.5).abs() < 1e-6);
    assert_eq!(timeline.advanced(1.0, 0.0), 0.0);
}

#[test]
fn a_dropped_environment_image_lights_the_scene_and_a_bad_one_is_reported() {
    use chiaro_scene::settings::EnvironmentSource;
    let dir = std::env::temp_dir().join(format!("chiaro-view-drop-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, width: u32, height: u32| {
        let path = dir.join(name);
        let texels = vec![glam::Vec3::splat(0.5); (width * height) as usize];
        let map = chiaro_scene::environment::EnvironmentMap { width, height, texels };
        map.write_hdr(&path).unwrap();
        path
    };
    let mut viewer = demo_viewer();
    let good = write("studio.hdr", 16, 8);
    viewer.apply(crate::input::dropped_file(good.clone(), &viewer.state.settings.current));
    assert_eq!(viewer.state.settings.current.environment.source, EnvironmentSource::File(good.clone()));
    assert_eq!(viewer.state.panel.error, None);

    let square = write("square.hdr", 8, 8);
    viewer.apply(crate::input::dropped_file(square, &viewer.state.settings.current));
    assert_eq!(viewer.state.settings.current.environment.source, EnvironmentSource::File(good), "kept");
    let error = viewer.state.panel.error.clone().unwrap_or_default();
    assert!(error.contains("square.hdr") && error.contains("not equirectangular"), "{error}");

    // Anything else dropped is a scene to open.
    let scene = asset("ShadowsSpot/glTF/shadows-spot.gltf");
    assert!(matches!(crate::input::dropped_file(scene, &Settings::default()), Action::Open(_)));
}

#[test]
fn the_viewer_opens_every_file_under_the_default_environment_as_chiaro_render_does() {
    use chiaro_scene::environment::{EnvironmentMap, SceneEnvironment};
    use chiaro_scene::settings::EnvironmentSource;
    let path = asset("ShadowsSpot/glTF/shadows-spot.gltf");
    let plain = chiaro_scene::load_gltf(&path).unwrap();
    let own = SceneEnvironment::new("EXT_lights_image_based light 0".into(), EnvironmentMap::uniform(glam::Vec3::ONE));
    let carrying = Scene { environment: Some(own), ..plain.clone() };
    let opened = |scene: &Scene| {
        let view = View::from_camera(scene, 0, 64, 48);
        let config = ViewerConfig {
            scene_path: Some(path.clone()),
            ..ViewerConfig::new(scene.clone(), Settings::default(), view)
        };
        Viewer::new(config)
    };
    let source = |v: &Viewer| v.state.settings.current.environment.source.clone();
    // `none`: the file's own EXT_lights_image_based light where it has one, else the
    // ambient term; never a studio the file did not ask for.
    assert_eq!(source(&opened(&plain)), EnvironmentSource::None);
    assert_eq!(source(&opened(&carrying)), EnvironmentSource::None);
    assert_eq!(Settings::default().environment.source, EnvironmentSource::None);
}
