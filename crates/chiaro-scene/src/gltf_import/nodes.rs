//! The node hierarchy in, a [`Placement`] (world transform and KHR_node_visibility) for each
//! node of the scene out, parents before children. Cycles, shared children and non-finite
//! transforms are errors.

use super::{Loader, json_label};
use crate::error::SceneError;
use glam::{Mat4, Quat, Vec3};
use gltf::json;

/// A node's place in the world, found by walking the scene graph.
pub(super) struct Placement {
    pub(super) node: usize,
    pub(super) world_from_local: Mat4,
    /// KHR_node_visibility: false where the node or an ancestor has `visible: false`.
    pub(super) visible: bool,
}

impl Loader<'_> {
    /// The scene shown: the default scene, else scene 0; `None` for a file without scenes.
    pub(super) fn scene_index(&self) -> Option<usize> {
        let root = self.root;
        root.scene.map(|s| s.value()).or(if root.scenes.is_empty() { None } else { Some(0) })
    }

    /// World transforms of the nodes of the default scene (else scene 0), parents before
    /// children. A file without scenes, or a scene without nodes, is empty, with a note
    /// that says so. A node reached twice (a cycle, or a child shared by two parents) is an
    /// error, as glTF requires disjoint trees.
    pub(super) fn walk_scene(&mut self) -> Result<Vec<Placement>, SceneError> {
        let root = self.root;
        let scene = self.scene_index();
        let roots: Vec<usize> = match scene {
            Some(scene) => root.scenes[scene].nodes.iter().map(|n| n.value()).collect(),
            None => Vec::new(),
        };
        match scene {
            None => self.ignored.push("the file has no scene: nothing to draw".into()),
            Some(scene) if roots.is_empty() => {
                self.ignored.push(format!("scenes[{scene}] has no nodes: nothing to draw"));
            }
            Some(_) => {}
        }

        let mut visited = vec![false; root.nodes.len()];
        let mut placements = Vec::new();
        let mut stack: Vec<(usize, Mat4, bool)> = roots.iter().rev().map(|&n| (n, Mat4::IDENTITY, true)).collect();
        while let Some((index, parent_from_world, parent_visible)) = stack.pop() {
            let node = &root.nodes[index];
            let label = json_label("nodes", index, None, node.name.as_deref());
            if std::mem::replace(&mut visited[index], true) {
                return Err(
                    self.invalid(format!("{label}: reached twice in the node hierarchy (a cycle or a shared child)"))
                );
            }
            let world_from_local = parent_from_world * local_transform(node);
            if !world_from_local.is_finite() {
                return Err(self.invalid(format!("{label}: transform is not finite")));
            }
            let visible = parent_visible && self.node_visible(index);
            for child in node.children.iter().flatten().rev() {
                stack.push((child.value(), world_from_local, visible));
            }
            placements.push(Placement { node: index, world_from_local, visible });
        }
        Ok(placements)
    }
}

impl Loader<'_> {
    /// Every node of the file: its name, its parent, and where the walk placed it (its
    /// local transform when the drawn scene does not hold it).
    pub(super) fn node_table(&self, placements: &[Placement]) -> Vec<crate::nodes::SceneNode> {
        let nodes = &self.root.nodes;
        let mut table: Vec<crate::nodes::SceneNode> = nodes
            .iter()
            .enumerate()
            .map(|(i, n)| crate::nodes::SceneNode {
                name: n.name.clone().unwrap_or_else(|| format!("node {i}")),
                parent: None,
                world_from_node: local_transform(n),
            })
            .collect();
        for (i, n) in nodes.iter().enumerate() {
            for child in n.children.iter().flatten() {
                if let Some(entry) = table.get_mut(child.value()) {
                    entry.parent = Some(i);
                }
            }
        }
        for p in placements {
            table[p.node].world_from_node = p.world_from_local;
        }
        table
    }

    /// KHR_node_visibility's `visible` on the node itself; true without the extension.
    fn node_visible(&self, index: usize) -> bool {
        let visible = self.raw.pointer(&format!("/nodes/{index}/extensions/KHR_node_visibility/visible"));
        visible.and_then(serde_json::Value::as_bool).unwrap_or(true)
    }

    /// Per node, whether a glTF animation moves it or one of its ancestors, or the joints of
    /// its skin: those nodes are dynamic, so the baker gives them light probes rather than
    /// lightmaps.
    pub(super) fn animated_nodes(&self) -> Vec<bool> {
        let nodes = &self.root.nodes;
        let mut moving = vec![false; nodes.len()];
        let mut stack: Vec<usize> = self
            .root
            .animations
            .iter()
            .flat_map(|a| &a.channels)
            .map(|c| c.target.node.value())
            .chain(self.pointer_channels.iter().filter_map(|p| {
                match super::animation_pointer::parse_pointer(&p.pointer) {
                    Some(super::animation_pointer::PointerTarget::Node(n, _)) => Some(n),
                    _ => None,
                }
            }))
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
        // A skinned mesh moves with its joints wherever its own node is.
        let skin_moves: Vec<bool> =
            self.root.skins.iter().map(|s| s.joints.iter().any(|j| moving.get(j.value()) == Some(&true))).collect();
        for (n, node) in nodes.iter().enumerate() {
            if node.skin.is_some_and(|s| skin_moves.get(s.value()) == Some(&true)) {
                moving[n] = true;
            }
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
