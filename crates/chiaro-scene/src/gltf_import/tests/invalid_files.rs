//! Files the importer refuses or tolerates: missing files, broken JSON, required
//! extensions, short buffers, indices out of range, non-finite numbers, node cycles and
//! what the glTF 2.0 spec forbids, each in; a `SceneError` whose message names what is
//! wrong (its JSON path where it has one) out.

use super::{TRIANGLE, TempDir, data_uri, f32_bytes, invalid_message, load_doc, png_bytes, textured_doc, triangle_doc};
use crate::error::SceneError;
use crate::gltf_import::load_gltf;
use serde_json::{Value, json};

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
    doc["extensionsUsed"] = json!(["EXT_lights_ies"]);
    doc["extensionsRequired"] = json!(["EXT_lights_ies"]);
    match load_doc(&dir, &doc) {
        Err(SceneError::UnsupportedExtension { extension, .. }) => {
            assert_eq!(extension, "EXT_lights_ies");
        }
        other => panic!("expected UnsupportedExtension, got {other:?}"),
    }

    // Used but not required: loads, and says what it ignored.
    doc["extensionsRequired"] = json!([]);
    doc["extensionsUsed"] = json!(["EXT_lights_ies", "KHR_lights_punctual", "KHR_materials_transmission"]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.ignored, vec!["extension EXT_lights_ies: not supported, ignored".to_owned()]);
}

#[test]
fn short_or_missing_buffers_name_the_buffer() {
    let dir = TempDir::new("buffers");
    let mut doc = triangle_doc();
    doc["buffers"][0]["byteLength"] = json!(400);
    doc["bufferViews"][0]["byteLength"] = json!(36);
    let message = invalid_message(load_doc(&dir, &doc));
    assert_eq!(message, "buffers[0] is 36 bytes but the file says 400");

    doc["buffers"][0] = json!({ "byteLength": 36, "uri": "missing%20file.bin" });
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.starts_with("buffers[0] (missing%20file.bin): cannot read"), "{message}");
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
    assert!(message.starts_with("accessors[0] (POSITION of meshes[0].primitives[0] (triangle))"), "{message}");

    // A buffer view past the end of its buffer.
    let mut doc = triangle_doc();
    doc["bufferViews"][0]["byteOffset"] = json!(8);
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("bufferViews[0]"), "{message}");

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
    assert_eq!(
        message,
        "meshes[0].primitives[0].indices (accessors[1]): element 2 is 5, but POSITION has only 3 vertices"
    );
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
    assert_eq!(message, "nodes[1] (Bigger): transform is not finite");

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
