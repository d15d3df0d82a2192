//! KHR_animation_pointer channels (set aside by `normalize`) in; node channels and light
//! and material [`PropertyChannel`]s out. A pointer names a node's translation, rotation,
//! scale or weights (read as the core channels are), a KHR_lights_punctual light's colour,
//! intensity, range or spot cone angles, or a material's factors; any other pointer, or one
//! naming a node, light or material the file lacks, is noted and its channel ignored, as
//! the extension asks of pointers a viewer cannot animate.

use super::Loader;
use super::animation::{KeyWidth, channel_label};
use crate::animation::properties::{AnimatedProperty, PropertyChannel};
use crate::animation::{Channel, Property};
use crate::error::SceneError;
use glam::Vec3;
use serde_json::Value;

pub(super) const EXTENSION: &str = "KHR_animation_pointer";

/// What a pointer animates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum PointerTarget {
    Node(usize, Property),
    Light(LightKey, usize),
    Material(MaterialKey, usize),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum LightKey {
    Color,
    Intensity,
    Range,
    InnerCone,
    OuterCone,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum MaterialKey {
    BaseColor,
    Metallic,
    Roughness,
    Emissive,
    EmissiveStrength,
    AlphaCutoff,
    NormalScale,
    OcclusionStrength,
}

/// The target of a JSON pointer, if Chiaro animates it (indices not yet checked).
pub(super) fn parse_pointer(pointer: &str) -> Option<PointerTarget> {
    let parts: Vec<&str> = pointer.strip_prefix('/')?.split('/').collect();
    let index = |s: &str| s.parse::<usize>().ok().filter(|_| s.bytes().all(|b| b.is_ascii_digit()));
    match parts.as_slice() {
        ["nodes", n, property] => {
            let property = match *property {
                "translation" => Property::Translation,
                "rotation" => Property::Rotation,
                "scale" => Property::Scale,
                "weights" => Property::Weights,
                _ => return None,
            };
            Some(PointerTarget::Node(index(n)?, property))
        }
        ["extensions", "KHR_lights_punctual", "lights", i, rest @ ..] => {
            let key = match rest {
                ["color"] => LightKey::Color,
                ["intensity"] => LightKey::Intensity,
                ["range"] => LightKey::Range,
                ["spot", "innerConeAngle"] => LightKey::InnerCone,
                ["spot", "outerConeAngle"] => LightKey::OuterCone,
                _ => return None,
            };
            Some(PointerTarget::Light(key, index(i)?))
        }
        ["materials", m, rest @ ..] => {
            let key = match rest {
                ["pbrMetallicRoughness", "baseColorFactor"] => MaterialKey::BaseColor,
                ["pbrMetallicRoughness", "metallicFactor"] => MaterialKey::Metallic,
                ["pbrMetallicRoughness", "roughnessFactor"] => MaterialKey::Roughness,
                ["emissiveFactor"] => MaterialKey::Emissive,
                ["extensions", "KHR_materials_emissive_strength", "emissiveStrength"] => MaterialKey::EmissiveStrength,
                ["alphaCutoff"] => MaterialKey::AlphaCutoff,
                ["normalTexture", "scale"] => MaterialKey::NormalScale,
                ["occlusionTexture", "strength"] => MaterialKey::OcclusionStrength,
                _ => return None,
            };
            Some(PointerTarget::Material(key, index(m)?))
        }
        _ => None,
    }
}

impl Loader<'_> {
    /// The pointer channels as core node channels and property channels (their rest values
    /// filled in once the scene is built, by `fill_property_rests`).
    pub(super) fn pointer_channels(&mut self) -> Result<(Vec<Channel>, Vec<PropertyChannel>), SceneError> {
        let (mut nodes, mut properties) = (Vec::new(), Vec::new());
        for pc in self.pointer_channels {
            let animation = self.root.animations.get(pc.animation);
            let label = channel_label(pc.animation, animation.and_then(|a| a.name.as_deref()), pc.channel);
            let Some(sampler) = pc.sampler.and_then(|s| animation?.samplers.get(s)) else {
                return Err(self.invalid(format!("{label}: its sampler does not exist")));
            };
            let ignore = |why: &str| format!("{label}: pointer \"{}\" {why}, ignored", pc.pointer);
            let Some(target) = parse_pointer(&pc.pointer) else {
                self.ignored.push(ignore("is not a property Chiaro animates"));
                continue;
            };
            let exists = match target {
                PointerTarget::Node(n, _) => n < self.root.nodes.len(),
                PointerTarget::Light(_, i) => self.light_count() > i,
                PointerTarget::Material(_, m) => m < self.root.materials.len(),
            };
            if !exists {
                self.ignored.push(ignore("names something the file does not have"));
                continue;
            }
            match target {
                PointerTarget::Node(node, property) => {
                    let keys = self.keyframes(sampler, KeyWidth::of(property), &label)?;
                    nodes.push(Channel { node, property, keys });
                }
                PointerTarget::Light(key, i) => {
                    let target = match key {
                        LightKey::Color => AnimatedProperty::LightColor(i),
                        LightKey::Intensity => AnimatedProperty::LightIntensity(i),
                        LightKey::Range => AnimatedProperty::LightRange(i),
                        LightKey::InnerCone => AnimatedProperty::SpotInnerCone(i),
                        LightKey::OuterCone => AnimatedProperty::SpotOuterCone(i),
                    };
                    let keys = self.keyframes(sampler, KeyWidth::Fixed(target.width()), &label)?;
                    properties.push(PropertyChannel { target, keys, rest: Vec::new() });
                }
                PointerTarget::Material(key, m) => {
                    let target = self.material_property(key, m);
                    let keys = self.keyframes(sampler, KeyWidth::Fixed(target.width()), &label)?;
                    properties.push(PropertyChannel { target, keys, rest: Vec::new() });
                }
            }
        }
        Ok((nodes, properties))
    }

    fn light_count(&self) -> usize {
        let lights = self.root.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref());
        lights.map_or(0, |l| l.lights.len())
    }

    /// The material property `key` of material `m`; the emissive factor and strength carry
    /// the other's value from the file, since the material keeps their product.
    fn material_property(&self, key: MaterialKey, m: usize) -> AnimatedProperty {
        let material = &self.root.materials[m];
        let strength = self
            .raw
            .pointer(&format!("/materials/{m}/extensions/KHR_materials_emissive_strength/emissiveStrength"))
            .and_then(Value::as_f64)
            .map_or(1.0, |s| s as f32);
        match key {
            MaterialKey::BaseColor => AnimatedProperty::BaseColorFactor(m),
            MaterialKey::Metallic => AnimatedProperty::MetallicFactor(m),
            MaterialKey::Roughness => AnimatedProperty::RoughnessFactor(m),
            MaterialKey::Emissive => AnimatedProperty::EmissiveFactor { material: m, strength },
            MaterialKey::EmissiveStrength => {
                AnimatedProperty::EmissiveStrength { material: m, factor: Vec3::from_array(material.emissive_factor.0) }
            }
            MaterialKey::AlphaCutoff => AnimatedProperty::AlphaCutoff(m),
            MaterialKey::NormalScale => AnimatedProperty::NormalScale(m),
            MaterialKey::OcclusionStrength => AnimatedProperty::OcclusionStrength(m),
        }
    }

    /// Per scene light, the KHR_lights_punctual light its node places.
    pub(super) fn light_sources(&self, lights: &[crate::types::Light]) -> Vec<Option<usize>> {
        lights
            .iter()
            .map(|l| {
                // Pointers name KHR_lights_punctual lights only.
                if l.is_area() {
                    return None;
                }
                let node = self.root.nodes.get(l.node)?;
                node.extensions.as_ref()?.khr_lights_punctual.as_ref().map(|p| p.light.value())
            })
            .collect()
    }
}

/// Each property channel's value at rest, read from the built scene; channels whose light
/// no visible node places, or whose property the light lacks (a point light's cone, a
/// range never given), have nothing to move and are dropped with a note.
pub(super) fn fill_property_rests(scene: &mut crate::types::Scene) {
    let Some(mut animation) = scene.animation.take() else { return };
    let sources = animation.light_sources.clone();
    let mut notes = Vec::new();
    animation.properties.retain_mut(|channel| {
        match crate::animation::properties::read(scene, &sources, channel.target) {
            Some(rest) => {
                channel.rest = rest;
                true
            }
            None => {
                notes.push(format!("{EXTENSION}: {:?} has nothing in the scene to animate, ignored", channel.target));
                false
            }
        }
    });
    scene.ignored.extend(notes);
    let mut rest_cones = Vec::new();
    for channel in &animation.properties {
        let (AnimatedProperty::SpotInnerCone(source) | AnimatedProperty::SpotOuterCone(source)) = channel.target else {
            continue;
        };
        let read = |target| crate::animation::properties::read(scene, &sources, target).map(|v| v[0]);
        let cones = (read(AnimatedProperty::SpotInnerCone(source)), read(AnimatedProperty::SpotOuterCone(source)));
        if let (Some(inner), Some(outer)) = cones
            && !rest_cones.iter().any(|&(s, _, _)| s == source)
        {
            rest_cones.push((source, inner, outer));
        }
    }
    animation.rest_cones = rest_cones;
    scene.animation = Some(animation);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pointers_name_nodes_lights_and_material_factors() {
        assert_eq!(parse_pointer("/nodes/3/rotation"), Some(PointerTarget::Node(3, Property::Rotation)));
        assert_eq!(
            parse_pointer("/extensions/KHR_lights_punctual/lights/0/spot/outerConeAngle"),
            Some(PointerTarget::Light(LightKey::OuterCone, 0))
        );
        assert_eq!(
            parse_pointer("/materials/12/pbrMetallicRoughness/baseColorFactor"),
            Some(PointerTarget::Material(MaterialKey::BaseColor, 12))
        );
        assert_eq!(
            parse_pointer("/materials/1/extensions/KHR_materials_emissive_strength/emissiveStrength"),
            Some(PointerTarget::Material(MaterialKey::EmissiveStrength, 1))
        );
        for unknown in [
            "/materials/1/extensions/KHR_texture_transform/offset",
            "/cameras/0/perspective/yfov",
            "nodes/0/scale",
            "/nodes/-1/scale",
            "/nodes/+1/scale",
            "",
        ] {
            assert_eq!(parse_pointer(unknown), None, "{unknown}");
        }
    }
}
