//! Meshes and nodes as they come out of the importer: buffers, indices, strips,
//! quantized positions and GLB containers in; primitives, normals, transforms, instances,
//! static flags and the ignored-feature notes out.

use super::{TRIANGLE, TempDir, data_uri, f32_bytes, invalid_message, load_doc, triangle_doc};
use crate::error::SceneError;
use crate::gltf_import::load_gltf;
use crate::types::Topology;
use glam::{Vec2, Vec3, Vec4};
use serde_json::json;

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
    colored["attributes"]["COLOR_1"] = json!(0);
    doc["meshes"][0]["primitives"] = json!([prim, points.clone(), points, colored, { "attributes": {} }]);
    doc["animations"] = json!([
        { "channels": [], "samplers": [] },
        { "channels": [], "samplers": [] },
        { "channels": [], "samplers": [] }
    ]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.meshes[0].primitives.len(), 2);
    assert_eq!(scene.meshes[0].points_and_lines.len(), 2);
    assert_eq!(
        scene.ignored,
        vec![
            "1 primitive with COLOR_1 or above: only COLOR_0 is read".to_owned(),
            "1 primitive without POSITION: nothing to draw, ignored".to_owned(),
        ]
    );
}

#[test]
fn points_and_lines_of_every_mode_load_as_lists_unlit_without_normals() {
    let dir = TempDir::new("points-lines");
    let mut doc = triangle_doc();
    let prim = doc["meshes"][0]["primitives"][0].clone();
    let with_mode = |mode: u32| {
        let mut p = prim.clone();
        p["mode"] = json!(mode);
        p
    };
    // The triangle's three vertices as LINES (one segment, one vertex left), LINE_LOOP,
    // LINE_STRIP and POINTS; then lines with normals on a material of the file's.
    let mut lit = with_mode(1);
    lit["attributes"]["NORMAL"] = json!(1);
    lit["material"] = json!(0);
    doc["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3" }));
    doc["bufferViews"].as_array_mut().unwrap().push(json!({ "buffer": 1, "byteLength": 36 }));
    doc["buffers"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "byteLength": 36, "uri": data_uri(&f32_bytes(&[0.0, 1.0, 0.0].repeat(3))) }));
    doc["materials"] = json!([{ "name": "ink", "pbrMetallicRoughness": { "baseColorFactor": [0.2, 0.3, 0.4, 1.0] } }]);
    doc["meshes"][0]["primitives"] = json!([prim, with_mode(1), with_mode(2), with_mode(3), with_mode(0), lit]);
    let scene = load_doc(&dir, &doc).unwrap();
    let mesh = &scene.meshes[0];
    assert_eq!(mesh.primitives.len(), 1, "the triangle");
    let parts: Vec<(Topology, Vec<u32>)> =
        mesh.points_and_lines.iter().map(|p| (p.topology, p.primitive.indices.clone())).collect();
    assert_eq!(
        parts,
        vec![
            (Topology::Lines, vec![0, 1]),
            (Topology::Lines, vec![0, 1, 1, 2, 2, 0]),
            (Topology::Lines, vec![0, 1, 1, 2]),
            (Topology::Points, vec![0, 1, 2]),
            (Topology::Lines, vec![0, 1]),
        ]
    );
    // Without normals: the default material's unlit copy, made once for all four.
    let unlit = mesh.points_and_lines[0].primitive.material.unwrap();
    assert!(
        mesh.points_and_lines[..4]
            .iter()
            .all(|p| p.primitive.material == Some(unlit) && p.primitive.normals.is_empty())
    );
    assert_eq!(scene.materials.len(), 2);
    assert!(scene.materials[unlit].unlit && scene.materials[unlit].name.contains("unlit: points or lines"));
    // With normals: lit, on the file's material.
    let lit = &mesh.points_and_lines[4].primitive;
    assert_eq!((lit.material, lit.normals.len()), (Some(0), 3));
    assert!(!scene.materials[0].unlit);
    assert_eq!(scene.triangle_count(), 1, "points and lines are not triangles");
    assert!(
        scene
            .ignored
            .iter()
            .any(|s| s.contains("primitives[1]") && s.contains("1 of its 3 indices make no whole LINES segment")),
        "{:?}",
        scene.ignored
    );
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
    // One time and one translation; only the channels' targets matter here.
    let extra = f32_bytes(&[0.0, 0.0, 0.0, 0.0]);
    doc["buffers"].as_array_mut().unwrap().push(json!({ "byteLength": 16, "uri": data_uri(&extra) }));
    doc["bufferViews"].as_array_mut().unwrap().push(json!({ "buffer": 1, "byteLength": 16 }));
    let accessors = doc["accessors"].as_array_mut().unwrap();
    accessors.push(json!({ "bufferView": 1, "componentType": 5126, "count": 1, "type": "SCALAR" }));
    accessors.push(json!({ "bufferView": 1, "byteOffset": 4, "componentType": 5126, "count": 1, "type": "VEC3" }));
    doc["animations"] = json!([{
        "channels": [
            { "sampler": 0, "target": { "node": 1, "path": "translation" } },
            { "sampler": 0, "target": { "node": 4, "path": "translation" } }
        ],
        "samplers": [{ "input": 1, "output": 2 }]
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
fn vertex_colours_load_from_every_allowed_layout() {
    let dir = TempDir::new("colours");
    // The triangle's three corners: float RGB, normalised unsigned byte RGBA and
    // normalised unsigned short RGBA, each its own accessor after the positions.
    let mut bytes = f32_bytes(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let float_rgb = bytes.len();
    bytes.extend(f32_bytes(&[1.0, 0.5, 0.25, 2.0, -1.0, 0.0, 0.0, 0.0, 1.0]));
    let byte_rgba = bytes.len();
    bytes.extend([255u8, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 0]);
    let short_rgba = bytes.len();
    for v in [65535u16, 0, 0, 65535, 0, 32768, 0, 65535, 0, 0, 0, 0] {
        bytes.extend(v.to_le_bytes());
    }
    let mut doc = triangle_doc();
    doc["accessors"] = json!([
        { "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] },
        { "bufferView": 0, "byteOffset": float_rgb, "componentType": 5126, "count": 3, "type": "VEC3" },
        { "bufferView": 0, "byteOffset": byte_rgba, "componentType": 5121, "normalized": true, "count": 3, "type": "VEC4" },
        { "bufferView": 0, "byteOffset": short_rgba, "componentType": 5123, "normalized": true, "count": 3, "type": "VEC4" },
        { "bufferView": 0, "byteOffset": byte_rgba, "componentType": 5121, "count": 3, "type": "VEC4" }
    ]);
    doc["bufferViews"] = json!([{ "buffer": 0, "byteLength": bytes.len() }]);
    doc["buffers"] = json!([{ "byteLength": bytes.len(), "uri": data_uri(&bytes) }]);
    let colours = |accessor: usize| {
        let mut doc = doc.clone();
        doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = json!(accessor);
        load_doc(&dir, &doc)
    };
    // The triangle has no normals: its corners are unwelded, and keep their colours.
    let float = colours(1).unwrap().meshes[0].primitives[0].colors.clone();
    assert_eq!(
        float,
        vec![Vec4::new(1.0, 0.5, 0.25, 1.0), Vec4::new(1.0, 0.0, 0.0, 1.0), Vec4::new(0.0, 0.0, 1.0, 1.0)]
    );
    let byte = colours(2).unwrap().meshes[0].primitives[0].colors.clone();
    assert_eq!(byte[1], Vec4::new(0.0, 1.0, 0.0, 128.0 / 255.0));
    let short = colours(3).unwrap().meshes[0].primitives[0].colors.clone();
    assert_eq!(short[0], Vec4::new(1.0, 0.0, 0.0, 1.0));
    assert_eq!(short[1].y, 32768.0 / 65535.0);
    // Integers that are not normalised are not colours.
    let message = invalid_message(colours(4));
    assert!(message.contains("COLOR_0") && message.contains("UNSIGNED_BYTE"), "{message}");
    // Without COLOR_0 the primitive stays white.
    assert!(load_doc(&dir, &triangle_doc()).unwrap().meshes[0].primitives[0].colors.is_empty());
}

#[test]
fn a_texture_only_lines_read_is_decoded_and_kept() {
    let dir = TempDir::new("textured-lines");
    let mut doc = triangle_doc();
    doc["meshes"][0]["primitives"][0]["mode"] = json!(3);
    doc["meshes"][0]["primitives"][0]["material"] = json!(0);
    doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(1);
    doc["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2" }));
    doc["bufferViews"].as_array_mut().unwrap().push(json!({ "buffer": 1, "byteLength": 24 }));
    doc["buffers"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "byteLength": 24, "uri": data_uri(&f32_bytes(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0])) }));
    let image = image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 100, 50, 255]));
    doc["images"] = json!([{ "uri": data_uri(&super::png_bytes(image.into())), "mimeType": "image/png" }]);
    doc["textures"] = json!([{ "source": 0 }]);
    doc["materials"] = json!([{ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } } }]);
    let scene = load_doc(&dir, &doc).unwrap();
    let line = &scene.meshes[0].points_and_lines[0].primitive;
    let material = &scene.materials[line.material.unwrap()];
    assert!(material.unlit, "no normals: the unlit copy");
    let texture = material.base_color_texture.expect("the copy keeps the texture");
    assert_eq!((scene.images.len(), scene.images[texture.image].width), (1, 2));
}
