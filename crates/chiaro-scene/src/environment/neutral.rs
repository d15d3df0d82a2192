//! The `neutral` source: a studio Chiaro makes, so that no file (or licence) ships. A grey
//! room, lighter overhead and darker underfoot, with three rectangular soft boxes: a key
//! light above and left of a camera on +Z, a dimmer fill on the right, and a rim light
//! behind. Its mean radiance is about 1 nit, which `intensity` scales; in a scene with a
//! sun, the studio is scaled to light a horizontal surface with `STUDIO_TO_SUN_ILLUMINANCE`
//! of the sun's illuminance, so that the sun's shadows read under it (a 1-nit studio
//! beside a 3-lux sun fills shadows to nearly the lit level; beside a 100,000-lux sun it
//! vanishes).

use super::EnvironmentMap;
use glam::Vec3;

/// A rectangular emitter seen from the centre: its direction, the tangents of its half
/// extents, and its radiance.
struct SoftBox {
    centre: Vec3,
    half_extent: (f32, f32),
    radiance: f32,
}

const BOXES: [SoftBox; 3] = [
    SoftBox { centre: Vec3::new(-0.55, 0.55, 0.63), half_extent: (0.35, 0.25), radiance: 9.0 },
    SoftBox { centre: Vec3::new(0.8, 0.15, 0.58), half_extent: (0.3, 0.45), radiance: 3.0 },
    SoftBox { centre: Vec3::new(0.0, 0.7, -0.7), half_extent: (0.6, 0.12), radiance: 6.0 },
];

/// Tangent-plane distance over which a box's edge fades, so that the prefiltered mips
/// and the background show no stair steps.
const EDGE: f32 = 0.04;

fn smooth_inside(half: f32, x: f32) -> f32 {
    let t = ((half + EDGE * 0.5 - x.abs()) / EDGE).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn box_radiance(b: &SoftBox, d: Vec3) -> f32 {
    let c = b.centre.normalize();
    let along = d.dot(c);
    if along <= 0.0 {
        return 0.0;
    }
    let right = Vec3::Y.cross(c).normalize();
    let up = c.cross(right);
    let (x, y) = (d.dot(right) / along, d.dot(up) / along);
    b.radiance * smooth_inside(b.half_extent.0, x) * smooth_inside(b.half_extent.1, y)
}

/// The room without its boxes: 0.2 underfoot, 0.45 at the horizon, 0.7 overhead.
fn room_radiance(d: Vec3) -> f32 {
    if d.y < 0.0 { 0.2 + 0.25 * (1.0 + d.y).powi(4) } else { 0.45 + 0.25 * d.y }
}

/// The studio's illuminance on a horizontal surface, as a share of the sun's, where the
/// scene has one: the sky's share (`SKY_TO_SUN_ILLUMINANCE`), so that a shadow on the
/// ground keeps about a fifth of the lit ground's light under a sun 45 degrees up.
pub const STUDIO_TO_SUN_ILLUMINANCE: f32 = super::SKY_TO_SUN_ILLUMINANCE;

/// The studio environment, 512 x 256: as made (about 1 nit) without a sun, else scaled to
/// `STUDIO_TO_SUN_ILLUMINANCE` of the sun's illuminance `sun_lux`.
pub fn neutral(sun_lux: Option<f32>) -> EnvironmentMap {
    let mut map = EnvironmentMap::from_fn(512, |d| {
        let boxes: f32 = BOXES.iter().map(|b| box_radiance(b, d)).sum();
        Vec3::splat(room_radiance(d) + boxes)
    });
    if let Some(lux) = sun_lux.filter(|&l| l > 0.0) {
        let scale = STUDIO_TO_SUN_ILLUMINANCE * lux / map.upward_irradiance().x;
        map.texels.iter_mut().for_each(|t| *t *= scale);
    }
    map
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_math::environment::project_equirect;
    use std::f32::consts::PI;

    #[test]
    fn the_studio_is_lit_from_above_and_the_key_side() {
        let map = neutral(None);
        let sh = project_equirect(&map.texels, map.width, map.height);
        let mean = sh.irradiance(Vec3::Y).x / PI;
        // About 1 nit of mean radiance seen from the top.
        assert!((0.7..2.0).contains(&mean), "{mean}");
        assert!(sh.irradiance(Vec3::Y).x > 2.0 * sh.irradiance(Vec3::NEG_Y).x);
        assert!(sh.irradiance(Vec3::NEG_X).x > sh.irradiance(Vec3::X).x);
        assert!(map.radiance(BOXES[0].centre.normalize()).x > 8.0);
    }

    #[test]
    fn beside_a_sun_the_studio_lights_the_ground_with_its_share_of_the_sun() {
        for lux in [3.0, 100_000.0] {
            let map = neutral(Some(lux));
            let e = map.upward_irradiance().x;
            assert!((e / (STUDIO_TO_SUN_ILLUMINANCE * lux) - 1.0).abs() < 1e-3, "{lux}: {e}");
        }
    }
}
