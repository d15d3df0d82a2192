//! The texel stage: every lightmap texel traced (irradiance, coverage and shadow mask,
//! supersampled over the texel), atlas by atlas and row by row in parallel; where the
//! denoiser would leave a texel noisier than `TARGET_FILTERED_NOISE` (near contacts and
//! in corners, where it may not blend), more samples traced; the noisy part of the light
//! denoised (direct light from baked lights is left sharp); then dilated across the
//! gutters. The laid-out atlases flow in; `BakedAtlases` flows out.

use super::{BakeError, BakedAtlases, DOMAIN_TEXEL, DOMAIN_TEXEL_MORE, Job, ShuffledStrata, stratum};
use crate::denoise::{Halves, NoiseEstimate, NoisyAtlas, TexelGuide, denoise, standard_errors};
use crate::layout::{AtlasLayout, GUTTER_TEXELS, PlacedTriangle};
use crate::raster::{TexelTriangles, barycentric, clamp_to_triangle, dilate, inside};
use crate::rng::Rng;
use crate::surface::Surfaces;
use crate::tracer::RayCount;
use chiaro_math::tonemap::luminance;
use chiaro_scene::Scene;
use chiaro_scene::baked::{Lightmap, ShadowMask};
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::sync::atomic::Ordering;

/// One traced texel: its direct light, the two half estimates of its noisy light (even
/// and odd samples), its coverage and shadow mask, and for the denoiser where it lies;
/// `guide` is `None` where no surface touches it (left for dilation).
#[derive(Clone, Copy)]
struct BakedTexel {
    direct: Vec3,
    noisy: Halves,
    coverage: f32,
    mask: [f32; 4],
    guide: Option<TexelGuide>,
}

/// The relative standard error of a texel's light that the denoised bake aims at: a texel
/// whose first samples, once filtered, would stay noisier than this gets more samples,
/// (relative error / target)^2 times as many, up to `MAX_SAMPLE_FACTOR`. Open surfaces
/// meet it from the filter's blending; texels beside a contact or in a corner, where the
/// filter keeps the light's gradient and blends little, take the extra samples.
const TARGET_FILTERED_NOISE: f32 = 0.012;

/// The most samples a texel takes, as a multiple of the bake's samples per texel.
const MAX_SAMPLE_FACTOR: u32 = 4;

/// What a texel's samples added up to, before they are averaged.
#[derive(Clone, Copy, Default)]
struct TexelSums {
    direct: Vec3,
    even: Vec3,
    odd: Vec3,
    evens: u32,
    odds: u32,
    covered: u32,
    mask: [f32; 4],
    position: Vec3,
    inverse_distances: f32,
    hits: u32,
    guide: Option<TexelGuide>,
}

impl TexelSums {
    fn samples(&self) -> u32 {
        self.evens + self.odds
    }

    /// The averaged texel (`EMPTY_TEXEL` where no sample was taken).
    fn texel(&self, mask_channels: &[(usize, usize, usize)]) -> BakedTexel {
        let samples = self.samples();
        if samples == 0 || self.guide.is_none() {
            return EMPTY_TEXEL;
        }
        let n = samples as f32;
        let even = self.even / self.evens.max(1) as f32;
        // One sample leaves no odd half: it repeats the even one (and the noise reads 0).
        let odd = if self.odds > 0 { self.odd / self.odds as f32 } else { even };
        let mut mask = [1.0f32; 4];
        for &(channel, _, _) in mask_channels {
            mask[channel] = self.mask[channel] / n;
        }
        let guide = self.guide.map(|g| TexelGuide {
            position: self.position / n,
            // The harmonic mean distance to the surfaces the paths met, as irradiance
            // caching measures it (infinite where every path escaped).
            reach: if self.hits > 0 { self.hits as f32 / self.inverse_distances } else { f32::INFINITY },
            ..g
        });
        BakedTexel {
            direct: self.direct / n,
            noisy: Halves { even, odd },
            coverage: self.covered as f32 / n,
            mask,
            guide,
        }
    }
}

/// Nearer first hits than this (metres) count as this near: a path starting in a corner
/// must not pin its texel's reach to nothing.
const MIN_REACH: f32 = 1e-3;

/// What an untouched texel holds until dilation fills it.
const EMPTY_TEXEL: BakedTexel = BakedTexel {
    direct: Vec3::ZERO,
    noisy: Halves { even: Vec3::ZERO, odd: Vec3::ZERO },
    coverage: 0.0,
    mask: [1.0; 4],
    guide: None,
};

/// One atlas being baked: its triangles in atlas and world space, and which triangles
/// touch each texel.
struct Atlas<'a> {
    layer: u32,
    size: u32,
    triangles: &'a [PlacedTriangle],
    world: &'a [WorldTriangle],
    map: &'a TexelTriangles,
    surfaces: &'a Surfaces<'a>,
}

/// Bakes every atlas of `layout`, one after the other, each row in parallel.
pub(super) fn bake_texels(job: &Job, layout: &AtlasLayout) -> Result<BakedAtlases, BakeError> {
    let size = layout.size;
    job.progress.stage("lightmap rows", layout.atlas_count as u64 * size as u64);
    let surfaces = Surfaces::new(job.scene);
    let mut baked = BakedAtlases {
        lightmaps: Vec::new(),
        shadow_masks: Vec::new(),
        covered_texels: 0,
        noise_traced: NoiseEstimate::default(),
        noise: NoiseEstimate::default(),
    };
    for layer in 0..layout.atlas_count {
        let triangles: Vec<PlacedTriangle> = layout.triangles_of(layer).copied().collect();
        let world: Vec<WorldTriangle> = triangles.iter().map(|t| WorldTriangle::of(job.scene, t)).collect();
        let map = TexelTriangles::build(size, &triangles);
        let atlas = Atlas { layer, size, triangles: &triangles, world: &world, map: &map, surfaces: &surfaces };
        let samples = job.texel_samples;
        let mut sums: Vec<TexelSums> = (0..size)
            .into_par_iter()
            .flat_map_iter(|y| trace_row(job, &atlas, y, |_| (DOMAIN_TEXEL, samples), Vec::new()))
            .collect();
        if job.cancelled() {
            return Err(BakeError::Cancelled);
        }
        let more = more_samples(job, size, &sums);
        if more.iter().any(|&m| m > 0) {
            let rows: Vec<Vec<TexelSums>> = sums.chunks(size as usize).map(<[TexelSums]>::to_vec).collect();
            sums = rows
                .into_par_iter()
                .enumerate()
                .flat_map_iter(|(y, row)| {
                    let more = &more[y * size as usize..(y + 1) * size as usize];
                    trace_row(job, &atlas, y as u32, |x| (DOMAIN_TEXEL_MORE, more[x as usize]), row)
                })
                .collect();
            if job.cancelled() {
                return Err(BakeError::Cancelled);
            }
        }
        let texels = sums.iter().map(|s| s.texel(job.channel_lights)).collect();
        finish_atlas(job, size, texels, &mut baked);
    }
    Ok(baked)
}

/// Per texel, the samples to add to the `sums` of a first pass: where its light, denoised,
/// would stay noisier than `TARGET_FILTERED_NOISE`. None without the denoiser (a bake
/// asked to stay as traced takes its samples evenly) or with an odd sample count (the
/// halves must stay equal).
fn more_samples(job: &Job, size: u32, sums: &[TexelSums]) -> Vec<u32> {
    let base = job.texel_samples;
    let (Some(strength), true) = (job.denoise, base.is_multiple_of(2)) else {
        return vec![0; sums.len()];
    };
    let texels: Vec<BakedTexel> = sums.iter().map(|s| s.texel(job.channel_lights)).collect();
    let guides: Vec<Option<TexelGuide>> = texels.iter().map(|t| t.guide).collect();
    let traced: Vec<Halves> = texels.iter().map(|t| t.noisy).collect();
    let filtered = denoise(&NoisyAtlas { size, guides: &guides, halves: &traced, even_share: 0.5 }, strength);
    let errors = standard_errors(size, &guides, &filtered, 0.5);
    texels
        .iter()
        .zip(&filtered)
        .zip(&errors)
        .map(|((t, f), &error)| {
            let light = luminance(t.direct + f.whole(0.5));
            if t.guide.is_none() || light <= 0.0 {
                return 0;
            }
            let factor = (error / (TARGET_FILTERED_NOISE * light)).powi(2).min(MAX_SAMPLE_FACTOR as f32);
            // An even number, so that both halves keep the same count.
            let more = ((factor - 1.0).max(0.0) * base as f32 / 2.0).round() as u32 * 2;
            more.min((MAX_SAMPLE_FACTOR - 1) * base)
        })
        .collect()
}

/// One row of texels, each adding the samples `plan(x)` gives (its RNG domain and count)
/// to its sums in `row` (empty: from none); empty once the bake is cancelled.
fn trace_row(
    job: &Job,
    atlas: &Atlas,
    y: u32,
    plan: impl Fn(u32) -> (u64, u32),
    mut row: Vec<TexelSums>,
) -> Vec<TexelSums> {
    if job.cancelled() {
        return Vec::new();
    }
    // Progress counts each row once, in the first pass.
    let first_pass = row.is_empty();
    row.resize(atlas.size as usize, TexelSums::default());
    let mut row_rays: RayCount = 0;
    for (x, sums) in row.iter_mut().enumerate() {
        let (domain, samples) = plan(x as u32);
        trace_texel(job, atlas, x as u32, y, domain, samples, sums, &mut row_rays);
    }
    job.rays.fetch_add(row_rays, Ordering::Relaxed);
    job.progress.advance(u64::from(first_pass), row_rays);
    row
}

/// Adds `samples` stratified points over one texel, each with a stratified direction
/// (random numbers from `domain`), to its `sums`.
#[allow(clippy::too_many_arguments)]
fn trace_texel(
    job: &Job,
    atlas: &Atlas,
    x: u32,
    y: u32,
    domain: u64,
    samples: u32,
    sums: &mut TexelSums,
    rays: &mut RayCount,
) {
    let texel = (y * atlas.size + x) as usize;
    let ids = atlas.map.of(texel);
    // Checked per texel too: at many samples a row takes seconds.
    if ids.is_empty() || samples == 0 || job.cancelled() {
        return;
    }
    let index = atlas.layer as u64 * atlas.size as u64 * atlas.size as u64 + texel as u64;
    let mut rng = Rng::new(job.settings.seed, domain, index);
    let directions = ShuffledStrata::new(samples, &mut rng);
    for k in 0..samples {
        let (u, v) = stratum(k, samples, &mut rng);
        let q = Vec2::new(x as f32 + u, y as f32 + v);
        let (id, w, hit) = locate(atlas.triangles, ids, q);
        sums.covered += hit as u32;
        let (t, wt) = (&atlas.triangles[id as usize], &atlas.world[id as usize]);
        let p = wt.corners[0] * w[0] + wt.corners[1] * w[1] + wt.corners[2] * w[2];
        sums.position += p;
        // The texel's first sample names its chart and plane.
        sums.guide.get_or_insert(TexelGuide {
            position: p,
            normal: wt.normal,
            chart: t.chart,
            metres_per_texel: wt.metres_per_texel,
            reach: f32::INFINITY,
        });
        let shading =
            atlas.surfaces.at(t.instance as usize, t.primitive as usize, t.triangle as usize, w).shading_normal;
        let n = if shading.dot(wt.normal) > 0.0 { shading } else { wt.normal };
        let direction = directions.point(k, &mut rng);
        let sample = job.tracer.texel_sample(p, n, wt.normal, direction, &mut rng, rays);
        sums.direct += sample.direct;
        if k % 2 == 0 {
            sums.even += sample.path;
            sums.evens += 1;
        } else {
            sums.odd += sample.path;
            sums.odds += 1;
        }
        if let Some(t) = sample.first_hit {
            sums.inverse_distances += 1.0 / t.max(MIN_REACH);
            sums.hits += 1;
        }
        // The same supersampled points: the mask's edges are as soft as the texel, no
        // softer.
        for &(channel, _, slot) in job.channel_lights {
            sums.mask[channel] += job.tracer.mask_visibility(slot, p, wt.normal, rays);
        }
    }
}

/// Denoises one atlas's noisy light (when asked), adds it to the direct light, dilates
/// the texels (and mask) over the gutters and adds the atlas to `baked`.
fn finish_atlas(job: &Job, size: u32, texels: Vec<BakedTexel>, baked: &mut BakedAtlases) {
    let guides: Vec<Option<TexelGuide>> = texels.iter().map(|t| t.guide).collect();
    let traced: Vec<Halves> = texels.iter().map(|t| t.noisy).collect();
    let even_share = job.texel_samples.div_ceil(2) as f32 / job.texel_samples as f32;
    let light_of = |halves: &[Halves]| -> Vec<Vec3> {
        texels.iter().zip(halves).map(|(t, h)| t.direct + h.whole(even_share)).collect()
    };
    let traced_light = light_of(&traced);
    let traced_errors = standard_errors(size, &guides, &traced, even_share);
    baked.noise_traced.add(&guides, &traced_errors, &traced_light);
    let light = match job.denoise {
        Some(strength) => {
            let noisy = NoisyAtlas { size, guides: &guides, halves: &traced, even_share };
            let filtered = denoise(&noisy, strength);
            let light = light_of(&filtered);
            let errors = standard_errors(size, &guides, &filtered, even_share);
            baked.noise.add(&guides, &errors, &light);
            light
        }
        None => {
            baked.noise.add(&guides, &traced_errors, &traced_light);
            traced_light
        }
    };
    let mut texel_light: Vec<[f32; 4]> = light.iter().zip(&texels).map(|(l, t)| [l.x, l.y, l.z, t.coverage]).collect();
    let mut mask: Vec<[f32; 4]> = texels.iter().map(|t| t.mask).collect();
    let touched: Vec<bool> = guides.iter().map(Option::is_some).collect();
    baked.covered_texels += touched.iter().filter(|&&f| f).count() as u64;
    let mut filled = touched.clone();
    dilate(&mut texel_light, &mut filled, size, GUTTER_TEXELS);
    // Dilated texels cover nothing of the surface.
    for (t, &was) in texel_light.iter_mut().zip(&touched) {
        if !was {
            t[3] = 0.0;
        }
    }
    baked.lightmaps.push(Lightmap { width: size, height: size, texels: texel_light });
    if job.masks() {
        let mut filled = touched;
        dilate(&mut mask, &mut filled, size, GUTTER_TEXELS);
        baked.shadow_masks.push(ShadowMask { width: size, height: size, texels: mask });
    }
}

/// A placed triangle's world corners, front-face normal and world size of a texel.
struct WorldTriangle {
    corners: [Vec3; 3],
    normal: Vec3,
    metres_per_texel: f32,
}

impl WorldTriangle {
    fn of(scene: &Scene, t: &PlacedTriangle) -> WorldTriangle {
        let instance = &scene.instances[t.instance as usize];
        let p = &scene.meshes[instance.mesh].primitives[t.primitive as usize];
        let corners = [0, 1, 2].map(|k| {
            let i = p.indices[3 * t.triangle as usize + k] as usize;
            instance.world_from_local.transform_point3(p.positions[i])
        });
        let cross = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let c = &t.corners;
        let atlas_area = ((c[1] - c[0]).perp_dot(c[2] - c[0])).abs();
        // World area over atlas area is the square of a texel's world size.
        let metres_per_texel = if atlas_area > 0.0 { (cross.length() / atlas_area).sqrt() } else { 0.0 };
        WorldTriangle { corners, normal: cross.normalize_or_zero(), metres_per_texel }
    }
}

/// The triangle (of the texel's `ids`) under atlas point `q`, its weights there, and
/// whether `q` is really on it; otherwise the nearest point of the nearest one.
fn locate(triangles: &[PlacedTriangle], ids: &[u32], q: Vec2) -> (u32, [f32; 3], bool) {
    for &id in ids {
        if let Some(w) = barycentric(&triangles[id as usize].corners, q).filter(inside) {
            return (id, w, true);
        }
    }
    let mut best = (ids[0], [1.0, 0.0, 0.0], f32::INFINITY);
    for &id in ids {
        let c = &triangles[id as usize].corners;
        let w = clamp_to_triangle(c, q);
        let d = (c[0] * w[0] + c[1] * w[1] + c[2] * w[2]).distance_squared(q);
        if d < best.2 {
            best = (id, w, d);
        }
    }
    (best.0, nudged_inside(&triangles[best.0 as usize].corners, best.1), false)
}

/// Texels a clamped sample moves from the edge towards the triangle's centre. On the edge
/// itself the ray origin would lie in the plane of the surface across the edge (a wall
/// meeting a floor), and rays along it would slip out of a closed room.
const EDGE_NUDGE_TEXELS: f32 = 0.05;

fn nudged_inside(corners: &[Vec2; 3], w: [f32; 3]) -> [f32; 3] {
    let on_edge = corners[0] * w[0] + corners[1] * w[1] + corners[2] * w[2];
    let centre = (corners[0] + corners[1] + corners[2]) / 3.0;
    let towards = centre - on_edge;
    let step = towards.length().min(EDGE_NUDGE_TEXELS);
    let moved = on_edge + towards.normalize_or_zero() * step;
    barycentric(corners, moved).filter(inside).unwrap_or([1.0 / 3.0; 3])
}
