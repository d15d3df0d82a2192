//! Virtual shadow maps (`[shadows] technique = "virtual"`), free of the GPU: each map is
//! 16384 texels a side in pages of 128, with a mip chain down to one page; a page is drawn
//! into a slot of a fixed pool with a border of `PAGE_BORDER` texels on every side, so
//! that a filter tap near its edge reads the right depths without knowing about pages.
//! This module has the page grid and its crops, the pool's layout, the pool's
//! least-recently-used placement, and the directional clipmap: levels doubling in size
//! around the camera whose pages are fixed in the world, so a moving camera keeps them.

use glam::{Mat4, Vec2, Vec3};
use std::collections::{BinaryHeap, HashMap};
use std::hash::Hash;

/// Texels of a page's own area, a side.
pub const PAGE_TEXELS: u32 = 128;
/// Texels drawn around a page's own area on each side: the widest filter (7x7 tent)
/// reaches 4, and a blocker search is kept within it.
pub const PAGE_BORDER: u32 = 8;
/// A pool slot's side: a page with its border.
pub const PAGE_SLOT: u32 = PAGE_TEXELS + 2 * PAGE_BORDER;
/// Pages a side of a map's finest mip.
pub const MAP_PAGES: u32 = 128;
/// Texels a side of a map's finest mip.
pub const MAP_TEXELS: u32 = MAP_PAGES * PAGE_TEXELS;
/// Mips of a point or spot light's map: 128 pages a side down to one.
pub const LOCAL_MIPS: u32 = 8;
/// Most clipmap levels of a directional light.
pub const MAX_CLIPMAP_LEVELS: u32 = 16;
/// Metres a side of a directional light's finest clipmap level: a texel is 0.24 mm.
pub const CLIPMAP_FIRST_EXTENT_M: f32 = 4.0;
/// Bytes of one slot in the pool (32-bit depth).
pub const SLOT_BYTES: u64 = (PAGE_SLOT * PAGE_SLOT * 4) as u64;

/// Pages a side at `mip`.
pub const fn pages_per_side(mip: u32) -> u32 {
    MAP_PAGES >> mip
}

/// Where `mip`'s pages start in a map's page table (row-major, finest mip first).
pub fn mip_table_offset(mip: u32) -> u32 {
    (0..mip).map(|m| pages_per_side(m) * pages_per_side(m)).sum()
}

/// Page-table entries of a map with `mips` mips.
pub fn table_entries(mips: u32) -> u32 {
    mip_table_offset(mips)
}

/// A page's area with its border in the map's texture coordinates (u right, v down,
/// both 0 to 1 over the map): its top-left corner and its side.
pub fn page_uv_rect(mip: u32, x: u32, y: u32) -> (Vec2, f32) {
    let pages = pages_per_side(mip) as f32;
    let border = PAGE_BORDER as f32 / (PAGE_TEXELS as f32 * pages);
    let corner = Vec2::new(x as f32, y as f32) / pages - Vec2::splat(border);
    (corner, 1.0 / pages + 2.0 * border)
}

/// The crop that takes a map's clip space (x, y in [-1, 1], y up) to the clip space of
/// page (`x`, `y`) of `mip` with its border, depth and w unchanged: a page is drawn with
/// `page_clip_from_map_clip * map_clip_from_world` into its slot.
pub fn page_clip_from_map_clip(mip: u32, x: u32, y: u32) -> Mat4 {
    let (corner, side) = page_uv_rect(mip, x, y);
    let s = 1.0 / side;
    Mat4::from_cols_array(&[
        s,
        0.0,
        0.0,
        0.0,
        0.0,
        s,
        0.0,
        0.0,
        0.0,
        0.0,
        1.0,
        0.0,
        (1.0 - 2.0 * corner.x) * s - 1.0,
        1.0 - (1.0 - 2.0 * corner.y) * s,
        0.0,
        1.0,
    ])
}

/// The pool: a square depth texture of slots `PAGE_SLOT` texels a side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PagePoolLayout {
    /// Slots a side.
    pub slots_per_side: u32,
}

impl PagePoolLayout {
    /// The largest square pool within `megabytes` and a texture side of
    /// `max_texture_side` (at least one slot).
    pub fn for_megabytes(megabytes: u32, max_texture_side: u32) -> PagePoolLayout {
        let slots = (megabytes as u64 * (1 << 20)) / SLOT_BYTES;
        let side = ((slots as f64).sqrt().floor() as u32).clamp(1, (max_texture_side / PAGE_SLOT).max(1));
        PagePoolLayout { slots_per_side: side }
    }

    /// Slots in the pool.
    pub fn capacity(&self) -> usize {
        (self.slots_per_side * self.slots_per_side) as usize
    }

    /// The pool texture's side in texels.
    pub fn side_texels(&self) -> u32 {
        self.slots_per_side * PAGE_SLOT
    }

    /// Megabytes the pool texture takes.
    pub fn megabytes(&self) -> f64 {
        self.capacity() as f64 * SLOT_BYTES as f64 / (1 << 20) as f64
    }

    /// A slot's viewport in texels: (x, y, side).
    pub fn slot_viewport(&self, slot: u32) -> (u32, u32, u32) {
        let (x, y) = (slot % self.slots_per_side, slot / self.slots_per_side);
        (x * PAGE_SLOT, y * PAGE_SLOT, PAGE_SLOT)
    }

    /// A resident page's page-table entry: 1 + its slot's column + (row << 16), so that
    /// 0 means no page and the shader finds the slot without an integer division (which
    /// a CPU rasteriser does lane by lane).
    pub fn table_entry(&self, slot: u32) -> u32 {
        let (x, y) = (slot % self.slots_per_side, slot / self.slots_per_side);
        1 + x + (y << 16)
    }
}

/// Which slot holds which page, kept from frame to frame: pages asked for again keep
/// their slots (and, unless their content changed, their depths); new pages take free
/// slots, then those no page of this frame uses, least recently used first.
#[derive(Clone, Debug)]
pub struct PagePool<K> {
    owners: Vec<Option<K>>,
    last_used: Vec<u64>,
    slots: HashMap<K, u32>,
    frame: u64,
}

impl<K: Clone + Eq + Hash> PagePool<K> {
    /// An empty pool of `capacity` slots.
    pub fn new(capacity: usize) -> PagePool<K> {
        PagePool { owners: vec![None; capacity], last_used: vec![0; capacity], slots: HashMap::new(), frame: 0 }
    }

    /// Slots in the pool.
    pub fn capacity(&self) -> usize {
        self.owners.len()
    }

    /// Pages the pool holds (this frame's and older ones').
    pub fn resident(&self) -> usize {
        self.slots.len()
    }

    /// Forgets every page (the pool texture was made anew).
    pub fn clear(&mut self) {
        self.owners.fill(None);
        self.last_used.fill(0);
        self.slots.clear();
    }

    /// The slot of each of this frame's `requests`, most important first (a frame asks
    /// for every light's coarsest pages first). When the pool cannot hold them all, the
    /// least important go without (None): a slot this frame gave a later request is taken
    /// back for an earlier one, so the coarse pages every pixel can fall back to are the
    /// last to go.
    pub fn place(&mut self, requests: &[K]) -> Vec<Option<u32>> {
        self.frame += 1;
        let frame = self.frame;
        let mut placed = vec![None; requests.len()];
        // Per slot given out this frame, the request that has it (max-heap: least
        // important on top).
        let mut given: BinaryHeap<(usize, u32)> = BinaryHeap::new();
        for (i, key) in requests.iter().enumerate() {
            if let Some(&slot) = self.slots.get(key)
                && self.last_used[slot as usize] != frame
            {
                placed[i] = Some(slot);
                self.last_used[slot as usize] = frame;
                given.push((i, slot));
            }
        }
        let mut free: Vec<u32> =
            (0..self.owners.len() as u32).filter(|&s| self.last_used[s as usize] != frame).collect();
        // Popped from the end: empty slots first, then the least recently used.
        free.sort_by_key(|&s| std::cmp::Reverse((self.owners[s as usize].is_some(), self.last_used[s as usize], s)));
        for i in 0..requests.len() {
            if placed[i].is_some() {
                continue;
            }
            let slot = match free.pop() {
                Some(slot) => slot,
                None => match given.peek() {
                    Some(&(owner, slot)) if owner > i => {
                        given.pop();
                        placed[owner] = None;
                        slot
                    }
                    _ => continue,
                },
            };
            if let Some(old) = self.owners[slot as usize].take() {
                self.slots.remove(&old);
            }
            self.owners[slot as usize] = Some(requests[i].clone());
            self.slots.insert(requests[i].clone(), slot);
            self.last_used[slot as usize] = frame;
            placed[i] = Some(slot);
            given.push((i, slot));
        }
        placed
    }
}

/// Clipmap levels a directional light needs so that the coarsest covers `max_distance`
/// around the camera (less one page of snapping).
pub fn clipmap_level_count(max_distance: f32) -> u32 {
    let mut levels = 1;
    while levels < MAX_CLIPMAP_LEVELS {
        let extent = clipmap_extent_m(levels - 1);
        if extent * 0.5 - extent / MAP_PAGES as f32 >= max_distance {
            break;
        }
        levels += 1;
    }
    levels
}

/// Metres a side of clipmap `level`.
pub fn clipmap_extent_m(level: u32) -> f32 {
    CLIPMAP_FIRST_EXTENT_M * (1u64 << level) as f32
}

/// The world-to-light rotation of a directional light's clipmap (the cascades' own, so
/// that its grid is anchored at the world origin).
pub fn clipmap_light_from_world(light_direction: Vec3) -> Mat4 {
    let dir = light_direction.normalize();
    let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    Mat4::look_to_rh(Vec3::ZERO, dir, up)
}

/// One clipmap level of a directional light this frame: its map's projection, and the
/// world-fixed index of the map's top-left page.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipmapLevel {
    /// World space to the level's map clip space (orthographic, depth 0 to 1 over
    /// `depth_range`).
    pub clip_from_world: Mat4,
    /// The world-fixed page index of the map's page (0, 0): page (x, y) of the map is
    /// world page (`first_page.0 + x`, `first_page.1 - y`).
    pub first_page: (i64, i64),
    /// Metres a texel spans.
    pub texel_m: f32,
}

/// Light-space depths (metres along the light from the origin's plane) that the levels'
/// projections span: `near` and `far` of everything that casts or receives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthRange {
    /// Nearest to the light.
    pub near: f32,
    /// Farthest from it.
    pub far: f32,
}

/// Clipmap `level` of a light shining along `light_direction`, centred on the page under
/// `camera`, over `depth`.
pub fn clipmap_level(light_direction: Vec3, camera: Vec3, level: u32, depth: DepthRange) -> ClipmapLevel {
    let extent = clipmap_extent_m(level);
    let page_m = extent / MAP_PAGES as f32;
    let light_from_world = clipmap_light_from_world(light_direction);
    let camera_ls = light_from_world.transform_point3(camera);
    let half = (MAP_PAGES / 2) as i64;
    let left_page = (camera_ls.x / page_m).floor() as i64 - half;
    let bottom_page = (camera_ls.y / page_m).floor() as i64 - half;
    let top_page = bottom_page + MAP_PAGES as i64 - 1;
    let clip_from_world = orthographic(light_from_world, page_m, (left_page, bottom_page), MAP_PAGES, 0.0, depth);
    ClipmapLevel { clip_from_world, first_page: (left_page, top_page), texel_m: extent / MAP_TEXELS as f32 }
}

/// The projection that draws world page (`page_x`, `page_y`) of clipmap `level` with its
/// border: computed from the page's own index, so that it is the same bits in every frame
/// whatever the camera did (what keeps the page's cached depths valid).
pub fn clipmap_page_clip_from_world(light_direction: Vec3, level: u32, page: (i64, i64), depth: DepthRange) -> Mat4 {
    let page_m = clipmap_extent_m(level) / MAP_PAGES as f32;
    let border_m = page_m * PAGE_BORDER as f32 / PAGE_TEXELS as f32;
    orthographic(clipmap_light_from_world(light_direction), page_m, page, 1, border_m, depth)
}

/// An orthographic projection over `pages` pages from light-space page corner
/// (`left`, `bottom`), widened by `border_m` on every side.
fn orthographic(
    light_from_world: Mat4,
    page_m: f32,
    (left, bottom): (i64, i64),
    pages: u32,
    border_m: f32,
    depth: DepthRange,
) -> Mat4 {
    let (l, b) = (left as f64 * page_m as f64, bottom as f64 * page_m as f64);
    let side = pages as f64 * page_m as f64;
    let projection = Mat4::orthographic_rh(
        (l - border_m as f64) as f32,
        (l + side + border_m as f64) as f32,
        (b - border_m as f64) as f32,
        (b + side + border_m as f64) as f32,
        depth.near,
        depth.far,
    );
    projection * light_from_world
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_table_holds_every_mip_once() {
        assert_eq!(mip_table_offset(0), 0);
        assert_eq!(mip_table_offset(1), 128 * 128);
        assert_eq!(table_entries(LOCAL_MIPS), (0..8).map(|m| (128u32 >> m).pow(2)).sum::<u32>());
        assert_eq!(pages_per_side(LOCAL_MIPS - 1), 1);
    }

    #[test]
    fn a_page_crop_takes_the_page_and_its_border_to_the_whole_clip_square() {
        for (mip, x, y) in [(0, 0, 0), (0, 37, 101), (3, 5, 9), (7, 0, 0)] {
            let crop = page_clip_from_map_clip(mip, x, y);
            let (corner, side) = page_uv_rect(mip, x, y);
            for (u, v, expect) in [(0.0, 0.0, (-1.0, 1.0)), (1.0, 1.0, (1.0, -1.0)), (0.5, 0.5, (0.0, 0.0))] {
                let uv = corner + Vec2::new(u, v) * side;
                let w = 2.5;
                let clip = glam::Vec4::new((uv.x * 2.0 - 1.0) * w, (1.0 - uv.y * 2.0) * w, 0.3 * w, w);
                let page = crop * clip;
                assert!((page.x / page.w - expect.0).abs() < 1e-4, "{mip} {x} {y} {page}");
                assert!((page.y / page.w - expect.1).abs() < 1e-4, "{mip} {x} {y} {page}");
                assert_eq!((page.z, page.w), (clip.z, clip.w));
            }
            // The border is PAGE_BORDER texels of the page's mip.
            let texel = 1.0 / (pages_per_side(mip) * PAGE_TEXELS) as f32;
            assert!((side - (PAGE_SLOT as f32) * texel).abs() < 1e-6);
        }
    }

    #[test]
    fn the_pool_is_the_largest_square_within_its_megabytes() {
        let pool = PagePoolLayout::for_megabytes(128, 16384);
        assert_eq!(pool.slots_per_side, 40);
        assert!(pool.megabytes() <= 128.0 && pool.megabytes() > 120.0, "{}", pool.megabytes());
        assert_eq!(pool.slot_viewport(41), (PAGE_SLOT, PAGE_SLOT, PAGE_SLOT));
        // Slot 41 is column 1 of row 1; entry 0 is kept for "no page".
        assert_eq!(pool.table_entry(41), 1 + 1 + (1 << 16));
        assert_eq!(pool.table_entry(0), 1);
        // A small device texture limit caps it.
        assert_eq!(PagePoolLayout::for_megabytes(2048, 8192).slots_per_side, 8192 / PAGE_SLOT);
    }

    #[test]
    fn pages_keep_their_slots_and_the_least_recently_used_go_first() {
        let mut pool = PagePool::new(3);
        assert_eq!(pool.place(&["a", "b"]), vec![Some(0), Some(1)]);
        assert_eq!(pool.place(&["b", "c"]), vec![Some(1), Some(2)]);
        // "a" (unused last frame) goes before "b" and "c".
        assert_eq!(pool.place(&["c", "d"]), vec![Some(2), Some(0)]);
        assert_eq!(pool.resident(), 3);
        assert_eq!(pool.place(&["b"]), vec![Some(1)]);
    }

    #[test]
    fn a_full_pool_gives_the_earlier_requests_their_slots() {
        let mut pool = PagePool::new(2);
        assert_eq!(pool.place(&["fine 1", "fine 2"]), vec![Some(0), Some(1)]);
        // Both slots were this frame's; a coarse page asked for first takes one back.
        let placed = pool.place(&["coarse", "fine 1", "fine 2"]);
        assert_eq!(placed.iter().filter(|s| s.is_some()).count(), 2);
        assert!(placed[0].is_some() && placed[1].is_some() && placed[2].is_none(), "{placed:?}");
        assert_eq!(pool.resident(), 2);
    }

    #[test]
    fn clipmap_levels_cover_the_shadow_distance() {
        for max_distance in [1.0f32, 20.0, 100.0, 5000.0] {
            let levels = clipmap_level_count(max_distance);
            let extent = clipmap_extent_m(levels - 1);
            assert!(extent * 0.5 - extent / MAP_PAGES as f32 >= max_distance, "{max_distance}: {levels}");
            assert!(levels == 1 || clipmap_extent_m(levels - 2) * 0.5 < max_distance + extent / MAP_PAGES as f32);
        }
    }

    #[test]
    fn clipmap_pages_stay_put_in_the_world_as_the_camera_moves() {
        let dir = Vec3::new(0.3, -1.0, 0.2).normalize();
        let depth = DepthRange { near: -50.0, far: 50.0 };
        let a = clipmap_level(dir, Vec3::new(1.0, 2.0, 3.0), 2, depth);
        let b = clipmap_level(dir, Vec3::new(1.7, 2.0, 2.1), 2, depth);
        // A world point lands in the same world page from either map.
        let p = Vec3::new(0.9, 0.1, 2.4);
        let world_page = |level: &ClipmapLevel| {
            let clip = level.clip_from_world.project_point3(p);
            let (u, v) = (clip.x * 0.5 + 0.5, 0.5 - clip.y * 0.5);
            let (x, y) = ((u * MAP_PAGES as f32).floor() as i64, (v * MAP_PAGES as f32).floor() as i64);
            (level.first_page.0 + x, level.first_page.1 - y)
        };
        assert_eq!(world_page(&a), world_page(&b));
        // And the page's own projection puts it inside the page, away from the border.
        let page = clipmap_page_clip_from_world(dir, 2, world_page(&a), depth).project_point3(p);
        let inner = PAGE_TEXELS as f32 / PAGE_SLOT as f32;
        assert!(page.x.abs() <= inner + 1e-4 && page.y.abs() <= inner + 1e-4, "{page}");
        assert!((0.0..=1.0).contains(&page.z));
        assert!((a.texel_m - 16.0 / 16384.0).abs() < 1e-9);
    }
}
