//! Plans the virtual shadow technique (`[shadows] technique = "virtual"`) on the CPU: each
//! shadowed light's maps (a clipmap level per directional level, a spot's one map, a
//! point or area light's six cube faces) before the frame, and, once the marking pass has
//! said which pages the frame's pixels want, where each page lies in the pool (kept from
//! frame to frame by chiaro_math's `PagePool`), the page table the shaders read and one
//! caster tile per page, which the shadow pass draws as it draws atlas tiles (the tile
//! cache keeps pages whose light and casters did not move). The math is
//! chiaro_math::shadow::virtual_map; this module only arranges it.

use super::draws::Draw;
use super::lights::LightId;
use super::shadows::{CasterTile, ShadowAtlas, ShadowPlan, ShadowSlot, ShadowSlots, light_filter, tile_casters};
use crate::gpu::{GpuAtlas, GpuVirtualMap};
use crate::shader_constants::{MAX_VIRTUAL_MAPS, VIRTUAL_MAP_CUBE_FACE, VIRTUAL_MAP_DIRECTIONAL, VIRTUAL_MAP_SPOT};
use crate::view::View;
use chiaro_math::camera::Projection;
use chiaro_math::shadow::bias::normal_bias_ws;
use chiaro_math::shadow::local::{POINT_LIGHT_FACES, perspective_normal_bias, point_face_view, spot_shadow_view};
use chiaro_math::shadow::virtual_map::{
    DepthRange, LOCAL_MIPS, MAP_PAGES, MAP_TEXELS, PagePool, PagePoolLayout, clipmap_extent_m, clipmap_level,
    clipmap_level_count, clipmap_page_clip_from_world, mip_table_offset, page_clip_from_map_clip, pages_per_side,
    table_entries,
};
use chiaro_math::{Aabb, Sphere};
use chiaro_scene::{Light, LightKind, Scene, Settings, ShadowMode};
use glam::{Mat4, Vec3};

/// A page as the pool knows it: a clipmap page by its place in the world, so that it
/// keeps its slot (and depths) while the camera moves; a point or spot page by its map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PageKey {
    /// World page (`x`, `y`) of a directional light's clipmap `level`.
    #[allow(missing_docs)]
    Clipmap { light: LightId, level: u32, x: i64, y: i64 },
    /// Page (`x`, `y`) of `mip` of a point or spot light's map `face` (0 for a spot).
    #[allow(missing_docs)]
    Local { light: LightId, face: u32, mip: u32, x: u32, y: u32 },
}

/// What the renderer keeps of the virtual technique from frame to frame.
#[derive(Clone, Debug)]
pub struct VirtualPages {
    /// Which slot holds which page.
    pub pool: PagePool<PageKey>,
    /// The pool's layout the slots were placed in.
    pub layout: PagePoolLayout,
}

/// How a map projects, for drawing its pages.
#[derive(Clone, Copy, Debug)]
enum MapProjection {
    /// A clipmap level: its pages' projections come from their world place.
    Clipmap { direction: Vec3, level: u32, first_page: (i64, i64), depth: DepthRange },
    /// A spot's map or a cube face: a page is a crop of it.
    Perspective { clip_from_world: Mat4, face: u32 },
}

/// One map besides its GPU record: whose it is and how its pages are drawn.
#[derive(Clone, Copy, Debug)]
struct MapSource {
    light: LightId,
    projection: MapProjection,
    slope_bias: f32,
    light_range: Option<Sphere>,
}

/// Counts of the frame's pages, for `bench` and the tests.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VirtualPageStats {
    /// Pages the frame's pixels asked for.
    pub requested: usize,
    /// Of those, the pages the pool could not hold (their pixels read a coarser page).
    pub dropped: usize,
    /// Pages the pool holds after the frame (this frame's and older ones').
    pub resident: usize,
    /// Megabytes the pool takes.
    pub pool_mb: f64,
}

/// The frame's virtual maps, its page table, and what its pages are.
#[derive(Clone, Debug, Default)]
pub struct VirtualShadowPlan {
    /// The maps the shaders read (`GpuVirtualMap`), by light.
    pub maps: Vec<GpuVirtualMap>,
    sources: Vec<MapSource>,
    /// Page-table entries of all maps.
    pub table_entries: u32,
    /// Per entry, 0 for no page, else the slot holding it as `PagePoolLayout::table_entry`
    /// writes it (1 + column + row << 16); filled by `place_pages`.
    pub page_table: Vec<u32>,
    /// The pool's layout (None without virtual maps).
    pub pool: Option<PagePoolLayout>,
    /// This frame's page counts.
    pub stats: VirtualPageStats,
}

impl VirtualShadowPlan {
    /// Whether the frame has virtual maps (and so a marking pass).
    pub fn is_active(&self) -> bool {
        !self.maps.is_empty()
    }

    /// Bytes of the marking pass's request bits: one bit per page-table entry.
    pub fn request_bytes(&self) -> u64 {
        self.table_entries.div_ceil(32) as u64 * 4
    }
}

/// Maps a row in the page-table debug view.
const PAGE_VIEW_MAPS_PER_ROW: usize = 6;
/// Pixels between maps in the page-table debug view.
const PAGE_VIEW_GAP: usize = 4;

impl VirtualShadowPlan {
    /// The page table as an image (the `virtual-pages` debug view): every map's finest
    /// page grid side by side (a clipmap's levels finest first, then each spot and cube
    /// face), a pixel per page of mip 0, coloured by the finest mip the pool holds there:
    /// white for mip 0 through yellow, green and cyan to blue for mip 7; dark grey where
    /// no page is held. (width, height, RGBA8); None without virtual maps.
    pub fn page_table_image(&self) -> Option<(usize, usize, Vec<[u8; 4]>)> {
        if !self.is_active() {
            return None;
        }
        let side = MAP_PAGES as usize;
        let columns = self.maps.len().min(PAGE_VIEW_MAPS_PER_ROW);
        let rows = self.maps.len().div_ceil(PAGE_VIEW_MAPS_PER_ROW);
        let (width, height) =
            (columns * (side + PAGE_VIEW_GAP) - PAGE_VIEW_GAP, rows * (side + PAGE_VIEW_GAP) - PAGE_VIEW_GAP);
        let mut pixels = vec![[0, 0, 0, 255]; width * height];
        for (i, map) in self.maps.iter().enumerate() {
            let (x0, y0) = (
                (i % PAGE_VIEW_MAPS_PER_ROW) * (side + PAGE_VIEW_GAP),
                (i / PAGE_VIEW_MAPS_PER_ROW) * (side + PAGE_VIEW_GAP),
            );
            for y in 0..MAP_PAGES {
                for x in 0..MAP_PAGES {
                    let held = (0..map.mips).find(|&mip| {
                        let (px, py, pages) = (x >> mip, y >> mip, pages_per_side(mip));
                        self.page_table[(map.table_offset + mip_table_offset(mip) + py * pages + px) as usize] != 0
                    });
                    pixels[(y0 + y as usize) * width + x0 + x as usize] = match held {
                        Some(mip) => mip_colour(mip),
                        None => [48, 48, 48, 255],
                    };
                }
            }
        }
        Some((width, height, pixels))
    }
}

/// The page-table view's colour of `mip`: white, yellow, green, cyan, blue.
fn mip_colour(mip: u32) -> [u8; 4] {
    const RAMP: [[u8; 3]; 8] = [
        [255, 255, 255],
        [255, 240, 110],
        [230, 200, 40],
        [120, 220, 60],
        [40, 200, 120],
        [40, 200, 220],
        [50, 120, 240],
        [70, 60, 230],
    ];
    let [r, g, b] = RAMP[(mip as usize).min(RAMP.len() - 1)];
    [r, g, b, 255]
}

/// The depths along `direction` that every drawn surface spans, with a metre to spare:
/// a clipmap's projections cover casters and receivers alike, and stay the same while
/// nothing moves past them.
fn depth_range(draws: &[Draw], direction: Vec3) -> DepthRange {
    let bounds = draws.iter().fold(Aabb::EMPTY, |b, d| b.union(&d.bounds_ws));
    if bounds.min.x > bounds.max.x {
        return DepthRange { near: -1.0, far: 1.0 };
    }
    let depths = bounds.corners().map(|c| c.dot(direction.normalize()));
    let near = depths.iter().copied().fold(f32::INFINITY, f32::min);
    let far = depths.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    DepthRange { near: near - 1.0, far: far + 1.0 }
}

/// How far from the eye a shadowed point can lie: the corners of the view at
/// `max_distance` (view depth), which lie further off the axis than the depth itself.
fn farthest_shadowed_point(view: &View, max_distance: f32) -> f32 {
    match view.projection {
        Projection::Perspective { yfov_rad } => {
            let tan_v = (yfov_rad * 0.5).tan();
            let tan_h = tan_v * view.aspect();
            max_distance * (1.0 + tan_v * tan_v + tan_h * tan_h).sqrt()
        }
        Projection::Orthographic { ymag } => {
            let xmag = ymag * view.aspect();
            (max_distance * max_distance + xmag * xmag + ymag * ymag).sqrt()
        }
    }
}

/// Plans the virtual maps of the frame's shadow-casting `directional` lights (slot order)
/// and `local` lights (most important first, with their ranges; at most
/// `shadows.other.max_tiles` maps of them, the rest `BakedOnly`), and the pool's size.
#[allow(clippy::too_many_arguments)]
pub fn plan_virtual_maps(
    plan: &mut ShadowPlan,
    scene: &Scene,
    draws: &[Draw],
    view: &View,
    settings: &Settings,
    max_distance: f32,
    directional: &[LightId],
    local: &[(LightId, f32)],
    max_texture_side: u32,
) -> ShadowSlots {
    let mut out = VirtualShadowPlan::default();
    let camera = view.eye();
    let levels = clipmap_level_count(farthest_shadowed_point(view, max_distance));
    let directional_filter = settings.shadows.directional.shadow_filter();
    let directional_slots = directional
        .iter()
        .map(|&id| {
            let light = &scene.lights[id.index()];
            if !light.shadow.casts() {
                return ShadowSlot::None;
            }
            if out.maps.len() + levels as usize > MAX_VIRTUAL_MAPS as usize {
                return ShadowSlot::BakedOnly;
            }
            let filter = light_filter(light, directional_filter);
            let first = out.maps.len() as u32;
            let (reach_size, reach_cap_texels) = reach(light);
            let depth = depth_range(draws, light.direction());
            for level in 0..levels {
                let fit = clipmap_level(light.direction(), camera, level, depth);
                push_map(
                    &mut out,
                    GpuVirtualMap {
                        clip_from_world: fit.clip_from_world,
                        mips: 1,
                        first_map: first,
                        map_count: levels,
                        kind: VIRTUAL_MAP_DIRECTIONAL,
                        texel_m: fit.texel_m,
                        normal_bias: light.shadow.normal_bias * normal_bias_ws(fit.texel_m, filter),
                        lens_far: depth.far - depth.near,
                        lens_metres_per_uv: clipmap_extent_m(level),
                        reach_size,
                        reach_cap_texels,
                        ..GpuVirtualMap::default()
                    },
                    MapSource {
                        light: id,
                        projection: MapProjection::Clipmap {
                            direction: light.direction(),
                            level,
                            first_page: fit.first_page,
                            depth,
                        },
                        slope_bias: light.shadow.depth_bias,
                        light_range: None,
                    },
                );
            }
            ShadowSlot::Realtime {
                first_tile: first,
                tile_count: levels,
                filter,
                pcss: light.shadow.mode == ShadowMode::Pcss,
                virtual_map: true,
            }
        })
        .collect();
    let local_filter = settings.shadows.other.shadow_filter();
    let mut local_maps_left =
        (settings.shadows.other.max_tiles as usize).min(MAX_VIRTUAL_MAPS as usize - out.maps.len());
    let local_slots = local
        .iter()
        .map(|&(id, range)| {
            let light = &scene.lights[id.index()];
            if !light.shadow.casts() {
                return ShadowSlot::None;
            }
            let faces = if light.kind == LightKind::Point || light.is_area() { POINT_LIGHT_FACES } else { 1 };
            if faces > local_maps_left {
                return ShadowSlot::BakedOnly;
            }
            local_maps_left -= faces;
            let filter = light_filter(light, local_filter);
            let first = out.maps.len() as u32;
            let (reach_size, reach_cap_texels) = reach(light);
            for (face, (clip_from_view, clip_from_world)) in local_views(light, range).into_iter().enumerate() {
                let lens = chiaro_math::shadow::pcss::perspective_lens(&clip_from_view, 1.0);
                push_map(
                    &mut out,
                    GpuVirtualMap {
                        clip_from_world,
                        light_position_ws: light.position(),
                        range,
                        mips: LOCAL_MIPS,
                        first_map: first,
                        map_count: faces as u32,
                        kind: if faces == 1 { VIRTUAL_MAP_SPOT } else { VIRTUAL_MAP_CUBE_FACE },
                        texel_m: 2.0 / (clip_from_view.x_axis.x * MAP_TEXELS as f32),
                        normal_bias: perspective_normal_bias(MAP_TEXELS, &clip_from_view, filter)
                            * light.shadow.normal_bias,
                        lens_near: lens[0],
                        lens_far: lens[1],
                        lens_metres_per_uv: lens[2],
                        reach_size,
                        reach_cap_texels,
                        ..GpuVirtualMap::default()
                    },
                    MapSource {
                        light: id,
                        projection: MapProjection::Perspective { clip_from_world, face: face as u32 },
                        slope_bias: light.shadow.depth_bias,
                        light_range: Some(Sphere { center: light.position(), radius: range }),
                    },
                );
            }
            ShadowSlot::Realtime {
                first_tile: first,
                tile_count: faces as u32,
                filter,
                pcss: light.shadow.mode == ShadowMode::Pcss,
                virtual_map: true,
            }
        })
        .collect();
    if out.is_active() {
        let pool = PagePoolLayout::for_megabytes(settings.shadows.virtual_pool_mb, max_texture_side);
        let side = pool.side_texels();
        plan.local_atlas_size = side;
        plan.gpu.local_atlas = GpuAtlas { size_texels: side as f32, texel_uv: 1.0 / side as f32, _pad: [0.0; 2] };
        plan.gpu.virtual_maps.map_count = out.maps.len() as u32;
        plan.gpu.virtual_map_records[..out.maps.len()].copy_from_slice(&out.maps);
        out.stats.pool_mb = pool.megabytes();
        out.pool = Some(pool);
        out.page_table = vec![0; out.table_entries as usize];
    }
    plan.virtual_maps = out;
    ShadowSlots { directional: directional_slots, local: local_slots }
}

/// Mip-0 texels of a PCSS light's blocker search that its lookups' mip keeps within a
/// page's border. The search itself reaches further where the light is wide and the
/// receiver far from the near plane; capping what the mip holds keeps the pages fine
/// (the search is then clamped to the page, as the atlas's is to an eighth of its tile).
/// Against the reference on the plank under 0.2 m point and spot lights and a 5 degree
/// sun (tests/soft_shadows.rs), mean |dv| point / spot / sun: a cap of 8 texels (the
/// footprint's mip alone) 0.0063 / 0.0063 / 0.0033, 256 0.0063 / 0.0059 / 0.0030, 1024
/// 0.0077 / 0.0167 (8.5% of pixels off by 0.1) / -.
const PCSS_REACH_CAP_TEXELS: f32 = 256.0;

/// What a contact-hardening light's lookups must reach (`GpuVirtualMap::reach_size`,
/// `reach_cap_texels`): the size its blocker search reads (shaders/shadows/pcss.wesl and
/// local.wesl's area_light_shadow), the tangent of a sun's half angle, an area light's
/// half diagonal, a point or spot light's radius; and the cap. An area light's rays reach
/// its whole extent from the receiver, so its mip holds all of it (uncapped); (0, 0) for
/// the other modes, whose filters reach no further than the pages' borders.
fn reach(light: &Light) -> (f32, f32) {
    if light.shadow.mode != ShadowMode::Pcss {
        return (0.0, 0.0);
    }
    match light.kind {
        LightKind::Directional => ((light.shadow.angular_diameter_deg.to_radians() * 0.5).tan(), PCSS_REACH_CAP_TEXELS),
        _ if light.is_area() => (light.kind.area_shape().map_or(0.0, |shape| shape.half_extents().length()), f32::MAX),
        _ => (light.shadow.light_radius, PCSS_REACH_CAP_TEXELS),
    }
}

/// A spot's view, or a point or area light's six cube faces of exactly 90 degrees (the
/// pages' borders hold what a filter near a face's edge reaches).
fn local_views(light: &Light, range: f32) -> Vec<(Mat4, Mat4)> {
    let near = light.shadow.near_plane;
    match light.kind {
        LightKind::Spot { outer_cone_rad, .. } => {
            vec![spot_shadow_view(light.position(), light.direction(), outer_cone_rad, near, range)]
        }
        _ => (0..POINT_LIGHT_FACES)
            .map(|face| point_face_view(light.position(), face, std::f32::consts::FRAC_PI_2, near, range))
            .collect(),
    }
}

fn push_map(out: &mut VirtualShadowPlan, map: GpuVirtualMap, source: MapSource) {
    out.maps.push(GpuVirtualMap { table_offset: out.table_entries, ..map });
    out.sources.push(source);
    out.table_entries += table_entries(map.mips);
}

/// A requested page: which map, which mip, where.
#[derive(Clone, Copy, Debug)]
struct RequestedPage {
    map: usize,
    mip: u32,
    x: u32,
    y: u32,
}

/// The pages whose bits `requests` (the marking pass's, one per page-table entry) sets,
/// coarsest first: when the pool is short, the pages every pixel can fall back to come
/// first.
fn requested_pages(plan: &VirtualShadowPlan, requests: &[u32]) -> Vec<RequestedPage> {
    let mut pages = Vec::new();
    for (map, gpu) in plan.maps.iter().enumerate() {
        for mip in 0..gpu.mips {
            let side = pages_per_side(mip);
            let first = gpu.table_offset + mip_table_offset(mip);
            for i in 0..side * side {
                let entry = (first + i) as usize;
                if requests.get(entry / 32).is_some_and(|word| word & (1 << (entry % 32)) != 0) {
                    pages.push(RequestedPage { map, mip, x: i % side, y: i / side });
                }
            }
        }
    }
    // Every map's fallback pages first (a clipmap's coarsest level, a point or spot map's
    // one-page mip), then coarser before finer: a clipmap's coarser level is its later
    // map, a point or spot map's its larger mip.
    let rank = |p: &RequestedPage| match plan.sources[p.map].projection {
        MapProjection::Clipmap { level, .. } => (level + 1 == plan.maps[p.map].map_count, level),
        MapProjection::Perspective { .. } => (p.mip + 1 == plan.maps[p.map].mips, p.mip),
    };
    pages.sort_by_key(|p| std::cmp::Reverse(rank(p)));
    pages
}

/// Places the pages the marking pass asked for (`requests`) in the pool kept in `pages`
/// (made anew when the pool's size changed), fills the page table, and adds a caster
/// tile per page to `shadows` (drawn by the shadow pass where the tile cache says so).
pub fn place_pages(
    shadows: &mut ShadowPlan,
    draws: &[Draw],
    requests: &[u32],
    unmarked: &[Aabb],
    pages: &mut Option<VirtualPages>,
) {
    let Some(layout) = shadows.virtual_maps.pool else {
        return;
    };
    let mut requests = requests.to_vec();
    request_fallbacks(&shadows.virtual_maps, unmarked, &mut requests);
    if pages.as_ref().is_none_or(|p| p.layout != layout) {
        *pages = Some(VirtualPages { pool: PagePool::new(layout.capacity()), layout });
    }
    let kept = pages.as_mut().expect("made above");
    let plan = &shadows.virtual_maps;
    let wanted = requested_pages(plan, &requests);
    let keys: Vec<PageKey> = wanted.iter().map(|p| page_key(plan, p)).collect();
    let slots = kept.pool.place(&keys);
    let mut tiles = Vec::new();
    let mut table = std::mem::take(&mut shadows.virtual_maps.page_table);
    for (page, slot) in wanted.iter().zip(&slots) {
        let Some(slot) = *slot else {
            continue;
        };
        let map = &shadows.virtual_maps.maps[page.map];
        let side = pages_per_side(page.mip);
        table[(map.table_offset + mip_table_offset(page.mip) + page.y * side + page.x) as usize] =
            layout.table_entry(slot);
        let source = &shadows.virtual_maps.sources[page.map];
        let clip_from_world = match source.projection {
            MapProjection::Clipmap { direction, level, first_page, depth } => {
                let world = (first_page.0 + page.x as i64, first_page.1 - page.y as i64);
                clipmap_page_clip_from_world(direction, level, world, depth)
            }
            MapProjection::Perspective { clip_from_world, .. } => {
                page_clip_from_map_clip(page.mip, page.x, page.y) * clip_from_world
            }
        };
        let mut tile = CasterTile {
            atlas: ShadowAtlas::Local,
            light: source.light,
            tile: slot,
            clip_from_world,
            viewport: layout.slot_viewport(slot),
            slope_bias: source.slope_bias,
            light_range: source.light_range,
            orthographic: matches!(source.projection, MapProjection::Clipmap { .. }),
            casters: Vec::new(),
            tint_casters: Vec::new(),
        };
        // Casters that let light through tint no virtual page: they cast no shadow here.
        tile.casters = tile_casters(draws, &tile).into_iter().filter(|&d| !draws[d as usize].tints_shadows).collect();
        tiles.push(tile);
    }
    shadows.virtual_maps.page_table = table;
    shadows.virtual_maps.stats.requested = wanted.len();
    shadows.virtual_maps.stats.dropped = slots.iter().filter(|s| s.is_none()).count();
    shadows.virtual_maps.stats.resident = kept.pool.resident();
    shadows.tiles = tiles;
}

/// Adds to `requests` the fallback pages the marking frame cannot ask for: every point
/// and spot map's one-page mip, and the coarsest clipmap level's pages over the bounds
/// of the `unmarked` surfaces (those its opaque-only prepass leaves out: alpha-tested,
/// transmissive and blended ones), so that no lookup finds no page.
fn request_fallbacks(plan: &VirtualShadowPlan, unmarked: &[Aabb], requests: &mut [u32]) {
    let mut set = |entry: u32| set_request(requests, entry);
    for (i, map) in plan.maps.iter().enumerate() {
        if map.kind != VIRTUAL_MAP_DIRECTIONAL {
            set(map.table_offset + mip_table_offset(map.mips - 1));
        } else if map.first_map + map.map_count == i as u32 + 1 {
            for bounds in unmarked {
                let uv = bounds.corners().map(|c| {
                    let ndc = map.clip_from_world.project_point3(c);
                    glam::Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5)
                });
                let (lo, hi) = uv
                    .iter()
                    .fold((glam::Vec2::INFINITY, glam::Vec2::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
                let pages = MAP_PAGES as f32;
                let first = (lo * pages).floor().clamp(glam::Vec2::ZERO, glam::Vec2::splat(pages - 1.0));
                let last = (hi * pages).floor().clamp(glam::Vec2::ZERO, glam::Vec2::splat(pages - 1.0));
                for y in first.y as u32..=last.y as u32 {
                    for x in first.x as u32..=last.x as u32 {
                        set(map.table_offset + y * MAP_PAGES + x);
                    }
                }
            }
        }
    }
}

/// Sets the request bit of page-table entry `entry` (as the marking pass does).
fn set_request(requests: &mut [u32], entry: u32) {
    if let Some(word) = requests.get_mut(entry as usize / 32) {
        *word |= 1 << (entry % 32);
    }
}

fn page_key(plan: &VirtualShadowPlan, page: &RequestedPage) -> PageKey {
    let source = &plan.sources[page.map];
    match source.projection {
        MapProjection::Clipmap { level, first_page, .. } => PageKey::Clipmap {
            light: source.light,
            level,
            x: first_page.0 + page.x as i64,
            y: first_page.1 - page.y as i64,
        },
        MapProjection::Perspective { face, .. } => {
            PageKey::Local { light: source.light, face, mip: page.mip, x: page.x, y: page.y }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Adds a spot's map (an identity projection) as map `first`.
    fn push_spot_map(plan: &mut VirtualShadowPlan, first: u32) {
        let source = MapSource {
            light: LightId(first),
            projection: MapProjection::Perspective { clip_from_world: Mat4::IDENTITY, face: 0 },
            slope_bias: 0.0,
            light_range: None,
        };
        let map = GpuVirtualMap {
            mips: LOCAL_MIPS,
            first_map: first,
            map_count: 1,
            kind: VIRTUAL_MAP_SPOT,
            ..Default::default()
        };
        push_map(plan, map, source);
    }

    #[test]
    fn coarse_pages_come_first() {
        let mut plan = VirtualShadowPlan::default();
        push_spot_map(&mut plan, 0);
        let mut bits = vec![0u32; plan.request_bytes() as usize / 4];
        // Page (3, 2) of mip 0 and the one page of the last mip.
        set_request(&mut bits, 2 * MAP_PAGES + 3);
        set_request(&mut bits, mip_table_offset(LOCAL_MIPS - 1));
        let pages = requested_pages(&plan, &bits);
        assert_eq!(pages.len(), 2);
        assert_eq!((pages[0].mip, pages[0].x, pages[0].y), (LOCAL_MIPS - 1, 0, 0));
        assert_eq!((pages[1].mip, pages[1].x, pages[1].y), (0, 3, 2));
    }

    #[test]
    fn fallback_pages_cover_what_the_marks_cannot() {
        let mut plan = VirtualShadowPlan::default();
        let depth = DepthRange { near: -20.0, far: 20.0 };
        let direction = Vec3::new(0.2, -1.0, 0.1);
        let levels = 3;
        for level in 0..levels {
            let fit = clipmap_level(direction, Vec3::ZERO, level, depth);
            let map = GpuVirtualMap {
                clip_from_world: fit.clip_from_world,
                mips: 1,
                map_count: levels,
                kind: VIRTUAL_MAP_DIRECTIONAL,
                ..GpuVirtualMap::default()
            };
            let projection = MapProjection::Clipmap { direction, level, first_page: fit.first_page, depth };
            let source = MapSource { light: LightId(0), projection, slope_bias: 0.0, light_range: None };
            push_map(&mut plan, map, source);
        }
        push_spot_map(&mut plan, 3);
        let mut bits = vec![0u32; plan.request_bytes() as usize / 4];
        // A blended pane 1 m across at the origin: the coarsest level's pages under it.
        let pane = Aabb { min: Vec3::new(-0.5, 0.0, -0.5), max: Vec3::new(0.5, 1.0, 0.5) };
        request_fallbacks(&plan, &[pane], &mut bits);
        let pages = requested_pages(&plan, &bits);
        let spot_pages: Vec<_> = pages.iter().filter(|p| p.map == 3).collect();
        assert_eq!(spot_pages.len(), 1, "the spot's one-page mip");
        assert_eq!(spot_pages[0].mip, LOCAL_MIPS - 1);
        let clipmap: Vec<_> = pages.iter().filter(|p| p.map < 3).collect();
        assert!(clipmap.iter().all(|p| p.map == 2), "only the coarsest level");
        // 16 m across in 128 pages: 1/8 m pages, the pane and its slant span a few.
        assert!((4..=200).contains(&clipmap.len()), "{}", clipmap.len());
        // Fallbacks come first.
        assert!(pages[0].map == 2 || pages[0].map == 3);
    }

    #[test]
    fn the_page_table_view_colours_each_page_by_the_finest_mip_held() {
        let mut plan = VirtualShadowPlan::default();
        push_spot_map(&mut plan, 0);
        plan.page_table = vec![0; plan.table_entries as usize];
        // Page (3, 2) of mip 0, and mip 1's page over (0..2, 0..2).
        plan.page_table[(2 * MAP_PAGES + 3) as usize] = 1;
        plan.page_table[mip_table_offset(1) as usize] = 2;
        let (width, height, pixels) = plan.page_table_image().unwrap();
        assert_eq!((width, height), (128, 128));
        assert_eq!(pixels[2 * 128 + 3], mip_colour(0));
        assert_eq!(pixels[128 + 1], mip_colour(1));
        assert_eq!(pixels[0], mip_colour(1));
        assert_eq!(pixels[5 * 128 + 5], [48, 48, 48, 255]);
    }
}
