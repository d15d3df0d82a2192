//! Which shadow tiles a frame draws again. With `shadows.cache`, a tile keeps last frame's
//! depths unless what it would hold changed: its light's projection, slope bias, place in
//! the atlas, the atlas's size, or any caster's `caster_key` (its transform, mesh and how
//! it casts). The cache remembers, per atlas tile, the content key of what the atlas holds
//! there; the frame's tiles flow in, one redraw flag per tile flows out.

use super::draws::Draw;
use super::shadows::{CasterTile, ShadowAtlas, ShadowPlan};
use std::collections::HashMap;
use std::hash::{Hash, Hasher};

/// A tile's content key and its viewport (x, y, size).
type CachedTile = (u64, (u32, u32, u32));

/// What each atlas holds, kept by the renderer from frame to frame.
#[derive(Clone, Debug, Default)]
pub struct TileCache {
    /// Per (atlas, tile index), the content key of what the atlas holds there, and where.
    cached: HashMap<(ShadowAtlas, u32), CachedTile>,
    /// Each atlas's size when last drawn: a new size is a new texture, holding nothing.
    atlas_sizes: HashMap<ShadowAtlas, u32>,
}

/// What a tile holds: equal keys, equal depths.
fn tile_key(tile: &CasterTile, atlas_size: u32, draws: &[Draw]) -> u64 {
    let mut h = std::hash::DefaultHasher::new();
    (tile.viewport, atlas_size, tile.slope_bias.to_bits()).hash(&mut h);
    tile.clip_from_world.to_cols_array().map(f32::to_bits).hash(&mut h);
    for &d in &tile.casters {
        draws[d as usize].caster_key.hash(&mut h);
    }
    h.finish()
}

fn overlap((x, y, s): (u32, u32, u32), (tx, ty, ts): (u32, u32, u32)) -> bool {
    x < tx + ts && tx < x + s && y < ty + ts && ty < y + s
}

impl TileCache {
    /// Per tile of `shadows`, whether the frame draws it, remembering what the atlases
    /// will hold after it. Without the cache every tile is drawn (into atlases cleared
    /// whole).
    pub fn redraws(&mut self, shadows: &ShadowPlan, draws: &[Draw], cache: bool) -> Vec<bool> {
        if !cache {
            // The atlases are cleared whole: only this frame's tiles will hold anything.
            self.cached.clear();
        }
        for (atlas, size) in
            [(ShadowAtlas::Directional, shadows.directional_atlas_size), (ShadowAtlas::Local, shadows.local_atlas_size)]
        {
            if size > 0 && self.atlas_sizes.insert(atlas, size).is_some_and(|old| old != size) {
                self.cached.retain(|&(a, _), _| a != atlas);
            }
        }
        let redraw: Vec<bool> = shadows
            .tiles
            .iter()
            .map(|tile| {
                let key = tile_key(tile, shadows.atlas_size(tile.atlas), draws);
                let kept = self.cached.insert((tile.atlas, tile.tile), (key, tile.viewport)).map(|c| c.0) == Some(key);
                !(kept && cache)
            })
            .collect();
        // A tile drawn now overwrites whatever other tiles (of an older layout) held there.
        for (tile, _) in shadows.tiles.iter().zip(&redraw).filter(|(_, drawn)| **drawn) {
            self.cached.retain(|&(atlas, index), &mut (_, viewport)| {
                atlas != tile.atlas || index == tile.tile || !overlap(viewport, tile.viewport)
            });
        }
        redraw
    }
}
