//! One light of the frame's light buffer and one entry of its light lists
//! (`shaders/lighting/light.wesl`), and the light the shadow AOV pass reports.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2, Vec3};

/// Directional, point or spot light, as the shading reads it. What an unshadowed point or
/// spot light is shaded with comes first, in three 16-byte records (colour, sphere, cone),
/// so that the culled loops read three texels of it where the lights are in a texel
/// table (docs/forward.md).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct GpuLight {
    /// Colour times intensity: lux for directional lights, nits for rect and disk
    /// lights, candela for the others.
    pub color: Vec3,
    /// `(a, b)` of the spot cone `saturate(dot(direction, -l) * a + b)^2`; (0, 1) for
    /// lights that never fade by angle. A spot's `a` is positive (`spot_angle_params`).
    pub spot_scale: f32,
    /// World-space position, metres; unused by directional lights.
    pub position_ws: Vec3,
    /// Where the range window reaches zero; unused by directional lights.
    pub range: f32,
    /// Unit vector the light shines along (spot axis, sun direction); unused by points.
    pub direction_ws: Vec3,
    /// See `spot_scale`.
    pub spot_offset: f32,
    /// `LIGHT_KIND_*`.
    pub kind: u32,
    /// `SHADOW_SLOT_*`.
    pub shadow_slot: u32,
    /// 0 to 1: how dark its realtime shadow is.
    pub shadow_strength: f32,
    /// First tile of its atlas (directional: one per cascade; spot: one; point: six).
    pub shadow_first_tile: u32,
    /// `SHADOW_FILTER_*`.
    pub shadow_filter: u32,
    /// Its cookie's layer (2D array for directional and spot lights, cube array for
    /// points), or `NO_COOKIE`.
    pub cookie_layer: u32,
    /// Directional: (1 / width, 1 / height), metres; spot: (1 / tan(outer), 0); rect and
    /// disk lights (which have no cookie): half their extent along local X and Y, metres.
    pub cookie_scale: Vec2,
    /// The light's local +X and +Y, which orient its cookie.
    pub axis_x_ws: Vec3,
    /// Its shadow mask channel (0 to 3), or `NO_MASK_CHANNEL`.
    pub shadow_mask_channel: u32,
    /// See `axis_x_ws`.
    pub axis_y_ws: Vec3,
    /// The light's size for contact-hardening shadows: a point or spot light's radius in
    /// metres, tan of half a directional light's angular diameter, the radius of an area
    /// light's area as a disc.
    pub shadow_light_size: f32,
}

/// One light volume of the deferred path, at a dynamic offset.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct GpuVolumeLight {
    /// The volume mesh (unit sphere or pyramid) to world space.
    pub world_from_volume: Mat4,
    /// The light the volume shades.
    pub light: GpuLight,
}

/// One entry of the frame's light lists: an index into the light buffer.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct GpuLightListEntry {
    /// Index into the frame's light buffer.
    pub light: u32,
    /// Pads the entry to 16 bytes (uniform arrays stride by 16).
    pub _pad: [u32; 3],
}

/// The light the shadow AOV pass reports, at a dynamic offset.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuAovLight {
    /// The light's index in the frame's light buffer (`FramePlan::lights`), or `NO_LIGHT`.
    pub light_index: u32,
    /// Pads the struct to 16 bytes.
    pub _pad: [u32; 3],
}
