//! The scene's nodes (glTF's, or one per object for scenes made in code) and moving one:
//! a node's new world transform moves its descendants and every mesh instance, light and
//! camera they carry, each keeping its place relative to the node.

use crate::types::Scene;
use glam::Mat4;

/// One node of the scene, at its glTF index.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneNode {
    /// The node's name, or `node N` when the file gives none.
    pub name: String,
    /// The node whose children list holds this one; `None` for roots.
    pub parent: Option<usize>,
    /// Where the node is, metres; for nodes outside the drawn scene, their local transform.
    pub world_from_node: Mat4,
}

/// Why a node could not be moved.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NodeError {
    /// No node has that index.
    #[error("no node {node} in the scene (it has {count} nodes)")]
    NoSuchNode {
        /// The index asked for.
        node: usize,
        /// How many nodes the scene has.
        count: usize,
    },
    /// The transform has NaN or infinite entries, or cannot be inverted.
    #[error("the transform for node {node} ({name}) {problem}")]
    BadTransform {
        /// The node.
        node: usize,
        /// Its name.
        name: String,
        /// What is wrong with the matrix.
        problem: &'static str,
    },
}

/// What a move changed, so a renderer knows whether its uploaded geometry is stale.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NodeMove {
    /// Mesh instances moved (their transforms live in GPU buffers).
    pub instances: usize,
    /// Lights moved.
    pub lights: usize,
    /// Cameras moved.
    pub cameras: usize,
}

/// A node table for a scene made in code: one root node per index its instances, lights and
/// cameras name, called after the first object found there.
pub fn nodes_from_objects(scene: &Scene) -> Vec<SceneNode> {
    let objects = scene
        .instances
        .iter()
        .map(|i| (i.node, &i.name, i.world_from_local))
        .chain(scene.lights.iter().map(|l| (l.node, &l.name, l.world_from_light)))
        .chain(scene.cameras.iter().map(|c| (c.node, &c.name, c.world_from_view)));
    let mut nodes: Vec<Option<SceneNode>> = Vec::new();
    for (node, name, world) in objects {
        if nodes.len() <= node {
            nodes.resize(node + 1, None);
        }
        nodes[node].get_or_insert_with(|| SceneNode { name: name.clone(), parent: None, world_from_node: world });
    }
    nodes
        .into_iter()
        .enumerate()
        .map(|(i, n)| {
            n.unwrap_or_else(|| SceneNode { name: format!("node {i}"), parent: None, world_from_node: Mat4::IDENTITY })
        })
        .collect()
}

impl Scene {
    /// Gives a scene made in code its node table (`nodes_from_objects`) if it has none.
    pub fn ensure_nodes(&mut self) {
        if self.nodes.is_empty() {
            self.nodes = nodes_from_objects(self);
        }
    }

    /// Places `node` at `world_from_node`. Its descendants and whatever the moved nodes
    /// carry follow, keeping their transforms relative to it (a change `D = new * old⁻¹`
    /// applied on the left); lights and cameras keep no scale.
    pub fn set_node_transform(&mut self, node: usize, world_from_node: Mat4) -> Result<NodeMove, NodeError> {
        self.ensure_nodes();
        let count = self.nodes.len();
        let Some(target) = self.nodes.get(node) else { return Err(NodeError::NoSuchNode { node, count }) };
        let bad = |problem| NodeError::BadTransform { node, name: target.name.clone(), problem };
        if !world_from_node.is_finite() {
            return Err(bad("has entries that are NaN or infinite"));
        }
        // A transposed matrix (translation in the bottom row) is the usual mistake: it
        // would make meshes projective while lights and cameras kept only their rigid part.
        if !world_from_node.row(3).abs_diff_eq(glam::Vec4::W, 1e-6) {
            return Err(bad("is not affine: its bottom row must be (0, 0, 0, 1) (transposed?)"));
        }
        if world_from_node.determinant().abs() < 1e-12 {
            return Err(bad("cannot be inverted (a zero scale?)"));
        }
        if target.world_from_node.determinant().abs() < 1e-12 {
            return Err(bad("cannot be applied: the node's present transform cannot be inverted"));
        }
        let change = world_from_node * target.world_from_node.inverse();
        let moved = self.subtree(node);
        for (entry, _) in self.nodes.iter_mut().zip(&moved).filter(|(_, inside)| **inside) {
            entry.world_from_node = change * entry.world_from_node;
        }
        // Exact for the node itself rather than through the inverse's rounding.
        self.nodes[node].world_from_node = world_from_node;
        let follows = |n: usize| moved.get(n).copied().unwrap_or(false);
        let mut result = NodeMove::default();
        for instance in self.instances.iter_mut().filter(|i| follows(i.node)) {
            instance.world_from_local = change * instance.world_from_local;
            result.instances += 1;
        }
        for light in self.lights.iter_mut().filter(|l| follows(l.node)) {
            light.world_from_light = rigid(change * light.world_from_light);
            result.lights += 1;
        }
        for camera in self.cameras.iter_mut().filter(|c| follows(c.node)) {
            camera.world_from_view = rigid(change * camera.world_from_view);
            result.cameras += 1;
        }
        Ok(result)
    }

    /// Per node, whether it is `node` or below it.
    fn subtree(&self, node: usize) -> Vec<bool> {
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); self.nodes.len()];
        for (i, n) in self.nodes.iter().enumerate() {
            if let Some(parent) = n.parent.filter(|&p| p < self.nodes.len()) {
                children[parent].push(i);
            }
        }
        let mut inside = vec![false; self.nodes.len()];
        inside[node] = true;
        let mut stack = vec![node];
        while let Some(n) = stack.pop() {
            // The import refuses cycles; the mark keeps a hand-made table from looping.
            for &c in &children[n] {
                if !std::mem::replace(&mut inside[c], true) {
                    stack.push(c);
                }
            }
        }
        inside
    }
}

/// The rotation and translation of `m`, without scale: lights and cameras are placed by
/// rigid frames.
fn rigid(m: Mat4) -> Mat4 {
    let (_, rotation, translation) = m.to_scale_rotation_translation();
    Mat4::from_rotation_translation(rotation.normalize(), translation)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo::demo_scene;
    use glam::{Quat, Vec3};

    #[test]
    fn code_made_scenes_get_one_node_per_object() {
        let mut scene = demo_scene(2);
        scene.ensure_nodes();
        for i in &scene.instances {
            assert_eq!(scene.nodes[i.node].name, i.name);
        }
        for l in &scene.lights {
            assert_eq!(scene.nodes[l.node].name, l.name);
        }
        assert_eq!(scene.nodes.len(), scene.cameras[0].node + 1);
    }

    #[test]
    fn moving_a_parent_moves_its_children_and_what_they_carry() {
        let mut scene = demo_scene(2);
        scene.ensure_nodes();
        // Hang the first box (node 1) and the first spot light under the floor (node 0).
        let light_node = scene.lights[1].node;
        scene.nodes[1].parent = Some(0);
        scene.nodes[light_node].parent = Some(0);
        let box_before = scene.instances[1].world_from_local;
        let light_before = scene.lights[1].position();
        let lift = Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0));
        let moved = scene.set_node_transform(0, lift).unwrap();
        assert_eq!(moved, NodeMove { instances: 2, lights: 1, cameras: 0 });
        assert_eq!(scene.instances[0].world_from_local, lift);
        assert!(scene.instances[1].world_from_local.abs_diff_eq(lift * box_before, 1e-6));
        assert!(scene.lights[1].position().abs_diff_eq(light_before + Vec3::new(0.0, 2.0, 0.0), 1e-5));
        // A node outside the subtree stays.
        assert_eq!(
            scene.instances[2].world_from_local,
            nodes_from_objects(&demo_scene(2)).get(2).unwrap().world_from_node
        );
    }

    #[test]
    fn cameras_keep_no_scale_and_bad_transforms_are_refused() {
        let mut scene = demo_scene(0);
        let camera = scene.cameras[0].node;
        let m = Mat4::from_scale_rotation_translation(Vec3::splat(3.0), Quat::from_rotation_y(0.5), Vec3::X);
        scene.set_node_transform(camera, m).unwrap();
        let (scale, rotation, translation) = scene.cameras[0].world_from_view.to_scale_rotation_translation();
        assert!(scale.abs_diff_eq(Vec3::ONE, 1e-5));
        assert!(rotation.abs_diff_eq(Quat::from_rotation_y(0.5), 1e-5));
        assert!(translation.abs_diff_eq(Vec3::X, 1e-5));
        let count = scene.nodes.len();
        assert_eq!(scene.set_node_transform(count, Mat4::IDENTITY), Err(NodeError::NoSuchNode { node: count, count }));
        let error = scene.set_node_transform(0, Mat4::from_scale(Vec3::ZERO)).unwrap_err().to_string();
        assert_eq!(error, "the transform for node 0 (floor) cannot be inverted (a zero scale?)");
        let error = scene.set_node_transform(0, Mat4::from_cols_array(&[f32::NAN; 16])).unwrap_err().to_string();
        assert!(error.ends_with("has entries that are NaN or infinite"), "{error}");
        let transposed = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0)).transpose();
        let error = scene.set_node_transform(0, transposed).unwrap_err().to_string();
        assert!(error.ends_with("bottom row must be (0, 0, 0, 1) (transposed?)"), "{error}");
    }
}
