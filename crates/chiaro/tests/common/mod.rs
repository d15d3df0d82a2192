//! What the command-line tests share: running the binary in a scratch folder, small glTF
//! files, and reading its outputs back.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A triangle's three positions as a data URI.
pub const TRIANGLE_BUFFER: &str =
    "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAAAAAAIC/";

pub fn triangle_gltf(nodes: &str, buffer_uri: &str, byte_length: u32, position_accessor: u32) -> String {
    format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [0]}}],
  "nodes": {nodes},
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": {position_accessor}}}}}]}}],
  "buffers": [{{"uri": "{buffer_uri}", "byteLength": {byte_length}}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, -1], "max": [1, 0, 0]}}]
}}"#
    )
}

pub fn good_triangle() -> String {
    triangle_gltf(r#"[{"mesh": 0}]"#, TRIANGLE_BUFFER, 36, 0)
}

pub struct Run {
    pub code: i32,
    pub stderr: String,
    pub stdout: String,
}

pub fn chiaro(args: &[&str], env: &[(&str, &str)], dir: &Path) -> Run {
    chiaro_env(args, env, &[], dir)
}

/// `chiaro` with `set` added to its environment and `removed` taken out.
pub fn chiaro_env(args: &[&str], set: &[(&str, &str)], removed: &[&str], dir: &Path) -> Run {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_chiaro"));
    cmd.args(args).current_dir(dir);
    for (k, v) in set {
        cmd.env(k, v);
    }
    for k in removed {
        cmd.env_remove(k);
    }
    let Output { status, stdout, stderr } = cmd.output().expect("run chiaro");
    Run {
        code: status.code().unwrap_or(-1),
        stderr: String::from_utf8_lossy(&stderr).into_owned(),
        stdout: String::from_utf8_lossy(&stdout).into_owned(),
    }
}

/// The error line, without lavapipe's harmless XDG_RUNTIME_DIR complaints.
pub fn error_lines(run: &Run) -> Vec<&str> {
    run.stderr.lines().filter(|l| l.starts_with("chiaro: error:")).collect()
}

/// Writes `files` into a fresh folder, renders `scene` there, and checks the failure;
/// returns its exit status.
pub fn expect_failure(files: &[(&str, &[u8])], args: &[&str], env: &[(&str, &str)], must_contain: &[&str]) -> i32 {
    let dir = tempfile::tempdir().unwrap();
    for (name, content) in files {
        std::fs::write(dir.path().join(name), content).unwrap();
    }
    let run = chiaro(args, env, dir.path());
    assert_ne!(run.code, 0, "succeeded: {}", run.stderr);
    assert_ne!(run.code, 101, "panicked: {}", run.stderr);
    assert!(!run.stderr.contains("panicked"), "panicked: {}", run.stderr);
    let lines = error_lines(&run);
    assert_eq!(lines.len(), 1, "one error line expected: {}", run.stderr);
    for needle in must_contain {
        assert!(lines[0].contains(needle), "'{}' lacks '{needle}'", lines[0]);
    }
    let leftovers: Vec<PathBuf> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_string_lossy();
            let given = files.iter().any(|(n, _)| *n == name);
            !given && (name.ends_with(".png") || name.ends_with(".exr") || name.ends_with(".tmp"))
        })
        .collect();
    assert!(leftovers.is_empty(), "left files behind: {leftovers:?}");
    run.code
}

pub fn read_exr_channels(path: &Path) -> Vec<(String, Vec<f32>)> {
    use exr::prelude::*;
    let image = read_all_flat_layers_from_file(path).unwrap();
    let layer = &image.layer_data[0];
    layer.channel_data.list.iter().map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect())).collect()
}

/// A clap usage error: exit status 2, the message naming the option and what it takes.
pub fn expect_usage_error(args: &[&str], must_contain: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let run = chiaro(args, &[], dir.path());
    assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
    let first = run.stderr.lines().next().unwrap_or_default();
    for needle in must_contain {
        assert!(first.contains(needle), "{args:?}: '{first}' lacks '{needle}'");
    }
}

/// PNG bytes of a small grey image.
pub fn png_bytes() -> Vec<u8> {
    let image = image::RgbaImage::from_pixel(2, 2, image::Rgba([128, 128, 128, 255]));
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write_to(&mut bytes, image::ImageFormat::Png).unwrap();
    bytes.into_inner()
}

/// `scene.gltf`: the triangle with TEXCOORD_0 and a material textured by the PNG
/// `texture`, as (file, bytes) pairs.
pub fn textured_scene(texture: &str) -> Vec<(String, Vec<u8>)> {
    // Positions, then UVs.
    let buffer = "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAAAAAAIC/\
                  AAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/";
    let gltf = format!(
        r#"{{
  "asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1}}, "material": 0}}]}}],
  "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}}}}}],
  "textures": [{{"source": 0}}], "images": [{{"uri": "{texture}"}}],
  "buffers": [{{"uri": "{buffer}", "byteLength": 60}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 60}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, -1], "max": [1, 0, 0]}},
    {{"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC2"}}
  ]
}}"#
    );
    vec![("scene.gltf".into(), gltf.into_bytes()), (texture.into(), png_bytes())]
}
