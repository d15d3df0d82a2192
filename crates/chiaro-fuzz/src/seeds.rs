//! The corpus the mutators start from: every scene of the repository's `tests/assets`, made
//! self-contained (buffers inlined as data URIs, images swapped for a 1x1 PNG so that
//! each input loads in milliseconds, but KTX2 images inlined whole), one of them packed as a GLB, the GLBs there (the
//! Draco- and meshopt-compressed files) with their binary chunk inlined, so that payload
//! mutations reach the compressed streams, the seeds written by code for the rules and
//! extensions the assets lack (`spec_seeds`), and a few settings files that cover every
//! section.

use base64::Engine as _;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// A 1x1 PNG, standing in for the assets' textures.
const TINY_PNG: &str = "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk+M9QDwADhgGAWjR9awAAAABJRU5ErkJggg==";

/// The repository's test scenes (`tests/assets`, with their licenses and provenance).
pub fn test_assets() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets"))
}

/// The files under `dir` whose extension is `extension`.
fn files_named(dir: &Path, extension: &str, found: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            files_named(&path, extension, found)?;
        } else if path.extension().is_some_and(|e| e == extension) {
            found.push(path);
        }
    }
    Ok(())
}

/// A GLB as a .gltf document whose one buffer, the BIN chunk, is a data URI.
fn unpacked_glb(path: &Path) -> anyhow::Result<Vec<u8>> {
    let bytes = std::fs::read(path)?;
    let (json, bin) =
        chiaro_scene::gltf_import::glb::split_glb(&bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let mut doc: Value = serde_json::from_slice(json)?;
    if let (Some(bin), Some(buffer)) = (bin, doc.pointer_mut("/buffers/0").and_then(Value::as_object_mut)) {
        let payload = base64::engine::general_purpose::STANDARD.encode(bin);
        buffer.insert("uri".into(), Value::from(format!("data:application/octet-stream;base64,{payload}")));
    }
    Ok(serde_json::to_vec(&doc)?)
}

/// One asset as a self-contained document: its JSON and the bytes of its buffers.
fn inline(path: &Path) -> anyhow::Result<(Value, Vec<Vec<u8>>)> {
    let mut doc: Value = serde_json::from_slice(&std::fs::read(path)?)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut buffers = Vec::new();
    for buffer in doc.get_mut("buffers").and_then(Value::as_array_mut).into_iter().flatten() {
        let uri = buffer.get("uri").and_then(Value::as_str).unwrap_or_default().to_owned();
        let bytes = match uri.split_once(";base64,") {
            Some((head, payload)) if head.starts_with("data:") => {
                base64::engine::general_purpose::STANDARD.decode(payload)?
            }
            _ if uri.is_empty() => Vec::new(),
            _ => std::fs::read(dir.join(&uri))?,
        };
        buffer["uri"] = Value::from(format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&bytes)
        ));
        buffers.push(bytes);
    }
    for image in doc.get_mut("images").and_then(Value::as_array_mut).into_iter().flatten() {
        if let Some(object) = image.as_object_mut() {
            // KTX2 images are small and are what the KHR_texture_basisu seeds are for:
            // inlined whole, so that payload mutations reach the transcoder.
            let ktx2 = object.get("mimeType").and_then(Value::as_str) == Some("image/ktx2");
            let uri = object.get("uri").and_then(Value::as_str).map(str::to_owned);
            object.remove("bufferView");
            object.remove("mimeType");
            let inlined = match uri {
                Some(uri) if ktx2 => format!(
                    "data:image/ktx2;base64,{}",
                    base64::engine::general_purpose::STANDARD.encode(std::fs::read(dir.join(&uri))?)
                ),
                _ => TINY_PNG.to_owned(),
            };
            object.insert("uri".into(), Value::from(inlined));
        }
    }
    Ok((doc, buffers))
}

/// A GLB container of `json` with `bin` as its binary chunk (glTF 2.0 §4.4).
pub fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |n: usize| (4 - n % 4) % 4;
    let json_len = json.len() + pad(json.len());
    let bin_len = bin.len() + pad(bin.len());
    let total = 12 + 8 + json_len + 8 + bin_len;
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json_len as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(json);
    out.extend(std::iter::repeat_n(b' ', pad(json.len())));
    out.extend((bin_len as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out.extend(std::iter::repeat_n(0, pad(bin.len())));
    out
}

/// The glTF seeds: each test scene inlined, the smallest also as a GLB, then the spec seeds.
pub fn gltf_seeds() -> anyhow::Result<Vec<Vec<u8>>> {
    let mut files = Vec::new();
    files_named(&test_assets(), "gltf", &mut files)?;
    files.sort();
    anyhow::ensure!(!files.is_empty(), "no glTF files under {}", test_assets().display());
    let mut seeds = Vec::new();
    let mut smallest: Option<(Value, Vec<u8>)> = None;
    for path in &files {
        let (doc, buffers) = inline(path)?;
        if buffers.len() == 1 && smallest.as_ref().is_none_or(|(_, b)| buffers[0].len() < b.len()) {
            smallest = Some((doc.clone(), buffers[0].clone()));
        }
        seeds.push(serde_json::to_vec(&doc)?);
    }
    if let Some((mut doc, bin)) = smallest {
        doc["buffers"][0].as_object_mut().map(|b| b.remove("uri"));
        seeds.push(glb(&serde_json::to_vec(&doc)?, &bin));
    }
    let mut containers = Vec::new();
    files_named(&test_assets(), "glb", &mut containers)?;
    containers.sort();
    for path in &containers {
        seeds.push(unpacked_glb(path)?);
    }
    seeds.extend(crate::spec_seeds::spec_seeds().into_iter().map(|seed| seed.bytes));
    Ok(seeds)
}

/// Settings files touching every section and value kind.
pub fn settings_seeds() -> Vec<Vec<u8>> {
    [
        "",
        "[render]\nwidth = 640\nheight = 360\nexposure_ev100 = 1.5\nambient = [0.1, 0.1, 0.1]\nbackground = [0, 0, 0]\n",
        "[lights]\nmax_other_lights = 16\nrange_threshold_lux = 0.05\n[camera]\nauto_yfov_deg = 60\n",
        "[render]\npath = \"forward\"\nlight_buffer = \"ldr-exp2\"\n[lights]\nmax_other_lights = 64\n",
        "[render]\nmsaa = 4\n[lights]\nculling = \"per-object\"\nmax_other_lights = 4096\n[shadows.other]\nmax_tiles = 40\n",
        "[bake]\nsamples = 16\nbounces = 2\ntexels_per_metre = 4.5\nseed = 7\nprobe_spacing = 1.5\nprobe_samples = 32\n[lighting]\nmixed_mode = \"shadowmask\"\n",
        "[shadows]\nmax_distance = 50\ndistance_fade = 0.2\n[shadows.directional]\natlas_size = 1024\nfilter = \"tent5x5\"\ncascade_count = 3\ncascade_ratios = [0.2, 0.5]\ncascade_fade = 0.1\ncascade_blend = \"soft\"\n[shadows.other]\natlas_size = 512\nfilter = \"tent3x3\"\n",
    ]
    .iter()
    .map(|s| s.as_bytes().to_vec())
    .collect()
}
