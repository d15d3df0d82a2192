//! Vertex attributes a glTF file may leave out. Triangle-list positions, normals, UVs and
//! indices flow in; flat normals and tangents (`xyz`, `w` the bitangent sign) flow out.
//!
//! glTF 2.0 §3.7.2.1: without normals, clients calculate flat normals (and ignore any
//! tangents); without tangents, they calculate them with MikkTSpace from the positions,
//! normals and the normal texture's UV set.

use glam::{Vec2, Vec3, Vec4};

/// Copies per-vertex values out to one per index, so that each triangle owns its corners.
/// Every index must be below `values.len()` (the importer checks this first).
pub fn unweld<T: Copy>(values: &[T], indices: &[u32]) -> Vec<T> {
    indices.iter().map(|&i| values[i as usize]).collect()
}

/// The face normal of each triangle, once per corner, for unwelded positions (triangle `t`
/// at `3t..3t + 3`). Counter-clockwise corners face the viewer, glTF's front face. A
/// zero-area triangle gets +Z: it covers no pixels, but its normal must stay finite.
pub fn flat_normals(positions: &[Vec3]) -> Vec<Vec3> {
    debug_assert_eq!(positions.len() % 3, 0);
    positions
        .chunks_exact(3)
        .flat_map(|t| {
            let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or(Vec3::Z);
            [n; 3]
        })
        .collect()
}

/// MikkTSpace tangents for an indexed triangle list, or `None` when MikkTSpace gives up.
///
/// glTF puts the UV origin at the image's top-left corner, so `v` grows downwards while
/// the normal map's +Y (green) points up the image. MikkTSpace's bitangent follows +v, so
/// it is fed `1 - v`: a quad in the XY plane facing +Z with the image upright then gets
/// tangent (1, 0, 0, +1), the bitangent `cross(n, t) * w` pointing up +Y as glTF expects
/// (glTF-Transform flips `w` after MikkTSpace for the same reason).
///
/// Where a vertex is shared by triangles whose tangents differ, the last one written wins,
/// as in Bevy; files that need split tangents split their vertices at UV seams already.
/// Degenerate corners (zero-area UVs) get a tangent perpendicular to the normal.
pub fn mikktspace_tangents(positions: &[Vec3], normals: &[Vec3], uvs: &[Vec2], indices: &[u32]) -> Option<Vec<Vec4>> {
    struct Geometry<'a> {
        positions: &'a [Vec3],
        normals: &'a [Vec3],
        uvs: &'a [Vec2],
        indices: &'a [u32],
        tangents: Vec<Vec4>,
    }

    impl Geometry<'_> {
        fn vertex(&self, face: usize, vert: usize) -> usize {
            self.indices[face * 3 + vert] as usize
        }
    }

    impl mikktspace::Geometry for Geometry<'_> {
        fn num_faces(&self) -> usize {
            self.indices.len() / 3
        }
        fn num_vertices_of_face(&self, _face: usize) -> usize {
            3
        }
        fn position(&self, face: usize, vert: usize) -> [f32; 3] {
            self.positions[self.vertex(face, vert)].to_array()
        }
        fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
            self.normals[self.vertex(face, vert)].to_array()
        }
        fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
            let uv = self.uvs[self.vertex(face, vert)];
            [uv.x, 1.0 - uv.y]
        }
        fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
            let v = self.vertex(face, vert);
            self.tangents[v] = Vec4::from_array(tangent);
        }
    }

    debug_assert!(normals.len() == positions.len() && uvs.len() == positions.len());
    let mut geometry = Geometry { positions, normals, uvs, indices, tangents: vec![Vec4::ZERO; positions.len()] };
    // MikkTSpace is a port of C code with raw indexing; inputs are finite and in range,
    // but a panic inside it must still not take the caller down with the user's file.
    let ok = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| mikktspace::generate_tangents(&mut geometry)))
        .unwrap_or(false);
    if !ok {
        return None;
    }
    let mut tangents = geometry.tangents;
    repair_tangents(&mut tangents, normals);
    Some(tangents)
}

/// A unit tangent perpendicular to each normal, `w = 1`: enough for shading without a
/// normal map, where the tangent frame is never used.
pub fn perpendicular_tangents(normals: &[Vec3]) -> Vec<Vec4> {
    normals.iter().map(|n| n.any_orthonormal_vector().extend(1.0)).collect()
}

/// Makes every tangent unit length with `w = ±1`, replacing non-finite or zero-length ones
/// (MikkTSpace writes zero for corners of zero-area UV triangles) by a perpendicular.
pub fn repair_tangents(tangents: &mut [Vec4], normals: &[Vec3]) {
    for (t, n) in tangents.iter_mut().zip(normals) {
        let sign = if t.w < 0.0 { -1.0 } else { 1.0 };
        *t = match t.truncate().try_normalize() {
            Some(xyz) => xyz.extend(sign),
            None => n.any_orthonormal_vector().extend(sign),
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_normal_follows_counter_clockwise_winding() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        assert_eq!(flat_normals(&tri), vec![Vec3::Z; 3]);
        let flipped = [Vec3::ZERO, Vec3::Y, Vec3::X];
        assert_eq!(flat_normals(&flipped), vec![-Vec3::Z; 3]);
        let degenerate = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        assert_eq!(flat_normals(&degenerate), vec![Vec3::Z; 3]);
    }

    #[test]
    fn upright_quad_gets_plus_x_tangent_and_plus_y_bitangent() {
        // glTF UVs: v = 0 at the top of the image, which sits at y = 1.
        let positions =
            [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let uvs = [Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 0.0)];
        let normals = [Vec3::Z; 4];
        let tangents = mikktspace_tangents(&positions, &normals, &uvs, &[0, 1, 2, 0, 2, 3])
            .expect("mikktspace succeeds on a quad");
        for t in tangents {
            assert!(t.truncate().distance(Vec3::X) < 1e-5, "{t}");
            assert_eq!(t.w, 1.0);
            let bitangent = Vec3::Z.cross(t.truncate()) * t.w;
            assert!(bitangent.distance(Vec3::Y) < 1e-5);
        }
    }

    #[test]
    fn perpendicular_tangents_are_unit_and_orthogonal() {
        let normals = [Vec3::X, Vec3::Y, Vec3::new(1.0, 2.0, 3.0).normalize()];
        for (t, n) in perpendicular_tangents(&normals).iter().zip(normals) {
            assert!(t.truncate().dot(n).abs() < 1e-5);
            assert!((t.truncate().length() - 1.0).abs() < 1e-5);
            assert_eq!(t.w, 1.0);
        }
    }

    #[test]
    fn repair_replaces_zero_tangents() {
        let mut tangents = [Vec4::new(0.0, 0.0, 0.0, -1.0), Vec4::new(2.0, 0.0, 0.0, 0.5)];
        repair_tangents(&mut tangents, &[Vec3::Z, Vec3::Z]);
        assert!(tangents[0].truncate().dot(Vec3::Z).abs() < 1e-5);
        assert_eq!(tangents[0].w, -1.0);
        assert_eq!(tangents[1], Vec4::new(1.0, 0.0, 0.0, 1.0));
    }
}
