//! glTF metallic-roughness materials as `shaders/common/material.wesl` reads them.

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3, Vec4};

/// KHR_texture_transform and the UV set of one texture slot.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuTextureTransform {
    /// Columns of the 2x2 part: (m00, m01, m10, m11).
    pub linear: Vec4,
    /// UV offset, added after the 2x2 part.
    pub offset: Vec2,
    /// 0 or 1: TEXCOORD_0 or TEXCOORD_1.
    pub uv_set: u32,
    /// Pads the transform to 16-byte alignment.
    pub _pad: u32,
}

/// One glTF metallic-roughness material (`Material` in `shaders/common/material.wesl`):
/// its factors, alpha handling and the transform of each texture slot.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuMaterial {
    /// Linear RGBA base colour factor, multiplied with the base colour texture.
    pub base_color: Vec4,
    /// Linear RGB emissive factor, multiplied with the emissive texture.
    pub emissive: Vec3,
    /// 0 (dielectric) to 1 (metal), multiplied with the texture's blue channel.
    pub metallic: f32,
    /// Perceptual roughness, 0 to 1, multiplied with the texture's green channel.
    pub roughness: f32,
    /// Scale of the normal texture's x and y.
    pub normal_scale: f32,
    /// 0 to 1: how much the occlusion texture darkens indirect light.
    pub occlusion_strength: f32,
    /// MASK materials discard below this alpha.
    pub alpha_cutoff: f32,
    /// `MATERIAL_ALPHA_*`.
    pub alpha_mode: u32,
    /// 1 for double-sided materials.
    pub double_sided: u32,
    /// `MATERIAL_FLAG_*` bits.
    pub flags: u32,
    /// Pads the factors to 16-byte alignment.
    pub _pad: u32,
    /// The base colour texture's transform and UV set.
    pub base_color_uv: GpuTextureTransform,
    /// The metallic-roughness texture's transform and UV set.
    pub metallic_roughness_uv: GpuTextureTransform,
    /// The normal texture's transform and UV set.
    pub normal_uv: GpuTextureTransform,
    /// The occlusion texture's transform and UV set.
    pub occlusion_uv: GpuTextureTransform,
    /// The emissive texture's transform and UV set.
    pub emissive_uv: GpuTextureTransform,
}
