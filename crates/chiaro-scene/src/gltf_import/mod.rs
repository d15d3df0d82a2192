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
//!
//! The work is split by what flows through it: `document` turns the file's bytes into
//! checked JSON (with `glb` unpacking containers and `validate` vetting indices and
//! required extensions); the `Loader` here then reads buffers through `uri` and
//! `accessor`, and builds `meshes`, `materials`, `images`, the node placements of
//! `nodes` and the `lights_cameras` placed at them.

mod accessor;
mod animation;
mod animation_pointer;
mod document;
mod draco;
mod extras;
pub mod glb;
mod image_based_light;
mod images;
mod instancing;
mod ktx2_image;
mod layers;
mod lights_area;
mod lights_cameras;
mod materials;
mod meshes;
mod meshopt;
mod nodes;
mod normalize;
mod points_lines;
mod spec;
mod uri;
mod validate;
mod variants;

#[cfg(test)]
mod tests;

use crate::animation::deform::Deformation;
use crate::error::SceneError;
use crate::types::{GpuInstance, Material, Mesh, MeshInstance, Scene};
use document::Document;
use gltf::json;
use json::validation::Checked;
pub(crate) use lights_cameras::light_frame;
use nodes::Placement;
use serde_json::Value;
use std::borrow::Cow;
use std::cell::{OnceCell, RefCell};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
pub use uri::GivenFiles;

/// Extensions Chiaro reads. A file may require these and no others; KHR_mesh_quantization
/// needs nothing beyond the integer attribute formats the accessor reader handles anyway.
pub const SUPPORTED_EXTENSIONS: [&str; 25] = [
    "KHR_lights_punctual",
    lights_area::EXTENSION,
    image_based_light::EXTENSION,
    "KHR_materials_emissive_strength",
    "KHR_materials_unlit",
    "KHR_texture_transform",
    "KHR_mesh_quantization",
    "KHR_node_visibility",
    "EXT_meshopt_compression",
    draco::EXTENSION,
    instancing::EXTENSION,
    variants::EXTENSION,
    "EXT_texture_webp",
    ktx2_image::EXTENSION,
    animation_pointer::EXTENSION,
    layers::EXTENSIONS[0],
    layers::EXTENSIONS[1],
    layers::EXTENSIONS[2],
    layers::EXTENSIONS[3],
    layers::EXTENSIONS[4],
    layers::EXTENSIONS[5],
    layers::EXTENSIONS[6],
    layers::EXTENSIONS[7],
    layers::EXTENSIONS[8],
    layers::EXTENSIONS[9],
];

/// Loads a `.gltf` or `.glb` file and everything it references.
pub fn load_gltf(path: &Path) -> Result<Scene, SceneError> {
    let bytes =
        crate::files::read_regular_file(path).map_err(|source| SceneError::Io { path: path.to_path_buf(), source })?;
    load_gltf_bytes(path, &bytes)
}

/// Loads a glTF document from `bytes` as if read from `path` (which names it in errors,
/// and whose folder holds its external buffers and images).
pub fn load_gltf_bytes(path: &Path, bytes: &[u8]) -> Result<Scene, SceneError> {
    load_document(path, bytes, None)
}

/// Loads a glTF document from `bytes` as if read from `path`, its external buffers and
/// images from `files` (by the paths [`referenced_files`] names) rather than the disk.
pub fn load_gltf_given(path: &Path, bytes: &[u8], files: &GivenFiles) -> Result<Scene, SceneError> {
    load_document(path, bytes, Some(files))
}

/// The files beside the document that its buffers and images name (not `data:` URIs), as
/// the paths [`load_gltf_given`] looks them up by: what a caller without a filesystem
/// fetches first.
pub fn referenced_files(path: &Path, bytes: &[u8]) -> Result<Vec<PathBuf>, SceneError> {
    let document = Document::parse(path, bytes)?;
    let base_dir = path.parent().unwrap_or(Path::new("."));
    let buffers = document.root.buffers.iter().filter_map(|b| b.uri.as_deref());
    let images = document.root.images.iter().filter_map(|i| i.uri.as_deref());
    let mut files = Vec::new();
    // A URI that names no file (another scheme, a broken escape) is left to the loader,
    // which names it if something drawn reads it, as it does reading from disk.
    for uri in buffers.chain(images).filter(|u| !u.starts_with("data:")) {
        if let Ok(file) = uri::resolve(base_dir, uri)
            && !files.contains(&file)
        {
            files.push(file);
        }
    }
    Ok(files)
}

fn load_document(path: &Path, bytes: &[u8], given_files: Option<&GivenFiles>) -> Result<Scene, SceneError> {
    let document = Document::parse(path, bytes)?;
    let base_dir = path.parent().unwrap_or(Path::new("."));
    let mut loader = Loader {
        path,
        base_dir,
        given_files,
        raw: &document.raw,
        root: &document.root,
        bin: document.bin,
        buffers: vec![OnceCell::new(); document.root.buffers.len()],
        decoded_views: vec![OnceCell::new(); document.root.buffer_views.len()],
        decompressed: HashMap::new(),
        decompressed_primitives: 0,
        variant_names: Vec::new(),
        variant_mappings: Vec::new(),
        mesh_copies: Vec::new(),
        material_uv_sets: Vec::new(),
        skipped_lights: &document.skipped_lights,
        pointer_channels: &document.pointer_channels,
        ignored: document.notes.clone(),
        tally: Tally::default(),
        inputs: RefCell::new(vec![path.to_path_buf()]),
        deformations: HashMap::new(),
    };
    let mut scene = loader.load()?;
    scene.source = Some(path.to_path_buf());
    scene.inputs = loader.inputs.into_inner();
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

/// Counts of what the file has and Chiaro ignores, reported once per kind.
#[derive(Default)]
struct Tally {
    without_positions: usize,
    vertex_colors: usize,
    extra_uv_sets: usize,
}

struct Loader<'a> {
    path: &'a Path,
    base_dir: &'a Path,
    /// The external files, where the caller gave them rather than the disk.
    given_files: Option<&'a GivenFiles>,
    raw: &'a Value,
    root: &'a json::Root,
    /// A GLB's BIN chunk.
    bin: Option<&'a [u8]>,
    /// Buffers are read when something drawn needs them, so a broken buffer nothing uses
    /// does not refuse the file.
    buffers: Vec<OnceCell<Cow<'a, [u8]>>>,
    /// EXT_meshopt_compression views, decoded when first read.
    decoded_views: Vec<OnceCell<Vec<u8>>>,
    /// Accessors decoded from KHR_draco_mesh_compression streams, by accessor index.
    decompressed: HashMap<usize, draco::Decompressed>,
    /// Primitives decoded from Draco streams.
    decompressed_primitives: usize,
    /// KHR_materials_variants: the variants' names, and the primitives they change.
    variant_names: Vec<String>,
    variant_mappings: Vec<crate::variants::VariantMapping>,
    /// Per material, the texture coordinate sets its primitives load into the two UV slots.
    material_uv_sets: Vec<[u32; 2]>,
    /// Meshes the animation copied for an instance to pose: (original, copy).
    mesh_copies: Vec<(usize, usize)>,
    /// Per KHR_lights_punctual light, whether its type is unknown and it is skipped.
    skipped_lights: &'a [bool],
    /// KHR_animation_pointer channels, read by `animation_pointer`.
    pointer_channels: &'a [normalize::PointerChannel],
    ignored: Vec<String>,
    tally: Tally,
    /// Files read: the document and its external buffers and images.
    inputs: RefCell<Vec<PathBuf>>,
    /// Per converted mesh with skin weights or morph targets, what moves each primitive.
    deformations: HashMap<usize, Vec<Option<Deformation>>>,
}

impl<'a> Loader<'a> {
    fn invalid(&self, message: impl Into<String>) -> SceneError {
        SceneError::Invalid { path: self.path.to_path_buf(), message: message.into() }
    }

    fn load(&mut self) -> Result<Scene, SceneError> {
        self.note_unsupported_extensions();
        let placements = self.walk_scene()?;
        let moving = self.animated_nodes();
        self.variant_names = self.variant_names()?;
        let mut materials =
            (0..self.root.materials.len()).map(|index| self.material(index)).collect::<Result<Vec<_>, _>>()?;
        self.material_uv_sets =
            materials.iter_mut().enumerate().map(|(index, m)| self.assign_uv_slots(index, m)).collect();
        let mut meshes = self.drawn_meshes(&placements, &materials)?;
        points_lines::unlit_materials_for_bare_points_and_lines(&mut meshes, &mut materials);

        let gpu_instances = self.gpu_instances(&placements)?;
        let mut instances = Vec::new();
        let mut lights = Vec::new();
        let mut cameras = Vec::new();
        for placement in &placements {
            // KHR_node_visibility: a hidden node neither draws nor lights; cameras stay.
            if placement.visible {
                if let Some(instance) = self.instance(placement, &moving)? {
                    match gpu_instances.get(&placement.node) {
                        Some(copies) => instances.extend(instance.gpu_instances(copies)),
                        None => instances.push(instance),
                    }
                }
                if let Some(light) = self.light(placement)? {
                    lights.push(light);
                }
                if let Some(light) = self.area_light(placement)? {
                    lights.push(light);
                }
            }
            if let Some(camera) = self.camera(placement)? {
                cameras.push(camera);
            }
        }

        let mut animation = self.animation(&placements, &mut instances, &mut meshes)?;
        if let Some(animation) = animation.as_mut() {
            animation.light_sources = self.light_sources(&lights);
        }
        let variants = self.material_variants();
        let image_uses = images::image_uses(&materials, &meshes, variants.variant_materials());
        let images = self.decode_images(&image_uses, &mut materials, &mut lights)?;
        let environment = self.scene_environment(self.scene_index())?;
        self.note_tally();
        self.note_unknown_accessor_types();
        let mut scene = Scene {
            source: None,
            meshes,
            instances,
            materials,
            images,
            lights,
            cameras,
            ignored: std::mem::take(&mut self.ignored),
            extensions_read: self.extensions_read(&gpu_instances),
            inputs: Vec::new(),
            baked: None,
            nodes: self.node_table(&placements),
            animation: animation.map(Box::new),
            environment,
            variants,
        };
        animation_pointer::fill_property_rests(&mut scene);
        // Skinned and morphed meshes at rest: joints at their rest transforms, the rest
        // weights applied. The rest time is always a valid pose.
        scene.pose(None).expect("the rest pose needs no time");
        Ok(scene)
    }

    /// Every mesh a visible node of the scene places, converted; the others stay empty
    /// (keeping the file's indices) and are not read.
    fn drawn_meshes(&mut self, placements: &[Placement], materials: &[Material]) -> Result<Vec<Mesh>, SceneError> {
        let mut drawn = vec![false; self.root.meshes.len()];
        for placement in placements.iter().filter(|p| p.visible) {
            if let Some(mesh) = self.root.nodes[placement.node].mesh {
                drawn[mesh.value()] = true;
            }
        }
        let unread = drawn.iter().filter(|d| !**d).count();
        if unread > 0 {
            let what = if unread == 1 { "mesh" } else { "meshes" };
            self.ignored.push(format!("{unread} {what}: no visible node of the scene places it, not read"));
        }
        (0..self.root.meshes.len())
            .map(|index| match drawn[index] {
                true => self.mesh(index, materials),
                false => Ok(Mesh::of_triangles(self.mesh_name(index), Vec::new())),
            })
            .collect()
    }

    /// Per visible mesh node with EXT_mesh_gpu_instancing, its copies, numbered for the
    /// instance AOV from the file's node count on, node by node in index order.
    fn gpu_instances(&self, placements: &[Placement]) -> Result<HashMap<usize, Vec<GpuInstance>>, SceneError> {
        let mut nodes: Vec<usize> = placements
            .iter()
            .filter(|p| p.visible && self.root.nodes[p.node].mesh.is_some() && self.is_instanced(p.node))
            .map(|p| p.node)
            .collect();
        nodes.sort_unstable();
        let mut next_id = self.root.nodes.len();
        let mut copies = HashMap::new();
        for node in nodes {
            let transforms = self.instance_transforms(node)?.unwrap_or_default();
            let first = next_id;
            next_id += transforms.len();
            let id = |k: usize| u32::try_from(first + k).map_err(|_| self.invalid("more than 2^32 instances"));
            let node_copies = transforms
                .into_iter()
                .enumerate()
                .map(|(k, node_from_instance)| Ok(GpuInstance { id: id(k)?, node_from_instance }))
                .collect::<Result<Vec<_>, SceneError>>()?;
            copies.insert(node, node_copies);
        }
        Ok(copies)
    }

    /// The file's variants and mappings, each mapping repeated for the copies the
    /// animation made of its mesh.
    fn material_variants(&mut self) -> crate::variants::MaterialVariants {
        let mut mappings = std::mem::take(&mut self.variant_mappings);
        for &(original, copy) in &self.mesh_copies {
            let copies: Vec<_> = mappings
                .iter()
                .filter(|m| m.mesh == original)
                .map(|m| crate::variants::VariantMapping { mesh: copy, ..m.clone() })
                .collect();
            mappings.extend(copies);
        }
        crate::variants::MaterialVariants { names: self.variant_names.clone(), mappings, selected: None }
    }

    /// One line per extension read that changed what the file holds: compressed
    /// primitives and views, each instanced node with its copies' ids, and the material
    /// variants.
    fn extensions_read(&self, gpu_instances: &HashMap<usize, Vec<GpuInstance>>) -> Vec<String> {
        let mut lines = Vec::new();
        let draco = self.decompressed_primitives;
        if draco > 0 {
            lines.push(format!("{}: {draco} primitives decoded", draco::EXTENSION));
        }
        let meshopt = self.decoded_views.iter().filter(|v| v.get().is_some()).count();
        if meshopt > 0 {
            lines.push(format!("EXT_meshopt_compression: {meshopt} buffer views decoded"));
        }
        if !self.variant_names.is_empty() {
            let names: Vec<String> = self.variant_names.iter().map(|n| format!("'{n}'")).collect();
            lines.push(format!("{}: {} variants: {}", variants::EXTENSION, names.len(), names.join(", ")));
        }
        let mut nodes: Vec<(&usize, &Vec<GpuInstance>)> = gpu_instances.iter().collect();
        nodes.sort_by_key(|(node, _)| **node);
        for (node, copies) in nodes {
            let name = self.root.nodes[*node].name.as_deref().unwrap_or_default();
            let ids = match (copies.first(), copies.last()) {
                (Some(first), Some(last)) => format!("instance ids {}..={}", first.id, last.id),
                _ => "no copies".into(),
            };
            lines.push(format!("{}: node {node} '{name}': {} copies, {ids}", instancing::EXTENSION, copies.len()));
        }
        lines
    }

    fn instance(&self, placement: &Placement, moving: &[bool]) -> Result<Option<MeshInstance>, SceneError> {
        let node = &self.root.nodes[placement.node];
        let Some(mesh) = node.mesh else { return Ok(None) };
        let name = node
            .name
            .clone()
            .or_else(|| self.root.meshes[mesh.value()].name.clone())
            .unwrap_or_else(|| format!("node {}", placement.node));
        let (cast_shadows, receive_shadows) =
            extras::node_shadows(node).map_err(|e| self.invalid(format!("node {} ({name}): {e}", placement.node)))?;
        let is_static = extras::node_static(node)
            .map_err(|e| self.invalid(format!("node {} ({name}): {e}", placement.node)))?
            .unwrap_or(!moving[placement.node]);
        let label =
            extras::node_label(node).map_err(|e| self.invalid(format!("node {} ({name}): {e}", placement.node)))?;
        Ok(Some(MeshInstance {
            mesh: mesh.value(),
            node: placement.node,
            name,
            world_from_local: placement.world_from_local,
            cast_shadows,
            receive_shadows,
            is_static,
            lightmap: None,
            gpu_instance: None,
            label,
        }))
    }

    fn note_unsupported_extensions(&mut self) {
        let used = self.raw.get("extensionsUsed").and_then(Value::as_array);
        for name in used.into_iter().flatten().filter_map(Value::as_str) {
            if !SUPPORTED_EXTENSIONS.contains(&name) {
                self.ignored.push(format!("extension {name}: not supported, ignored"));
            }
        }
    }

    /// Accessors whose `type` or `componentType` glTF does not define (the validator's
    /// VALUE_NOT_IN_LIST, a warning): nothing drawn read them, or the load would have
    /// failed naming them, so they are read past with a note.
    fn note_unknown_accessor_types(&mut self) {
        for (a, accessor) in self.root.accessors.iter().enumerate() {
            for (key, valid) in [
                ("type", matches!(accessor.type_, Checked::Valid(_))),
                ("componentType", matches!(accessor.component_type, Checked::Valid(_))),
            ] {
                if !valid {
                    let value = self.raw.pointer(&format!("/accessors/{a}/{key}")).map(Value::to_string);
                    let value = value.unwrap_or_default();
                    self.ignored.push(format!(
                        "accessors[{a}].{key}: {value} is not a glTF accessor {key}; nothing drawn reads it"
                    ));
                }
            }
        }
    }

    fn note_tally(&mut self) {
        let t = &self.tally;
        let notes = [
            (t.vertex_colors, "primitive with COLOR_1 or above", "only COLOR_0 is read"),
            (t.without_positions, "primitive without POSITION", "nothing to draw, ignored"),
            (t.extra_uv_sets, "primitive with TEXCOORD_2 or above that its material does not read", "not read"),
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

/// `kind[index] (detail)`: the object's JSON path, with its file name or name as in
/// [`object_label`].
fn json_label(kind: &str, index: usize, uri: Option<&str>, name: Option<&str>) -> String {
    let detail = uri.filter(|u| !u.starts_with("data:")).or(name);
    match detail {
        Some(detail) => format!("{kind}[{index}] ({detail})"),
        None => format!("{kind}[{index}]"),
    }
}

fn plural(what: &str) -> String {
    // "primitive with vertex colours" -> "primitives with vertex colours".
    match what.split_once(' ') {
        Some((head, tail)) => format!("{head}s {tail}"),
        None => format!("{what}s"),
    }
}
