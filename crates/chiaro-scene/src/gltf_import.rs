//! glTF 2.0 import. A `.gltf` (with external or `data:` buffers and images) or a `.glb`
//! flows in; a [`Scene`] flows out: every glTF mesh converted once (so `Scene::meshes` and
//! `Scene::materials` keep the file's indices), complete vertex attributes, one instance per
//! mesh node with its world transform, materials with their images decoded to RGBA8, and
//! KHR_lights_punctual lights and perspective cameras placed in world space. What the file
//! has and Chiaro does not use is listed in `Scene::ignored`; a malformed file is a
//! [`SceneError`] naming the file and the problem, never a panic.
//!
//! Only the `gltf` crate's JSON data model is used. Its wrapper API unwraps on files that
//! pass its validation (an image with a `bufferView` but no `mimeType`, a perspective camera
//! without a `perspective` object), its validation indexes the POSITION accessor unchecked,
//! and its GLB reader underflows on short headers; so this module parses GLB containers,
//! resolves URIs and reads accessors itself, checking every offset before it reads.

use crate::error::SceneError;
use crate::types::{
    AlphaMode, Camera, ColorSpace, Image, Light, LightKind, Material, Mesh, MeshInstance,
    Primitive, SamplerDesc, Scene, TextureRef, UvTransform, WrapMode,
};
use crate::vertex_gen;
use chiaro_math::Aabb;
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use gltf::json;
use json::accessor::ComponentType;
use json::validation::{Checked, Validate};
use serde_json::Value;
use std::borrow::Cow;
use std::path::{Path, PathBuf};

/// Extensions Chiaro reads. A file may require these and no others; KHR_mesh_quantization
/// needs nothing beyond the integer attribute formats the accessor reader handles anyway.
pub const SUPPORTED_EXTENSIONS: [&str; 4] = [
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_texture_transform",
    "KHR_mesh_quantization",
];

/// Accessors with more elements than this are rejected before anything is allocated:
/// 67 million vertices in one primitive is far past what a real-time scene draws.
const MAX_ACCESSOR_COUNT: usize = 1 << 26;

/// Loads a `.gltf` or `.glb` file and everything it references.
pub fn load_gltf(path: &Path) -> Result<Scene, SceneError> {
    let bytes = std::fs::read(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let document = Document::parse(path, &bytes)?;
    let base_dir = path.parent().unwrap_or(Path::new("."));
    let mut loader = Loader {
        path,
        base_dir,
        raw: &document.raw,
        root: &document.root,
        buffers: Vec::new(),
        ignored: Vec::new(),
        tally: Tally::default(),
    };
    let mut scene = loader.load(document.bin)?;
    scene.source = Some(path.to_path_buf());
    tracing::debug!(
        path = %path.display(),
        meshes = scene.meshes.len(),
        instances = scene.instances.len(),
        triangles = scene.triangle_count(),
        images = scene.images.len(),
        lights = scene.lights.len(),
        cameras = scene.cameras.len(),
        "loaded glTF"
    );
    Ok(scene)
}

/// The parsed JSON twice over: `raw` for extension data the typed model drops (texture
/// transforms on normal and occlusion textures) and for naming values in messages.
struct Document<'a> {
    raw: Value,
    root: json::Root,
    bin: Option<&'a [u8]>,
}

impl<'a> Document<'a> {
    fn parse(path: &Path, bytes: &'a [u8]) -> Result<Document<'a>, SceneError> {
        let parse_error = |message: String| SceneError::Parse {
            path: path.to_path_buf(),
            message,
        };
        let (json_bytes, bin) = if bytes.starts_with(b"glTF") {
            split_glb(bytes).map_err(parse_error)?
        } else {
            (bytes, None)
        };
        let json_bytes = json_bytes
            .strip_prefix(b"\xEF\xBB\xBF")
            .unwrap_or(json_bytes);
        let raw: Value =
            serde_json::from_slice(json_bytes).map_err(|e| parse_error(e.to_string()))?;
        if !raw.is_object() {
            return Err(parse_error("the document is not a JSON object".into()));
        }
        check_required_extensions(path, &raw)?;
        let root: json::Root =
            serde_json::from_slice(json_bytes).map_err(|e| parse_error(e.to_string()))?;
        if !root.asset.version.starts_with("2.") {
            return Err(parse_error(format!(
                "asset version is {}; Chiaro reads glTF 2.x",
                root.asset.version
            )));
        }
        validate(path, &raw, &root)?;
        Ok(Document { raw, root, bin })
    }
}

/// Splits a GLB container into its JSON chunk and its optional BIN chunk (glTF 2.0 §4.4).
/// Unknown chunk types are skipped, as the specification asks.
fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let u32_at = |offset: usize| -> Option<u32> {
        let b = bytes.get(offset..offset.checked_add(4)?)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let (Some(version), Some(length)) = (u32_at(4), u32_at(8)) else {
        return Err("GLB header is truncated".into());
    };
    if version != 2 {
        return Err(format!(
            "GLB container version {version}; Chiaro reads version 2"
        ));
    }
    let length = length as usize;
    if length > bytes.len() {
        return Err(format!(
            "GLB header says {length} bytes but the file has {}",
            bytes.len()
        ));
    }
    let mut offset = 12;
    let mut json_chunk = None;
    let mut bin_chunk = None;
    while offset + 8 <= length {
        let chunk_length = u32_at(offset).unwrap_or(0) as usize;
        let chunk_type = &bytes[offset + 4..offset + 8];
        let start = offset + 8;
        let end = start
            .checked_add(chunk_length)
            .filter(|&end| end <= length)
            .ok_or_else(|| format!("GLB chunk at byte {offset} runs past the end of the file"))?;
        match chunk_type {
            b"JSON" if json_chunk.is_none() && offset == 12 => {
                json_chunk = Some(&bytes[start..end]);
            }
            b"BIN\0" if bin_chunk.is_none() && json_chunk.is_some() => {
                bin_chunk = Some(&bytes[start..end]);
            }
            _ if offset == 12 => return Err("GLB file does not start with a JSON chunk".into()),
            _ => {}
        }
        offset = end;
    }
    let json_chunk = json_chunk.ok_or("GLB file has no JSON chunk")?;
    Ok((json_chunk, bin_chunk))
}

/// `extensionsRequired` naming anything Chiaro cannot read is an error of its own kind,
/// checked on the raw JSON so that it wins over any other complaint about the file.
fn check_required_extensions(path: &Path, raw: &Value) -> Result<(), SceneError> {
    let Some(required) = raw.get("extensionsRequired") else {
        return Ok(());
    };
    let not_strings = || SceneError::Parse {
        path: path.to_path_buf(),
        message: "extensionsRequired is not an array of strings".into(),
    };
    for name in required.as_array().ok_or_else(not_strings)? {
        let name = name.as_str().ok_or_else(not_strings)?;
        if !SUPPORTED_EXTENSIONS.contains(&name) {
            return Err(SceneError::UnsupportedExtension {
                path: path.to_path_buf(),
                extension: name.to_owned(),
            });
        }
    }
    Ok(())
}

/// Runs the `gltf` crate's index and enum validation, after checking the one thing its
/// validation would otherwise panic on, and tolerating what Chiaro handles itself: required
/// extensions already vetted, primitives without POSITION (skipped), and POSITION accessors
/// without `min`/`max` (bounds are computed from the data).
fn validate(path: &Path, raw: &Value, root: &json::Root) -> Result<(), SceneError> {
    let invalid = |message: String| SceneError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for (semantic, accessor) in &primitive.attributes {
                if accessor.value() >= root.accessors.len() {
                    return Err(invalid(format!(
                        "meshes[{m}].primitives[{p}].attributes[\"{}\"]: accessor {} is out \
                         of range (the file has {})",
                        semantic_name(semantic),
                        accessor.value(),
                        root.accessors.len()
                    )));
                }
            }
        }
    }

    let mut problems: Vec<(json::Path, json::validation::Error)> = Vec::new();
    root.validate(root, json::Path::new, &mut |path, error| {
        let path = path();
        let p = path.as_str();
        let tolerated = p.starts_with("extensionsRequired")
            || (p.ends_with("attributes[\"POSITION\"]")
                && error == json::validation::Error::Missing)
            || p.ends_with("attributes[\"POSITION\"].min")
            || p.ends_with("attributes[\"POSITION\"].max");
        if !tolerated {
            problems.push((path, error));
        }
    });
    if problems.is_empty() {
        return Ok(());
    }
    let mut message = problems
        .iter()
        .take(3)
        .map(|(path, error)| describe_problem(raw, path.as_str(), *error))
        .collect::<Vec<_>>()
        .join("; ");
    if problems.len() > 3 {
        message += &format!("; and {} more", problems.len() - 3);
    }
    Err(invalid(message))
}

fn semantic_name(semantic: &Checked<json::mesh::Semantic>) -> String {
    match semantic {
        Checked::Valid(s) => s.to_string(),
        Checked::Invalid => "?".into(),
    }
}

/// One validation problem in words: `meshes[0].primitives[0].indices: accessor 7 is out of
/// range`. Validation paths use camelCased Rust field names, so the light extension's key
/// is mapped back before looking the value up.
fn describe_problem(raw: &Value, path: &str, error: json::validation::Error) -> String {
    use json::validation::Error as E;
    let path = path.replace("khrLightsPunctual", "KHR_lights_punctual");
    match error {
        E::IndexOutOfBounds => {
            let kind = index_kind(&path);
            match json_at(raw, &path).and_then(Value::as_u64) {
                Some(index) => format!("{path}: {kind} {index} is out of range"),
                None => format!("{path}: {kind} index is out of range"),
            }
        }
        E::Invalid => format!("{path}: invalid value"),
        E::Missing => format!("{path}: missing"),
        E::Oversize => format!("{path}: too large"),
        E::Unsupported => format!("{path}: not supported"),
    }
}

/// What an index at `path` points to, from the last field name on the path.
fn index_kind(path: &str) -> &'static str {
    let field = path
        .rsplit('.')
        .next()
        .unwrap_or(path)
        .split('[')
        .next()
        .unwrap_or("");
    match field {
        "indices"
        | "attributes"
        | "input"
        | "output"
        | "inverseBindMatrices"
        | "POSITION"
        | "NORMAL"
        | "TANGENT" => "accessor",
        "children" | "nodes" | "node" | "joints" | "skeleton" => "node",
        "bufferView" => "buffer view",
        "buffer" => "buffer",
        "source" => "image",
        "index" => "texture",
        "material" => "material",
        "mesh" => "mesh",
        "camera" => "camera",
        "skin" => "skin",
        "sampler" => "sampler",
        "scene" => "scene",
        "light" => "light",
        _ => "index",
    }
}

/// The value at a validation path such as `meshes[0].primitives[1].attributes["NORMAL"]`.
fn json_at<'v>(mut value: &'v Value, path: &str) -> Option<&'v Value> {
    let mut rest = path;
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix("[\"") {
            let end = r.find("\"]")?;
            value = value.get(&r[..end])?;
            rest = &r[end + 2..];
        } else if let Some(r) = rest.strip_prefix('[') {
            let end = r.find(']')?;
            value = value.get(r[..end].parse::<usize>().ok()?)?;
            rest = &r[end + 1..];
        } else {
            let r = rest.strip_prefix('.').unwrap_or(rest);
            let end = r.find(['.', '[']).unwrap_or(r.len());
            value = value.get(&r[..end])?;
            rest = &r[end..];
        }
    }
    Some(value)
}

/// Counts of what the file has and Chiaro ignores, reported once per kind.
#[derive(Default)]
struct Tally {
    points_or_lines: usize,
    without_positions: usize,
    vertex_colors: usize,
    morph_targets: usize,
    extra_uv_sets: usize,
}

struct Loader<'a> {
    path: &'a Path,
    base_dir: &'a Path,
    raw: &'a Value,
    root: &'a json::Root,
    buffers: Vec<Cow<'a, [u8]>>,
    ignored: Vec<String>,
    tally: Tally,
}

/// A node's place in the world, found by walking the scene graph.
struct Placement {
    node: usize,
    world_from_local: Mat4,
}

impl<'a> Loader<'a> {
    fn invalid(&self, message: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            path: self.path.to_path_buf(),
            message: message.into(),
        }
    }

    fn load(&mut self, bin: Option<&'a [u8]>) -> Result<Scene, SceneError> {
        self.note_unsupported_extensions();
        self.buffers = self.load_buffers(bin)?;

        let mut image_uses: Vec<Option<ColorSpace>> = vec![None; self.root.images.len()];
        let mut materials = (0..self.root.materials.len())
            .map(|index| self.material(index, &mut image_uses))
            .collect::<Result<Vec<_>, _>>()?;
        let meshes = (0..self.root.meshes.len())
            .map(|index| self.mesh(index, &materials))
            .collect::<Result<Vec<_>, _>>()?;

        let placements = self.walk_scene()?;
        let mut instances = Vec::new();
        let mut lights = Vec::new();
        let mut cameras = Vec::new();
        for placement in &placements {
            let node = &self.root.nodes[placement.node];
            if let Some(mesh) = node.mesh {
                let name = node
                    .name
                    .clone()
                    .or_else(|| self.root.meshes[mesh.value()].name.clone())
                    .unwrap_or_else(|| format!("node {}", placement.node));
                instances.push(MeshInstance {
                    mesh: mesh.value(),
                    node: placement.node,
                    name,
                    world_from_local: placement.world_from_local,
                });
            }
            if let Some(light) = self.light(placement)? {
                lights.push(light);
            }
            if let Some(camera) = self.camera(placement)? {
                cameras.push(camera);
            }
        }

        let images = self.decode_images(&image_uses, &mut materials)?;
        self.note_tally();
        Ok(Scene {
            source: None,
            meshes,
            instances,
            materials,
            images,
            lights,
            cameras,
            ignored: std::mem::take(&mut self.ignored),
        })
    }

    fn note_unsupported_extensions(&mut self) {
        let used = self.raw.get("extensionsUsed").and_then(Value::as_array);
        for name in used.into_iter().flatten().filter_map(Value::as_str) {
            if !SUPPORTED_EXTENSIONS.contains(&name) {
                self.ignored
                    .push(format!("extension {name}: not supported, ignored"));
            }
        }
    }

    fn note_tally(&mut self) {
        let root = self.root;
        let t = &self.tally;
        let notes = [
            (root.animations.len(), "animation", "not supported, ignored"),
            (
                root.skins.len(),
                "skin",
                "not supported, skinned meshes drawn in their bind pose",
            ),
            (
                t.morph_targets,
                "primitive with morph targets",
                "not supported, drawn with base positions",
            ),
            (
                t.vertex_colors,
                "primitive with vertex colours",
                "not supported, ignored",
            ),
            (
                t.points_or_lines,
                "primitive of points or lines",
                "not supported, ignored",
            ),
            (
                t.without_positions,
                "primitive without POSITION",
                "nothing to draw, ignored",
            ),
            (
                t.extra_uv_sets,
                "primitive with TEXCOORD_2 or above",
                "only TEXCOORD_0 and TEXCOORD_1 are read",
            ),
        ];
        for (count, what, why) in notes {
            if count > 0 {
                let what = match count {
                    1 => what.to_owned(),
                    _ => plural(what),
                };
                self.ignored.push(format!("{count} {what}: {why}"));
            }
        }
    }

    // ---- Buffers, URIs, accessors -------------------------------------------------------

    fn load_buffers(&self, bin: Option<&'a [u8]>) -> Result<Vec<Cow<'a, [u8]>>, SceneError> {
        let mut buffers = Vec::with_capacity(self.root.buffers.len());
        for (index, buffer) in self.root.buffers.iter().enumerate() {
            let label = object_label("buffer", index, buffer.uri.as_deref(), None);
            let data: Cow<'a, [u8]> = match &buffer.uri {
                None => Cow::Borrowed(bin.ok_or_else(|| {
                    self.invalid(format!(
                        "{label} has no uri and the file has no binary chunk"
                    ))
                })?),
                Some(uri) => Cow::Owned(
                    self.read_uri(uri)
                        .map_err(|e| self.invalid(format!("{label}: {e}")))?
                        .bytes,
                ),
            };
            let declared = buffer.byte_length.0;
            if (data.len() as u64) < declared {
                return Err(self.invalid(format!(
                    "{label} is {} bytes but the file says {declared}",
                    data.len()
                )));
            }
            buffers.push(data);
        }
        Ok(buffers)
    }

    /// Reads a `data:` URI, a `file:` URI or a path relative to the glTF file.
    fn read_uri(&self, uri: &str) -> Result<UriData, String> {
        if let Some(rest) = uri.strip_prefix("data:") {
            let (header, payload) = rest
                .split_once(',')
                .ok_or("data URI has no comma before its payload")?;
            let (mime, base64) = match header.strip_suffix(";base64") {
                Some(mime) => (mime, true),
                None => (header, false),
            };
            let bytes = if base64 {
                decode_base64(payload)?
            } else {
                percent_decode(payload)?
            };
            let mime = mime.split(';').next().unwrap_or("");
            return Ok(UriData {
                bytes,
                mime: (!mime.is_empty()).then(|| mime.to_ascii_lowercase()),
            });
        }
        let scheme_end = uri.find(':');
        let path = match scheme_end {
            Some(colon) if !uri[..colon].contains('/') => {
                let scheme = &uri[..colon];
                if !scheme.eq_ignore_ascii_case("file") {
                    return Err(format!("URI scheme {scheme}: is not supported"));
                }
                let rest = &uri[colon + 1..];
                let rest = rest.strip_prefix("//").unwrap_or(rest);
                PathBuf::from(bytes_to_path(percent_decode(rest)?)?)
            }
            _ => self.base_dir.join(bytes_to_path(percent_decode(uri)?)?),
        };
        let bytes =
            std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        Ok(UriData { bytes, mime: None })
    }

    /// The bytes of a buffer view and its stride, checked to lie inside its buffer.
    fn view_bytes(&self, view_index: usize) -> Result<(&[u8], Option<usize>), SceneError> {
        let view = &self.root.buffer_views[view_index];
        let buffer = &self.buffers[view.buffer.value()];
        let offset = view.byte_offset.map_or(0, |o| o.0);
        let length = view.byte_length.0;
        let end = offset.checked_add(length);
        match end {
            Some(end) if end <= buffer.len() as u64 => {
                let stride = view.byte_stride.map(|s| s.0);
                Ok((&buffer[offset as usize..end as usize], stride))
            }
            _ => Err(self.invalid(format!(
                "buffer view {view_index} (bytes {offset}..{}) runs past the end of buffer {} \
                 ({} bytes)",
                offset.saturating_add(length),
                view.buffer.value(),
                buffer.len()
            ))),
        }
    }

    /// Gathers an accessor's elements into tightly packed bytes, sparse substitution
    /// applied. Every offset is checked against its buffer view before any byte is read.
    fn read_packed(&self, index: usize, dims: usize, what: &str) -> Result<Packed, SceneError> {
        use json::accessor::Type;
        debug_assert!((1..=4).contains(&dims));
        let accessor = &self.root.accessors[index];
        let label = format!("accessor {index} ({what})");
        let (Checked::Valid(component), Checked::Valid(ty)) =
            (accessor.component_type, accessor.type_)
        else {
            return Err(self.invalid(format!("{label} has an invalid type")));
        };
        let component = component.0;
        let expected = [Type::Scalar, Type::Vec2, Type::Vec3, Type::Vec4][dims - 1];
        if ty != expected {
            return Err(self.invalid(format!(
                "{label} is {}, expected {}",
                type_name(ty),
                type_name(expected)
            )));
        }
        let count = usize::try_from(accessor.count.0)
            .ok()
            .filter(|&c| c <= MAX_ACCESSOR_COUNT)
            .ok_or_else(|| {
                self.invalid(format!(
                    "{label} has {} elements, more than Chiaro reads ({MAX_ACCESSOR_COUNT})",
                    accessor.count.0
                ))
            })?;
        let element_size = dims * component.size();
        let mut bytes = Vec::new();

        if let Some(view_index) = accessor.buffer_view {
            let (view, stride) = self.view_bytes(view_index.value())?;
            let stride = stride.unwrap_or(element_size);
            let offset = accessor.byte_offset.map_or(0, |o| o.0);
            let end = if count == 0 {
                Some(offset)
            } else {
                ((count - 1) as u64)
                    .checked_mul(stride as u64)
                    .and_then(|x| x.checked_add(offset))
                    .and_then(|x| x.checked_add(element_size as u64))
            };
            match end {
                Some(end) if end <= view.len() as u64 => {}
                _ => {
                    return Err(self.invalid(format!(
                        "{label} reads {count} elements of {element_size} bytes every {stride} \
                         from byte {offset}, past the end of buffer view {} ({} bytes)",
                        view_index.value(),
                        view.len()
                    )));
                }
            }
            let offset = offset as usize;
            bytes.reserve_exact(count * element_size);
            for i in 0..count {
                let start = offset + i * stride;
                bytes.extend_from_slice(&view[start..start + element_size]);
            }
        } else {
            bytes.resize(count * element_size, 0);
        }

        if let Some(sparse) = &accessor.sparse {
            let n = sparse.count.0;
            if n > count as u64 {
                return Err(self.invalid(format!(
                    "{label} replaces {n} sparse elements but has only {count}"
                )));
            }
            let n = n as usize;
            let Checked::Valid(index_type) = sparse.indices.component_type else {
                return Err(self.invalid(format!("{label} has invalid sparse indices")));
            };
            let index_type = index_type.0;
            let indices = self.sparse_slice(
                sparse.indices.buffer_view.value(),
                sparse.indices.byte_offset.0,
                n * index_type.size(),
                &label,
            )?;
            let values = self.sparse_slice(
                sparse.values.buffer_view.value(),
                sparse.values.byte_offset.0,
                n * element_size,
                &label,
            )?;
            for k in 0..n {
                let target = read_index(index_type, &indices[k * index_type.size()..])
                    .filter(|&t| (t as usize) < count)
                    .ok_or_else(|| {
                        self.invalid(format!("{label} has a sparse index out of range"))
                    })? as usize;
                bytes[target * element_size..(target + 1) * element_size]
                    .copy_from_slice(&values[k * element_size..(k + 1) * element_size]);
            }
        }

        Ok(Packed {
            component,
            normalized: accessor.normalized,
            dims,
            bytes,
        })
    }

    fn sparse_slice(
        &self,
        view_index: usize,
        offset: u64,
        length: usize,
        label: &str,
    ) -> Result<&[u8], SceneError> {
        let (view, _) = self.view_bytes(view_index)?;
        offset
            .checked_add(length as u64)
            .filter(|&end| end <= view.len() as u64)
            .map(|end| &view[offset as usize..end as usize])
            .ok_or_else(|| {
                self.invalid(format!(
                    "{label}: sparse data runs past the end of buffer view {view_index}"
                ))
            })
    }

    /// Float elements of `N` components, integer formats converted as
    /// KHR_mesh_quantization and glTF's normalized-integer rules say.
    fn read_floats<const N: usize>(
        &self,
        index: usize,
        what: &str,
    ) -> Result<Vec<[f32; N]>, SceneError> {
        let packed = self.read_packed(index, N, what)?;
        let size = packed.component.size();
        Ok(packed
            .bytes
            .chunks_exact(packed.dims * size)
            .map(|element| {
                std::array::from_fn(|c| {
                    component_to_f32(packed.component, packed.normalized, &element[c * size..])
                })
            })
            .collect())
    }

    fn read_indices(&self, index: usize, what: &str) -> Result<Vec<u32>, SceneError> {
        let packed = self.read_packed(index, 1, what)?;
        if !matches!(
            packed.component,
            ComponentType::U8 | ComponentType::U16 | ComponentType::U32
        ) {
            return Err(self.invalid(format!(
                "accessor {index} ({what}) has component type {:?}; indices must be unsigned \
                 integers",
                packed.component
            )));
        }
        let size = packed.component.size();
        Ok(packed
            .bytes
            .chunks_exact(size)
            .filter_map(|b| read_index(packed.component, b))
            .collect())
    }

    // ---- Meshes -------------------------------------------------------------------------

    fn mesh(&mut self, index: usize, materials: &[Material]) -> Result<Mesh, SceneError> {
        let mesh = &self.root.meshes[index];
        let label = object_label("mesh", index, None, mesh.name.as_deref());
        let mut primitives = Vec::new();
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let label = format!("{label} primitive {p}");
            if let Some(primitive) = self.primitive(primitive, &label, materials)? {
                primitives.push(primitive);
            }
        }
        Ok(Mesh {
            name: mesh.name.clone().unwrap_or_else(|| format!("mesh {index}")),
            primitives,
        })
    }

    fn primitive(
        &mut self,
        primitive: &json::mesh::Primitive,
        label: &str,
        materials: &[Material],
    ) -> Result<Option<Primitive>, SceneError> {
        use json::mesh::{Mode, Semantic};

        let mode = match primitive.mode {
            Checked::Valid(mode @ (Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan)) => {
                mode
            }
            _ => {
                self.tally.points_or_lines += 1;
                return Ok(None);
            }
        };
        let attribute = |semantic: Semantic| {
            primitive
                .attributes
                .get(&Checked::Valid(semantic))
                .map(|a| a.value())
        };
        let Some(position_accessor) = attribute(Semantic::Positions) else {
            self.tally.without_positions += 1;
            return Ok(None);
        };
        let has = |wanted: fn(&Semantic) -> bool| {
            primitive.attributes.keys().any(|s| match s {
                Checked::Valid(s) => wanted(s),
                Checked::Invalid => false,
            })
        };
        self.tally.vertex_colors += usize::from(has(|s| matches!(s, Semantic::Colors(_))));
        self.tally.extra_uv_sets += usize::from(has(|s| matches!(s, Semantic::TexCoords(2..))));
        if primitive.targets.as_ref().is_some_and(|t| !t.is_empty()) {
            self.tally.morph_targets += 1;
        }

        let mut positions: Vec<Vec3> = self
            .read_floats::<3>(position_accessor, &format!("POSITION of {label}"))?
            .into_iter()
            .map(Vec3::from_array)
            .collect();
        if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
            return Err(self.invalid(format!("{label}: POSITION {v} is not finite")));
        }
        let vertex_count = positions.len();
        let check_count = |name: &str, count: usize| {
            if count == vertex_count {
                Ok(())
            } else {
                Err(self.invalid(format!(
                    "{label}: {name} has {count} values but POSITION has {vertex_count}"
                )))
            }
        };

        let indices = match primitive.indices {
            Some(accessor) => {
                let indices =
                    self.read_indices(accessor.value(), &format!("indices of {label}"))?;
                if let Some(&bad) = indices.iter().find(|&&i| i as usize >= vertex_count) {
                    return Err(self.invalid(format!(
                        "{label}: index {bad} is out of range for {vertex_count} vertices"
                    )));
                }
                indices
            }
            None => (0..vertex_count as u32).collect(),
        };
        let mut indices = triangle_list(mode, indices);
        if indices.is_empty() {
            return Ok(None);
        }

        let read_uv = |set: u32| -> Result<Vec<Vec2>, SceneError> {
            match attribute(Semantic::TexCoords(set)) {
                Some(accessor) => {
                    let name = format!("TEXCOORD_{set}");
                    let uvs = self.read_floats::<2>(accessor, &format!("{name} of {label}"))?;
                    check_count(&name, uvs.len())?;
                    Ok(uvs
                        .into_iter()
                        .map(Vec2::from_array)
                        .map(|uv| if uv.is_finite() { uv } else { Vec2::ZERO })
                        .collect())
                }
                None => Ok(vec![Vec2::ZERO; vertex_count]),
            }
        };
        let mut uv0 = read_uv(0)?;
        let mut uv1 = read_uv(1)?;

        let mut normals = match attribute(Semantic::Normals) {
            Some(accessor) => {
                let normals = self.read_floats::<3>(accessor, &format!("NORMAL of {label}"))?;
                check_count("NORMAL", normals.len())?;
                Some(
                    normals
                        .into_iter()
                        .map(|n| Vec3::from_array(n).normalize_or(Vec3::Z))
                        .collect::<Vec<_>>(),
                )
            }
            None => None,
        };
        // Tangents are only trusted alongside the file's own normals (glTF 2.0 §3.7.2.1).
        let mut tangents = match (attribute(Semantic::Tangents), &normals) {
            (Some(accessor), Some(normals)) => {
                let tangents = self.read_floats::<4>(accessor, &format!("TANGENT of {label}"))?;
                check_count("TANGENT", tangents.len())?;
                let mut tangents: Vec<Vec4> = tangents.into_iter().map(Vec4::from_array).collect();
                vertex_gen::repair_tangents(&mut tangents, normals);
                Some(tangents)
            }
            _ => None,
        };

        let normals = match normals.take() {
            Some(normals) => normals,
            None => {
                positions = vertex_gen::unweld(&positions, &indices);
                uv0 = vertex_gen::unweld(&uv0, &indices);
                uv1 = vertex_gen::unweld(&uv1, &indices);
                indices = (0..positions.len() as u32).collect();
                vertex_gen::flat_normals(&positions)
            }
        };

        let material = primitive.material.map(|m| m.value());
        let normal_map_uv_set = material
            .and_then(|m| materials.get(m))
            .and_then(|m| m.normal_texture)
            .map(|t| t.tex_coord);
        let tangents = match (tangents.take(), normal_map_uv_set) {
            (Some(tangents), _) => tangents,
            (None, Some(set)) => {
                let uvs = if set == 1 { &uv1 } else { &uv0 };
                vertex_gen::mikktspace_tangents(&positions, &normals, uvs, &indices)
                    .unwrap_or_else(|| vertex_gen::perpendicular_tangents(&normals))
            }
            (None, None) => vertex_gen::perpendicular_tangents(&normals),
        };

        let bounds = Aabb::from_points(positions.iter().copied());
        Ok(Some(Primitive {
            positions,
            normals,
            tangents,
            uv0,
            uv1,
            indices,
            material,
            bounds,
        }))
    }

    // ---- Materials and images -----------------------------------------------------------

    /// A material with `TextureRef::image` still holding the glTF image index;
    /// `decode_images` maps it to `Scene::images`.
    fn material(
        &mut self,
        index: usize,
        image_uses: &mut [Option<ColorSpace>],
    ) -> Result<Material, SceneError> {
        let m = &self.root.materials[index];
        let label = object_label("material", index, None, m.name.as_deref());
        let raw = self
            .raw
            .get("materials")
            .and_then(|ms| ms.get(index))
            .unwrap_or(&Value::Null);
        let raw_pbr = raw.get("pbrMetallicRoughness").unwrap_or(&Value::Null);
        let pbr = &m.pbr_metallic_roughness;

        let mut texture = |slot: &str,
                           texture: usize,
                           tex_coord: u32,
                           info: Option<&Value>,
                           color_space: ColorSpace|
         -> Result<TextureRef, SceneError> {
            let reference =
                self.texture_ref(&format!("{label} {slot}"), texture, tex_coord, info)?;
            let used = &mut image_uses[reference.image];
            if *used != Some(ColorSpace::Srgb) {
                *used = Some(color_space);
            }
            Ok(reference)
        };

        let base_color_texture = match &pbr.base_color_texture {
            Some(info) => Some(texture(
                "baseColorTexture",
                info.index.value(),
                info.tex_coord,
                raw_pbr.get("baseColorTexture"),
                ColorSpace::Srgb,
            )?),
            None => None,
        };
        let metallic_roughness_texture = match &pbr.metallic_roughness_texture {
            Some(info) => Some(texture(
                "metallicRoughnessTexture",
                info.index.value(),
                info.tex_coord,
                raw_pbr.get("metallicRoughnessTexture"),
                ColorSpace::Linear,
            )?),
            None => None,
        };
        let normal_texture = match &m.normal_texture {
            Some(info) => Some(texture(
                "normalTexture",
                info.index.value(),
                info.tex_coord,
                raw.get("normalTexture"),
                ColorSpace::Linear,
            )?),
            None => None,
        };
        let occlusion_texture = match &m.occlusion_texture {
            Some(info) => Some(texture(
                "occlusionTexture",
                info.index.value(),
                info.tex_coord,
                raw.get("occlusionTexture"),
                ColorSpace::Linear,
            )?),
            None => None,
        };
        let emissive_texture = match &m.emissive_texture {
            Some(info) => Some(texture(
                "emissiveTexture",
                info.index.value(),
                info.tex_coord,
                raw.get("emissiveTexture"),
                ColorSpace::Srgb,
            )?),
            None => None,
        };

        let emissive_strength = m
            .extensions
            .as_ref()
            .and_then(|e| e.emissive_strength.as_ref())
            .map_or(1.0, |s| s.emissive_strength.0);
        let material = Material {
            name: m
                .name
                .clone()
                .unwrap_or_else(|| format!("material {index}")),
            base_color: Vec4::from_array(pbr.base_color_factor.0),
            base_color_texture,
            metallic: pbr.metallic_factor.0,
            roughness: pbr.roughness_factor.0,
            metallic_roughness_texture,
            normal_scale: m.normal_texture.as_ref().map_or(1.0, |t| t.scale),
            normal_texture,
            occlusion_strength: m.occlusion_texture.as_ref().map_or(1.0, |t| t.strength.0),
            occlusion_texture,
            emissive: Vec3::from_array(m.emissive_factor.0) * emissive_strength,
            emissive_texture,
            alpha_mode: match m.alpha_mode {
                Checked::Valid(json::material::AlphaMode::Mask) => AlphaMode::Mask,
                Checked::Valid(json::material::AlphaMode::Blend) => AlphaMode::Blend,
                _ => AlphaMode::Opaque,
            },
            alpha_cutoff: m.alpha_cutoff.map_or(0.5, |c| c.0),
            double_sided: m.double_sided,
        };
        let factors_finite = material.base_color.is_finite()
            && material.emissive.is_finite()
            && [
                material.metallic,
                material.roughness,
                material.normal_scale,
                material.occlusion_strength,
                material.alpha_cutoff,
            ]
            .iter()
            .all(|f| f.is_finite());
        if !factors_finite {
            return Err(self.invalid(format!("{label}: a factor is not finite")));
        }
        Ok(material)
    }

    /// A texture info's image, sampler, UV set and KHR_texture_transform. The transform is
    /// read from the raw JSON because the typed model drops it on normal and occlusion
    /// textures.
    fn texture_ref(
        &mut self,
        label: &str,
        texture: usize,
        tex_coord: u32,
        info: Option<&Value>,
    ) -> Result<TextureRef, SceneError> {
        #[derive(serde::Deserialize)]
        #[serde(rename_all = "camelCase")]
        struct TextureTransform {
            #[serde(default)]
            offset: [f32; 2],
            #[serde(default)]
            rotation: f32,
            #[serde(default = "unit_scale")]
            scale: [f32; 2],
            tex_coord: Option<u32>,
        }
        fn unit_scale() -> [f32; 2] {
            [1.0, 1.0]
        }

        let gltf_texture = &self.root.textures[texture];
        let sampler = gltf_texture
            .sampler
            .map(|s| sampler_desc(&self.root.samplers[s.value()]))
            .unwrap_or_default();
        let mut reference = TextureRef {
            image: gltf_texture.source.value(),
            sampler,
            tex_coord,
            transform: UvTransform::default(),
        };
        let transform_json = info
            .and_then(|i| i.get("extensions"))
            .and_then(|e| e.get("KHR_texture_transform"));
        if let Some(value) = transform_json {
            let t: TextureTransform = serde_json::from_value(value.clone()).map_err(|e| {
                self.invalid(format!("{label}: invalid KHR_texture_transform: {e}"))
            })?;
            reference.transform = UvTransform {
                offset: Vec2::from_array(t.offset),
                rotation_rad: t.rotation,
                scale: Vec2::from_array(t.scale),
            };
            if let Some(set) = t.tex_coord {
                reference.tex_coord = set;
            }
            let m = reference.transform.matrix();
            if !m.iter().all(|c| c.is_finite()) {
                return Err(self.invalid(format!("{label}: KHR_texture_transform is not finite")));
            }
        }
        if reference.tex_coord > 1 {
            self.ignored.push(format!(
                "{label}: TEXCOORD_{} is not read, uses TEXCOORD_0",
                reference.tex_coord
            ));
            reference.tex_coord = 0;
        }
        Ok(reference)
    }

    /// Decodes each image a material uses, once, and points the materials' texture
    /// references at `Scene::images`. An image used as colour anywhere is sRGB.
    fn decode_images(
        &self,
        uses: &[Option<ColorSpace>],
        materials: &mut [Material],
    ) -> Result<Vec<Image>, SceneError> {
        let mut images = Vec::new();
        let mut scene_index = vec![usize::MAX; uses.len()];
        for (index, color_space) in uses.iter().enumerate() {
            if let Some(color_space) = color_space {
                scene_index[index] = images.len();
                images.push(self.decode_image(index, *color_space)?);
            }
        }
        for material in materials {
            for texture in [
                &mut material.base_color_texture,
                &mut material.metallic_roughness_texture,
                &mut material.normal_texture,
                &mut material.occlusion_texture,
                &mut material.emissive_texture,
            ]
            .into_iter()
            .flatten()
            {
                texture.image = scene_index[texture.image];
                debug_assert!(texture.image < images.len());
            }
        }
        Ok(images)
    }

    fn decode_image(&self, index: usize, color_space: ColorSpace) -> Result<Image, SceneError> {
        let image = &self.root.images[index];
        let label = object_label("image", index, image.uri.as_deref(), image.name.as_deref());
        let (bytes, mime): (Cow<[u8]>, Option<String>) = match (&image.buffer_view, &image.uri) {
            (Some(view), _) => (
                Cow::Borrowed(self.view_bytes(view.value())?.0),
                image.mime_type.as_ref().map(|m| m.0.to_ascii_lowercase()),
            ),
            (None, Some(uri)) => {
                let data = self
                    .read_uri(uri)
                    .map_err(|e| self.invalid(format!("{label}: {e}")))?;
                let mime = image
                    .mime_type
                    .as_ref()
                    .map(|m| m.0.to_ascii_lowercase())
                    .or(data.mime.filter(|m| m.starts_with("image/")));
                (Cow::Owned(data.bytes), mime)
            }
            (None, None) => {
                return Err(self.invalid(format!("{label} has neither a uri nor a bufferView")));
            }
        };
        if let Some(mime) = mime.as_deref()
            && !matches!(mime, "image/png" | "image/jpeg" | "image/jpg")
        {
            return Err(self.invalid(format!(
                "{label}: unsupported image format {mime}; Chiaro reads PNG and JPEG"
            )));
        }
        let format = match image::guess_format(&bytes) {
            Ok(format @ (image::ImageFormat::Png | image::ImageFormat::Jpeg)) => format,
            Ok(other) => {
                return Err(self.invalid(format!(
                    "{label}: unsupported image format ({other:?}); Chiaro reads PNG and JPEG"
                )));
            }
            Err(_) => {
                return Err(self.invalid(format!(
                    "{label}: unsupported image format; Chiaro reads PNG and JPEG"
                )));
            }
        };
        let decoded = image::load_from_memory_with_format(&bytes, format)
            .map_err(|e| self.invalid(format!("{label}: cannot decode: {e}")))?;
        let rgba = decoded.into_rgba8();
        let name = image
            .name
            .clone()
            .or_else(|| image.uri.clone().filter(|u| !u.starts_with("data:")))
            .unwrap_or_else(|| format!("image {index}"));
        Ok(Image {
            name,
            width: rgba.width(),
            height: rgba.height(),
            rgba8: rgba.into_raw(),
            color_space,
        })
    }

    // ---- Nodes, lights, cameras ---------------------------------------------------------

    /// World transforms of the nodes of the default scene (else scene 0, else every root
    /// node), parents before children. A node reached twice (a cycle, or a child shared by
    /// two parents) is an error, as glTF requires disjoint trees.
    fn walk_scene(&self) -> Result<Vec<Placement>, SceneError> {
        let root = self.root;
        let roots: Vec<usize> = match root.scene.map(|s| s.value()).or(if root.scenes.is_empty() {
            None
        } else {
            Some(0)
        }) {
            Some(scene) => root.scenes[scene].nodes.iter().map(|n| n.value()).collect(),
            None => {
                let mut is_child = vec![false; root.nodes.len()];
                for node in &root.nodes {
                    for child in node.children.iter().flatten() {
                        is_child[child.value()] = true;
                    }
                }
                (0..root.nodes.len()).filter(|&n| !is_child[n]).collect()
            }
        };

        let mut visited = vec![false; root.nodes.len()];
        let mut placements = Vec::new();
        let mut stack: Vec<(usize, Mat4)> =
            roots.iter().rev().map(|&n| (n, Mat4::IDENTITY)).collect();
        while let Some((index, parent_from_world)) = stack.pop() {
            let node = &root.nodes[index];
            let label = object_label("node", index, None, node.name.as_deref());
            if std::mem::replace(&mut visited[index], true) {
                return Err(self.invalid(format!(
                    "{label}: reached twice in the node hierarchy (a cycle or a shared child)"
                )));
            }
            let world_from_local = parent_from_world * local_transform(node);
            if !world_from_local.is_finite() {
                return Err(self.invalid(format!("{label}: transform is not finite")));
            }
            for child in node.children.iter().flatten().rev() {
                stack.push((child.value(), world_from_local));
            }
            placements.push(Placement {
                node: index,
                world_from_local,
            });
        }
        Ok(placements)
    }

    fn light(&self, placement: &Placement) -> Result<Option<Light>, SceneError> {
        use json::extensions::scene::khr_lights_punctual::Type;

        let node = &self.root.nodes[placement.node];
        let Some(light_index) = node
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
            .map(|l| l.light.value())
        else {
            return Ok(None);
        };
        let Some(light) = self
            .root
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
            .and_then(|l| l.lights.get(light_index))
        else {
            return Err(self.invalid(format!(
                "node {}: light {light_index} is out of range",
                placement.node
            )));
        };
        let label = object_label("light", light_index, None, light.name.as_deref());
        let color = Vec3::from_array(light.color);
        if !color.is_finite() || color.min_element() < 0.0 {
            return Err(self.invalid(format!(
                "{label}: colour {color} is not a linear RGB colour"
            )));
        }
        if !light.intensity.is_finite() || light.intensity < 0.0 {
            return Err(self.invalid(format!(
                "{label}: intensity {} is negative or not finite",
                light.intensity
            )));
        }
        if let Some(range) = light.range
            && !(range.is_finite() && range > 0.0)
        {
            return Err(self.invalid(format!("{label}: range {range} is not positive")));
        }
        let kind = match (light.type_, &light.spot) {
            (Checked::Valid(Type::Directional), _) => LightKind::Directional,
            (Checked::Valid(Type::Point), _) => LightKind::Point,
            (Checked::Valid(Type::Spot), Some(spot)) => {
                let (inner, outer) = spot_cone(spot.inner_cone_angle, spot.outer_cone_angle)
                    .ok_or_else(|| {
                        self.invalid(format!(
                            "{label}: spot cone angles must satisfy 0 <= inner ({}) < outer \
                             ({}) <= pi/2",
                            spot.inner_cone_angle, spot.outer_cone_angle
                        ))
                    })?;
                LightKind::Spot {
                    inner_cone_rad: inner,
                    outer_cone_rad: outer,
                }
            }
            _ => return Err(self.invalid(format!("{label}: invalid light type"))),
        };
        let world = placement.world_from_local;
        Ok(Some(Light {
            name: light
                .name
                .clone()
                .or_else(|| node.name.clone())
                .unwrap_or_else(|| format!("light {light_index}")),
            node: placement.node,
            kind,
            color,
            intensity: light.intensity,
            range: light.range,
            position: world.w_axis.truncate(),
            direction: world
                .transform_vector3(Vec3::NEG_Z)
                .normalize_or(Vec3::NEG_Z),
        }))
    }

    fn camera(&mut self, placement: &Placement) -> Result<Option<Camera>, SceneError> {
        let node = &self.root.nodes[placement.node];
        let Some(camera_index) = node.camera.map(|c| c.value()) else {
            return Ok(None);
        };
        let camera = &self.root.cameras[camera_index];
        let label = object_label("camera", camera_index, None, camera.name.as_deref());
        let perspective = match (camera.type_, &camera.perspective) {
            (Checked::Valid(json::camera::Type::Perspective), Some(p)) => p,
            (Checked::Valid(json::camera::Type::Perspective), None) => {
                return Err(self.invalid(format!(
                    "{label}: type is perspective but it has no perspective parameters"
                )));
            }
            _ => {
                self.ignored.push(format!(
                    "{label} on node {}: orthographic cameras are not supported, ignored",
                    placement.node
                ));
                return Ok(None);
            }
        };
        let yfov = perspective.yfov;
        let znear = perspective.znear;
        if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
            return Err(self.invalid(format!("{label}: yfov {yfov} is not in (0, pi)")));
        }
        if !(znear > 0.0 && znear.is_finite()) {
            return Err(self.invalid(format!("{label}: znear {znear} is not positive")));
        }
        if let Some(zfar) = perspective.zfar
            && !(zfar > znear && zfar.is_finite())
        {
            return Err(self.invalid(format!("{label}: zfar {zfar} is not beyond znear {znear}")));
        }
        if let Some(aspect) = perspective.aspect_ratio
            && !(aspect > 0.0 && aspect.is_finite())
        {
            return Err(self.invalid(format!("{label}: aspect ratio {aspect} is not positive")));
        }
        let world_from_view = without_scale(placement.world_from_local).ok_or_else(|| {
            self.invalid(format!(
                "{label} on node {}: the node's transform is degenerate",
                placement.node
            ))
        })?;
        Ok(Some(Camera {
            name: camera
                .name
                .clone()
                .or_else(|| node.name.clone())
                .unwrap_or_else(|| format!("camera {camera_index}")),
            node: placement.node,
            yfov_rad: yfov,
            znear,
            zfar: perspective.zfar,
            aspect_ratio: perspective.aspect_ratio,
            world_from_view,
        }))
    }
}

struct UriData {
    bytes: Vec<u8>,
    /// The media type of a `data:` URI.
    mime: Option<String>,
}

struct Packed {
    component: ComponentType,
    normalized: bool,
    dims: usize,
    bytes: Vec<u8>,
}

/// One component as a float. Normalized integers map to [0, 1] or [-1, 1] (glTF 2.0
/// §3.11: signed values use `max(c / 127, -1)`, so -128 and -127 both give -1).
fn component_to_f32(component: ComponentType, normalized: bool, b: &[u8]) -> f32 {
    match component {
        ComponentType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        ComponentType::U8 => {
            let v = f32::from(b[0]);
            if normalized { v / 255.0 } else { v }
        }
        ComponentType::I8 => {
            let v = f32::from(b[0] as i8);
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        ComponentType::U16 => {
            let v = f32::from(u16::from_le_bytes([b[0], b[1]]));
            if normalized { v / 65535.0 } else { v }
        }
        ComponentType::I16 => {
            let v = f32::from(i16::from_le_bytes([b[0], b[1]]));
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        ComponentType::U32 => {
            let v = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
            if normalized {
                (f64::from(v) / f64::from(u32::MAX)) as f32
            } else {
                v as f32
            }
        }
    }
}

fn type_name(ty: json::accessor::Type) -> &'static str {
    use json::accessor::Type;
    match ty {
        Type::Scalar => "SCALAR",
        Type::Vec2 => "VEC2",
        Type::Vec3 => "VEC3",
        Type::Vec4 => "VEC4",
        Type::Mat2 => "MAT2",
        Type::Mat3 => "MAT3",
        Type::Mat4 => "MAT4",
    }
}

fn read_index(component: ComponentType, b: &[u8]) -> Option<u32> {
    match component {
        ComponentType::U8 => b.first().map(|&v| u32::from(v)),
        ComponentType::U16 => b
            .get(..2)
            .map(|b| u32::from(u16::from_le_bytes([b[0], b[1]]))),
        ComponentType::U32 => b
            .get(..4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        _ => None,
    }
}

/// Strips and fans become lists with the winding glTF 2.0 §3.7.2.1 gives them: strip
/// triangle `i` is `(i, i+1, i+2)` with odd ones flipped, fan triangle `i` is
/// `(i+1, i+2, 0)`. A list's incomplete last triangle is dropped.
fn triangle_list(mode: json::mesh::Mode, indices: Vec<u32>) -> Vec<u32> {
    use json::mesh::Mode;
    let n = indices.len();
    match mode {
        Mode::TriangleStrip if n >= 3 => (0..n - 2)
            .flat_map(|i| {
                if i % 2 == 0 {
                    [indices[i], indices[i + 1], indices[i + 2]]
                } else {
                    [indices[i], indices[i + 2], indices[i + 1]]
                }
            })
            .collect(),
        Mode::TriangleFan if n >= 3 => (0..n - 2)
            .flat_map(|i| [indices[i + 1], indices[i + 2], indices[0]])
            .collect(),
        Mode::Triangles => {
            let mut indices = indices;
            indices.truncate(n - n % 3);
            indices
        }
        _ => Vec::new(),
    }
}

fn local_transform(node: &json::scene::Node) -> Mat4 {
    if let Some(m) = node.matrix {
        return Mat4::from_cols_array(&m);
    }
    let translation = Vec3::from_array(node.translation.unwrap_or([0.0; 3]));
    let rotation = node
        .rotation
        .map_or(Quat::IDENTITY, |r| Quat::from_array(r.0));
    let scale = Vec3::from_array(node.scale.unwrap_or([1.0; 3]));
    // Exporters write quaternions a few ulps off unit length; a zero one stays zero and
    // fails the finiteness check after normalising.
    Mat4::from_scale_rotation_translation(scale, rotation.normalize(), translation)
}

/// The rigid part of a transform: the view direction (-Z) kept exactly, +Y made
/// perpendicular to it, +X completing a right-handed frame. `None` when an axis collapses.
fn without_scale(m: Mat4) -> Option<Mat4> {
    let z = m.z_axis.truncate().try_normalize()?;
    let y_in = m.y_axis.truncate();
    let y = (y_in - z * z.dot(y_in)).try_normalize()?;
    let x = y.cross(z);
    Some(Mat4::from_cols(
        x.extend(0.0),
        y.extend(0.0),
        z.extend(0.0),
        m.w_axis,
    ))
}

/// Validated spot cone half-angles: `0 <= inner < outer <= pi/2`. `inner == outer` (a
/// hard-edged cone some exporters write) is tolerated by pulling inner in by 1e-4 rad, so
/// that the smoothstep between them never divides by zero.
fn spot_cone(inner: f32, outer: f32) -> Option<(f32, f32)> {
    const EPS: f32 = 1e-4;
    let half_pi = std::f32::consts::FRAC_PI_2;
    let ordered = inner >= 0.0 && outer > 0.0 && inner <= outer && outer <= half_pi + 1e-6;
    if !ordered {
        return None;
    }
    let outer = outer.min(half_pi);
    let inner = if inner >= outer - EPS {
        (outer - EPS).max(0.0)
    } else {
        inner
    };
    Some((inner, outer))
}

fn sampler_desc(sampler: &json::texture::Sampler) -> SamplerDesc {
    use json::texture::{MagFilter, MinFilter, WrappingMode};
    let wrap = |mode: Checked<WrappingMode>| match mode {
        Checked::Valid(WrappingMode::ClampToEdge) => WrapMode::ClampToEdge,
        Checked::Valid(WrappingMode::MirroredRepeat) => WrapMode::MirroredRepeat,
        _ => WrapMode::Repeat,
    };
    let (min_linear, mipmaps) = match sampler.min_filter {
        Some(Checked::Valid(MinFilter::Nearest)) => (false, false),
        Some(Checked::Valid(MinFilter::Linear)) => (true, false),
        Some(Checked::Valid(MinFilter::NearestMipmapNearest | MinFilter::NearestMipmapLinear)) => {
            (false, true)
        }
        _ => (true, true),
    };
    SamplerDesc {
        wrap_u: wrap(sampler.wrap_s),
        wrap_v: wrap(sampler.wrap_t),
        mag_linear: !matches!(sampler.mag_filter, Some(Checked::Valid(MagFilter::Nearest))),
        min_linear,
        mipmaps,
    }
}

/// `kind index (detail)`: the detail is a file name for external resources, else the
/// object's name.
fn object_label(kind: &str, index: usize, uri: Option<&str>, name: Option<&str>) -> String {
    let detail = uri.filter(|u| !u.starts_with("data:")).or(name);
    match detail {
        Some(detail) => format!("{kind} {index} ({detail})"),
        None => format!("{kind} {index}"),
    }
}

fn plural(what: &str) -> String {
    // "primitive with vertex colours" -> "primitives with vertex colours".
    match what.split_once(' ') {
        Some((head, tail)) => format!("{head}s {tail}"),
        None => format!("{what}s"),
    }
}

/// Standard or URL-safe base64, padding optional (RFC 4648 §4 and §5).
fn decode_base64(text: &str) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(text.len() / 4 * 3);
    let mut acc = 0u32;
    let mut bits = 0;
    for (i, c) in text.bytes().enumerate() {
        let value = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' => break,
            b' ' | b'\t' | b'\r' | b'\n' => continue,
            _ => return Err(format!("invalid base64 character at {i}")),
        };
        acc = (acc << 6) | u32::from(value);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
        }
    }
    Ok(out)
}

fn percent_decode(text: &str) -> Result<Vec<u8>, String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("invalid percent escape in URI {text}"))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    Ok(out)
}

fn bytes_to_path(bytes: Vec<u8>) -> Result<String, String> {
    String::from_utf8(bytes).map_err(|_| "URI is not UTF-8 after percent-decoding".into())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A scratch folder under the system temp dir, removed when dropped.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(tag: &str) -> TempDir {
            static NEXT: AtomicUsize = AtomicUsize::new(0);
            let n = NEXT.fetch_add(1, Ordering::Relaxed);
            let dir = std::env::temp_dir()
                .join(format!("chiaro-gltf-test-{}-{tag}-{n}", std::process::id()));
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

    fn base64(bytes: &[u8]) -> String {
        const ALPHABET: &[u8; 64] =
            b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut out = String::new();
        for chunk in bytes.chunks(3) {
            let b = [
                chunk[0],
                *chunk.get(1).unwrap_or(&0),
                *chunk.get(2).unwrap_or(&0),
            ];
            let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
            for i in 0..4 {
                if i <= chunk.len() {
                    out.push(ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char);
                } else {
                    out.push('=');
                }
            }
        }
        out
    }

    fn data_uri(bytes: &[u8]) -> String {
        format!("data:application/octet-stream;base64,{}", base64(bytes))
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
        assert_eq!(
            scene.source.as_deref(),
            Some(dir.0.join("scene.gltf").as_path())
        );
    }

    #[test]
    fn indexed_quad_without_normals_is_unwelded() {
        let dir = TempDir::new("quad");
        let positions = f32_bytes(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0]);
        let indices: Vec<u8> = [0u16, 1, 2, 0, 2, 3]
            .iter()
            .flat_map(|i| i.to_le_bytes())
            .collect();
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
    fn punctual_lights_take_their_node_transforms() {
        let dir = TempDir::new("lights");
        let mut doc = triangle_doc();
        let half = std::f32::consts::FRAC_1_SQRT_2;
        doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
        doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [
            { "type": "point", "name": "bulb", "color": [1.0, 0.5, 0.25], "intensity": 10.0 },
            { "type": "spot", "intensity": 20.0, "range": 8.0,
              "spot": { "innerConeAngle": 0.2, "outerConeAngle": 0.5 } },
            { "type": "directional", "intensity": 3.0 },
            { "type": "spot", "spot": {} }
        ] } });
        doc["scenes"] = json!([{ "nodes": [0, 1, 2, 3, 4] }]);
        doc["nodes"] = json!([
            { "mesh": 0 },
            { "translation": [1.0, 2.0, 3.0], "extensions": { "KHR_lights_punctual": { "light": 0 } } },
            { "name": "spot node", "rotation": [half, 0.0, 0.0, half],
              "extensions": { "KHR_lights_punctual": { "light": 1 } } },
            { "extensions": { "KHR_lights_punctual": { "light": 2 } } },
            { "extensions": { "KHR_lights_punctual": { "light": 3 } } }
        ]);
        let scene = load_doc(&dir, &doc).unwrap();
        assert_eq!(scene.lights.len(), 4);

        let point = &scene.lights[0];
        assert_eq!(point.name, "bulb");
        assert_eq!(point.node, 1);
        assert_eq!(point.kind, LightKind::Point);
        assert_eq!(point.color, Vec3::new(1.0, 0.5, 0.25));
        assert_eq!(point.intensity, 10.0);
        assert_eq!(point.range, None);
        assert_eq!(point.position, Vec3::new(1.0, 2.0, 3.0));

        let spot = &scene.lights[1];
        assert_eq!(spot.name, "spot node");
        assert_eq!(
            spot.kind,
            LightKind::Spot {
                inner_cone_rad: 0.2,
                outer_cone_rad: 0.5
            }
        );
        assert_eq!(spot.range, Some(8.0));
        // +90 degrees about X turns -Z into +Y.
        assert!(
            spot.direction.distance(Vec3::Y) < 1e-6,
            "{}",
            spot.direction
        );

        let sun = &scene.lights[2];
        assert_eq!(sun.kind, LightKind::Directional);
        assert_eq!(sun.direction, Vec3::NEG_Z);
        assert_eq!(sun.color, Vec3::ONE);
        assert_eq!(sun.name, "light 2");

        let default_spot = &scene.lights[3];
        assert_eq!(default_spot.intensity, 1.0);
        assert_eq!(
            default_spot.kind,
            LightKind::Spot {
                inner_cone_rad: 0.0,
                outer_cone_rad: std::f32::consts::FRAC_PI_4
            }
        );
    }

    #[test]
    fn bad_lights_are_invalid() {
        let dir = TempDir::new("bad-lights");
        for (light, needle) in [
            (json!({ "type": "point", "intensity": -1.0 }), "intensity"),
            (json!({ "type": "point", "range": 0.0 }), "range"),
            (
                json!({ "type": "spot", "spot": { "innerConeAngle": 0.6, "outerConeAngle": 0.5 } }),
                "cone",
            ),
            (
                json!({ "type": "spot", "spot": { "outerConeAngle": 2.0 } }),
                "cone",
            ),
        ] {
            let mut doc = triangle_doc();
            doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [light] } });
            doc["nodes"][0]["extensions"] = json!({ "KHR_lights_punctual": { "light": 0 } });
            let message = invalid_message(load_doc(&dir, &doc));
            assert!(
                message.contains("light 0") && message.contains(needle),
                "{message}"
            );
        }

        // A hard-edged cone (inner == outer) is tolerated.
        let mut doc = triangle_doc();
        doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [
            { "type": "spot", "spot": { "innerConeAngle": 0.5, "outerConeAngle": 0.5 } }
        ] } });
        doc["nodes"][0]["extensions"] = json!({ "KHR_lights_punctual": { "light": 0 } });
        let scene = load_doc(&dir, &doc).unwrap();
        let LightKind::Spot {
            inner_cone_rad,
            outer_cone_rad,
        } = scene.lights[0].kind
        else {
            panic!("not a spot light");
        };
        assert_eq!(outer_cone_rad, 0.5);
        assert!(inner_cone_rad < outer_cone_rad && inner_cone_rad > 0.49);
    }

    #[test]
    fn perspective_camera_drops_node_scale() {
        let dir = TempDir::new("camera");
        let mut doc = triangle_doc();
        doc["cameras"] = json!([
            { "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5 } },
            { "type": "orthographic", "name": "ortho",
              "orthographic": { "xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 10.0 } }
        ]);
        doc["scenes"] = json!([{ "nodes": [0, 1, 2] }]);
        doc["nodes"] = json!([
            { "mesh": 0 },
            { "name": "eye", "camera": 0, "translation": [0.0, 1.0, 4.0], "scale": [3.0, 3.0, 3.0] },
            { "camera": 1 }
        ]);
        let scene = load_doc(&dir, &doc).unwrap();
        assert_eq!(scene.cameras.len(), 1);
        let camera = &scene.cameras[0];
        assert_eq!(camera.name, "eye");
        assert_eq!(camera.node, 1);
        assert_eq!(camera.yfov_rad, 0.8);
        assert_eq!(camera.zfar, None);
        assert_eq!(camera.aspect_ratio, Some(1.5));
        let expected = Mat4::from_translation(Vec3::new(0.0, 1.0, 4.0));
        assert!(camera.world_from_view.abs_diff_eq(expected, 1e-6));
        assert!(
            scene
                .ignored
                .iter()
                .any(|s| s.contains("camera 1 (ortho)") && s.contains("orthographic")),
            "{:?}",
            scene.ignored
        );
    }

    #[test]
    fn missing_file_is_io_error_naming_the_path() {
        let path = std::env::temp_dir().join("chiaro-no-such-dir/scene.gltf");
        let error = load_gltf(&path).unwrap_err();
        assert!(matches!(error, SceneError::Io { .. }), "{error:?}");
        let message = error.to_string();
        assert!(
            message.contains("chiaro-no-such-dir/scene.gltf"),
            "{message}"
        );
        assert!(message.contains("cannot read file"), "{message}");
    }

    #[test]
    fn broken_json_is_parse_error_with_its_line() {
        let dir = TempDir::new("broken");
        let path = dir.write(
            "broken.gltf",
            b"{\n  \"asset\": {\n    \"version\": \"2.0\",,\n  }\n}",
        );
        let error = load_gltf(&path).unwrap_err();
        let SceneError::Parse { message, .. } = &error else {
            panic!("expected Parse, got {error:?}");
        };
        assert!(message.contains("line 3"), "{message}");
        assert!(
            error
                .to_string()
                .contains("broken.gltf: not a valid glTF file")
        );

        let path = dir.write(
            "image.gltf",
            &png_bytes(image::DynamicImage::new_rgba8(1, 1)),
        );
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
        doc["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
        doc["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
        match load_doc(&dir, &doc) {
            Err(SceneError::UnsupportedExtension { extension, .. }) => {
                assert_eq!(extension, "KHR_draco_mesh_compression");
            }
            other => panic!("expected UnsupportedExtension, got {other:?}"),
        }

        // Used but not required: loads, and says what it ignored.
        doc["extensionsRequired"] = json!([]);
        doc["extensionsUsed"] = json!(["KHR_materials_transmission", "KHR_lights_punctual"]);
        let scene = load_doc(&dir, &doc).unwrap();
        assert_eq!(
            scene.ignored,
            vec!["extension KHR_materials_transmission: not supported, ignored".to_owned()]
        );
    }

    #[test]
    fn quantized_positions_load_when_mesh_quantization_is_required() {
        let dir = TempDir::new("quantized");
        let bytes: Vec<u8> = [0i16, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let mut doc = triangle_doc();
        doc["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
        doc["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
        // VEC3 of i16 with a 8-byte stride (4-byte aligned), as the extension requires.
        doc["accessors"][0]["componentType"] = json!(5122);
        doc["bufferViews"][0] = json!({ "buffer": 0, "byteLength": 24, "byteStride": 8 });
        doc["buffers"] = json!([{ "byteLength": bytes.len(), "uri": data_uri(&bytes) }]);
        let scene = load_doc(&dir, &doc).unwrap();
        let p = &scene.meshes[0].primitives[0];
        assert_eq!(
            p.positions,
            vec![
                Vec3::ZERO,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 2.0, 0.0)
            ]
        );
    }

    #[test]
    fn short_or_missing_buffers_name_the_buffer() {
        let dir = TempDir::new("buffers");
        let mut doc = triangle_doc();
        doc["buffers"][0]["byteLength"] = json!(400);
        doc["bufferViews"][0]["byteLength"] = json!(36);
        let message = invalid_message(load_doc(&dir, &doc));
        assert_eq!(message, "buffer 0 is 36 bytes but the file says 400");

        doc["buffers"][0] = json!({ "byteLength": 36, "uri": "missing%20file.bin" });
        let message = invalid_message(load_doc(&dir, &doc));
        assert!(
            message.starts_with("buffer 0 (missing%20file.bin): cannot read"),
            "{message}"
        );
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
        assert!(
            message.starts_with("accessor 0 (POSITION of mesh 0 (triangle) primitive 0)"),
            "{message}"
        );

        // A buffer view past the end of its buffer.
        let mut doc = triangle_doc();
        doc["bufferViews"][0]["byteOffset"] = json!(8);
        let message = invalid_message(load_doc(&dir, &doc));
        assert!(message.contains("buffer view 0"), "{message}");

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
        assert!(
            message.contains("index 5 is out of range for 3 vertices"),
            "{message}"
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
        assert_eq!(message, "node 1 (Bigger): transform is not finite");

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

    /// The triangle with a material whose base colour texture is `image`.
    fn textured_doc(image: Value) -> Value {
        let mut doc = triangle_doc();
        doc["meshes"][0]["primitives"][0]["material"] = json!(0);
        doc["materials"] =
            json!([{ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } } }]);
        doc["textures"] = json!([{ "source": 0 }]);
        doc["images"] = json!([image]);
        doc
    }

    #[test]
    fn unsupported_image_formats_name_the_image() {
        let dir = TempDir::new("gif");
        dir.write("tex.gif", b"GIF89a\x01\0\x01\0\0\0\0;");
        let message = invalid_message(load_doc(&dir, &textured_doc(json!({ "uri": "tex.gif" }))));
        assert!(
            message.starts_with("image 0 (tex.gif): unsupported image format"),
            "{message}"
        );

        dir.write("tex.png", b"definitely not a png");
        let message = invalid_message(load_doc(&dir, &textured_doc(json!({ "uri": "tex.png" }))));
        assert!(
            message.starts_with("image 0 (tex.png): unsupported image format"),
            "{message}"
        );

        let doc = textured_doc(json!({ "uri": "tex.png", "mimeType": "image/ktx2" }));
        let message = invalid_message(load_doc(&dir, &doc));
        assert!(message.contains("image/ktx2"), "{message}");

        // An image with a bufferView and no mimeType: the gltf crate's wrapper would panic.
        let message = invalid_message(load_doc(&dir, &textured_doc(json!({ "bufferView": 0 }))));
        assert!(
            message.starts_with("image 0: unsupported image format"),
            "{message}"
        );
    }

    #[test]
    fn materials_textures_and_generated_tangents() {
        let dir = TempDir::new("material");
        let mut rgba = image::RgbaImage::new(2, 1);
        rgba.put_pixel(1, 0, image::Rgba([10, 20, 30, 255]));
        dir.write("color.png", &png_bytes(rgba.into()));
        let grey16 =
            image::ImageBuffer::<image::Luma<u16>, _>::from_raw(1, 1, vec![65535u16]).unwrap();
        dir.write(
            "orm.png",
            &png_bytes(image::DynamicImage::ImageLuma16(grey16)),
        );

        // A quad facing +Z with upright glTF UVs (v = 0 at the top, y = 1).
        let mut bytes = f32_bytes(&[
            0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0, // POSITION
            0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, // NORMAL
            0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, // TEXCOORD_0
        ]);
        bytes.extend([0u8, 1, 2, 0, 2, 3]);
        let mut doc = triangle_doc();
        doc["meshes"][0]["primitives"][0] = json!({
            "attributes": { "POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2 },
            "indices": 3, "material": 0
        });
        doc["accessors"] = json!([
            { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] },
            { "bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3" },
            { "bufferView": 0, "byteOffset": 96, "componentType": 5126, "count": 4, "type": "VEC2" },
            { "bufferView": 0, "byteOffset": 128, "componentType": 5121, "count": 6, "type": "SCALAR" }
        ]);
        doc["bufferViews"] = json!([{ "buffer": 0, "byteLength": bytes.len() }]);
        doc["buffers"] = json!([{ "byteLength": bytes.len(), "uri": data_uri(&bytes) }]);
        doc["extensionsUsed"] = json!(["KHR_texture_transform", "KHR_materials_emissive_strength"]);
        doc["materials"] = json!([{
            "name": "painted",
            "pbrMetallicRoughness": {
                "baseColorFactor": [0.5, 0.5, 0.5, 1.0],
                "baseColorTexture": { "index": 0, "extensions": { "KHR_texture_transform": {
                    "offset": [0.5, 0.0], "rotation": 0.25, "scale": [2.0, 2.0], "texCoord": 1 } } },
                "metallicFactor": 0.25, "roughnessFactor": 0.75,
                "metallicRoughnessTexture": { "index": 1 }
            },
            "normalTexture": { "index": 0, "scale": 0.5,
                "extensions": { "KHR_texture_transform": { "scale": [3.0, 3.0] } } },
            "occlusionTexture": { "index": 1, "strength": 0.25 },
            "emissiveFactor": [1.0, 0.5, 0.0],
            "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": 4.0 } },
            "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true
        }, { "name": "unused image", "emissiveTexture": { "index": 2 } }]);
        doc["samplers"] =
            json!([{ "magFilter": 9728, "minFilter": 9729, "wrapS": 33071, "wrapT": 33648 }]);
        doc["textures"] = json!([{ "source": 0, "sampler": 0 }, { "source": 1 }, { "source": 0 }]);
        doc["images"] =
            json!([{ "uri": "color.png" }, { "uri": "orm.png" }, { "uri": "never-read.png" }]);
        let scene = load_doc(&dir, &doc).unwrap();

        // Image 0 is both colour and normal map: decoded once, as sRGB.
        assert_eq!(scene.images.len(), 2);
        let color = &scene.images[0];
        assert_eq!((color.width, color.height), (2, 1));
        assert_eq!(color.color_space, ColorSpace::Srgb);
        assert_eq!(&color.rgba8[4..], &[10, 20, 30, 255]);
        assert_eq!(color.name, "color.png");
        let orm = &scene.images[1];
        assert_eq!(orm.color_space, ColorSpace::Linear);
        assert_eq!(orm.rgba8, vec![255, 255, 255, 255]);

        let m = &scene.materials[0];
        assert_eq!(m.name, "painted");
        assert_eq!(m.base_color, Vec4::new(0.5, 0.5, 0.5, 1.0));
        assert_eq!((m.metallic, m.roughness), (0.25, 0.75));
        assert_eq!(m.emissive, Vec3::new(4.0, 2.0, 0.0));
        assert_eq!(m.alpha_mode, AlphaMode::Mask);
        assert_eq!(m.alpha_cutoff, 0.3);
        assert!(m.double_sided);
        assert_eq!((m.normal_scale, m.occlusion_strength), (0.5, 0.25));
        let base = m.base_color_texture.unwrap();
        assert_eq!(base.image, 0);
        assert_eq!(base.tex_coord, 1);
        assert_eq!(
            base.transform,
            UvTransform {
                offset: Vec2::new(0.5, 0.0),
                rotation_rad: 0.25,
                scale: Vec2::splat(2.0)
            }
        );
        assert_eq!(
            base.sampler,
            SamplerDesc {
                wrap_u: WrapMode::ClampToEdge,
                wrap_v: WrapMode::MirroredRepeat,
                mag_linear: false,
                min_linear: true,
                mipmaps: false,
            }
        );
        let normal = m.normal_texture.unwrap();
        assert_eq!(normal.image, 0);
        assert_eq!(normal.transform.scale, Vec2::splat(3.0));
        assert_eq!(m.metallic_roughness_texture.unwrap().image, 1);
        assert_eq!(m.occlusion_texture.unwrap().sampler, SamplerDesc::default());
        // The second material's image was never decoded (its file does not exist) but
        // materials still refer into `Scene::images`.
        assert_eq!(scene.materials[1].emissive_texture.unwrap().image, 0);

        let p = &scene.meshes[0].primitives[0];
        assert_eq!(p.triangle_count(), 2);
        for t in &p.tangents {
            assert!(t.truncate().distance(Vec3::X) < 1e-5, "{t}");
            assert_eq!(t.w, 1.0);
        }
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
        colored["attributes"]["COLOR_0"] = json!(0);
        doc["meshes"][0]["primitives"] =
            json!([prim, points.clone(), points, colored, { "attributes": {} }]);
        doc["animations"] = json!([
            { "channels": [], "samplers": [] },
            { "channels": [], "samplers": [] },
            { "channels": [], "samplers": [] }
        ]);
        let scene = load_doc(&dir, &doc).unwrap();
        assert_eq!(scene.meshes[0].primitives.len(), 2);
        assert_eq!(
            scene.ignored,
            vec![
                "3 animations: not supported, ignored".to_owned(),
                "1 primitive with vertex colours: not supported, ignored".to_owned(),
                "2 primitives of points or lines: not supported, ignored".to_owned(),
                "1 primitive without POSITION: nothing to draw, ignored".to_owned(),
            ]
        );
    }

    /// Every scene under shared/assets loads with triangles and the lights its README lists.
    #[test]
    fn shared_assets_load_with_their_documented_lights() {
        let assets = Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../../shared/assets"
        ));
        // (folder, directional, spot, point, cameras)
        let expected = [
            ("ShadowsDirectional", 1, 0, 0, 1),
            ("ShadowsSpot", 0, 1, 0, 1),
            ("LightsPunctualLamp", 0, 0, 5, 0),
            ("GlamVelvetSofa", 1, 0, 0, 0),
            ("IridescenceSuzanne", 1, 0, 0, 0),
            ("chiaro-bench", 1, 4, 60, 1),
        ];
        fn scene_files(dir: &Path, out: &mut Vec<PathBuf>) {
            for entry in std::fs::read_dir(dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    scene_files(&path, out);
                } else if path.extension().is_some_and(|e| e == "gltf" || e == "glb") {
                    out.push(path);
                }
            }
        }
        for (folder, directional, spot, point, cameras) in expected {
            let mut files = Vec::new();
            scene_files(&assets.join(folder), &mut files);
            assert!(!files.is_empty(), "no glTF under {folder}");
            for file in files {
                let scene = load_gltf(&file).unwrap_or_else(|e| panic!("{e}"));
                assert!(scene.triangle_count() > 0, "{folder}: no triangles");
                let count =
                    |f: fn(&LightKind) -> bool| scene.lights.iter().filter(|l| f(&l.kind)).count();
                assert_eq!(
                    count(|k| *k == LightKind::Directional),
                    directional,
                    "{folder}"
                );
                assert_eq!(
                    count(|k| matches!(k, LightKind::Spot { .. })),
                    spot,
                    "{folder}"
                );
                assert_eq!(count(|k| *k == LightKind::Point), point, "{folder}");
                assert_eq!(scene.cameras.len(), cameras, "{folder}");
                for light in &scene.lights {
                    assert!(
                        (light.direction.length() - 1.0).abs() < 1e-4,
                        "{folder}: {}",
                        light.name
                    );
                }
                for mesh in &scene.meshes {
                    for p in &mesh.primitives {
                        let n = p.positions.len();
                        assert!(p.normals.len() == n && p.tangents.len() == n);
                        assert!(p.uv0.len() == n && p.uv1.len() == n);
                        assert!(p.indices.iter().all(|&i| (i as usize) < n));
                        assert!(p.tangents.iter().all(|t| t.is_finite() && t.w.abs() == 1.0));
                    }
                }
                if folder == "ShadowsSpot" {
                    assert_eq!(scene.lights[0].range, Some(25.0));
                }
            }
        }
    }
}
