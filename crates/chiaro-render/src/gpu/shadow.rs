//! Shadow data (`shaders/shadows/data.wesl`): every atlas tile's projection, clamp
//! bounds and normal bias, the cascades' culling spheres, and the fades; and one caster
//! view of the shadow-caster pass (`shaders/shadow_caster.wesl`).

use crate::shader_constants::{MAX_CASCADES, MAX_DIRECTIONAL_SHADOW_TILES, MAX_LOCAL_SHADOW_TILES, MAX_VIRTUAL_MAPS};
use bytemuck::{Pod, Zeroable};
use chiaro_math::shadow::pcss::TileLens;
use glam::{Mat4, Vec2, Vec3};

/// One atlas tile as the receivers sample it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuShadowTile {
    /// Atlas texture coordinates (and depth) from world space; perspective tiles need the
    /// divide by w.
    pub atlas_from_world: Mat4,
    /// Samples are clamped into [uv_min, uv_max], half a texel inside the tile, so that no
    /// filter tap reads a neighbouring tile.
    pub uv_min: Vec2,
    /// See `uv_min`.
    pub uv_max: Vec2,
    /// How far receivers move along their normal before sampling: metres for cascade
    /// tiles; metres per metre of distance from the light's plane for perspective tiles.
    pub normal_bias: f32,
    /// How the tile's depths and texture offsets map back to metres, for contact-hardening
    /// shadows (chiaro_math::shadow::pcss::TileLens): perspective tiles' near plane, 0 for
    /// cascades.
    pub lens_near: f32,
    /// See `lens_near`: the far plane, or the metres a cascade's depth 0 to 1 spans.
    pub lens_far: f32,
    /// See `lens_near`: the metres one unit of texture coordinates spans (perspective
    /// tiles: at 1 m from the light).
    pub lens_metres_per_uv: f32,
}

impl GpuShadowTile {
    /// The tile with its lens from chiaro_math::shadow::pcss.
    pub fn with_lens(self, [near, far, metres_per_uv]: TileLens) -> GpuShadowTile {
        GpuShadowTile { lens_near: near, lens_far: far, lens_metres_per_uv: metres_per_uv, ..self }
    }
}

impl Default for GpuShadowTile {
    fn default() -> Self {
        GpuShadowTile {
            atlas_from_world: Mat4::IDENTITY,
            uv_min: Vec2::ZERO,
            uv_max: Vec2::ZERO,
            normal_bias: 0.0,
            lens_near: 0.0,
            lens_far: 0.0,
            lens_metres_per_uv: 0.0,
        }
    }
}

/// One cascade's culling sphere, shared by every directional light.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuCascade {
    /// The sphere's centre in world space, metres.
    pub culling_sphere_center_ws: Vec3,
    /// Of the sphere shrunk by the filter's reach.
    pub radius_squared: f32,
    /// 1 / `radius_squared`, so that the cascade fade multiplies.
    pub inverse_radius_squared: f32,
    /// Pads the cascade to 16-byte alignment.
    pub _pad: [f32; 3],
}

/// One shadow atlas's size, for the filters' texel steps.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuAtlas {
    /// The atlas side in texels.
    pub size_texels: f32,
    /// One texel in texture coordinates: 1 / size.
    pub texel_uv: f32,
    /// Pads the atlas to 16 bytes.
    pub _pad: [f32; 2],
}

/// The tutorial's fades, as reciprocals so the shader multiplies.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuShadowFade {
    /// 1 / the shadow distance (metres of view depth): shadows end there.
    pub inverse_max_distance: f32,
    /// 1 / the distance fade, a share of the shadow distance over which shadows fade out.
    pub inverse_distance_fade: f32,
    /// 1 / (1 - (1 - cascade fade)^2).
    pub inverse_cascade_fade: f32,
    /// Pads the fades to 16 bytes.
    pub _pad: f32,
}

/// The shadow uniform (`shaders/shadows/data.wesl`): both atlases' tiles, the cascades'
/// culling spheres, the atlas sizes and the fades.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuShadows {
    /// The directional atlas's tiles: cascades of each shadowed directional light in turn.
    pub directional_tiles: [GpuShadowTile; MAX_DIRECTIONAL_SHADOW_TILES as usize],
    /// The point and spot atlas's tiles: one per spot light, six per point light.
    pub local_tiles: [GpuShadowTile; MAX_LOCAL_SHADOW_TILES as usize],
    /// The cascades' culling spheres, nearest first.
    pub cascades: [GpuCascade; MAX_CASCADES as usize],
    /// The directional atlas's size.
    pub directional_atlas: GpuAtlas,
    /// The point and spot atlas's size.
    pub local_atlas: GpuAtlas,
    /// Where shadows end and how they fade, by distance and by cascade.
    pub fade: GpuShadowFade,
    /// 0 when no directional light has a shadow map this frame.
    pub cascade_count: u32,
    /// `CASCADE_BLEND_*`.
    pub cascade_blend: u32,
    /// Depth samples of a contact-hardening shadow's blocker search.
    pub pcss_blocker_samples: u32,
    /// Comparison samples filtering a contact-hardening shadow's penumbra.
    pub pcss_filter_samples: u32,
    /// The screen-space contact shadows' march.
    pub contact: GpuContactShadows,
    /// The virtual shadow maps' count.
    pub virtual_maps: GpuVirtualShadows,
    /// The virtual shadow maps, `virtual_maps.map_count` of them: in the uniform, which
    /// lavapipe reads faster than a storage buffer, once per shadowed light and pixel.
    pub virtual_map_records: [GpuVirtualMap; MAX_VIRTUAL_MAPS as usize],
}

/// What the shaders need of the virtual technique besides its maps: how many there are.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuVirtualShadows {
    /// Maps in the frame's `GpuVirtualMap` buffer (0 with the atlas technique).
    pub map_count: u32,
    /// Pads the struct to 16 bytes.
    pub _pad: [u32; 3],
}

/// One virtual shadow map (`shaders/shadows/virtual_map.wesl`): a directional light's
/// clipmap level, a spot light's map or a point light's cube face, with its mip chain of
/// pages (chiaro_math::shadow::virtual_map).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuVirtualMap {
    /// World space to the map's clip space (x, y in [-1, 1] over the map, depth 0 to 1;
    /// perspective maps divide by w).
    pub clip_from_world: Mat4,
    /// A point or spot light's position, metres.
    pub light_position_ws: Vec3,
    /// Its range, metres: no page is asked for beyond it.
    pub range: f32,
    /// Where its mip 0 starts in the page table.
    pub table_offset: u32,
    /// Its mips (one for a clipmap level: the next level is the coarser page).
    pub mips: u32,
    /// The light's first map (this one or an earlier one).
    pub first_map: u32,
    /// The light's maps: its clipmap levels, 1 for a spot, 6 for a point light.
    pub map_count: u32,
    /// `VIRTUAL_MAP_*`.
    pub kind: u32,
    /// Metres a texel of mip 0 spans: at any depth (directional), or per metre along the
    /// map's axis (perspective).
    pub texel_m: f32,
    /// The normal bias at mip 0, as `GpuShadowTile::normal_bias` (doubling with each mip).
    pub normal_bias: f32,
    /// See `GpuShadowTile::lens_near`.
    pub lens_near: f32,
    /// See `GpuShadowTile::lens_far`.
    pub lens_far: f32,
    /// The metres one unit of the map's texture coordinates spans (perspective: at 1 m).
    pub lens_metres_per_uv: f32,
    /// A contact-hardening light's size as its blocker search reads it (0 for the other
    /// filters): the lookup takes a mip coarse enough that the search stays within the
    /// page's border.
    pub reach_size: f32,
    /// The most mip-0 texels of that search the lookup's mip holds within a page's
    /// border (`plan::virtual_shadows::reach`).
    pub reach_cap_texels: f32,
}

impl Default for GpuVirtualMap {
    fn default() -> Self {
        GpuVirtualMap { clip_from_world: Mat4::IDENTITY, ..Zeroable::zeroed() }
    }
}

/// The contact shadows' march (`shaders/shadows/contact.wesl`); `steps` 0 turns them off.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuContactShadows {
    /// Metres the march reaches towards the light.
    pub length_m: f32,
    /// Metres behind a depth-buffer surface that still count as inside its caster.
    pub thickness_m: f32,
    /// Depth samples along the march; 0: no contact shadows.
    pub steps: u32,
    /// Pads the march to 16 bytes.
    pub _pad: u32,
}

impl Default for GpuShadows {
    fn default() -> Self {
        GpuShadows {
            directional_tiles: [GpuShadowTile::default(); MAX_DIRECTIONAL_SHADOW_TILES as usize],
            local_tiles: [GpuShadowTile::default(); MAX_LOCAL_SHADOW_TILES as usize],
            cascades: [GpuCascade::default(); MAX_CASCADES as usize],
            directional_atlas: GpuAtlas { size_texels: 1.0, texel_uv: 1.0, _pad: [0.0; 2] },
            local_atlas: GpuAtlas { size_texels: 1.0, texel_uv: 1.0, _pad: [0.0; 2] },
            fade: GpuShadowFade::default(),
            cascade_count: 0,
            cascade_blend: 0,
            pcss_blocker_samples: 16,
            pcss_filter_samples: 16,
            contact: GpuContactShadows::default(),
            virtual_maps: GpuVirtualShadows::default(),
            virtual_map_records: [GpuVirtualMap::default(); MAX_VIRTUAL_MAPS as usize],
        }
    }
}

/// One shadow-caster view (a tile's light projection), at a dynamic offset.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuCasterView {
    /// World space to the tile's light clip space.
    pub clip_from_world: Mat4,
    /// `CASTER_*` bits.
    pub flags: u32,
    /// Pads the view to 16 bytes.
    pub _pad: [u32; 3],
}
