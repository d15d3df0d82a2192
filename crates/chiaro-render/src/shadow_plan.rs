//! Plans a frame's directional shadows on the CPU: which lights get tiles, each cascade's
//! culling sphere and stable projection, and the uniform the shaders read. The math is
//! chiaro_math::shadow; this module only arranges it for the GPU.

use crate::gpu_types::{GpuShadows, MAX_DIRECTIONAL_SHADOW_TILES};
use crate::view::View;
use chiaro_math::Sphere;
use chiaro_math::shadow::bias::cascade_texel_size_ws;
use chiaro_math::shadow::fade::distance_fade_params;
use chiaro_math::shadow::{AtlasLayout, ShadowFilter, cascade_splits, fit_cascade, slice_culling_sphere};
use chiaro_scene::{CascadeBlend, Light, Settings, ShadowMode};
use glam::{Mat4, Vec4};

/// One tile of the atlas to render casters into.
#[derive(Clone, Copy, Debug)]
pub struct CasterTile {
    pub clip_from_world: Mat4,
    /// (x, y, size) in texels.
    pub viewport: (u32, u32, u32),
    /// Slope-scale depth bias of the light.
    pub slope_bias: f32,
}

pub struct ShadowPlan {
    pub gpu: GpuShadows,
    /// Per directional light slot: (strength, first tile, normal bias, filter).
    pub directional: [Vec4; 4],
    /// Atlas side in texels; 0 when no light casts a shadow this frame.
    pub atlas_size: u32,
    pub tiles: Vec<CasterTile>,
    /// World-space culling spheres (unshrunk), for the debug view and the tests.
    pub cascade_spheres: Vec<Sphere>,
}

/// `directional` holds the scene lights in the frame's directional slots, in order.
pub fn plan_shadows(view: &View, settings: &Settings, directional: &[&Light]) -> ShadowPlan {
    let ds = &settings.shadows.directional;
    let filter = ds.shadow_filter();
    let shadowed: Vec<(usize, &Light)> =
        directional.iter().enumerate().filter(|(_, l)| l.shadow.casts()).map(|(slot, l)| (slot, *l)).collect();
    let cascade_count = ds.cascade_count as usize;
    let max_distance = match view.zfar {
        Some(far) => settings.shadows.max_distance.min(far),
        None => settings.shadows.max_distance,
    };
    let fade = distance_fade_params(max_distance, settings.shadows.distance_fade, ds.cascade_fade);
    let mut gpu = GpuShadows {
        directional_atlas_from_world: [Mat4::IDENTITY; MAX_DIRECTIONAL_SHADOW_TILES],
        culling_spheres: [Vec4::ZERO; 4],
        cascade_data: [Vec4::ZERO; 4],
        distance_fade: Vec4::new(fade[0], fade[1], fade[2], 0.0),
        directional_atlas: Vec4::ONE,
        cascade_count: 0,
        cascade_blend: match ds.cascade_blend {
            CascadeBlend::Hard => 0,
            CascadeBlend::Soft => 1,
            CascadeBlend::Dither => 2,
        },
        _pad: [0; 2],
    };
    let mut plan =
        ShadowPlan { gpu, directional: [Vec4::ZERO; 4], atlas_size: 0, tiles: Vec::new(), cascade_spheres: Vec::new() };
    if shadowed.is_empty() {
        return plan;
    }

    let layout = AtlasLayout::for_tiles(ds.atlas_size, shadowed.len() * cascade_count);
    let tile_size = layout.tile_size();
    let splits = cascade_splits(max_distance, ds.cascade_ratios, cascade_count);
    let tan_half_fov = (view.yfov_rad * 0.5).tan();
    for (i, &far) in splits.iter().enumerate() {
        let near = if i == 0 { view.znear } else { splits[i - 1] };
        let sphere_vs = slice_culling_sphere(near, far.max(near + 1e-3), tan_half_fov, view.aspect());
        let sphere =
            Sphere { center: view.world_from_view.transform_point3(sphere_vs.center), radius: sphere_vs.radius };
        let texel = cascade_texel_size_ws(sphere.radius, tile_size);
        // Shrink by the filter's reach so samples near the edge stay inside the tile.
        let shrunk = (sphere.radius - texel * filter.footprint_texels()).max(sphere.radius * 0.5);
        gpu.culling_spheres[i] = sphere.center.extend(shrunk * shrunk);
        gpu.cascade_data[i] = Vec4::new(1.0 / (shrunk * shrunk), texel * std::f32::consts::SQRT_2, 0.0, 0.0);
        plan.cascade_spheres.push(sphere);
    }
    for (k, &(slot, light)) in shadowed.iter().enumerate() {
        let first_tile = k * cascade_count;
        for (c, sphere) in plan.cascade_spheres.iter().enumerate() {
            let tile = first_tile + c;
            let fit = fit_cascade(*sphere, light.direction, tile_size, light.shadow.near_plane);
            gpu.directional_atlas_from_world[tile] = layout.atlas_from_clip(tile) * fit.clip_from_world;
            plan.tiles.push(CasterTile {
                clip_from_world: fit.clip_from_world,
                viewport: layout.tile_viewport(tile),
                slope_bias: light.shadow.depth_bias,
            });
        }
        let light_filter = match light.shadow.mode {
            ShadowMode::Hard => ShadowFilter::Pcf2x2,
            _ => filter,
        };
        plan.directional[slot] =
            Vec4::new(light.shadow.strength, first_tile as f32, light.shadow.normal_bias, light_filter.index() as f32);
    }
    gpu.cascade_count = cascade_count as u32;
    gpu.directional_atlas = Vec4::new(ds.atlas_size as f32, 1.0 / ds.atlas_size as f32, layout.split as f32, 0.0);
    plan.gpu = gpu;
    plan.atlas_size = ds.atlas_size;
    plan
}
