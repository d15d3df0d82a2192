//! Packing chart rectangles into square atlases: shelves, tallest first. Every rectangle
//! already includes its gutter, so packed rectangles touching edge to edge keep their
//! charts two gutters apart.

/// A rectangle's place: its atlas and top-left texel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Placed {
    pub x: u32,
    pub y: u32,
}

/// Shelf packing into one atlas of `size` texels a side.
#[derive(Clone, Debug)]
pub struct ShelfPacker {
    size: u32,
    /// Top of the current shelf, its height, and the next free x on it.
    shelf_y: u32,
    shelf_height: u32,
    cursor_x: u32,
}

impl ShelfPacker {
    pub fn new(size: u32) -> ShelfPacker {
        ShelfPacker { size, shelf_y: 0, shelf_height: 0, cursor_x: 0 }
    }

    /// Places rectangles `(width, height)` all in this atlas, or none of them (the packer
    /// is left as it was) when they do not all fit. They should come tallest first.
    pub fn place_all(&mut self, sizes: &[(u32, u32)]) -> Option<Vec<Placed>> {
        let saved = self.clone();
        let mut placed = Vec::with_capacity(sizes.len());
        for &(w, h) in sizes {
            match self.place(w, h) {
                Some(p) => placed.push(p),
                None => {
                    *self = saved;
                    return None;
                }
            }
        }
        Some(placed)
    }

    fn place(&mut self, w: u32, h: u32) -> Option<Placed> {
        if w > self.size || h > self.size {
            return None;
        }
        if self.cursor_x + w > self.size || h > self.shelf_height {
            // A new shelf under the current one, unless this one is empty and tall enough.
            if self.cursor_x > 0 || h > self.shelf_height {
                self.shelf_y += self.shelf_height;
                self.shelf_height = h;
                self.cursor_x = 0;
            }
        }
        if self.shelf_y + self.shelf_height > self.size {
            return None;
        }
        let p = Placed { x: self.cursor_x, y: self.shelf_y };
        self.cursor_x += w;
        Some(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn packed_rectangles_stay_inside_and_never_overlap(
            mut sizes in proptest::collection::vec((1u32..40, 1u32..40), 1..60),
        ) {
            sizes.sort_by_key(|s| std::cmp::Reverse(s.1));
            let mut packer = ShelfPacker::new(128);
            let mut rects = Vec::new();
            for chunk in sizes.chunks(5) {
                if let Some(placed) = packer.place_all(chunk) {
                    rects.extend(placed.iter().zip(chunk).map(|(p, &(w, h))| (p.x, p.y, w, h)));
                }
            }
            for (i, a) in rects.iter().enumerate() {
                prop_assert!(a.0 + a.2 <= 128 && a.1 + a.3 <= 128);
                for b in &rects[i + 1..] {
                    let apart = a.0 + a.2 <= b.0 || b.0 + b.2 <= a.0 || a.1 + a.3 <= b.1 || b.1 + b.3 <= a.1;
                    prop_assert!(apart, "{a:?} overlaps {b:?}");
                }
            }
        }
    }

    #[test]
    fn a_group_that_does_not_fit_leaves_the_packer_as_it_was() {
        let mut packer = ShelfPacker::new(64);
        assert!(packer.place_all(&[(64, 40)]).is_some());
        assert!(packer.place_all(&[(10, 10), (64, 30)]).is_none());
        // The 10x10 was rolled back, so a 64x24 still fits under the first shelf.
        assert_eq!(packer.place_all(&[(64, 24)]), Some(vec![Placed { x: 0, y: 40 }]));
        assert!(packer.place_all(&[(65, 1)]).is_none());
    }
}
