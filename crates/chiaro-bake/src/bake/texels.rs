//! The texel stage: every lightmap texel traced (irradiance, coverage and shadow mask,
//! supersampled over the texel), atlas by atlas and row by row in parallel; the noisy
//! part of the light denoised (direct light from baked lights is left sharp); then
//! dilated across the gutters. The laid-out atlases flow in; `BakedAtlases` flows out.

use super::{BakeError, BakedAtlases, DOMAIN_TEXEL, Job, stratum};
use crate::denoise::{Halves, NoiseEstimate, NoisyAtlas, TexelGuide, denoise, standard_errors};
use crate::layout::{AtlasLayout, GUTTER_TEXELS, PlacedTriangle};
use crate::raster::{TexelTriangles, barycentric, clamp_to_triangle, dilate, inside};
use crate::rng::Rng;
use crate::surface::Surfaces;
use crate::tracer::RayCount;
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
        let rows: Vec<Vec<BakedTexel>> = (0..size).into_par_iter().map(|y| bake_row(job, &atlas, y)).collect();
        if job.cancelled() {
            return Err(BakeError::Cancelled);
        }
        finish_atlas(job, size, rows.into_iter().flatten().collect(), &mut baked);
    }
    Ok(baked)
}

/// One row of texels; empty once the bake is cancelled.
fn bake_row(job: &Job, atlas: &Atlas, y: u32) -> Vec<BakedTexel> {
    if job.cancelled() {
        return Vec::new();
    }
    let mut row_rays: RayCount = 0;
    let row = (0..atlas.size).map(|x| bake_texel(job, atlas, x, y, &mut row_rays)).collect();
    job.rays.fetch_add(row_rays, Ordering::Relaxed);
    job.progress.advance(1, row_rays);
    row
}

/// One texel: `samples` stratified points over it, each with a stratified direction.
fn bake_texel(job: &Job, atlas: &Atlas, x: u32, y: u32, rays: &mut RayCount) -> BakedTexel {
    let texel = (y * atlas.size + x) as usize;
    let ids = atlas.map.of(texel);
    // Checked per texel too: at many samples a row takes seconds.
    if ids.is_empty() || job.cancelled() {
        return EMPTY_TEXEL;
    }
    let index = atlas.layer as u64 * atlas.size as u64 * atlas.size as u64 + texel as u64;
    let mut rng = Rng::new(job.settings.seed, DOMAIN_TEXEL, index);
    let shift = rng.next_u32();
    let (mut direct, mut noisy, mut covered, mut mask) = (Vec3::ZERO, Halves::default(), 0u32, [0.0f32; 4]);
    let mut guide: Option<TexelGuide> = None;
    let mut position_sum = Vec3::ZERO;
    let (mut inverse_distances, mut hits) = (0.0f32, 0u32);
    for k in 0..job.texel_samples {
        let (u, v) = stratum(k, job.texel_samples, 0, &mut rng);
        let q = Vec2::new(x as f32 + u, y as f32 + v);
        let (id, w, hit) = locate(atlas.triangles, ids, q);
        covered += hit as u32;
        let (t, wt) = (&atlas.triangles[id as usize], &atlas.world[id as usize]);
        let p = wt.corners[0] * w[0] + wt.corners[1] * w[1] + wt.corners[2] * w[2];
        position_sum += p;
        // The texel's first sample names its chart and plane.
        guide.get_or_insert(TexelGuide {
            position: p,
            normal: wt.normal,
            chart: t.chart,
            metres_per_texel: wt.metres_per_texel,
            reach: f32::INFINITY,
        });
        let shading =
            atlas.surfaces.at(t.instance as usize, t.primitive as usize, t.triangle as usize, w).shading_normal;
        let n = if shading.dot(wt.normal) > 0.0 { shading } else { wt.normal };
        let direction = stratum(k, job.texel_samples, shift, &mut rng);
        let sample = job.tracer.texel_sample(p, n, wt.normal, direction, &mut rng, rays);
        direct += sample.direct;
        if k % 2 == 0 {
            noisy.even += sample.path
        } else {
            noisy.odd += sample.path
        }
        if let Some(t) = sample.first_hit {
            inverse_distances += 1.0 / t.max(MIN_REACH);
            hits += 1;
        }
        // The same supersampled points: the mask's edges are as soft as the texel, no
        // softer.
        for &(channel, _, slot) in job.channel_lights {
            mask[channel] += job.tracer.mask_visibility(slot, p, wt.normal, rays);
        }
    }
    let (evens, odds) = (job.texel_samples.div_ceil(2), job.texel_samples / 2);
    noisy.even /= evens as f32;
    // One sample leaves no odd half: it repeats the even one (and the noise reads 0).
    noisy.odd = if odds > 0 { noisy.odd / odds as f32 } else { noisy.even };
    let mut texel_mask = [1.0f32; 4];
    for &(channel, _, _) in job.channel_lights {
        texel_mask[channel] = mask[channel] / job.texel_samples as f32;
    }
    if let Some(g) = guide.as_mut() {
        g.position = position_sum / job.texel_samples as f32;
        // The harmonic mean distance to the surfaces the paths met, as irradiance
        // caching measures it (infinite where every path escaped).
        g.reach = if hits > 0 { hits as f32 / inverse_distances } else { f32::INFINITY };
    }
    BakedTexel {
        direct: direct / job.texel_samples as f32,
        noisy,
        coverage: covered as f32 / job.texel_samples as f32,
        mask: texel_mask,
        guide,
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
