//! The per-frame uniform and the per-object transforms (`shaders/common/frame.wesl`).

use crate::shader_constants::{NO_NODE, OBJECT_LIGHTMAPPED, OBJECT_PROBE_LIT, OBJECT_RECEIVES_SHADOWS};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

/// The per-frame uniform (`Frame` in `shaders/common/frame.wesl`): camera matrices, exposure,
/// ambient light, light counts and the clustered-culling grid.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuFrame {
    /// World space to reverse-Z clip space.
    pub clip_from_world: Mat4,
    /// World space to the camera's view space (right-handed, -Z forward).
    pub view_from_world: Mat4,
    /// For rebuilding positions from the G-buffer's view depth.
    pub world_from_view: Mat4,
    /// Clip space back to view space.
    pub view_from_clip: Mat4,
    /// The camera's position in world space, metres.
    pub camera_position_ws: Vec3,
    /// Linear scale applied to radiance before it is stored (pre-exposure).
    pub exposure_scale: f32,
    /// Linear RGB ambient radiance added to every surface.
    pub ambient: Vec3,
    /// `DEBUG_VIEW_*`.
    pub debug_view: u32,
    /// The frame's light index list holds, in order, this many directional lights, then
    /// the shadowed point and spot lights, then the rest: `local_light_count` in all.
    pub directional_light_count: u32,
    /// Shadowed point and spot lights, listed right after the directional ones.
    pub shadowed_local_light_count: u32,
    /// Point and spot lights in the list, shadowed and unshadowed together.
    pub local_light_count: u32,
    /// The output size in pixels.
    pub width: u32,
    /// The output height in pixels.
    pub height: u32,
    /// `MIXED_MODE_*`: how mixed lights' baked and realtime shadows combine.
    pub mixed_mode: u32,
    /// Pixels per cluster tile, across and down (clustered light culling).
    pub cluster_tile_width: u32,
    /// Pixels per cluster tile down.
    pub cluster_tile_height: u32,
    /// A pixel's depth slice is `floor(log2(view depth) * scale + bias)`.
    pub cluster_slice_scale: f32,
    /// See `cluster_slice_scale`.
    pub cluster_slice_bias: f32,
    /// Cluster tiles across and down.
    pub cluster_tiles_x: u32,
    /// See `cluster_tiles_x`.
    pub cluster_tiles_y: u32,
    /// 1 for an orthographic camera (parallel rays: the view direction is the camera's
    /// backward axis everywhere), 0 for a perspective one.
    pub orthographic: u32,
    /// Pads the struct to 16 bytes.
    pub _pad: [u32; 3],
}

/// One object (a mesh instance) as `shaders/common/frame.wesl` reads it: its transforms
/// and flags.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuObject {
    /// Local (mesh) space to world space.
    pub world_from_local: Mat4,
    /// Inverse transpose of `world_from_local`, for normals and tangents.
    pub normal_from_local: Mat4,
    /// `OBJECT_*` bits.
    pub flags: u32,
    /// Its lightmap's layer in the lightmap array, with `OBJECT_LIGHTMAPPED`.
    pub lightmap_layer: u32,
    /// The glTF node that places it, for the id pass; `NO_NODE` for none.
    pub node: u32,
    /// Its node's `extras.label`, 0 if none.
    pub label: u32,
}

/// The head of the light probe buffer (`shaders/lighting/baked.wesl`); nine RGB
/// coefficients (as vec4) per probe follow, x varying fastest, then y, then z.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuProbeGridHeader {
    /// World-space position of the grid's first probe, metres.
    pub origin: Vec3,
    /// The lightmaps hold irradiance divided by this, so that bright bakes (a 100,000 lux
    /// sun) stay within half floats.
    pub lightmap_scale: f32,
    /// Distance between neighbouring probes along x, y and z, metres.
    pub spacing: Vec3,
    /// Pads `spacing` to 16 bytes.
    pub _pad1: f32,
    /// Probes along x, y and z.
    pub counts: [u32; 3],
    /// Pads the header to 16-byte alignment.
    pub _pad2: u32,
}

impl GpuObject {
    /// An object at `world_from_local`, with its normal matrix, not lightmapped.
    pub fn new(world_from_local: Mat4, receives_shadows: bool) -> GpuObject {
        GpuObject {
            world_from_local,
            normal_from_local: world_from_local.inverse().transpose(),
            flags: if receives_shadows { OBJECT_RECEIVES_SHADOWS } else { 0 },
            lightmap_layer: 0,
            node: NO_NODE,
            label: 0,
        }
    }

    /// Placed by glTF node `node`, labelled `label`, as the id pass writes them.
    pub fn identified(self, node: usize, label: u32) -> GpuObject {
        GpuObject { node: u32::try_from(node).unwrap_or(NO_NODE), label, ..self }
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
