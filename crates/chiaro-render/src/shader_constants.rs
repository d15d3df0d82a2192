//! Numbers the CPU and the shaders must agree on: limits that size arrays, and the
//! enumerations and flag bits of the `Gpu*` structs. build.rs hands every entry of
//! `U32_CONSTANTS` and `F32_CONSTANTS` to WESL's virtual `constants` module, so a shader
//! writes `import constants::LIGHT_KIND_POINT;` and gets the very value Rust uses.

use chiaro_math::light::{MAX_DIRECTIONAL_LIGHTS, MAX_LOCAL_LIGHTS};
use chiaro_math::shadow::local::MAX_LOCAL_SHADOW_TILES as LOCAL_TILES;
use chiaro_math::shadow::{MAX_CASCADES as CASCADES, MAX_SHADOWED_DIRECTIONAL_LIGHTS, ShadowFilter, virtual_map};

/// Cascades per directional light at most.
pub const MAX_CASCADES: u32 = CASCADES as u32;
/// Shadowed directional lights x cascades.
pub const MAX_DIRECTIONAL_SHADOW_TILES: u32 = (MAX_SHADOWED_DIRECTIONAL_LIGHTS * CASCADES) as u32;
/// Tiles of the point and spot atlas at most (one per spot, six per point light).
pub const MAX_LOCAL_SHADOW_TILES: u32 = LOCAL_TILES as u32;
/// Virtual shadow maps a frame has at most, in the shadow uniform: four directional
/// lights' clipmaps of up to 16 levels, and `shadows.other.max_tiles` (at most 64) spots
/// and cube faces.
pub const MAX_VIRTUAL_MAPS: u32 = 128;
/// Lights one frame shades: four directional lights and `MAX_LOCAL_LIGHTS` point and
/// spot lights (the light buffer's length).
pub const MAX_FRAME_LIGHTS: u32 = (MAX_DIRECTIONAL_LIGHTS + MAX_LOCAL_LIGHTS) as u32;
/// Lights the uniform light buffer holds (57 KiB, under the 64 KiB uniform binding
/// limit). Culled lists read their lights from it when the frame has no more, since
/// llvmpipe's forward pass reads uniforms faster than storage (a lavapipe choice:
/// docs/performance.md); frames with more read the texel table (`texel_table`).
pub const MAX_UNIFORM_LIGHTS: u32 = 512;

/// `GpuLight::kind`.
pub const LIGHT_KIND_DIRECTIONAL: u32 = 0;
/// `GpuLight::kind` of a point light.
pub const LIGHT_KIND_POINT: u32 = 1;
/// `GpuLight::kind` of a spot light.
pub const LIGHT_KIND_SPOT: u32 = 2;
/// `GpuLight::kind` of an EXT_lights_area rect light.
pub const LIGHT_KIND_RECT: u32 = 3;
/// `GpuLight::kind` of an EXT_lights_area disk light.
pub const LIGHT_KIND_DISK: u32 = 4;
/// The BRDF table's layer that holds the LTC matrices of area lights (`chiaro_math::ltc`).
pub const LTC_LAYER: u32 = 1;

/// `GpuLight::shadow_slot`: the GPU side of `plan::ShadowSlot`.
pub const SHADOW_SLOT_NONE: u32 = 0;
/// `GpuLight::shadow_slot`: shadowed from its atlas tiles.
pub const SHADOW_SLOT_REALTIME: u32 = 1;
/// `GpuLight::shadow_slot`: casts shadows but got no tile; only baked shadows apply.
pub const SHADOW_SLOT_BAKED_ONLY: u32 = 2;
/// `GpuLight::shadow_slot`: shadowed from its virtual maps (`[shadows] technique =
/// "virtual"`); its first tile is its first map.
pub const SHADOW_SLOT_VIRTUAL: u32 = 3;

/// `GpuVirtualMap::kind`: a directional light's clipmap level.
pub const VIRTUAL_MAP_DIRECTIONAL: u32 = 0;
/// `GpuVirtualMap::kind`: a spot light's map.
pub const VIRTUAL_MAP_SPOT: u32 = 1;
/// `GpuVirtualMap::kind`: a cube face of a point (or area) light.
pub const VIRTUAL_MAP_CUBE_FACE: u32 = 2;
/// chiaro_math::shadow::virtual_map's page grid, for the shaders.
pub const VIRTUAL_PAGE_TEXELS: u32 = virtual_map::PAGE_TEXELS;
/// See `VIRTUAL_PAGE_TEXELS`.
pub const VIRTUAL_PAGE_BORDER: u32 = virtual_map::PAGE_BORDER;
/// See `VIRTUAL_PAGE_TEXELS`.
pub const VIRTUAL_PAGE_SLOT: u32 = virtual_map::PAGE_SLOT;
/// See `VIRTUAL_PAGE_TEXELS`.
pub const VIRTUAL_MAP_PAGES: u32 = virtual_map::MAP_PAGES;

/// `GpuLight::shadow_filter`.
pub const SHADOW_FILTER_PCF2X2: u32 = ShadowFilter::Pcf2x2.index();
/// `GpuLight::shadow_filter`: 3x3 tent.
pub const SHADOW_FILTER_TENT3X3: u32 = ShadowFilter::Tent3x3.index();
/// `GpuLight::shadow_filter`: 5x5 tent.
pub const SHADOW_FILTER_TENT5X5: u32 = ShadowFilter::Tent5x5.index();
/// `GpuLight::shadow_filter`: 7x7 tent.
pub const SHADOW_FILTER_TENT7X7: u32 = ShadowFilter::Tent7x7.index();
/// `GpuLight::shadow_filter`: contact-hardening (PCSS) from the light's size.
pub const SHADOW_FILTER_PCSS: u32 = 4;
/// A contact-hardening blocker search reaches at most the tile's width over this.
pub const PCSS_SEARCH_TILE_DIVISOR: u32 = chiaro_math::shadow::pcss::SEARCH_TILE_DIVISOR;

/// `GpuShadows::cascade_blend`.
pub const CASCADE_BLEND_HARD: u32 = 0;
/// `GpuShadows::cascade_blend`: the next cascade fades in over the cascade fade.
pub const CASCADE_BLEND_SOFT: u32 = 1;
/// `GpuShadows::cascade_blend`: a dither picks one cascade per pixel.
pub const CASCADE_BLEND_DITHER: u32 = 2;

/// `GpuObject::flags` bit: the object receives shadows.
pub const OBJECT_RECEIVES_SHADOWS: u32 = 1;
/// `GpuObject::flags` bit: baked light comes from its lightmap layer.
pub const OBJECT_LIGHTMAPPED: u32 = 2;
/// `GpuObject::flags` bit: baked light comes from the light probes.
pub const OBJECT_PROBE_LIT: u32 = 4;

/// `GpuMaterial::alpha_mode`.
pub const MATERIAL_ALPHA_OPAQUE: u32 = 0;
/// `GpuMaterial::alpha_mode`: discard below the alpha cutoff.
pub const MATERIAL_ALPHA_MASK: u32 = 1;
/// `GpuMaterial::alpha_mode`: blended over what is behind.
pub const MATERIAL_ALPHA_BLEND: u32 = 2;
/// `GpuMaterial::flags` bit: the material has a normal texture.
pub const MATERIAL_FLAG_NORMAL_TEXTURE: u32 = 1;
/// `GpuMaterial::flags` bit: KHR_materials_unlit, the surface shows its base colour and no
/// light.
pub const MATERIAL_FLAG_UNLIT: u32 = 2;

/// Extension texture slots of a material (`GpuMaterialLayers::textures`), one per
/// `chiaro_scene::LayerTexture`; a test holds the two equal.
pub const LAYER_TEXTURE_SLOTS: u32 = 14;
/// The slot of `LayerTexture::Specular` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_SPECULAR: u32 = 0;
/// The slot of `LayerTexture::SpecularColor` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_SPECULAR_COLOR: u32 = 1;
/// The slot of `LayerTexture::Clearcoat` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_CLEARCOAT: u32 = 2;
/// The slot of `LayerTexture::ClearcoatRoughness` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_CLEARCOAT_ROUGHNESS: u32 = 3;
/// The slot of `LayerTexture::ClearcoatNormal` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_CLEARCOAT_NORMAL: u32 = 4;
/// The slot of `LayerTexture::SheenColor` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_SHEEN_COLOR: u32 = 5;
/// The slot of `LayerTexture::SheenRoughness` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_SHEEN_ROUGHNESS: u32 = 6;
/// The slot of `LayerTexture::Transmission` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_TRANSMISSION: u32 = 7;
/// The slot of `LayerTexture::Thickness` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_THICKNESS: u32 = 8;
/// The slot of `LayerTexture::Iridescence` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_IRIDESCENCE: u32 = 9;
/// The slot of `LayerTexture::IridescenceThickness` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_IRIDESCENCE_THICKNESS: u32 = 10;
/// The slot of `LayerTexture::Anisotropy` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_ANISOTROPY: u32 = 11;
/// The slot of `LayerTexture::DiffuseTransmission` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_DIFFUSE_TRANSMISSION: u32 = 12;
/// The slot of `LayerTexture::DiffuseTransmissionColor` (its index in `LayerTexture::ALL`).
pub const LAYER_SLOT_DIFFUSE_TRANSMISSION_COLOR: u32 = 13;

/// `GpuFrame::debug_view`.
pub const DEBUG_VIEW_NONE: u32 = 0;
/// `GpuFrame::debug_view`: tint each surface by its cascade.
pub const DEBUG_VIEW_CASCADES: u32 = 1;

/// `GpuCasterView::flags` bit: clamp depth in the vertex shader (pancaking), for devices
/// that cannot leave depth unclipped.
pub const CASTER_CLAMP_DEPTH: u32 = 1;

/// `GpuLight::cookie_layer` of a light without a cookie.
pub const NO_COOKIE: u32 = u32::MAX;

/// `GpuLight::shadow_mask_channel` of a light without one.
pub const NO_MASK_CHANNEL: u32 = u32::MAX;

/// `GpuFrame::mixed_mode`.
pub const MIXED_MODE_BAKED_INDIRECT: u32 = 0;
/// `GpuFrame::mixed_mode`: the baked mask at every distance, darkened by realtime shadows
/// within the shadow distance.
pub const MIXED_MODE_SHADOWMASK: u32 = 1;
/// `GpuFrame::mixed_mode`: realtime shadows within the shadow distance, the baked mask
/// beyond, blended across the fade.
pub const MIXED_MODE_DISTANCE_SHADOWMASK: u32 = 2;

/// The forward pass's `light_culling` override: how it finds its point and spot lights.
pub const LIGHT_CULLING_NONE: u32 = 0;
/// `light_culling`: each pixel reads its cluster's list.
pub const LIGHT_CULLING_CLUSTERED: u32 = 1;
/// `light_culling`: each draw reads its object's list.
pub const LIGHT_CULLING_PER_OBJECT: u32 = 2;
/// The tone mapping pass's `tone_mapping` override: `[render] tone_mapping`.
pub const TONE_MAPPING_PBR_NEUTRAL: u32 = 0;
/// `tone_mapping`: the fitted ACES filmic curve.
pub const TONE_MAPPING_ACES: u32 = 1;
/// `tone_mapping`: Blender's AgX base.
pub const TONE_MAPPING_AGX: u32 = 2;
/// `tone_mapping`: clamped.
pub const TONE_MAPPING_LINEAR: u32 = 3;
/// Depth slices of the cluster grid (`plan::clusters`; its tiles across and down follow
/// the image size and come in the frame uniform), spread exponentially over the depths
/// where surfaces are. More slices list fewer lights per cluster but cost the CPU more to
/// build; since the shader tests the entries' ranges in a cheap pass (culled.wesl), more
/// than 64 did not pay on lavapipe (docs/performance.md).
pub const CLUSTER_SLICES: u32 = 64;

/// The mark of a shadowed light's entry in `CulledLightLists::indices` (a frame has a few
/// thousand lights, so an index never reaches this bit).
pub const SHADOWED_ENTRY: u32 = 1 << 31;
/// Records a row of a texel table (`crate::texel_table`); a power of two, so that the
/// shaders' `%` and `/` are a mask and a shift.
pub const TEXEL_TABLE_WIDTH: u32 = 4096;
/// 16-byte texel table records one `GpuLight` takes (checked where the table is built).
pub const LIGHT_RECORDS: u32 = 7;

/// `GpuAovLight::list_index` of a light the frame does not shade.
pub const NO_LIGHT: u32 = u32::MAX;
/// `GpuObject::node` of an object no glTF node places, and the id pass's sky.
pub const NO_NODE: u32 = u32::MAX;

/// Every `u32` constant above, by the name the shaders import it with.
pub const U32_CONSTANTS: &[(&str, u32)] = &[
    ("MAX_CASCADES", MAX_CASCADES),
    ("MAX_DIRECTIONAL_SHADOW_TILES", MAX_DIRECTIONAL_SHADOW_TILES),
    ("MAX_LOCAL_SHADOW_TILES", MAX_LOCAL_SHADOW_TILES),
    ("MAX_VIRTUAL_MAPS", MAX_VIRTUAL_MAPS),
    ("MAX_FRAME_LIGHTS", MAX_FRAME_LIGHTS),
    ("MAX_UNIFORM_LIGHTS", MAX_UNIFORM_LIGHTS),
    ("LIGHT_KIND_DIRECTIONAL", LIGHT_KIND_DIRECTIONAL),
    ("LIGHT_KIND_POINT", LIGHT_KIND_POINT),
    ("LIGHT_KIND_SPOT", LIGHT_KIND_SPOT),
    ("LIGHT_KIND_RECT", LIGHT_KIND_RECT),
    ("LIGHT_KIND_DISK", LIGHT_KIND_DISK),
    ("LTC_LAYER", LTC_LAYER),
    ("SHADOW_SLOT_NONE", SHADOW_SLOT_NONE),
    ("SHADOW_SLOT_REALTIME", SHADOW_SLOT_REALTIME),
    ("SHADOW_SLOT_BAKED_ONLY", SHADOW_SLOT_BAKED_ONLY),
    ("SHADOW_SLOT_VIRTUAL", SHADOW_SLOT_VIRTUAL),
    ("VIRTUAL_MAP_DIRECTIONAL", VIRTUAL_MAP_DIRECTIONAL),
    ("VIRTUAL_MAP_SPOT", VIRTUAL_MAP_SPOT),
    ("VIRTUAL_MAP_CUBE_FACE", VIRTUAL_MAP_CUBE_FACE),
    ("VIRTUAL_PAGE_TEXELS", VIRTUAL_PAGE_TEXELS),
    ("VIRTUAL_PAGE_BORDER", VIRTUAL_PAGE_BORDER),
    ("VIRTUAL_PAGE_SLOT", VIRTUAL_PAGE_SLOT),
    ("VIRTUAL_MAP_PAGES", VIRTUAL_MAP_PAGES),
    ("SHADOW_FILTER_PCF2X2", SHADOW_FILTER_PCF2X2),
    ("SHADOW_FILTER_TENT3X3", SHADOW_FILTER_TENT3X3),
    ("SHADOW_FILTER_TENT5X5", SHADOW_FILTER_TENT5X5),
    ("SHADOW_FILTER_TENT7X7", SHADOW_FILTER_TENT7X7),
    ("SHADOW_FILTER_PCSS", SHADOW_FILTER_PCSS),
    ("PCSS_SEARCH_TILE_DIVISOR", PCSS_SEARCH_TILE_DIVISOR),
    ("CASCADE_BLEND_HARD", CASCADE_BLEND_HARD),
    ("CASCADE_BLEND_SOFT", CASCADE_BLEND_SOFT),
    ("CASCADE_BLEND_DITHER", CASCADE_BLEND_DITHER),
    ("OBJECT_RECEIVES_SHADOWS", OBJECT_RECEIVES_SHADOWS),
    ("OBJECT_LIGHTMAPPED", OBJECT_LIGHTMAPPED),
    ("OBJECT_PROBE_LIT", OBJECT_PROBE_LIT),
    ("MATERIAL_ALPHA_OPAQUE", MATERIAL_ALPHA_OPAQUE),
    ("MATERIAL_ALPHA_MASK", MATERIAL_ALPHA_MASK),
    ("MATERIAL_ALPHA_BLEND", MATERIAL_ALPHA_BLEND),
    ("MATERIAL_FLAG_NORMAL_TEXTURE", MATERIAL_FLAG_NORMAL_TEXTURE),
    ("MATERIAL_FLAG_UNLIT", MATERIAL_FLAG_UNLIT),
    ("LAYER_TEXTURE_SLOTS", LAYER_TEXTURE_SLOTS),
    ("LAYER_SLOT_SPECULAR", LAYER_SLOT_SPECULAR),
    ("LAYER_SLOT_SPECULAR_COLOR", LAYER_SLOT_SPECULAR_COLOR),
    ("LAYER_SLOT_CLEARCOAT", LAYER_SLOT_CLEARCOAT),
    ("LAYER_SLOT_CLEARCOAT_ROUGHNESS", LAYER_SLOT_CLEARCOAT_ROUGHNESS),
    ("LAYER_SLOT_CLEARCOAT_NORMAL", LAYER_SLOT_CLEARCOAT_NORMAL),
    ("LAYER_SLOT_SHEEN_COLOR", LAYER_SLOT_SHEEN_COLOR),
    ("LAYER_SLOT_SHEEN_ROUGHNESS", LAYER_SLOT_SHEEN_ROUGHNESS),
    ("LAYER_SLOT_TRANSMISSION", LAYER_SLOT_TRANSMISSION),
    ("LAYER_SLOT_THICKNESS", LAYER_SLOT_THICKNESS),
    ("LAYER_SLOT_IRIDESCENCE", LAYER_SLOT_IRIDESCENCE),
    ("LAYER_SLOT_IRIDESCENCE_THICKNESS", LAYER_SLOT_IRIDESCENCE_THICKNESS),
    ("LAYER_SLOT_ANISOTROPY", LAYER_SLOT_ANISOTROPY),
    ("LAYER_SLOT_DIFFUSE_TRANSMISSION", LAYER_SLOT_DIFFUSE_TRANSMISSION),
    ("LAYER_SLOT_DIFFUSE_TRANSMISSION_COLOR", LAYER_SLOT_DIFFUSE_TRANSMISSION_COLOR),
    ("DEBUG_VIEW_NONE", DEBUG_VIEW_NONE),
    ("DEBUG_VIEW_CASCADES", DEBUG_VIEW_CASCADES),
    ("CASTER_CLAMP_DEPTH", CASTER_CLAMP_DEPTH),
    ("NO_LIGHT", NO_LIGHT),
    ("NO_NODE", NO_NODE),
    ("LIGHT_CULLING_NONE", LIGHT_CULLING_NONE),
    ("LIGHT_CULLING_CLUSTERED", LIGHT_CULLING_CLUSTERED),
    ("LIGHT_CULLING_PER_OBJECT", LIGHT_CULLING_PER_OBJECT),
    ("CLUSTER_SLICES", CLUSTER_SLICES),
    ("TONE_MAPPING_PBR_NEUTRAL", TONE_MAPPING_PBR_NEUTRAL),
    ("TONE_MAPPING_ACES", TONE_MAPPING_ACES),
    ("TONE_MAPPING_AGX", TONE_MAPPING_AGX),
    ("TONE_MAPPING_LINEAR", TONE_MAPPING_LINEAR),
    ("TEXEL_TABLE_WIDTH", TEXEL_TABLE_WIDTH),
    ("SHADOWED_ENTRY", SHADOWED_ENTRY),
    ("LIGHT_RECORDS", LIGHT_RECORDS),
    ("NO_COOKIE", NO_COOKIE),
    ("NO_MASK_CHANNEL", NO_MASK_CHANNEL),
    ("MIXED_MODE_BAKED_INDIRECT", MIXED_MODE_BAKED_INDIRECT),
    ("MIXED_MODE_SHADOWMASK", MIXED_MODE_SHADOWMASK),
    ("MIXED_MODE_DISTANCE_SHADOWMASK", MIXED_MODE_DISTANCE_SHADOWMASK),
];

/// Every `f32` constant the shaders share with chiaro_math.
pub const F32_CONSTANTS: &[(&str, f32)] = &[
    ("MIN_DISTANCE_SQUARED", chiaro_math::light::MIN_DISTANCE_SQUARED),
    ("MAX_EXPOSED_RADIANCE", chiaro_math::tonemap::MAX_EXPOSED_RADIANCE),
    ("MAX_EXPOSED_VOLUME_RADIANCE", MAX_EXPOSED_VOLUME_RADIANCE),
];

/// The most one deferred light draw adds to a pixel of the light buffer: a sixteenth of
/// `MAX_EXPOSED_RADIANCE`. Blending sums the draws in half floats, which do not saturate,
/// so sixteen draws at their brightest still sum to a finite value (radiance this high
/// tone-maps to white either way).
pub const MAX_EXPOSED_VOLUME_RADIANCE: f32 = chiaro_math::tonemap::MAX_EXPOSED_RADIANCE / 16.0;

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::LayerTexture;

    #[test]
    fn layer_slots_are_the_scene_s() {
        assert_eq!(LayerTexture::ALL.len(), LAYER_TEXTURE_SLOTS as usize);
        let slots = [
            (LayerTexture::Specular, LAYER_SLOT_SPECULAR),
            (LayerTexture::SpecularColor, LAYER_SLOT_SPECULAR_COLOR),
            (LayerTexture::Clearcoat, LAYER_SLOT_CLEARCOAT),
            (LayerTexture::ClearcoatRoughness, LAYER_SLOT_CLEARCOAT_ROUGHNESS),
            (LayerTexture::ClearcoatNormal, LAYER_SLOT_CLEARCOAT_NORMAL),
            (LayerTexture::SheenColor, LAYER_SLOT_SHEEN_COLOR),
            (LayerTexture::SheenRoughness, LAYER_SLOT_SHEEN_ROUGHNESS),
            (LayerTexture::Transmission, LAYER_SLOT_TRANSMISSION),
            (LayerTexture::Thickness, LAYER_SLOT_THICKNESS),
            (LayerTexture::Iridescence, LAYER_SLOT_IRIDESCENCE),
            (LayerTexture::IridescenceThickness, LAYER_SLOT_IRIDESCENCE_THICKNESS),
            (LayerTexture::Anisotropy, LAYER_SLOT_ANISOTROPY),
            (LayerTexture::DiffuseTransmission, LAYER_SLOT_DIFFUSE_TRANSMISSION),
            (LayerTexture::DiffuseTransmissionColor, LAYER_SLOT_DIFFUSE_TRANSMISSION_COLOR),
        ];
        for (texture, slot) in slots {
            assert_eq!(texture.index(), slot as usize, "{texture:?}");
        }
    }
}
