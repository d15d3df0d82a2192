//! File bytes in (a `.gltf` JSON text or a `.glb` container), a checked [`Document`] out:
//! the JSON parsed both as a raw `serde_json::Value` and as the `gltf` crate's typed
//! `Root`, with the BIN chunk of a GLB alongside. Required extensions, the index and enum
//! validation and the spec's other rules (`spec`) are checked here, so the loader can
//! index the typed model freely. Both views read the document as `normalize` rewrites it,
//! where the typed model is stricter than the specification.

use super::glb::split_glb;
use super::normalize::normalize;
use super::spec::check_spec;
use super::validate::{check_required_extensions, validate};
use crate::error::SceneError;
use gltf::json;
use serde::Deserialize as _;
use serde_json::Value;
use std::path::Path;

/// The parsed JSON twice over: `raw` for extension data the typed model drops (texture
/// transforms on normal and occlusion textures) and for naming values in messages.
pub(super) struct Document<'a> {
    pub(super) raw: Value,
    pub(super) root: json::Root,
    pub(super) bin: Option<&'a [u8]>,
    /// Per KHR_lights_punctual light, whether its type is unknown and the light skipped.
    pub(super) skipped_lights: Vec<bool>,
    /// KHR_animation_pointer channels, set aside from the typed model.
    pub(super) pointer_channels: Vec<super::normalize::PointerChannel>,
    /// What the rewrites set aside, for `Scene::ignored`.
    pub(super) notes: Vec<String>,
}

impl<'a> Document<'a> {
    pub(super) fn parse(path: &Path, bytes: &'a [u8]) -> Result<Document<'a>, SceneError> {
        let parse_error = |message: String| SceneError::Parse { path: path.to_path_buf(), message };
        let (json_bytes, bin) =
            if bytes.starts_with(b"glTF") { split_glb(bytes).map_err(parse_error)? } else { (bytes, None) };
        let json_bytes = json_bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(json_bytes);
        let raw: Value = serde_json::from_slice(json_bytes).map_err(|e| parse_error(e.to_string()))?;
        if !raw.is_object() {
            return Err(parse_error("the document is not a JSON object".into()));
        }
        check_required_extensions(path, &raw)?;
        let normalized = normalize(raw);
        let raw = normalized.json;
        let root: json::Root = json::Root::deserialize(&raw).map_err(|e| parse_error(e.to_string()))?;
        if !root.asset.version.starts_with("2.") {
            return Err(parse_error(format!("asset version is {}; Chiaro reads glTF 2.x", root.asset.version)));
        }
        validate(path, &raw, &root)?;
        check_spec(&raw, &root).map_err(|message| SceneError::Invalid { path: path.to_path_buf(), message })?;
        Ok(Document {
            raw,
            root,
            bin,
            skipped_lights: normalized.skipped_lights,
            notes: normalized.notes,
            pointer_channels: normalized.pointer_channels,
        })
    }
}
