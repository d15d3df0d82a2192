//! `#[repr(C)]` mirrors of the WGSL structs the shaders read, with named fields and the
//! flag bits and enumerations of `shader_constants`. The WGSL names drop the `Gpu` prefix;
//! `GPU_STRUCT_LAYOUTS` lists every one with its fields' offsets, and a test checks each
//! against naga's layout of the composed shaders.

mod environment;
mod frame;
mod light;
mod material;
mod shadow;
mod vertex;

pub use environment::{GpuEnvironment, GpuEnvironmentBake};
pub use frame::{GpuFrame, GpuObject, GpuProbeGridHeader};
pub use light::{GpuAovLight, GpuLight, GpuLightListEntry, GpuVolumeLight};
pub use material::{GpuLayerTextureSlot, GpuMaterial, GpuMaterialLayers, GpuTextureTransform};
pub use shadow::{
    GpuAtlas, GpuCascade, GpuCasterView, GpuContactShadows, GpuShadowFade, GpuShadowTile, GpuShadows, GpuVirtualMap,
    GpuVirtualShadows,
};
pub use vertex::GpuVertex;

/// A `Gpu*` struct's size and the byte offset of each named field.
#[derive(Clone, Copy, Debug)]
pub struct StructLayout {
    /// The Rust type's name (`GpuFrame`); the WGSL struct is named without `Gpu`.
    pub rust_name: &'static str,
    /// `size_of` the Rust type, in bytes.
    pub size: usize,
    /// Each field's name and byte offset, in declaration order.
    pub fields: &'static [(&'static str, usize)],
}

macro_rules! layouts {
    ($($ty:ident { $($field:ident),* $(,)? })*) => {
        /// Every `Gpu*` struct a shader reads as a struct (not `GpuVertex`, which arrives
        /// as vertex attributes), with the fields its WGSL twin names alike.
        pub const GPU_STRUCT_LAYOUTS: &[StructLayout] = &[$(
            StructLayout {
                rust_name: stringify!($ty),
                size: std::mem::size_of::<$ty>(),
                fields: &[$((stringify!($field), std::mem::offset_of!($ty, $field))),*],
            }
        ),*];
    };
}

layouts! {
    GpuFrame {
        clip_from_world, view_from_world, world_from_view, view_from_clip, camera_position_ws, exposure_scale,
        ambient, debug_view, directional_light_count, shadowed_local_light_count, local_light_count, width, height,
        mixed_mode, cluster_tile_width, cluster_tile_height, cluster_slice_scale, cluster_slice_bias, cluster_tiles_x,
        cluster_tiles_y, orthographic,
    }
    GpuObject { world_from_local, normal_from_local, flags, lightmap_layer, node, label }
    GpuProbeGridHeader { origin, lightmap_scale, spacing, counts }
    GpuLight {
        color, spot_scale, position_ws, range, direction_ws, spot_offset, kind, shadow_slot,
        shadow_strength, shadow_first_tile, shadow_filter, cookie_layer, cookie_scale, axis_x_ws,
        shadow_mask_channel, axis_y_ws, shadow_light_size,
    }
    GpuVolumeLight { world_from_volume, light }
    GpuLightListEntry { light }
    GpuAovLight { light_index }
    GpuShadowTile { atlas_from_world, uv_min, uv_max, normal_bias, lens_near, lens_far, lens_metres_per_uv }
    GpuCascade { culling_sphere_center_ws, radius_squared, inverse_radius_squared }
    GpuAtlas { size_texels, texel_uv }
    GpuShadowFade { inverse_max_distance, inverse_distance_fade, inverse_cascade_fade }
    GpuShadows {
        directional_tiles, local_tiles, cascades, directional_atlas, local_atlas, fade, cascade_count,
        cascade_blend, pcss_blocker_samples, pcss_filter_samples, contact, virtual_maps, virtual_map_records,
    }
    GpuContactShadows { length_m, thickness_m, steps }
    GpuVirtualShadows { map_count }
    GpuVirtualMap {
        clip_from_world, light_position_ws, range, table_offset, mips, first_map, map_count, kind, texel_m,
        normal_bias, lens_near, lens_far, lens_metres_per_uv, reach_size,
        reach_cap_texels,
    }
    GpuCasterView { clip_from_world, flags }
    GpuEnvironment { radiance_sh, turn_cos, turn_sin, intensity, specular_last_mip, diffuse_baked }
    GpuEnvironmentBake { size, source_size, roughness, samples }
    GpuTextureTransform { linear, offset, uv_set }
    GpuMaterial {
        base_color, emissive, metallic, roughness, normal_scale, occlusion_strength, alpha_cutoff,
        alpha_mode, double_sided, flags, base_color_uv, metallic_roughness_uv, normal_uv, occlusion_uv,
        emissive_uv, layers,
    }
    GpuLayerTextureSlot { linear, offset, uv_set, layer }
    GpuMaterialLayers {
        specular_color, specular, sheen_color, sheen_roughness, attenuation_color, attenuation_distance,
        diffuse_transmission_color, diffuse_transmission, ior, clearcoat, clearcoat_roughness, clearcoat_normal_scale,
        transmission, thickness, iridescence, iridescence_ior, iridescence_thickness_min, iridescence_thickness_max,
        anisotropy_strength, anisotropy_rotation, dispersion, shadow_transmittance_r, shadow_transmittance_g,
        shadow_transmittance_b, textures,
    }
}
