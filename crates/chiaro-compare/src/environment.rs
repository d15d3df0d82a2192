//! The environment judged as a light: where `[environment] mode = "baked"`, the baked
//! irradiance each pixel's surface reads (its lightmap or the probes) against the
//! irradiance chiaro-trace's reference gathers from the same environment at that surface,
//! shadowed by the scene. Realtime environment light has no shadows to judge, and a bake
//! that also holds baked or mixed lights is not the environment alone; both are reported
//! as not compared, with the reason.

use chiaro_scene::environment::EnvironmentLight;
use chiaro_scene::settings::EnvironmentMode;
use chiaro_scene::{LightMode, Scene, Settings};
use chiaro_trace::{SceneBvh, environment_irradiance};
use glam::Vec3;
use rayon::prelude::*;

/// Rays per judged pixel: `STRATA` x `STRATA` stratified cosine directions.
pub const STRATA: u32 = 16;
/// Every `PIXEL_STEP`-th covered pixel is judged (the reference costs 256 rays a pixel).
const PIXEL_STEP: usize = 3;
/// Pixels whose traced irradiance is below this share of the brightest are left out
/// (a ratio of two small numbers says little).
const DARK_SHARE: f32 = 0.02;

/// How the baked environment light compares with the traced one.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvironmentReport {
    /// Judged: baked / traced irradiance (luminance) over `pixels` pixels.
    Compared { pixels: usize, median: f32, p10: f32, p90: f32 },
    /// Not judged, and why.
    NotCompared(&'static str),
}

/// What a comparison needs of each pixel: its surface's position and normal, and the
/// baked irradiance it read.
pub struct EnvironmentPixels<'a> {
    pub positions: &'a [Option<Vec3>],
    pub normals: &'a [Vec3],
    pub baked_irradiance: &'a [[f32; 3]],
}

/// Judges the baked environment light of `pixels`, or says why it is not judged; `None`
/// where the settings name no environment.
pub fn compare_environment(
    scene: &Scene,
    settings: &Settings,
    pixels: &EnvironmentPixels<'_>,
) -> Option<EnvironmentReport> {
    let env = &settings.environment;
    if !env.enabled_for(scene) {
        return None;
    }
    if env.mode == EnvironmentMode::Realtime {
        return Some(EnvironmentReport::NotCompared(
            "realtime: image-based light is unshadowed, nothing to judge (mode = \"baked\" shadows it)",
        ));
    }
    if scene.baked.is_none() {
        return Some(EnvironmentReport::NotCompared("no bake applied: bake the scene with mode = \"baked\""));
    }
    if scene.lights.iter().any(|l| l.mode != LightMode::Realtime) {
        return Some(EnvironmentReport::NotCompared(
            "the bake also holds baked or mixed lights: not the environment alone",
        ));
    }
    let Ok(Some(light)) = EnvironmentLight::from_settings(env, scene) else {
        return Some(EnvironmentReport::NotCompared("the environment could not be read"));
    };
    let bvh = SceneBvh::build(scene);
    let luminance = chiaro_math::tonemap::luminance;
    let judged: Vec<(f32, f32)> = (0..pixels.positions.len())
        .into_par_iter()
        .step_by(PIXEL_STEP)
        .filter_map(|i| {
            let p = pixels.positions[i]?;
            let baked = luminance(Vec3::from(pixels.baked_irradiance[i]));
            (baked > 0.0).then_some(())?;
            let traced = luminance(environment_irradiance(&bvh, &light, p, pixels.normals[i], STRATA, i as u64));
            Some((baked, traced))
        })
        .collect();
    let brightest = judged.iter().map(|j| j.1).fold(0.0, f32::max);
    let mut ratios: Vec<f32> =
        judged.iter().filter(|j| j.1 > DARK_SHARE * brightest).map(|(baked, traced)| baked / traced).collect();
    if ratios.is_empty() {
        return Some(EnvironmentReport::NotCompared("no pixel reads a bake"));
    }
    ratios.sort_by(f32::total_cmp);
    let at = |q: f32| ratios[((ratios.len() - 1) as f32 * q).round() as usize];
    Some(EnvironmentReport::Compared { pixels: ratios.len(), median: at(0.5), p10: at(0.1), p90: at(0.9) })
}
