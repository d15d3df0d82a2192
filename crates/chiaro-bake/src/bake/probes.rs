//! The probe stage: the light probe grid placed over the scene's bounds, and every probe
//! traced in parallel (spherical harmonics of the light arriving there, and what it sees
//! of each shadow mask channel's light). The grid's origin and counts flow in; a
//! `ProbeGrid` flows out.

use super::{BakeError, DOMAIN_PROBE, Job, MAX_PROBES, stratum};
use crate::rng::Rng;
use crate::tracer::{Came, RayCount, Tracer};
use chiaro_math::sampling::sphere_direction;
use chiaro_math::sh::ShRgb;
use chiaro_scene::baked::ProbeGrid;
use chiaro_scene::{LightKind, Scene};
use glam::{UVec3, Vec3};
use rayon::prelude::*;
use std::f32::consts::PI;
use std::sync::atomic::Ordering;

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

/// Traces every probe of the grid at `origin` with `counts` probes per axis.
pub(super) fn bake_probes(job: &Job, origin: Vec3, counts: UVec3) -> Result<ProbeGrid, BakeError> {
    let total = counts.x * counts.y * counts.z;
    job.progress.stage("light probes", total as u64);
    let spacing = Vec3::splat(job.settings.probe_spacing);
    let traced: Vec<(ShRgb, [f32; 4])> = (0..total)
        .into_par_iter()
        .map(|index| {
            if job.cancelled() {
                return (ShRgb::default(), [1.0; 4]);
            }
            let (x, y, z) = (index % counts.x, (index / counts.x) % counts.y, index / (counts.x * counts.y));
            let p = origin + spacing * Vec3::new(x as f32, y as f32, z as f32);
            let mut probe_rays: RayCount = 0;
            let sh = trace_probe(job.tracer, p, job.settings.seed, job.probe_samples, index as u64, &mut probe_rays);
            let occlusion = probe_occlusion(job, p, &mut probe_rays);
            job.rays.fetch_add(probe_rays, Ordering::Relaxed);
            job.progress.advance(1, probe_rays);
            (sh, occlusion)
        })
        .collect();
    if job.cancelled() {
        return Err(BakeError::Cancelled);
    }
    let (probes, occlusion): (Vec<ShRgb>, Vec<[f32; 4]>) = traced.into_iter().unzip();
    let occlusion = if job.masks() { occlusion } else { Vec::new() };
    Ok(ProbeGrid { origin, spacing, counts, probes, occlusion })
}

/// Probe occlusion: what the probe at `p` itself sees of each channel's light.
fn probe_occlusion(job: &Job, p: Vec3, rays: &mut RayCount) -> [f32; 4] {
    let mut occlusion = [1.0f32; 4];
    for &(channel, light, slot) in job.channel_lights {
        let light = &job.scene.lights[light];
        let side = match light.kind {
            LightKind::Directional => -light.direction(),
            _ => (light.position() - p).normalize_or_zero(),
        };
        occlusion[channel] = job.tracer.mask_visibility(slot, p, side, rays);
    }
    occlusion
}

fn trace_probe(tracer: &Tracer, p: Vec3, seed: u64, samples: u32, index: u64, rays: &mut RayCount) -> ShRgb {
    let mut rng = Rng::new(seed, DOMAIN_PROBE, index);
    let mut sh = ShRgb::default();
    let weight = 4.0 * PI / samples as f32;
    for k in 0..samples {
        let (u, v) = stratum(k, samples, &mut rng);
        let d = sphere_direction(u, v);
        let (radiance, _) = tracer.incoming(p, d, Came::Unweighted, tracer.bounces(), &mut rng, rays);
        sh.add_sample(d, radiance, weight);
    }
    for (d, e) in tracer.probe_deltas(p, rays) {
        sh.add_delta(d, e);
    }
    sh
}
