//! A glTF mesh index in, a [`Mesh`] out: each triangle primitive's attributes read through
//! the accessor reader, strips and fans turned into lists, missing normals generated flat
//! (unwelding the vertices) and missing tangents generated with MikkTSpace when the
//! primitive's material has a normal map. Points and lines go to `points_lines`;
//! primitives without positions are skipped and counted in the loader's tally.

use super::Loader;
use super::points_lines::points_or_lines_topology;
use crate::animation::deform::Deformation;
use crate::error::SceneError;
use crate::types::{Material, Mesh, Primitive};
use crate::vertex_gen;
use chiaro_math::Aabb;
use glam::{Vec2, Vec3, Vec4};
use gltf::json;
use json::validation::Checked;

impl Loader<'_> {
    pub(super) fn mesh(&mut self, index: usize, materials: &[Material]) -> Result<Mesh, SceneError> {
        let mesh = &self.root.meshes[index];
        let name = mesh.name.as_deref().map(|n| format!(" ({n})")).unwrap_or_default();
        let mut primitives = Vec::new();
        let mut points_and_lines = Vec::new();
        let mut deformations = Vec::new();
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let label = format!("meshes[{index}].primitives[{p}]{name}");
            // Draco streams hold triangles: a compressed point or line primitive is refused
            // here, naming it, rather than read from accessors without data.
            self.decode_draco(index, p, &label)?;
            if let Some(topology) = points_or_lines_topology(primitive.mode) {
                points_and_lines.extend(self.points_or_lines(primitive, topology, &label)?);
                continue;
            }
            if let Some((primitive, deformation)) = self.primitive(primitive, &label, materials)? {
                if let Some(mapping) = self.variant_mapping((index, p), primitives.len(), &label)? {
                    self.variant_mappings.push(mapping);
                }
                primitives.push(primitive);
                deformations.push(deformation);
            }
        }
        if deformations.iter().any(Option::is_some) {
            self.deformations.insert(index, deformations);
        }
        Ok(Mesh { name: self.mesh_name(index), primitives, points_and_lines })
    }

    pub(super) fn mesh_name(&self, index: usize) -> String {
        self.root.meshes[index].name.clone().unwrap_or_else(|| format!("mesh {index}"))
    }

    fn primitive(
        &mut self,
        primitive: &json::mesh::Primitive,
        label: &str,
        materials: &[Material],
    ) -> Result<Option<(Primitive, Option<Deformation>)>, SceneError> {
        use json::mesh::{Mode, Semantic};

        let attribute = |semantic: Semantic| primitive.attributes.get(&Checked::Valid(semantic)).map(|a| a.value());
        let Some(position_accessor) = attribute(Semantic::Positions) else {
            self.tally.without_positions += 1;
            return Ok(None);
        };
        let mode = match primitive.mode {
            Checked::Valid(mode @ (Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan)) => mode,
            // Points and lines are read by `points_or_lines`; an invalid mode fails the
            // document's validation before this.
            _ => return Ok(None),
        };
        self.count_ignored_attributes(primitive);
        self.check_unread_accessors(primitive, label, false)?;

        let mut positions = self.finite_positions(position_accessor, label)?;
        let vertex_count = positions.len();
        let (mut indices, left_over) = self.triangle_indices(primitive, mode, vertex_count, label)?;
        if left_over > 0 {
            self.note_left_over_vertices(primitive, mode, label, (indices.len(), vertex_count, left_over));
        }
        if indices.is_empty() {
            return Ok(None);
        }
        let mut skin = self.skin_weights(primitive, label, vertex_count)?;
        let mut targets = self.morph_targets(primitive, label, vertex_count)?;
        // The sets the material reads, in the vertex's two UV slots.
        let material = primitive.material.map(|m| m.value());
        let [set0, set1] = material.and_then(|m| self.material_uv_sets.get(m)).copied().unwrap_or([0, 1]);
        let mut uv0 = self.uv_set(primitive, set0, label, vertex_count)?;
        let mut uv1 = self.uv_set(primitive, set1, label, vertex_count)?;
        let mut colors = self.vertex_colors(primitive, label, vertex_count)?;
        let (mut normals, mut tangents) = self.file_normals_and_tangents(primitive, label, vertex_count)?;

        let mut flat_normals = false;
        let normals = match normals.take() {
            Some(normals) => normals,
            None => {
                positions = vertex_gen::unweld(&positions, &indices);
                uv0 = vertex_gen::unweld(&uv0, &indices);
                uv1 = vertex_gen::unweld(&uv1, &indices);
                if !colors.is_empty() {
                    colors = vertex_gen::unweld(&colors, &indices);
                }
                if let Some(skin) = &mut skin {
                    skin.unweld(&indices);
                }
                for target in &mut targets {
                    target.unweld(&indices);
                }
                indices = (0..positions.len() as u32).collect();
                flat_normals = true;
                vertex_gen::flat_normals(&positions)
            }
        };

        // The UV set tangents follow: the normal map's, else the clearcoat's normal map's or
        // the anisotropy texture's, whose directions live in the same frame.
        let normal_map_uv_set = material.and_then(|m| materials.get(m)).and_then(|m| {
            m.normal_texture
                .or(m.layers.textures[crate::layers::LayerTexture::ClearcoatNormal.index()])
                .or(m.layers.textures[crate::layers::LayerTexture::Anisotropy.index()])
                .map(|t| t.tex_coord)
        });
        let tangents = tangents.take().unwrap_or_else(|| {
            let uvs = if normal_map_uv_set == Some(1) { &uv1 } else { &uv0 };
            generated_tangents(&positions, &normals, normal_map_uv_set.map(|_| uvs.as_slice()), &indices)
        });

        let bounds = Aabb::from_points(positions.iter().copied());
        let deformation = (skin.is_some() || !targets.is_empty()).then(|| Deformation {
            positions: positions.clone(),
            normals: normals.clone(),
            tangents: tangents.clone(),
            targets,
            skin,
            flat_normals,
        });
        let primitive = Primitive {
            positions,
            normals,
            tangents,
            uv0,
            uv1,
            colors,
            indices,
            material,
            bounds,
            lightmap_uv: Vec::new(),
        };
        Ok(Some((primitive, deformation)))
    }

    pub(super) fn finite_positions(&self, accessor: usize, label: &str) -> Result<Vec<Vec3>, SceneError> {
        let positions: Vec<Vec3> = self
            .read_floats::<3>(accessor, &format!("POSITION of {label}"))?
            .into_iter()
            .map(Vec3::from_array)
            .collect();
        match positions.iter().position(|p| !p.is_finite()) {
            Some(v) => Err(self.invalid(format!("{label}: POSITION {v} is not finite"))),
            None => Ok(positions),
        }
    }

    /// Notes the indices (or vertices) past the last whole triangle; `counts` is the drawn
    /// index count, the vertex count and the left-over count.
    fn note_left_over_vertices(
        &mut self,
        primitive: &json::mesh::Primitive,
        mode: json::mesh::Mode,
        label: &str,
        (drawn_indices, vertex_count, left_over): (usize, usize, usize),
    ) {
        let (count, what) = match primitive.indices {
            Some(_) => (drawn_indices + left_over, "indices"),
            None => (vertex_count, "vertices"),
        };
        let drawn = drawn_indices / 3;
        self.ignored.push(format!(
            "{label}: {count} {what} do not make whole {}; the last {left_over} not drawn ({drawn} triangles drawn)",
            mode_name(mode)
        ));
    }

    /// COLOR_0 as linear RGBA (alpha 1 where it is RGB), or nothing where the primitive has
    /// none. Its type and components were checked with the file's (`spec.rs`: float, or
    /// normalised unsigned byte or short; VEC3 or VEC4); floats outside 0..1 are clamped
    /// into it (non-finite ones read as white), so that no colour brightens a material or
    /// makes a NaN.
    pub(super) fn vertex_colors(
        &self,
        primitive: &json::mesh::Primitive,
        label: &str,
        vertex_count: usize,
    ) -> Result<Vec<Vec4>, SceneError> {
        let Some(index) = primitive.attributes.get(&Checked::Valid(json::mesh::Semantic::Colors(0))).map(|a| a.value())
        else {
            return Ok(Vec::new());
        };
        let colors: Vec<Vec4> = match self.root.accessors[index].type_ {
            Checked::Valid(json::accessor::Type::Vec3) => self
                .vertex_attribute::<3>(index, "COLOR_0", label, vertex_count)?
                .into_iter()
                .map(|c| Vec3::from_array(c).extend(1.0))
                .collect(),
            _ => self
                .vertex_attribute::<4>(index, "COLOR_0", label, vertex_count)?
                .into_iter()
                .map(Vec4::from_array)
                .collect(),
        };
        Ok(colors.into_iter().map(|c| if c.is_finite() { c.clamp(Vec4::ZERO, Vec4::ONE) } else { Vec4::ONE }).collect())
    }

    /// The file's own normals (normalised) and tangents (repaired), where it has them.
    /// Tangents are only trusted alongside the file's own normals (glTF 2.0 §3.7.2.1).
    #[allow(clippy::type_complexity)]
    pub(super) fn file_normals_and_tangents(
        &self,
        primitive: &json::mesh::Primitive,
        label: &str,
        vertex_count: usize,
    ) -> Result<(Option<Vec<Vec3>>, Option<Vec<Vec4>>), SceneError> {
        use json::mesh::Semantic;
        let attribute = |semantic: Semantic| primitive.attributes.get(&Checked::Valid(semantic)).map(|a| a.value());
        let normals: Option<Vec<Vec3>> = match attribute(Semantic::Normals) {
            Some(accessor) => Some(
                self.vertex_attribute::<3>(accessor, "NORMAL", label, vertex_count)?
                    .into_iter()
                    .map(|n| Vec3::from_array(n).normalize_or(Vec3::Z))
                    .collect(),
            ),
            None => None,
        };
        let tangents = match (attribute(Semantic::Tangents), &normals) {
            (Some(accessor), Some(normals)) => {
                let tangents = self.vertex_attribute::<4>(accessor, "TANGENT", label, vertex_count)?;
                let mut tangents: Vec<Vec4> = tangents.into_iter().map(Vec4::from_array).collect();
                vertex_gen::repair_tangents(&mut tangents, normals);
                Some(tangents)
            }
            _ => None,
        };
        Ok((normals, tangents))
    }
}

impl Loader<'_> {
    /// Counts the attributes Chiaro reads past: colour sets past the first, UV sets past
    /// the second that the primitive's material does not read.
    pub(super) fn count_ignored_attributes(&mut self, primitive: &json::mesh::Primitive) {
        use json::mesh::Semantic;
        let read_sets =
            primitive.material.and_then(|m| self.material_uv_sets.get(m.value())).copied().unwrap_or([0, 1]);
        let has = |wanted: fn(&Semantic) -> bool| {
            primitive.attributes.keys().any(|s| match s {
                Checked::Valid(s) => wanted(s),
                Checked::Invalid => false,
            })
        };
        self.tally.vertex_colors += usize::from(has(|s| matches!(s, Semantic::Colors(1..))));
        let unread_uv_set = primitive
            .attributes
            .keys()
            .any(|s| matches!(s, Checked::Valid(Semantic::TexCoords(set)) if *set >= 2 && !read_sets.contains(set)));
        self.tally.extra_uv_sets += usize::from(unread_uv_set);
    }

    /// Vertex attribute `name` of the primitive `label` from `accessor`: exactly one value
    /// per vertex.
    pub(super) fn vertex_attribute<const N: usize>(
        &self,
        accessor: usize,
        name: &str,
        label: &str,
        vertex_count: usize,
    ) -> Result<Vec<[f32; N]>, SceneError> {
        let values = self.read_floats::<N>(accessor, &format!("{name} of {label}"))?;
        if values.len() != vertex_count {
            let count = values.len();
            return Err(self.invalid(format!("{label}: {name} has {count} values but POSITION has {vertex_count}")));
        }
        Ok(values)
    }

    /// The primitive's triangles as a list: its indices (checked by `checked_indices`) or,
    /// without any, the vertices in order; and how many of those made no whole triangle.
    fn triangle_indices(
        &self,
        primitive: &json::mesh::Primitive,
        mode: json::mesh::Mode,
        vertex_count: usize,
        label: &str,
    ) -> Result<(Vec<u32>, usize), SceneError> {
        let indices = match self.checked_indices(primitive, vertex_count, label)? {
            Some(indices) => indices,
            None => (0..vertex_count as u32).collect(),
        };
        Ok(triangle_list(mode, indices))
    }

    /// The primitive's indices, if it has any, each checked to name one of its
    /// `vertex_count` vertices and not to be the primitive restart value (glTF 2.0
    /// §3.7.2.1; the validator's ACCESSOR_INDEX_OOB and ACCESSOR_INDEX_PRIMITIVE_RESTART):
    /// either would draw what the file does not hold.
    pub(super) fn checked_indices(
        &self,
        primitive: &json::mesh::Primitive,
        vertex_count: usize,
        label: &str,
    ) -> Result<Option<Vec<u32>>, SceneError> {
        let Some(accessor) = primitive.indices else { return Ok(None) };
        let (indices, restart) = self.read_indices(accessor.value(), &format!("indices of {label}"))?;
        // The label's JSON path, without the mesh's name.
        let primitive_path = label.split_once(" (").map_or(label, |(path, _)| path);
        let path = format!("{primitive_path}.indices (accessors[{}])", accessor.value());
        if let Some(at) = indices.iter().position(|&i| i == restart) {
            return Err(self.invalid(format!(
                "{path}: element {at} is {restart}, the primitive restart value, which glTF forbids in indices"
            )));
        }
        if let Some(at) = indices.iter().position(|&i| i as usize >= vertex_count) {
            return Err(self.invalid(format!(
                "{path}: element {at} is {}, but POSITION has only {vertex_count} vertices",
                indices[at]
            )));
        }
        Ok(Some(indices))
    }

    /// Checks the accessors of a drawn primitive that Chiaro does not read (vertex
    /// colours, UV sets past the second, JOINTS without WEIGHTS, custom attributes; with
    /// `all`, every one) as those it reads are checked: inside their buffer views, inside
    /// their buffers.
    pub(super) fn check_unread_accessors(
        &self,
        primitive: &json::mesh::Primitive,
        label: &str,
        all: bool,
    ) -> Result<(), SceneError> {
        use json::mesh::Semantic;
        let has = |semantic: Semantic| primitive.attributes.contains_key(&Checked::Valid(semantic));
        for (semantic, accessor) in &primitive.attributes {
            let read = match semantic {
                Checked::Valid(Semantic::Positions | Semantic::Normals | Semantic::Tangents) => true,
                Checked::Valid(Semantic::TexCoords(set)) => *set < 2,
                Checked::Valid(Semantic::Colors(set)) => *set == 0,
                Checked::Valid(Semantic::Joints(set)) => has(Semantic::Weights(*set)),
                Checked::Valid(Semantic::Weights(set)) => has(Semantic::Joints(*set)),
                _ => false,
            };
            if all || !read {
                let name = match semantic {
                    Checked::Valid(s) => s.to_string(),
                    Checked::Invalid => "an attribute".into(),
                };
                self.check_accessor(accessor.value(), &format!("{name} of {label}"))?;
            }
        }
        Ok(())
    }
}

/// Tangents for a primitive whose file gives none: MikkTSpace's over the normal map's UV
/// set where there is a normal map (`normal_map_uvs`), any perpendicular ones otherwise
/// or where MikkTSpace fails.
fn generated_tangents(
    positions: &[Vec3],
    normals: &[Vec3],
    normal_map_uvs: Option<&[Vec2]>,
    indices: &[u32],
) -> Vec<Vec4> {
    normal_map_uvs
        .and_then(|uvs| vertex_gen::mikktspace_tangents(positions, normals, uvs, indices))
        .unwrap_or_else(|| vertex_gen::perpendicular_tangents(normals))
}

fn mode_name(mode: json::mesh::Mode) -> &'static str {
    use json::mesh::Mode;
    match mode {
        Mode::Points => "POINTS",
        Mode::Lines => "LINES",
        Mode::LineLoop => "LINE_LOOP",
        Mode::LineStrip => "LINE_STRIP",
        Mode::Triangles => "TRIANGLES",
        Mode::TriangleStrip => "TRIANGLE_STRIP",
        Mode::TriangleFan => "TRIANGLE_FAN",
    }
}

/// Strips and fans become lists with the winding glTF 2.0 §3.7.2.1 gives them: strip
/// triangle `i` is `(i, i+1, i+2)` with odd ones flipped, fan triangle `i` is
/// `(i+1, i+2, 0)`. A list whose count is not a multiple of 3 (the validator warns:
/// MESH_PRIMITIVE_INCOMPATIBLE_MODE) draws its whole triangles, as WebGL and Vulkan
/// do, and a strip or fan of fewer than 3 draws nothing; the second value counts the
/// indices left over.
fn triangle_list(mode: json::mesh::Mode, mut indices: Vec<u32>) -> (Vec<u32>, usize) {
    use json::mesh::Mode;
    let n = indices.len();
    if mode == Mode::Triangles {
        indices.truncate(n - n % 3);
        return (indices, n % 3);
    }
    let list = match mode {
        Mode::TriangleStrip if n >= 3 => (0..n - 2)
            .flat_map(|i| {
                if i % 2 == 0 {
                    [indices[i], indices[i + 1], indices[i + 2]]
                } else {
                    [indices[i], indices[i + 2], indices[i + 1]]
                }
            })
            .collect(),
        Mode::TriangleFan if n >= 3 => (0..n - 2).flat_map(|i| [indices[i + 1], indices[i + 2], indices[0]]).collect(),
        _ => Vec::new(),
    };
    let left_over = if n < 3 { n } else { 0 };
    (list, left_over)
}
