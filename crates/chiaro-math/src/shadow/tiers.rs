//! Tile sizes for the point/spot atlas by importance, and where the tiles go.
//!
//! Up to 16 tiles the uniform layout of Catlike Coding's Custom SRP tutorial "Point and
//! Spot Shadows" stands (one tile the whole atlas, up to 4 a quarter each, up to 16 a
//! sixteenth). Past that, as URP does, each light gets a tier
//! by how much of the screen its influence covers: a sixteenth of the atlas for lights
//! over a fifth of the screen, a 64th for most, a 256th for lights under 1% of it. If the
//! large tiles overfill the atlas, the least important of them step down to the middle
//! tier, which 64 tiles always fit in.
//! Where the atlas has room left, an area light's cube faces towards the side it emits
//! from get tiles twice as wide (`double_facing_tiles`).
//! Tiles are packed largest first along a Z-order curve: with power-of-two sizes in
//! decreasing order, every tile lands aligned and none overlap.

use glam::{Mat4, Vec2, Vec3, Vec4};

/// Screen coverage (0 to 1) from which a light gets the large tier, and under which it
/// gets the small one.
pub const LARGE_TIER_COVERAGE: f32 = 0.2;
pub const SMALL_TIER_COVERAGE: f32 = 0.01;
/// A light keeps last frame's tier until its coverage is this factor past the threshold,
/// so that one hovering at a threshold does not switch (and reallocate every tile) each
/// frame.
pub const TIER_HYSTERESIS: f32 = 1.25;

/// A tile's place in the atlas, in texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TileRect {
    pub x: u32,
    pub y: u32,
    pub size: u32,
}

impl TileRect {
    /// Atlas-from-clip: clip x, y in [-1, 1] (y up) map to the tile's texture coordinates
    /// (v down); depth passes through.
    pub fn atlas_from_clip(&self, atlas_size: u32) -> Mat4 {
        let scale = self.size as f32 / atlas_size as f32;
        let offset = Vec2::new(self.x as f32, self.y as f32) / atlas_size as f32;
        Mat4::from_cols(
            Vec4::new(0.5 * scale, 0.0, 0.0, 0.0),
            Vec4::new(0.0, -0.5 * scale, 0.0, 0.0),
            Vec4::new(0.0, 0.0, 1.0, 0.0),
            Vec3::new(0.5 * scale + offset.x, 0.5 * scale + offset.y, 0.0).extend(1.0),
        )
    }

    /// Bounds in texture coordinates shrunk by half a texel, so that clamped samples
    /// never read a neighbour: (min, max).
    pub fn bounds_uv(&self, atlas_size: u32) -> (Vec2, Vec2) {
        let to_uv = 1.0 / atlas_size as f32;
        let (x, y, s) = (self.x as f32, self.y as f32, self.size as f32);
        (Vec2::new(x + 0.5, y + 0.5) * to_uv, Vec2::new(x + s - 0.5, y + s - 0.5) * to_uv)
    }

    pub fn viewport(&self) -> (u32, u32, u32) {
        (self.x, self.y, self.size)
    }
}

/// How much of the screen (0 to 1) a world-space sphere covers, from the area of its
/// projected disc; 1 when the eye is inside it. An orthographic projection (no division
/// by depth) draws the sphere the same size at every distance.
pub fn screen_coverage(view_from_world: &Mat4, clip_from_view: &Mat4, center: Vec3, radius: f32) -> f32 {
    let (sx, sy) = (clip_from_view.x_axis.x.abs(), clip_from_view.y_axis.y.abs());
    if clip_from_view.z_axis.w == 0.0 {
        return (std::f32::consts::PI * radius * radius * sx * sy / 4.0).min(1.0);
    }
    let distance = view_from_world.transform_point3(center).length();
    if distance <= radius {
        return 1.0;
    }
    let sin = radius / distance;
    let tan_squared = sin * sin / (1.0 - sin * sin);
    // The projection's x and y scales are 1 / tan of the half fields of view; the screen
    // spans 2 x 2 in clip units.
    (std::f32::consts::PI * tan_squared * sx * sy / 4.0).min(1.0)
}

/// The tile side a light covering `coverage` of the screen asks for, before the atlas's
/// budget: `atlas_size` / 4, / 8 or / 16. `previous` (last frame's answer) is kept while
/// the coverage stays within `TIER_HYSTERESIS` of the threshold between them.
pub fn coverage_tier(atlas_size: u32, coverage: f32, previous: Option<u32>) -> u32 {
    let tier = |c: f32| {
        if c >= LARGE_TIER_COVERAGE {
            atlas_size / 4
        } else if c >= SMALL_TIER_COVERAGE {
            atlas_size / 8
        } else {
            atlas_size / 16
        }
    };
    // Tiers grow with coverage, so a tier between these two is within the margin.
    let (smaller, larger) = (tier(coverage / TIER_HYSTERESIS), tier(coverage * TIER_HYSTERESIS));
    match previous {
        Some(p) if (smaller..=larger).contains(&p) => p,
        _ => tier(coverage),
    }
}

/// Per light (in importance order, `(tiles, coverage tier)` from `coverage_tier`), the
/// side in texels of each of its tiles, for lights that all fit in `atlas_size` (the
/// caller caps the tile count).
pub fn tile_sizes(atlas_size: u32, lights: &[(usize, u32)]) -> Vec<u32> {
    let total: usize = lights.iter().map(|&(n, _)| n).sum();
    let uniform_split = match total {
        0 | 1 => Some(1),
        2..=4 => Some(2),
        5..=16 => Some(4),
        _ => None,
    };
    if let Some(split) = uniform_split {
        return vec![atlas_size / split; lights.len()];
    }
    let (large, medium) = (atlas_size / 4, atlas_size / 8);
    let mut sizes: Vec<u32> = lights.iter().map(|&(_, tier)| tier).collect();
    let area =
        |sizes: &[u32]| -> u64 { lights.iter().zip(sizes).map(|(&(n, _), &s)| n as u64 * (s as u64).pow(2)).sum() };
    let budget = (atlas_size as u64).pow(2);
    // Over budget: the least important large light steps down to the middle tier, until
    // it fits (64 middle tiles fill the atlas exactly).
    while area(&sizes) > budget {
        match sizes.iter().rposition(|&s| s == large) {
            Some(k) => sizes[k] = medium,
            None => break,
        }
    }
    sizes
}

/// Doubles the side of the tiles that each light's `facing` lists (tile indices within
/// the light, most worth it first), lights in the order given, while the atlas's area
/// allows and a doubled tile stays within it. `sizes` holds every light's tiles, `facing`
/// the tiles to widen for each light (empty for most). An area light emits from one side:
/// its cube faces towards that side hold most of its light and its penumbrae, and a cube
/// alone uses 6 of the 16 tiles of the uniform layout, so the room left pays for them.
pub fn double_facing_tiles(atlas_size: u32, sizes: &mut [Vec<u32>], facing: &[Vec<usize>]) {
    let budget = (atlas_size as u64).pow(2);
    let mut area: u64 = sizes.iter().flatten().map(|&s| (s as u64).pow(2)).sum();
    for (tiles, wanted) in sizes.iter_mut().zip(facing) {
        for &k in wanted {
            let Some(size) = tiles.get_mut(k) else { continue };
            let extra = 3 * (*size as u64).pow(2);
            if *size == 0 || 2 * *size > atlas_size || area + extra > budget {
                continue;
            }
            *size *= 2;
            area += extra;
        }
    }
}

/// Places `sizes` (powers of two, each at most `atlas_size`) in the atlas; tiles are
/// packed in order of decreasing size, ties in the given order. Returns `None` when they
/// do not fit.
pub fn pack_tiles(atlas_size: u32, sizes: &[u32]) -> Option<Vec<TileRect>> {
    let Some(&unit) = sizes.iter().min() else {
        return Some(Vec::new());
    };
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    order.sort_by_key(|&k| std::cmp::Reverse(sizes[k]));
    let cells_per_side = (atlas_size / unit) as u64;
    let mut next_cell = 0u64;
    let mut rects = vec![TileRect { x: 0, y: 0, size: 0 }; sizes.len()];
    for k in order {
        let side = (sizes[k] / unit) as u64;
        if next_cell + side * side > cells_per_side * cells_per_side {
            return None;
        }
        let (cx, cy) = morton_decode(next_cell);
        rects[k] = TileRect { x: cx * unit, y: cy * unit, size: sizes[k] };
        next_cell += side * side;
    }
    Some(rects)
}

/// The cell at position `index` of the Z-order curve.
fn morton_decode(index: u64) -> (u32, u32) {
    let (mut x, mut y) = (0u32, 0u32);
    for bit in 0..32 {
        x |= (((index >> (2 * bit)) & 1) as u32) << bit;
        y |= (((index >> (2 * bit + 1)) & 1) as u32) << bit;
    }
    (x, y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::perspective_reverse_z;

    /// Tiles and tier per light, from coverages, with no previous frame.
    fn tiered(lights: &[(usize, f32)]) -> Vec<(usize, u32)> {
        lights.iter().map(|&(n, c)| (n, coverage_tier(2048, c, None))).collect()
    }

    #[test]
    fn up_to_sixteen_tiles_keep_the_uniform_layout() {
        assert_eq!(tile_sizes(2048, &tiered(&[(1, 0.0)])), vec![2048]);
        assert_eq!(tile_sizes(2048, &tiered(&[(1, 0.0), (1, 0.9), (1, 0.1)])), vec![1024; 3]);
        assert_eq!(tile_sizes(2048, &tiered(&[(6, 0.9), (6, 0.0), (1, 0.5)])), vec![512; 3]);
    }

    #[test]
    fn tiers_switch_only_past_the_margin() {
        assert_eq!(coverage_tier(2048, 0.21, None), 512);
        assert_eq!(coverage_tier(2048, 0.19, None), 256);
        // Hovering around the threshold keeps last frame's tier.
        assert_eq!(coverage_tier(2048, 0.19, Some(512)), 512);
        assert_eq!(coverage_tier(2048, 0.21, Some(256)), 256);
        assert_eq!(coverage_tier(2048, 0.009, Some(256)), 256);
        // Well past it, the tier follows the coverage.
        assert_eq!(coverage_tier(2048, 0.15, Some(512)), 256);
        assert_eq!(coverage_tier(2048, 0.3, Some(256)), 512);
        assert_eq!(coverage_tier(2048, 0.005, Some(256)), 128);
        assert_eq!(coverage_tier(2048, 0.9, Some(128)), 512);
    }

    #[test]
    fn past_sixteen_tiles_size_follows_screen_coverage_within_the_atlas() {
        // Five points (30 tiles): one fills the screen, three are ordinary, one is tiny.
        let lights = [(6, 1.0), (6, 0.05), (6, 0.3), (6, 0.002), (6, 0.1)];
        let sizes = tile_sizes(2048, &tiered(&lights));
        assert_eq!(sizes, vec![512, 256, 512, 128, 256]);
        let area: u64 = lights.iter().zip(&sizes).map(|(&(n, _), &s)| n as u64 * (s as u64).pow(2)).sum();
        assert!(area <= 2048 * 2048);
        // Too many large lights: the least important step down until they fit.
        let crowded = [(6, 1.0); 6];
        let sizes = tile_sizes(2048, &tiered(&crowded));
        assert_eq!(sizes, vec![512, 256, 256, 256, 256, 256], "the most important keeps its tier");
        // Ten of them fit only as middle tiles, never smaller.
        assert_eq!(tile_sizes(2048, &tiered(&[(6, 1.0); 10])), vec![256; 10]);
    }

    #[test]
    fn facing_tiles_double_while_the_atlas_has_room() {
        // One cube (6 of 16 tiles of 512): its two facing faces double, 6 + 2 x 3 = 12 of 16.
        let mut sizes = vec![vec![512; 6]];
        double_facing_tiles(2048, &mut sizes, &[vec![3, 0]]);
        assert_eq!(sizes, vec![vec![1024, 512, 512, 1024, 512, 512]]);
        // A cube and a spot and a point (13 tiles): room for one doubled face, the first
        // light's most facing one.
        let mut sizes = vec![vec![512; 6], vec![512], vec![512; 6]];
        double_facing_tiles(2048, &mut sizes, &[vec![3, 0], vec![], vec![]]);
        assert_eq!(sizes[0], vec![512, 512, 512, 1024, 512, 512]);
        // Sixteen tiles fill the atlas: nothing doubles.
        let mut full = vec![vec![512; 6], vec![512; 6], vec![512; 4]];
        double_facing_tiles(2048, &mut full, &[vec![3], vec![3], vec![]]);
        assert!(full.iter().flatten().all(|&s| s == 512));
        // A tile as wide as half the atlas does not double past it... and a whole-atlas
        // tile stays whole.
        let mut whole = vec![vec![2048]];
        double_facing_tiles(2048, &mut whole, &[vec![0]]);
        assert_eq!(whole, vec![vec![2048]]);
        // Whatever doubles, the tiles still pack.
        let mut tiered = vec![vec![256; 6], vec![128; 6], vec![256; 6]];
        double_facing_tiles(2048, &mut tiered, &[vec![2, 4, 0], vec![1], vec![5]]);
        let flat: Vec<u32> = tiered.iter().flatten().copied().collect();
        assert!(pack_tiles(2048, &flat).is_some(), "{flat:?}");
        assert_eq!(tiered[0][2], 512);
    }

    #[test]
    fn packed_tiles_are_disjoint_aligned_and_inside() {
        let sizes: Vec<u32> = [512, 128, 256, 256, 128, 256, 128, 128].iter().flat_map(|&s| [s; 6]).collect();
        let rects = pack_tiles(2048, &sizes).expect("fits");
        for (k, r) in rects.iter().enumerate() {
            assert_eq!(r.size, sizes[k]);
            assert!(r.x + r.size <= 2048 && r.y + r.size <= 2048);
            assert_eq!((r.x % r.size, r.y % r.size), (0, 0), "aligned");
            for q in &rects[k + 1..] {
                let apart = r.x + r.size <= q.x || q.x + q.size <= r.x || r.y + r.size <= q.y || q.y + q.size <= r.y;
                assert!(apart, "{r:?} overlaps {q:?}");
            }
        }
        assert!(pack_tiles(2048, &[1024; 5]).is_none(), "five quarters do not fit");
        assert_eq!(pack_tiles(2048, &[]), Some(Vec::new()));
    }

    #[test]
    fn rect_matrices_map_clip_corners_to_the_tile() {
        let r = TileRect { x: 512, y: 1536, size: 256 };
        let m = r.atlas_from_clip(2048);
        let top_left = m.transform_point3(Vec3::new(-1.0, 1.0, 0.5));
        let bottom_right = m.transform_point3(Vec3::new(1.0, -1.0, 0.5));
        assert!((top_left.truncate() * 2048.0 - Vec2::new(512.0, 1536.0)).length() < 1e-3);
        assert!((bottom_right.truncate() * 2048.0 - Vec2::new(768.0, 1792.0)).length() < 1e-3);
    }

    #[test]
    fn coverage_grows_as_a_light_nears_and_is_whole_inside_it() {
        let view = Mat4::look_at_rh(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y);
        let proj = perspective_reverse_z(60f32.to_radians(), 1.0, 0.1, None);
        let far = screen_coverage(&view, &proj, Vec3::new(0.0, 0.0, -50.0), 1.0);
        let near = screen_coverage(&view, &proj, Vec3::new(0.0, 0.0, -5.0), 1.0);
        assert!(far < near && near < 1.0, "{far} {near}");
        // A disc of half the screen's height at 60 degrees: pi/4 * ~0.25 of the square screen.
        assert!((far - std::f32::consts::PI * (1.0f32 / 50.0 / 30f32.to_radians().tan()).powi(2) / 4.0).abs() < 1e-4);
        assert_eq!(screen_coverage(&view, &proj, Vec3::new(0.0, 0.0, -1.0), 2.0), 1.0);
    }

    #[test]
    fn an_orthographic_view_covers_the_same_share_at_every_distance() {
        let view = Mat4::look_at_rh(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y);
        let proj = crate::camera::orthographic_reverse_z(4.0, 4.0, 0.1, 100.0);
        let far = screen_coverage(&view, &proj, Vec3::new(0.0, 0.0, -50.0), 1.0);
        let near = screen_coverage(&view, &proj, Vec3::new(0.0, 0.0, -5.0), 1.0);
        // A disc of radius 1 in an 8 x 8 m view: pi / 64 of it.
        assert!((far - std::f32::consts::PI / 64.0).abs() < 1e-6 && far == near, "{far} {near}");
    }
}
