//! Seeds written by code, one per glTF rule or extension that the repository's assets do
//! not carry: quantized and meshopt-compressed geometry, WebP textures, sparse accessors,
//! hidden nodes, unlit materials, unknown light types, integers written as floats, and
//! the properties the specification lets a file leave out. Each is a small textured quad
//! under a spot light, so that its mutants reach the code the rule runs. The compressed
//! one comes as a GLB too, so that byte mutations land in the meshopt streams themselves.

use crate::seeds::glb;
use base64::Engine as _;
use serde_json::{Value, json};
use std::f32::consts::FRAC_1_SQRT_2;

/// The quad: positions, normals and texture coordinates of four corners, two triangles.
const POSITIONS: [[f32; 3]; 4] = [[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]];
const NORMAL: [f32; 3] = [0.0, 1.0, 0.0];
const UVS: [[f32; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
const INDICES: [u32; 6] = [0, 2, 1, 0, 3, 2];

const FLOAT: u32 = 5126;
const BYTE: u32 = 5120;
const UNSIGNED_BYTE: u32 = 5121;
const SHORT: u32 = 5122;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;

/// A seed: what it exercises, and its bytes (.gltf JSON, or a GLB).
pub struct SpecSeed {
    pub name: &'static str,
    pub bytes: Vec<u8>,
}

fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes))
}

fn le_bytes<const N: usize, T: Copy>(values: &[T], to_bytes: impl Fn(T) -> [u8; N]) -> Vec<u8> {
    values.iter().flat_map(|&v| to_bytes(v)).collect()
}

fn floats(values: impl IntoIterator<Item = f32>) -> Vec<u8> {
    values.into_iter().flat_map(f32::to_le_bytes).collect()
}

/// A 2x2 RGBA texture in `format` (PNG, or lossless WebP).
fn texture(format: image::ImageFormat) -> Vec<u8> {
    let pixels = [255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128];
    let image = image::RgbaImage::from_raw(2, 2, pixels.to_vec()).expect("2x2 RGBA");
    let mut out = std::io::Cursor::new(Vec::new());
    image.write_to(&mut out, format).expect("a 2x2 image encodes");
    out.into_inner()
}

/// A document as it is written: one buffer whose bytes grow with each view.
struct Writer {
    doc: Value,
    bin: Vec<u8>,
}

impl Writer {
    /// The quad's document with no geometry yet: a textured material, a spot light on a
    /// child node, a camera, and one scene.
    fn new() -> Writer {
        let doc = json!({
            "asset": { "version": "2.0", "generator": "chiaro-fuzz spec seeds" },
            "scene": 0,
            "scenes": [{ "nodes": [0, 2] }],
            "nodes": [
                { "name": "quad", "mesh": 0, "children": [1] },
                { "name": "spot", "translation": [0, 2, 0], "rotation": [-FRAC_1_SQRT_2, 0, 0, FRAC_1_SQRT_2],
                  "extensions": { "KHR_lights_punctual": { "light": 0 } } },
                { "name": "camera", "camera": 0, "translation": [0, 1, 4] }
            ],
            "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1, "zfar": 50, "aspectRatio": 1 } }],
            "extensionsUsed": ["KHR_lights_punctual"],
            "extensions": { "KHR_lights_punctual": { "lights": [
                { "type": "spot", "intensity": 20, "range": 8, "spot": { "innerConeAngle": 0.3, "outerConeAngle": 0.6 } }
            ] } },
            "materials": [{ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 }, "metallicFactor": 0 } }],
            "textures": [{ "source": 0, "sampler": 0 }],
            "samplers": [{ "magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 10497 }],
            "images": [{ "uri": data_uri("image/png", &texture(image::ImageFormat::Png)) }],
            "meshes": [{ "primitives": [{ "attributes": {}, "material": 0 }] }],
            "buffers": [],
            "bufferViews": [],
            "accessors": []
        });
        Writer { doc, bin: Vec::new() }
    }

    fn push(&mut self, array: &str, value: Value) -> usize {
        let items = self.doc[array].as_array_mut().expect("the writer's arrays exist");
        items.push(value);
        items.len() - 1
    }

    /// `bytes` appended to the buffer, 4-byte aligned, as a new buffer view.
    fn view(&mut self, bytes: &[u8], stride: Option<usize>) -> usize {
        let mut view = json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() });
        if let Some(stride) = stride {
            view["byteStride"] = json!(stride);
        }
        self.bin.extend(bytes);
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        self.push("bufferViews", view)
    }

    fn accessor(&mut self, view: Option<usize>, component: u32, normalized: bool, count: usize, kind: &str) -> usize {
        let mut accessor = json!({ "componentType": component, "count": count, "type": kind });
        if normalized {
            accessor["normalized"] = json!(true);
        }
        if let Some(view) = view {
            accessor["bufferView"] = json!(view);
        }
        self.push("accessors", accessor)
    }

    fn attribute(&mut self, name: &str, accessor: usize) {
        self.doc["meshes"][0]["primitives"][0]["attributes"][name] = json!(accessor);
    }

    /// POSITION with the bounds the specification requires.
    fn positions(&mut self, accessor: usize, min: [f32; 3], max: [f32; 3]) {
        self.doc["accessors"][accessor]["min"] = json!(min);
        self.doc["accessors"][accessor]["max"] = json!(max);
        self.attribute("POSITION", accessor);
    }

    fn indices(&mut self, accessor: usize) {
        self.doc["meshes"][0]["primitives"][0]["indices"] = json!(accessor);
    }

    /// The quad in floats, indexed by unsigned shorts.
    fn plain_quad(&mut self) {
        let view = self.view(&floats(POSITIONS.into_iter().flatten()), Some(12));
        let position = self.accessor(Some(view), FLOAT, false, 4, "VEC3");
        self.positions(position, POSITIONS[0], POSITIONS[2]);
        let view = self.view(&floats([NORMAL; 4].into_iter().flatten()), None);
        let normal = self.accessor(Some(view), FLOAT, false, 4, "VEC3");
        self.attribute("NORMAL", normal);
        let view = self.view(&floats(UVS.into_iter().flatten()), None);
        let uv = self.accessor(Some(view), FLOAT, false, 4, "VEC2");
        self.attribute("TEXCOORD_0", uv);
        let view = self.view(&le_bytes(&INDICES.map(|i| i as u16), u16::to_le_bytes), None);
        let indices = self.accessor(Some(view), UNSIGNED_SHORT, false, INDICES.len(), "SCALAR");
        self.indices(indices);
    }

    fn uses(&mut self, extension: &str, required: bool) {
        let lists: &[&str] = if required { &["extensionsUsed", "extensionsRequired"] } else { &["extensionsUsed"] };
        for list in lists {
            let items = self.doc.as_object_mut().expect("a document is an object").entry(*list).or_insert(json!([]));
            items.as_array_mut().expect("extension lists are arrays").push(json!(extension));
        }
    }

    /// The document with its buffer as a data URI.
    fn gltf(mut self) -> Vec<u8> {
        let buffer = json!({ "byteLength": self.bin.len(), "uri": data_uri("application/octet-stream", &self.bin) });
        self.doc["buffers"].as_array_mut().expect("buffers").insert(0, buffer);
        serde_json::to_vec(&self.doc).expect("a Value serializes")
    }

    /// The document as a GLB, its buffer the binary chunk.
    fn glb(mut self) -> Vec<u8> {
        self.doc["buffers"].as_array_mut().expect("buffers").insert(0, json!({ "byteLength": self.bin.len() }));
        glb(&serde_json::to_vec(&self.doc).expect("a Value serializes"), &self.bin)
    }
}

/// KHR_mesh_quantization: SHORT positions scaled by the node, normalized BYTE normals,
/// normalized UNSIGNED_SHORT texture coordinates, UNSIGNED_BYTE indices.
fn quantized() -> Vec<u8> {
    let mut w = Writer::new();
    let positions: Vec<i16> =
        POSITIONS.iter().flat_map(|p| [p[0], p[1], p[2], 0.0]).map(|c| (c * 100.0) as i16).collect();
    let view = w.view(&le_bytes(&positions, i16::to_le_bytes), Some(8));
    let position = w.accessor(Some(view), SHORT, false, 4, "VEC3");
    w.positions(position, [-100.0, 0.0, -100.0], [100.0, 0.0, 100.0]);
    w.doc["nodes"][0]["scale"] = json!([0.01, 0.01, 0.01]);
    let normals: Vec<i8> = [[0i8, 127, 0, 0]; 4].into_iter().flatten().collect();
    let view = w.view(&le_bytes(&normals, i8::to_le_bytes), Some(4));
    let normal = w.accessor(Some(view), BYTE, true, 4, "VEC3");
    w.attribute("NORMAL", normal);
    let uvs: Vec<u16> = UVS.into_iter().flatten().map(|c| (c * 65535.0) as u16).collect();
    let view = w.view(&le_bytes(&uvs, u16::to_le_bytes), None);
    let uv = w.accessor(Some(view), UNSIGNED_SHORT, true, 4, "VEC2");
    w.attribute("TEXCOORD_0", uv);
    let view = w.view(&INDICES.map(|i| i as u8), None);
    let indices = w.accessor(Some(view), UNSIGNED_BYTE, false, 6, "SCALAR");
    w.indices(indices);
    w.uses("KHR_mesh_quantization", true);
    w.gltf()
}

/// EXT_meshopt_compression: every view compressed into buffer 0, behind a fallback buffer
/// with no data; positions through the EXPONENTIAL filter, normals OCTAHEDRAL, texture
/// coordinates unfiltered, indices as TRIANGLES, and a second primitive's as INDICES.
fn meshopt_writer() -> Writer {
    use meshopt::encoding::{EncodeExpMode, encode_filter_exp, encode_filter_oct, encode_index_buffer};
    use meshopt::encoding::{encode_index_sequence, encode_vertex_buffer};
    let mut w = Writer::new();
    // The plain views live in the fallback buffer (1), their compressed bytes in buffer 0.
    let mut plain_length = 0;
    let mut compressed_view =
        |w: &mut Writer, compressed: Vec<u8>, count: usize, stride: usize, mode: &str, filter: &str| {
            let length = count * stride;
            let extension = json!({ "buffer": 0, "byteOffset": w.bin.len(), "byteLength": compressed.len(),
            "byteStride": stride, "count": count, "mode": mode, "filter": filter });
            w.bin.extend(&compressed);
            w.bin.resize(w.bin.len().next_multiple_of(4), 0);
            let mut view = json!({ "buffer": 1, "byteOffset": plain_length, "byteLength": length,
            "extensions": { "EXT_meshopt_compression": extension } });
            if mode == "ATTRIBUTES" {
                view["byteStride"] = json!(stride);
            }
            plain_length += length.next_multiple_of(4);
            w.push("bufferViews", view)
        };
    let exponents = encode_filter_exp(&POSITIONS, 15, EncodeExpMode::Separate);
    let view =
        compressed_view(&mut w, encode_vertex_buffer(&exponents).expect("encodes"), 4, 12, "ATTRIBUTES", "EXPONENTIAL");
    let position = w.accessor(Some(view), FLOAT, false, 4, "VEC3");
    w.positions(position, POSITIONS[0], POSITIONS[2]);
    let octahedral = encode_filter_oct::<i8>(&[[NORMAL[0], NORMAL[1], NORMAL[2], 0.0]; 4], 8);
    let view =
        compressed_view(&mut w, encode_vertex_buffer(&octahedral).expect("encodes"), 4, 4, "ATTRIBUTES", "OCTAHEDRAL");
    let normal = w.accessor(Some(view), BYTE, true, 4, "VEC3");
    w.attribute("NORMAL", normal);
    let view = compressed_view(&mut w, encode_vertex_buffer(&UVS).expect("encodes"), 4, 8, "ATTRIBUTES", "NONE");
    let uv = w.accessor(Some(view), FLOAT, false, 4, "VEC2");
    w.attribute("TEXCOORD_0", uv);
    let view = compressed_view(&mut w, encode_index_buffer(&INDICES, 4).expect("encodes"), 6, 2, "TRIANGLES", "NONE");
    let triangles = w.accessor(Some(view), UNSIGNED_SHORT, false, 6, "SCALAR");
    w.indices(triangles);
    let view = compressed_view(&mut w, encode_index_sequence(&INDICES, 4).expect("encodes"), 6, 4, "INDICES", "NONE");
    let sequence = w.accessor(Some(view), UNSIGNED_INT, false, 6, "SCALAR");
    let mut second = w.doc["meshes"][0]["primitives"][0].clone();
    second["indices"] = json!(sequence);
    w.push(
        "buffers",
        json!({ "byteLength": plain_length, "extensions": { "EXT_meshopt_compression": { "fallback": true } } }),
    );
    w.doc["meshes"][0]["primitives"].as_array_mut().expect("primitives").push(second);
    w.uses("EXT_meshopt_compression", true);
    // Octahedral normals are normalized bytes, which glTF allows only with quantization.
    w.uses("KHR_mesh_quantization", true);
    w
}

/// EXT_texture_webp: the texture's only image is WebP, named by the extension.
fn webp() -> Vec<u8> {
    let mut w = Writer::new();
    w.plain_quad();
    w.doc["images"][0]["uri"] = json!(data_uri("image/webp", &texture(image::ImageFormat::WebP)));
    w.doc["textures"][0] = json!({ "sampler": 0, "extensions": { "EXT_texture_webp": { "source": 0 } } });
    w.uses("EXT_texture_webp", true);
    w.gltf()
}

/// Sparse accessors: positions on a buffer view with one corner substituted (UNSIGNED_BYTE
/// index), texture coordinates on zeros with two (UNSIGNED_INT indices).
fn sparse() -> Vec<u8> {
    let mut w = Writer::new();
    w.plain_quad();
    let position = w.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"].as_u64().expect("POSITION") as usize;
    let index = w.view(&[2], None);
    let value = w.view(&floats([1.0, 0.5, 1.0]), None);
    w.doc["accessors"][position]["sparse"] = json!({ "count": 1,
        "indices": { "bufferView": index, "componentType": UNSIGNED_BYTE }, "values": { "bufferView": value } });
    w.doc["accessors"][position]["max"] = json!([1.0, 0.5, 1.0]);
    let indices = w.view(&le_bytes(&[1u32, 3], u32::to_le_bytes), None);
    let values = w.view(&floats([1.0, 0.0, 0.0, 1.0]), None);
    let uv = w.accessor(None, FLOAT, false, 4, "VEC2");
    w.doc["accessors"][uv]["sparse"] = json!({ "count": 2,
        "indices": { "bufferView": indices, "componentType": UNSIGNED_INT }, "values": { "bufferView": values } });
    w.attribute("TEXCOORD_0", uv);
    w.gltf()
}

/// KHR_node_visibility: the quad's node hidden (and its child light with it), a visible
/// copy beside it.
fn hidden_nodes() -> Vec<u8> {
    let mut w = Writer::new();
    w.plain_quad();
    w.doc["nodes"][0]["extensions"] = json!({ "KHR_node_visibility": { "visible": false } });
    let copy = w.push(
        "nodes",
        json!({ "name": "shown", "mesh": 0, "translation": [3, 0, 0],
        "extensions": { "KHR_node_visibility": { "visible": true } } }),
    );
    w.doc["scenes"][0]["nodes"].as_array_mut().expect("scene nodes").push(json!(copy));
    w.uses("KHR_node_visibility", false);
    w.gltf()
}

/// KHR_materials_unlit on an alpha-masked material.
fn unlit() -> Vec<u8> {
    let mut w = Writer::new();
    w.plain_quad();
    w.doc["materials"][0]["extensions"] = json!({ "KHR_materials_unlit": {} });
    w.doc["materials"][0]["alphaMode"] = json!("MASK");
    w.uses("KHR_materials_unlit", true);
    w.gltf()
}

/// A light type KHR_lights_punctual does not define, on the node that had the spot; the
/// spot moves to the second light.
fn unknown_light_type() -> Vec<u8> {
    let mut w = Writer::new();
    w.plain_quad();
    let lights = w.doc["extensions"]["KHR_lights_punctual"]["lights"].as_array_mut().expect("lights");
    lights.insert(0, json!({ "type": "area", "intensity": 5, "size": [1, 2] }));
    let spot =
        w.push("nodes", json!({ "translation": [1, 2, 0], "extensions": { "KHR_lights_punctual": { "light": 1 } } }));
    w.doc["scenes"][0]["nodes"].as_array_mut().expect("scene nodes").push(json!(spot));
    w.gltf()
}

/// KHR_animation_pointer channels on the spot's colour, intensity and cone, the material's
/// base colour and the quad's translation, and an orthographic second camera.
fn animation_pointer() -> Vec<u8> {
    let mut w = Writer::new();
    w.plain_quad();
    let times = w.view(&floats([0.0, 1.0, 2.0]), None);
    let times = w.accessor(Some(times), 5126, false, 3, "SCALAR");
    w.doc["accessors"][times]["min"] = json!([0.0]);
    w.doc["accessors"][times]["max"] = json!([2.0]);
    let scalars = w.view(&floats([20.0, 5.0, 40.0]), None);
    let scalars = w.accessor(Some(scalars), 5126, false, 3, "SCALAR");
    let colors = w.view(&floats([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]), None);
    let colors = w.accessor(Some(colors), 5126, false, 3, "VEC3");
    let fours = w.view(&floats([1.0, 1.0, 1.0, 1.0, 0.5, 0.2, 0.1, 1.0, 0.0, 0.0, 0.0, 0.5]), None);
    let fours = w.accessor(Some(fours), 5126, false, 3, "VEC4");
    let pointer = |sampler: usize, p: &str| json!({ "sampler": sampler, "target": { "path": "pointer", "extensions": { "KHR_animation_pointer": { "pointer": p } } } });
    w.doc["animations"] = json!([{
        "samplers": [
            { "input": times, "output": colors }, { "input": times, "output": scalars, "interpolation": "STEP" },
            { "input": times, "output": fours }, { "input": times, "output": colors, "interpolation": "LINEAR" }
        ],
        "channels": [
            pointer(0, "/extensions/KHR_lights_punctual/lights/0/color"),
            pointer(1, "/extensions/KHR_lights_punctual/lights/0/intensity"),
            pointer(1, "/extensions/KHR_lights_punctual/lights/0/spot/outerConeAngle"),
            pointer(2, "/materials/0/pbrMetallicRoughness/baseColorFactor"),
            pointer(3, "/nodes/0/translation"),
            pointer(1, "/materials/0/alphaCutoff")
        ]
    }]);
    w.push(
        "cameras",
        json!({ "type": "orthographic", "orthographic": { "xmag": 2, "ymag": 1.5, "znear": 0, "zfar": 20 } }),
    );
    let camera = w.push(
        "nodes",
        json!({ "camera": 1, "translation": [0, 5, 0], "rotation": [-FRAC_1_SQRT_2, 0, 0, FRAC_1_SQRT_2] }),
    );
    w.doc["scenes"][0]["nodes"].as_array_mut().expect("scene nodes").push(json!(camera));
    w.uses("KHR_animation_pointer", true);
    w.gltf()
}

/// Every integer written as a float: JSON has one number type.
fn integers_as_floats() -> Vec<u8> {
    fn as_floats(value: &mut Value) {
        match value {
            Value::Number(n) if n.is_u64() || n.is_i64() => {
                *value = json!(n.as_f64().expect("an integer is a float"));
            }
            Value::Array(items) => items.iter_mut().for_each(as_floats),
            Value::Object(map) => map.values_mut().for_each(as_floats),
            _ => {}
        }
    }
    let mut w = Writer::new();
    w.plain_quad();
    let mut bytes = w.gltf();
    let mut doc: Value = serde_json::from_slice(&bytes).expect("the writer writes JSON");
    as_floats(&mut doc);
    bytes = serde_json::to_vec(&doc).expect("a Value serializes");
    bytes
}

/// What the specification lets a file leave out: a texture coordinate accessor without a
/// buffer view (zeros), a texture without a source, a texture without a sampler, a second
/// primitive without a material, a camera without aspect ratio and zfar, an animation
/// channel whose target has no node, and a second scene without nodes.
fn optional_properties_absent() -> Vec<u8> {
    let mut w = Writer::new();
    w.plain_quad();
    let zeros = w.accessor(None, FLOAT, false, 4, "VEC2");
    w.attribute("TEXCOORD_1", zeros);
    w.push("textures", json!({}));
    w.push("textures", json!({ "source": 0 }));
    w.doc["materials"][0]["emissiveTexture"] = json!({ "index": 1 });
    w.doc["materials"][0]["occlusionTexture"] = json!({ "index": 2, "texCoord": 1 });
    let mut second = w.doc["meshes"][0]["primitives"][0].clone();
    second.as_object_mut().expect("a primitive").remove("material");
    w.doc["meshes"][0]["primitives"].as_array_mut().expect("primitives").push(second);
    w.doc["cameras"][0]["perspective"] = json!({ "yfov": 0.8, "znear": 0.1 });
    let times = w.view(&floats([0.0, 1.0]), None);
    let times = w.accessor(Some(times), FLOAT, false, 2, "SCALAR");
    w.doc["accessors"][times]["min"] = json!([0.0]);
    w.doc["accessors"][times]["max"] = json!([1.0]);
    let values = w.view(&floats([0.0, 1.0]), None);
    let values = w.accessor(Some(values), FLOAT, false, 2, "SCALAR");
    w.doc["animations"] = json!([{
        "samplers": [{ "input": times, "output": values }],
        "channels": [{ "sampler": 0, "target": { "path": "pointer",
            "extensions": { "KHR_animation_pointer": { "pointer": "/materials/0/alphaCutoff" } } } }]
    }]);
    w.push("scenes", json!({}));
    w.gltf()
}

/// A file without a scene: valid, and draws nothing.
fn no_scene() -> Vec<u8> {
    let mut w = Writer::new();
    w.plain_quad();
    let doc = w.doc.as_object_mut().expect("a document is an object");
    doc.remove("scene");
    doc.remove("scenes");
    w.gltf()
}

/// Every spec seed, named for what it exercises.
pub fn spec_seeds() -> Vec<SpecSeed> {
    let seed = |name, bytes| SpecSeed { name, bytes };
    vec![
        seed("quantized", quantized()),
        seed("meshopt", meshopt_writer().gltf()),
        seed("meshopt glb", meshopt_writer().glb()),
        seed("webp", webp()),
        seed("sparse", sparse()),
        seed("hidden nodes", hidden_nodes()),
        seed("unlit", unlit()),
        seed("animation pointer", animation_pointer()),
        seed("unknown light type", unknown_light_type()),
        seed("integers as floats", integers_as_floats()),
        seed("optional properties absent", optional_properties_absent()),
        seed("no scene", no_scene()),
    ]
}
