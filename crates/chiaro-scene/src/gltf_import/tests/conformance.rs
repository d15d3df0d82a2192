//! The glTF 2.0 specification's rules, one small document per rule, written by the test: each
//! loads and gives what the rule says (zeros for an accessor without a buffer view, the
//! sparse values, the default sampler, ...), and the extensions real assets carry read as
//! their specifications say. What is refused is in `invalid_files`.

use super::{TRIANGLE, TempDir, data_uri, f32_bytes, invalid_message, load_doc, png_bytes, textured_doc, triangle_doc};
use crate::types::{SamplerDesc, WrapMode};
use glam::{Vec2, Vec3};
use serde_json::{Value, json};

fn positions(doc: &Value) -> Vec<Vec3> {
    let dir = TempDir::new("conformance");
    let scene = load_doc(&dir, doc).unwrap();
    scene.meshes[0].primitives[0].positions.clone()
}

fn triangle() -> Vec<Vec3> {
    TRIANGLE.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect()
}

#[test]
fn accessor_without_buffer_view_is_zeros() {
    let mut doc = triangle_doc();
    doc["accessors"].as_array_mut().unwrap().push(json!({ "componentType": 5126, "count": 3, "type": "VEC2" }));
    doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(1);
    let dir = TempDir::new("zeros");
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.meshes[0].primitives[0].uv0, vec![Vec2::ZERO; 3]);
}

/// Sparse substitution on zeros (no buffer view) gives exactly the substituted elements.
#[test]
fn sparse_accessor_on_zeros_takes_its_values() {
    let mut doc = triangle_doc();
    let indices: Vec<u8> = [1u16, 2].iter().flat_map(|i| i.to_le_bytes()).collect();
    let values = f32_bytes(&TRIANGLE[3..]);
    let bytes = [indices.as_slice(), &values].concat();
    doc["buffers"][0] = json!({ "byteLength": bytes.len(), "uri": data_uri(&bytes) });
    doc["bufferViews"] = json!([
        { "buffer": 0, "byteLength": 4 },
        { "buffer": 0, "byteOffset": 4, "byteLength": 24 }
    ]);
    doc["accessors"][0] = json!({
        "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0],
        "sparse": { "count": 2,
            "indices": { "bufferView": 0, "componentType": 5123 },
            "values": { "bufferView": 1 } }
    });
    assert_eq!(positions(&doc), triangle());
}

/// Sparse substitution on a buffer view replaces only the listed elements.
#[test]
fn sparse_accessor_on_a_buffer_view_replaces_its_elements() {
    let mut doc = triangle_doc();
    let mut bytes = f32_bytes(&TRIANGLE);
    let replacement = [5.0f32, 6.0, 7.0];
    bytes.extend([2u8, 0, 0, 0]); // index 2, padded to 4 bytes
    bytes.extend(f32_bytes(&replacement));
    doc["buffers"][0] = json!({ "byteLength": bytes.len(), "uri": data_uri(&bytes) });
    doc["bufferViews"] = json!([
        { "buffer": 0, "byteLength": 36 },
        { "buffer": 0, "byteOffset": 36, "byteLength": 1 },
        { "buffer": 0, "byteOffset": 40, "byteLength": 12 }
    ]);
    doc["accessors"][0]["sparse"] = json!({ "count": 1,
        "indices": { "bufferView": 1, "componentType": 5121 }, "values": { "bufferView": 2 } });
    let mut expected = triangle();
    expected[2] = Vec3::from_array(replacement);
    assert_eq!(positions(&doc), expected);
}

#[test]
fn sparse_indices_that_do_not_increase_are_refused() {
    let mut doc = triangle_doc();
    let mut bytes = f32_bytes(&TRIANGLE);
    bytes.extend([2u8, 1, 0, 0]);
    bytes.extend(f32_bytes(&[0.0; 6]));
    doc["buffers"][0] = json!({ "byteLength": bytes.len(), "uri": data_uri(&bytes) });
    doc["bufferViews"] = json!([
        { "buffer": 0, "byteLength": 36 },
        { "buffer": 0, "byteOffset": 36, "byteLength": 2 },
        { "buffer": 0, "byteOffset": 40, "byteLength": 24 }
    ]);
    doc["accessors"][0]["sparse"] = json!({ "count": 2,
        "indices": { "bufferView": 1, "componentType": 5121 }, "values": { "bufferView": 2 } });
    let message = invalid_message(load_doc(&TempDir::new("sparse-order"), &doc));
    assert!(message.starts_with("accessors[0].sparse.indices"), "{message}");
    assert!(message.contains("strictly increase"), "{message}");
}

/// Normalized UNSIGNED_BYTE and UNSIGNED_SHORT texture coordinates map to [0, 1].
#[test]
fn normalized_integer_texcoords_map_to_the_unit_range() {
    for (component, bytes, stride) in [
        (5121, vec![0u8, 255, 0, 0, 51, 0, 0, 0, 0, 102, 0, 0], 4),
        (5123, [0u16, 65535, 13107, 0, 0, 26214].iter().flat_map(|v| v.to_le_bytes()).collect(), 4),
    ] {
        let mut doc = triangle_doc();
        let mut buffer = f32_bytes(&TRIANGLE);
        buffer.extend(&bytes);
        doc["buffers"][0] = json!({ "byteLength": buffer.len(), "uri": data_uri(&buffer) });
        let view = if component == 5121 {
            json!({ "buffer": 0, "byteOffset": 36, "byteLength": 12, "byteStride": stride })
        } else {
            json!({ "buffer": 0, "byteOffset": 36, "byteLength": 12 })
        };
        doc["bufferViews"].as_array_mut().unwrap().push(view);
        doc["accessors"].as_array_mut().unwrap().push(
            json!({ "bufferView": 1, "componentType": component, "normalized": true, "count": 3, "type": "VEC2" }),
        );
        doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(1);
        let scene = load_doc(&TempDir::new("normalized"), &doc).unwrap();
        let uv = &scene.meshes[0].primitives[0].uv0;
        let expected = [Vec2::new(0.0, 1.0), Vec2::new(0.2, 0.0), Vec2::new(0.0, 0.4)];
        for (got, want) in uv.iter().zip(expected) {
            assert!((*got - want).abs().max_element() < 1e-6, "component {component}: {uv:?}");
        }
    }
}

/// JSON has one number type: integer properties written as floats load as integers.
#[test]
fn integers_written_as_floats_load() {
    let mut doc = triangle_doc();
    doc["scene"] = json!(0.0);
    doc["scenes"][0]["nodes"] = json!([0.0]);
    doc["nodes"][0]["mesh"] = json!(0.0);
    doc["accessors"][0]["componentType"] = json!(5126.0);
    doc["accessors"][0]["count"] = json!(3.0);
    doc["accessors"][0]["bufferView"] = json!(0.0);
    doc["bufferViews"][0]["byteLength"] = json!(36.0);
    doc["meshes"][0]["primitives"][0]["mode"] = json!(4.0);
    assert_eq!(positions(&doc), triangle());

    // A fraction is no integer: refused, naming the problem.
    doc["accessors"][0]["count"] = json!(3.5);
    let error = load_doc(&TempDir::new("fraction"), &doc).unwrap_err().to_string();
    assert!(error.contains("floating point"), "{error}");
}

/// Optional properties absent: scene nodes, texture source, sampler, material, camera
/// aspect ratio and zfar, channel target node.
#[test]
fn optional_properties_may_be_absent() {
    let dir = TempDir::new("optional");

    let mut doc = triangle_doc();
    doc["scenes"][0].as_object_mut().unwrap().remove("nodes");
    let scene = load_doc(&dir, &doc).unwrap();
    assert!(scene.instances.is_empty());
    assert!(scene.ignored.iter().any(|i| i == "scenes[0] has no nodes: nothing to draw"), "{:?}", scene.ignored);

    let mut doc = triangle_doc();
    doc.as_object_mut().unwrap().remove("scenes");
    doc.as_object_mut().unwrap().remove("scene");
    let scene = load_doc(&dir, &doc).unwrap();
    assert!(scene.instances.is_empty());
    assert!(scene.ignored.iter().any(|i| i == "the file has no scene: nothing to draw"), "{:?}", scene.ignored);

    // A texture without a source draws untextured, and says so.
    let mut doc = textured_doc(json!({ "uri": "unused.png" }));
    doc["textures"][0].as_object_mut().unwrap().remove("source");
    doc["images"] = json!([]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.materials[0].base_color_texture, None);
    assert!(scene.ignored.iter().any(|i| i.contains("textures[0] has no image")), "{:?}", scene.ignored);

    // No sampler: the spec's default (repeat, linear, mipmaps); no material: the default one.
    let png = png_bytes(image::DynamicImage::new_rgba8(2, 2));
    let scene = load_doc(&dir, &textured_doc(json!({ "uri": data_uri(&png), "mimeType": "image/png" }))).unwrap();
    let sampler = scene.materials[0].base_color_texture.unwrap().sampler;
    assert_eq!(sampler, SamplerDesc::default());
    assert_eq!((sampler.wrap_u, sampler.mag_linear, sampler.mipmaps), (WrapMode::Repeat, true, true));
    assert_eq!(scene.materials[0].alpha_cutoff, 0.5);
    let scene = load_doc(&dir, &triangle_doc()).unwrap();
    assert_eq!(scene.meshes[0].primitives[0].material, None);

    // A perspective camera without aspect ratio and zfar.
    let mut doc = triangle_doc();
    doc["cameras"] = json!([{ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1 } }]);
    doc["nodes"].as_array_mut().unwrap().push(json!({ "camera": 0 }));
    doc["scenes"][0]["nodes"] = json!([0, 1]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!((scene.cameras[0].aspect_ratio, scene.cameras[0].zfar), (None, None));

    // An animation channel whose target has no node (an extension's target).
    let mut doc = triangle_doc();
    let times = f32_bytes(&[0.0, 1.0]);
    doc["buffers"].as_array_mut().unwrap().push(json!({ "byteLength": 8, "uri": data_uri(&times) }));
    doc["bufferViews"].as_array_mut().unwrap().push(json!({ "buffer": 1, "byteLength": 8 }));
    doc["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "bufferView": 1, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1] }));
    doc["animations"] = json!([{
        "samplers": [{ "input": 1, "output": 1 }],
        "channels": [{ "sampler": 0, "target": { "path": "pointer" } }]
    }]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.instances.len(), 1);
    assert!(scene.instances[0].is_static, "a channel with no node moves nothing");
    assert!(
        scene.ignored.iter().any(|i| i.starts_with("animations[0]: 1 channel targets no node")),
        "{:?}",
        scene.ignored
    );
}

/// A KHR_lights_punctual light of a type the extension does not define is skipped with a
/// note; the others load.
#[test]
fn unknown_light_types_are_skipped() {
    let mut doc = triangle_doc();
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [
        { "type": "area", "intensity": 5 }, { "type": "point", "intensity": 2, "name": "kept" }
    ] } });
    doc["nodes"].as_array_mut().unwrap().extend([
        json!({ "extensions": { "KHR_lights_punctual": { "light": 0 } } }),
        json!({ "extensions": { "KHR_lights_punctual": { "light": 1 } } }),
    ]);
    doc["scenes"][0]["nodes"] = json!([0, 1, 2]);
    let scene = load_doc(&TempDir::new("lights"), &doc).unwrap();
    assert_eq!(scene.lights.len(), 1);
    assert_eq!(scene.lights[0].name, "kept");
    assert!(scene.ignored.iter().any(|i| i.contains("\"area\"") && i.contains("skipped")), "{:?}", scene.ignored);
}

/// What nothing in the scene uses is not read: a missing buffer, an undecodable image and an
/// accessor past its buffer, all unused, load with notes at most.
#[test]
fn unused_broken_objects_are_not_read() {
    let mut doc = textured_doc(json!({ "uri": "no-such-image.png" }));
    // The textured material is on a mesh no node places.
    let textured_mesh = doc["meshes"][0].clone();
    doc["meshes"].as_array_mut().unwrap().push(textured_mesh);
    doc["meshes"][0]["primitives"][0].as_object_mut().unwrap().remove("material");
    doc["meshes"][0]["primitives"][0]["attributes"].as_object_mut().unwrap().remove("TEXCOORD_0");
    doc["buffers"].as_array_mut().unwrap().push(json!({ "byteLength": 1000, "uri": "no-such-buffer.bin" }));
    doc["bufferViews"].as_array_mut().unwrap().push(json!({ "buffer": 1, "byteLength": 1000 }));
    doc["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "bufferView": 0, "componentType": 5126, "count": 90, "type": "VEC3" }));
    doc["meshes"].as_array_mut().unwrap().push(json!({ "primitives": [{ "attributes": { "POSITION": 2 } }] }));
    let dir = TempDir::new("unused");
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.triangle_count(), 1);
    assert!(scene.images.is_empty());
    assert!(scene.meshes[1].primitives.is_empty() && scene.meshes[2].primitives.is_empty());
    assert!(scene.ignored.iter().any(|i| i.starts_with("2 meshes: no visible node")), "{:?}", scene.ignored);
    assert!(!scene.inputs.iter().any(|p| p.ends_with("no-such-buffer.bin")));

    // Placed, the same mesh is read, and its broken image refuses the file by name.
    doc["scenes"][0]["nodes"] = json!([0, 1]);
    doc["nodes"].as_array_mut().unwrap().push(json!({ "mesh": 1 }));
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("no-such-image.png"), "{message}");
}

/// KHR_node_visibility: a hidden node hides its meshes and lights and its descendants';
/// cameras stay.
#[test]
fn hidden_nodes_neither_draw_nor_light() {
    let mut doc = triangle_doc();
    doc["extensionsUsed"] = json!(["KHR_node_visibility", "KHR_lights_punctual"]);
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [{ "type": "point" }] } });
    doc["cameras"] = json!([{ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1 } }]);
    doc["nodes"] = json!([
        { "mesh": 0, "children": [1], "extensions": { "KHR_node_visibility": { "visible": false } } },
        { "mesh": 0, "camera": 0, "extensions": {
            "KHR_node_visibility": { "visible": true }, "KHR_lights_punctual": { "light": 0 } } },
        { "mesh": 0, "name": "shown" }
    ]);
    doc["scenes"][0]["nodes"] = json!([0, 2]);
    let scene = load_doc(&TempDir::new("visibility"), &doc).unwrap();
    let names: Vec<&str> = scene.instances.iter().map(|i| i.name.as_str()).collect();
    assert_eq!(names, ["shown"]);
    assert!(scene.lights.is_empty());
    assert_eq!(scene.cameras.len(), 1);
    assert!(!scene.ignored.iter().any(|i| i.contains("KHR_node_visibility")), "{:?}", scene.ignored);
}

/// EXT_texture_webp: the WebP image is read, not the PNG fallback in `source`.
#[test]
fn webp_textures_are_read() {
    let webp = {
        let image = image::RgbaImage::from_pixel(4, 4, image::Rgba([10, 200, 30, 255]));
        let mut bytes = std::io::Cursor::new(Vec::new());
        image::DynamicImage::ImageRgba8(image).write_to(&mut bytes, image::ImageFormat::WebP).unwrap();
        bytes.into_inner()
    };
    let png = png_bytes(image::DynamicImage::new_rgba8(4, 4));
    let mut doc = textured_doc(json!({ "uri": data_uri(&png), "mimeType": "image/png" }));
    doc["images"].as_array_mut().unwrap().push(json!({ "uri": data_uri(&webp), "mimeType": "image/webp" }));
    doc["textures"][0]["extensions"] = json!({ "EXT_texture_webp": { "source": 1 } });
    doc["extensionsUsed"] = json!(["EXT_texture_webp"]);
    doc["extensionsRequired"] = json!(["EXT_texture_webp"]);
    let scene = load_doc(&TempDir::new("webp"), &doc).unwrap();
    assert_eq!(scene.images.len(), 1);
    assert_eq!(&scene.images[0].rgba8[..4], &[10, 200, 30, 255]);

    // Required with no `source` at all, as the extension allows.
    doc["textures"][0].as_object_mut().unwrap().remove("source");
    let scene = load_doc(&TempDir::new("webp-only"), &doc).unwrap();
    assert_eq!(&scene.images[0].rgba8[..4], &[10, 200, 30, 255]);
}

/// EXT_meshopt_compression: compressed vertices and indices decode to the plain ones, and the
/// fallback buffer, which has no data, is never read.
#[test]
fn meshopt_compressed_views_decode() {
    let vertices: Vec<[f32; 3]> = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
    let indices: Vec<u32> = vec![0, 1, 2, 2, 1, 3];
    let compressed_vertices = meshopt::encoding::encode_vertex_buffer(&vertices).unwrap();
    let compressed_indices = meshopt::encoding::encode_index_buffer(&indices, 4).unwrap();
    let mut bytes = compressed_vertices.clone();
    while !bytes.len().is_multiple_of(4) {
        bytes.push(0);
    }
    let index_offset = bytes.len();
    bytes.extend(&compressed_indices);
    let doc = json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["EXT_meshopt_compression"],
        "extensionsRequired": ["EXT_meshopt_compression"],
        "scene": 0, "scenes": [{ "nodes": [0] }], "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] },
            { "bufferView": 1, "componentType": 5125, "count": 6, "type": "SCALAR" }
        ],
        "bufferViews": [
            { "buffer": 0, "byteLength": 48, "byteStride": 12, "extensions": { "EXT_meshopt_compression": {
                "buffer": 1, "byteLength": compressed_vertices.len(), "byteStride": 12, "count": 4, "mode": "ATTRIBUTES" } } },
            { "buffer": 0, "byteLength": 24, "extensions": { "EXT_meshopt_compression": {
                "buffer": 1, "byteOffset": index_offset, "byteLength": compressed_indices.len(), "byteStride": 4,
                "count": 6, "mode": "TRIANGLES" } } }
        ],
        "buffers": [
            { "byteLength": 72, "extensions": { "EXT_meshopt_compression": { "fallback": true } } },
            { "byteLength": bytes.len(), "uri": data_uri(&bytes) }
        ]
    });
    let scene = load_doc(&TempDir::new("meshopt"), &doc).unwrap();
    assert_eq!(scene.triangle_count(), 2);
    let primitive = &scene.meshes[0].primitives[0];
    // Without normals the vertices are unwelded in index order; corners may be rotated.
    let corner = |i: u32| Vec3::from_array(vertices[i as usize]);
    let mut got: Vec<Vec<[i32; 3]>> = primitive
        .positions
        .chunks_exact(3)
        .map(|t| t.iter().map(|p| p.to_array().map(|c| c as i32)).collect())
        .collect();
    let mut want: Vec<Vec<[i32; 3]>> =
        indices.chunks_exact(3).map(|t| t.iter().map(|&i| corner(i).to_array().map(|c| c as i32)).collect()).collect();
    for triangle in got.iter_mut().chain(want.iter_mut()) {
        let first = (0..3).min_by_key(|&k| triangle[k]).unwrap();
        triangle.rotate_left(first);
    }
    got.sort();
    want.sort();
    assert_eq!(got, want);

    // A stream that does not decode is refused with the view's JSON path.
    let mut broken = doc.clone();
    broken["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"] = json!(4);
    let message = invalid_message(load_doc(&TempDir::new("meshopt-broken"), &broken));
    assert!(message.starts_with("bufferViews[0].extensions.EXT_meshopt_compression"), "{message}");
}
