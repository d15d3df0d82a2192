//! What a hostile user's inputs found (issue 12), each pinned by its message and exit
//! status: counts bounded, blinding lights and vanishing ranges refused, outputs that
//! would replace an input refused, spec-invalid glTF and settings named by path and line,
//! FIFOs refused, output folders checked before rendering, and one line per error.

mod common;

use common::*;

fn files(list: &[(String, Vec<u8>)]) -> Vec<(&str, &[u8])> {
    list.iter().map(|(n, b)| (n.as_str(), b.as_slice())).collect()
}

#[test]
fn count_options_are_bounded() {
    let start = std::time::Instant::now();
    expect_usage_error(&["render", "--demo-lights", "4294967295"], &["--demo-lights", "not in 0..=65536"]);
    expect_usage_error(&["render", "--demo-shadowed-spots", "70000"], &["--demo-shadowed-spots", "0..=65536"]);
    expect_usage_error(&["bench", "--frames", "0"], &["--frames", "not in 1..=100000"]);
    expect_usage_error(&["bench", "--warmup", "4294967295"], &["--warmup", "0..=100000"]);
    assert!(start.elapsed().as_secs() < 20, "refused at once, not after growing memory");
}

#[test]
fn blinding_lights_and_vanishing_ranges_are_refused() {
    let light = good_triangle().replace(
        r#""nodes": [{"mesh": 0}]"#,
        r#""nodes": [{"mesh": 0}, {"extensions": {"KHR_lights_punctual": {"light": 0}}}],
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "name": "sun in a box", "intensity": 1e37}]}}"#,
    );
    let light = light.replace(r#""scenes": [{"nodes": [0]}]"#, r#""scenes": [{"nodes": [0, 1]}]"#);
    expect_failure(
        &[("bright.gltf", light.as_bytes())],
        &["render", "bright.gltf", "-o", "out.png"],
        &[],
        &["bright.gltf: light 0 (sun in a box): intensity 1e37", "beyond 1e15"],
    );
    expect_failure(
        &[("settings.toml", b"[lights]\nrange_threshold_lux = 1e-40\n")],
        &["render", "--settings", "settings.toml", "-o", "out.png"],
        &[],
        &["settings.toml: lights.range_threshold_lux (line 2): 1e-40 is out of range (1e-6 to 1000000)"],
    );
}

#[test]
fn outputs_never_replace_inputs() {
    let scene = textured_scene("tex.png");
    expect_failure(
        &files(&scene),
        &["render", "scene.gltf", "-o", "tex.png"],
        &[],
        &["tex.png: is a file the scene reads", "choose another output path"],
    );
    // The texture is still the texture: a second render from the same folder works.
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in &scene {
        std::fs::write(dir.path().join(name), bytes).unwrap();
    }
    let run = chiaro(&["render", "scene.gltf", "-o", "tex.png", "--width", "8", "--height", "8"], &[], dir.path());
    assert_eq!(run.code, 1);
    assert_eq!(std::fs::read(dir.path().join("tex.png")).unwrap(), png_bytes());
    // A scene file renamed to .png, rendered onto itself.
    let renamed = vec![("s.png".to_string(), good_triangle().into_bytes())];
    expect_failure(&files(&renamed), &["render", "s.png", "-o", "s.png"], &[], &["s.png: is the scene file"]);
    // An AOV beside the output that would land on the texture.
    let aov_clash = textured_scene("out.depth.exr");
    expect_failure(
        &files(&aov_clash),
        &["render", "scene.gltf", "-o", "out.png", "--aov", "depth"],
        &[],
        &["out.depth.exr: is a file the scene reads"],
    );
    // The settings file is an input too.
    expect_failure(
        &[("set.png", b"")],
        &["render", "--settings", "set.png", "-o", "set.png"],
        &[],
        &["set.png: is the settings file"],
    );
}

#[test]
fn fail_above_is_a_percentage() {
    for bad in ["nan", "200", "-5", "inf"] {
        expect_usage_error(&["compare", "--fail-above", bad], &["--fail-above", bad]);
    }
}

#[test]
fn edge_band_is_a_pixel_count_up_to_64() {
    for bad in ["-1", "65", "1.5", "wide"] {
        expect_usage_error(&["compare", "--edge-band", bad], &["--edge-band", bad]);
    }
}

#[test]
fn spec_invalid_gltf_is_refused_with_its_json_path() {
    let triangle = good_triangle();
    let with_material = |material: &str| {
        triangle.replace(r#""POSITION": 0}"#, r#""POSITION": 0}, "material": 0"#).replace(
            r#""asset": {"version": "2.0"},"#,
            &format!(r#""asset": {{"version": "2.0"}}, "materials": [{material}],"#),
        )
    };
    let cases: Vec<(String, &str)> = vec![
        (
            with_material(r#"{"pbrMetallicRoughness": {"baseColorFactor": [1, -0.5, 1, 1]}}"#),
            "materials[0].pbrMetallicRoughness.baseColorFactor[1]: -0.5 is outside [0, 1]",
        ),
        (with_material(r#"{"pbrMetallicRoughness": {"metallicFactor": 5}}"#), "metallicFactor: 5 is outside [0, 1]"),
        (with_material(r#"{"pbrMetallicRoughness": {"roughnessFactor": -1}}"#), "roughnessFactor: -1 is outside"),
        (
            triangle.replace(r#""byteLength": 36}],"#, r#""byteLength": 36, "byteStride": 4}],"#),
            "accessors[0]: its elements are 12 bytes, more than bufferViews[0].byteStride (4)",
        ),
        (
            triangle.replace(r#""componentType": 5126"#, r#""componentType": 5121"#),
            "accessor 0 holds UNSIGNED_BYTE, which POSITION cannot be (without KHR_mesh_quantization)",
        ),
        (
            with_material(r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}}}"#)
                .replace(r#""asset""#, r#""textures": [{"source": 0}], "images": [{"uri": "t.png"}], "asset""#),
            "materials[0].pbrMetallicRoughness.baseColorTexture.texCoord is 1, but the primitive has no TEXCOORD_1",
        ),
        (
            triangle.replace(
                r#"[{"mesh": 0}]"#,
                r#"[{"mesh": 0, "matrix": [1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1], "scale": [2,2,2]}]"#,
            ),
            "nodes[0]: has both matrix and scale",
        ),
    ];
    for (gltf, expected) in &cases {
        expect_failure(
            &[("scene.gltf", gltf.as_bytes())],
            &["render", "scene.gltf", "-o", "out.png"],
            &[],
            &["scene.gltf: ", expected],
        );
    }
    // The primitive restart value among the indices: four UNSIGNED_BYTE indices (0, 1,
    // 255, 0) after the positions.
    let restart_index = r#"{
  "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "buffers": [{"uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAAAAAAIC/AAH/AA==", "byteLength": 40}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 4}],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, -1], "max": [1, 0, 0]},
    {"bufferView": 1, "componentType": 5121, "count": 4, "type": "SCALAR"}
  ]
}"#;
    expect_failure(
        &[("scene.gltf", restart_index.as_bytes())],
        &["render", "scene.gltf", "-o", "out.png"],
        &[],
        &["scene.gltf: meshes[0].primitives[0].indices (accessors[1]): element 2 is 255, the primitive restart value"],
    );
}

#[test]
fn settings_errors_name_the_key_and_line() {
    for (text, expected) in [
        (
            "[render]\nwidth = \"64\"\n",
            "settings.toml: render.width (line 2): invalid type: string \"64\", expected u32",
        ),
        ("[render]\nwidth = 64\nwidth = 65\n", "render.width (line 3): duplicate key"),
        ("[shadows.directional]\nfilter = 3\n", "shadows.directional.filter (line 2): invalid type: integer `3`"),
        ("[shadows.directional]\ncascade_blend = \"smooth\"\n", "cascade_blend (line 2): unknown variant `smooth`"),
        (
            "[shadows.directional]\ncascade_ratios = [0.1, 0.2, 0.3, 0.4]\n",
            "cascade_ratios (line 2): takes cascade_count - 1 = 3 entries",
        ),
    ] {
        expect_failure(
            &[("settings.toml", text.as_bytes())],
            &["render", "--settings", "settings.toml", "-o", "out.png"],
            &[],
            &[expected],
        );
    }
}

#[cfg(unix)]
#[test]
fn fifos_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["scene.gltf", "settings.toml"] {
        let status = std::process::Command::new("mkfifo").arg(dir.path().join(name)).status().unwrap();
        assert!(status.success());
    }
    let start = std::time::Instant::now();
    let run = chiaro(&["render", "scene.gltf", "-o", "out.png"], &[], dir.path());
    assert_eq!(
        (run.code, error_lines(&run)),
        (1, vec!["chiaro: error: scene.gltf: cannot read file: not a regular file (a FIFO)"])
    );
    let run = chiaro(&["render", "--settings", "settings.toml", "-o", "out.png"], &[], dir.path());
    assert_eq!(run.code, 1);
    assert!(
        error_lines(&run)[0].contains("settings.toml: cannot read settings: not a regular file (a FIFO)"),
        "{}",
        run.stderr
    );
    assert!(start.elapsed().as_secs() < 20, "nothing blocked");
}

#[test]
fn unwritable_outputs_are_found_before_rendering_and_named() {
    let dir = tempfile::tempdir().unwrap();
    let run = chiaro(&["render", "-o", "nowhere/out.png"], &[], dir.path());
    assert_eq!(run.code, 1);
    assert_eq!(
        error_lines(&run),
        vec![
            "chiaro: error: nowhere/out.png: cannot write there: folder nowhere: No such file or directory (os error 2)"
        ]
    );
    // An AOV whose path is a folder: refused before rendering, so no main image either.
    std::fs::create_dir(dir.path().join("demo.depth.exr")).unwrap();
    let run =
        chiaro(&["render", "-o", "demo.png", "--aov", "depth", "--width", "16", "--height", "16"], &[], dir.path());
    assert_eq!(run.code, 1);
    assert!(error_lines(&run)[0].contains("demo.depth.exr: is a folder"), "{}", run.stderr);
    assert!(!dir.path().join("demo.png").exists(), "nothing written when one output cannot be");
}

#[test]
fn radiance_and_aovs_are_float32_and_clipping_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    // EV100 -30 is 2^30 brighter than EV100 0: the sun's floor passes the half-float target.
    let run = chiaro(
        &["render", "-o", "hot.exr", "--aov", "depth", "--exposure", "-30", "--width", "32", "--height", "32"],
        &[],
        dir.path(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("pixels reached the HDR target's limit"), "{}", run.stderr);
    for file in ["hot.exr", "hot.depth.exr"] {
        let meta = exr::meta::MetaData::read_from_file(dir.path().join(file), false).unwrap();
        for channel in &meta.headers[0].channels.list {
            assert_eq!(channel.sample_type, exr::meta::attribute::SampleType::F32, "{file} {}", channel.name);
        }
    }
}

#[test]
fn the_automatic_camera_frames_small_scenes_and_refuses_huge_ones() {
    let dir = tempfile::tempdir().unwrap();
    let scaled =
        |s: &str| triangle_gltf(&format!(r#"[{{"mesh": 0, "scale": [{s}, {s}, {s}]}}]"#), TRIANGLE_BUFFER, 36, 0);
    for scale in ["1e-5", "1e14"] {
        std::fs::write(dir.path().join("t.gltf"), scaled(scale)).unwrap();
        let run = chiaro(
            &["render", "t.gltf", "-o", "t.png", "--aov", "depth", "--width", "32", "--height", "32"],
            &[],
            dir.path(),
        );
        assert_eq!(run.code, 0, "{}", run.stderr);
        let depth = &read_exr_channels(&dir.path().join("t.depth.exr"))[0].1;
        let covered = depth.iter().filter(|d| d.is_finite()).count();
        assert!(covered > 32 * 32 / 10, "scale {scale}: triangle covers {covered} pixels");
    }
    expect_failure(
        &[("huge.gltf", scaled("1e19").as_bytes())],
        &["render", "huge.gltf", "-o", "out.png"],
        &[],
        &["huge.gltf: the scene's bounding sphere", "give the file a camera"],
    );
}

#[test]
fn an_error_after_the_gpu_starts_is_one_line_without_xdg_runtime_dir() {
    let dir = tempfile::tempdir().unwrap();
    let run = chiaro_env(
        &["render", "--width", "4000000", "--height", "4", "-o", "out.png"],
        &[],
        &["XDG_RUNTIME_DIR"],
        dir.path(),
    );
    assert_eq!(run.code, 1);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(run.stderr.starts_with("chiaro: error: output size 4000000x4"), "{}", run.stderr);
}

/// Data broken where it is drawn is refused: status 1, one line naming the file, the JSON
/// path and the rule, and no output left behind.
#[test]
fn data_broken_where_drawn_is_refused_with_status_1() {
    let triangle = good_triangle();
    let cases: Vec<(Vec<u8>, &str, &str)> = vec![
        (
            triangle.replace(r#""count": 3"#, r#""count": 30"#).into_bytes(),
            "scene.gltf",
            "accessors[0] (POSITION of meshes[0].primitives[0]) reads 30 elements",
        ),
        (
            triangle.replace(r#"[{"mesh": 0}]"#, r#"[{"mesh": 0, "children": [0]}]"#).into_bytes(),
            "scene.gltf",
            "nodes[0]: reached twice in the node hierarchy",
        ),
        (
            triangle
                .replace(r#""byteOffset": 0, "byteLength": 36"#, r#""byteOffset": 8, "byteLength": 36"#)
                .into_bytes(),
            "scene.gltf",
            "bufferViews[0] (bytes 8..44) runs past the end of buffers[0] (36 bytes)",
        ),
        (
            b"glTF\x02\x00\x00\x00\xff\x00\x00\x00".to_vec(),
            "scene.glb",
            "GLB header says 255 bytes but the file has 12",
        ),
    ];
    for (bytes, name, expected) in &cases {
        let code = expect_failure(
            &[(name, bytes)],
            &["render", name, "-o", "out.png"],
            &[],
            &[&format!("{name}: "), expected],
        );
        assert_eq!(code, 1, "{name}: {expected}");
    }
}

/// A file without a scene is valid: it renders empty, with a warning, and `info` lists
/// what was set aside under `ignored:`.
#[test]
fn a_file_without_a_scene_renders_empty_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let gltf = r#"{"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "area"}]}}}"#;
    std::fs::write(dir.path().join("empty.gltf"), gltf).unwrap();
    let run = chiaro(&["render", "empty.gltf", "-o", "out.png"], &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("empty.gltf: the file has no scene: nothing to draw"), "{}", run.stderr);
    assert!(dir.path().join("out.png").is_file());
    let info = chiaro(&["info", "empty.gltf"], &[], dir.path());
    assert_eq!(info.code, 0, "{}", info.stderr);
    let ignored = info.stdout.split_once("ignored:").map(|(_, rest)| rest).unwrap_or_default();
    assert!(ignored.contains("the file has no scene"), "{}", info.stdout);
    assert!(ignored.contains("lights[0]: type \"area\""), "{}", info.stdout);
}
