//! Shadow strength fades: at the max shadow distance and at the edge of the last cascade,
//! as the tutorial's `FadedShadowStrength(distance, scale, fade) = saturate((1 - d * scale) * fade)`.

/// `saturate((1 - distance * scale) * fade)`.
pub fn faded_shadow_strength(distance: f32, scale: f32, fade: f32) -> f32 {
    ((1.0 - distance * scale) * fade).clamp(0.0, 1.0)
}

/// The shader's `(1 / max_distance, 1 / distance_fade, 1 / (1 - (1 - cascade_fade)²))`:
/// strength falls linearly over the last `distance_fade` fraction of the max distance,
/// and over the last `cascade_fade` fraction of the last cascade's radius (measured in
/// squared distance, hence the squared term).
pub fn distance_fade_params(max_distance: f32, distance_fade: f32, cascade_fade: f32) -> [f32; 3] {
    let f = 1.0 - cascade_fade;
    [1.0 / max_distance, 1.0 / distance_fade, 1.0 / (1.0 - f * f)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_fade_goes_from_one_to_zero_over_the_fade_band() {
        let [scale, fade, _] = distance_fade_params(100.0, 0.1, 0.1);
        assert_eq!(faded_shadow_strength(50.0, scale, fade), 1.0);
        assert_eq!(faded_shadow_strength(90.0, scale, fade), 1.0);
        assert!((faded_shadow_strength(95.0, scale, fade) - 0.5).abs() < 1e-4);
        assert_eq!(faded_shadow_strength(100.0, scale, fade), 0.0);
        assert_eq!(faded_shadow_strength(120.0, scale, fade), 0.0);
    }

    #[test]
    fn cascade_fade_reaches_zero_at_the_sphere_edge() {
        let [_, _, fade] = distance_fade_params(100.0, 0.1, 0.2);
        let radius_sq: f32 = 400.0;
        assert_eq!(faded_shadow_strength(radius_sq, 1.0 / radius_sq, fade), 0.0);
        let inner = (0.8 * 20.0f32).powi(2);
        assert!((faded_shadow_strength(inner, 1.0 / radius_sq, fade) - 1.0).abs() < 1e-4);
    }
}
