//! The node hierarchy in, a [`Placement`] (world transform) for each node of the scene out,
//! parents before children. Cycles, shared children and non-finite transforms are errors.

use super::{Loader, object_label};
use crate::error::SceneError;
use glam::{Mat4, Quat, Vec3};
use gltf::json;

/// A node's place in the world, found by walking the scene graph.
pub(super) struct Placement {
    pub(super) node: usize,
    pub(super) world_from_local: Mat4,
}

impl Loader<'_> {
    /// World transforms of the nodes of the default scene (else scene 0, else every root
    /// node), parents before children. A node reached twice (a cycle, or a child shared by
    /// two parents) is an error, as glTF requires disjoint trees.
    pub(super) fn walk_scene(&self) -> Result<Vec<Placement>, SceneError> {
        let root = self.root;
        let roots: Vec<usize> =
            match root.scene.map(|s| s.value()).or(if root.scenes.is_empty() { None } else { Some(0) }) {
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
        let mut stack: Vec<(usize, Mat4)> = roots.iter().rev().map(|&n| (n, Mat4::IDENTITY)).collect();
        while let Some((index, parent_from_world)) = stack.pop() {
            let node = &root.nodes[index];
            let label = object_label("node", index, None, node.name.as_deref());
            if std::mem::replace(&mut visited[index], true) {
                return Err(
                    self.invalid(format!("{label}: reached twice in the node hierarchy (a cycle or a shared child)"))
                );
            }
            let world_from_local = parent_from_world * local_transform(node);
            if !world_from_local.is_finite() {
                return Err(self.invalid(format!("{label}: transform is not finite")));
            }
            for child in node.children.iter().flatten().rev() {
                stack.push((child.value(), world_from_local));
            }
            placements.push(Placement { node: index, world_from_local });
        }
        Ok(placements)
    }
}

impl Loader<'_> {
    /// Per node, whether a glTF animation moves it or one of its ancestors: those nodes are
    /// dynamic, so the baker gives them light probes rather than lightmaps.
    pub(super) fn animated_nodes(&self) -> Vec<bool> {
        let nodes = &self.root.nodes;
        let mut moving = vec![false; nodes.len()];
        let mut stack: Vec<usize> = self
            .root
            .animations
            .iter()
            .flat_map(|a| &a.channels)
            .map(|c| c.target.node.value())
            .filter(|&n| n < nodes.len())
            .collect();
        // The hierarchy was checked to be a forest in `walk_scene`; `moving` also guards
        // against revisiting.
        while let Some(n) = stack.pop() {
            if std::mem::replace(&mut moving[n], true) {
                continue;
            }
            stack.extend(nodes[n].children.iter().flatten().map(|c| c.value()).filter(|&c| c < nodes.len()));
        }
        moving
    }
}

fn local_transform(node: &json::scene::Node) -> Mat4 {
    if let Some(m) = node.matrix {
        return Mat4::from_cols_array(&m);
    }
    let translation = Vec3::from_array(node.translation.unwrap_or([0.0; 3]));
    let rotation = node.rotation.map_or(Quat::IDENTITY, |r| Quat::from_array(r.0));
    let scale = Vec3::from_array(node.scale.unwrap_or([1.0; 3]));
    // Exporters write quaternions a few ulps off unit length; a zero one stays zero and
    // fails the finiteness check after normalising.
    Mat4::from_scale_rotation_translation(scale, rotation.normalize(), translation)
}
