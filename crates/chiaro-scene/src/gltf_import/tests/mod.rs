//! End-to-end tests of the importer: glTF documents written to a scratch folder flow in
//! through [`load_gltf`], and the resulting `Scene` (or the `SceneError` and its message)
//! is checked. This module holds what the topics share: the scratch folder, a one-triangle
//! document to edit, and readers of the result; each submodule tests one topic.

mod animation;
mod conformance;
mod encoded_assets;
mod geometry;
mod image_based_light;
mod instancing;
mod invalid_files;
mod layers;
mod lights_area;
mod lights_cameras;
mod materials;
mod test_assets;
mod validator_rules;
mod variants;

use super::load_gltf;
use crate::error::SceneError;
use crate::types::Scene;
use base64::Engine as _;
use serde_json::{Value, json};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A seeded xorshift generator, for the tests that mutate encoded files: the same seed
/// gives the same mutants.
pub(crate) fn xorshift(seed: u64) -> impl FnMut() -> u64 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    }
}

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
