//! Light culling for forward shading: which point and spot lights a pixel loops over.
//!
//! - Clustered: the view is cut into a froxel grid (screen tiles x depth slices that grow
//!   exponentially with distance); each cluster lists the lights whose range sphere
//!   touches its view-space bounds.
//! - Per object: each object gets the few lights that matter most to it (the "lights per
//!   object" of Catlike Coding's Custom SRP tutorial "Point and Spot Lights").
//!
//! Both produce `LightLists`: one record per cluster or object, pointing into one flat
//! index list where the shadowed lights come first, so the shader keeps the shadow lookup
//! out of the loop over unshadowed lights.

use crate::bounds::{Aabb, Sphere};
use glam::{Mat4, Vec3};

/// Pixels a cluster tile spans across and down, at most `MAX_TILES_ACROSS` tiles each
/// way (larger images get larger tiles). Small tiles and thin slices keep a far cluster
/// (metres wide at a hundred metres) from listing the many small lights of its volume
/// that reach none of its pixels.
pub const CLUSTER_TILE_PX: u32 = 32;
pub const MAX_TILES_ACROSS: u32 = 48;
/// Depth slices, spread exponentially over the depths where surfaces are. More slices
/// list fewer lights per cluster, but since the shader tests ranges in a cheap pass
/// (culled.wesl), 128 measured no faster than 64 on the light-scaling scene while their
/// lists took the CPU a fifth longer to build (docs/forward.md).
pub const CLUSTER_SLICES: u32 = 64;
/// Most lights one object is shaded with under per-object culling.
pub const MAX_LIGHTS_PER_OBJECT: usize = 8;

/// A point or spot light as culling sees it: its range sphere, whether its loop needs a
/// shadow lookup, and how bright it is at 1 m (for ranking per object).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CullLight {
    pub sphere: Sphere,
    pub shadowed: bool,
    pub peak_intensity: f32,
}

/// Lists of light indices, one per cluster or object, laid end to end: list `k` is
/// `indices[starts[k]..starts[k + 1]]`. Its shadowed lights come first, each marked with
/// `SHADOWED_ENTRY`, so the shader runs the loop with the shadow lookup while the mark is
/// set. One `u32` per list, uploaded as built: a frame has up to a hundred thousand
/// clusters.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightLists {
    /// Where each list starts in `indices`, then where the last one ends (empty for no
    /// lists).
    pub starts: Vec<u32>,
    /// Light indices, the shadowed ones with `SHADOWED_ENTRY` added.
    pub indices: Vec<u32>,
}

/// The mark of a shadowed light's entry in `LightLists::indices` (a frame has a few
/// thousand lights, so the index never reaches this bit).
pub const SHADOWED_ENTRY: u32 = 1 << 31;

impl LightLists {
    /// How many lists there are.
    pub fn len(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The entries of list `k`, marks included.
    pub fn entries(&self, k: usize) -> &[u32] {
        &self.indices[self.starts[k] as usize..self.starts[k + 1] as usize]
    }

    /// The light indices of list `k`, in order (shadowed lights first), without marks.
    pub fn list(&self, k: usize) -> Vec<u32> {
        self.entries(k).iter().map(|&e| e & !SHADOWED_ENTRY).collect()
    }

    /// How many lights list `k` holds.
    pub fn count(&self, k: usize) -> usize {
        (self.starts[k + 1] - self.starts[k]) as usize
    }

    /// How many shadowed lights lead list `k`.
    pub fn shadowed(&self, k: usize) -> usize {
        self.entries(k).iter().take_while(|&&e| e & SHADOWED_ENTRY != 0).count()
    }

    /// Appends a list: the shadowed lights of `lights` (indices into `all`) first.
    fn push(&mut self, lights: &[u32], all: &[CullLight]) {
        if self.starts.is_empty() {
            self.starts.push(0);
        }
        let shadowed = lights.iter().filter(|&&i| all[i as usize].shadowed);
        self.indices.extend(shadowed.map(|&i| i | SHADOWED_ENTRY));
        self.indices.extend(lights.iter().filter(|&&i| !all[i as usize].shadowed));
        self.starts.push(self.indices.len() as u32);
    }
}

/// The froxel grid of one view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterGrid {
    pub width: u32,
    pub height: u32,
    /// Tiles across and down.
    pub tiles_x: u32,
    pub tiles_y: u32,
    /// Pixels per tile, across and down.
    pub tile_width: u32,
    pub tile_height: u32,
    /// View depths (metres, positive) the slices span: from the nearest surface to the
    /// farthest one a light can reach. Depths beyond `far` fall in the last slice, depths
    /// before `near` in the first.
    pub near: f32,
    pub far: f32,
}

/// What `assign` reads of a grid for every light, computed once per frame (thousands of
/// lights each take a few slices: a division or `powf` saved per slice counts).
struct FrameConstants {
    /// `ClusterGrid::slice_params`.
    slice_params: (f32, f32),
    /// `slice_start` of every slice and of the last one's end.
    slice_starts: Vec<f32>,
    /// The image's width and height in tiles (fractional where a tile is cut off).
    tiles_across: (f32, f32),
}

/// One light's clusters in one slice: a rectangle of tiles.
#[derive(Clone, Copy, Debug)]
struct SliceCover {
    light: u32,
    slice: u32,
    tiles_x: (u32, u32),
    tiles_y: (u32, u32),
}

impl ClusterGrid {
    /// The grid for a `width` x `height` image whose surfaces lie between view depths
    /// `near` and `far` (as far as any light reaches them).
    pub fn new(width: u32, height: u32, near: f32, far: f32) -> ClusterGrid {
        let tile = |side: u32| CLUSTER_TILE_PX.max(side.div_ceil(MAX_TILES_ACROSS)).max(1);
        let (tile_width, tile_height) = (tile(width), tile(height));
        ClusterGrid {
            width,
            height,
            tiles_x: width.div_ceil(tile_width).max(1),
            tiles_y: height.div_ceil(tile_height).max(1),
            tile_width,
            tile_height,
            near,
            far: far.max(near * 1.01),
        }
    }

    pub fn cluster_count(&self) -> usize {
        (self.tiles_x * self.tiles_y * CLUSTER_SLICES) as usize
    }

    /// `(scale, bias)` with `slice = floor(log2(depth) * scale + bias)`.
    pub fn slice_params(&self) -> (f32, f32) {
        let scale = CLUSTER_SLICES as f32 / (self.far / self.near).log2();
        (scale, -self.near.log2() * scale)
    }

    /// The slice a view depth falls in.
    pub fn slice_of(&self, depth: f32) -> u32 {
        self.slice_with(self.slice_params(), depth)
    }

    /// `slice_of` with `slice_params` computed once by the caller.
    fn slice_with(&self, (scale, bias): (f32, f32), depth: f32) -> u32 {
        // Clamped to non-negative first, truncation floors.
        (depth.max(self.near).log2() * scale + bias).clamp(0.0, (CLUSTER_SLICES - 1) as f32) as u32
    }

    /// View depth where slice `s` begins (`s = slices` gives `far`).
    pub fn slice_start(&self, s: u32) -> f32 {
        self.near * (self.far / self.near).powf(s as f32 / CLUSTER_SLICES as f32)
    }

    /// The cluster of pixel `(x, y)` at view depth `depth`, as the shader finds it.
    pub fn cluster_at(&self, x: f32, y: f32, depth: f32) -> usize {
        let tx = ((x / self.tile_width as f32) as u32).min(self.tiles_x - 1);
        let ty = ((y / self.tile_height as f32) as u32).min(self.tiles_y - 1);
        self.index(tx, ty, self.slice_of(depth))
    }

    pub fn index(&self, tx: u32, ty: u32, slice: u32) -> usize {
        ((slice * self.tiles_y + ty) * self.tiles_x + tx) as usize
    }

    /// Per cluster, the lights (indices into `lights`, whose spheres are in view space)
    /// that may reach it: in each slice a sphere spans, the part of it within the slice's
    /// depths (a disc of the sphere's cross-section there, swept over the slice) is
    /// projected to the screen and covers a rectangle of tiles. Built by counting, in time
    /// linear in the clusters plus the light-cluster pairs; shadowed lights lead each list.
    pub fn assign(&self, clip_from_view: &Mat4, lights: &[CullLight]) -> LightLists {
        self.assign_numbered(clip_from_view, lights, 0)
    }

    /// `assign` with `first_index` added to every light index (where `lights` start in
    /// the frame's list of lights), as the lists are written.
    pub fn assign_numbered(&self, clip_from_view: &Mat4, lights: &[CullLight], first_index: u32) -> LightLists {
        // Most small lights span a few slices; reserving spares the copies of growing.
        let mut covers = Vec::with_capacity(lights.len() * 4);
        let perspective = Perspective::of(clip_from_view);
        let constants = FrameConstants {
            slice_params: self.slice_params(),
            slice_starts: (0..=CLUSTER_SLICES).map(|s| self.slice_start(s)).collect(),
            tiles_across: (self.width as f32 / self.tile_width as f32, self.height as f32 / self.tile_height as f32),
        };
        // Shadowed lights first, so that they lead every list they are in.
        for shadowed in [true, false] {
            for (i, light) in lights.iter().enumerate().filter(|(_, l)| l.shadowed == shadowed) {
                self.cover(perspective, &constants, i as u32, &light.sphere, &mut covers);
            }
        }
        // A counting sort of the light-cluster pairs: count each list, turn the counts
        // into each list's end, then fill every list backwards from its end, so that the
        // starts alone serve as the cursors and each list keeps the covers' order
        // (shadowed lights first, then ascending).
        let clusters = self.cluster_count();
        let mut starts = vec![0u32; clusters + 1];
        for c in &covers {
            self.for_each_cluster(c, |k| starts[k] += 1);
        }
        let mut end = 0u32;
        for place in &mut starts[..clusters] {
            end += *place;
            *place = end;
        }
        starts[clusters] = end;
        let mut indices = vec![0u32; end as usize];
        for c in covers.iter().rev() {
            let mark = if lights[c.light as usize].shadowed { SHADOWED_ENTRY } else { 0 };
            let entry = (c.light + first_index) | mark;
            self.for_each_cluster(c, |k| {
                starts[k] -= 1;
                indices[starts[k] as usize] = entry;
            });
        }
        LightLists { starts, indices }
    }

    /// Calls `f` with each cluster of one cover, row by row.
    #[inline]
    fn for_each_cluster(&self, c: &SliceCover, mut f: impl FnMut(usize)) {
        for ty in c.tiles_y.0..=c.tiles_y.1 {
            let row = self.index(0, ty, c.slice);
            for k in row + c.tiles_x.0 as usize..=row + c.tiles_x.1 as usize {
                f(k);
            }
        }
    }

    /// Appends the tiles light `light`'s view-space sphere covers in each slice it spans
    /// (every tile where the projection is not a plain perspective).
    fn cover(
        &self,
        perspective: Option<Perspective>,
        constants: &FrameConstants,
        light: u32,
        sphere: &Sphere,
        out: &mut Vec<SliceCover>,
    ) {
        let Sphere { center, radius } = *sphere;
        let depth = -center.z;
        if depth + radius < self.near || depth - radius > self.far {
            return;
        }
        let all_x = (0, self.tiles_x - 1);
        let all_y = (0, self.tiles_y - 1);
        let (slice_starts, params) = (&constants.slice_starts, constants.slice_params);
        for slice in self.slice_with(params, depth - radius)..=self.slice_with(params, depth + radius) {
            // The slice's depths; the first and last take in what lies before and beyond.
            let z0 = if slice == 0 { 0.0 } else { slice_starts[slice as usize] };
            let z1 = if slice == CLUSTER_SLICES - 1 { f32::INFINITY } else { slice_starts[slice as usize + 1] };
            let (d0, d1) = ((depth - radius).max(z0), (depth + radius).min(z1));
            if d0 > d1 {
                continue;
            }
            // The sphere's widest cross-section within the slice.
            let gap = (z0 - depth).max(depth - z1).max(0.0);
            let r = (radius * radius - gap * gap).max(0.0).sqrt();
            let (tiles_x, tiles_y) = match perspective {
                Some(p) if d0 > 1e-4 => {
                    let inverse_depths = (1.0 / d0, 1.0 / d1);
                    let (x0, x1) = p.ndc_range(p.scale_x, p.offset_x, center.x - r, center.x + r, inverse_depths);
                    let (y0, y1) = p.ndc_range(p.scale_y, p.offset_y, center.y - r, center.y + r, inverse_depths);
                    if x0 > 1.0 || x1 < -1.0 || y0 > 1.0 || y1 < -1.0 {
                        continue;
                    }
                    let (across, down) = constants.tiles_across;
                    // Screen y grows downwards while NDC y grows upwards.
                    let tile_x = |ndc: f32| Self::tile_of((ndc * 0.5 + 0.5) * across, self.tiles_x);
                    let tile_y = |ndc: f32| Self::tile_of((0.5 - ndc * 0.5) * down, self.tiles_y);
                    ((tile_x(x0), tile_x(x1)), (tile_y(y1), tile_y(y0)))
                }
                _ => (all_x, all_y),
            };
            out.push(SliceCover { light, slice, tiles_x, tiles_y });
        }
    }

    /// The tile at `position` (in tiles) among `tiles`, clamped to the grid; truncating
    /// after the clamp to non-negative floors without a call to `floorf`.
    #[inline]
    fn tile_of(position: f32, tiles: u32) -> u32 {
        position.clamp(0.0, (tiles - 1) as f32) as u32
    }
}

/// A perspective projection without skew: `ndc = scale * v / depth - offset` along x and
/// y, for view depth `depth = -z` (what `perspective_reverse_z` and off-centre frusta
/// give).
#[derive(Clone, Copy, Debug)]
struct Perspective {
    scale_x: f32,
    scale_y: f32,
    offset_x: f32,
    offset_y: f32,
}

impl Perspective {
    /// `None` for projections of another shape (their clusters take every tile).
    fn of(m: &Mat4) -> Option<Perspective> {
        let skewless = m.x_axis.y == 0.0 && m.y_axis.x == 0.0 && m.x_axis.w == 0.0 && m.y_axis.w == 0.0;
        let divides_by_depth = m.z_axis.w == -1.0 && m.w_axis.w == 0.0 && m.w_axis.x == 0.0 && m.w_axis.y == 0.0;
        (skewless && divides_by_depth && m.x_axis.x > 0.0 && m.y_axis.y > 0.0).then_some(Perspective {
            scale_x: m.x_axis.x,
            scale_y: m.y_axis.y,
            offset_x: m.z_axis.x,
            offset_y: m.z_axis.y,
        })
    }

    /// The NDC interval of `scale * v / d - offset` over `v` in `[v0, v1]` and `d` in
    /// `[d0, d1]` (0 < d0 <= d1), given as `(1 / d0, 1 / d1)`.
    fn ndc_range(&self, scale: f32, offset: f32, v0: f32, v1: f32, (inv_d0, inv_d1): (f32, f32)) -> (f32, f32) {
        let low = if v0 >= 0.0 { v0 * inv_d1 } else { v0 * inv_d0 };
        let high = if v1 >= 0.0 { v1 * inv_d0 } else { v1 * inv_d1 };
        (scale * low - offset, scale * high - offset)
    }
}

/// The smallest sphere around what a spot light can reach: the spherical sector with
/// apex `position`, axis `direction` (unit), radius `range` and half-angle `outer_rad`.
/// Up to 45 degrees it passes through the apex and the cap's rim; from 45 to 90 degrees
/// it is the rim's own sphere (centred on the axis at the rim's height), which holds the
/// apex and the cap; wider cones get the range sphere.
pub fn spot_bounding_sphere(position: Vec3, direction: Vec3, range: f32, outer_rad: f32) -> Sphere {
    let (sin, cos) = outer_rad.sin_cos();
    if cos <= 0.0 {
        return Sphere { center: position, radius: range };
    }
    if cos <= std::f32::consts::FRAC_1_SQRT_2 {
        return Sphere { center: position + direction * (range * cos), radius: range * sin };
    }
    // Equidistant from the apex and the rim: c^2 = (R cos - c)^2 + (R sin)^2.
    let radius = range / (2.0 * cos);
    Sphere { center: position + direction * radius, radius }
}

/// Per object (by its world bounds), up to `MAX_LIGHTS_PER_OBJECT` of `lights` (world
/// space) whose range touches it, the brightest at the object first; lights the object
/// cannot see are never listed, so every index names one of the frame's lights.
pub fn lights_per_object(objects: &[Aabb], lights: &[CullLight]) -> LightLists {
    let mut lists = LightLists::default();
    let mut ranked: Vec<(f32, u32)> = Vec::new();
    for bounds in objects {
        ranked.clear();
        if !bounds.is_empty() {
            for (i, light) in lights.iter().enumerate() {
                let Sphere { center, radius } = light.sphere;
                let nearest = center.clamp(bounds.min, bounds.max);
                let d2 = nearest.distance_squared(center);
                if d2 <= radius * radius {
                    // Inverse-square brightness at the object's nearest point, with a
                    // floor so that lights inside it rank by intensity alone.
                    ranked.push((light.peak_intensity / d2.max(0.01), i as u32));
                }
            }
            ranked.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
            ranked.truncate(MAX_LIGHTS_PER_OBJECT);
        }
        let chosen: Vec<u32> = ranked.iter().map(|&(_, i)| i).collect();
        lists.push(&chosen, lights);
    }
    lists
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::perspective_reverse_z;

    fn light(center: Vec3, radius: f32, shadowed: bool) -> CullLight {
        CullLight { sphere: Sphere { center, radius }, shadowed, peak_intensity: 1.0 }
    }

    /// View-space bounds of every cluster, in `index` order: the boxes culling tested
    /// against before it projected each slice of a sphere. `view_from_clip` inverts a
    /// projection with clip-space depth 1 at the near plane (reverse-Z) or 0 (standard);
    /// either works, as only rays through pixel corners are taken from it.
    fn cluster_bounds(grid: &ClusterGrid, view_from_clip: &Mat4) -> Vec<Aabb> {
        // The ray through each tile corner, as (origin, direction) in view space.
        let corner_ray = |tx: u32, ty: u32| {
            let px = (tx * grid.tile_width).min(grid.width) as f32;
            let py = (ty * grid.tile_height).min(grid.height) as f32;
            let ndc_x = px / grid.width as f32 * 2.0 - 1.0;
            let ndc_y = 1.0 - py / grid.height as f32 * 2.0;
            let a = view_from_clip.project_point3(Vec3::new(ndc_x, ndc_y, 1.0));
            let b = view_from_clip.project_point3(Vec3::new(ndc_x, ndc_y, 0.5));
            (a, b - a)
        };
        let at_depth = |(origin, dir): (Vec3, Vec3), depth: f32| {
            // Where the ray meets the plane z = -depth (the camera looks along -Z).
            if dir.z.abs() < 1e-12 { origin } else { origin + dir * ((-depth - origin.z) / dir.z) }
        };
        let mut rays = Vec::with_capacity(((grid.tiles_x + 1) * (grid.tiles_y + 1)) as usize);
        for ty in 0..=grid.tiles_y {
            for tx in 0..=grid.tiles_x {
                rays.push(corner_ray(tx, ty));
            }
        }
        let ray = |tx: u32, ty: u32| rays[(ty * (grid.tiles_x + 1) + tx) as usize];
        let mut bounds = Vec::with_capacity(grid.cluster_count());
        for s in 0..CLUSTER_SLICES {
            let (z0, z1) = (grid.slice_start(s), grid.slice_start(s + 1));
            for ty in 0..grid.tiles_y {
                for tx in 0..grid.tiles_x {
                    let corners = [ray(tx, ty), ray(tx + 1, ty), ray(tx, ty + 1), ray(tx + 1, ty + 1)];
                    bounds.push(Aabb::from_points(corners.iter().flat_map(|&r| [at_depth(r, z0), at_depth(r, z1)])));
                }
            }
        }
        bounds
    }

    fn projection() -> Mat4 {
        perspective_reverse_z(1.0, 16.0 / 9.0, 0.1, None)
    }

    /// A view-space point seen at pixel (x, y), depth `depth`.
    fn point_at(grid: &ClusterGrid, proj: &Mat4, x: f32, y: f32, depth: f32) -> Vec3 {
        let ndc = Vec3::new(x / grid.width as f32 * 2.0 - 1.0, 1.0 - y / grid.height as f32 * 2.0, 0.5);
        let p = proj.inverse().project_point3(ndc);
        p * (depth / -p.z)
    }

    #[test]
    fn slices_cover_near_to_far_exponentially() {
        let grid = ClusterGrid::new(1280, 720, 0.1, 100.0);
        assert_eq!(grid.slice_of(0.05), 0);
        assert_eq!(grid.slice_of(0.1001), 0);
        assert_eq!(grid.slice_of(99.9), CLUSTER_SLICES - 1);
        assert_eq!(grid.slice_of(1e6), CLUSTER_SLICES - 1);
        for s in 0..CLUSTER_SLICES {
            let mid = (grid.slice_start(s) * grid.slice_start(s + 1)).sqrt();
            assert_eq!(grid.slice_of(mid), s);
        }
        assert!((grid.slice_start(CLUSTER_SLICES) - 100.0).abs() < 1e-3);
    }

    #[test]
    fn every_pixel_a_light_reaches_lists_it() {
        // Brute force: sample pixels and depths; wherever a point lies inside a light's
        // sphere, that pixel's cluster must list the light.
        let proj = projection();
        let grid = ClusterGrid::new(320, 180, 0.1, 40.0);
        let lights = vec![
            light(Vec3::new(0.0, 0.0, -5.0), 1.0, false),
            light(Vec3::new(3.0, -1.0, -12.0), 4.0, true),
            light(Vec3::new(-0.2, 0.1, -0.3), 0.5, false),
            light(Vec3::new(-20.0, 5.0, -30.0), 6.0, true),
            light(Vec3::new(0.0, 0.0, 2.0), 3.0, false),
        ];
        let lists = grid.assign(&proj, &lights);
        let mut checked = 0;
        for y in (0..180).step_by(7) {
            for x in (0..320).step_by(7) {
                for k in 0..60 {
                    let depth = 0.1 * 1.12f32.powi(k);
                    let p = point_at(&grid, &proj, x as f32 + 0.5, y as f32 + 0.5, depth);
                    let listed = lists.list(grid.cluster_at(x as f32 + 0.5, y as f32 + 0.5, depth));
                    for (i, l) in lights.iter().enumerate() {
                        if p.distance(l.sphere.center) < l.sphere.radius {
                            assert!(listed.contains(&(i as u32)), "light {i} missing at ({x}, {y}, {depth})");
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 1000, "the lights must cover many samples ({checked})");
    }

    #[test]
    fn lights_small_for_their_depth_are_listed_wherever_they_reach() {
        let proj = projection();
        let fine = ClusterGrid::new(320, 180, 0.5, 60.0);
        // Lights a hundredth of their depth wide: far thinner than a slice.
        let small: Vec<CullLight> = (0..400)
            .map(|k| {
                let depth = 2.0 + (k % 40) as f32 * 1.4;
                let x = ((k * 37) % 41) as f32 / 41.0 - 0.5;
                light(Vec3::new(x * depth, -0.3 * depth * 0.56, -depth), 0.01 * depth, k % 9 == 0)
            })
            .collect();
        // Brute force: every sampled point inside a light lies in a cluster that lists it;
        // shadowed lights lead each list.
        let lists = fine.assign(&proj, &small);
        assert_eq!(lists.len(), fine.cluster_count());
        let mut checked = 0;
        for y in (0..180).step_by(3) {
            for x in (0..320).step_by(3) {
                for k in 0..200 {
                    let depth = 2.0 * 1.02f32.powi(k);
                    let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                    let p = point_at(&fine, &proj, px, py, depth);
                    let cluster = fine.cluster_at(px, py, depth);
                    for (i, l) in small.iter().enumerate() {
                        if p.distance(l.sphere.center) < l.sphere.radius {
                            assert!(
                                lists.list(cluster).contains(&(i as u32)),
                                "light {i} missing at ({x}, {y}, {depth})"
                            );
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 200, "the lights must cover many samples ({checked})");
        for k in 0..lists.len() {
            let list = lists.list(k);
            let (lead, rest) = list.split_at(lists.shadowed(k));
            assert!(lead.iter().all(|&i| small[i as usize].shadowed));
            assert!(rest.iter().all(|&i| !small[i as usize].shadowed));
        }
    }

    #[test]
    fn numbered_lists_are_the_lists_moved_along() {
        let proj = projection();
        let grid = ClusterGrid::new(320, 180, 0.1, 40.0);
        let lights: Vec<CullLight> = (0..50)
            .map(|k| light(Vec3::new(k as f32 * 0.3 - 7.0, -1.0, -3.0 - k as f32 * 0.5), 1.5, k % 4 == 0))
            .collect();
        let plain = grid.assign(&proj, &lights);
        let numbered = grid.assign_numbered(&proj, &lights, 3);
        assert_eq!(numbered.starts, plain.starts);
        assert!(plain.indices.iter().any(|&e| e & SHADOWED_ENTRY != 0), "some entries are marked");
        // The marks stay; the indices move by 3.
        assert!(numbered.indices.iter().zip(&plain.indices).all(|(&n, &p)| n == p + 3));
        for k in 0..plain.len() {
            assert_eq!(numbered.shadowed(k), plain.shadowed(k));
        }
    }

    #[test]
    fn clusters_far_from_a_light_do_not_list_it() {
        let proj = projection();
        let grid = ClusterGrid::new(320, 180, 0.1, 40.0);
        let lists = grid.assign(&proj, &[light(Vec3::new(0.0, 0.0, -5.0), 0.5, false)]);
        let listed = (0..lists.len()).filter(|&k| lists.count(k) > 0).count();
        assert!(listed > 0 && listed < 40, "a small light touches a few clusters, not {listed}");
        // A light behind the camera touches none.
        let behind = grid.assign(&proj, &[light(Vec3::new(0.0, 0.0, 5.0), 1.0, false)]);
        assert!(behind.indices.is_empty());
    }

    #[test]
    fn lists_are_no_longer_than_the_cluster_boxes_give() {
        // Many small lights over a floor below the camera: each slice's projected
        // cross-section lists at most the lights whose sphere touches the cluster's
        // view-space box (the old test), and far fewer than the lights in the frame.
        let proj = projection();
        let grid = ClusterGrid::new(640, 360, 2.0, 120.0);
        let view_from_world = Mat4::look_at_rh(Vec3::new(0.0, 10.0, 0.0), Vec3::new(0.0, 0.0, -40.0), Vec3::Y);
        let mut lights = Vec::new();
        for i in 0..64 {
            for j in 0..64 {
                let p = Vec3::new(-60.0 + i as f32 * 1.875, 0.5, -j as f32 * 1.875);
                lights.push(light(view_from_world.transform_point3(p), 1.8, (i + j) % 7 == 0));
            }
        }
        let lists = grid.assign(&proj, &lights);
        let bounds = cluster_bounds(&grid, &proj.inverse());
        let boxed: usize = bounds
            .iter()
            .map(|b| {
                lights
                    .iter()
                    .filter(|l| l.sphere.center.clamp(b.min, b.max).distance(l.sphere.center) <= l.sphere.radius)
                    .count()
            })
            .sum();
        let longest = (0..lists.len()).map(|k| lists.count(k)).max().unwrap();
        println!("{} light-cluster pairs, {boxed} by the boxes; longest list {longest}", lists.indices.len());
        assert!(lists.indices.len() <= boxed, "{} > {boxed}", lists.indices.len());
        assert!(longest < 64, "a cluster lists {longest} of {} lights", lights.len());
        // Every list is in order: the shadowed lights, marked, first.
        for k in 0..lists.len() {
            let list = lists.list(k);
            assert!(list[..lists.shadowed(k)].iter().all(|&i| lights[i as usize].shadowed));
            assert!(list[lists.shadowed(k)..].iter().all(|&i| !lights[i as usize].shadowed));
        }
    }

    #[test]
    fn shadowed_lights_lead_each_list() {
        let proj = projection();
        let grid = ClusterGrid::new(64, 64, 0.1, 20.0);
        let lights = [
            light(Vec3::new(0.0, 0.0, -5.0), 3.0, false),
            light(Vec3::new(0.0, 0.0, -5.0), 3.0, true),
            light(Vec3::new(0.0, 0.0, -5.0), 3.0, false),
        ];
        let lists = grid.assign(&proj, &lights);
        let k = grid.cluster_at(32.0, 32.0, 5.0);
        assert_eq!(lists.list(k), &[1, 0, 2]);
        assert_eq!(lists.shadowed(k), 1);
    }

    #[test]
    fn spot_spheres_hold_their_cone() {
        let apex = Vec3::new(1.0, 2.0, 3.0);
        let dir = Vec3::new(0.0, -1.0, 0.0);
        for outer_deg in [5.0f32, 20.0, 35.0, 44.0, 45.0, 46.0, 59.0, 60.0, 80.0, 89.0] {
            let outer = outer_deg.to_radians();
            let s = spot_bounding_sphere(apex, dir, 10.0, outer);
            assert!(s.radius <= 10.0 + 1e-4, "never larger than the range sphere");
            // Points of the sector: the apex, along the axis, and over the cap and sides.
            for i in 0..=20 {
                for j in 0..16 {
                    let angle = outer * i as f32 / 20.0;
                    let around = std::f32::consts::TAU * j as f32 / 16.0;
                    let off_axis = Vec3::new(around.cos(), 0.0, around.sin());
                    for r in [0.0, 2.5, 5.0, 7.5, 10.0] {
                        let p = apex + (dir * angle.cos() + off_axis * angle.sin()) * r;
                        assert!(p.distance(s.center) <= s.radius * (1.0 + 1e-4), "{outer_deg} deg: {p} outside");
                    }
                }
            }
        }
        let narrow = spot_bounding_sphere(apex, dir, 25.0, 35f32.to_radians());
        assert!(narrow.radius < 16.0, "a 35 degree cone needs far less than its range: {}", narrow.radius);
        let wide = spot_bounding_sphere(apex, dir, 10.0, 60f32.to_radians());
        assert!(wide.radius < 8.7, "a 60 degree cone needs less than its range: {}", wide.radius);
    }

    #[test]
    fn objects_get_their_brightest_lights_first() {
        let object = Aabb { min: Vec3::splat(-1.0), max: Vec3::splat(1.0) };
        let far_object = Aabb { min: Vec3::splat(50.0), max: Vec3::splat(51.0) };
        let mut lights: Vec<CullLight> =
            (0..12).map(|i| light(Vec3::new(2.0 + i as f32, 0.0, 0.0), 20.0, i == 5)).collect();
        lights[7].peak_intensity = 1000.0;
        let lists = lights_per_object(&[object, far_object], &lights);
        // Light 7 is brightest at the object; 5 is shadowed, so it leads; then by distance.
        assert_eq!(lists.list(0), &[5, 7, 0, 1, 2, 3, 4, 6]);
        assert_eq!(lists.shadowed(0), 1);
        assert!(lists.list(1).is_empty(), "no light reaches the far object");
    }
}
