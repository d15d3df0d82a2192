//! Plans a frame's realtime shadows on the CPU: which lights get atlas tiles (kept from
//! frame to frame by chiaro_math's `TileAllocator`), each directional cascade's culling
//! sphere and stable projection, each spot's and cube face's perspective projection, the
//! casters each tile draws, and the shadow uniform the shaders read. The math is
//! chiaro_math::shadow; this module only arranges it.

use super::draws::Draw;
use super::lights::LightId;
use super::shadow_cache::TileCache;
use super::virtual_shadows::{VirtualPages, VirtualShadowPlan, plan_virtual_maps};
use crate::gpu::{GpuAtlas, GpuCascade, GpuContactShadows, GpuShadowFade, GpuShadowTile, GpuShadows};
use crate::shader_constants::{
    CASCADE_BLEND_DITHER, CASCADE_BLEND_HARD, CASCADE_BLEND_SOFT, MAX_DIRECTIONAL_SHADOW_TILES, MAX_LOCAL_SHADOW_TILES,
};
use crate::view::View;
use chiaro_math::camera::Projection;
use chiaro_math::shadow::bias::{cascade_texel_size_ws, normal_bias_ws};
use chiaro_math::shadow::cascades::orthographic_slice_culling_sphere;
use chiaro_math::shadow::culling::{caster_in_range, caster_in_tile};
use chiaro_math::shadow::fade::distance_fade_params;
use chiaro_math::shadow::local::{
    POINT_LIGHT_FACES, facing_faces, perspective_normal_bias, point_face_fov_rad, point_face_view, spot_shadow_view,
};
use chiaro_math::shadow::pcss::{DIRECTIONAL_NEAR_PLANE_PULL, orthographic_lens, perspective_lens};
use chiaro_math::shadow::tiers::{
    TileRect, coverage_tier, double_facing_tiles, pack_tiles, screen_coverage, tile_sizes,
};
use chiaro_math::shadow::{
    AtlasLayout, ShadowFilter, TileAllocation, TileAllocator, cascade_splits, first_fit_tiles, fit_cascade,
    slice_culling_sphere,
};
use chiaro_math::{Frustum, Sphere};
use chiaro_scene::settings::LocalShadowSettings;
use chiaro_scene::{CascadeBlend, Light, LightKind, Scene, Settings, ShadowMode, ShadowTechnique};
use glam::Mat4;

/// Where a light's realtime shadow comes from this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadowSlot {
    /// The light casts no shadows (extras `shadows: none`, or strength 0).
    None,
    /// Sampled from `tile_count` tiles of its atlas from `first_tile` (one per cascade,
    /// one per spot, six per point light).
    Realtime {
        /// Index of its first tile in its atlas.
        first_tile: u32,
        /// Tiles it has, consecutive from `first_tile`.
        tile_count: u32,
        /// The filter its shadow is sampled with (and, for `pcss`, whose reach sizes the
        /// biases).
        filter: ShadowFilter,
        /// Contact-hardening (`"shadows": "pcss"`) instead of `filter`.
        pcss: bool,
        /// From `tile_count` virtual maps from `first_tile` (`[shadows] technique =
        /// "virtual"`, `plan::virtual_shadows`) instead of atlas tiles.
        virtual_map: bool,
    },
    /// It casts shadows but found no free atlas tiles: no realtime shadow; baked shadows
    /// (the tutorial's negative strength) are what would apply.
    BakedOnly,
}

/// Which of the two atlases a tile lies in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShadowAtlas {
    /// Directional cascades: orthographic tiles, depth clamped (pancaking).
    Directional,
    /// Spot and point lights: perspective tiles, never clamped.
    Local,
}

/// One tile to render casters into.
#[derive(Clone, Debug)]
pub struct CasterTile {
    /// The atlas the tile lies in.
    pub atlas: ShadowAtlas,
    /// The light it holds the shadow of.
    pub light: LightId,
    /// Tile index in its atlas.
    pub tile: u32,
    /// World space to the tile's light clip space.
    pub clip_from_world: Mat4,
    /// (x, y, size) in texels.
    pub viewport: (u32, u32, u32),
    /// Slope-scale depth bias of the light.
    pub slope_bias: f32,
    /// A point or spot light's range sphere: its tiles draw the casters inside it.
    pub light_range: Option<Sphere>,
    /// An orthographic projection (cascades, clipmap pages): casters before its near
    /// plane are flattened onto it (depth clamping); perspective tiles must not flatten
    /// casters behind the light.
    pub orthographic: bool,
    /// Indices into the scene's draws of the casters that can reach the tile and write
    /// its depth.
    pub casters: Vec<u32>,
    /// Those that can reach it and let light through (`Draw::tints_shadows`): drawn into
    /// the shadow tints instead.
    pub tint_casters: Vec<u32>,
}

/// A local light's request in the atlas: the light, its tiles' side in texels, and which
/// of its tiles (bit k: tile k) are twice that (an area light's faces towards its
/// emitting side, `tiers::double_facing_tiles`).
pub type LocalTileKey = (LightId, u32, u8);

/// Tile allocators of both atlases, kept by the renderer from frame to frame.
#[derive(Clone, Debug)]
pub struct ShadowAtlasTiles {
    /// The directional atlas's allocator: one run of cascade tiles per light.
    pub directional: TileAllocator<LightId>,
    /// Keyed by light and tile sizes: a light whose tier changes is allocated anew.
    pub local: TileAllocator<LocalTileKey>,
    /// Each point and spot light's coverage tier last frame (`tiers::coverage_tier`).
    pub local_tiers: std::collections::HashMap<LightId, u32>,
    /// What the atlases hold, so that unchanged tiles are not drawn again.
    pub cache: TileCache,
    /// Which pool slot holds which virtual page (`[shadows] technique = "virtual"`).
    pub virtual_pages: Option<VirtualPages>,
    /// The device's largest texture side, which bounds the virtual pool.
    pub max_texture_side: u32,
}

impl Default for ShadowAtlasTiles {
    fn default() -> Self {
        ShadowAtlasTiles {
            directional: TileAllocator::new(MAX_DIRECTIONAL_SHADOW_TILES as usize),
            local: TileAllocator::new(MAX_LOCAL_SHADOW_TILES as usize),
            local_tiers: std::collections::HashMap::new(),
            cache: TileCache::default(),
            virtual_pages: None,
            max_texture_side: 8192,
        }
    }
}

/// A frame's realtime shadows: the shadow uniform, atlas sizes, tiles to draw and the
/// cascades' spheres.
#[derive(Clone, Debug)]
pub struct ShadowPlan {
    /// The shadow uniform the shaders read.
    pub gpu: GpuShadows,
    /// Atlas sides in texels; 0 when no light casts into that atlas this frame.
    pub directional_atlas_size: u32,
    /// See `directional_atlas_size`.
    pub local_atlas_size: u32,
    /// Directional tiles first, then point and spot tiles.
    pub tiles: Vec<CasterTile>,
    /// World-space culling spheres (unshrunk), for the debug view and the tests.
    pub cascade_spheres: Vec<Sphere>,
    /// Every shadowed light kept the tiles it had last frame.
    pub tiles_kept: bool,
    /// Per tile, whether this frame draws it (`shadow_cache::TileCache`); the others keep
    /// the depths an earlier frame drew. None are drawn for a frame that shades nothing.
    pub redraw: Vec<bool>,
    /// The virtual technique's maps, page table and pool (empty with the atlas
    /// technique); its pages join `tiles` once placed.
    pub virtual_maps: VirtualShadowPlan,
}

impl ShadowPlan {
    /// The side of `atlas` in texels this frame.
    pub fn atlas_size(&self, atlas: ShadowAtlas) -> u32 {
        match atlas {
            ShadowAtlas::Directional => self.directional_atlas_size,
            ShadowAtlas::Local => self.local_atlas_size,
        }
    }

    /// The tiles this frame draws, with their index in `tiles`.
    pub fn redrawn_tiles(&self) -> impl Iterator<Item = (usize, &CasterTile)> {
        self.tiles.iter().enumerate().filter(|(i, _)| self.redraw[*i])
    }
}

/// The slot of each input light, in input order.
pub struct ShadowSlots {
    /// One slot per directional light.
    pub directional: Vec<ShadowSlot>,
    /// One slot per point and spot light.
    pub local: Vec<ShadowSlot>,
}

/// The light's filter: `hard` lights take the 2x2 one whatever the settings say.
pub(super) fn light_filter(light: &Light, settings_filter: ShadowFilter) -> ShadowFilter {
    match light.shadow.mode {
        ShadowMode::Hard => ShadowFilter::Pcf2x2,
        _ => settings_filter,
    }
}

/// Plans shadows for the frame's `directional` lights (slot order) and `local` lights
/// (most important first, with the range each is shaded with).
pub fn plan_shadows(
    scene: &Scene,
    draws: &[Draw],
    view: &View,
    settings: &Settings,
    directional: &[LightId],
    local: &[(LightId, f32)],
    atlases: &mut ShadowAtlasTiles,
) -> (ShadowPlan, ShadowSlots) {
    let ds = &settings.shadows.directional;
    let max_distance = match view.zfar {
        Some(far) => settings.shadows.max_distance.min(far),
        None => settings.shadows.max_distance,
    };
    let [inverse_max_distance, inverse_distance_fade, inverse_cascade_fade] =
        distance_fade_params(max_distance, settings.shadows.distance_fade, ds.cascade_fade);
    let mut plan = ShadowPlan {
        gpu: GpuShadows {
            fade: GpuShadowFade { inverse_max_distance, inverse_distance_fade, inverse_cascade_fade, _pad: 0.0 },
            cascade_blend: match ds.cascade_blend {
                CascadeBlend::Hard => CASCADE_BLEND_HARD,
                CascadeBlend::Soft => CASCADE_BLEND_SOFT,
                CascadeBlend::Dither => CASCADE_BLEND_DITHER,
            },
            // At least one: the shaders' sample loops test at their end.
            pcss_blocker_samples: settings.shadows.pcss_blocker_samples.max(1),
            pcss_filter_samples: settings.shadows.pcss_filter_samples.max(1),
            contact: GpuContactShadows {
                length_m: settings.shadows.contact_length,
                thickness_m: settings.shadows.contact_thickness,
                steps: if settings.shadows.contact { settings.shadows.contact_steps } else { 0 },
                _pad: 0,
            },
            ..GpuShadows::default()
        },
        directional_atlas_size: 0,
        local_atlas_size: 0,
        tiles: Vec::new(),
        cascade_spheres: Vec::new(),
        tiles_kept: true,
        redraw: Vec::new(),
        virtual_maps: VirtualShadowPlan::default(),
    };
    if settings.shadows.technique == ShadowTechnique::Virtual {
        let max_side = atlases.max_texture_side;
        let slots =
            plan_virtual_maps(&mut plan, scene, draws, view, settings, max_distance, directional, local, max_side);
        return (plan, slots);
    }
    let directional_slots = plan_directional(&mut plan, scene, view, settings, max_distance, directional, atlases);
    let local_slots = plan_local(&mut plan, scene, view, settings, local, atlases);
    for tile in &mut plan.tiles {
        let (casters, tint_casters) =
            tile_casters(draws, tile).into_iter().partition(|&d| !draws[d as usize].tints_shadows);
        tile.casters = casters;
        tile.tint_casters = tint_casters;
    }
    (plan, ShadowSlots { directional: directional_slots, local: local_slots })
}

fn plan_directional(
    plan: &mut ShadowPlan,
    scene: &Scene,
    view: &View,
    settings: &Settings,
    max_distance: f32,
    directional: &[LightId],
    atlases: &mut ShadowAtlasTiles,
) -> Vec<ShadowSlot> {
    let ds = &settings.shadows.directional;
    let filter = ds.shadow_filter();
    let cascade_count = ds.cascade_count as usize;
    let requests: Vec<(LightId, usize)> = directional
        .iter()
        .filter(|id| scene.lights[id.index()].shadow.casts())
        .map(|&id| (id, cascade_count))
        .collect();
    let allocation = atlases.directional.allocate(&requests);
    plan.tiles_kept &= allocation.kept;
    if requests.is_empty() {
        return vec![ShadowSlot::None; directional.len()];
    }
    let layout = AtlasLayout::for_tiles(ds.atlas_size, allocation.used_tiles);
    let tile_size = layout.tile_size();
    let splits = cascade_splits(max_distance, ds.ratios(), cascade_count);
    let texel_sizes = plan_cascade_spheres(plan, view, &splits, tile_size, filter);
    let first_tiles: std::collections::HashMap<LightId, usize> = requests
        .iter()
        .zip(&allocation.first_tiles)
        .map(|(&(id, _), first)| (id, first.expect("every directional light fits its atlas")))
        .collect();
    let slots = directional
        .iter()
        .map(|id| {
            let Some(&first_tile) = first_tiles.get(id) else {
                return ShadowSlot::None;
            };
            let light = &scene.lights[id.index()];
            let filter = light_filter(light, filter);
            let pcss = light.shadow.mode == ShadowMode::Pcss;
            for (c, sphere) in plan.cascade_spheres.iter().enumerate() {
                let tile = first_tile + c;
                let near_plane = match pcss {
                    true => light.shadow.near_plane.max(DIRECTIONAL_NEAR_PLANE_PULL * sphere.radius),
                    false => light.shadow.near_plane,
                };
                let fit = fit_cascade(*sphere, light.direction(), tile_size, near_plane);
                let (uv_min, uv_max) = layout.tile_bounds_uv(tile);
                let atlas_from_world = layout.atlas_from_clip(tile) * fit.clip_from_world;
                plan.gpu.directional_tiles[tile] = GpuShadowTile {
                    atlas_from_world,
                    uv_min,
                    uv_max,
                    normal_bias: light.shadow.normal_bias * normal_bias_ws(texel_sizes[c], filter),
                    ..GpuShadowTile::default()
                }
                .with_lens(orthographic_lens(&atlas_from_world));
                plan.tiles.push(CasterTile {
                    atlas: ShadowAtlas::Directional,
                    light: *id,
                    tile: tile as u32,
                    clip_from_world: fit.clip_from_world,
                    viewport: layout.tile_viewport(tile),
                    slope_bias: light.shadow.depth_bias,
                    light_range: None,
                    orthographic: true,
                    casters: Vec::new(),
                    tint_casters: Vec::new(),
                });
            }
            ShadowSlot::Realtime {
                first_tile: first_tile as u32,
                tile_count: cascade_count as u32,
                filter,
                pcss,
                virtual_map: false,
            }
        })
        .collect();
    plan.gpu.cascade_count = cascade_count as u32;
    plan.gpu.directional_atlas = atlas_params(ds.atlas_size);
    plan.directional_atlas_size = ds.atlas_size;
    slots
}

/// Each cascade's culling sphere around its slice of the view (kept in the plan, shrunk by
/// the filter's reach for the shader), and the world-space size of its texels.
fn plan_cascade_spheres(
    plan: &mut ShadowPlan,
    view: &View,
    splits: &[f32],
    tile_size: u32,
    filter: ShadowFilter,
) -> Vec<f32> {
    let mut texel_sizes = Vec::with_capacity(splits.len());
    for (i, &far) in splits.iter().enumerate() {
        let near = if i == 0 { view.znear } else { splits[i - 1] };
        let far = far.max(near + 1e-3);
        let sphere_vs = match view.projection {
            Projection::Perspective { yfov_rad } => {
                slice_culling_sphere(near, far, (yfov_rad * 0.5).tan(), view.aspect())
            }
            Projection::Orthographic { ymag } => {
                orthographic_slice_culling_sphere(near, far, ymag * view.aspect(), ymag)
            }
        };
        let sphere =
            Sphere { center: view.world_from_view.transform_point3(sphere_vs.center), radius: sphere_vs.radius };
        let texel = cascade_texel_size_ws(sphere.radius, tile_size);
        // Shrink by the filter's reach so samples near the edge stay inside the tile.
        let shrunk = (sphere.radius - texel * filter.footprint_texels()).max(sphere.radius * 0.5);
        plan.gpu.cascades[i] = GpuCascade {
            culling_sphere_center_ws: sphere.center,
            radius_squared: shrunk * shrunk,
            inverse_radius_squared: 1.0 / (shrunk * shrunk),
            _pad: [0.0; 3],
        };
        plan.cascade_spheres.push(sphere);
        texel_sizes.push(texel);
    }
    texel_sizes
}

/// Tiles in the second atlas for the point and spot lights that cast shadows, in
/// importance order, sized by how much of the screen each light covers
/// (chiaro_math::shadow::tiers); a light that does not fit becomes `BakedOnly`.
fn plan_local(
    plan: &mut ShadowPlan,
    scene: &Scene,
    view: &View,
    settings: &Settings,
    local: &[(LightId, f32)],
    atlases: &mut ShadowAtlasTiles,
) -> Vec<ShadowSlot> {
    let os = &settings.shadows.other;
    let requests = local_tile_requests(scene, view, os, local, atlases);
    let allocation = atlases.local.allocate(&requests);
    plan.tiles_kept &= allocation.kept;
    if requests.is_empty() {
        return vec![ShadowSlot::None; local.len()];
    }
    let (first_tiles, rects) = place_local_tiles(os.atlas_size, &requests, &allocation);
    let mut overflow = Vec::new();
    let slots = local
        .iter()
        .map(|&(id, range)| {
            let light = &scene.lights[id.index()];
            let Some(&first) = first_tiles.get(&id) else {
                return ShadowSlot::None;
            };
            let Some(first_tile) = first else {
                overflow.push(light.name.clone());
                return ShadowSlot::BakedOnly;
            };
            let placed = PlacedLight { id, light, range, first_tile };
            plan_local_light_tiles(plan, &placed, &rects, os)
        })
        .collect();
    if !overflow.is_empty() {
        tracing::warn!("{}", overflow_warning(&overflow, os.max_tiles));
    }
    plan.gpu.local_atlas = atlas_params(os.atlas_size);
    plan.local_atlas_size = os.atlas_size;
    slots
}

/// The warning for the point and spot lights that found no atlas tiles: how many, and
/// the first few by name.
fn overflow_warning(names: &[String], max_tiles: u32) -> String {
    format!(
        "{} point/spot lights get no realtime shadow, the {max_tiles} tiles of the local-light atlas being taken \
         (shadows.other.max_tiles): {}",
        names.len(),
        chiaro_scene::names::few_names(names)
    )
}

/// The tile requests of the shadow-casting `local` lights, in their order: each light's
/// key (id, tile size of its coverage tier, the tiles doubled) and tile count (six for a
/// point or area light). Also records the tiers in `atlases` and resizes its allocator
/// when `max_tiles` changed.
fn local_tile_requests(
    scene: &Scene,
    view: &View,
    os: &LocalShadowSettings,
    local: &[(LightId, f32)],
    atlases: &mut ShadowAtlasTiles,
) -> Vec<(LocalTileKey, usize)> {
    // Area lights are shadowed from their centre by a cube, as points are.
    let tiles_wanted =
        |light: &Light| if light.kind == LightKind::Point || light.is_area() { POINT_LIGHT_FACES } else { 1 };
    let view_from_world = view.view_from_world();
    let casting: Vec<(LightId, usize, u32)> = local
        .iter()
        .filter(|&&(id, _)| scene.lights[id.index()].shadow.casts())
        .map(|&(id, range)| {
            let light = &scene.lights[id.index()];
            let coverage = screen_coverage(&view_from_world, &view.clip_from_view, light.position(), range);
            let tier = coverage_tier(os.atlas_size, coverage, atlases.local_tiers.get(&id).copied());
            (id, tiles_wanted(light), tier)
        })
        .collect();
    atlases.local_tiers = casting.iter().map(|&(id, _, tier)| (id, tier)).collect();
    if atlases.local.capacity() != os.max_tiles as usize {
        atlases.local = TileAllocator::new(os.max_tiles as usize);
    }
    // Which lights fit decides the tile sizes; the sizes are part of each request.
    let counts: Vec<usize> = casting.iter().map(|&(_, n, _)| n).collect();
    let fits = first_fit_tiles(&counts, os.max_tiles as usize);
    let fitting: Vec<&(LightId, usize, u32)> =
        casting.iter().zip(&fits).filter(|(_, f)| f.is_some()).map(|(c, _)| c).collect();
    let base_sizes = tile_sizes(os.atlas_size, &fitting.iter().map(|&&(_, n, tier)| (n, tier)).collect::<Vec<_>>());
    let doubled = doubled_faces(scene, os.atlas_size, &fitting, &base_sizes);
    let mut per_fitting = base_sizes.into_iter().zip(doubled);
    casting
        .iter()
        .zip(&fits)
        .map(|(&(id, n, _), fit)| {
            // Lights that do not fit ask for the smallest tiles; they get none anyway.
            let (size, doubled) =
                if fit.is_some() { per_fitting.next().expect("one size per fitting light") } else { (0, 0) };
            ((id, size, doubled), n)
        })
        .collect()
}

/// Per light of `fitting` (id, tile count, tier), the bitmask of its tiles that are twice
/// `base_sizes`: an area light emits from one side, so the cube faces facing it get finer
/// tiles where the atlas has room. Lights are taken in the scene's order, not by
/// importance, which changes as the camera moves: where room is contended, the doubled
/// faces (part of the allocator's key) would otherwise swap and every tile be allocated
/// anew.
fn doubled_faces(scene: &Scene, atlas_size: u32, fitting: &[&(LightId, usize, u32)], base_sizes: &[u32]) -> Vec<u8> {
    let mut by_scene_order: Vec<usize> = (0..fitting.len()).collect();
    by_scene_order.sort_by_key(|&k| fitting[k].0.index());
    let facing: Vec<Vec<usize>> = by_scene_order
        .iter()
        .map(|&k| {
            let light = &scene.lights[fitting[k].0.index()];
            if light.is_area() { facing_faces(light.direction()) } else { Vec::new() }
        })
        .collect();
    let mut tiles: Vec<Vec<u32>> = by_scene_order.iter().map(|&k| vec![base_sizes[k]; fitting[k].1]).collect();
    double_facing_tiles(atlas_size, &mut tiles, &facing);
    let mut masks = vec![0u8; fitting.len()];
    for (&k, sides) in by_scene_order.iter().zip(&tiles) {
        masks[k] = sides.iter().enumerate().filter(|&(_, &side)| side != base_sizes[k]).fold(0, |m, (i, _)| m | 1 << i);
    }
    masks
}

/// Each requesting light's first tile (None: no free tile), and every used tile's
/// rectangle in the atlas.
type LocalTilePlaces = (std::collections::HashMap<LightId, Option<usize>>, Vec<TileRect>);

/// Where the allocated tiles lie: tile slot -> size, then their places, packed by slot
/// so that kept slots keep their places.
fn place_local_tiles(
    atlas_size: u32,
    requests: &[(LocalTileKey, usize)],
    allocation: &TileAllocation,
) -> LocalTilePlaces {
    let mut slot_sizes = vec![0u32; allocation.used_tiles.max(1)];
    let mut first_tiles = std::collections::HashMap::new();
    for (&((id, size, doubled), n), &first) in requests.iter().zip(&allocation.first_tiles) {
        first_tiles.insert(id, first);
        if let Some(f) = first {
            for (k, slot) in slot_sizes[f..f + n].iter_mut().enumerate() {
                *slot = size << ((doubled >> k) & 1);
            }
        }
    }
    let rects = pack_tiles(atlas_size, &slot_sizes[..allocation.used_tiles]).expect("tier sizes fit the atlas");
    (first_tiles, rects)
}

/// A point or spot light that was given tiles in the local-light atlas.
struct PlacedLight<'a> {
    id: LightId,
    light: &'a Light,
    /// The range it is shaded with, in metres: the far plane of its projections.
    range: f32,
    first_tile: usize,
}

/// Writes a placed light's tiles (one for a spot, six cube faces for a point light)
/// into the shadow uniform and the caster tiles, and returns its slot.
fn plan_local_light_tiles(
    plan: &mut ShadowPlan,
    placed: &PlacedLight<'_>,
    rects: &[TileRect],
    os: &LocalShadowSettings,
) -> ShadowSlot {
    let &PlacedLight { id, light, range, first_tile } = placed;
    let filter = light_filter(light, os.shadow_filter());
    let views: Vec<(Mat4, Mat4)> = match light.kind {
        LightKind::Spot { outer_cone_rad, .. } => {
            vec![spot_shadow_view(light.position(), light.direction(), outer_cone_rad, light.shadow.near_plane, range)]
        }
        // Each face's field of view widens by its own tile's texels (an area light's
        // facing faces may have finer tiles than the rest).
        _ => (0..POINT_LIGHT_FACES)
            .map(|face| {
                let fov = point_face_fov_rad(rects[first_tile + face].size, filter, light.shadow.normal_bias);
                point_face_view(light.position(), face, fov, light.shadow.near_plane, range)
            })
            .collect(),
    };
    for (k, (clip_from_view, clip_from_world)) in views.iter().enumerate() {
        let tile = first_tile + k;
        let rect = rects[tile];
        let tile_size = rect.size;
        let (uv_min, uv_max) = rect.bounds_uv(os.atlas_size);
        plan.gpu.local_tiles[tile] = GpuShadowTile {
            atlas_from_world: rect.atlas_from_clip(os.atlas_size) * *clip_from_world,
            uv_min,
            uv_max,
            normal_bias: perspective_normal_bias(tile_size, clip_from_view, filter) * light.shadow.normal_bias,
            ..GpuShadowTile::default()
        }
        .with_lens(perspective_lens(clip_from_view, tile_size as f32 / os.atlas_size as f32));
        plan.tiles.push(CasterTile {
            atlas: ShadowAtlas::Local,
            light: id,
            tile: tile as u32,
            clip_from_world: *clip_from_world,
            viewport: rect.viewport(),
            slope_bias: light.shadow.depth_bias,
            light_range: Some(Sphere { center: light.position(), radius: range }),
            orthographic: false,
            casters: Vec::new(),
            tint_casters: Vec::new(),
        });
    }
    ShadowSlot::Realtime {
        first_tile: first_tile as u32,
        tile_count: views.len() as u32,
        filter,
        pcss: light.shadow.mode == ShadowMode::Pcss,
        virtual_map: false,
    }
}

fn atlas_params(size: u32) -> GpuAtlas {
    GpuAtlas { size_texels: size as f32, texel_uv: 1.0 / size as f32, _pad: [0.0; 2] }
}

/// The casters that can draw into `tile`: those overlapping a perspective tile's light
/// range and its pyramid (each cube face of a point light draws only what lies in front
/// of that face), or a cascade tile's box (with pancaking).
pub(super) fn tile_casters(draws: &[Draw], tile: &CasterTile) -> Vec<u32> {
    let pyramid = Frustum::from_clip_from_world(&tile.clip_from_world);
    let reaches = |d: &Draw| match &tile.light_range {
        Some(sphere) => caster_in_range(&d.bounds_ws, sphere) && pyramid.sides_hold_aabb(&d.bounds_ws),
        None => caster_in_tile(&tile.clip_from_world, &d.bounds_ws, true),
    };
    let mut casters: Vec<u32> =
        (0..draws.len() as u32).filter(|&i| draws[i as usize].casts_shadows() && reaches(&draws[i as usize])).collect();
    // Primitive by primitive, so that the copies of an instanced mesh draw as one
    // instanced draw (`instanced_runs`); depth-only drawing does not depend on order.
    casters.sort_by_key(|&i| (draws[i as usize].first_index, i));
    casters
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_overflow_warning_counts_every_light_and_names_a_few() {
        let names: Vec<String> = (0..235).map(|i| format!("lamp {i}")).collect();
        let line = overflow_warning(&names, 64);
        assert!(line.starts_with("235 point/spot lights get no realtime shadow"), "{line}");
        assert!(line.ends_with("'lamp 0', 'lamp 1', 'lamp 2', 'lamp 3' and 231 more"), "{line}");
        assert!(!line.contains("lamp 4"), "{line}");
    }
}
