//! EXT_mesh_gpu_instancing: a node's instances become one `MeshInstance` each, placed by
//! the node's transform times the instance's (float translations and scales, normalised
//! short rotations), numbered for the instance AOV after the file's nodes; broken
//! instance data is refused naming the node.

use super::*;
use crate::types::MeshInstance;
use glam::{Mat4, Quat, Vec3};

/// The triangle on node 0 (moved 5 m down -Z) with three instances, and again on node 1
/// without instancing.
fn instanced_doc() -> Value {
    let mut doc = triangle_doc();
    let translations = f32_bytes(&[1.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 3.0]);
    // Identity, 90 degrees about Z, 180 degrees about Y; normalised shorts.
    let s = (0.5f32.sqrt() * 32767.0).round() as i16;
    let rotations: Vec<u8> =
        [0i16, 0, 0, 32767, 0, 0, s, s, 0, 32767, 0, 0].iter().flat_map(|v| v.to_le_bytes()).collect();
    let scales = f32_bytes(&[1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 1.0, 0.5, 1.0]);
    let bytes = [translations, rotations, scales].concat();
    doc["buffers"].as_array_mut().unwrap().push(json!({ "byteLength": bytes.len(), "uri": data_uri(&bytes) }));
    doc["bufferViews"].as_array_mut().unwrap().push(json!({ "buffer": 1, "byteLength": bytes.len() }));
    let accessors = doc["accessors"].as_array_mut().unwrap();
    accessors.push(json!({ "bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3" }));
    accessors.push(json!({ "bufferView": 1, "byteOffset": 36, "componentType": 5122, "normalized": true, "count": 3, "type": "VEC4" }));
    accessors.push(json!({ "bufferView": 1, "byteOffset": 60, "componentType": 5126, "count": 3, "type": "VEC3" }));
    doc["nodes"] = json!([
        { "mesh": 0, "name": "grass", "translation": [0.0, 0.0, -5.0], "extensions": { "EXT_mesh_gpu_instancing": {
            "attributes": { "TRANSLATION": 1, "ROTATION": 2, "SCALE": 3 } } } },
        { "mesh": 0, "name": "single" }
    ]);
    doc["scenes"][0]["nodes"] = json!([0, 1]);
    doc["extensionsUsed"] = json!(["EXT_mesh_gpu_instancing"]);
    doc["extensionsRequired"] = json!(["EXT_mesh_gpu_instancing"]);
    doc
}

#[test]
fn each_instance_is_placed_by_the_node_and_its_own_transform() {
    let dir = TempDir::new("instancing");
    let scene = load_doc(&dir, &instanced_doc()).unwrap();
    let copies: Vec<&MeshInstance> = scene.instances.iter().filter(|i| i.node == 0).collect();
    assert_eq!(copies.len(), 3);
    let node = Mat4::from_translation(Vec3::new(0.0, 0.0, -5.0));
    let expected = [
        Mat4::from_translation(Vec3::X),
        Mat4::from_scale_rotation_translation(
            Vec3::splat(2.0),
            Quat::from_rotation_z(90f32.to_radians()),
            2.0 * Vec3::Y,
        ),
        Mat4::from_scale_rotation_translation(
            Vec3::new(1.0, 0.5, 1.0),
            Quat::from_rotation_y(180f32.to_radians()),
            3.0 * Vec3::Z,
        ),
    ];
    for (k, (copy, local)) in copies.iter().zip(expected).enumerate() {
        assert!(copy.world_from_local.abs_diff_eq(node * local, 1e-4), "instance {k}: {}", copy.world_from_local);
        assert_eq!(copy.name, format!("grass [{k}]"));
        // Ids after the file's two nodes, in accessor order.
        assert_eq!(copy.aov_id(), 2 + k);
    }
    let single: Vec<&MeshInstance> = scene.instances.iter().filter(|i| i.node == 1).collect();
    assert_eq!(single.len(), 1);
    assert_eq!(single[0].aov_id(), 1);
    assert!(single[0].gpu_instance.is_none());
}

#[test]
fn broken_instance_data_is_refused_naming_the_node() {
    let dir = TempDir::new("instancing-broken");
    let mut doc = instanced_doc();
    doc["accessors"][3]["count"] = json!(2);
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(
        message.contains("nodes[0].extensions.EXT_mesh_gpu_instancing") && message.contains("different counts"),
        "{message}"
    );

    let mut doc = instanced_doc();
    doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] = json!({ "SCALE": 3, "TRANSLATION": 9 });
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("attributes.TRANSLATION: 9 is not an accessor"), "{message}");

    // A zero scale cannot be inverted, as the normals need.
    let mut doc = instanced_doc();
    let zero = f32_bytes(&[0.0; 9]);
    doc["buffers"].as_array_mut().unwrap().push(json!({ "byteLength": 36, "uri": data_uri(&zero) }));
    doc["bufferViews"].as_array_mut().unwrap().push(json!({ "buffer": 2, "byteLength": 36 }));
    doc["accessors"][3] = json!({ "bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3" });
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("instance 0 has a transform that is not finite or cannot be inverted"), "{message}");
}
