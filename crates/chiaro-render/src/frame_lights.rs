//! Chooses and packs the lights a frame shades: up to four directional lights, and the
//! most important visible point and spot lights (chiaro_math::light::select_other_lights).

use crate::gpu_types::{GpuDirectionalLight, GpuLights, GpuOtherLight};
use crate::view::View;
use chiaro_math::Frustum;
use chiaro_math::light::{
    LightSelection, MAX_DIRECTIONAL_LIGHTS, OtherLightBounds, derived_range, select_other_lights, spot_angle_params,
};
use chiaro_scene::{Light, LightKind, Scene, Settings};
use glam::{Vec2, Vec3};

/// The packed lights and what was left out.
pub struct FrameLights {
    pub gpu: GpuLights,
    pub directional_count: u32,
    pub other_count: u32,
    /// Scene light index of each shaded directional light, in slot order.
    pub directional_scene_index: Vec<usize>,
    /// Scene light index of each shaded other light, in upload order.
    pub other_scene_index: Vec<usize>,
    pub dropped_directional: usize,
    pub selection: LightSelection,
}

/// The range a light is shaded with: its own, or one derived from its intensity.
pub fn effective_range(light: &Light, settings: &Settings) -> f32 {
    light.range.unwrap_or_else(|| {
        derived_range(light.intensity * light.color.max_element(), settings.lights.range_threshold_lux)
    })
}

pub fn prepare_lights(scene: &Scene, view: &View, settings: &Settings) -> FrameLights {
    let mut gpu = GpuLights {
        directional: [GpuDirectionalLight::default(); MAX_DIRECTIONAL_LIGHTS],
        other: [GpuOtherLight::default(); chiaro_math::light::MAX_OTHER_LIGHTS],
    };
    let directional_scene_index: Vec<usize> = scene
        .lights
        .iter()
        .enumerate()
        .filter(|(_, l)| l.kind == LightKind::Directional)
        .map(|(i, _)| i)
        .take(MAX_DIRECTIONAL_LIGHTS)
        .collect();
    let directional: Vec<&Light> = scene.lights.iter().filter(|l| l.kind == LightKind::Directional).collect();
    let directional_count = directional.len().min(MAX_DIRECTIONAL_LIGHTS);
    for (slot, light) in gpu.directional.iter_mut().zip(&directional) {
        *slot = GpuDirectionalLight {
            color: light.color * light.intensity,
            direction_to_light_ws: -light.direction.normalize_or(Vec3::NEG_Y),
            ..Default::default()
        };
    }
    let dropped_directional = directional.len() - directional_count;
    if dropped_directional > 0 {
        tracing::warn!(
            "{dropped_directional} directional lights over the limit of {MAX_DIRECTIONAL_LIGHTS} are not shaded"
        );
    }

    let others: Vec<usize> =
        scene.lights.iter().enumerate().filter(|(_, l)| l.kind != LightKind::Directional).map(|(i, _)| i).collect();
    let bounds: Vec<OtherLightBounds> = others
        .iter()
        .map(|&i| {
            let l = &scene.lights[i];
            OtherLightBounds {
                position: l.position,
                range: effective_range(l, settings),
                peak_intensity: l.intensity * l.color.max_element(),
                spot: match l.kind {
                    LightKind::Spot { outer_cone_rad, .. } => Some((l.direction, outer_cone_rad)),
                    _ => None,
                },
            }
        })
        .collect();
    let selection = select_other_lights(
        &bounds,
        &Frustum::from_clip_from_world(&view.clip_from_world()),
        view.eye(),
        settings.lights.max_other_lights as usize,
    );
    if selection.dropped > 0 {
        tracing::warn!(
            "{} visible point/spot lights over the limit of {} are not shaded",
            selection.dropped,
            settings.lights.max_other_lights
        );
    }
    let mut other_scene_index = Vec::with_capacity(selection.visible.len());
    for (slot, &k) in gpu.other.iter_mut().zip(&selection.visible) {
        let light = &scene.lights[others[k]];
        other_scene_index.push(others[k]);
        let spot_angles = match light.kind {
            LightKind::Spot { inner_cone_rad, outer_cone_rad } => {
                let (a, b) = spot_angle_params(inner_cone_rad, outer_cone_rad);
                Vec2::new(a, b)
            }
            // saturate(x * 0 + 1)^2 = 1: a point light is a spot that never fades.
            _ => Vec2::new(0.0, 1.0),
        };
        *slot = GpuOtherLight {
            position_ws: light.position,
            range: bounds[k].range,
            color: light.color * light.intensity,
            spot_direction_ws: light.direction.normalize_or(Vec3::NEG_Z),
            spot_angles,
            ..Default::default()
        };
    }
    FrameLights {
        gpu,
        directional_count: directional_count as u32,
        directional_scene_index,
        other_count: other_scene_index.len() as u32,
        other_scene_index,
        dropped_directional,
        selection,
    }
}
