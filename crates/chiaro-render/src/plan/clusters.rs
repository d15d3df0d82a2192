//! Light culling for forward shading: which point and spot lights a pixel loops over.
//!
//! - Clustered: the view is cut into a froxel grid (screen tiles x depth slices that grow
//!   exponentially with distance); each cluster lists the lights whose range sphere
//!   touches its view-space bounds.
//! - Per object: each object gets the few lights that matter most to it (the "lights per
//!   object" of Catlike Coding's Custom SRP tutorial "Point and Spot Lights").
//!
//! Both produce `CulledLightLists`, the lists in the layout the shaders read (this is the
//! format's one home): one start per cluster or object into one flat index list, where
//! the shadowed lights come first, marked, so the shader keeps the shadow lookup out of the
//! loop over unshadowed lights. Pure CPU, as the rest of the plan.

use crate::shader_constants::{CLUSTER_SLICES, SHADOWED_ENTRY};
use chiaro_math::{Aabb, Sphere};
use glam::Mat4;

/// Pixels a cluster tile spans across and down, at most `MAX_TILES_ACROSS` tiles each
/// way (larger images get larger tiles). Small tiles and thin slices keep a far cluster
/// (metres wide at a hundred metres) from listing the many small lights of its volume
/// that reach none of its pixels.
pub const CLUSTER_TILE_PX: u32 = 32;
/// Most tiles across or down: past it, tiles grow.
pub const MAX_TILES_ACROSS: u32 = 48;
/// Most lights one object is shaded with under per-object culling.
pub const MAX_LIGHTS_PER_OBJECT: usize = 8;

/// A point or spot light as culling sees it: its range sphere, whether its loop needs a
/// shadow lookup, and how bright it is at 1 m (for ranking per object).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CullLight {
    /// World or view space, as the caller culls in.
    pub sphere: Sphere,
    /// Its loop needs a shadow lookup: it leads its lists, marked.
    pub shadowed: bool,
    /// The brightest channel's intensity, candela.
    pub peak_intensity: f32,
}

/// Lists of light indices, one per cluster or object, laid end to end: list `k` is
/// `indices[starts[k]..starts[k + 1]]`. Its shadowed lights come first, each marked with
/// `SHADOWED_ENTRY`, so the shader runs the loop with the shadow lookup while the mark is
/// set. One `u32` per list, uploaded as built: a frame has up to a hundred thousand
/// clusters.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CulledLightLists {
    /// Where each list starts in `indices`, then where the last one ends (empty for no
    /// lists).
    pub starts: Vec<u32>,
    /// Light indices, the shadowed ones with `SHADOWED_ENTRY` added.
    pub indices: Vec<u32>,
}

impl CulledLightLists {
    /// How many lists there are.
    pub fn len(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    /// No lists at all (no culling this frame).
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
    /// The image's width in pixels.
    pub width: u32,
    /// The image's height in pixels.
    pub height: u32,
    /// Tiles across.
    pub tiles_x: u32,
    /// Tiles down.
    pub tiles_y: u32,
    /// Pixels per tile across.
    pub tile_width: u32,
    /// Pixels per tile down.
    pub tile_height: u32,
    /// View depths (metres, positive) the slices span: from the nearest surface to the
    /// farthest one a light can reach. Depths beyond `far` fall in the last slice, depths
    /// before `near` in the first.
    pub near: f32,
    /// See `near`.
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

    /// Clusters in the grid: tiles across x down x slices.
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

    /// The cluster of tile (`tx`, `ty`) in `slice`: slices outermost, rows, then columns.
    pub fn index(&self, tx: u32, ty: u32, slice: u32) -> usize {
        ((slice * self.tiles_y + ty) * self.tiles_x + tx) as usize
    }

    /// Per cluster, the lights (indices into `lights`, whose spheres are in view space)
    /// that may reach it: in each slice a sphere spans, the part of it within the slice's
    /// depths (a disc of the sphere's cross-section there, swept over the slice) is
    /// projected to the screen and covers a rectangle of tiles. Built by counting, in time
    /// linear in the clusters plus the light-cluster pairs; shadowed lights lead each list.
    pub fn assign(&self, clip_from_view: &Mat4, lights: &[CullLight]) -> CulledLightLists {
        self.assign_numbered(clip_from_view, lights, 0)
    }

    /// `assign` with `first_index` added to every light index (where `lights` start in
    /// the frame's list of lights), as the lists are written.
    pub fn assign_numbered(&self, clip_from_view: &Mat4, lights: &[CullLight], first_index: u32) -> CulledLightLists {
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
        CulledLightLists { starts, indices }
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
    /// (every tile where the projection is neither a plain perspective nor orthographic).
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
                Some(p) if d0 > 1e-4 || !p.divides_by_depth => {
                    let inverse_depths = if p.divides_by_depth { (1.0 / d0, 1.0 / d1) } else { (1.0, 1.0) };
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

/// A projection without skew: `ndc = scale * v / depth - offset` along x and y for a
/// perspective, for view depth `depth = -z` (what `perspective_reverse_z` and off-centre
/// frusta give), or `ndc = scale * v - offset` for an orthographic one.
#[derive(Clone, Copy, Debug)]
struct Perspective {
    scale_x: f32,
    scale_y: f32,
    offset_x: f32,
    offset_y: f32,
    divides_by_depth: bool,
}

impl Perspective {
    /// `None` for projections of another shape (their clusters take every tile).
    fn of(m: &Mat4) -> Option<Perspective> {
        let skewless = m.x_axis.y == 0.0 && m.y_axis.x == 0.0 && m.x_axis.w == 0.0 && m.y_axis.w == 0.0;
        let divides_by_depth = m.z_axis.w == -1.0 && m.w_axis.w == 0.0 && m.w_axis.x == 0.0 && m.w_axis.y == 0.0;
        let parallel = m.z_axis.w == 0.0 && m.w_axis.w == 1.0 && m.z_axis.x == 0.0 && m.z_axis.y == 0.0;
        let (offset_x, offset_y) = if divides_by_depth { (m.z_axis.x, m.z_axis.y) } else { (-m.w_axis.x, -m.w_axis.y) };
        (skewless && (divides_by_depth || parallel) && m.x_axis.x > 0.0 && m.y_axis.y > 0.0).then_some(Perspective {
            scale_x: m.x_axis.x,
            scale_y: m.y_axis.y,
            offset_x,
            offset_y,
            divides_by_depth,
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

/// Per object (by its world bounds), up to `MAX_LIGHTS_PER_OBJECT` of `lights` (world
/// space) whose range touches it, the brightest at the object first; lights the object
/// cannot see are never listed, so every index names one of the frame's lights.
pub fn lights_per_object(objects: &[Aabb], lights: &[CullLight]) -> CulledLightLists {
    let mut lists = CulledLightLists::default();
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
#[path = "clusters_tests.rs"]
mod tests;
