//! End-to-end tests of the importer: glTF documents written to a scratch folder flow in
//! through [`load_gltf`], and the resulting `Scene` (or the `SceneError` and its message)
//! is checked. The shared assets under `shared/assets` are loaded too.

use super::load_gltf;
use crate::error::SceneError;
use crate::types::{AlphaMode, ColorSpace, LightKind, LightMode, SamplerDesc, Scene, UvTransform, WrapMode};
use base64::Engine as _;
use glam::{Mat4, Vec2, Vec3, Vec4};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A scratch folder under the system temp dir, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> TempDir {
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("chiaro-gltf-test-{}-{tag}-{n}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }

    fn write(&self, name: &str, bytes: &[u8]) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn data_uri(bytes: &[u8]) -> String {
    format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes))
}

fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

fn png_bytes(image: image::DynamicImage) -> Vec<u8> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write_to(&mut bytes, image::ImageFormat::Png).unwrap();
    bytes.into_inner()
}

const TRIANGLE: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

/// One counter-clockwise triangle in the XY plane (facing +Z) on node 0, its positions
/// in a data-URI buffer.
fn triangle_doc() -> Value {
    let bytes = f32_bytes(&TRIANGLE);
    json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0, "name": "tri" }],
        "meshes": [{ "name": "triangle", "primitives": [{ "attributes": { "POSITION": 0 } }] }],
        "accessors": [{
            "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
            "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]
        }],
        "bufferViews": [{ "buffer": 0, "byteLength": bytes.len() }],
        "buffers": [{ "byteLength": bytes.len(), "uri": data_uri(&bytes) }]
    })
}

fn load_doc(dir: &TempDir, doc: &Value) -> Result<Scene, SceneError> {
    let path = dir.write("scene.gltf", doc.to_string().as_bytes());
    load_gltf(&path)
}

fn invalid_message(result: Result<Scene, SceneError>) -> String {
    match result {
        Err(SceneError::Invalid { message, .. }) => message,
        other => panic!("expected SceneError::Invalid, got {other:?}"),
    }
}

#[test]
fn triangle_from_data_uri_gets_flat_normals_facing_its_front() {
    let dir = TempDir::new("triangle");
    let scene = load_doc(&dir, &triangle_doc()).unwrap();
    assert_eq!(scene.triangle_count(), 1);
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.instances.len(), 1);
    assert_eq!(scene.instances[0].name, "tri");
    let p = &scene.meshes[0].primitives[0];
    assert_eq!(p.positions.len(), 3);
    assert_eq!(p.normals, vec![Vec3::Z; 3]);
    assert_eq!(p.uv0, vec![Vec2::ZERO; 3]);
    assert_eq!(p.uv1, vec![Vec2::ZERO; 3]);
    for t in &p.tangents {
        assert!(t.truncate().dot(Vec3::Z).abs() < 1e-6);
        assert_eq!(t.w, 1.0);
    }
    assert_eq!(p.bounds.min, Vec3::ZERO);
    assert_eq!(p.bounds.max, Vec3::new(1.0, 1.0, 0.0));
    assert_eq!(p.material, None);
    assert!(scene.ignored.is_empty(), "{:?}", scene.ignored);
    assert_eq!(scene.source.as_deref(), Some(dir.0.join("scene.gltf").as_path()));
}

#[test]
fn indexed_quad_without_normals_is_unwelded() {
    let dir = TempDir::new("quad");
    let positions = f32_bytes(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0]);
    let indices: Vec<u8> = [0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()).collect();
    let mut bytes = positions.clone();
    bytes.extend_from_slice(&indices);
    let mut doc = triangle_doc();
    doc["meshes"][0]["primitives"][0]["indices"] = json!(1);
    doc["accessors"][0]["count"] = json!(4);
    doc["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR" }));
    doc["bufferViews"] = json!([
        { "buffer": 0, "byteLength": 48 },
        { "buffer": 0, "byteOffset": 48, "byteLength": 12 }
    ]);
    doc["buffers"] = json!([{ "byteLength": bytes.len(), "uri": data_uri(&bytes) }]);
    let scene = load_doc(&dir, &doc).unwrap();
    let p = &scene.meshes[0].primitives[0];
    assert_eq!(p.triangle_count(), 2);
    assert_eq!(p.positions.len(), 6);
    assert_eq!(p.indices, (0..6).collect::<Vec<u32>>());
    assert_eq!(p.positions[5], Vec3::new(0.0, 1.0, 0.0));
    assert!(p.normals.iter().all(|&n| n == Vec3::Z));
}

#[test]
fn triangle_strip_becomes_a_list_with_consistent_winding() {
    let dir = TempDir::new("strip");
    let bytes = f32_bytes(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0]);
    let mut doc = triangle_doc();
    doc["meshes"][0]["primitives"][0]["mode"] = json!(5);
    doc["accessors"][0]["count"] = json!(4);
    doc["bufferViews"][0]["byteLength"] = json!(bytes.len());
    doc["buffers"] = json!([{ "byteLength": bytes.len(), "uri": data_uri(&bytes) }]);
    let scene = load_doc(&dir, &doc).unwrap();
    let p = &scene.meshes[0].primitives[0];
    assert_eq!(p.triangle_count(), 2);
    assert!(p.normals.iter().all(|&n| n == Vec3::Z), "{:?}", p.normals);
}

#[test]
fn child_translation_composes_under_parent_scale() {
    let dir = TempDir::new("hierarchy");
    let mut doc = triangle_doc();
    doc["nodes"] = json!([
        { "name": "parent", "translation": [0.0, 0.0, 5.0], "scale": [2.0, 2.0, 2.0], "children": [1] },
        { "name": "child", "translation": [1.0, 0.0, 0.0], "mesh": 0 }
    ]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.instances.len(), 1);
    let instance = &scene.instances[0];
    assert_eq!(instance.node, 1);
    assert_eq!(instance.name, "child");
    let origin = instance.world_from_local.transform_point3(Vec3::ZERO);
    assert!(origin.distance(Vec3::new(2.0, 0.0, 5.0)) < 1e-6, "{origin}");
    let x = instance.world_from_local.transform_vector3(Vec3::X);
    assert!(x.distance(Vec3::new(2.0, 0.0, 0.0)) < 1e-6);
    let bounds = scene.bounds();
    assert!(bounds.max.distance(Vec3::new(4.0, 2.0, 5.0)) < 1e-6);
}

#[test]
fn one_mesh_instanced_twice_is_converted_once() {
    let dir = TempDir::new("instances");
    let mut doc = triangle_doc();
    doc["scenes"] = json!([{ "nodes": [0, 1] }]);
    doc["nodes"] = json!([{ "mesh": 0 }, { "mesh": 0, "translation": [3.0, 0.0, 0.0] }]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.instances.len(), 2);
    assert_eq!(scene.instances[1].node, 1);
    assert_eq!(scene.instances[1].name, "triangle");
    assert_eq!(scene.triangle_count(), 2);
}

#[test]
fn a_scaled_light_node_keeps_its_roll_and_loses_its_scale() {
    let dir = TempDir::new("light-scale");
    let mut doc = triangle_doc();
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [{ "type": "spot", "spot": {} }] } });
    doc["scenes"] = json!([{ "nodes": [0, 1, 2] }]);
    // A quarter turn about Z (roll only), scaled unevenly.
    let half = std::f32::consts::FRAC_1_SQRT_2;
    doc["nodes"] = json!([
        { "mesh": 0 },
        { "translation": [0.0, 1.0, 0.0], "rotation": [0.0, 0.0, half, half], "scale": [2.0, 3.0, 4.0],
          "extensions": { "KHR_lights_punctual": { "light": 0 } } },
        { "scale": [0.0, 0.0, 0.0], "extensions": { "KHR_lights_punctual": { "light": 0 } } }
    ]);
    let scene = load_doc(&dir, &doc).unwrap();
    let m = scene.lights[0].world_from_light;
    assert!(m.x_axis.truncate().distance(Vec3::Y) < 1e-6, "{m}");
    assert!(m.y_axis.truncate().distance(Vec3::NEG_X) < 1e-6, "{m}");
    assert!(m.z_axis.truncate().distance(Vec3::Z) < 1e-6, "{m}");
    assert_eq!(scene.lights[0].position(), Vec3::Y);
    // A node scaled to nothing still gives a light with a unit direction.
    let collapsed = &scene.lights[1];
    assert!((collapsed.direction().length() - 1.0).abs() < 1e-6);
    assert!(collapsed.world_from_light.is_finite());
}

#[test]
fn punctual_lights_take_their_node_transforms() {
    let dir = TempDir::new("lights");
    let mut doc = triangle_doc();
    let half = std::f32::consts::FRAC_1_SQRT_2;
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [
        { "type": "point", "name": "bulb", "color": [1.0, 0.5, 0.25], "intensity": 10.0 },
        { "type": "spot", "intensity": 20.0, "range": 8.0,
          "spot": { "innerConeAngle": 0.2, "outerConeAngle": 0.5 } },
        { "type": "directional", "intensity": 3.0 },
        { "type": "spot", "spot": {} }
    ] } });
    doc["scenes"] = json!([{ "nodes": [0, 1, 2, 3, 4] }]);
    doc["nodes"] = json!([
        { "mesh": 0 },
        { "translation": [1.0, 2.0, 3.0], "extensions": { "KHR_lights_punctual": { "light": 0 } } },
        { "name": "spot node", "rotation": [half, 0.0, 0.0, half],
          "extensions": { "KHR_lights_punctual": { "light": 1 } } },
        { "extensions": { "KHR_lights_punctual": { "light": 2 } } },
        { "extensions": { "KHR_lights_punctual": { "light": 3 } } }
    ]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.lights.len(), 4);

    let point = &scene.lights[0];
    assert_eq!(point.name, "bulb");
    assert_eq!(point.node, 1);
    assert_eq!(point.kind, LightKind::Point);
    assert_eq!(point.color, Vec3::new(1.0, 0.5, 0.25));
    assert_eq!(point.intensity, 10.0);
    assert_eq!(point.range, None);
    assert_eq!(point.position(), Vec3::new(1.0, 2.0, 3.0));

    let spot = &scene.lights[1];
    assert_eq!(spot.name, "spot node");
    assert_eq!(spot.kind, LightKind::Spot { inner_cone_rad: 0.2, outer_cone_rad: 0.5 });
    assert_eq!(spot.range, Some(8.0));
    // +90 degrees about X turns -Z into +Y.
    assert!(spot.direction().distance(Vec3::Y) < 1e-6, "{}", spot.direction());
    // The roll comes along: the node's +Y turns into +Z.
    assert!(spot.world_from_light.y_axis.truncate().distance(Vec3::Z) < 1e-6, "{}", spot.world_from_light);

    let sun = &scene.lights[2];
    assert_eq!(sun.kind, LightKind::Directional);
    assert_eq!(sun.direction(), Vec3::NEG_Z);
    assert_eq!(sun.color, Vec3::ONE);
    assert_eq!(sun.name, "light 2");

    let default_spot = &scene.lights[3];
    assert_eq!(default_spot.intensity, 1.0);
    assert_eq!(default_spot.kind, LightKind::Spot { inner_cone_rad: 0.0, outer_cone_rad: std::f32::consts::FRAC_PI_4 });
}

#[test]
fn bad_lights_are_invalid() {
    let dir = TempDir::new("bad-lights");
    for (light, needle) in [
        (json!({ "type": "point", "intensity": -1.0 }), "intensity"),
        (json!({ "type": "point", "range": 0.0 }), "range"),
        (json!({ "type": "spot", "spot": { "innerConeAngle": 0.6, "outerConeAngle": 0.5 } }), "cone"),
        (json!({ "type": "spot", "spot": { "outerConeAngle": 2.0 } }), "cone"),
    ] {
        let mut doc = triangle_doc();
        doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [light] } });
        doc["nodes"][0]["extensions"] = json!({ "KHR_lights_punctual": { "light": 0 } });
        let message = invalid_message(load_doc(&dir, &doc));
        assert!(message.contains("light 0") && message.contains(needle), "{message}");
    }

    // A hard-edged cone (inner == outer) is tolerated.
    let mut doc = triangle_doc();
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [
        { "type": "spot", "spot": { "innerConeAngle": 0.5, "outerConeAngle": 0.5 } }
    ] } });
    doc["nodes"][0]["extensions"] = json!({ "KHR_lights_punctual": { "light": 0 } });
    let scene = load_doc(&dir, &doc).unwrap();
    let LightKind::Spot { inner_cone_rad, outer_cone_rad } = scene.lights[0].kind else {
        panic!("not a spot light");
    };
    assert_eq!(outer_cone_rad, 0.5);
    assert!(inner_cone_rad < outer_cone_rad && inner_cone_rad > 0.49);
}

#[test]
fn perspective_camera_drops_node_scale() {
    let dir = TempDir::new("camera");
    let mut doc = triangle_doc();
    doc["cameras"] = json!([
        { "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5 } },
        { "type": "orthographic", "name": "ortho",
          "orthographic": { "xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 10.0 } }
    ]);
    doc["scenes"] = json!([{ "nodes": [0, 1, 2] }]);
    doc["nodes"] = json!([
        { "mesh": 0 },
        { "name": "eye", "camera": 0, "translation": [0.0, 1.0, 4.0], "scale": [3.0, 3.0, 3.0] },
        { "camera": 1 }
    ]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.cameras.len(), 1);
    let camera = &scene.cameras[0];
    assert_eq!(camera.name, "eye");
    assert_eq!(camera.node, 1);
    assert_eq!(camera.yfov_rad, 0.8);
    assert_eq!(camera.zfar, None);
    assert_eq!(camera.aspect_ratio, Some(1.5));
    let expected = Mat4::from_translation(Vec3::new(0.0, 1.0, 4.0));
    assert!(camera.world_from_view.abs_diff_eq(expected, 1e-6));
    assert!(
        scene.ignored.iter().any(|s| s.contains("camera 1 (ortho)") && s.contains("orthographic")),
        "{:?}",
        scene.ignored
    );
}

#[test]
fn missing_file_is_io_error_naming_the_path() {
    let path = std::env::temp_dir().join("chiaro-no-such-dir/scene.gltf");
    let error = load_gltf(&path).unwrap_err();
    assert!(matches!(error, SceneError::Io { .. }), "{error:?}");
    let message = error.to_string();
    assert!(message.contains("chiaro-no-such-dir/scene.gltf"), "{message}");
    assert!(message.contains("cannot read file"), "{message}");
}

#[test]
fn broken_json_is_parse_error_with_its_line() {
    let dir = TempDir::new("broken");
    let path = dir.write("broken.gltf", b"{\n  \"asset\": {\n    \"version\": \"2.0\",,\n  }\n}");
    let error = load_gltf(&path).unwrap_err();
    let SceneError::Parse { message, .. } = &error else {
        panic!("expected Parse, got {error:?}");
    };
    assert!(message.contains("line 3"), "{message}");
    assert!(error.to_string().contains("broken.gltf: not a valid glTF file"));

    let path = dir.write("image.gltf", &png_bytes(image::DynamicImage::new_rgba8(1, 1)));
    assert!(matches!(load_gltf(&path), Err(SceneError::Parse { .. })));
    let path = dir.write("empty.gltf", b"{}");
    assert!(matches!(load_gltf(&path), Err(SceneError::Parse { .. })));
    let path = dir.write("short.glb", b"glTF\x02\0\0\0");
    assert!(matches!(load_gltf(&path), Err(SceneError::Parse { .. })));
}

#[test]
fn required_extensions_are_checked() {
    let dir = TempDir::new("required");
    let mut doc = triangle_doc();
    doc["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
    doc["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    match load_doc(&dir, &doc) {
        Err(SceneError::UnsupportedExtension { extension, .. }) => {
            assert_eq!(extension, "KHR_draco_mesh_compression");
        }
        other => panic!("expected UnsupportedExtension, got {other:?}"),
    }

    // Used but not required: loads, and says what it ignored.
    doc["extensionsRequired"] = json!([]);
    doc["extensionsUsed"] = json!(["KHR_materials_transmission", "KHR_lights_punctual"]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.ignored, vec!["extension KHR_materials_transmission: not supported, ignored".to_owned()]);
}

#[test]
fn quantized_positions_load_when_mesh_quantization_is_required() {
    let dir = TempDir::new("quantized");
    let bytes: Vec<u8> = [0i16, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0].iter().flat_map(|v| v.to_le_bytes()).collect();
    let mut doc = triangle_doc();
    doc["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
    doc["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
    // VEC3 of i16 with a 8-byte stride (4-byte aligned), as the extension requires.
    doc["accessors"][0]["componentType"] = json!(5122);
    doc["bufferViews"][0] = json!({ "buffer": 0, "byteLength": 24, "byteStride": 8 });
    doc["buffers"] = json!([{ "byteLength": bytes.len(), "uri": data_uri(&bytes) }]);
    let scene = load_doc(&dir, &doc).unwrap();
    let p = &scene.meshes[0].primitives[0];
    assert_eq!(p.positions, vec![Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0)]);
}

#[test]
fn short_or_missing_buffers_name_the_buffer() {
    let dir = TempDir::new("buffers");
    let mut doc = triangle_doc();
    doc["buffers"][0]["byteLength"] = json!(400);
    doc["bufferViews"][0]["byteLength"] = json!(36);
    let message = invalid_message(load_doc(&dir, &doc));
    assert_eq!(message, "buffer 0 is 36 bytes but the file says 400");

    doc["buffers"][0] = json!({ "byteLength": 36, "uri": "missing%20file.bin" });
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.starts_with("buffer 0 (missing%20file.bin): cannot read"), "{message}");
    assert!(message.contains("missing file.bin"), "{message}");

    // An external buffer next to the file loads.
    dir.write("tri.bin", &f32_bytes(&TRIANGLE));
    doc["buffers"][0]["uri"] = json!("tri.bin");
    assert_eq!(load_doc(&dir, &doc).unwrap().triangle_count(), 1);
}

#[test]
fn out_of_range_indices_are_errors_not_panics() {
    let dir = TempDir::new("ranges");
    let mut doc = triangle_doc();
    doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(7);
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("accessor 7 is out of range"), "{message}");

    let mut doc = triangle_doc();
    doc["meshes"][0]["primitives"][0]["indices"] = json!(7);
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("accessor 7 is out of range"), "{message}");

    let mut doc = triangle_doc();
    doc["nodes"][0]["children"] = json!([5]);
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("node 5 is out of range"), "{message}");

    // In range, but reading past the end of its buffer view.
    let mut doc = triangle_doc();
    doc["accessors"][0]["count"] = json!(30);
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.starts_with("accessor 0 (POSITION of mesh 0 (triangle) primitive 0)"), "{message}");

    // A buffer view past the end of its buffer.
    let mut doc = triangle_doc();
    doc["bufferViews"][0]["byteOffset"] = json!(8);
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("buffer view 0"), "{message}");

    // Sizes that would overflow.
    let mut doc = triangle_doc();
    doc["accessors"][0]["count"] = json!(u64::MAX);
    assert!(load_doc(&dir, &doc).is_err());
    let mut doc = triangle_doc();
    doc["accessors"][0]["byteOffset"] = json!(u64::MAX - 2);
    assert!(load_doc(&dir, &doc).is_err());
}

#[test]
fn vertex_index_beyond_vertex_count_is_invalid() {
    let dir = TempDir::new("index");
    let mut bytes = f32_bytes(&TRIANGLE);
    bytes.extend([0u8, 1, 5, 0]);
    let mut doc = triangle_doc();
    doc["meshes"][0]["primitives"][0]["indices"] = json!(1);
    doc["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "bufferView": 1, "componentType": 5121, "count": 3, "type": "SCALAR" }));
    doc["bufferViews"] = json!([
        { "buffer": 0, "byteLength": 36 },
        { "buffer": 0, "byteOffset": 36, "byteLength": 3 }
    ]);
    doc["buffers"] = json!([{ "byteLength": bytes.len(), "uri": data_uri(&bytes) }]);
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("index 5 is out of range for 3 vertices"), "{message}");
}

#[test]
fn non_finite_positions_and_transforms_are_invalid() {
    let dir = TempDir::new("finite");
    let mut doc = triangle_doc();
    doc["scenes"] = json!([{ "nodes": [0] }]);
    doc["nodes"] = json!([
        { "name": "Big", "scale": [1e38, 1e38, 1e38], "children": [1] },
        { "name": "Bigger", "scale": [1e38, 1e38, 1e38], "mesh": 0 }
    ]);
    let message = invalid_message(load_doc(&dir, &doc));
    assert_eq!(message, "node 1 (Bigger): transform is not finite");

    let mut doc = triangle_doc();
    let bytes = f32_bytes(&[0.0, 0.0, 0.0, f32::NAN, 0.0, 0.0, 0.0, 1.0, 0.0]);
    doc["buffers"] = json!([{ "byteLength": bytes.len(), "uri": data_uri(&bytes) }]);
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("POSITION 1 is not finite"), "{message}");
}

#[test]
fn node_cycles_are_invalid() {
    let dir = TempDir::new("cycle");
    let mut doc = triangle_doc();
    doc["nodes"] = json!([{ "children": [1] }, { "children": [0], "mesh": 0 }]);
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("reached twice"), "{message}");
}

/// The triangle with TEXCOORD_0 and a material whose base colour texture is `image`.
fn textured_doc(image: Value) -> Value {
    let mut doc = triangle_doc();
    let bytes = f32_bytes(&[TRIANGLE.as_slice(), &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]].concat());
    doc["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC2" }));
    doc["bufferViews"][0]["byteLength"] = json!(bytes.len());
    doc["buffers"][0] = json!({ "byteLength": bytes.len(), "uri": data_uri(&bytes) });
    doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(1);
    doc["meshes"][0]["primitives"][0]["material"] = json!(0);
    doc["materials"] = json!([{ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } } }]);
    doc["textures"] = json!([{ "source": 0 }]);
    doc["images"] = json!([image]);
    doc
}

#[test]
fn unsupported_image_formats_name_the_image() {
    let dir = TempDir::new("gif");
    dir.write("tex.gif", b"GIF89a\x01\0\x01\0\0\0\0;");
    let message = invalid_message(load_doc(&dir, &textured_doc(json!({ "uri": "tex.gif" }))));
    assert!(message.starts_with("image 0 (tex.gif): unsupported image format"), "{message}");

    dir.write("tex.png", b"definitely not a png");
    let message = invalid_message(load_doc(&dir, &textured_doc(json!({ "uri": "tex.png" }))));
    assert!(message.starts_with("image 0 (tex.png): unsupported image format"), "{message}");

    let doc = textured_doc(json!({ "uri": "tex.png", "mimeType": "image/ktx2" }));
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("image/ktx2"), "{message}");

    // An image with a bufferView and no mimeType: the gltf crate's wrapper would panic.
    let message = invalid_message(load_doc(&dir, &textured_doc(json!({ "bufferView": 0 }))));
    assert!(message.starts_with("image 0: unsupported image format"), "{message}");
}

#[test]
fn materials_textures_and_generated_tangents() {
    let dir = TempDir::new("material");
    let mut rgba = image::RgbaImage::new(2, 1);
    rgba.put_pixel(1, 0, image::Rgba([10, 20, 30, 255]));
    dir.write("color.png", &png_bytes(rgba.into()));
    let grey16 = image::ImageBuffer::<image::Luma<u16>, _>::from_raw(1, 1, vec![65535u16]).unwrap();
    dir.write("orm.png", &png_bytes(image::DynamicImage::ImageLuma16(grey16)));

    // A quad facing +Z with upright glTF UVs (v = 0 at the top, y = 1).
    let mut bytes = f32_bytes(&[
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0, // POSITION
        0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, // NORMAL
        0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, // TEXCOORD_0
    ]);
    bytes.extend([0u8, 1, 2, 0, 2, 3]);
    let mut doc = triangle_doc();
    doc["meshes"][0]["primitives"][0] = json!({
        "attributes": { "POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "TEXCOORD_1": 2 },
        "indices": 3, "material": 0
    });
    doc["accessors"] = json!([
        { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] },
        { "bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3" },
        { "bufferView": 0, "byteOffset": 96, "componentType": 5126, "count": 4, "type": "VEC2" },
        { "bufferView": 0, "byteOffset": 128, "componentType": 5121, "count": 6, "type": "SCALAR" }
    ]);
    doc["bufferViews"] = json!([{ "buffer": 0, "byteLength": bytes.len() }]);
    doc["buffers"] = json!([{ "byteLength": bytes.len(), "uri": data_uri(&bytes) }]);
    doc["extensionsUsed"] = json!(["KHR_texture_transform", "KHR_materials_emissive_strength"]);
    doc["materials"] = json!([{
        "name": "painted",
        "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 0.5, 0.5, 1.0],
            "baseColorTexture": { "index": 0, "extensions": { "KHR_texture_transform": {
                "offset": [0.5, 0.0], "rotation": 0.25, "scale": [2.0, 2.0], "texCoord": 1 } } },
            "metallicFactor": 0.25, "roughnessFactor": 0.75,
            "metallicRoughnessTexture": { "index": 1 }
        },
        "normalTexture": { "index": 0, "scale": 0.5,
            "extensions": { "KHR_texture_transform": { "scale": [3.0, 3.0] } } },
        "occlusionTexture": { "index": 1, "strength": 0.25 },
        "emissiveFactor": [1.0, 0.5, 0.0],
        "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": 4.0 } },
        "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true
    }, { "name": "unused image", "emissiveTexture": { "index": 2 } }]);
    doc["samplers"] = json!([{ "magFilter": 9728, "minFilter": 9729, "wrapS": 33071, "wrapT": 33648 }]);
    doc["textures"] = json!([{ "source": 0, "sampler": 0 }, { "source": 1 }, { "source": 0 }]);
    doc["images"] = json!([{ "uri": "color.png" }, { "uri": "orm.png" }, { "uri": "never-read.png" }]);
    let scene = load_doc(&dir, &doc).unwrap();

    // Image 0 is both colour and normal map: decoded once, as sRGB.
    assert_eq!(scene.images.len(), 2);
    let color = &scene.images[0];
    assert_eq!((color.width, color.height), (2, 1));
    assert_eq!(color.color_space, ColorSpace::Srgb);
    assert_eq!(&color.rgba8[4..], &[10, 20, 30, 255]);
    assert_eq!(color.name, "color.png");
    let orm = &scene.images[1];
    assert_eq!(orm.color_space, ColorSpace::Linear);
    assert_eq!(orm.rgba8, vec![255, 255, 255, 255]);

    let m = &scene.materials[0];
    assert_eq!(m.name, "painted");
    assert_eq!(m.base_color, Vec4::new(0.5, 0.5, 0.5, 1.0));
    assert_eq!((m.metallic, m.roughness), (0.25, 0.75));
    assert_eq!(m.emissive, Vec3::new(4.0, 2.0, 0.0));
    assert_eq!(m.alpha_mode, AlphaMode::Mask);
    assert_eq!(m.alpha_cutoff, 0.3);
    assert!(m.double_sided);
    assert_eq!((m.normal_scale, m.occlusion_strength), (0.5, 0.25));
    let base = m.base_color_texture.unwrap();
    assert_eq!(base.image, 0);
    assert_eq!(base.tex_coord, 1);
    assert_eq!(
        base.transform,
        UvTransform { offset: Vec2::new(0.5, 0.0), rotation_rad: 0.25, scale: Vec2::splat(2.0) }
    );
    assert_eq!(
        base.sampler,
        SamplerDesc {
            wrap_u: WrapMode::ClampToEdge,
            wrap_v: WrapMode::MirroredRepeat,
            mag_linear: false,
            min_linear: true,
            mipmaps: false,
        }
    );
    let normal = m.normal_texture.unwrap();
    assert_eq!(normal.image, 0);
    assert_eq!(normal.transform.scale, Vec2::splat(3.0));
    assert_eq!(m.metallic_roughness_texture.unwrap().image, 1);
    assert_eq!(m.occlusion_texture.unwrap().sampler, SamplerDesc::default());
    // The second material's image was never decoded (its file does not exist) but
    // materials still refer into `Scene::images`.
    assert_eq!(scene.materials[1].emissive_texture.unwrap().image, 0);

    let p = &scene.meshes[0].primitives[0];
    assert_eq!(p.triangle_count(), 2);
    for t in &p.tangents {
        assert!(t.truncate().distance(Vec3::X) < 1e-5, "{t}");
        assert_eq!(t.w, 1.0);
    }
}

#[test]
fn glb_with_bin_chunk_loads() {
    let dir = TempDir::new("glb");
    let mut bin = f32_bytes(&TRIANGLE);
    let mut doc = triangle_doc();
    doc["buffers"] = json!([{ "byteLength": bin.len() }]);
    let mut json_chunk = doc.to_string().into_bytes();
    while !json_chunk.len().is_multiple_of(4) {
        json_chunk.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json_chunk.len() + 8 + bin.len();
    let mut glb = Vec::new();
    glb.extend_from_slice(b"glTF");
    glb.extend(2u32.to_le_bytes());
    glb.extend((total as u32).to_le_bytes());
    glb.extend((json_chunk.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&json_chunk);
    glb.extend((bin.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&bin);
    let path = dir.write("scene.glb", &glb);
    assert_eq!(load_gltf(&path).unwrap().triangle_count(), 1);

    // Truncated: the header promises more than the file has.
    let path = dir.write("cut.glb", &glb[..glb.len() - 10]);
    assert!(matches!(load_gltf(&path), Err(SceneError::Parse { .. })));
}

#[test]
fn ignored_features_are_counted_once_per_kind() {
    let dir = TempDir::new("ignored");
    let mut doc = triangle_doc();
    let prim = doc["meshes"][0]["primitives"][0].clone();
    let mut points = prim.clone();
    points["mode"] = json!(0);
    let mut colored = prim.clone();
    colored["attributes"]["COLOR_0"] = json!(0);
    doc["meshes"][0]["primitives"] = json!([prim, points.clone(), points, colored, { "attributes": {} }]);
    doc["animations"] = json!([
        { "channels": [], "samplers": [] },
        { "channels": [], "samplers": [] },
        { "channels": [], "samplers": [] }
    ]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.meshes[0].primitives.len(), 2);
    assert_eq!(
        scene.ignored,
        vec![
            "3 animations: not played; the nodes it moves are dynamic (lit by light probes)".to_owned(),
            "1 primitive with vertex colours: not supported, ignored".to_owned(),
            "2 primitives of points or lines: not supported, ignored".to_owned(),
            "1 primitive without POSITION: nothing to draw, ignored".to_owned(),
        ]
    );
}

/// Every scene under shared/assets loads with triangles and the lights its README lists.
#[test]
fn shared_assets_load_with_their_documented_lights() {
    let assets = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/assets"));
    // (folder, directional, spot, point, cameras)
    let expected = [
        ("ShadowsDirectional", 1, 0, 0, 1),
        ("ShadowsSpot", 0, 1, 0, 1),
        ("LightsPunctualLamp", 0, 0, 5, 0),
        ("GlamVelvetSofa", 1, 0, 0, 0),
        ("IridescenceSuzanne", 1, 0, 0, 0),
        ("chiaro-bench", 1, 4, 60, 1),
    ];
    fn scene_files(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                scene_files(&path, out);
            } else if path.extension().is_some_and(|e| e == "gltf" || e == "glb") {
                out.push(path);
            }
        }
    }
    for (folder, directional, spot, point, cameras) in expected {
        let mut files = Vec::new();
        scene_files(&assets.join(folder), &mut files);
        assert!(!files.is_empty(), "no glTF under {folder}");
        for file in files {
            let scene = load_gltf(&file).unwrap_or_else(|e| panic!("{e}"));
            assert!(scene.triangle_count() > 0, "{folder}: no triangles");
            let count = |f: fn(&LightKind) -> bool| scene.lights.iter().filter(|l| f(&l.kind)).count();
            assert_eq!(count(|k| *k == LightKind::Directional), directional, "{folder}");
            assert_eq!(count(|k| matches!(k, LightKind::Spot { .. })), spot, "{folder}");
            assert_eq!(count(|k| *k == LightKind::Point), point, "{folder}");
            assert_eq!(scene.cameras.len(), cameras, "{folder}");
            for light in &scene.lights {
                assert!((light.direction().length() - 1.0).abs() < 1e-4, "{folder}: {}", light.name);
            }
            for mesh in &scene.meshes {
                for p in &mesh.primitives {
                    let n = p.positions.len();
                    assert!(p.normals.len() == n && p.tangents.len() == n);
                    assert!(p.uv0.len() == n && p.uv1.len() == n);
                    assert!(p.indices.iter().all(|&i| (i as usize) < n));
                    assert!(p.tangents.iter().all(|t| t.is_finite() && t.w.abs() == 1.0));
                }
            }
            if folder == "ShadowsSpot" {
                assert_eq!(scene.lights[0].range, Some(25.0));
            }
        }
    }
}

/// Files the glTF 2.0 spec forbids, each refused with the JSON path of what is wrong.
#[test]
fn spec_violations_are_errors_naming_the_json_path() {
    let dir = TempDir::new("spec");
    let textured = || textured_doc(json!({ "uri": "never-read.png" }));
    let cases: Vec<(Value, &str)> = vec![
        (
            {
                let mut d = textured();
                d["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = json!([1.0, -0.5, 1.0, 1.0]);
                d
            },
            "materials[0].pbrMetallicRoughness.baseColorFactor[1]: -0.5 is outside [0, 1]",
        ),
        (
            {
                let mut d = textured();
                d["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = json!(5.0);
                d
            },
            "materials[0].pbrMetallicRoughness.metallicFactor: 5 is outside [0, 1]",
        ),
        (
            {
                let mut d = textured();
                d["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] = json!(-1.0);
                d
            },
            "materials[0].pbrMetallicRoughness.roughnessFactor: -1 is outside [0, 1]",
        ),
        (
            {
                let mut d = textured();
                d["materials"][0]["emissiveFactor"] = json!([0.0, 2.0, 0.0]);
                d
            },
            "materials[0].emissiveFactor[1]: 2 is outside [0, 1]",
        ),
        (
            {
                let mut d = triangle_doc();
                d["bufferViews"][0]["byteStride"] = json!(4);
                d
            },
            "accessors[0]: its elements are 12 bytes, more than bufferViews[0].byteStride (4), so they would overlap",
        ),
        (
            {
                let mut d = triangle_doc();
                d["accessors"][0]["componentType"] = json!(5121);
                d
            },
            "meshes[0].primitives[0].attributes[\"POSITION\"]: accessor 0 holds UNSIGNED_BYTE, which POSITION \
             cannot be (without KHR_mesh_quantization)",
        ),
        (
            {
                let mut d = triangle_doc();
                let bytes = f32_bytes(&[TRIANGLE.as_slice(), &[0.0, 0.0, 0.0]].concat());
                d["accessors"][0]["count"] = json!(4);
                d["bufferViews"][0]["byteLength"] = json!(bytes.len());
                d["buffers"][0] = json!({ "byteLength": bytes.len(), "uri": data_uri(&bytes) });
                d
            },
            "meshes[0].primitives[0]: 4 vertices do not make whole triangles (TRIANGLES takes a multiple of 3)",
        ),
        (
            {
                let mut d = textured();
                d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = json!(1);
                d
            },
            "meshes[0].primitives[0]: materials[0].pbrMetallicRoughness.baseColorTexture.texCoord is 1, but the \
             primitive has no TEXCOORD_1",
        ),
        (
            {
                let mut d = triangle_doc();
                d["nodes"][0]["matrix"] = json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);
                d["nodes"][0]["translation"] = json!([1, 2, 3]);
                d
            },
            "nodes[0]: has both matrix and translation; glTF allows one or the other",
        ),
    ];
    for (doc, expected) in cases {
        let message = invalid_message(load_doc(&dir, &doc));
        assert_eq!(message, expected);
    }
}

#[test]
fn quantized_positions_and_whole_index_lists_load() {
    let dir = TempDir::new("spec-ok");
    // UNSIGNED_BYTE positions are fine once the file uses KHR_mesh_quantization.
    let mut doc = triangle_doc();
    let bytes: Vec<u8> = vec![0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0];
    doc["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
    doc["accessors"][0] = json!({ "bufferView": 0, "componentType": 5121, "count": 3, "type": "VEC3",
        "min": [0, 0, 0], "max": [1, 1, 0] });
    doc["bufferViews"][0] = json!({ "buffer": 0, "byteLength": 12, "byteStride": 4 });
    doc["buffers"][0] = json!({ "byteLength": bytes.len(), "uri": data_uri(&bytes) });
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.triangle_count(), 1);
    assert_eq!(scene.meshes[0].primitives[0].positions[1], Vec3::X);
}

/// The triangle lit by one light of `light` (JSON) on a second node, with `images`.
fn cookie_doc(light: Value, images: Value) -> Value {
    let mut doc = triangle_doc();
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [light] } });
    doc["nodes"].as_array_mut().unwrap().push(json!({
        "name": "lamp",
        "translation": [1.0, 2.0, 3.0],
        "extensions": { "KHR_lights_punctual": { "light": 0 } }
    }));
    doc["scenes"][0]["nodes"] = json!([0, 1]);
    doc["images"] = images;
    doc
}

fn png_uri(width: u32, height: u32) -> Value {
    let image = image::RgbaImage::from_fn(width, height, |x, y| image::Rgba([x as u8 * 10, y as u8 * 10, 7, 255]));
    json!({ "uri": data_uri(&png_bytes(image.into())), "mimeType": "image/png" })
}

#[test]
fn cookies_load_for_every_light_type_with_their_images_as_stored() {
    let dir = TempDir::new("cookies");
    let cases = [
        (
            json!({ "type": "directional", "extras": { "cookie": { "image": 1, "size": [2.0, 0.5] } } }),
            Vec2::new(2.0, 0.5),
        ),
        (
            json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 }, "extras": { "cookie": { "image": 1 } } }),
            Vec2::ONE,
        ),
        (json!({ "type": "point", "extras": { "cookie": { "image": 0 } } }), Vec2::ONE),
    ];
    for (light, size) in cases {
        let image = light["extras"]["cookie"]["image"].as_u64().unwrap() as usize;
        let scene = load_doc(&dir, &cookie_doc(light, json!([png_uri(12, 2), png_uri(4, 3)]))).unwrap();
        let cookie = scene.lights[0].cookie.expect("a cookie");
        assert_eq!(cookie.size_m, size);
        // Only the image the cookie uses is decoded, linear, with its texels as stored.
        assert_eq!(scene.images.len(), 1);
        let decoded = &scene.images[cookie.image];
        assert_eq!(decoded.color_space, ColorSpace::Linear);
        let (width, height) = if image == 0 { (12, 2) } else { (4, 3) };
        assert_eq!((decoded.width, decoded.height), (width, height));
        let texel = 4 * (width as usize + 3);
        assert_eq!(&decoded.rgba8[texel..texel + 4], &[30, 10, 7, 255], "texel (3, 1)");
    }
}

#[test]
fn bad_cookies_are_errors_naming_the_light() {
    let dir = TempDir::new("bad-cookies");
    dir.write("broken.png", b"not a png");
    let images = json!([png_uri(12, 2), png_uri(4, 4), { "uri": "broken.png" }, { "uri": "missing.png" }]);
    for (cookie_light, needle) in [
        (
            json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 }, "extras": { "cookie": { "image": 9 } } }),
            "extras.cookie.image: 9 is not an image",
        ),
        (json!({ "type": "point", "extras": { "cookie": { "image": 1 } } }), "six square faces side by side (6:1)"),
        (json!({ "type": "directional", "extras": { "cookie": { "image": 1 } } }), "needs [width, height]"),
        (json!({ "type": "directional", "extras": { "cookie": { "image": 1, "size": [1.0, 0.0] } } }), "both positive"),
        (
            json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 }, "extras": { "cookie": { "image": 2 } } }),
            "broken.png",
        ),
        (
            json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 }, "extras": { "cookie": { "image": 3 } } }),
            "missing.png",
        ),
        (
            json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 }, "extras": { "cookie": { "image": 0, "tiles": 2 } } }),
            "tiles",
        ),
        (json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 }, "extras": { "cookie": 3 } }), "cookie"),
    ] {
        let mut light = cookie_light;
        light["name"] = json!("gobo");
        let message = match load_doc(&dir, &cookie_doc(light, images.clone())) {
            Err(SceneError::Invalid { message, .. }) => message,
            Err(SceneError::Io { .. }) => panic!("a missing cookie image is an invalid scene naming the light"),
            other => panic!("expected an error, got {other:?}"),
        };
        assert!(message.contains("gobo") && message.contains(needle), "{needle}: {message}");
    }
}

#[test]
fn animated_nodes_and_their_children_are_dynamic_and_extras_override() {
    let dir = TempDir::new("animated");
    let mut doc = triangle_doc();
    // Node 0 still; node 1 animated, carrying node 2; node 3 still but says static: false;
    // node 4 animated but says static: true.
    doc["scenes"] = json!([{ "nodes": [0, 1, 3, 4] }]);
    doc["nodes"] = json!([
        { "mesh": 0, "name": "still" },
        { "mesh": 0, "name": "spinning", "children": [2] },
        { "mesh": 0, "name": "carried" },
        { "mesh": 0, "name": "declared", "extras": { "static": false } },
        { "mesh": 0, "name": "pinned", "extras": { "static": true } },
    ]);
    // The channels' samplers reuse the position accessor; only the targets matter here.
    doc["animations"] = json!([{
        "channels": [
            { "sampler": 0, "target": { "node": 1, "path": "translation" } },
            { "sampler": 0, "target": { "node": 4, "path": "translation" } }
        ],
        "samplers": [{ "input": 0, "output": 0 }]
    }]);
    let scene = load_doc(&dir, &doc).unwrap();
    let flags: Vec<(&str, bool)> = scene.instances.iter().map(|i| (i.name.as_str(), i.is_static)).collect();
    assert_eq!(
        flags,
        vec![("still", true), ("spinning", false), ("carried", false), ("declared", false), ("pinned", true)]
    );
    let mut bad = triangle_doc();
    bad["nodes"][0]["extras"] = json!({ "static": 1 });
    assert!(invalid_message(load_doc(&dir, &bad)).contains("extras.static"));
}

#[test]
fn light_mode_comes_from_extras() {
    let dir = TempDir::new("light mode");
    let mut doc = triangle_doc();
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [
        { "type": "point", "extras": { "mode": "baked" } },
        { "type": "point" }
    ] } });
    doc["scenes"] = json!([{ "nodes": [0, 1, 2] }]);
    doc["nodes"] = json!([
        { "mesh": 0 },
        { "extensions": { "KHR_lights_punctual": { "light": 0 } } },
        { "extensions": { "KHR_lights_punctual": { "light": 1 } } }
    ]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.lights.iter().map(|l| l.mode).collect::<Vec<_>>(), vec![LightMode::Baked, LightMode::Realtime]);
    doc["extensions"]["KHR_lights_punctual"]["lights"][1]["extras"] = json!({ "mode": "never" });
    assert!(invalid_message(load_doc(&dir, &doc)).contains("extras.mode"));
}
