//! glTF animation, skins and morph targets, posed on the CPU. The loader keeps what posing
//! needs in a [`SceneAnimation`] (rest transforms, sampled channels, skins, and per deformed
//! instance its rest vertices); [`Scene::pose`] takes a time (or none, for the rest pose)
//! and places every node, mesh instance, light and camera, and rewrites the vertices of
//! skinned and morphed meshes, so that everything downstream (the renderer, its shadow
//! passes, the ray-traced reference) sees the posed scene as if it were static.

pub mod deform;
pub mod properties;
pub mod sample;

use crate::types::Scene;
use deform::Deformation;
use glam::{Mat4, Quat, Vec3};
use properties::PropertyChannel;
use sample::Keyframes;

/// Why a scene could not be posed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AnimationError {
    /// The time is NaN or infinite.
    #[error("time {0} is not a finite number of seconds")]
    BadTime(f32),
}

/// A node's local transform at rest: the file's matrix, or translation, rotation, scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalTransform {
    /// The file's `matrix`, used as is while no channel animates the node.
    pub matrix: Option<Mat4>,
    /// Translation (the matrix's, decomposed, where the file gave one).
    pub translation: Vec3,
    /// Rotation.
    pub rotation: Quat,
    /// Scale.
    pub scale: Vec3,
}

impl LocalTransform {
    /// The parent-from-node matrix. Exporters write quaternions a few ulps off unit length.
    pub fn matrix(&self) -> Mat4 {
        self.matrix.unwrap_or_else(|| {
            Mat4::from_scale_rotation_translation(self.scale, self.rotation.normalize(), self.translation)
        })
    }
}

/// Which property a channel animates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    /// The node's translation.
    Translation,
    /// The node's rotation.
    Rotation,
    /// The node's scale.
    Scale,
    /// The morph target weights of the node's mesh.
    Weights,
}

/// One animated property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The node (glTF index).
    pub node: usize,
    /// What it animates.
    pub property: Property,
    /// Its keyframes.
    pub keys: Keyframes,
}

/// A skin: its joints (node indices) and their inverse bind matrices.
#[derive(Clone, Debug, PartialEq)]
pub struct Skin {
    /// Joint nodes.
    pub joints: Vec<usize>,
    /// Bind space from joint space, one per joint (identity where the file gives none).
    pub inverse_bind: Vec<Mat4>,
}

/// A mesh instance whose vertices are posed: its own copy of the mesh, rewritten per pose.
#[derive(Clone, Debug, PartialEq)]
pub struct PosedInstance {
    /// Index into `Scene::instances`.
    pub instance: usize,
    /// The posed copy, an index into `Scene::meshes`.
    pub mesh: usize,
    /// The skin moving it; its vertices are then in world space and the instance's
    /// transform is the identity.
    pub skin: Option<usize>,
    /// Per primitive of the mesh, what moves its vertices (`None`: nothing does).
    pub primitives: Vec<Option<Deformation>>,
}

/// What the loader kept to pose the scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneAnimation {
    /// Every node's rest transform, at its glTF index.
    pub rest: Vec<LocalTransform>,
    /// The drawn scene's nodes, parents before children, each with its parent in that walk.
    pub order: Vec<(usize, Option<usize>)>,
    /// Every channel of every animation.
    pub channels: Vec<Channel>,
    /// The file's skins.
    pub skins: Vec<Skin>,
    /// Per node, the morph weights of its mesh at rest (the node's, else the mesh's).
    pub rest_weights: Vec<Vec<f32>>,
    /// Instances with skinned or morphed meshes.
    pub posed: Vec<PosedInstance>,
    /// KHR_animation_pointer channels of light and material properties, with their rest
    /// values.
    pub properties: Vec<PropertyChannel>,
    /// Per scene light, the KHR_lights_punctual light it places (what `properties` name).
    pub light_sources: Vec<Option<usize>>,
    /// The file's (inner, outer) cone of each KHR_lights_punctual spot a channel animates a
    /// cone of: every pose starts from them, since ordering one cone moves the other.
    pub rest_cones: Vec<(usize, f32, f32)>,
}

impl SceneAnimation {
    /// The latest key of any channel: the animations' length in seconds.
    pub fn duration(&self) -> f32 {
        let ends = self.channels.iter().map(|c| c.keys.end()).chain(self.properties.iter().map(|p| p.keys.end()));
        ends.fold(0.0, f32::max)
    }

    /// Whether anything changes with time.
    pub fn has_channels(&self) -> bool {
        !self.channels.is_empty() || !self.properties.is_empty()
    }

    /// World transforms of the walked nodes (`None` for nodes outside the drawn scene) and
    /// every node's morph weights, at `time` (`None`: at rest).
    fn sample(&self, time: Option<f32>) -> (Vec<Option<Mat4>>, Vec<Vec<f32>>) {
        let mut locals = self.rest.clone();
        let mut weights = self.rest_weights.clone();
        if let Some(t) = time {
            for channel in &self.channels {
                let Some(local) = locals.get_mut(channel.node) else { continue };
                if channel.property != Property::Weights {
                    // An animated node moves by its parts; glTF forbids animating a matrix,
                    // so one given anyway is decomposed.
                    if let Some(m) = local.matrix.take() {
                        let (scale, rotation, translation) = m.to_scale_rotation_translation();
                        (local.scale, local.rotation, local.translation) = (scale, rotation, translation);
                    }
                }
                match channel.property {
                    Property::Translation => local.translation = Vec3::from_slice(&channel.keys.sample(t)),
                    Property::Rotation => local.rotation = channel.keys.rotation(t),
                    Property::Scale => local.scale = Vec3::from_slice(&channel.keys.sample(t)),
                    Property::Weights => weights[channel.node] = channel.keys.sample(t),
                }
            }
        }
        let mut world: Vec<Option<Mat4>> = vec![None; self.rest.len()];
        for &(node, parent) in &self.order {
            let parent_from_world = parent.and_then(|p| world[p]).unwrap_or(Mat4::IDENTITY);
            world[node] = Some(parent_from_world * locals[node].matrix());
        }
        (world, weights)
    }
}

impl Scene {
    /// Poses the scene at `time` seconds into every animation at once (each holds its first
    /// key before it and its last after), or at rest for `None`: nodes, mesh instances,
    /// lights and cameras are placed, skinned and morphed meshes rewritten. Posing starts
    /// from the rest state each time, so poses never drift. A scene without animation,
    /// skins or morph targets is unchanged.
    pub fn pose(&mut self, time: Option<f32>) -> Result<(), AnimationError> {
        if let Some(t) = time.filter(|t| !t.is_finite()) {
            return Err(AnimationError::BadTime(t));
        }
        let Some(animation) = self.animation.take() else { return Ok(()) };
        self.apply_pose(&animation, time);
        self.animation = Some(animation);
        Ok(())
    }

    /// The animations' length in seconds; `None` when the scene has no animation.
    pub fn animation_duration(&self) -> Option<f32> {
        self.animation.as_ref().filter(|a| a.has_channels()).map(|a| a.duration())
    }

    fn apply_pose(&mut self, animation: &SceneAnimation, time: Option<f32>) {
        for &(source, inner, outer) in &animation.rest_cones {
            properties::reset_cones(self, &animation.light_sources, source, inner, outer);
        }
        for channel in &animation.properties {
            let value = match time {
                Some(t) => channel.keys.sample(t),
                None => channel.rest.clone(),
            };
            properties::write(self, &animation.light_sources, channel.target, &value);
        }
        let (world, weights) = animation.sample(time);
        for (node, entry) in self.nodes.iter_mut().enumerate() {
            if let Some(m) = world.get(node).copied().flatten() {
                entry.world_from_node = m;
            }
        }
        let placed = |node: usize| world.get(node).copied().flatten();
        for instance in &mut self.instances {
            if let Some(m) = placed(instance.node) {
                instance.world_from_local = m * instance.gpu_instance.map_or(Mat4::IDENTITY, |g| g.node_from_instance);
            }
        }
        for light in &mut self.lights {
            if let Some(m) = placed(light.node) {
                light.world_from_light = crate::gltf_import::light_frame(m);
            }
        }
        for camera in &mut self.cameras {
            // A camera on a node scaled to nothing keeps its last frame.
            if let Some(frame) = placed(camera.node).and_then(chiaro_math::rigid::rigid_part) {
                camera.world_from_view = frame;
            }
        }
        for posed in &animation.posed {
            let Some(instance) = self.instances.get_mut(posed.instance) else { continue };
            let node_world = placed(instance.node).unwrap_or(instance.world_from_local);
            let joint_matrices: Vec<Mat4> = match posed.skin.and_then(|s| animation.skins.get(s)) {
                Some(skin) => skin
                    .joints
                    .iter()
                    .zip(&skin.inverse_bind)
                    .map(|(&joint, inverse_bind)| {
                        let joint_world = placed(joint)
                            .or_else(|| self.nodes.get(joint).map(|n| n.world_from_node))
                            .unwrap_or(Mat4::IDENTITY);
                        joint_world * *inverse_bind
                    })
                    .collect(),
                None => Vec::new(),
            };
            if posed.skin.is_some() {
                instance.world_from_local = Mat4::IDENTITY;
            }
            let node_weights = weights.get(instance.node).map(Vec::as_slice).unwrap_or(&[]);
            let Some(mesh) = self.meshes.get_mut(posed.mesh) else { continue };
            for (primitive, deformation) in mesh.primitives.iter_mut().zip(&posed.primitives) {
                let Some(deformation) = deformation else { continue };
                let out = deformation.pose(node_weights, &joint_matrices, node_world);
                primitive.bounds = chiaro_math::Aabb::from_points(out.positions.iter().copied());
                primitive.positions = out.positions;
                primitive.normals = out.normals;
                primitive.tangents = out.tangents;
            }
        }
    }
}
