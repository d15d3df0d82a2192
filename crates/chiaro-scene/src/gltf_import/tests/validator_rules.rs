//! Rules of the Khronos glTF-Validator that decide whether drawn data is sound, each on a
//! document shaped like the validator's own test file for it (test/base/data/…), once as
//! the validator has it (nothing draws the object: it loads, with a note at most) and once
//! placed in the scene (drawn: refused, naming the JSON path); and two files the validator
//! passes with a warning, which load.

use super::{TempDir, data_uri, f32_bytes, invalid_message, load_doc, triangle_doc};
use serde_json::{Value, json};

/// `doc` with its mesh 0 placed by node 0 of scene 0.
fn placed(mut doc: Value) -> Value {
    doc["scene"] = json!(0);
    doc["scenes"] = json!([{ "nodes": [0] }]);
    doc["nodes"] = json!([{ "mesh": 0 }]);
    doc
}

/// As mesh_data/index_buffer_oob.gltf: six UNSIGNED_BYTE indices 0..5 into four vertices.
fn index_oob_doc() -> Value {
    json!({
        "asset": { "version": "2.0" },
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 1 }, "mode": 4, "indices": 0 }] }],
        "accessors": [
            { "type": "SCALAR", "componentType": 5121, "count": 6, "bufferView": 0 },
            { "type": "VEC3", "componentType": 5126, "count": 4, "min": [0, 0, 0], "max": [0, 0, 0] }
        ],
        "bufferViews": [{ "buffer": 0, "byteLength": 6, "target": 34963 }],
        "buffers": [{ "byteLength": 6, "uri": data_uri(&[0, 1, 2, 3, 4, 5]) }]
    })
}

#[test]
fn an_index_past_the_vertices_is_refused_where_drawn() {
    let dir = TempDir::new("index-oob");
    let scene = load_doc(&dir, &index_oob_doc()).unwrap();
    assert_eq!(scene.triangle_count(), 0);
    let message = invalid_message(load_doc(&dir, &placed(index_oob_doc())));
    assert_eq!(
        message,
        "meshes[0].primitives[0].indices (accessors[0]): element 4 is 4, but POSITION has only 4 vertices"
    );
}

/// As mesh_data/index_buffer_primitive_restart.gltf: indices 0, 1, 255 into 256 vertices.
fn restart_doc(indices: Value, bytes: &[u8]) -> Value {
    json!({
        "asset": { "version": "2.0" },
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 1 }, "indices": 0 }] }],
        "accessors": [
            indices,
            { "type": "VEC3", "componentType": 5126, "count": 70000, "min": [0, 0, 0], "max": [0, 0, 0] }
        ],
        "bufferViews": [{ "buffer": 0, "byteLength": bytes.len(), "target": 34963 }],
        "buffers": [{ "byteLength": bytes.len(), "uri": data_uri(bytes) }]
    })
}

#[test]
fn the_primitive_restart_value_is_refused_in_drawn_indices() {
    let dir = TempDir::new("restart");
    let bytes_u8 = [0u8, 1, 255];
    let u8_indices = json!({ "type": "SCALAR", "componentType": 5121, "count": 3, "bufferView": 0 });
    assert_eq!(load_doc(&dir, &restart_doc(u8_indices.clone(), &bytes_u8)).unwrap().triangle_count(), 0);
    let message = invalid_message(load_doc(&dir, &placed(restart_doc(u8_indices, &bytes_u8))));
    assert_eq!(
        message,
        "meshes[0].primitives[0].indices (accessors[0]): element 2 is 255, the primitive restart value, which glTF \
         forbids in indices"
    );
    // 255 is an ordinary index among UNSIGNED_SHORT ones; 65535 is their restart value.
    let short = |values: [u16; 3]| values.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<u8>>();
    let u16_indices = json!({ "type": "SCALAR", "componentType": 5123, "count": 3, "bufferView": 0 });
    let scene = load_doc(&dir, &placed(restart_doc(u16_indices.clone(), &short([0, 1, 255])))).unwrap();
    assert_eq!(scene.triangle_count(), 1);
    let message = invalid_message(load_doc(&dir, &placed(restart_doc(u16_indices, &short([65535, 1, 2])))));
    assert!(message.contains("element 0 is 65535, the primitive restart value"), "{message}");
}

/// As mesh_data/joints_no_weights.gltf: a 32-byte buffer view on a 16-byte buffer, read by
/// a skinned points primitive of a node outside any scene.
fn view_too_long_doc() -> Value {
    json!({
        "asset": { "version": "2.0" },
        "nodes": [{}, { "mesh": 0, "skin": 0 }],
        "skins": [{ "joints": [0] }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0, "JOINTS_0": 1, "WEIGHTS_0": 2 }, "mode": 0 }] }],
        "accessors": [
            { "type": "VEC3", "componentType": 5126, "count": 1, "min": [0, 0, 0], "max": [0, 0, 0] },
            { "type": "VEC4", "componentType": 5121, "count": 1, "bufferView": 0, "byteOffset": 12 },
            { "type": "VEC4", "componentType": 5126, "count": 1, "bufferView": 0, "byteOffset": 16 }
        ],
        "bufferViews": [{ "buffer": 0, "byteLength": 32, "byteStride": 32, "target": 34962 }],
        "buffers": [{ "byteLength": 16, "uri": data_uri(&[0; 16]) }]
    })
}

#[test]
fn a_buffer_view_past_its_buffer_is_refused_wherever_a_drawn_primitive_reads_it() {
    let dir = TempDir::new("view-too-long");
    // As the validator has it: no scene draws the node.
    load_doc(&dir, &view_too_long_doc()).unwrap();
    let expected = "bufferViews[0] (bytes 0..32) runs past the end of buffers[0] (16 bytes)";

    // Placed: its points are not drawn, but their data is checked all the same.
    let mut doc = view_too_long_doc();
    doc["scene"] = json!(0);
    doc["scenes"] = json!([{ "nodes": [1] }]);
    assert_eq!(invalid_message(load_doc(&dir, &doc)), expected);

    // JOINTS_0 without WEIGHTS_0 on a drawn triangle: Chiaro reads past the joints, and
    // checks them as if it read them.
    let mut doc = triangle_doc();
    let positions = f32_bytes(&super::TRIANGLE);
    doc["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = json!(1);
    doc["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "type": "VEC4", "componentType": 5121, "count": 3, "bufferView": 1 }));
    doc["bufferViews"] = json!([
        { "buffer": 0, "byteLength": 36 },
        { "buffer": 1, "byteLength": 32 }
    ]);
    doc["buffers"] = json!([
        { "byteLength": 36, "uri": data_uri(&positions) },
        { "byteLength": 16, "uri": data_uri(&[0; 16]) }
    ]);
    let message = invalid_message(load_doc(&dir, &doc));
    assert_eq!(message, expected.replace("buffers[0]", "buffers[1]").replace("bufferViews[0]", "bufferViews[1]"));

    // The data behind the buffer goes on (a longer .bin), yet the view runs past the
    // buffer's byteLength: still refused, since the file says the buffer ends there.
    let mut doc = triangle_doc();
    let mut bytes = positions.clone();
    bytes.extend([0u8; 40]);
    dir.write("long.bin", &bytes);
    doc["buffers"][0] = json!({ "byteLength": 24, "uri": "long.bin" });
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.starts_with("bufferViews[0] (bytes 0..36) runs past the end of buffers[0] (24 bytes"), "{message}");
}

/// As accessor/unknown_type.gltf: two accessors of type "NotaVEC3" that nothing uses.
#[test]
fn an_unused_accessor_of_unknown_type_is_read_past_with_a_note() {
    let dir = TempDir::new("unknown-type");
    let mut doc = triangle_doc();
    for component in [5126, 5125] {
        doc["accessors"].as_array_mut().unwrap().push(json!({
            "componentType": component, "count": 24, "max": [1, 1, 1], "min": [-1, -1, -1], "type": "NotaVEC3"
        }));
    }
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.triangle_count(), 1);
    for a in [1, 2] {
        let note = format!("accessors[{a}].type: \"NotaVEC3\" is not a glTF accessor type; nothing drawn reads it");
        assert!(scene.ignored.contains(&note), "{:?}", scene.ignored);
    }
    // Drawn, it is refused by name.
    doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(1);
    let message = invalid_message(load_doc(&dir, &doc));
    assert_eq!(message, "accessors[1] (POSITION of meshes[0].primitives[0] (triangle)) has an invalid type");
}

/// As mesh/primitive_incompatible_mode.gltf: TRIANGLES over 4 vertices.
#[test]
fn a_vertex_count_that_does_not_fit_its_mode_draws_its_whole_triangles() {
    let dir = TempDir::new("incompatible-mode");
    let mut doc = triangle_doc();
    let bytes = f32_bytes(&[super::TRIANGLE.as_slice(), &[1.0, 1.0, 0.0]].concat());
    doc["accessors"][0]["count"] = json!(4);
    doc["accessors"][0]["max"] = json!([1, 1, 0]);
    doc["bufferViews"][0]["byteLength"] = json!(bytes.len());
    doc["buffers"][0] = json!({ "byteLength": bytes.len(), "uri": data_uri(&bytes) });
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.triangle_count(), 1);
    let note = "meshes[0].primitives[0] (triangle): 4 vertices do not make whole TRIANGLES; the last 1 not drawn \
                (1 triangles drawn)";
    assert!(scene.ignored.iter().any(|i| i == note), "{:?}", scene.ignored);

    // A strip of two vertices draws nothing, and says so.
    doc["meshes"][0]["primitives"][0]["mode"] = json!(5);
    doc["accessors"][0]["count"] = json!(2);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.triangle_count(), 0);
    assert!(
        scene.ignored.iter().any(|i| i.contains("2 vertices do not make whole TRIANGLE_STRIP; the last 2 not drawn")),
        "{:?}",
        scene.ignored
    );
}
