//! glTF metallic-roughness materials as `shaders/common/material.wesl` reads them.

use crate::shader_constants::LAYER_TEXTURE_SLOTS;
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
    /// The KHR_materials_* extensions.
    pub layers: GpuMaterialLayers,
}

/// One extension texture slot (`LayerTextureSlot` in `shaders/common/layers.wesl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuLayerTextureSlot {
    /// Columns of the 2x2 part: (m00, m01, m10, m11).
    pub linear: Vec4,
    /// UV offset, added after the 2x2 part.
    pub offset: Vec2,
    /// 0 or 1: TEXCOORD_0 or TEXCOORD_1.
    pub uv_set: u32,
    /// The layer of the material's extension texture array; -1 where it has none.
    pub layer: i32,
}

/// A material's KHR_materials_* factors and extension texture slots (`MaterialLayers` in
/// `shaders/common/layers.wesl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuMaterialLayers {
    /// KHR_materials_specular: the dielectric's F0 colour.
    pub specular_color: Vec3,
    /// KHR_materials_specular: the dielectric's Fresnel strength.
    pub specular: f32,
    /// KHR_materials_sheen: the sheen's colour (black: none).
    pub sheen_color: Vec3,
    /// KHR_materials_sheen: the sheen's roughness.
    pub sheen_roughness: f32,
    /// KHR_materials_volume: the colour white light turns after `attenuation_distance`.
    pub attenuation_color: Vec3,
    /// Infinite distances are sent as f32::MAX (WGSL has no infinity literal to test).
    pub attenuation_distance: f32,
    /// KHR_materials_diffuse_transmission: the colour diffuse light takes through.
    pub diffuse_transmission_color: Vec3,
    /// KHR_materials_diffuse_transmission: the share of diffuse light passed to the back.
    pub diffuse_transmission: f32,
    /// KHR_materials_ior: the dielectric's index of refraction (0: infinite).
    pub ior: f32,
    /// KHR_materials_clearcoat: the coat's strength.
    pub clearcoat: f32,
    /// KHR_materials_clearcoat: the coat's perceptual roughness.
    pub clearcoat_roughness: f32,
    /// KHR_materials_clearcoat: the coat normal map's X and Y scale.
    pub clearcoat_normal_scale: f32,
    /// KHR_materials_transmission: the share of light passing through the surface.
    pub transmission: f32,
    /// KHR_materials_volume: the volume's thickness (0: thin-walled).
    pub thickness: f32,
    /// KHR_materials_iridescence: the thin film's strength.
    pub iridescence: f32,
    /// KHR_materials_iridescence: the film's index of refraction.
    pub iridescence_ior: f32,
    /// KHR_materials_iridescence: the film's thickness (nm) where its texture reads 0.
    pub iridescence_thickness_min: f32,
    /// KHR_materials_iridescence: the film's thickness (nm) where its texture reads 1.
    pub iridescence_thickness_max: f32,
    /// KHR_materials_anisotropy: how far the highlight stretches.
    pub anisotropy_strength: f32,
    /// KHR_materials_anisotropy: the stretch's angle from the tangent, radians.
    pub anisotropy_rotation: f32,
    /// KHR_materials_dispersion: 20 / Abbe number.
    pub dispersion: f32,
    /// What one crossing of the surface lets through for coloured shadows
    /// (`Material::shadow_transmittance`), red, green and blue; ones for an opaque one.
    pub shadow_transmittance_r: f32,
    /// See `shadow_transmittance_r`.
    pub shadow_transmittance_g: f32,
    /// See `shadow_transmittance_r`.
    pub shadow_transmittance_b: f32,
    /// By `chiaro_scene::LayerTexture::index`.
    pub textures: [GpuLayerTextureSlot; LAYER_TEXTURE_SLOTS as usize],
}
