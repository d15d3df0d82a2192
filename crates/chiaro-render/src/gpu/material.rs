//! glTF metallic-roughness materials as `shaders/common/material.wesl` reads them.

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3, Vec4};

/// KHR_texture_transform and the UV set of one texture slot.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuTextureTransform {
    /// Columns of the 2x2 part: (m00, m01, m10, m11).
    pub linear: Vec4,
    pub offset: Vec2,
    /// 0 or 1: TEXCOORD_0 or TEXCOORD_1.
    pub uv_set: u32,
    pub _pad: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuMaterial {
    pub base_color: Vec4,
    pub emissive: Vec3,
    pub metallic: f32,
    pub roughness: f32,
    pub normal_scale: f32,
    pub occlusion_strength: f32,
    pub alpha_cutoff: f32,
    /// `MATERIAL_ALPHA_*`.
    pub alpha_mode: u32,
    /// 1 for double-sided materials.
    pub double_sided: u32,
    /// `MATERIAL_FLAG_*` bits.
    pub flags: u32,
    pub _pad: u32,
    pub base_color_uv: GpuTextureTransform,
    pub metallic_roughness_uv: GpuTextureTransform,
    pub normal_uv: GpuTextureTransform,
    pub occlusion_uv: GpuTextureTransform,
    pub emissive_uv: GpuTextureTransform,
}
