//! Baking a scene: lay out the lightmaps, trace every texel and every probe in parallel,
//! dilate the atlases. Deterministic for a seed: each texel and probe draws from its own
//! random stream.

use crate::channels::{ChannelAssignment, ChannelCandidate, assign_channels, spot_bounds};
use crate::layout::{AtlasLayout, GUTTER_TEXELS, PlacedTriangle, layout_scene};
use crate::raster::{TexelTriangles, barycentric, clamp_to_triangle, dilate, inside};
use crate::rng::Rng;
use crate::surface::Surfaces;
use crate::tracer::{RayCount, Tracer, sphere_direction};
use chiaro_math::sh::ShRgb;
use chiaro_scene::baked::{BakedLighting, Lightmap, ProbeGrid, ShadowMask};
use chiaro_scene::settings::BakeSettings;
use chiaro_scene::{LightKind, LightMode, Scene, Settings};
use chiaro_trace::SceneBvh;
use glam::{UVec3, Vec2, Vec3};
use rayon::prelude::*;
use std::f32::consts::PI;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

/// Most probes a bake makes.
pub const MAX_PROBES: u64 = 262_144;

/// Random stream domains, so texels and probes never share a stream.
const DOMAIN_TEXEL: u64 = 1;
const DOMAIN_PROBE: u64 = 2;

/// Where a long bake reports how far it got.
pub trait Progress: Sync {
    /// A stage of `total` work units begins.
    fn stage(&self, name: &str, total: u64);
    fn advance(&self, units: u64);
}

/// Reports nothing.
pub struct Silent;

impl Progress for Silent {
    fn stage(&self, _: &str, _: u64) {}
    fn advance(&self, _: u64) {}
}

#[derive(Debug, thiserror::Error)]
pub enum BakeError {
    #[error("interrupted; nothing was written")]
    Cancelled,
    #[error("{0}")]
    Invalid(String),
    #[error("{path}: {message}")]
    Io { path: std::path::PathBuf, message: String },
}

#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BakeStats {
    pub seconds: f64,
    pub rays: u64,
    pub rays_per_second: f64,
    /// Texels some surface covers (before dilation), over all atlases.
    pub texels: u64,
    pub probes: u64,
}

pub struct BakeResult {
    pub layout: AtlasLayout,
    pub lighting: BakedLighting,
    pub stats: BakeStats,
}

/// The probe grid's placement over `scene`'s bounds: centred, `spacing` apart.
pub fn probe_layout(scene: &Scene, spacing: f32) -> Result<Option<(Vec3, UVec3)>, BakeError> {
    let bounds = scene.bounds();
    if !(bounds.min.is_finite() && bounds.max.is_finite()) {
        return Ok(None);
    }
    let extent = (bounds.max - bounds.min).max(Vec3::ZERO);
    // In f64 so that a huge scene cannot overflow the count before it is checked.
    let per_axis = extent.as_dvec3() / spacing as f64;
    let counts_f = per_axis.floor() + 1.0;
    let total = counts_f.x * counts_f.y * counts_f.z;
    // NaN (an infinite extent) fails too.
    if total.is_nan() || total > MAX_PROBES as f64 {
        return Err(BakeError::Invalid(format!(
            "bake.probe_spacing: {spacing} m gives {} x {} x {} = {total:.0} probes over the scene's bounds, more \
             than {MAX_PROBES}; use a wider spacing",
            counts_f.x, counts_f.y, counts_f.z
        )));
    }
    let counts = counts_f.as_uvec3();
    let used = (counts - 1).as_vec3() * spacing;
    Ok(Some((bounds.min + (extent - used) * 0.5, counts)))
}

/// The `k`th of `n` stratified points of the unit square, jittered, in an order scrambled
/// by `shift` so that positions and directions are not correlated.
fn stratum(k: u32, n: u32, shift: u32, rng: &mut Rng) -> (f32, f32) {
    let m = (n as f32).sqrt().ceil().max(1.0) as u32;
    let cells = m * m;
    // 7919 is prime and larger than any m, so stepping by it visits every cell once.
    let cell = (k as u64 * 7919 + shift as u64) % cells as u64;
    let (i, j) = ((cell % m as u64) as f32, (cell / m as u64) as f32);
    ((i + rng.next_f32()) / m as f32, (j + rng.next_f32()) / m as f32)
}

pub fn bake(
    scene: &Scene,
    settings: &Settings,
    progress: &dyn Progress,
    cancel: &AtomicBool,
) -> Result<BakeResult, BakeError> {
    let start = Instant::now();
    let b = &settings.bake;
    settings.validate().map_err(BakeError::Invalid)?;
    let probe_grid = probe_layout(scene, b.probe_spacing)?;
    let layout = layout_scene(scene, b.texels_per_metre);
    if layout.atlas_count as usize > crate::bake_dir::MAX_ATLASES {
        return Err(BakeError::Invalid(format!(
            "bake.texels_per_metre: {} gives {} lightmap atlases of {} texels, more than the {} a texture array \
             holds; use fewer texels per metre",
            b.texels_per_metre,
            layout.atlas_count,
            layout.size,
            crate::bake_dir::MAX_ATLASES
        )));
    }
    // Baked light and shadows come from static objects alone: dynamic ones move, and
    // take their light from the probes and their shadows from the realtime maps.
    let bvh = SceneBvh::build_with(scene, |instance| instance.is_static);
    let assignment = if settings.lighting.mixed_mode.uses_shadow_mask() {
        mask_channels(scene, settings)
    } else {
        ChannelAssignment::default()
    };
    let mut modes: Vec<LightMode> = scene.lights.iter().map(|l| l.mode).collect();
    for &light in &assignment.demoted {
        modes[light] = LightMode::Baked;
        tracing::warn!(
            "light '{}': a fifth mixed light overlapping four others, no shadow mask channel left: baked instead",
            scene.lights[light].name
        );
    }
    let tracer = Tracer::new(
        scene,
        &modes,
        &bvh,
        Vec3::from(settings.render.ambient),
        b.bounces,
        settings.lights.range_threshold_lux,
    );
    // Each channel's (channel, scene light, tracer slot): mixed lights are all traced.
    let channel_lights: Vec<(usize, usize, usize)> = assignment
        .channels
        .iter()
        .filter_map(|&(light, channel)| Some((channel as usize, light, tracer.light_slot(light)?)))
        .collect();
    let masks = !channel_lights.is_empty();
    let surfaces = Surfaces::new(scene);
    let rays = AtomicU64::new(0);
    let texel_count = AtomicU64::new(0);

    let size = layout.size;
    progress.stage("lightmap rows", layout.atlas_count as u64 * size as u64);
    let mut lightmaps = Vec::new();
    let mut shadow_masks = Vec::new();
    for layer in 0..layout.atlas_count {
        let triangles: Vec<PlacedTriangle> = layout.triangles_of(layer).copied().collect();
        let world: Vec<WorldTriangle> = triangles.iter().map(|t| WorldTriangle::of(scene, t)).collect();
        let map = TexelTriangles::build(size, &triangles);
        let rows: Vec<Vec<BakedTexel>> = (0..size)
            .into_par_iter()
            .map(|y| {
                if cancel.load(Ordering::Relaxed) {
                    return Vec::new();
                }
                let mut row_rays: RayCount = 0;
                let row = (0..size)
                    .map(|x| {
                        let texel = (y * size + x) as usize;
                        let ids = map.of(texel);
                        // Checked per texel too: at many samples a row takes seconds.
                        if ids.is_empty() || cancel.load(Ordering::Relaxed) {
                            return ([0.0; 4], [1.0; 4], false);
                        }
                        let index = layer as u64 * size as u64 * size as u64 + texel as u64;
                        let mut rng = Rng::new(b.seed, DOMAIN_TEXEL, index);
                        let shift = rng.next_u32();
                        let (mut sum, mut covered, mut mask) = (Vec3::ZERO, 0u32, [0.0f32; 4]);
                        for k in 0..b.samples {
                            let (u, v) = stratum(k, b.samples, 0, &mut rng);
                            let q = Vec2::new(x as f32 + u, y as f32 + v);
                            let (id, w, hit) = locate(&triangles, ids, q);
                            covered += hit as u32;
                            let (t, wt) = (&triangles[id as usize], &world[id as usize]);
                            let p = wt.corners[0] * w[0] + wt.corners[1] * w[1] + wt.corners[2] * w[2];
                            let shading = surfaces
                                .at(t.instance as usize, t.primitive as usize, t.triangle as usize, w)
                                .shading_normal;
                            let n = if shading.dot(wt.normal) > 0.0 { shading } else { wt.normal };
                            let direction = stratum(k, b.samples, shift, &mut rng);
                            sum += tracer.texel_sample(p, n, wt.normal, direction, &mut rng, &mut row_rays);
                            if masks {
                                // The same supersampled points: the mask's edges are as
                                // soft as the texel, no softer.
                                for &(channel, _, slot) in &channel_lights {
                                    mask[channel] += tracer.mask_visibility(slot, p, wt.normal, &mut row_rays);
                                }
                            }
                        }
                        let e = sum / b.samples as f32;
                        let mut texel_mask = [1.0f32; 4];
                        for &(channel, _, _) in &channel_lights {
                            texel_mask[channel] = mask[channel] / b.samples as f32;
                        }
                        ([e.x, e.y, e.z, covered as f32 / b.samples as f32], texel_mask, true)
                    })
                    .collect();
                rays.fetch_add(row_rays, Ordering::Relaxed);
                progress.advance(1);
                row
            })
            .collect();
        if cancel.load(Ordering::Relaxed) {
            return Err(BakeError::Cancelled);
        }
        let texel_rows: Vec<BakedTexel> = rows.into_iter().flatten().collect();
        let mut texels: Vec<[f32; 4]> = texel_rows.iter().map(|r| r.0).collect();
        let mut mask: Vec<[f32; 4]> = texel_rows.iter().map(|r| r.1).collect();
        let baked: Vec<bool> = texel_rows.iter().map(|r| r.2).collect();
        texel_count.fetch_add(baked.iter().filter(|&&f| f).count() as u64, Ordering::Relaxed);
        let mut filled = baked.clone();
        dilate(&mut texels, &mut filled, size, GUTTER_TEXELS);
        // Dilated texels cover nothing of the surface.
        for (t, &was) in texels.iter_mut().zip(&baked) {
            if !was {
                t[3] = 0.0;
            }
        }
        lightmaps.push(Lightmap { width: size, height: size, texels });
        if masks {
            let mut filled = baked;
            dilate(&mut mask, &mut filled, size, GUTTER_TEXELS);
            shadow_masks.push(ShadowMask { width: size, height: size, texels: mask });
        }
    }

    let probes = match probe_grid {
        Some((origin, counts)) => {
            let total = counts.x * counts.y * counts.z;
            progress.stage("light probes", total as u64);
            let spacing = Vec3::splat(b.probe_spacing);
            let traced: Vec<(ShRgb, [f32; 4])> = (0..total)
                .into_par_iter()
                .map(|index| {
                    if cancel.load(Ordering::Relaxed) {
                        return (ShRgb::default(), [1.0; 4]);
                    }
                    let (x, y, z) = (index % counts.x, (index / counts.x) % counts.y, index / (counts.x * counts.y));
                    let p = origin + spacing * Vec3::new(x as f32, y as f32, z as f32);
                    let mut probe_rays: RayCount = 0;
                    let sh = trace_probe(&tracer, p, b, index as u64, &mut probe_rays);
                    // Probe occlusion: what the probe itself sees of each channel's light.
                    let mut occlusion = [1.0f32; 4];
                    for &(channel, light, slot) in &channel_lights {
                        let light = &scene.lights[light];
                        let side = match light.kind {
                            LightKind::Directional => -light.direction(),
                            _ => (light.position() - p).normalize_or_zero(),
                        };
                        occlusion[channel] = tracer.mask_visibility(slot, p, side, &mut probe_rays);
                    }
                    rays.fetch_add(probe_rays, Ordering::Relaxed);
                    progress.advance(1);
                    (sh, occlusion)
                })
                .collect();
            if cancel.load(Ordering::Relaxed) {
                return Err(BakeError::Cancelled);
            }
            let (probes, occlusion): (Vec<ShRgb>, Vec<[f32; 4]>) = traced.into_iter().unzip();
            let occlusion = if masks { occlusion } else { Vec::new() };
            Some(ProbeGrid { origin, spacing, counts, probes, occlusion })
        }
        None => None,
    };

    let seconds = start.elapsed().as_secs_f64();
    let rays = rays.load(Ordering::Relaxed);
    let stats = BakeStats {
        seconds,
        rays,
        rays_per_second: rays as f64 / seconds.max(1e-9),
        texels: texel_count.load(Ordering::Relaxed),
        probes: probes.as_ref().map_or(0, |p| p.probes.len() as u64),
    };
    let mut light_channels = vec![None; scene.lights.len()];
    for &(light, channel) in &assignment.channels {
        light_channels[light] = Some(channel);
    }
    let lighting =
        BakedLighting { lightmaps, probes, shadow_masks, light_channels, demoted: assignment.demoted.clone() };
    Ok(BakeResult { layout, lighting, stats })
}

/// Shadow mask channels for the scene's shadowed mixed lights.
fn mask_channels(scene: &Scene, settings: &Settings) -> ChannelAssignment {
    let candidates: Vec<ChannelCandidate> = scene
        .lights
        .iter()
        .enumerate()
        .filter(|(_, l)| l.mode == LightMode::Mixed && l.shadow.casts())
        .map(|(light, l)| {
            let range = l.shaded_range(settings.lights.range_threshold_lux);
            ChannelCandidate {
                light,
                importance: l.intensity * l.color.max_element(),
                bounds: match l.kind {
                    LightKind::Directional => None,
                    LightKind::Point => Some((l.position(), range)),
                    LightKind::Spot { outer_cone_rad, .. } => {
                        Some(spot_bounds(l.position(), l.direction(), range, outer_cone_rad))
                    }
                },
            }
        })
        .collect();
    assign_channels(&candidates)
}

fn trace_probe(tracer: &Tracer, p: Vec3, b: &BakeSettings, index: u64, rays: &mut RayCount) -> ShRgb {
    let mut rng = Rng::new(b.seed, DOMAIN_PROBE, index);
    let mut sh = ShRgb::default();
    let weight = 4.0 * PI / b.probe_samples as f32;
    for k in 0..b.probe_samples {
        let (u, v) = stratum(k, b.probe_samples, 0, &mut rng);
        let d = sphere_direction(u, v);
        let radiance = tracer.incoming(p, d, tracer.bounces(), &mut rng, rays);
        sh.add_sample(d, radiance, weight);
    }
    for (d, e) in tracer.probe_deltas(p, rays) {
        sh.add_delta(d, e);
    }
    sh
}

/// One texel's irradiance (RGB, coverage in A), its shadow mask, and whether a surface
/// touches it (the rest are left for dilation).
type BakedTexel = ([f32; 4], [f32; 4], bool);

/// A placed triangle's world corners and front-face normal.
struct WorldTriangle {
    corners: [Vec3; 3],
    normal: Vec3,
}

impl WorldTriangle {
    fn of(scene: &Scene, t: &PlacedTriangle) -> WorldTriangle {
        let instance = &scene.instances[t.instance as usize];
        let p = &scene.meshes[instance.mesh].primitives[t.primitive as usize];
        let corners = [0, 1, 2].map(|k| {
            let i = p.indices[3 * t.triangle as usize + k] as usize;
            instance.world_from_local.transform_point3(p.positions[i])
        });
        let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalize_or_zero();
        WorldTriangle { corners, normal }
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
