//! glTF POINTS, LINES, LINE_LOOP and LINE_STRIP primitives in, [`PointsOrLines`] out:
//! loops and strips become segment lists, the attributes read as a triangle primitive's
//! are (positions, normals, the material's UV sets, COLOR_0). A primitive without normals
//! has no surface to light, so after the meshes load its material becomes an unlit copy
//! of the file's (base colour times vertex colour, as KHR_materials_unlit shows it).

use super::Loader;
use crate::error::SceneError;
use crate::types::{Material, Mesh, PointsOrLines, Primitive, Topology};
use crate::vertex_gen;
use chiaro_math::Aabb;
use glam::Vec2;
use gltf::json;
use json::mesh::Mode;
use json::validation::Checked;
use std::collections::HashMap;

/// The topology a point or line mode draws with; `None` for the triangle modes.
pub(super) fn points_or_lines_topology(mode: Checked<Mode>) -> Option<Topology> {
    match mode {
        Checked::Valid(Mode::Points) => Some(Topology::Points),
        Checked::Valid(Mode::Lines | Mode::LineLoop | Mode::LineStrip) => Some(Topology::Lines),
        _ => None,
    }
}

/// The mode's elements as a list of points or of segments (glTF 2.0 §3.7.2.1: a strip
/// joins each vertex to the next, a loop the last back to the first too), and how many
/// indices were left over (an odd count of LINES, a strip or loop of one vertex).
pub(super) fn element_list(mode: Mode, indices: Vec<u32>) -> (Vec<u32>, usize) {
    let n = indices.len();
    match mode {
        Mode::Lines => {
            let mut list = indices;
            list.truncate(n - n % 2);
            (list, n % 2)
        }
        Mode::LineStrip | Mode::LineLoop if n >= 2 => {
            let mut list: Vec<u32> = indices.windows(2).flat_map(|w| [w[0], w[1]]).collect();
            if mode == Mode::LineLoop {
                list.extend([indices[n - 1], indices[0]]);
            }
            (list, 0)
        }
        Mode::LineStrip | Mode::LineLoop => (Vec::new(), n),
        _ => (indices, 0),
    }
}

impl Loader<'_> {
    /// A point or line primitive, read and checked as a triangle one is; `None` where it
    /// has no POSITION or nothing is left to draw.
    pub(super) fn points_or_lines(
        &mut self,
        primitive: &json::mesh::Primitive,
        topology: Topology,
        label: &str,
    ) -> Result<Option<PointsOrLines>, SceneError> {
        use json::mesh::Semantic;
        let Checked::Valid(mode) = primitive.mode else { return Ok(None) };
        let attribute = |semantic: Semantic| primitive.attributes.get(&Checked::Valid(semantic)).map(|a| a.value());
        let Some(position_accessor) = attribute(Semantic::Positions) else {
            self.tally.without_positions += 1;
            return Ok(None);
        };
        self.count_ignored_attributes(primitive);
        // Every accessor checked, the skin's too, which points and lines do not read.
        self.check_unread_accessors(primitive, label, true)?;
        let positions = self.finite_positions(position_accessor, label)?;
        let vertex_count = positions.len();
        let indices =
            self.checked_indices(primitive, vertex_count, label)?.unwrap_or_else(|| (0..vertex_count as u32).collect());
        let (indices, left_over) = element_list(mode, indices);
        if left_over > 0 {
            self.ignored.push(format!(
                "{label}: {left_over} of its {} indices make no whole {} segment, not drawn",
                indices.len() + left_over,
                mode_name(mode)
            ));
        }
        if indices.is_empty() {
            return Ok(None);
        }
        let material = primitive.material.map(|m| m.value());
        let [set0, set1] = material.and_then(|m| self.material_uv_sets.get(m)).copied().unwrap_or([0, 1]);
        let uv0 = self.uv_set(primitive, set0, label, vertex_count)?;
        let uv1 = self.uv_set(primitive, set1, label, vertex_count)?;
        let colors = self.vertex_colors(primitive, label, vertex_count)?;
        let (normals, tangents) = self.file_normals_and_tangents(primitive, label, vertex_count)?;
        let normals = normals.unwrap_or_default();
        let tangents = tangents.unwrap_or_else(|| vertex_gen::perpendicular_tangents(&normals));
        Ok(Some(PointsOrLines {
            topology,
            primitive: Primitive {
                bounds: Aabb::from_points(positions.iter().copied()),
                positions,
                normals,
                tangents,
                uv0,
                uv1,
                colors,
                indices,
                material,
                lightmap_uv: Vec::new(),
            },
        }))
    }

    /// TEXCOORD_`set` of a primitive, non-finite pairs read as zero; zeros where it has
    /// none.
    pub(super) fn uv_set(
        &self,
        primitive: &json::mesh::Primitive,
        set: u32,
        label: &str,
        vertex_count: usize,
    ) -> Result<Vec<Vec2>, SceneError> {
        let semantic = Checked::Valid(json::mesh::Semantic::TexCoords(set));
        let Some(accessor) = primitive.attributes.get(&semantic).map(|a| a.value()) else {
            return Ok(vec![Vec2::ZERO; vertex_count]);
        };
        let uvs = self.vertex_attribute::<2>(accessor, &format!("TEXCOORD_{set}"), label, vertex_count)?;
        Ok(uvs.into_iter().map(Vec2::from_array).map(|uv| if uv.is_finite() { uv } else { Vec2::ZERO }).collect())
    }
}

fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::LineLoop => "LINE_LOOP",
        Mode::LineStrip => "LINE_STRIP",
        _ => "LINES",
    }
}

/// Points and lines without normals get an unlit copy of their material (one copy per
/// material, the glTF default material's too), appended to `materials`.
pub(super) fn unlit_materials_for_bare_points_and_lines(meshes: &mut [Mesh], materials: &mut Vec<Material>) {
    let mut copies: HashMap<Option<usize>, usize> = HashMap::new();
    for part in meshes.iter_mut().flat_map(|m| &mut m.points_and_lines) {
        let p = &mut part.primitive;
        if !p.normals.is_empty() {
            continue;
        }
        let original = p.material.filter(|&m| m < materials.len());
        let copy = *copies.entry(original).or_insert_with(|| {
            let base = original.map(|m| materials[m].clone()).unwrap_or_default();
            let name = if base.name.is_empty() { "default".to_string() } else { base.name.clone() };
            materials.push(Material {
                name: format!("{name} (unlit: points or lines without normals)"),
                unlit: true,
                ..base
            });
            materials.len() - 1
        });
        p.material = Some(copy);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_loops_become_segment_lists_and_odd_lines_leave_one() {
        let indices = vec![4, 5, 6, 7];
        assert_eq!(element_list(Mode::Lines, indices.clone()), (vec![4, 5, 6, 7], 0));
        assert_eq!(element_list(Mode::Lines, vec![4, 5, 6]), (vec![4, 5], 1));
        assert_eq!(element_list(Mode::LineStrip, indices.clone()), (vec![4, 5, 5, 6, 6, 7], 0));
        assert_eq!(element_list(Mode::LineLoop, indices.clone()), (vec![4, 5, 5, 6, 6, 7, 7, 4], 0));
        assert_eq!(element_list(Mode::LineLoop, vec![3]), (vec![], 1));
        assert_eq!(element_list(Mode::Points, indices.clone()), (indices, 0));
    }
}
