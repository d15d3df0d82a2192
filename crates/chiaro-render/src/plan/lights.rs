//! Which lights a frame shades: up to four directional lights, and the most important
//! visible point and spot lights (chiaro_math::light::select_local_lights), each known by
//! the stable id of its scene light; and the GPU record of each.

use super::shadows::ShadowSlot;
use crate::gpu::GpuLight;
use crate::shader_constants::{
    LIGHT_KIND_DIRECTIONAL, LIGHT_KIND_DISK, LIGHT_KIND_POINT, LIGHT_KIND_RECT, LIGHT_KIND_SPOT, NO_COOKIE,
    NO_MASK_CHANNEL, SHADOW_FILTER_PCSS, SHADOW_SLOT_BAKED_ONLY, SHADOW_SLOT_NONE, SHADOW_SLOT_REALTIME,
    SHADOW_SLOT_VIRTUAL,
};
use crate::view::View;
use chiaro_math::Frustum;
use chiaro_math::light::{
    LightSelection, LocalLightBounds, MAX_DIRECTIONAL_LIGHTS, select_local_lights, spot_angle_params,
};
use chiaro_scene::{Light, LightKind, LightMode, Scene, Settings};
use glam::Vec2;

/// A light's index in `Scene::lights`: the same light has the same id in every frame of
/// the same scene, so atlas tiles (and later caches and cluster lists) can be keyed by it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LightId(pub u32);

impl LightId {
    /// The index into `Scene::lights`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// One light the frame shades.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameLight {
    /// Which scene light.
    pub id: LightId,
    /// The range it is shaded with (its own, or derived from its intensity); infinite for
    /// directional lights.
    pub range: f32,
    /// Where its realtime shadow comes from.
    pub shadow: ShadowSlot,
}

/// The lights chosen for a frame, before shadows are planned.
#[derive(Clone, Debug, Default)]
pub struct LightChoice {
    /// Directional lights in scene order, at most `MAX_DIRECTIONAL_LIGHTS`.
    pub directional: Vec<LightId>,
    /// Visible point and spot lights, most important first, with their ranges.
    pub local: Vec<(LightId, f32)>,
    /// Directional lights over the limit.
    pub dropped_directional: usize,
    /// The visible point and spot lights as chiaro_math chose them (with drop and cull
    /// counts).
    pub selection: LightSelection,
}

/// Chooses the frame's lights: directional ones up to the limit, then the point and spot
/// lights the view can see, most important first (baked lights skipped when a bake is
/// applied).
pub fn choose_lights(scene: &Scene, view: &View, settings: &Settings) -> LightChoice {
    let id = |i: usize| LightId(i as u32);
    // With a bake applied, baked lights live in the lightmaps and probes alone.
    let skip_baked = scene.skips_baked_lights();
    // One pass over the scene's lights (thousands, in some scenes): the directional ones
    // apart, and the bounds of each point and spot light.
    let mut all_directional = Vec::new();
    let mut locals = Vec::with_capacity(scene.lights.len());
    let mut bounds = Vec::with_capacity(scene.lights.len());
    for (i, l) in scene.lights.iter().enumerate() {
        if skip_baked && l.mode == LightMode::Baked {
            continue;
        }
        let spot = match l.kind {
            LightKind::Directional => {
                all_directional.push(i);
                continue;
            }
            LightKind::Spot { outer_cone_rad, .. } => Some((l.direction(), outer_cone_rad)),
            // Area lights are bounded as points of their range, which reaches past their
            // extent (Light::shaded_range).
            LightKind::Point | LightKind::Rect { .. } | LightKind::Disk { .. } => None,
        };
        locals.push(i);
        bounds.push(LocalLightBounds {
            position: l.position(),
            range: l.shaded_range(settings.lights.range_threshold_lux),
            peak_intensity: l.peak_intensity_cd(),
            spot,
        });
    }
    let dropped_directional = all_directional.len().saturating_sub(MAX_DIRECTIONAL_LIGHTS);
    if dropped_directional > 0 {
        tracing::warn!(
            "{dropped_directional} directional lights over the limit of {MAX_DIRECTIONAL_LIGHTS} are not shaded"
        );
    }
    let directional = all_directional.iter().take(MAX_DIRECTIONAL_LIGHTS).map(|&i| id(i)).collect();

    let selection = select_local_lights(
        &bounds,
        &Frustum::from_clip_from_world(&view.clip_from_world()),
        view.eye(),
        settings.max_other_lights() as usize,
    );
    if selection.dropped > 0 {
        tracing::warn!(
            "{} visible point/spot lights over the limit of {} are not shaded",
            selection.dropped,
            settings.max_other_lights()
        );
    }
    let local = selection.visible.iter().map(|&k| (id(locals[k]), bounds[k].range)).collect();
    LightChoice { directional, local, dropped_directional, selection }
}

/// The light as the shaders read it; `cookie_layer` from `cookies::cookie_slots`,
/// `mask_channel` from the scene's bake.
pub fn gpu_light(
    light: &Light,
    frame_light: &FrameLight,
    cookie_layer: Option<u32>,
    mask_channel: Option<u8>,
) -> GpuLight {
    let (kind, (spot_scale, spot_offset)) = match light.kind {
        LightKind::Directional => (LIGHT_KIND_DIRECTIONAL, (0.0, 1.0)),
        // saturate(x * 0 + 1)^2 = 1: a point light is a spot that never fades.
        LightKind::Point => (LIGHT_KIND_POINT, (0.0, 1.0)),
        LightKind::Spot { inner_cone_rad, outer_cone_rad } => {
            (LIGHT_KIND_SPOT, spot_angle_params(inner_cone_rad, outer_cone_rad))
        }
        LightKind::Rect { .. } => (LIGHT_KIND_RECT, (0.0, 1.0)),
        LightKind::Disk { .. } => (LIGHT_KIND_DISK, (0.0, 1.0)),
    };
    let (shadow_slot, shadow_first_tile, shadow_filter) = match frame_light.shadow {
        ShadowSlot::None => (SHADOW_SLOT_NONE, 0, 0),
        ShadowSlot::Realtime { first_tile, pcss, filter, virtual_map, .. } => (
            if virtual_map { SHADOW_SLOT_VIRTUAL } else { SHADOW_SLOT_REALTIME },
            first_tile,
            if pcss { SHADOW_FILTER_PCSS } else { filter.index() },
        ),
        ShadowSlot::BakedOnly => (SHADOW_SLOT_BAKED_ONLY, 0, 0),
    };
    GpuLight {
        color: light.color * light.intensity,
        kind,
        position_ws: light.position(),
        range: frame_light.range,
        direction_ws: light.direction(),
        shadow_slot,
        spot_scale,
        spot_offset,
        shadow_strength: light.shadow.strength,
        shadow_first_tile,
        shadow_filter,
        cookie_layer: cookie_layer.unwrap_or(NO_COOKIE),
        cookie_scale: match (light.kind, light.cookie) {
            (LightKind::Directional, Some(c)) => Vec2::ONE / c.size_m,
            (LightKind::Spot { outer_cone_rad, .. }, Some(_)) => Vec2::new(1.0 / outer_cone_rad.tan(), 0.0),
            (LightKind::Rect { .. } | LightKind::Disk { .. }, _) => {
                light.kind.area_shape().map_or(Vec2::ZERO, |shape| shape.half_extents())
            }
            _ => Vec2::ZERO,
        },
        axis_x_ws: light.world_from_light.x_axis.truncate(),
        shadow_mask_channel: mask_channel.map_or(NO_MASK_CHANNEL, u32::from),
        axis_y_ws: light.world_from_light.y_axis.truncate(),
        shadow_light_size: match light.kind {
            LightKind::Directional => (light.shadow.angular_diameter_deg.to_radians() * 0.5).tan(),
            // The radius of the disc of the light's area.
            LightKind::Rect { .. } | LightKind::Disk { .. } => {
                light.kind.area_shape().map_or(0.0, |shape| (shape.area() / std::f32::consts::PI).sqrt())
            }
            _ => light.shadow.light_radius,
        },
    }
}
