//! Baking a scene, in named stages: `lay_out` (validate, place the probe grid and the
//! lightmap charts), `bake_texels` (trace every lightmap texel and its shadow mask, then
//! dilate the atlases), `bake_probes` (trace every light probe and its occlusion) and
//! `assemble` (the `BakedLighting` and the statistics). A `Scene` and `Settings` flow in,
//! a `BakeResult` flows out. Deterministic for a seed: each texel and probe draws from its
//! own random stream.

mod lights;
mod probes;
mod texels;

pub use probes::probe_layout;

use crate::channels::ChannelAssignment;
use crate::denoise::{NoiseEstimate, Strength, strength_for};
use crate::layout::{AtlasLayout, layout_scene};
use crate::rng::Rng;
use crate::tracer::{Sky, Tracer, bakes_instance};
use chiaro_scene::baked::{BakedLighting, Lightmap, ProbeGrid, ShadowMask};
use chiaro_scene::settings::BakeSettings;
use chiaro_scene::{Scene, Settings};
use chiaro_trace::SceneBvh;
use glam::{UVec3, Vec3};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

/// Most probes a bake makes.
pub const MAX_PROBES: u64 = 262_144;

/// Random stream domains, so texels and probes never share a stream.
const DOMAIN_TEXEL: u64 = 1;
const DOMAIN_PROBE: u64 = 2;
/// The samples a texel takes beyond the first pass's (`texels::more_samples`).
const DOMAIN_TEXEL_MORE: u64 = 3;

/// Where a long bake reports how far it got.
pub trait Progress: Sync {
    /// A stage of `total` work units begins.
    fn stage(&self, name: &str, total: u64);
    /// `units` more of the current stage's work units are done, having traced `rays` rays.
    fn advance(&self, units: u64, rays: u64);
}

/// Reports nothing.
pub struct Silent;

impl Progress for Silent {
    fn stage(&self, _: &str, _: u64) {}
    fn advance(&self, _: u64, _: u64) {}
}

/// Why a bake produced nothing.
#[derive(Debug, thiserror::Error)]
pub enum BakeError {
    /// The cancel flag was set.
    #[error("interrupted; nothing was written")]
    Cancelled,
    /// The settings do not fit the scene; the message names the setting.
    #[error("{0}")]
    Invalid(String),
}

/// How long a bake took and how much it traced.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BakeStats {
    pub seconds: f64,
    pub rays: u64,
    pub rays_per_second: f64,
    /// Texels some surface covers (before dilation), over all atlases.
    pub texels: u64,
    pub probes: u64,
    /// The lightmaps' estimated noise as traced: the median relative standard error of
    /// the lit texels (from each texel's two independent half estimates). It measures
    /// noise, not bias: after denoising it leaves out what the filter blurred.
    #[serde(default)]
    pub noise_traced: f32,
    /// The same after denoising (equal to `noise_traced` when not denoised).
    #[serde(default)]
    pub noise: f32,
}

/// A finished bake: the lightmap layout it was traced for, the baked lighting, its cost.
pub struct BakeResult {
    pub layout: AtlasLayout,
    pub lighting: BakedLighting,
    pub stats: BakeStats,
}

/// What the texel and probe stages share: the scene, the bake settings, the tracer, the
/// lights whose shadow masks are baked, and the counters and flags of the whole bake.
struct Job<'a, 't> {
    scene: &'a Scene,
    settings: &'a BakeSettings,
    tracer: &'a Tracer<'t>,
    /// Each shadow mask channel's (channel, scene light, tracer slot).
    channel_lights: &'a [(usize, usize, usize)],
    progress: &'a dyn Progress,
    cancel: &'a AtomicBool,
    rays: AtomicU64,
    /// Paths per texel and directions per probe, as the quality or the keys give them.
    texel_samples: u32,
    probe_samples: u32,
    /// How the texels' noisy light is filtered; `None` leaves it as traced.
    denoise: Option<Strength>,
}

impl Job<'_, '_> {
    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// Whether shadow masks are baked at all.
    fn masks(&self) -> bool {
        !self.channel_lights.is_empty()
    }
}

/// Bakes `scene`'s lightmaps, shadow masks and light probes with `settings`, reporting to
/// `progress`; returns `BakeError::Cancelled` soon after `cancel` is set.
pub fn bake(
    scene: &Scene,
    settings: &Settings,
    progress: &dyn Progress,
    cancel: &AtomicBool,
) -> Result<BakeResult, BakeError> {
    let start = Instant::now();
    let (layout, probe_grid) = lay_out(scene, settings)?;
    // Baked light and shadows come from static objects alone: dynamic ones move, and
    // take their light from the probes and their shadows from the realtime maps.
    let bvh = SceneBvh::build_with(scene, bakes_instance);
    let assignment = lights::shadow_mask_channels(scene, settings);
    let modes = lights::bake_modes(scene, &assignment);
    let sky = Sky::for_bake(settings, scene).map_err(|e| BakeError::Invalid(e.to_string()))?;
    let tracer = Tracer::new(scene, &modes, &bvh, sky, settings.bake.bounces, settings.lights.range_threshold_lux);
    let channel_lights = lights::channel_lights(&assignment, &tracer);
    let job = Job {
        scene,
        settings: &settings.bake,
        tracer: &tracer,
        channel_lights: &channel_lights,
        progress,
        cancel,
        rays: AtomicU64::new(0),
        texel_samples: settings.bake.texel_samples(),
        probe_samples: settings.bake.probe_samples(),
        denoise: settings.bake.denoise.then(|| strength_for(settings.bake.quality)),
    };
    let atlases = texels::bake_texels(&job, &layout)?;
    let probes = match probe_grid {
        Some((origin, counts)) => Some(probes::bake_probes(&job, origin, counts)?),
        None => None,
    };
    let rays = job.rays.load(Ordering::Relaxed);
    Ok(assemble(scene, layout, atlases, probes, &assignment, rays, start))
}

/// The layout stage: validates the settings, places the probe grid over the scene's
/// bounds and lays the lightmap charts out in atlases, refusing more atlases than a
/// texture array holds.
fn lay_out(scene: &Scene, settings: &Settings) -> Result<(AtlasLayout, Option<(Vec3, UVec3)>), BakeError> {
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
    Ok((layout, probe_grid))
}

/// The texel stage's output: per atlas its lightmap, its shadow mask (when masks are
/// baked) and the texels a surface covers.
struct BakedAtlases {
    lightmaps: Vec<Lightmap>,
    shadow_masks: Vec<ShadowMask>,
    covered_texels: u64,
    /// The texels' estimated error as traced, and after denoising.
    noise_traced: NoiseEstimate,
    noise: NoiseEstimate,
}

/// The assemble stage: the baked lighting with each light's mask channel, and the
/// bake's statistics.
fn assemble(
    scene: &Scene,
    layout: AtlasLayout,
    atlases: BakedAtlases,
    probes: Option<ProbeGrid>,
    assignment: &ChannelAssignment,
    rays: u64,
    start: Instant,
) -> BakeResult {
    let seconds = start.elapsed().as_secs_f64();
    let stats = BakeStats {
        seconds,
        rays,
        rays_per_second: rays as f64 / seconds.max(1e-9),
        texels: atlases.covered_texels,
        probes: probes.as_ref().map_or(0, |p| p.probes.len() as u64),
        noise_traced: atlases.noise_traced.median_relative(),
        noise: atlases.noise.median_relative(),
    };
    let mut light_channels = vec![None; scene.lights.len()];
    for &(light, channel) in &assignment.channels {
        light_channels[light] = Some(channel);
    }
    let lighting = BakedLighting {
        lightmaps: atlases.lightmaps,
        probes,
        shadow_masks: atlases.shadow_masks,
        light_channels,
        demoted: assignment.demoted.clone(),
    };
    BakeResult { layout, lighting, stats }
}

/// The `k`th of `n` stratified points of the unit square, jittered.
fn stratum(k: u32, n: u32, rng: &mut Rng) -> (f32, f32) {
    let m = grid_side(n);
    // 7919 is prime and larger than any m, so stepping by it visits every cell once.
    cell_point((k as u64 * 7919 % (m * m) as u64) as u32, m, rng)
}

fn grid_side(n: u32) -> u32 {
    (n as f32).sqrt().ceil().max(1.0) as u32
}

/// A jittered point of cell `cell` of an `m` x `m` grid over the unit square.
fn cell_point(cell: u32, m: u32, rng: &mut Rng) -> (f32, f32) {
    let (i, j) = ((cell % m) as f32, (cell / m) as f32);
    ((i + rng.next_f32()) / m as f32, (j + rng.next_f32()) / m as f32)
}

/// `n` stratified points of the unit square in a shuffled order: paired with `stratum`'s
/// points sample by sample, they stratify both and correlate neither. (A fixed pairing,
/// such as a shifted order, would give the positions in one part of a texel the
/// directions of one part of the hemisphere: a texel half under a box then misses a band
/// of directions, a bias no sample count removes.)
struct ShuffledStrata {
    side: u32,
    order: Vec<u32>,
}

impl ShuffledStrata {
    fn new(n: u32, rng: &mut Rng) -> ShuffledStrata {
        let side = grid_side(n);
        let mut order: Vec<u32> = (0..side * side).collect();
        // Fisher-Yates.
        for i in (1..order.len()).rev() {
            let j = ((rng.next_u32() as u64 * (i as u64 + 1)) >> 32) as usize;
            order.swap(i, j);
        }
        ShuffledStrata { side, order }
    }

    /// The `k`th point (`k` below the `n` it was made for).
    fn point(&self, k: u32, rng: &mut Rng) -> (f32, f32) {
        cell_point(self.order[k as usize], self.side, rng)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shuffled_strata_cover_every_cell_once_in_no_fixed_pairing() {
        let mut rng = Rng::new(1, DOMAIN_TEXEL, 7);
        let strata = ShuffledStrata::new(64, &mut rng);
        let mut cells: Vec<u32> = (0..64).map(|k| strata.order[k]).collect();
        cells.sort_unstable();
        assert_eq!(cells, (0..64).collect::<Vec<u32>>());
        // Positions in the left half of the square (stratum's order) meet directions
        // from both halves, about evenly.
        let left_with_left = (0..64)
            .filter(|&k| {
                let mut r = Rng::new(0, 0, 0);
                let (x, _) = stratum(k, 64, &mut r);
                x < 0.5 && strata.point(k, &mut r).0 < 0.5
            })
            .count();
        assert!((8..=24).contains(&left_with_left), "{left_with_left} of 32");
    }
}
