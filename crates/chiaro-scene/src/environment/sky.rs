//! The `sky` source: a clear daylight sky around the first directional light (the sun
//! itself stays that light). Its luminance follows the Perez sky model with Preetham's
//! coefficients for turbidity 3, blue overhead and whiter towards the horizon and the sun;
//! below the horizon a ground of albedo 0.2 lit by sun and sky. Scaled so that the sky
//! lights a horizontal surface with `SKY_TO_SUN_ILLUMINANCE` of the sun's illuminance.

use super::EnvironmentMap;
use glam::Vec3;
use std::f32::consts::PI;

/// The sky's illuminance on a horizontal surface, as a share of the sun's illuminance
/// (about what a clear sky gives beside a high sun).
pub const SKY_TO_SUN_ILLUMINANCE: f32 = 0.2;

/// Atmospheric turbidity: 2 is very clear, 3 a clear day.
const TURBIDITY: f32 = 3.0;
const GROUND_ALBEDO: f32 = 0.2;
const ZENITH_COLOR: Vec3 = Vec3::new(0.45, 0.62, 1.0);
const HORIZON_COLOR: Vec3 = Vec3::new(0.85, 0.9, 1.0);

/// Where the sun stands when the scene has no directional light: 45 degrees up, and
/// the sky then lights a horizontal surface with pi lux (as a uniform 1 nit would).
const DEFAULT_SUN: Vec3 = Vec3::new(0.5, 0.70710677, 0.5);

/// Perez's luminance distribution at view zenith angle cos `cos_theta` and angle `gamma`
/// from the sun.
fn perez(cos_theta: f32, gamma: f32) -> f32 {
    let t = TURBIDITY;
    let (a, b, c, d, e) =
        (0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251, 0.1206 * t - 2.5771, -0.0670 * t + 0.3703);
    (1.0 + a * (b / cos_theta.max(0.01)).exp()) * (1.0 + c * (d * gamma).exp() + e * gamma.cos().powi(2))
}

fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// The sky's radiance shape (not yet scaled) towards unit `d` above the horizon.
fn sky_shape(d: Vec3, sun: Vec3) -> Vec3 {
    let gamma = d.dot(sun).clamp(-1.0, 1.0).acos();
    let whiteness = (0.8 * (1.0 - d.y).powi(4) + 0.6 * (-3.0 * gamma).exp()).clamp(0.0, 1.0);
    let color = ZENITH_COLOR.lerp(HORIZON_COLOR, whiteness);
    color / luminance(color) * perez(d.y, gamma)
}

/// The sky for the sun towards unit `sun.0` with illuminance `sun.1` lux, or the default
/// sun; 512 x 256.
pub fn sky(sun: Option<(Vec3, f32)>) -> EnvironmentMap {
    let (towards, target) = match sun {
        Some((towards, lux)) => (towards.normalize(), SKY_TO_SUN_ILLUMINANCE * lux),
        None => (DEFAULT_SUN.normalize(), PI),
    };
    // A sun under the horizon shapes the sky as if at it.
    let shaped_sun = Vec3::new(towards.x, towards.y.max(0.02), towards.z).normalize();
    let unscaled = EnvironmentMap::from_fn(512, |d| if d.y >= 0.0 { sky_shape(d, shaped_sun) } else { Vec3::ZERO });
    // Scaled, the sky lights a horizontal surface with `target` lux.
    let scale = target / luminance(unscaled.upward_irradiance()).max(1e-12);
    let sun_lux = match sun {
        Some((_, lux)) => lux * towards.y.max(0.0),
        None => 0.0,
    };
    let ground = Vec3::splat(GROUND_ALBEDO * (target + sun_lux) / PI);
    let texels = unscaled.texels.iter().map(|t| if *t == Vec3::ZERO { ground } else { *t * scale }).collect();
    EnvironmentMap { texels, ..unscaled }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sky_lights_the_ground_with_its_share_of_the_sun() {
        let sun = Vec3::new(0.3, 0.8, -0.2).normalize();
        let map = sky(Some((sun, 10_000.0)));
        let up = luminance(map.upward_irradiance());
        assert!((up - 2_000.0).abs() < 20.0, "{up}");
        // Brighter around the sun than opposite it, and bluer overhead than at the horizon.
        let opposite = Vec3::new(-sun.x, sun.y, -sun.z);
        assert!(luminance(map.radiance(sun)) > 2.0 * luminance(map.radiance(opposite)));
        let zenith = map.radiance(Vec3::Y);
        let horizon = map.radiance(Vec3::new(-sun.x, 0.05, -sun.z).normalize());
        assert!(zenith.z / zenith.x > horizon.z / horizon.x);
        assert!(map.radiance(Vec3::NEG_Y).min_element() > 0.0);
    }
}
