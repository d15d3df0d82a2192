//! Which placed triangles touch which atlas texels, and where a point of a texel lies on
//! them. A texel belongs to every triangle that overlaps its square, however little, so
//! that texels along chart edges are baked from the surface they partly cover.

use crate::layout::PlacedTriangle;
use glam::Vec2;

/// For every texel of a `size` x `size` atlas, the indices of the triangles that overlap it.
pub struct TexelTriangles {
    pub size: u32,
    /// `ids[offsets[t]..offsets[t + 1]]` are texel `t`'s triangles (row-major from the top).
    offsets: Vec<u32>,
    ids: Vec<u32>,
}

impl TexelTriangles {
    pub fn build(size: u32, triangles: &[PlacedTriangle]) -> TexelTriangles {
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        for (id, t) in triangles.iter().enumerate() {
            let min = t.corners[0].min(t.corners[1]).min(t.corners[2]).floor().max(Vec2::ZERO);
            let max = t.corners[0].max(t.corners[1]).max(t.corners[2]).ceil().min(Vec2::splat(size as f32));
            for y in min.y as u32..max.y as u32 {
                for x in min.x as u32..max.x as u32 {
                    if overlaps_texel(&t.corners, x, y) {
                        pairs.push((y * size + x, id as u32));
                    }
                }
            }
        }
        pairs.sort_unstable();
        let mut offsets = vec![0u32; (size * size + 1) as usize];
        for &(texel, _) in &pairs {
            offsets[texel as usize + 1] += 1;
        }
        for k in 1..offsets.len() {
            offsets[k] += offsets[k - 1];
        }
        TexelTriangles { size, offsets, ids: pairs.into_iter().map(|(_, id)| id).collect() }
    }

    pub fn of(&self, texel: usize) -> &[u32] {
        &self.ids[self.offsets[texel] as usize..self.offsets[texel + 1] as usize]
    }
}

/// Separating-axis test of a triangle against the square of texel `(x, y)`.
pub fn overlaps_texel(corners: &[Vec2; 3], x: u32, y: u32) -> bool {
    let (lo, hi) = (Vec2::new(x as f32, y as f32), Vec2::new(x as f32 + 1.0, y as f32 + 1.0));
    let tmin = corners[0].min(corners[1]).min(corners[2]);
    let tmax = corners[0].max(corners[1]).max(corners[2]);
    if tmax.x <= lo.x || tmin.x >= hi.x || tmax.y <= lo.y || tmin.y >= hi.y {
        return false;
    }
    let square = [lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)];
    for e in 0..3 {
        let (a, b, c) = (corners[e], corners[(e + 1) % 3], corners[(e + 2) % 3]);
        let normal = (b - a).perp();
        let side = normal.dot(c - a);
        if side == 0.0 {
            continue;
        }
        // The square lies wholly on the far side of this edge: separated.
        if square.iter().all(|&q| normal.dot(q - a) * side <= 0.0) {
            return false;
        }
    }
    true
}

/// Barycentric weights of `p` for the triangle's corners (they may be negative outside).
pub fn barycentric(corners: &[Vec2; 3], p: Vec2) -> Option<[f32; 3]> {
    let [a, b, c] = *corners;
    let area = (b - a).perp_dot(c - a);
    if area.abs() < 1e-12 {
        return None;
    }
    let w1 = (p - a).perp_dot(c - a) / area;
    let w2 = (b - a).perp_dot(p - a) / area;
    Some([1.0 - w1 - w2, w1, w2])
}

pub fn inside(w: &[f32; 3]) -> bool {
    w.iter().all(|&x| x >= 0.0)
}

/// The closest point of the triangle to `p`, as weights (for samples of edge texels that
/// fall outside every triangle: they move onto the nearest surface).
pub fn clamp_to_triangle(corners: &[Vec2; 3], p: Vec2) -> [f32; 3] {
    if let Some(w) = barycentric(corners, p).filter(inside) {
        return w;
    }
    let mut best = ([1.0, 0.0, 0.0], f32::INFINITY);
    for e in 0..3 {
        let (a, b) = (corners[e], corners[(e + 1) % 3]);
        let ab = b - a;
        let t = if ab.length_squared() > 0.0 { ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
        let d = (a + ab * t).distance_squared(p);
        if d < best.1 {
            let mut w = [0.0; 3];
            w[e] = 1.0 - t;
            w[(e + 1) % 3] = t;
            best = (w, d);
        }
    }
    best.0
}

/// Fills empty texels from their filled neighbours, `passes` rings outwards: each pass
/// gives every empty texel next to a filled one the mean of those neighbours (all four
/// channels).
pub fn dilate(texels: &mut [[f32; 4]], filled: &mut [bool], size: u32, passes: u32) {
    let n = size as i64;
    for _ in 0..passes {
        let before = filled.to_vec();
        let source = texels.to_vec();
        for y in 0..n {
            for x in 0..n {
                let i = (y * n + x) as usize;
                if before[i] {
                    continue;
                }
                let (mut sum, mut count) = ([0.0f32; 4], 0);
                for (dx, dy) in [(-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
                    let (nx, ny) = (x + dx, y + dy);
                    if nx < 0 || ny < 0 || nx >= n || ny >= n {
                        continue;
                    }
                    let j = (ny * n + nx) as usize;
                    if before[j] {
                        for c in 0..4 {
                            sum[c] += source[j][c];
                        }
                        count += 1;
                    }
                }
                if count > 0 {
                    let k = 1.0 / count as f32;
                    texels[i] = sum.map(|v| v * k);
                    filled[i] = true;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn placed(corners: [Vec2; 3]) -> PlacedTriangle {
        PlacedTriangle { chart: 0, instance: 0, primitive: 0, triangle: 0, corners }
    }

    #[test]
    fn texels_touched_by_a_triangle_are_exactly_those_it_overlaps() {
        let tri = [Vec2::new(1.5, 1.5), Vec2::new(5.5, 1.5), Vec2::new(1.5, 5.5)];
        let map = TexelTriangles::build(8, &[placed(tri)]);
        for y in 0..8u32 {
            for x in 0..8u32 {
                // Texel (x, y) overlaps the triangle when its corner nearest the hypotenuse
                // lies below it: x + y < 7 with the lower corner at (x, y) clamped.
                let lo = Vec2::new((x as f32).max(1.5), (y as f32).max(1.5));
                let expected = x >= 1 && y >= 1 && x <= 5 && y <= 5 && lo.x + lo.y < 7.0;
                assert_eq!(!map.of((y * 8 + x) as usize).is_empty(), expected, "texel {x},{y}");
            }
        }
    }

    #[test]
    fn clamped_points_land_on_the_nearest_edge() {
        let tri = [Vec2::ZERO, Vec2::new(2.0, 0.0), Vec2::new(0.0, 2.0)];
        let w = clamp_to_triangle(&tri, Vec2::new(1.0, -1.0));
        let p = tri[0] * w[0] + tri[1] * w[1] + tri[2] * w[2];
        assert!(p.distance(Vec2::new(1.0, 0.0)) < 1e-6);
        let w = clamp_to_triangle(&tri, Vec2::new(2.0, 2.0));
        let p = tri[0] * w[0] + tri[1] * w[1] + tri[2] * w[2];
        assert!(p.distance(Vec2::new(1.0, 1.0)) < 1e-6);
    }

    #[test]
    fn dilation_fills_rings_outwards_with_neighbour_means() {
        let size = 5;
        let mut texels = vec![[0.0f32; 4]; 25];
        let mut filled = vec![false; 25];
        texels[12] = [4.0, 2.0, 1.0, 0.5];
        filled[12] = true;
        dilate(&mut texels, &mut filled, size, 1);
        // The centre's eight neighbours take its value; the outer ring is still empty.
        for i in [6, 7, 8, 11, 13, 16, 17, 18] {
            assert!(filled[i] && texels[i] == [4.0, 2.0, 1.0, 0.5], "{i}");
        }
        assert!(!filled[0] && !filled[24]);
        dilate(&mut texels, &mut filled, size, 1);
        assert!(filled.iter().all(|&f| f));
        assert_eq!(texels[12], [4.0, 2.0, 1.0, 0.5]);
    }
}
