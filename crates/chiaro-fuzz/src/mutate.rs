//! Mutations. Byte-level ones (flips, interesting bytes, insertions, deletions, repeats,
//! splices from another seed) find parser bugs; structure-aware ones keep the input
//! well-formed so that the importer's later checks are reached: on glTF JSON they swap a
//! value for an interesting one, delete or repeat members, add glTF keys, and change the
//! bytes inside a data URI (meshopt streams, WebP images, accessor data) while keeping it
//! a valid URI; on TOML they rewrite values, repeat lines and add keys.

use crate::rng::Rng;
use base64::Engine as _;
use serde_json::{Value, json};

const INTERESTING_BYTES: [u8; 12] = [0, 0xff, 0x7f, 0x80, b'"', b'{', b'[', b'-', b'9', b',', b'.', b'e'];

/// Keys the glTF schema knows, to add where they do not belong (or do, with bad values).
const GLTF_KEYS: [&str; 58] = [
    "byteStride",
    "byteOffset",
    "byteLength",
    "count",
    "componentType",
    "type",
    "matrix",
    "translation",
    "rotation",
    "scale",
    "texCoord",
    "indices",
    "mode",
    "material",
    "mesh",
    "children",
    "camera",
    "sparse",
    "extensions",
    "extensionsRequired",
    "uri",
    "bufferView",
    "min",
    "max",
    "normalized",
    "range",
    "spot",
    "intensity",
    "extras",
    "source",
    "sampler",
    "scene",
    "nodes",
    "alphaMode",
    "alphaCutoff",
    "doubleSided",
    "cookie",
    "image",
    "size",
    "mode",
    "static",
    "animations",
    "channels",
    "target",
    "visible",
    "filter",
    "fallback",
    "buffer",
    "KHR_node_visibility",
    "KHR_materials_unlit",
    "EXT_meshopt_compression",
    "EXT_texture_webp",
    "KHR_mesh_quantization",
    "scenes",
    "perspective",
    "aspectRatio",
    "zfar",
    "pointer",
];

fn interesting_value(rng: &mut Rng) -> Value {
    let values = [
        json!(-1),
        json!(0),
        json!(1),
        json!(2),
        json!(3),
        json!(4),
        json!(255),
        json!(65535),
        json!(4294967295u64),
        json!(18446744073709551615u64),
        json!(1e38),
        json!(-1e38),
        json!(3.5e38),
        json!(0.5),
        json!(1e-40),
        json!(-0.0),
        json!(""),
        json!("x"),
        json!("data:application/octet-stream;base64,AAAA"),
        json!("../../../../etc/passwd"),
        json!(null),
        json!(true),
        json!([]),
        json!({}),
        json!([0, 0, 0]),
        json!([1e38, 1e38, 1e38]),
        json!([0, 0, 0, 0]),
        json!({ "image": 0 }),
        json!({ "image": 0, "size": [1, 0.5] }),
        json!({ "cookie": { "image": 0 } }),
        json!({ "mode": "baked" }),
        json!({ "mode": "mixed", "shadows": "none" }),
        json!({ "static": false }),
        json!("baked"),
        json!([{ "channels": [{ "sampler": 0, "target": { "node": 0, "path": "translation" } }], "samplers": [] }]),
        json!([[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]),
        json!({"KHR_lights_punctual": {"light": 0}, "KHR_texture_transform": {"scale": [1e38, 0]}}),
        json!(["KHR_draco_mesh_compression"]),
        // Any buffer view read as a Draco stream.
        json!({"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0, "NORMAL": 1}}}),
        json!(0.0),
        json!(1.0),
        json!(2.5),
        json!("area"),
        json!("spot"),
        json!("ATTRIBUTES"),
        json!("TRIANGLES"),
        json!("INDICES"),
        json!("OCTAHEDRAL"),
        json!("QUATERNION"),
        json!("EXPONENTIAL"),
        json!({ "KHR_node_visibility": { "visible": false } }),
        json!({ "KHR_materials_unlit": {} }),
        json!({ "EXT_texture_webp": { "source": 0 } }),
        json!({ "EXT_meshopt_compression": { "fallback": true } }),
        json!({ "EXT_meshopt_compression": { "buffer": 0, "byteLength": 64, "byteStride": 4, "count": 16, "mode": "ATTRIBUTES" } }),
        json!({ "EXT_meshopt_compression": { "buffer": 0, "byteLength": 8, "byteStride": 8, "count": 1 << 30, "mode": "ATTRIBUTES", "filter": "QUATERNION" } }),
        json!({ "EXT_meshopt_compression": { "buffer": 0, "byteLength": 16, "byteStride": 2, "count": 3, "mode": "TRIANGLES" } }),
        json!({ "count": 1, "indices": { "bufferView": 0, "componentType": 5121 }, "values": { "bufferView": 0 } }),
        json!({ "count": 4294967295u64, "indices": { "bufferView": 0, "componentType": 5125 }, "values": { "bufferView": 0 } }),
        json!(["KHR_mesh_quantization", "EXT_meshopt_compression", "KHR_materials_unlit", "EXT_texture_webp"]),
        json!("data:image/webp;base64,UklGRg=="),
    ];
    rng.pick(&values).clone()
}

/// Every place in a JSON tree, as a path of object keys and array indices.
#[derive(Clone)]
enum Step {
    Key(String),
    Index(usize),
}

fn places(value: &Value, path: &mut Vec<Step>, out: &mut Vec<Vec<Step>>, budget: &mut usize) {
    if *budget == 0 {
        return;
    }
    *budget -= 1;
    out.push(path.clone());
    match value {
        Value::Object(map) => {
            for (k, v) in map {
                path.push(Step::Key(k.clone()));
                places(v, path, out, budget);
                path.pop();
            }
        }
        // Long arrays (animation data, matrices) are sampled, not walked in full.
        Value::Array(items) => {
            for (i, v) in items.iter().enumerate().take(64) {
                path.push(Step::Index(i));
                places(v, path, out, budget);
                path.pop();
            }
        }
        _ => {}
    }
}

fn at<'v>(value: &'v mut Value, path: &[Step]) -> Option<&'v mut Value> {
    path.iter().try_fold(value, |v, step| match step {
        Step::Key(k) => v.get_mut(k.as_str()),
        Step::Index(i) => v.get_mut(*i),
    })
}

/// One to three structure-aware changes to a glTF document.
pub fn mutate_json(rng: &mut Rng, doc: &Value) -> Vec<u8> {
    let mut doc = doc.clone();
    let mut all = Vec::new();
    places(&doc, &mut Vec::new(), &mut all, &mut 4096);
    // Data URIs are few among a document's places: picked at random they would rarely
    // be reached, so a quarter of the mutants change one's bytes.
    if rng.chance(4) {
        let uris: Vec<&Vec<Step>> =
            all.iter().filter(|path| at(&mut doc, path).and_then(|v| v.as_str()).is_some_and(is_data_uri)).collect();
        if !uris.is_empty() {
            let path = rng.pick(&uris).to_vec();
            if let Some(uri) = at(&mut doc, &path) {
                *uri = Value::from(mutate_payload(rng, uri.as_str().unwrap_or_default()));
            }
        }
    }
    for _ in 0..1 + rng.below(3) {
        let path = rng.pick(&all).clone();
        let Some(target) = at(&mut doc, &path) else { continue };
        match rng.below(7) {
            0 | 1 => *target = interesting_value(rng),
            2 => match target {
                Value::Object(map) if !map.is_empty() => {
                    let key = map.keys().nth(rng.below(map.len())).cloned().expect("non-empty");
                    map.remove(&key);
                }
                Value::Array(items) if !items.is_empty() => {
                    items.remove(rng.below(items.len()));
                }
                _ => *target = Value::Null,
            },
            3 => {
                if let Value::Object(map) = target {
                    map.insert(rng.pick(&GLTF_KEYS).to_string(), interesting_value(rng));
                }
            }
            4 => {
                if let Value::Array(items) = target
                    && !items.is_empty()
                {
                    let copy = items[rng.below(items.len())].clone();
                    items.insert(rng.below(items.len() + 1), copy);
                }
            }
            5 => {
                if let Some(n) = target.as_f64() {
                    let changed = match rng.below(5) {
                        0 => n + 1.0,
                        1 => n - 1.0,
                        2 => -n,
                        3 => n * 1e6,
                        _ => n * 0.5,
                    };
                    *target = serde_json::Number::from_f64(changed).map_or(Value::Null, Value::Number);
                }
            }
            _ => {
                if let Value::String(s) = target {
                    let keep = rng.below(s.len() + 1);
                    let mut cut = keep;
                    while !s.is_char_boundary(cut) {
                        cut -= 1;
                    }
                    s.truncate(cut);
                }
            }
        }
    }
    serde_json::to_vec(&doc).expect("a Value serializes")
}

fn is_data_uri(s: &str) -> bool {
    s.starts_with("data:") && s.contains(";base64,")
}

/// A base64 data URI with its decoded bytes mutated, still a valid URI.
fn mutate_payload(rng: &mut Rng, uri: &str) -> String {
    let base64 = &base64::engine::general_purpose::STANDARD;
    let Some((head, payload)) = uri.split_once(";base64,") else { return uri.to_owned() };
    let bytes = base64.decode(payload).unwrap_or_default();
    let mutated = mutate_bytes(rng, &bytes, &bytes);
    format!("{head};base64,{}", base64.encode(mutated))
}

/// Lines to add to a settings file.
const TOML_LINES: [&str; 17] = [
    "[render]",
    "[shadows.directional]",
    "[[render]]",
    "width = \"64\"",
    "width = 4294967296",
    "filter = 3",
    "cascade_ratios = [0.1, 0.2, 0.3, 0.4]",
    "cascade_blend = \"smooth\"",
    "max_other_lights = 4294967296",
    "x.y.z = 1",
    "ambient = [1e39, -0.0, nan]",
    "exposure_ev100 = inf",
    "range_threshold_lux = 1e-40",
    "cascade_count = 0",
    "msaa = 3",
    "culling = \"tiled\"",
    "culling = 1",
];

/// One to three line-level changes to a settings file.
pub fn mutate_toml(rng: &mut Rng, text: &[u8]) -> Vec<u8> {
    let text = String::from_utf8_lossy(text);
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    for _ in 0..1 + rng.below(3) {
        let at = rng.below(lines.len() + 1);
        match rng.below(4) {
            0 => lines.insert(at, rng.pick(&TOML_LINES).to_string()),
            1 if at < lines.len() => {
                let copy = lines[at].clone();
                lines.insert(at, copy);
            }
            2 if at < lines.len() => {
                if let Some((key, _)) = lines[at].split_once('=') {
                    let values = ["-1", "0", "1e38", "\"\"", "[]", "true", "nan", "-inf", "{}", "[0.5, 0.2]"];
                    lines[at] = format!("{key}= {}", rng.pick(&values));
                }
            }
            _ if at < lines.len() => {
                lines.remove(at);
            }
            _ => {}
        }
    }
    (lines.join("\n") + "\n").into_bytes()
}

/// One to four byte-level changes; `other` lends a chunk for splices.
pub fn mutate_bytes(rng: &mut Rng, input: &[u8], other: &[u8]) -> Vec<u8> {
    let mut bytes = input.to_vec();
    for _ in 0..1 + rng.below(4) {
        let len = bytes.len();
        match rng.below(7) {
            0 if len > 0 => {
                let i = rng.below(len);
                bytes[i] ^= 1 << rng.below(8);
            }
            1 if len > 0 => {
                let i = rng.below(len);
                bytes[i] = *rng.pick(&INTERESTING_BYTES);
            }
            2 => {
                let i = rng.below(len + 1);
                let n = 1 + rng.below(8);
                let insert: Vec<u8> = (0..n).map(|_| *rng.pick(&INTERESTING_BYTES)).collect();
                bytes.splice(i..i, insert);
            }
            3 if len > 0 => {
                let i = rng.below(len);
                let n = 1 + rng.below((len - i).min(64));
                bytes.drain(i..i + n);
            }
            4 if len > 0 => {
                let i = rng.below(len);
                let n = 1 + rng.below((len - i).min(64));
                let copy = bytes[i..i + n].to_vec();
                bytes.splice(i..i, copy);
            }
            5 if !other.is_empty() => {
                let i = rng.below(len + 1);
                let j = rng.below(other.len());
                let n = 1 + rng.below((other.len() - j).min(256));
                bytes.splice(i..(i + n).min(len), other[j..j + n].iter().copied());
            }
            _ if len > 0 => bytes.truncate(rng.below(len)),
            _ => {}
        }
    }
    bytes
}
