//! A primitive's rest vertices, its morph targets and skin weights in; posed vertices out.
//! Morph targets add weighted offsets first (glTF 2.0 §3.7.2.2), then each vertex is moved
//! by the blend of its joints' matrices (§3.7.3): `joint world * inverse bind`, which puts a
//! skinned vertex in world space. Normals follow the blended matrix's inverse transpose,
//! tangents the matrix itself, both renormalised.

use glam::{Mat3, Mat4, Vec3, Vec4};

/// One morph target's offsets, one per vertex where given.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MorphTarget {
    /// Position offsets, metres.
    pub positions: Option<Vec<Vec3>>,
    /// Normal offsets.
    pub normals: Option<Vec<Vec3>>,
    /// Tangent offsets (xyz; the handedness stays).
    pub tangents: Option<Vec<Vec3>>,
}

/// Four joints and their weights for every vertex, one entry per JOINTS_n/WEIGHTS_n set.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SkinWeights {
    /// Indices into the skin's joint list.
    pub joints: Vec<Vec<[u16; 4]>>,
    /// Weights, as the file gives them (normalised when used).
    pub weights: Vec<Vec<[f32; 4]>>,
}

/// What moves a primitive's vertices, beside its rest copy.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Deformation {
    /// Rest positions, normals and tangents (the file's, before any posing).
    pub positions: Vec<Vec3>,
    /// Rest normals.
    pub normals: Vec<Vec3>,
    /// Rest tangents.
    pub tangents: Vec<Vec4>,
    /// The morph targets, in the file's order.
    pub targets: Vec<MorphTarget>,
    /// Joint influences when the mesh is skinned.
    pub skin: Option<SkinWeights>,
    /// The normals were generated flat (the file gave none): regenerate them from the
    /// posed positions rather than moving them.
    pub flat_normals: bool,
}

/// Posed vertex attributes.
pub struct Posed {
    /// Positions: world space when skinned, the mesh's space otherwise.
    pub positions: Vec<Vec3>,
    /// Unit normals.
    pub normals: Vec<Vec3>,
    /// Unit tangents with the rest handedness.
    pub tangents: Vec<Vec4>,
}

impl Deformation {
    /// Poses the vertices with morph `weights` (missing ones are zero) and, when skinned,
    /// `joint_matrices` (world from bind space, per joint of the skin); `fallback` places
    /// vertices whose weights sum to zero (the mesh node's world transform).
    pub fn pose(&self, weights: &[f32], joint_matrices: &[Mat4], fallback: Mat4) -> Posed {
        let mut positions = self.positions.clone();
        let mut normals = self.normals.clone();
        let mut tangents = self.tangents.clone();
        for (target, &w) in self.targets.iter().zip(weights).filter(|(_, w)| **w != 0.0) {
            add_scaled(&mut positions, target.positions.as_deref(), w);
            add_scaled(&mut normals, target.normals.as_deref(), w);
            if let Some(offsets) = &target.tangents {
                for (t, d) in tangents.iter_mut().zip(offsets) {
                    *t += (*d * w).extend(0.0);
                }
            }
        }
        if let Some(skin) = &self.skin {
            for v in 0..positions.len() {
                let m = blended_matrix(skin, v, joint_matrices).unwrap_or(fallback);
                positions[v] = m.transform_point3(positions[v]);
                let linear = Mat3::from_mat4(m);
                normals[v] = linear.inverse().transpose() * normals[v];
                let t = linear * tangents[v].truncate();
                tangents[v] = t.extend(tangents[v].w);
            }
        }
        if self.flat_normals {
            normals = crate::vertex_gen::flat_normals(&positions);
        }
        for n in &mut normals {
            *n = n.normalize_or(Vec3::Z);
        }
        for t in &mut tangents {
            let xyz = t.truncate().normalize_or(Vec3::X);
            *t = xyz.extend(if t.w < 0.0 { -1.0 } else { 1.0 });
        }
        Posed { positions, normals, tangents }
    }
}

fn add_scaled(values: &mut [Vec3], offsets: Option<&[Vec3]>, w: f32) {
    for (v, d) in values.iter_mut().zip(offsets.into_iter().flatten()) {
        *v += *d * w;
    }
}

/// `Σ wᵢ · joint_matrices[jᵢ]` over the vertex's influences, weights normalised to sum to
/// one; `None` where they sum to zero (or name no joint).
fn blended_matrix(skin: &SkinWeights, vertex: usize, joint_matrices: &[Mat4]) -> Option<Mat4> {
    let mut sum = Mat4::ZERO;
    let mut total = 0.0;
    for (joints, weights) in skin.joints.iter().zip(&skin.weights) {
        for (&j, &w) in joints[vertex].iter().zip(&weights[vertex]) {
            if w > 0.0
                && let Some(m) = joint_matrices.get(usize::from(j))
            {
                sum += *m * w;
                total += w;
            }
        }
    }
    (total > 1e-8).then(|| sum * (1.0 / total))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    fn one_vertex(position: Vec3, skin: Option<SkinWeights>, targets: Vec<MorphTarget>) -> Deformation {
        Deformation {
            positions: vec![position],
            normals: vec![Vec3::Y],
            tangents: vec![Vec4::new(1.0, 0.0, 0.0, -1.0)],
            targets,
            skin,
            flat_normals: false,
        }
    }

    #[test]
    fn morph_targets_add_weighted_offsets() {
        let targets = vec![
            MorphTarget { positions: Some(vec![Vec3::X]), ..Default::default() },
            MorphTarget { positions: Some(vec![Vec3::Y * 2.0]), normals: Some(vec![Vec3::X]), tangents: None },
        ];
        let posed = one_vertex(Vec3::ZERO, None, targets).pose(&[0.5, 0.25], &[], Mat4::IDENTITY);
        assert_eq!(posed.positions[0], Vec3::new(0.5, 0.5, 0.0));
        assert!(posed.normals[0].abs_diff_eq(Vec3::new(0.25, 1.0, 0.0).normalize(), 1e-6));
    }

    #[test]
    fn a_vertex_follows_its_joints_blend_and_normals_their_inverse_transpose() {
        let skin = SkinWeights { joints: vec![vec![[0, 1, 0, 0]]], weights: vec![vec![[0.25, 0.75, 0.0, 0.0]]] };
        let a = Mat4::from_translation(Vec3::new(4.0, 0.0, 0.0));
        let b = Mat4::from_translation(Vec3::new(0.0, 8.0, 0.0));
        let posed = one_vertex(Vec3::ONE, Some(skin.clone()), vec![]).pose(&[], &[a, b], Mat4::IDENTITY);
        assert!(posed.positions[0].abs_diff_eq(Vec3::new(2.0, 7.0, 1.0), 1e-6));
        // A non-uniform scale: the normal of the plane y = 0 stays +Y, the tangent +X, and
        // the tangent keeps its handedness.
        let squash = Mat4::from_scale_rotation_translation(Vec3::new(3.0, 0.5, 1.0), Quat::IDENTITY, Vec3::ZERO);
        let posed = one_vertex(Vec3::ONE, Some(skin), vec![]).pose(&[], &[squash, squash], Mat4::IDENTITY);
        assert!(posed.normals[0].abs_diff_eq(Vec3::Y, 1e-6));
        assert_eq!(posed.tangents[0], Vec4::new(1.0, 0.0, 0.0, -1.0));
    }

    #[test]
    fn weights_that_sum_to_zero_use_the_fallback() {
        let skin = SkinWeights { joints: vec![vec![[0; 4]]], weights: vec![vec![[0.0; 4]]] };
        let fallback = Mat4::from_translation(Vec3::Z);
        let posed = one_vertex(Vec3::ZERO, Some(skin), vec![]).pose(&[], &[Mat4::IDENTITY], fallback);
        assert_eq!(posed.positions[0], Vec3::Z);
    }
}
