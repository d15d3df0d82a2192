//! The shadow atlas: a square depth texture split into 1, 2, 4 or 8 tiles per side, and
//! the matrix that takes a tile's clip space to atlas texture coordinates.

use super::tiers::TileRect;
use glam::{Mat4, Vec2};

/// How many tiles a side, and how big each is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AtlasLayout {
    pub atlas_size: u32,
    /// Tiles per side: 1, 2, 4 or 8.
    pub split: u32,
}

impl AtlasLayout {
    /// The tutorial's uniform layout, grown past it where more tiles are wanted: the
    /// fewest tiles per side that hold `tiles` (1 -> 1, 2..4 -> 2, 5..16 -> 4, 17..64 -> 8).
    pub fn for_tiles(atlas_size: u32, tiles: usize) -> AtlasLayout {
        let split = match tiles {
            0 | 1 => 1,
            2..=4 => 2,
            5..=16 => 4,
            _ => 8,
        };
        AtlasLayout { atlas_size, split }
    }

    pub fn tile_size(&self) -> u32 {
        self.atlas_size / self.split
    }

    pub fn capacity(&self) -> usize {
        (self.split * self.split) as usize
    }

    /// Tile position in tiles, row-major from the top-left.
    pub fn tile_offset(&self, index: usize) -> (u32, u32) {
        let i = index as u32;
        (i % self.split, i / self.split)
    }

    /// The tile's viewport in texels: (x, y, size).
    pub fn tile_viewport(&self, index: usize) -> (u32, u32, u32) {
        self.tile_rect(index).viewport()
    }

    pub fn tile_rect(&self, index: usize) -> TileRect {
        let (x, y) = self.tile_offset(index);
        let s = self.tile_size();
        TileRect { x: x * s, y: y * s, size: s }
    }

    /// Atlas-from-clip for a tile: clip x, y in [-1, 1] (y up) map to the tile's texture
    /// coordinates (v down), depth passes through.
    pub fn atlas_from_clip(&self, index: usize) -> Mat4 {
        self.tile_rect(index).atlas_from_clip(self.atlas_size)
    }

    /// The tile's bounds in atlas texture coordinates shrunk by half a texel, so that
    /// clamped samples never read a neighbouring tile: (min, max).
    pub fn tile_bounds_uv(&self, index: usize) -> (Vec2, Vec2) {
        self.tile_rect(index).bounds_uv(self.atlas_size)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn layouts_follow_the_tutorial() {
        assert_eq!(AtlasLayout::for_tiles(2048, 1).split, 1);
        assert_eq!(AtlasLayout::for_tiles(2048, 3).split, 2);
        assert_eq!(AtlasLayout::for_tiles(2048, 4).split, 2);
        assert_eq!(AtlasLayout::for_tiles(2048, 5).split, 4);
        assert_eq!(AtlasLayout::for_tiles(2048, 16).split, 4);
        assert_eq!(AtlasLayout::for_tiles(2048, 16).tile_size(), 512);
        assert_eq!(AtlasLayout::for_tiles(2048, 17).split, 8);
        assert_eq!(AtlasLayout::for_tiles(2048, 64).tile_size(), 256);
    }

    #[test]
    fn tiles_are_disjoint_and_inside_the_atlas() {
        for split_tiles in [1, 4, 16] {
            let layout = AtlasLayout::for_tiles(1024, split_tiles);
            let mut seen = std::collections::HashSet::new();
            for i in 0..layout.capacity() {
                let (x, y, s) = layout.tile_viewport(i);
                assert!(x + s <= 1024 && y + s <= 1024);
                assert!(seen.insert((x, y)));
            }
        }
    }

    #[test]
    fn atlas_matrix_maps_clip_corners_to_the_tile() {
        let layout = AtlasLayout::for_tiles(2048, 16);
        for i in 0..16 {
            let m = layout.atlas_from_clip(i);
            let (x, y, s) = layout.tile_viewport(i);
            let top_left = m.transform_point3(Vec3::new(-1.0, 1.0, 0.25));
            let bottom_right = m.transform_point3(Vec3::new(1.0, -1.0, 0.75));
            assert!((top_left.x * 2048.0 - x as f32).abs() < 1e-3);
            assert!((top_left.y * 2048.0 - y as f32).abs() < 1e-3);
            assert!((bottom_right.x * 2048.0 - (x + s) as f32).abs() < 1e-3);
            assert!((bottom_right.y * 2048.0 - (y + s) as f32).abs() < 1e-3);
            assert_eq!((top_left.z, bottom_right.z), (0.25, 0.75));
        }
    }

    #[test]
    fn clamping_bounds_stay_half_a_texel_inside() {
        let layout = AtlasLayout::for_tiles(1024, 4);
        let (min, max) = layout.tile_bounds_uv(3);
        assert!((min.x * 1024.0 - 512.5).abs() < 1e-3 && (max.x * 1024.0 - 1023.5).abs() < 1e-3);
        assert!((min.y * 1024.0 - 512.5).abs() < 1e-3 && (max.y * 1024.0 - 1023.5).abs() < 1e-3);
    }
}
