//! Which lights a bake traces and how: the shadow mask channel of each shadowed mixed
//! light, the mode each light is baked with (a mixed light left without a channel is
//! baked instead), and each channel's tracer slot. A scene and its settings flow in.

use crate::channels::{ChannelAssignment, ChannelCandidate, assign_channels, spot_bounds};
use crate::tracer::Tracer;
use chiaro_scene::{LightKind, LightMode, Scene, Settings};

/// Shadow mask channels for the scene's shadowed mixed lights; none where the mixed
/// lighting mode bakes no mask.
pub(super) fn shadow_mask_channels(scene: &Scene, settings: &Settings) -> ChannelAssignment {
    if !settings.lighting.mixed_mode.uses_shadow_mask() {
        return ChannelAssignment::default();
    }
    let candidates: Vec<ChannelCandidate> = scene
        .lights
        .iter()
        .enumerate()
        .filter(|(_, l)| l.mode == LightMode::Mixed && l.shadow.casts())
        .map(|(light, l)| {
            let range = l.shaded_range(settings.lights.range_threshold_lux);
            ChannelCandidate {
                light,
                importance: l.peak_intensity_cd(),
                bounds: match l.kind {
                    LightKind::Directional => None,
                    LightKind::Point | LightKind::Rect { .. } | LightKind::Disk { .. } => Some((l.position(), range)),
                    LightKind::Spot { outer_cone_rad, .. } => {
                        Some(spot_bounds(l.position(), l.direction(), range, outer_cone_rad))
                    }
                },
            }
        })
        .collect();
    assign_channels(&candidates)
}

/// Each scene light's mode for this bake: the file's, with demoted mixed lights baked.
pub(super) fn bake_modes(scene: &Scene, assignment: &ChannelAssignment) -> Vec<LightMode> {
    let mut modes: Vec<LightMode> = scene.lights.iter().map(|l| l.mode).collect();
    for &light in &assignment.demoted {
        modes[light] = LightMode::Baked;
    }
    if !assignment.demoted.is_empty() {
        let names: Vec<&str> = assignment.demoted.iter().map(|&l| scene.lights[l].name.as_str()).collect();
        tracing::warn!(
            "{} mixed lights each overlap four others and find no shadow mask channel left: baked instead: {}",
            names.len(),
            chiaro_scene::names::few_names(&names)
        );
    }
    modes
}

/// Each channel's (channel, scene light, tracer slot): mixed lights are all traced.
pub(super) fn channel_lights(assignment: &ChannelAssignment, tracer: &Tracer) -> Vec<(usize, usize, usize)> {
    assignment
        .channels
        .iter()
        .filter_map(|&(light, channel)| Some((channel as usize, light, tracer.light_slot(light)?)))
        .collect()
}
