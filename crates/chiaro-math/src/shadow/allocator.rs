//! Which atlas tiles each shadowed light renders into, kept from frame to frame.
//!
//! Requests (a light's key and how many contiguous tiles it needs: one per cascade, one
//! per spot, six per point) flow in, most important first; each light's first tile, or
//! none when the atlas is full, flows out. A light keeps its tiles while the frame asks
//! for the same set of lights and tile counts as the last one, so that a tile's contents
//! can later be cached; any change to that set allocates anew, first fit in order.

use std::collections::HashMap;
use std::hash::Hash;

/// First tile of each request, in order, or `None` for one that does not fit in what is
/// left; later, smaller requests may still fit. `[1, 6, 1]` in 16 tiles: `[0, 1, 7]`.
pub fn first_fit_tiles(tile_counts: &[usize], capacity: usize) -> Vec<Option<usize>> {
    let mut used = 0;
    tile_counts
        .iter()
        .map(|&n| {
            (used + n <= capacity).then(|| {
                used += n;
                used - n
            })
        })
        .collect()
}

/// The outcome of one frame's allocation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TileAllocation {
    /// First tile per request, in the order of the requests.
    pub first_tiles: Vec<Option<usize>>,
    /// Tiles in use (a contiguous prefix of the atlas, so it decides the layout).
    pub used_tiles: usize,
    /// Every light kept the tiles it had last frame.
    pub kept: bool,
}

/// A persistent allocator for one atlas of `capacity` tiles, keyed by light.
#[derive(Clone, Debug)]
pub struct TileAllocator<K> {
    capacity: usize,
    /// Last frame's tile count and first tile by light.
    held: HashMap<K, (usize, Option<usize>)>,
    used_tiles: usize,
}

impl<K: Copy + Eq + Hash> TileAllocator<K> {
    pub fn new(capacity: usize) -> TileAllocator<K> {
        TileAllocator { capacity, held: HashMap::new(), used_tiles: 0 }
    }

    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Tiles for this frame's `(light, tile count)` requests, most important first.
    pub fn allocate(&mut self, requests: &[(K, usize)]) -> TileAllocation {
        let same_set = requests.len() == self.held.len()
            && requests.iter().all(|(key, count)| self.held.get(key).is_some_and(|(held, _)| held == count));
        if same_set {
            let first_tiles = requests.iter().map(|(key, _)| self.held[key].1).collect();
            return TileAllocation { first_tiles, used_tiles: self.used_tiles, kept: true };
        }
        let counts: Vec<usize> = requests.iter().map(|&(_, n)| n).collect();
        let first_tiles = first_fit_tiles(&counts, self.capacity);
        self.used_tiles = counts.iter().zip(&first_tiles).filter(|(_, t)| t.is_some()).map(|(n, _)| n).sum();
        self.held = requests.iter().zip(&first_tiles).map(|(&(key, count), &first)| (key, (count, first))).collect();
        TileAllocation { first_tiles, used_tiles: self.used_tiles, kept: false }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn first_fit_skips_what_does_not_fit() {
        assert_eq!(first_fit_tiles(&[1, 6, 1], 16), vec![Some(0), Some(1), Some(7)]);
        // Two points fill 12; a third does not fit, but a spot after it still does.
        assert_eq!(
            first_fit_tiles(&[6, 6, 6, 1, 1, 1, 1, 1], 16),
            vec![Some(0), Some(6), None, Some(12), Some(13), Some(14), Some(15), None]
        );
        assert_eq!(first_fit_tiles(&[1; 17], 16)[16], None);
    }

    #[test]
    fn lights_keep_their_tiles_while_the_set_is_unchanged() {
        let mut atlas = TileAllocator::new(16);
        let first = atlas.allocate(&[('a', 1), ('b', 6), ('c', 1)]);
        assert_eq!(first, TileAllocation { first_tiles: vec![Some(0), Some(1), Some(7)], used_tiles: 8, kept: false });
        // The same lights in another order of importance keep their tiles.
        let again = atlas.allocate(&[('c', 1), ('a', 1), ('b', 6)]);
        assert_eq!(again, TileAllocation { first_tiles: vec![Some(7), Some(0), Some(1)], used_tiles: 8, kept: true });
    }

    #[test]
    fn a_changed_set_allocates_anew() {
        let mut atlas = TileAllocator::new(16);
        atlas.allocate(&[('a', 1), ('b', 6)]);
        let joined = atlas.allocate(&[('c', 6), ('a', 1), ('b', 6)]);
        assert_eq!(joined.first_tiles, vec![Some(0), Some(6), Some(7)]);
        assert!(!joined.kept);
        // A light changing its tile count (cascades) changes the set too.
        let recounted = atlas.allocate(&[('c', 4), ('a', 1), ('b', 6)]);
        assert_eq!(recounted.first_tiles, vec![Some(0), Some(4), Some(5)]);
        assert!(!recounted.kept);
        let left = atlas.allocate(&[('a', 1)]);
        assert_eq!((left.first_tiles, left.used_tiles, left.kept), (vec![Some(0)], 1, false));
    }

    #[test]
    fn an_overflowing_light_stays_out_while_the_set_is_unchanged() {
        let mut atlas = TileAllocator::new(16);
        let requests = [('a', 6), ('b', 6), ('c', 6)];
        assert_eq!(atlas.allocate(&requests).first_tiles, vec![Some(0), Some(6), None]);
        let swapped = atlas.allocate(&[('c', 6), ('b', 6), ('a', 6)]);
        assert_eq!(swapped.first_tiles, vec![None, Some(6), Some(0)]);
        assert_eq!(swapped.used_tiles, 12);
    }

    proptest! {
        #[test]
        fn tiles_are_disjoint_and_inside_the_atlas(
            frames in prop::collection::vec(prop::collection::vec((0u8..12, prop::sample::select(vec![1usize, 4, 6])), 0..10), 1..6)
        ) {
            let mut atlas = TileAllocator::new(16);
            for frame in frames {
                // One request per light.
                let mut seen = std::collections::HashSet::new();
                let requests: Vec<(u8, usize)> = frame.into_iter().filter(|(k, _)| seen.insert(*k)).collect();
                let allocation = atlas.allocate(&requests);
                let mut taken = [false; 16];
                let mut used = 0;
                for (&(_, count), first) in requests.iter().zip(&allocation.first_tiles) {
                    if let Some(first) = first {
                        prop_assert!(first + count <= 16);
                        for (tile, taken) in taken.iter_mut().enumerate().skip(*first).take(count) {
                            prop_assert!(!*taken, "tile {} given twice", tile);
                            *taken = true;
                        }
                        used += count;
                    }
                }
                prop_assert_eq!(used, allocation.used_tiles);
                prop_assert!(taken[..used].iter().all(|t| *t), "used tiles form a prefix");
            }
        }
    }
}
