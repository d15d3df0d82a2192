//! The per-frame uniform and the per-object transforms (`shaders/common/frame.wesl`).

use crate::shader_constants::{OBJECT_LIGHTMAPPED, OBJECT_PROBE_LIT, OBJECT_RECEIVES_SHADOWS};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuFrame {
    pub clip_from_world: Mat4,
    pub view_from_world: Mat4,
    /// For rebuilding positions from the G-buffer's view depth.
    pub world_from_view: Mat4,
    pub view_from_clip: Mat4,
    pub camera_position_ws: Vec3,
    /// Linear scale applied to radiance before it is stored (pre-exposure).
    pub exposure_scale: f32,
    pub ambient: Vec3,
    /// `DEBUG_VIEW_*`.
    pub debug_view: u32,
    /// The frame's light index list holds, in order, this many directional lights, then
    /// the shadowed point and spot lights, then the rest: `other_light_count` in all.
    pub directional_light_count: u32,
    pub shadowed_other_light_count: u32,
    pub other_light_count: u32,
    /// The output size in pixels.
    pub width: u32,
    pub height: u32,
    /// `MIXED_MODE_*`: how mixed lights' baked and realtime shadows combine.
    pub mixed_mode: u32,
    /// Pixels per cluster tile, across and down (clustered light culling).
    pub cluster_tile_width: u32,
    pub cluster_tile_height: u32,
    /// A pixel's depth slice is `floor(log2(view depth) * scale + bias)`.
    pub cluster_slice_scale: f32,
    pub cluster_slice_bias: f32,
    pub _pad: [u32; 2],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuObject {
    pub world_from_local: Mat4,
    /// Inverse transpose of `world_from_local`, for normals and tangents.
    pub normal_from_local: Mat4,
    /// `OBJECT_*` bits.
    pub flags: u32,
    /// Its lightmap's layer in the lightmap array, with `OBJECT_LIGHTMAPPED`.
    pub lightmap_layer: u32,
    pub _pad: [u32; 2],
}

/// The head of the light probe buffer (`shaders/lighting/baked.wesl`); nine RGB
/// coefficients (as vec4) per probe follow, x varying fastest, then y, then z.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuProbeGridHeader {
    pub origin: Vec3,
    /// The lightmaps hold irradiance divided by this, so that bright bakes (a 100,000 lux
    /// sun) stay within half floats.
    pub lightmap_scale: f32,
    pub spacing: Vec3,
    pub _pad1: f32,
    pub counts: [u32; 3],
    pub _pad2: u32,
}

impl GpuObject {
    pub fn new(world_from_local: Mat4, receives_shadows: bool) -> GpuObject {
        GpuObject {
            world_from_local,
            normal_from_local: world_from_local.inverse().transpose(),
            flags: if receives_shadows { OBJECT_RECEIVES_SHADOWS } else { 0 },
            lightmap_layer: 0,
            _pad: [0; 2],
        }
    }

    /// Lit by layer `layer` of the lightmaps instead of the ambient term.
    pub fn lightmapped(self, layer: u32) -> GpuObject {
        GpuObject { flags: self.flags | OBJECT_LIGHTMAPPED, lightmap_layer: layer, ..self }
    }

    /// Lit by the light probes instead of the ambient term.
    pub fn probe_lit(self) -> GpuObject {
        GpuObject { flags: self.flags | OBJECT_PROBE_LIT, ..self }
    }
}
