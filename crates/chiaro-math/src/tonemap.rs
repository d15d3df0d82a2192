//! Exposure and tone mapping, the CPU twin of chiaro-render's `shaders/tonemap.wesl` (a
//! GPU test renders a known radiance and compares both).
//!
//! Exposure follows the photographic EV100 convention used by Filament and Frostbite:
//! `scale = 1 / (1.2 * 2^ev100)`. EV100 0 maps a radiance of 1.2 to 1.0; a sunny scene
//! (100,000 lux) wants about EV100 15. Tone mapping is the Khronos PBR Neutral operator by
//! default, which keeps base colours faithful up to ~0.8 and rolls highlights off to
//! white; the fitted ACES curve that three.js and the Khronos render-fidelity renderers
//! use, Blender's AgX base, and a plain clamp are the others. Each takes exposed linear
//! Rec. 709 radiance and gives display-linear [0, 1] RGB, which the sRGB encoding follows.

use glam::{Mat3, Vec3};

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

/// The fitted ACES filmic curve (Stephen Hill's fit of the RRT and sRGB ODT, as three.js's
/// `ACESFilmicToneMapping` and the Khronos sample viewer apply it): exposure divided by
/// 0.6, sRGB to the fit's working space, the rational fit, back, clamped.
pub fn aces_fitted(color: Vec3) -> Vec3 {
    // sRGB => XYZ => D65 to D60 => AP1 => RRT saturation, and back (columns).
    let input = Mat3::from_cols(
        Vec3::new(0.59719, 0.07600, 0.02840),
        Vec3::new(0.35458, 0.90834, 0.13383),
        Vec3::new(0.04823, 0.01566, 0.83777),
    );
    let output = Mat3::from_cols(
        Vec3::new(1.60475, -0.10208, -0.00327),
        Vec3::new(-0.53108, 1.10813, -0.07276),
        Vec3::new(-0.07367, -0.00605, 1.07602),
    );
    let v = input * (color / 0.6);
    let a = v * (v + 0.0245786) - 0.000090537;
    let b = v * (v * 0.983729 + 0.432951) + 0.238081;
    (output * (a / b)).clamp(Vec3::ZERO, Vec3::ONE)
}

/// Blender's AgX base (Troy Sobotka's, in the Rec. 2020 form of Filament and three.js):
/// into Rec. 2020, the inset matrix, a log2 encoding over [-12.47, 4.03] EV, the default
/// contrast sigmoid (a polynomial fit), the outset matrix, the 2.2 display decoding, back
/// to Rec. 709, clamped. Greys stay grey.
pub fn agx(color: Vec3) -> Vec3 {
    const MIN_EV: f32 = -12.47393;
    const MAX_EV: f32 = 4.026069;
    let rec709_to_rec2020 = Mat3::from_cols(
        Vec3::new(0.6274, 0.0691, 0.0164),
        Vec3::new(0.3293, 0.9195, 0.0880),
        Vec3::new(0.0433, 0.0113, 0.8956),
    );
    let rec2020_to_rec709 = Mat3::from_cols(
        Vec3::new(1.6605, -0.1246, -0.0182),
        Vec3::new(-0.5876, 1.1329, -0.1006),
        Vec3::new(-0.0728, -0.0083, 1.1187),
    );
    let inset = Mat3::from_cols(
        Vec3::new(0.856_627_15, 0.137_318_97, 0.111_898_21),
        Vec3::new(0.095_121_24, 0.761_242, 0.076_799_42),
        Vec3::new(0.048_251_61, 0.101_439_04, 0.811_302_37),
    );
    let outset = Mat3::from_cols(
        Vec3::new(1.127_100_6, -0.141_329_76, -0.141_329_76),
        Vec3::new(-0.110_606_64, 1.157_823_7, -0.110_606_64),
        Vec3::new(-0.016_493_94, -0.016_493_94, 1.251_936_4),
    );
    let c = inset * (rec709_to_rec2020 * color);
    let encoded = ((c.max(Vec3::splat(1e-10)).log2() - MIN_EV) / (MAX_EV - MIN_EV)).clamp(Vec3::ZERO, Vec3::ONE);
    let c = outset * agx_contrast(encoded);
    (rec2020_to_rec709 * c.max(Vec3::ZERO).powf(2.2)).clamp(Vec3::ZERO, Vec3::ONE)
}

/// AgX's default contrast: a sixth-order polynomial fit of its sigmoid over [0, 1].
fn agx_contrast(x: Vec3) -> Vec3 {
    let x2 = x * x;
    let x4 = x2 * x2;
    15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x - 0.00232
}

/// No curve: exposed radiance clamped to [0, 1].
pub fn linear_clamp(color: Vec3) -> Vec3 {
    color.clamp(Vec3::ZERO, Vec3::ONE)
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

    #[test]
    fn aces_darkens_mid_grey_and_saturates_bright_white() {
        // 0.18 is 0.3 after the division by 0.6, which the fit takes to about 0.213 (the
        // matrices' rows sum to 1, so greys stay grey); black stays black.
        let mid = aces_fitted(Vec3::splat(0.18));
        assert!((mid.x - mid.y).abs() < 1e-3 && (mid.y - mid.z).abs() < 1e-3, "grey stays near grey: {mid}");
        assert!(mid.x > 0.2 && mid.x < 0.3, "{mid}");
        assert!(aces_fitted(Vec3::ZERO).max_element() < 1e-3);
        assert!(aces_fitted(Vec3::splat(100.0)).min_element() > 0.99);
        let mut last = 0.0;
        for i in 0..400 {
            let v = aces_fitted(Vec3::splat(i as f32 * 0.05)).x;
            assert!(v >= last - 1e-6, "monotonic");
            last = v;
        }
    }

    #[test]
    fn agx_keeps_greys_grey_and_rolls_every_colour_off_below_white() {
        for v in [0.001f32, 0.05, 0.18, 1.0, 10.0, 1000.0] {
            let g = agx(Vec3::splat(v));
            assert!((g.x - g.y).abs() < 2e-3 && (g.y - g.z).abs() < 2e-3, "{v}: {g}");
        }
        // Mid grey (log-encoded at 0.606) sits near the sigmoid's middle.
        let mid = agx(Vec3::splat(0.18)).x;
        assert!(mid > 0.15 && mid < 0.3, "{mid}");
        // A saturated colour desaturates towards white as it brightens, never past 1.
        let red = agx(Vec3::new(50.0, 0.0, 0.0));
        assert!(red.max_element() <= 1.0 && red.y > 0.1, "{red}");
        let mut last = 0.0;
        for i in 0..400 {
            let v = agx(Vec3::splat(i as f32 * 0.05)).x;
            assert!(v >= last - 1e-5, "monotonic");
            last = v;
        }
    }
}
