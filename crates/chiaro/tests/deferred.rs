//! The deferred path and cookies from the command line: `--path`, `[render] path` and
//! `light_buffer`, the deferred debug views, and cookie files that work or fail with an
//! error naming the file and the light.

mod common;

use common::*;

/// `scene.gltf`: the triangle (facing +Y) under a light on node 1, 1 m above it, shining
/// down, with `extras` and the image `cookie.png`.
fn lit_triangle(light_type: &str, extras: &str) -> String {
    format!(
        r#"{{
  "asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0, 1]}}],
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {{"KHR_lights_punctual": {{"lights": [
    {{"name": "gobo", "type": "{light_type}", "intensity": 20, "spot": {{"outerConeAngle": 0.7}}, "extras": {extras}}}
  ]}}}},
  "nodes": [{{"mesh": 0}}, {{"translation": [0.3, 1, -0.3], "rotation": [-0.7071068, 0, 0, 0.7071068],
             "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}}],
  "images": [{{"uri": "cookie.png"}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
  "buffers": [{{"uri": "{TRIANGLE_BUFFER}", "byteLength": 36}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, -1], "max": [1, 0, 0]}}]
}}"#
    )
}

fn png(width: u32, height: u32) -> Vec<u8> {
    let image = image::RgbaImage::from_fn(width, height, |x, _| image::Rgba([(x * 40) as u8, 200, 90, 255]));
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write_to(&mut bytes, image::ImageFormat::Png).unwrap();
    bytes.into_inner()
}

fn run_in(files: &[(&str, &[u8])], args: &[&str]) -> (tempfile::TempDir, Run) {
    let dir = tempfile::tempdir().unwrap();
    for (name, content) in files {
        std::fs::write(dir.path().join(name), content).unwrap();
    }
    let run = chiaro(args, &[], dir.path());
    assert_eq!(run.code, 0, "{args:?}: {}", run.stderr);
    (dir, run)
}

#[test]
fn cookies_of_every_light_type_render_on_both_paths() {
    for (light_type, extras, image) in [
        ("spot", r#"{"cookie": {"image": 0}}"#, png(4, 4)),
        ("point", r#"{"cookie": {"image": 0}}"#, png(24, 4)),
        ("directional", r#"{"cookie": {"image": 0, "size": [0.5, 0.25]}}"#, png(4, 4)),
    ] {
        let scene = lit_triangle(light_type, extras);
        for path in ["forward", "deferred"] {
            let files: [(&str, &[u8]); 2] = [("scene.gltf", scene.as_bytes()), ("cookie.png", &image)];
            let (dir, _) = run_in(&files, &["render", "scene.gltf", "--path", path, "-o", "out.exr"]);
            let rgb = read_exr_channels(&dir.path().join("out.exr"));
            let lit = rgb[1].1.iter().filter(|v| **v > 0.0).count();
            assert!(lit > 100, "{light_type} {path}: {lit} pixels lit");
        }
    }
}

#[test]
fn bad_cookies_name_the_file_and_the_light() {
    let image = png(4, 4);
    for (light_type, extras, needle) in [
        ("point", r#"{"cookie": {"image": 0}}"#, "six square faces"),
        ("spot", r#"{"cookie": {"image": 3}}"#, "extras.cookie.image: 3"),
        ("directional", r#"{"cookie": {"image": 0}}"#, "extras.cookie.size"),
        ("spot", r#"{"cookie": {"image": 0, "tiles": 2}}"#, "tiles"),
    ] {
        let scene = lit_triangle(light_type, extras);
        expect_failure(
            &[("scene.gltf", scene.as_bytes()), ("cookie.png", &image)],
            &["render", "scene.gltf", "-o", "out.png"],
            &[],
            &["scene.gltf", "gobo", needle],
        );
    }
    // A cookie image that is not there.
    let scene = lit_triangle("spot", r#"{"cookie": {"image": 0}}"#);
    expect_failure(
        &[("scene.gltf", scene.as_bytes())],
        &["render", "scene.gltf", "-o", "out.png"],
        &[],
        &["scene.gltf", "gobo", "cookie.png"],
    );
}

/// `chiaro bench --json` on the demo at 48x48 for two frames, with `files` in its folder:
/// the report it prints.
fn bench_json(files: &[(&str, &[u8])], args: &[&str]) -> serde_json::Value {
    let mut all = vec!["bench", "--json", "--width", "48", "--height", "48", "--frames", "2"];
    all.extend(args);
    let (_, run) = run_in(files, &all);
    serde_json::from_str(&run.stdout).unwrap_or_else(|e| panic!("bench --json printed no JSON ({e}): {}", run.stdout))
}

#[test]
fn the_path_comes_from_the_flag_or_the_settings() {
    let report = bench_json(&[], &["--path", "deferred"]);
    assert_eq!(report["path"], "deferred", "{report}");
    let passes = report["passes"].as_object().unwrap_or_else(|| panic!("no passes: {report}"));
    for pass in ["gbuffer", "deferred lights", "tonemap"] {
        assert!(passes.contains_key(pass), "no '{pass}' pass: {report}");
    }
    assert!(!passes.contains_key("forward"), "the demo has nothing transparent: {report}");

    let settings = b"[render]\npath = \"deferred\"\nlight_buffer = \"ldr-exp2\"\n[lights]\nmax_other_lights = 1000\nculling = \"none\"\n";
    let report = bench_json(&[("settings.toml", settings)], &["--settings", "settings.toml"]);
    assert_eq!(report["path"], "deferred", "{report}");
    assert!(report["passes"].get("ldr decode").is_some(), "no 'ldr decode' pass: {report}");
    // The flag wins over the file, and a forward path without culling cannot shade 1000
    // lights.
    expect_failure(
        &[("settings.toml", settings)],
        &["render", "--settings", "settings.toml", "--path", "forward", "-o", "out.png"],
        &[],
        &["--path", "lights.max_other_lights"],
    );
    expect_failure(
        &[("settings.toml", b"[render]\npath = \"sideways\"\n")],
        &["render", "--settings", "settings.toml", "-o", "out.png"],
        &[],
        &["settings.toml", "sideways"],
    );
    expect_failure(
        &[("settings.toml", b"[render]\nlight_buffer = \"ldr\"\n")],
        &["render", "--settings", "settings.toml", "-o", "out.png"],
        &[],
        &["settings.toml", "ldr"],
    );
    expect_usage_error(&["render", "--path", "backward"], &["backward"]);
    for path in ["forward", "deferred"] {
        let (_, run) = run_in(&[], &["compare", "--width", "48", "--height", "48", "--path", path]);
        assert!(run.stdout.contains("sun"), "{path}: {}", run.stdout);
    }
}

#[test]
fn debug_views_show_the_gbuffer_and_the_overdraw() {
    let pixel = |dir: &tempfile::TempDir, file: &str, x: u32, y: u32| {
        image::open(dir.path().join(file)).unwrap().to_rgb8().get_pixel(x, y).0
    };
    for (view, file) in
        [("gbuffer-albedo", "albedo.png"), ("gbuffer-normal", "normal.png"), ("light-overdraw", "overdraw.png")]
    {
        let (dir, _) = run_in(&[], &["render", "--width", "64", "--height", "64", "--debug", view, "-o", file]);
        assert_eq!(pixel(&dir, file, 0, 0), [0, 0, 0], "{view}: the sky is black");
        assert_ne!(pixel(&dir, file, 32, 63), [0, 0, 0], "{view}: the floor is not");
        if view == "gbuffer-normal" {
            // The floor faces +Y: (0.5, 1, 0.5) as sRGB.
            let [r, g, b] = pixel(&dir, file, 32, 63);
            assert!(g == 255 && r.abs_diff(188) <= 2 && b.abs_diff(188) <= 2, "{:?}", [r, g, b]);
        }
    }
    expect_failure(
        &[],
        &["render", "--debug", "gbuffer-albedo", "--debug", "light-overdraw", "-o", "out.png"],
        &[],
        &["--debug", "choose one"],
    );
    // The cascade tint is the forward path's; asked for on the deferred path, it renders forward.
    run_in(&[], &["render", "--width", "32", "--height", "32", "--debug", "cascades", "--path", "deferred"]);
}
