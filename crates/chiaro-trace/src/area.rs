//! The visibility of a light with a size, for contact-hardening (`pcss`) shadows: the
//! share of the light's disc a surface sees. A point or spot light of radius R is a disc
//! of radius R facing the surface (the sphere's outline, as the renderer's PCSS assumes);
//! a directional light is the cone of half its angular diameter. The disc is sampled on a
//! jittered AREA_SAMPLES_SIDE x AREA_SAMPLES_SIDE grid mapped to the disc (equal areas),
//! jittered by a hash of the pixel and the light, so the reference is the same on every
//! run.

use crate::bvh::SceneBvh;
use crate::reference::shadow_ray_origin;
use chiaro_math::sampling::multi_jittered;
use chiaro_scene::{Light, LightKind};
use glam::{Vec2, Vec3};

/// Strata per side: 64 shadow rays a pixel and light. Their visibility's standard error
/// on a straight penumbra is below 0.01 (stratified: about 1 / (side^1.5)).
pub const AREA_SAMPLES_SIDE: u32 = 8;

/// Point and spot shadow rays stop this fraction short of their point on the disc.
const LIGHT_END_MARGIN: f32 = 1.0e-4;

/// The share of `light`'s disc seen from just off the surface at `position`, `seed`
/// choosing the jitter (one per pixel and light).
pub fn area_light_visibility(bvh: &SceneBvh, light: &Light, position: Vec3, facing_normal: Vec3, seed: u64) -> f32 {
    let origin = shadow_ray_origin(position, facing_normal);
    let n = AREA_SAMPLES_SIDE;
    let mut state = seed;
    let mut sum = 0.0;
    for j in 0..n {
        for i in 0..n {
            let cell = Vec2::new(i as f32, j as f32);
            let jitter = Vec2::new(unit_float(&mut state), unit_float(&mut state));
            let disc = uniform_disc((cell + jitter) / n as f32);
            sum += match light.kind {
                LightKind::Directional => {
                    let axis = -light.direction().normalize();
                    let tan_half = (light.shadow.angular_diameter_deg.to_radians() * 0.5).tan();
                    let (e1, e2) = axis.any_orthonormal_pair();
                    let direction = (axis + (e1 * disc.x + e2 * disc.y) * tan_half).normalize();
                    bvh.transmittance(origin, direction, f32::INFINITY)
                }
                // Area lights are sampled over their own shape (`area_shape_visibility`);
                // here, as a disc like a point light's.
                LightKind::Point | LightKind::Spot { .. } | LightKind::Rect { .. } | LightKind::Disk { .. } => {
                    let to_centre = light.position() - origin;
                    let Some(axis) = to_centre.try_normalize() else {
                        sum += 1.0;
                        continue;
                    };
                    let (e1, e2) = axis.any_orthonormal_pair();
                    let target = light.position() + (e1 * disc.x + e2 * disc.y) * light.shadow.light_radius;
                    let to_target = target - origin;
                    let distance = to_target.length();
                    bvh.transmittance(origin, to_target / distance, distance * (1.0 - LIGHT_END_MARGIN))
                }
            };
        }
    }
    sum / (n * n) as f32
}

/// Shadow rays a pixel sends to a rect or disk light: AREA_LIGHT_SIDE^2, multi-jittered
/// over its shape (`sampling::multi_jittered`).
pub const AREA_LIGHT_SAMPLES: u32 = (AREA_LIGHT_SIDE * AREA_LIGHT_SIDE) as u32;

/// See `AREA_LIGHT_SAMPLES`. 8: 64 strata across a shadow edge along either of the light's
/// sides (a penumbra's visibility then has a standard error under 0.01, whichever side
/// makes it: a 1 x 0.1 m strip's 5 cm penumbra gets as many as its 0.5 m one), and 8 at
/// least at any other angle.
const AREA_LIGHT_SIDE: usize = 8;

/// The visible share of a rect or disk light's light at a surface: shadow rays to
/// multi-jittered points of its shape, each weighted by what that point gives the
/// surface (cos at the surface times cos at the light over the distance squared), so that
/// the share times the exact unshadowed irradiance (`area_light::projected_solid_angle`)
/// is the shadowed irradiance. Where no point of the light lights the surface (it faces
/// away, or lies behind the light), the plain share of rays that get through. `seed`
/// chooses the jitter; 1 for lights of other kinds.
pub fn area_shape_visibility(bvh: &SceneBvh, light: &Light, position: Vec3, facing_normal: Vec3, seed: u64) -> f32 {
    let Some(shape) = light.kind.area_shape() else {
        return 1.0;
    };
    let origin = shadow_ray_origin(position, facing_normal);
    let (axis_x, axis_y) = (light.world_from_light.x_axis.truncate(), light.world_from_light.y_axis.truncate());
    let emits_along = light.direction();
    let mut state = seed;
    let points = multi_jittered(AREA_LIGHT_SIDE, &mut || unit_float(&mut state));
    let (mut weighted, mut weights, mut plain) = (0.0f32, 0.0f32, 0.0f32);
    for u in &points {
        let local = shape.point(*u);
        let target = light.position() + axis_x * local.x + axis_y * local.y;
        let to_target = target - origin;
        let distance = to_target.length();
        if distance <= 0.0 {
            continue;
        }
        let l = to_target / distance;
        let weight = facing_normal.dot(l).max(0.0) * emits_along.dot(-l).max(0.0) / (distance * distance);
        let seen = bvh.transmittance(origin, l, distance * (1.0 - LIGHT_END_MARGIN));
        weighted += weight * seen;
        weights += weight;
        plain += seen;
    }
    if weights > 0.0 { weighted / weights } else { plain / points.len() as f32 }
}

/// A point of the unit disc from a point of the unit square, keeping areas (the polar
/// map: radius sqrt(u), angle 2 pi v).
fn uniform_disc(u: Vec2) -> Vec2 {
    let r = u.x.sqrt();
    let (sin, cos) = (std::f32::consts::TAU * u.y).sin_cos();
    Vec2::new(r * cos, r * sin)
}

/// The next float in [0, 1) of a SplitMix64 sequence.
pub(crate) fn unit_float(state: &mut u64) -> f32 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 40) as f32 / (1u64 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_disc_map_keeps_areas_and_stays_inside() {
        // The inner half of the square's u maps inside radius sqrt(1/2): half the area.
        assert!((uniform_disc(Vec2::new(0.5, 0.3)).length() - 0.5f32.sqrt()).abs() < 1e-6);
        for k in 0..100 {
            let p = uniform_disc(Vec2::new(k as f32 / 100.0, (k * 37 % 100) as f32 / 100.0));
            assert!(p.length() <= 1.0 + 1e-6);
        }
    }

    #[test]
    fn unit_floats_are_in_range_and_spread() {
        let mut state = 7;
        let values: Vec<f32> = (0..1000).map(|_| unit_float(&mut state)).collect();
        assert!(values.iter().all(|v| (0.0..1.0).contains(v)));
        let mean = values.iter().sum::<f32>() / values.len() as f32;
        assert!((mean - 0.5).abs() < 0.05, "{mean}");
    }
}
