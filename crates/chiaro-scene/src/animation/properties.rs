//! KHR_animation_pointer's light and material properties: which property a channel moves,
//! how a sampled value is written into the scene, and how it is read back (for the rest
//! value a pose without a time restores). Sampled values are held to what the importer
//! accepts from a file (a cubic spline may overshoot its keys): colours and factors to
//! their ranges, intensities and ranges non-negative, spot cones ordered.

use super::sample::Keyframes;
use crate::types::{LightKind, Scene};
use chiaro_math::light::MAX_LIGHT_INTENSITY;
use glam::{Vec3, Vec4};

/// A light (by its index in KHR_lights_punctual's list, which every node placing it
/// shares) or material (by index) property.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnimatedProperty {
    /// `color`, linear RGB.
    LightColor(usize),
    /// `intensity`, candela or lux.
    LightIntensity(usize),
    /// `range`, metres.
    LightRange(usize),
    /// `spot.innerConeAngle`, radians.
    SpotInnerCone(usize),
    /// `spot.outerConeAngle`, radians.
    SpotOuterCone(usize),
    /// `pbrMetallicRoughness.baseColorFactor`, linear RGBA.
    BaseColorFactor(usize),
    /// `pbrMetallicRoughness.metallicFactor`.
    MetallicFactor(usize),
    /// `pbrMetallicRoughness.roughnessFactor`.
    RoughnessFactor(usize),
    /// `emissiveFactor`, times the material's (unanimated) emissive strength.
    EmissiveFactor {
        /// The material's index.
        material: usize,
        /// Its KHR_materials_emissive_strength, 1 without.
        strength: f32,
    },
    /// KHR_materials_emissive_strength's `emissiveStrength`, times the material's
    /// (unanimated) emissive factor.
    EmissiveStrength {
        /// The material's index.
        material: usize,
        /// Its emissive factor, linear RGB.
        factor: Vec3,
    },
    /// `alphaCutoff`.
    AlphaCutoff(usize),
    /// `normalTexture.scale`.
    NormalScale(usize),
    /// `occlusionTexture.strength`.
    OcclusionStrength(usize),
}

impl AnimatedProperty {
    /// Floats per value.
    pub fn width(self) -> usize {
        match self {
            AnimatedProperty::LightColor(_) | AnimatedProperty::EmissiveFactor { .. } => 3,
            AnimatedProperty::BaseColorFactor(_) => 4,
            _ => 1,
        }
    }
}

/// One animated property: its keys and its value at rest.
#[derive(Clone, Debug, PartialEq)]
pub struct PropertyChannel {
    /// What it animates.
    pub target: AnimatedProperty,
    /// Its keyframes, `target.width()` floats a value.
    pub keys: Keyframes,
    /// The value the file gives the property, `target.width()` floats.
    pub rest: Vec<f32>,
}

/// The property's current value in `scene`; `None` where the light or material is not in
/// it (a light no visible node places, an index past the list).
pub fn read(scene: &Scene, light_sources: &[Option<usize>], target: AnimatedProperty) -> Option<Vec<f32>> {
    use AnimatedProperty as P;
    let light = |i: usize| {
        let k = light_sources.iter().position(|&s| s == Some(i))?;
        scene.lights.get(k)
    };
    let cone = |i: usize, outer: bool| match light(i)?.kind {
        LightKind::Spot { inner_cone_rad, outer_cone_rad } => {
            Some(vec![if outer { outer_cone_rad } else { inner_cone_rad }])
        }
        _ => None,
    };
    let material = |m: usize| scene.materials.get(m);
    match target {
        P::LightColor(i) => light(i).map(|l| l.color.to_array().to_vec()),
        P::LightIntensity(i) => light(i).map(|l| vec![l.intensity]),
        // A light without a range reaches everywhere: infinity at rest.
        P::LightRange(i) => light(i).map(|l| vec![l.range.unwrap_or(f32::INFINITY)]),
        P::SpotInnerCone(i) => cone(i, false),
        P::SpotOuterCone(i) => cone(i, true),
        P::BaseColorFactor(m) => material(m).map(|m| m.base_color.to_array().to_vec()),
        P::MetallicFactor(m) => material(m).map(|m| vec![m.metallic]),
        P::RoughnessFactor(m) => material(m).map(|m| vec![m.roughness]),
        P::EmissiveFactor { material: m, strength } => {
            material(m).map(|m| (m.emissive / strength.max(f32::MIN_POSITIVE)).to_array().to_vec())
        }
        P::EmissiveStrength { material: m, factor } => {
            let largest = factor.max_element();
            material(m).map(|m| vec![if largest > 0.0 { m.emissive.max_element() / largest } else { 1.0 }])
        }
        P::AlphaCutoff(m) => material(m).map(|m| vec![m.alpha_cutoff]),
        P::NormalScale(m) => material(m).map(|m| vec![m.normal_scale]),
        P::OcclusionStrength(m) => material(m).map(|m| vec![m.occlusion_strength]),
    }
}

/// Gives every scene light placing KHR_lights_punctual spot `source` the cones
/// `(inner, outer)`.
pub fn reset_cones(scene: &mut Scene, light_sources: &[Option<usize>], source: usize, inner: f32, outer: f32) {
    for (light, _) in scene.lights.iter_mut().zip(light_sources).filter(|(_, s)| **s == Some(source)) {
        if let LightKind::Spot { inner_cone_rad, outer_cone_rad } = &mut light.kind {
            (*inner_cone_rad, *outer_cone_rad) = (inner, outer);
        }
    }
}

/// Writes `value` (`target.width()` floats) into every light placing the animated light,
/// or into the material, held to the property's range.
pub fn write(scene: &mut Scene, light_sources: &[Option<usize>], target: AnimatedProperty, value: &[f32]) {
    use AnimatedProperty as P;
    let v = value.first().copied().unwrap_or(0.0);
    let unit = v.clamp(0.0, 1.0);
    match target {
        P::LightColor(i) | P::LightIntensity(i) | P::LightRange(i) | P::SpotInnerCone(i) | P::SpotOuterCone(i) => {
            let placed = scene.lights.iter_mut().zip(light_sources).filter(|(_, s)| **s == Some(i));
            for (light, _) in placed {
                match target {
                    P::LightColor(_) => light.color = Vec3::from_slice(value).max(Vec3::ZERO),
                    P::LightIntensity(_) => light.intensity = v.clamp(0.0, MAX_LIGHT_INTENSITY),
                    // A range of zero lights nothing and divides by zero; infinity is the
                    // rest value of a light without one.
                    P::LightRange(_) => light.range = v.is_finite().then_some(v.max(1.0e-3)),
                    _ => {
                        if let LightKind::Spot { inner_cone_rad, outer_cone_rad } = &mut light.kind {
                            let half_pi = std::f32::consts::FRAC_PI_2;
                            if matches!(target, P::SpotOuterCone(_)) {
                                *outer_cone_rad = v.clamp(2.0e-4, half_pi);
                            } else {
                                *inner_cone_rad = v.max(0.0);
                            }
                            // Ordered as the importer orders a file's cones; the pose
                            // started from the file's cones (`reset_cones`), so this
                            // narrowing lasts one pose.
                            *inner_cone_rad = inner_cone_rad.min(*outer_cone_rad - 1.0e-4);
                        }
                    }
                }
            }
        }
        P::BaseColorFactor(m) | P::MetallicFactor(m) | P::RoughnessFactor(m) | P::AlphaCutoff(m) => {
            let Some(material) = scene.materials.get_mut(m) else { return };
            match target {
                P::BaseColorFactor(_) => material.base_color = Vec4::from_slice(value).clamp(Vec4::ZERO, Vec4::ONE),
                P::MetallicFactor(_) => material.metallic = unit,
                P::RoughnessFactor(_) => material.roughness = unit,
                _ => material.alpha_cutoff = v.max(0.0),
            }
        }
        P::EmissiveFactor { material: m, strength } => {
            if let Some(material) = scene.materials.get_mut(m) {
                material.emissive = Vec3::from_slice(value).clamp(Vec3::ZERO, Vec3::ONE) * strength;
            }
        }
        P::EmissiveStrength { material: m, factor } => {
            if let Some(material) = scene.materials.get_mut(m) {
                material.emissive = factor * v.max(0.0);
            }
        }
        P::NormalScale(m) => {
            if let Some(material) = scene.materials.get_mut(m) {
                material.normal_scale = v;
            }
        }
        P::OcclusionStrength(m) => {
            if let Some(material) = scene.materials.get_mut(m) {
                material.occlusion_strength = unit;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::{Light, Material};

    fn scene() -> Scene {
        let spot = LightKind::Spot { inner_cone_rad: 0.2, outer_cone_rad: 0.5 };
        Scene {
            lights: vec![
                Light::new(spot, Vec3::Y, Vec3::NEG_Y),
                Light::new(LightKind::Point, Vec3::X, Vec3::NEG_Y),
                Light::new(spot, Vec3::Z, Vec3::NEG_Y),
            ],
            materials: vec![Material { emissive: Vec3::new(2.0, 1.0, 0.0), ..Material::default() }],
            ..Scene::default()
        }
    }

    #[test]
    fn values_reach_every_placement_of_a_light_and_read_back() {
        let mut scene = scene();
        // Lights 0 and 2 place file light 3; light 1 places file light 0.
        let sources = [Some(3), Some(0), Some(3)];
        write(&mut scene, &sources, AnimatedProperty::LightColor(3), &[0.5, 0.25, 1.0]);
        assert_eq!([scene.lights[0].color, scene.lights[2].color], [Vec3::new(0.5, 0.25, 1.0); 2]);
        assert_eq!(scene.lights[1].color, Vec3::ONE);
        assert_eq!(read(&scene, &sources, AnimatedProperty::LightColor(3)), Some(vec![0.5, 0.25, 1.0]));
        assert_eq!(read(&scene, &sources, AnimatedProperty::LightColor(7)), None, "no node places light 7");
        write(&mut scene, &sources, AnimatedProperty::SpotOuterCone(3), &[0.1]);
        assert_eq!(read(&scene, &sources, AnimatedProperty::SpotOuterCone(3)), Some(vec![0.1]));
        let inner = read(&scene, &sources, AnimatedProperty::SpotInnerCone(3)).unwrap()[0];
        assert!(inner < 0.1, "a narrowed outer cone pulls the inner one in: {inner}");
        assert_eq!(read(&scene, &sources, AnimatedProperty::SpotInnerCone(0)), None, "a point light has no cone");
    }

    #[test]
    fn overshooting_values_are_held_to_their_ranges() {
        let mut scene = scene();
        let sources = [Some(0), None, None];
        write(&mut scene, &sources, AnimatedProperty::LightIntensity(0), &[-3.0]);
        write(&mut scene, &sources, AnimatedProperty::LightColor(0), &[-1.0, 0.5, 2.0]);
        write(&mut scene, &sources, AnimatedProperty::BaseColorFactor(0), &[1.2, -0.1, 0.5, 1.0]);
        write(&mut scene, &sources, AnimatedProperty::RoughnessFactor(0), &[1.5]);
        write(
            &mut scene,
            &sources,
            AnimatedProperty::EmissiveStrength { material: 0, factor: Vec3::new(1.0, 0.5, 0.0) },
            &[4.0],
        );
        assert_eq!(scene.lights[0].intensity, 0.0);
        assert_eq!(scene.lights[0].color, Vec3::new(0.0, 0.5, 2.0));
        let m = &scene.materials[0];
        assert_eq!((m.base_color, m.roughness), (Vec4::new(1.0, 0.0, 0.5, 1.0), 1.0));
        assert_eq!(m.emissive, Vec3::new(4.0, 2.0, 0.0));
        let strength = AnimatedProperty::EmissiveStrength { material: 0, factor: Vec3::new(1.0, 0.5, 0.0) };
        assert_eq!(read(&scene, &sources, strength), Some(vec![4.0]));
    }
}
