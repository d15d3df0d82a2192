//! The file's animations, skins and morph targets in; a [`SceneAnimation`] out, with the
//! rest transforms and node walk that `Scene::pose` replays. Each instance of a skinned or
//! morphed mesh gets its own copy of the mesh to pose. Sampler times must be finite and
//! non-decreasing and outputs must match them; otherwise the file is refused, naming the
//! animation and channel.

use super::Loader;
use super::nodes::Placement;
use crate::animation::deform::{MorphTarget, SkinWeights};
use crate::animation::sample::{Interpolation, Keyframes};
use crate::animation::{Channel, LocalTransform, PosedInstance, Property, SceneAnimation, Skin};
use crate::error::SceneError;
use crate::types::{Mesh, MeshInstance};
use glam::{Mat4, Quat, Vec3};
use gltf::json;
use json::validation::Checked;

/// Floats per key value: fixed (a vector, a factor), or a morph target's weight per target
/// (the output's length over the keys).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum KeyWidth {
    Fixed(usize),
    PerTarget,
}

impl KeyWidth {
    /// The width of a node property's values.
    pub(super) fn of(property: Property) -> KeyWidth {
        match property {
            Property::Translation | Property::Scale => KeyWidth::Fixed(3),
            Property::Rotation => KeyWidth::Fixed(4),
            Property::Weights => KeyWidth::PerTarget,
        }
    }
}

/// Channel `c` of animation `a` (named `name`) as messages name it.
pub(super) fn channel_label(a: usize, name: Option<&str>, c: usize) -> String {
    match name {
        Some(name) => format!("animations[{a}] ({name}).channels[{c}]"),
        None => format!("animations[{a}].channels[{c}]"),
    }
}

impl Loader<'_> {
    /// Everything posing needs, or `None` for a file without animations, skins or morph
    /// targets. Instances of deformed meshes are pointed at their own posed copies.
    pub(super) fn animation(
        &mut self,
        placements: &[Placement],
        instances: &mut [MeshInstance],
        meshes: &mut Vec<Mesh>,
    ) -> Result<Option<SceneAnimation>, SceneError> {
        let mut channels = self.channels()?;
        let (pointer_nodes, properties) = self.pointer_channels()?;
        channels.extend(pointer_nodes);
        let skins = self.skins()?;
        let nodes = &self.root.nodes;
        let mut posed = Vec::new();
        let mut copies = Vec::new();
        for (i, instance) in instances.iter_mut().enumerate() {
            let Some(deformations) = self.deformations.get(&instance.mesh) else { continue };
            let skin = nodes[instance.node].skin.map(|s| s.value()).filter(|&s| s < skins.len());
            let skinned = skin.is_some() && deformations.iter().flatten().any(|d| d.skin.is_some());
            let morphed = deformations.iter().flatten().any(|d| !d.targets.is_empty());
            if !skinned && !morphed {
                continue;
            }
            let mesh = &meshes[instance.mesh];
            let primitives = mesh
                .primitives
                .iter()
                .zip(deformations)
                .map(|(primitive, deformation)| match (deformation, skinned) {
                    (Some(d), _) => Some(d.clone()),
                    // A primitive without joints in a skinned mesh stays with the mesh's
                    // node: it poses with no weights, so the node's transform places it.
                    (None, true) => Some(crate::animation::deform::Deformation {
                        positions: primitive.positions.clone(),
                        normals: primitive.normals.clone(),
                        tangents: primitive.tangents.clone(),
                        skin: Some(SkinWeights::default()),
                        ..Default::default()
                    }),
                    (None, false) => None,
                })
                .collect();
            let copy = Mesh { name: format!("{} (posed for {})", mesh.name, instance.name), ..mesh.clone() };
            meshes.push(copy);
            copies.push((instance.mesh, meshes.len() - 1));
            instance.mesh = meshes.len() - 1;
            posed.push(PosedInstance { instance: i, mesh: instance.mesh, skin: skin.filter(|_| skinned), primitives });
        }
        self.mesh_copies = copies;
        if channels.is_empty() && posed.is_empty() && properties.is_empty() {
            return Ok(None);
        }
        let mut walked = vec![false; nodes.len()];
        let parents = self.node_parents();
        let order = placements
            .iter()
            .map(|p| {
                walked[p.node] = true;
                (p.node, parents[p.node].filter(|&parent| walked[parent]))
            })
            .collect();
        let rest = nodes.iter().map(rest_transform).collect();
        let rest_weights = nodes
            .iter()
            .map(|n| {
                n.weights
                    .clone()
                    .or_else(|| n.mesh.and_then(|m| self.root.meshes.get(m.value())).and_then(|m| m.weights.clone()))
                    .unwrap_or_default()
            })
            .collect();
        let (light_sources, rest_cones) = (Vec::new(), Vec::new());
        Ok(Some(SceneAnimation {
            rest,
            order,
            channels,
            skins,
            rest_weights,
            posed,
            properties,
            light_sources,
            rest_cones,
        }))
    }

    /// Per node, the node whose children list holds it.
    fn node_parents(&self) -> Vec<Option<usize>> {
        let nodes = &self.root.nodes;
        let mut parents = vec![None; nodes.len()];
        for (i, n) in nodes.iter().enumerate() {
            for child in n.children.iter().flatten() {
                if let Some(slot) = parents.get_mut(child.value()) {
                    *slot = Some(i);
                }
            }
        }
        parents
    }

    fn channels(&self) -> Result<Vec<Channel>, SceneError> {
        let mut channels = Vec::new();
        for (a, animation) in self.root.animations.iter().enumerate() {
            for (c, channel) in animation.channels.iter().enumerate() {
                let label = channel_label(a, animation.name.as_deref(), c);
                let node = channel.target.node.value();
                if node >= self.root.nodes.len() {
                    return Err(self.invalid(format!("{label}: node {node} does not exist")));
                }
                let Checked::Valid(path) = channel.target.path else {
                    return Err(self.invalid(format!("{label}: invalid target path")));
                };
                let property = match path {
                    json::animation::Property::Translation => Property::Translation,
                    json::animation::Property::Rotation => Property::Rotation,
                    json::animation::Property::Scale => Property::Scale,
                    json::animation::Property::MorphTargetWeights => Property::Weights,
                };
                let sampler = animation.samplers.get(channel.sampler.value()).ok_or_else(|| {
                    self.invalid(format!("{label}: sampler {} does not exist", channel.sampler.value()))
                })?;
                let keys = self.keyframes(sampler, KeyWidth::of(property), &label)?;
                channels.push(Channel { node, property, keys });
            }
        }
        Ok(channels)
    }

    pub(super) fn keyframes(
        &self,
        sampler: &json::animation::Sampler,
        width: KeyWidth,
        label: &str,
    ) -> Result<Keyframes, SceneError> {
        let interpolation = match sampler.interpolation {
            Checked::Valid(json::animation::Interpolation::Step) => Interpolation::Step,
            Checked::Valid(json::animation::Interpolation::Linear) => Interpolation::Linear,
            Checked::Valid(json::animation::Interpolation::CubicSpline) => Interpolation::CubicSpline,
            Checked::Invalid => return Err(self.invalid(format!("{label}: invalid interpolation"))),
        };
        let times: Vec<f32> = self
            .read_floats::<1>(sampler.input.value(), &format!("input of {label}"))?
            .into_iter()
            .map(|[t]| t)
            .collect();
        if times.is_empty() {
            return Err(self.invalid(format!("{label}: the sampler has no keys")));
        }
        if let Some(bad) = times.iter().position(|t| !t.is_finite()) {
            return Err(self.invalid(format!("{label}: key time {bad} is not finite")));
        }
        if let Some(k) = times.windows(2).position(|w| w[1] < w[0]) {
            return Err(self.invalid(format!(
                "{label}: key times must increase, but key {} ({} s) comes after {} s",
                k + 1,
                times[k + 1],
                times[k]
            )));
        }
        let output = sampler.output.value();
        let what = format!("output of {label}");
        let values: Vec<f32> = match width {
            KeyWidth::Fixed(3) => self.read_floats::<3>(output, &what)?.concat(),
            KeyWidth::Fixed(4) => self.read_floats::<4>(output, &what)?.concat(),
            KeyWidth::Fixed(_) | KeyWidth::PerTarget => self.read_floats::<1>(output, &what)?.concat(),
        };
        let per_key = if interpolation == Interpolation::CubicSpline { 3 } else { 1 };
        let width = match width {
            KeyWidth::Fixed(width) => width,
            KeyWidth::PerTarget => values.len() / (times.len() * per_key),
        };
        if width == 0 || values.len() != times.len() * per_key * width {
            return Err(self.invalid(format!(
                "{label}: the output has {} floats, which is not {} keys of {per_key} value(s) each",
                values.len(),
                times.len()
            )));
        }
        if let Some(bad) = values.iter().position(|v| !v.is_finite()) {
            return Err(self.invalid(format!("{label}: output value {bad} is not finite")));
        }
        Ok(Keyframes { times, values, width, interpolation })
    }

    fn skins(&self) -> Result<Vec<Skin>, SceneError> {
        let mut skins = Vec::new();
        for (s, skin) in self.root.skins.iter().enumerate() {
            let label = super::json_label("skins", s, None, skin.name.as_deref());
            let joints: Vec<usize> = skin.joints.iter().map(|j| j.value()).collect();
            if let Some(bad) = joints.iter().find(|&&j| j >= self.root.nodes.len()) {
                return Err(self.invalid(format!("{label}: joint node {bad} does not exist")));
            }
            let inverse_bind = match skin.inverse_bind_matrices {
                Some(accessor) => {
                    let matrices =
                        self.read_floats::<16>(accessor.value(), &format!("inverseBindMatrices of {label}"))?;
                    if matrices.len() < joints.len() {
                        return Err(self.invalid(format!(
                            "{label}: {} inverse bind matrices for {} joints",
                            matrices.len(),
                            joints.len()
                        )));
                    }
                    let matrices: Vec<Mat4> = matrices.iter().map(Mat4::from_cols_array).collect();
                    if matrices.iter().any(|m| !m.is_finite()) {
                        return Err(self.invalid(format!("{label}: an inverse bind matrix is not finite")));
                    }
                    matrices
                }
                None => vec![Mat4::IDENTITY; joints.len()],
            };
            skins.push(Skin { joints, inverse_bind });
        }
        Ok(skins)
    }

    /// JOINTS_n and WEIGHTS_n, paired by set, for every vertex; `None` without JOINTS_0.
    pub(super) fn skin_weights(
        &self,
        primitive: &json::mesh::Primitive,
        label: &str,
        vertex_count: usize,
    ) -> Result<Option<SkinWeights>, SceneError> {
        use json::mesh::Semantic;
        let attribute = |semantic: Semantic| primitive.attributes.get(&Checked::Valid(semantic)).map(|a| a.value());
        let mut skin = SkinWeights::default();
        for set in 0.. {
            let (Some(joints), Some(weights)) = (attribute(Semantic::Joints(set)), attribute(Semantic::Weights(set)))
            else {
                break;
            };
            let joints = self.vertex_attribute::<4>(joints, &format!("JOINTS_{set}"), label, vertex_count)?;
            let weights = self.vertex_attribute::<4>(weights, &format!("WEIGHTS_{set}"), label, vertex_count)?;
            let joints: Vec<[u16; 4]> =
                joints.iter().map(|j| j.map(|x| x.clamp(0.0, f32::from(u16::MAX)) as u16)).collect();
            let weights: Vec<[f32; 4]> =
                weights.iter().map(|w| w.map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 })).collect();
            skin.joints.push(joints);
            skin.weights.push(weights);
        }
        Ok((!skin.joints.is_empty()).then_some(skin))
    }

    /// The primitive's morph targets, each attribute checked to give one offset per vertex.
    pub(super) fn morph_targets(
        &self,
        primitive: &json::mesh::Primitive,
        label: &str,
        vertex_count: usize,
    ) -> Result<Vec<MorphTarget>, SceneError> {
        let mut targets = Vec::new();
        for (t, target) in primitive.targets.iter().flatten().enumerate() {
            let read = |accessor: Option<json::Index<json::Accessor>>, name: &str| -> Result<_, SceneError> {
                let Some(accessor) = accessor else { return Ok(None) };
                let what = format!("targets[{t}].{name}");
                let offsets = self.vertex_attribute::<3>(accessor.value(), &what, label, vertex_count)?;
                if offsets.iter().flatten().any(|v| !v.is_finite()) {
                    return Err(self.invalid(format!("{label}: {what} has values that are not finite")));
                }
                Ok(Some(offsets.into_iter().map(Vec3::from_array).collect()))
            };
            targets.push(MorphTarget {
                positions: read(target.positions, "POSITION")?,
                normals: read(target.normals, "NORMAL")?,
                tangents: read(target.tangents, "TANGENT")?,
            });
        }
        Ok(targets)
    }
}

/// A node's rest transform as the file gives it.
fn rest_transform(node: &json::scene::Node) -> LocalTransform {
    let (scale, rotation, translation) = match node.matrix {
        Some(m) => Mat4::from_cols_array(&m).to_scale_rotation_translation(),
        None => (
            Vec3::from_array(node.scale.unwrap_or([1.0; 3])),
            node.rotation.map_or(Quat::IDENTITY, |r| Quat::from_array(r.0)),
            Vec3::from_array(node.translation.unwrap_or([0.0; 3])),
        ),
    };
    LocalTransform { matrix: node.matrix.map(|m| Mat4::from_cols_array(&m)), translation, rotation, scale }
}

impl SkinWeights {
    /// One entry per index, as `vertex_gen::unweld` does for the other attributes.
    pub(super) fn unweld(&mut self, indices: &[u32]) {
        for joints in &mut self.joints {
            *joints = crate::vertex_gen::unweld(joints, indices);
        }
        for weights in &mut self.weights {
            *weights = crate::vertex_gen::unweld(weights, indices);
        }
    }
}

impl MorphTarget {
    pub(super) fn unweld(&mut self, indices: &[u32]) {
        for offsets in [&mut self.positions, &mut self.normals, &mut self.tangents].into_iter().flatten() {
            *offsets = crate::vertex_gen::unweld(offsets, indices);
        }
    }
}
