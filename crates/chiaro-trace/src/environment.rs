//! The environment as a light for the reference: irradiance at a surface point from
//! stratified cosine-weighted rays (jittered by a SplitMix sequence from a seed), each that
//! leaves the scene bringing the environment's radiance from its direction, times the
//! transmittance of what it passed (dithered casters let part through). Against this the
//! baked environment light is judged.

use crate::area::unit_float;
use crate::bvh::SceneBvh;
use crate::reference::shadow_ray_origin;
use chiaro_math::sampling::cosine_direction;
use chiaro_scene::environment::EnvironmentLight;
use glam::Vec3;
use std::f32::consts::PI;

/// Irradiance (lux) at `position` on a surface facing `normal` from `light`, with
/// `strata` x `strata` rays.
pub fn environment_irradiance(
    bvh: &SceneBvh,
    light: &EnvironmentLight,
    position: Vec3,
    normal: Vec3,
    strata: u32,
    seed: u64,
) -> Vec3 {
    let origin = shadow_ray_origin(position, normal);
    let mut state = seed;
    let mut sum = Vec3::ZERO;
    for i in 0..strata * strata {
        let u = ((i % strata) as f32 + unit_float(&mut state)) / strata as f32;
        let v = ((i / strata) as f32 + unit_float(&mut state)) / strata as f32;
        // Cosine-weighted: the pdf cos / pi cancels the cosine, leaving pi / N per ray.
        let d = cosine_direction(normal, u, v);
        let through = bvh.transmittance(origin, d, f32::INFINITY);
        if through > 0.0 {
            sum += light.radiance(d) * through;
        }
    }
    sum * (PI / (strata * strata) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::Scene;
    use chiaro_scene::environment::EnvironmentMap;

    #[test]
    fn an_open_surface_under_a_uniform_sky_receives_pi_radiance() {
        let bvh = SceneBvh::build(&Scene::default());
        let light =
            EnvironmentLight { map: EnvironmentMap::uniform(Vec3::splat(2.0)), intensity: 1.5, rotation_deg: 0.0 };
        let e = environment_irradiance(&bvh, &light, Vec3::ZERO, Vec3::Y, 8, 1);
        assert!(e.abs_diff_eq(Vec3::splat(3.0 * PI), 1e-4), "{e}");
    }
}
