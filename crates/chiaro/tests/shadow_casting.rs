//! Material extras `shadowCasting` as a user meets them: a checkerboard MASK quad over a
//! floor casts a checkerboard shadow by default ("clip"), a solid one with "on", and none
//! with "off"; `compare` agrees with the reference in each case.

mod common;

use base64::Engine as _;
use common::*;

/// A 2x2 RGBA checker PNG: opaque where x == y.
fn checker_png() -> Vec<u8> {
    let mut image = image::RgbaImage::new(2, 2);
    for (x, y, p) in image.enumerate_pixels_mut() {
        *p = image::Rgba([255, 255, 255, if x == y { 255 } else { 0 }]);
    }
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write_to(&mut bytes, image::ImageFormat::Png).unwrap();
    bytes.into_inner()
}

/// An 8 m floor, a 2 m quad 1 m above it (UVs 0..2, so the checker repeats twice), a sun
/// straight down, and a camera above; the quad's material has `extras`.
fn scene(extras: &str) -> String {
    let f = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let mut buffer = f(&[-4.0, 0.0, 4.0, 4.0, 0.0, 4.0, 4.0, 0.0, -4.0, -4.0, 0.0, -4.0]);
    buffer.extend(f(&[-1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, -1.0, -1.0, 1.0, -1.0]));
    buffer.extend(f(&[0.0, 0.0, 2.0, 0.0, 2.0, 2.0, 0.0, 2.0]));
    buffer.extend([0u8, 0, 1, 0, 2, 0, 0, 0, 2, 0, 3, 0]);
    let engine = base64::engine::general_purpose::STANDARD;
    format!(
        r#"{{
  "asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0, 1, 2, 3]}}],
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {{"KHR_lights_punctual": {{"lights": [{{"type": "directional", "name": "sun", "intensity": 3}}]}}}},
  "nodes": [
    {{"mesh": 0}}, {{"mesh": 1}},
    {{"name": "sun", "rotation": [-0.7071068, 0, 0, 0.7071068], "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}},
    {{"camera": 0, "translation": [0, 5, 2.5], "rotation": [-0.5257311, 0, 0, 0.8506508]}}
  ],
  "cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.9, "znear": 0.1}}}}],
  "meshes": [
    {{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 3, "material": 0}}]}},
    {{"primitives": [{{"attributes": {{"POSITION": 1, "TEXCOORD_0": 2}}, "indices": 3, "material": 1}}]}}
  ],
  "materials": [
    {{"pbrMetallicRoughness": {{"metallicFactor": 0}}}},
    {{"alphaMode": "MASK", "doubleSided": true, "extras": {extras},
      "pbrMetallicRoughness": {{"metallicFactor": 0, "baseColorTexture": {{"index": 0}}}}}}
  ],
  "textures": [{{"source": 0, "sampler": 0}}],
  "samplers": [{{"magFilter": 9728, "minFilter": 9728}}],
  "images": [{{"uri": "data:image/png;base64,{}"}}],
  "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 48}},
    {{"buffer": 0, "byteOffset": 96, "byteLength": 32}}, {{"buffer": 0, "byteOffset": 128, "byteLength": 12}}
  ],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-4, 0, -4], "max": [4, 0, 4]}},
    {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, 1, -1], "max": [1, 1, 1]}},
    {{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}},
    {{"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}}
  ]
}}"#,
        engine.encode(checker_png()),
        buffer.len(),
        engine.encode(&buffer)
    )
}

/// Renders the scene's sun shadow AOV and returns the share of shadowed floor pixels
/// under the quad, checking `compare` agrees with the reference.
fn shadowed_share_under_quad(extras: &str) -> f32 {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("quad.gltf"), scene(extras)).unwrap();
    let size = ["--width", "96", "--height", "96"];
    let run = chiaro(
        &[&["render", "quad.gltf", "-o", "q.png", "--aov", "shadow", "--aov", "position"][..], &size].concat(),
        &[],
        dir.path(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let run = chiaro(&[&["compare", "quad.gltf", "--fail-above", "0.5"][..], &size].concat(), &[], dir.path());
    assert_eq!(run.code, 0, "{extras}: {}{}", run.stdout, run.stderr);
    let shadow = &read_exr_channels(&dir.path().join("q.shadow.2.exr"))[0].1;
    let position = read_exr_channels(&dir.path().join("q.position.exr"));
    // EXR channels come sorted: B, G, R hold z, y, x.
    let (z, y, x) = (&position[0].1, &position[1].1, &position[2].1);
    let under: Vec<usize> =
        (0..shadow.len()).filter(|&i| y[i].abs() < 1e-3 && x[i].abs() < 0.9 && z[i].abs() < 0.9).collect();
    assert!(under.len() > 100, "{extras}: {} floor pixels under the quad", under.len());
    under.iter().filter(|&&i| shadow[i] < 0.5).count() as f32 / under.len() as f32
}

#[test]
fn masked_materials_clip_by_default_and_extras_choose_otherwise() {
    let clipped = shadowed_share_under_quad("{}");
    assert!((0.3..0.7).contains(&clipped), "default clip: {clipped} of the footprint shadowed");
    let explicit = shadowed_share_under_quad(r#"{"shadowCasting": "clip"}"#);
    assert_eq!(clipped, explicit);
    let solid = shadowed_share_under_quad(r#"{"shadowCasting": "on"}"#);
    assert!(solid > 0.95, "on: {solid} of the footprint shadowed");
    let none = shadowed_share_under_quad(r#"{"shadowCasting": "off"}"#);
    assert_eq!(none, 0.0, "off: {none} of the footprint shadowed");
}

#[test]
fn a_bad_shadow_casting_extra_names_the_material() {
    expect_failure(
        &[("quad.gltf", scene(r#"{"shadowCasting": "sometimes"}"#).as_bytes())],
        &["render", "quad.gltf", "-o", "out.png"],
        &[],
        &["quad.gltf: material 1: extras.shadowCasting: 'sometimes' is not on, clip, dither or off"],
    );
}
