//! `chiaro view` in a real window on a virtual X display (Xvfb, which scripts/setup.sh
//! installs): it opens a shared scene, renders frames, writes `--screenshot`, exits 0, and
//! the screenshot matches `chiaro render` of the same camera and size.

mod common;

use common::{Run, chiaro};
use std::path::{Path, PathBuf};
use std::process::Command;

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

fn test_scene(name: &str) -> PathBuf {
    let path = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets")).join(name);
    assert!(path.exists(), "{} is missing", path.display());
    path
}

/// `chiaro view ARGS` under `xvfb-run`.
fn view_under_xvfb(args: &[&str], dir: &Path) -> Run {
    let output = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24", env!("CARGO_BIN_EXE_chiaro"), "view"])
        .args(args)
        .current_dir(dir)
        .output()
        .expect("xvfb-run is missing: install xvfb (scripts/setup.sh does)");
    Run {
        code: output.status.code().unwrap_or(-1),
        stderr: String::from_utf8_lossy(&output.stderr).into_owned(),
        stdout: String::from_utf8_lossy(&output.stdout).into_owned(),
    }
}

fn rgb(path: &Path) -> Vec<u8> {
    image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgb8().into_raw()
}

fn mean_flip(reference: &[u8], test: &[u8]) -> f32 {
    let error = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(WIDTH, HEIGHT, reference),
        nv_flip::FlipImageRgb8::with_data(WIDTH, HEIGHT, test),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    nv_flip::FlipPool::from_image(&error).mean()
}

#[test]
fn the_viewer_screenshot_and_window_show_what_chiaro_render_writes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = test_scene("ShadowsSpot/glTF/shadows-spot.gltf");
    let scene = scene.to_str().unwrap();
    let (w, h) = (WIDTH.to_string(), HEIGHT.to_string());
    let size = ["--width", w.as_str(), "--height", h.as_str()];
    let shot = view_under_xvfb(
        &[
            &[scene][..],
            &size,
            &["--screenshot", "shot.png", "--screenshot-window", "window.png", "--exit-after-frames", "3"],
        ]
        .concat(),
        dir.path(),
    );
    assert_eq!(shot.code, 0, "the viewer failed: {}", shot.stderr);
    assert!(shot.stderr.contains("after 3 frames"), "{}", shot.stderr);
    // The viewer opens under the default environment, as chiaro render does.
    let render = chiaro(&[&["render", scene][..], &size, &["-o", "render.png"]].concat(), &[], dir.path());
    assert_eq!(render.code, 0, "{}", render.stderr);
    let (shot, reference) = (rgb(&dir.path().join("shot.png")), rgb(&dir.path().join("render.png")));
    assert_eq!(shot.len(), reference.len(), "same size");
    let lit = reference.chunks(3).filter(|p| p.iter().any(|&c| c > 10)).count();
    assert!(lit * 10 > reference.len() / 3, "the scene is visible: {lit} pixels lit");
    let flip = mean_flip(&reference, &shot);
    println!("viewer screenshot against chiaro render: mean FLIP {flip}");
    assert!(flip < 0.01, "mean FLIP {flip}");

    // The window as the screen shows it: the view at its top-left corner, the panel beside.
    let window = image::open(dir.path().join("window.png")).unwrap().to_rgb8();
    assert!(window.width() > WIDTH && window.height() >= HEIGHT, "{}x{}", window.width(), window.height());
    let view = image::imageops::crop_imm(&window, 0, 0, WIDTH, HEIGHT).to_image().into_raw();
    let flip = mean_flip(&reference, &view);
    println!("the window's view against chiaro render: mean FLIP {flip}");
    assert!(flip < 0.01, "mean FLIP {flip}");
    let panel = image::imageops::crop_imm(&window, WIDTH, 0, window.width() - WIDTH, HEIGHT).to_image();
    let greys: std::collections::HashSet<u8> = panel.pixels().map(|p| p[0]).collect();
    assert!(greys.len() > 16, "the panel has text on it: {} grey levels", greys.len());
}

/// Mean absolute difference of two RGB8 images, as a share of full scale.
fn mean_abs_difference(a: &[u8], b: &[u8]) -> f64 {
    let sum: u64 = a.iter().zip(b).map(|(x, y)| u64::from(x.abs_diff(*y))).sum();
    sum as f64 / (a.len() as f64 * 255.0)
}

#[test]
fn a_sunlit_scene_in_the_viewer_is_what_chiaro_render_writes() {
    // Every front end opens under the same default environment: the viewer's screenshot
    // of a sun scene is chiaro render's image, not one washed out by a studio.
    let dir = tempfile::tempdir().unwrap();
    let scene = test_scene("ShadowsDirectional/glTF/shadows-directional.gltf");
    let scene = scene.to_str().unwrap();
    let (w, h) = (WIDTH.to_string(), HEIGHT.to_string());
    let size = ["--width", w.as_str(), "--height", h.as_str()];
    let shot = view_under_xvfb(
        &[&[scene][..], &size, &["--screenshot", "shot.png", "--exit-after-frames", "2"]].concat(),
        dir.path(),
    );
    assert_eq!(shot.code, 0, "the viewer failed: {}", shot.stderr);
    let render = chiaro(&[&["render", scene][..], &size, &["-o", "render.png"]].concat(), &[], dir.path());
    assert_eq!(render.code, 0, "{}", render.stderr);
    let (shot, reference) = (rgb(&dir.path().join("shot.png")), rgb(&dir.path().join("render.png")));
    let difference = mean_abs_difference(&reference, &shot);
    println!("viewer screenshot of a sun scene against chiaro render: mean absolute difference {difference:.5}");
    assert!(difference < 0.01, "mean absolute difference {difference}");
}

#[test]
fn a_debug_view_screenshot_equals_chiaro_render_with_the_same_debug_view() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (WIDTH.to_string(), HEIGHT.to_string());
    let size = ["--width", w.as_str(), "--height", h.as_str(), "--demo-lights", "2"];
    let shot = view_under_xvfb(
        &[&size[..], &["--debug", "cascades", "--screenshot", "shot.png", "--exit-after-frames", "2"]].concat(),
        dir.path(),
    );
    assert_eq!(shot.code, 0, "the viewer failed: {}", shot.stderr);
    let render =
        chiaro(&[&["render"][..], &size, &["--debug", "cascades", "-o", "render.png"]].concat(), &[], dir.path());
    assert_eq!(render.code, 0, "{}", render.stderr);
    let plain = chiaro(&[&["render"][..], &size, &["-o", "plain.png"]].concat(), &[], dir.path());
    assert_eq!(plain.code, 0, "{}", plain.stderr);
    let (shot, reference, plain) =
        (rgb(&dir.path().join("shot.png")), rgb(&dir.path().join("render.png")), rgb(&dir.path().join("plain.png")));
    let flip = mean_flip(&reference, &shot);
    println!("viewer --debug cascades against chiaro render --debug cascades: mean FLIP {flip}");
    assert!(flip < 0.01, "mean FLIP {flip}");
    assert!(mean_flip(&plain, &shot) > 0.05, "the screenshot is tinted by cascade");
}

#[test]
fn the_window_outlines_an_area_light_that_the_screenshot_leaves_out() {
    // The spot scene with a white 6 x 4 m rect light 3.5 m over its floor, shining down.
    let dir = tempfile::tempdir().unwrap();
    let path = copy_scene_folder("ShadowsSpot/glTF/shadows-spot.gltf", dir.path());
    let mut gltf: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    gltf["extensionsUsed"].as_array_mut().unwrap().push("EXT_lights_area".into());
    gltf["extensions"]["EXT_lights_area"] =
        serde_json::json!({"lights": [{"type": "rect", "intensity": 50, "size": 4, "rect": {"aspect": 1.5}}]});
    // A quarter turn about X (from -Z to -Y): its quaternion has sin 45 and cos 45.
    let sin_45 = std::f32::consts::FRAC_1_SQRT_2;
    let nodes = gltf["nodes"].as_array_mut().unwrap();
    nodes.push(serde_json::json!({"name": "Panel", "translation": [0, 3.5, 0],
        "rotation": [-sin_45, 0, 0, sin_45], "extensions": {"EXT_lights_area": {"light": 0}}}));
    let panel = nodes.len() - 1;
    gltf["scenes"][0]["nodes"].as_array_mut().unwrap().push(panel.into());
    std::fs::write(&path, gltf.to_string()).unwrap();

    let (w, h) = (WIDTH.to_string(), HEIGHT.to_string());
    let args = [path.to_str().unwrap(), "--width", &w, "--height", &h];
    let shot = view_under_xvfb(
        &[&args[..], &["--screenshot", "shot.png", "--screenshot-window", "window.png", "--exit-after-frames", "2"]]
            .concat(),
        dir.path(),
    );
    assert_eq!(shot.code, 0, "the viewer failed: {}", shot.stderr);
    let window = image::open(dir.path().join("window.png")).unwrap().to_rgb8();
    let view = image::imageops::crop_imm(&window, 0, 0, WIDTH, HEIGHT).to_image().into_raw();
    let screenshot = rgb(&dir.path().join("shot.png"));
    // The outline is white lines: pixels white in the window that the render has darker.
    let outline = view
        .chunks(3)
        .zip(screenshot.chunks(3))
        .filter(|(v, s)| v.iter().all(|&c| c >= 250) && s.iter().any(|&c| c < 200))
        .count();
    let changed = view.chunks(3).zip(screenshot.chunks(3)).filter(|(v, s)| v != s).count();
    println!("area light outline: {outline} white pixels, {changed} pixels differ from the screenshot");
    assert!(outline >= 60, "the rect's outline is drawn: {outline} pixels");
    assert!(changed < (WIDTH * HEIGHT / 10) as usize, "only lines are drawn over the view: {changed} pixels");
}

/// Copies the folder of a shared glTF into `dir`, so that the test can change the file.
fn copy_scene_folder(name: &str, dir: &Path) -> PathBuf {
    let source = test_scene(name);
    for entry in std::fs::read_dir(source.parent().unwrap()).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), dir.join(entry.file_name())).unwrap();
    }
    dir.join(source.file_name().unwrap())
}

#[test]
fn the_viewer_reloads_a_scene_whose_file_changes() {
    use std::io::{BufRead, BufReader};
    let dir = tempfile::tempdir().unwrap();
    let scene = copy_scene_folder("ShadowsSpot/glTF/shadows-spot.gltf", dir.path());
    let (w, h) = (WIDTH.to_string(), HEIGHT.to_string());
    let mut viewer = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24", env!("CARGO_BIN_EXE_chiaro"), "view"])
        .args([scene.to_str().unwrap(), "--width", &w, "--height", &h])
        .args(["--screenshot", "shot.png", "--exit-after-frames", "300"])
        .current_dir(dir.path())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("xvfb-run is missing: install xvfb (scripts/setup.sh does)");
    let mut stderr = BufReader::new(viewer.stderr.take().unwrap());
    let mut log = String::new();
    // Change the file once the window is up: the sphere moves 1.5 m along x.
    loop {
        let mut line = String::new();
        assert!(stderr.read_line(&mut line).unwrap() > 0, "the viewer ended before its window opened: {log}");
        log.push_str(&line);
        if line.contains("chiaro: viewing") {
            break;
        }
    }
    let mut gltf: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    let sphere = gltf["nodes"].as_array_mut().unwrap().iter_mut().find(|n| n["name"] == "Sphere").unwrap();
    sphere["translation"] = serde_json::json!([1.5, 1.1, 0.0]);
    let changed = dir.path().join("changed.gltf");
    std::fs::write(&changed, serde_json::to_string(&gltf).unwrap()).unwrap();
    std::fs::rename(&changed, &scene).unwrap();
    stderr.read_to_string_lossy(&mut log);
    let status = viewer.wait().unwrap();
    assert!(status.success(), "the viewer failed: {log}");
    assert!(log.contains(&format!("chiaro: reloaded {}", scene.display())), "no reload: {log}");
    // The screenshot shows the changed file, as chiaro render draws it.
    let size = ["--width", w.as_str(), "--height", h.as_str()];
    let render =
        chiaro(&[&["render", scene.to_str().unwrap()][..], &size, &["-o", "render.png"]].concat(), &[], dir.path());
    assert_eq!(render.code, 0, "{}", render.stderr);
    let shot = rgb(&dir.path().join("shot.png"));
    let flip = mean_flip(&rgb(&dir.path().join("render.png")), &shot);
    assert!(flip < 0.01, "the reloaded view against chiaro render of the changed file: mean FLIP {flip}");
    let original = test_scene("ShadowsSpot/glTF/shadows-spot.gltf");
    let before =
        chiaro(&[&["render", original.to_str().unwrap()][..], &size, &["-o", "before.png"]].concat(), &[], dir.path());
    assert_eq!(before.code, 0, "{}", before.stderr);
    let before = rgb(&dir.path().join("before.png"));
    let moved = before.chunks(3).zip(shot.chunks(3)).filter(|(a, b)| a.iter().zip(*b).any(|(x, y)| x.abs_diff(*y) > 8));
    let moved = moved.count();
    assert!(moved > 200, "the moved sphere shows: {moved} pixels differ from the file as it was");
}

/// Reads what is left of a stream, as text.
trait ReadRest {
    fn read_to_string_lossy(&mut self, into: &mut String);
}

impl<R: std::io::Read> ReadRest for R {
    fn read_to_string_lossy(&mut self, into: &mut String) {
        let mut bytes = Vec::new();
        let _ = self.read_to_end(&mut bytes);
        into.push_str(&String::from_utf8_lossy(&bytes));
    }
}

#[test]
fn viewer_arguments_are_checked_before_a_window_opens() {
    let dir = tempfile::tempdir().unwrap();
    // These fail without a display, so no Xvfb is needed.
    let run = chiaro(&["view", "--screenshot", "shot.png"], &[], dir.path());
    assert_ne!(run.code, 0);
    assert!(run.stderr.contains("--exit-after-frames"), "{}", run.stderr);
    let run =
        chiaro(&["view", "missing.gltf", "--screenshot", "shot.png", "--exit-after-frames", "1"], &[], dir.path());
    assert_ne!(run.code, 0);
    assert!(run.stderr.contains("missing.gltf"), "{}", run.stderr);
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    let run = chiaro(&["view", "--debug", "wireframe"], &[], dir.path());
    assert_ne!(run.code, 0);
    assert!(run.stderr.contains("'wireframe' is not a debug view"), "{}", run.stderr);
}
