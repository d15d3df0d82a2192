//! Exposure and tone mapping, the CPU twin of chiaro-render's `shaders/tonemap.wesl` (a
//! GPU test renders a known radiance and compares both).
//!
//! Exposure follows the photographic EV100 convention used by Filament and Frostbite:
//! `scale = 1 / (1.2 * 2^ev100)`. EV100 0 maps a radiance of 1.2 to 1.0; a sunny scene
//! (100,000 lux) wants about EV100 15. Tone mapping is the Khronos PBR Neutral operator,
//! which keeps base colours faithful up to ~0.8 and rolls highlights off to white.

use glam::Vec3;

/// The largest pre-exposed radiance the renderer stores: the largest finite half float,
/// the HDR targets' format. Shading clamps to it, so that a light a centimetre away or a
/// mirror highlight of the sun stores a bright but finite value (it tone-maps to white
/// either way) instead of overflowing to infinity, which tone mapping and FXAA would turn
/// into NaN.
pub const MAX_EXPOSED_RADIANCE: f32 = 65504.0;

/// Relative luminance of linear Rec. 709 RGB: how bright a colour looks, for measuring
/// light (noise, errors, emitter power) in one number.
pub fn luminance(linear_rgb: Vec3) -> f32 {
    linear_rgb.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Linear scale applied to scene radiance for a camera exposure of `ev100`.
pub fn exposure_scale(ev100: f32) -> f32 {
    1.0 / (1.2 * 2f32.powf(ev100))
}

/// Khronos PBR Neutral tone mapper: exposed linear radiance in, display-linear [0, 1] out.
pub fn pbr_neutral(color: Vec3) -> Vec3 {
    const START_COMPRESSION: f32 = 0.8 - 0.04;
    const DESATURATION: f32 = 0.15;
    let x = color.min_element();
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    let color = color - offset;
    let peak = color.max_element();
    if peak < START_COMPRESSION {
        return color;
    }
    let d = 1.0 - START_COMPRESSION;
    let new_peak = 1.0 - d * d / (peak + d - START_COMPRESSION);
    let color = color * (new_peak / peak);
    let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    color * (1.0 - g) + Vec3::splat(new_peak * g)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ev100_zero_maps_1_2_to_one() {
        assert!((exposure_scale(0.0) * 1.2 - 1.0).abs() < 1e-6);
        assert!((exposure_scale(1.0) * 2.0 - exposure_scale(0.0)).abs() < 1e-6);
    }

    #[test]
    fn neutral_keeps_dark_tones_and_caps_highlights() {
        let mid = Vec3::new(0.5, 0.3, 0.2);
        assert!((pbr_neutral(mid) - (mid - 0.04)).abs().max_element() < 1e-6);
        let bright = pbr_neutral(Vec3::splat(1000.0));
        assert!(bright.max_element() <= 1.0 && bright.min_element() > 0.99);
        // Monotonic along grey.
        let mut last = 0.0;
        for i in 0..200 {
            let v = pbr_neutral(Vec3::splat(i as f32 * 0.05)).x;
            assert!(v >= last - 1e-6);
            last = v;
        }
    }
}
