//! Plans a frame's directional shadows on the CPU: which lights get tiles, each cascade's
//! culling sphere and stable projection, and the uniform the shaders read. The math is
//! chiaro_math::shadow; this module only arranges it for the GPU.

use crate::gpu_types::{GpuShadows, MAX_DIRECTIONAL_SHADOW_TILES, MAX_OTHER_SHADOW_TILES};
use crate::view::View;
use chiaro_math::Sphere;
use chiaro_math::shadow::bias::cascade_texel_size_ws;
use chiaro_math::shadow::fade::distance_fade_params;
use chiaro_math::shadow::other::{
    OtherShadowRequest, allocate_other_tiles, perspective_normal_bias, point_face_fov_rad, point_face_view,
    spot_shadow_view,
};
use chiaro_math::shadow::{AtlasLayout, ShadowFilter, cascade_splits, fit_cascade, slice_culling_sphere};
use chiaro_scene::{CascadeBlend, Light, LightKind, Settings, ShadowMode};
use glam::{Mat4, Vec4};

/// One tile of an atlas to render casters into.
#[derive(Clone, Copy, Debug)]
pub struct CasterTile {
    pub clip_from_world: Mat4,
    /// (x, y, size) in texels.
    pub viewport: (u32, u32, u32),
    /// Slope-scale depth bias of the light.
    pub slope_bias: f32,
    /// Perspective tiles (spots, cube faces) cull casters by the light's range sphere and
    /// never clamp depth; orthographic cascade tiles cull by their box and pancake.
    pub light_sphere: Option<Sphere>,
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
    /// Per other-light slot (the frame's upload order): (strength, first tile, point, filter).
    pub other: Vec<Vec4>,
    /// Other-light atlas side in texels; 0 when no point or spot light casts a shadow.
    pub other_atlas_size: u32,
    pub other_tiles: Vec<CasterTile>,
    /// Other lights that cast shadows but found no free tiles.
    pub other_overflow: usize,
}

/// `directional` holds the scene lights in the frame's directional slots, in order;
/// `other` the point and spot lights in the frame's upload order (most important first),
/// with the range each is shaded with.
pub fn plan_shadows(view: &View, settings: &Settings, directional: &[&Light], other: &[(&Light, f32)]) -> ShadowPlan {
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
        other_atlas_from_world: [Mat4::IDENTITY; MAX_OTHER_SHADOW_TILES],
        other_tiles: [Vec4::ZERO; MAX_OTHER_SHADOW_TILES],
        other_atlas: Vec4::ONE,
        cascade_count: 0,
        cascade_blend: match ds.cascade_blend {
            CascadeBlend::Hard => 0,
            CascadeBlend::Soft => 1,
            CascadeBlend::Dither => 2,
        },
        _pad: [0; 2],
    };
    let mut plan = ShadowPlan {
        gpu,
        directional: [Vec4::ZERO; 4],
        atlas_size: 0,
        tiles: Vec::new(),
        cascade_spheres: Vec::new(),
        other: vec![Vec4::ZERO; other.len()],
        other_atlas_size: 0,
        other_tiles: Vec::new(),
        other_overflow: 0,
    };
    plan_other(&mut plan, &mut gpu, settings, other);
    if shadowed.is_empty() {
        plan.gpu = gpu;
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
                light_sphere: None,
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

/// Tiles in the second atlas for the point and spot lights that cast shadows, in
/// importance order; a light that does not fit keeps a negative strength (the tutorial's
/// convention: no realtime shadow, baked shadows still apply).
fn plan_other(plan: &mut ShadowPlan, gpu: &mut GpuShadows, settings: &Settings, other: &[(&Light, f32)]) {
    let os = &settings.shadows.other;
    let casting: Vec<(usize, &Light, f32, OtherShadowRequest)> = other
        .iter()
        .enumerate()
        .filter(|(_, (l, _))| l.shadow.casts())
        .map(|(slot, &(l, range))| {
            let request = match l.kind {
                LightKind::Point => OtherShadowRequest::Point,
                _ => OtherShadowRequest::Spot,
            };
            (slot, l, range, request)
        })
        .collect();
    if casting.is_empty() {
        return;
    }
    let requests: Vec<OtherShadowRequest> = casting.iter().map(|c| c.3).collect();
    let first_tiles = allocate_other_tiles(&requests, MAX_OTHER_SHADOW_TILES);
    let used: usize = requests.iter().zip(&first_tiles).filter(|(_, t)| t.is_some()).map(|(r, _)| r.tiles()).sum();
    let layout = AtlasLayout::for_tiles(os.atlas_size, used);
    let tile_size = layout.tile_size();
    for (&(slot, light, range, request), first) in casting.iter().zip(&first_tiles) {
        let light_filter = match light.shadow.mode {
            ShadowMode::Hard => ShadowFilter::Pcf2x2,
            _ => os.shadow_filter(),
        };
        let Some(first) = *first else {
            plan.other_overflow += 1;
            plan.other[slot] = Vec4::new(-light.shadow.strength, 0.0, 0.0, 0.0);
            continue;
        };
        let views: Vec<(Mat4, Mat4)> = match (request, light.kind) {
            (OtherShadowRequest::Spot, LightKind::Spot { outer_cone_rad, .. }) => {
                vec![spot_shadow_view(light.position, light.direction, outer_cone_rad, light.shadow.near_plane, range)]
            }
            _ => {
                let fov = point_face_fov_rad(tile_size, light_filter, light.shadow.normal_bias);
                (0..6).map(|face| point_face_view(light.position, face, fov, light.shadow.near_plane, range)).collect()
            }
        };
        for (k, (clip_from_view, clip_from_world)) in views.iter().enumerate() {
            let tile = first + k;
            let (min, max) = layout.tile_bounds_uv(tile);
            let bias = perspective_normal_bias(tile_size, clip_from_view, light_filter) * light.shadow.normal_bias;
            gpu.other_atlas_from_world[tile] = layout.atlas_from_clip(tile) * *clip_from_world;
            gpu.other_tiles[tile] = Vec4::new(min.x, min.y, max.x - min.x, bias);
            plan.other_tiles.push(CasterTile {
                clip_from_world: *clip_from_world,
                viewport: layout.tile_viewport(tile),
                slope_bias: light.shadow.depth_bias,
                light_sphere: Some(Sphere { center: light.position, radius: range }),
            });
        }
        let is_point = if request == OtherShadowRequest::Point { 1.0 } else { 0.0 };
        plan.other[slot] = Vec4::new(light.shadow.strength, first as f32, is_point, light_filter.index() as f32);
    }
    if plan.other_overflow > 0 {
        tracing::warn!(
            "{} point/spot lights get no realtime shadow: the {MAX_OTHER_SHADOW_TILES} tiles of the other-light atlas are taken",
            plan.other_overflow
        );
    }
    gpu.other_atlas = Vec4::new(os.atlas_size as f32, 1.0 / os.atlas_size as f32, 0.0, 0.0);
    plan.other_atlas_size = os.atlas_size;
}
