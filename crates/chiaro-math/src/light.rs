//! The punctual light model of the Custom SRP "Point and Spot Lights" tutorial, in glTF's
//! physical units: attenuation terms, derived ranges, and the per-frame choice of which
//! local (point and spot) lights the GPU sees.
//!
//! The shaders compute the same terms (chiaro-render's `shaders/lighting/light.wesl`); the
//! GPU tests measure rendered radiance against these functions.

use crate::bounds::Sphere;
use crate::frustum::Frustum;
use glam::Vec3;

/// Most directional lights shaded per frame.
pub const MAX_DIRECTIONAL_LIGHTS: usize = 4;
/// Most point and spot lights the forward path shades per frame when every pixel loops
/// over all of them (light culling "none"): the limit of Catlike Coding's Custom SRP
/// tutorial "Point and Spot Lights".
pub const MAX_LOCAL_LIGHTS: usize = 64;
/// Most point and spot lights shaded per frame with culled lists (clustered or per
/// object) or by the deferred path's volumes.
pub const MAX_DEFERRED_LOCAL_LIGHTS: usize = 4096;

/// Brightest light Chiaro shades, candela (point, spot) or lux (directional): ten billion
/// suns. Brighter lights make radiance overflow `f32` before any exposure applies.
pub const MAX_LIGHT_INTENSITY: f32 = 1.0e15;
/// Dimmest illuminance a derived range may cut off at (`range_threshold_lux`): lower
/// values give ranges whose squares overflow `f32`.
pub const MIN_RANGE_THRESHOLD_LUX: f32 = 1.0e-6;
/// Longest range a light is shaded with, metres. The range window is 1 to within 1e-30
/// over any distance a scene spans short of this, so a longer range changes nothing but
/// would overflow the squares the window takes.
pub const MAX_SHADED_RANGE_M: f32 = 1.0e15;

/// Smallest squared distance used in the inverse-square term, so a surface touching a
/// light does not divide by zero (1 mm squared).
pub const MIN_DISTANCE_SQUARED: f32 = 1.0e-6;

/// The windowed range attenuation `max(0, 1 - (d²/r²)²)²`: 1 at the light, exactly 0 at and
/// beyond `range`, smooth in between.
pub fn range_attenuation(distance_squared: f32, range: f32) -> f32 {
    let ratio = distance_squared / (range * range);
    let window = (1.0 - ratio * ratio).max(0.0);
    window * window
}

/// Inverse-square falloff times the range window: what multiplies a light's intensity
/// (candela) to give illuminance (lux) on a surface facing it.
pub fn distance_attenuation(distance_squared: f32, range: f32) -> f32 {
    range_attenuation(distance_squared, range) / distance_squared.max(MIN_DISTANCE_SQUARED)
}

/// The `(a, b)` pair of the spot cone: `saturate(dot(spot_dir, l) * a + b)²`, with
/// `a = 1 / max(cos(inner) - cos(outer), 0.001)` and `b = -cos(outer) * a`.
/// glTF's cone angles are half-angles already.
pub fn spot_angle_params(inner_rad: f32, outer_rad: f32) -> (f32, f32) {
    let cos_outer = outer_rad.cos();
    let a = 1.0 / (inner_rad.cos() - cos_outer).max(0.001);
    (a, -cos_outer * a)
}

/// Spot attenuation for the cosine between the spot direction and the direction from the
/// light to the surface.
pub fn spot_attenuation(cos_angle: f32, (a, b): (f32, f32)) -> f32 {
    let t = (cos_angle * a + b).clamp(0.0, 1.0);
    t * t
}

/// Range for a light whose glTF file gives none: the distance at which its illuminance
/// `intensity_cd / d²` falls to `threshold_lux`, so every local light has a bounding
/// volume. A 100 cd bulb with the default 0.01 lux threshold reaches 100 m.
pub fn derived_range(intensity_cd: f32, threshold_lux: f32) -> f32 {
    (intensity_cd.max(0.0) / threshold_lux).sqrt()
}

/// The range a point or spot light is shaded (and baked, and judged) with: its own
/// `own_range_m` where its file gives one, or the distance at which its peak illuminance
/// (`peak_intensity_cd`, the brightest colour channel times the intensity) falls to
/// `range_threshold_lux`; at most `MAX_SHADED_RANGE_M` either way. A 100 cd bulb with no
/// range and the default 0.01 lux threshold is shaded to 100 m.
pub fn shaded_range(own_range_m: Option<f32>, peak_intensity_cd: f32, range_threshold_lux: f32) -> f32 {
    own_range_m.unwrap_or_else(|| derived_range(peak_intensity_cd, range_threshold_lux)).min(MAX_SHADED_RANGE_M)
}

/// What the frame needs to know about a point or spot light to cull and order it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalLightBounds {
    pub position: Vec3,
    pub range: f32,
    /// Peak of the colour times intensity, the brightest channel in candela.
    pub peak_intensity: f32,
    /// `(axis, outer half angle)` for spot lights.
    pub spot: Option<(Vec3, f32)>,
}

/// Importance of a light for a camera at `eye`: its peak intensity at the eye with the same
/// falloff the shading uses, but with the distance clamped to a tenth of its range so that
/// lights right at the camera do not win everything. Depends only on the light and the eye,
/// so the same lights win from frame to frame.
pub fn importance(light: &LocalLightBounds, eye: Vec3) -> f32 {
    let near = light.range * 0.1;
    let d2 = light.position.distance_squared(eye).max(near * near);
    light.peak_intensity / d2.max(MIN_DISTANCE_SQUARED)
}

/// The lights a frame shades, in the order they are uploaded.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightSelection {
    /// Indices into the input, most important first.
    pub visible: Vec<usize>,
    /// Lights that intersect the view but did not fit under `max_lights`.
    pub dropped: usize,
    /// Lights whose volume lies outside the view.
    pub culled: usize,
}

/// Culls local lights against the view frustum (range spheres, cone spheres for spots),
/// orders the survivors by `importance` (ties broken by index, so the order is total and
/// stable), and keeps the first `max_lights`.
pub fn select_local_lights(
    lights: &[LocalLightBounds],
    frustum: &Frustum,
    eye: Vec3,
    max_lights: usize,
) -> LightSelection {
    let mut culled = 0;
    // One sort key per light: importance (positive, so its bits order as the number does)
    // inverted for most important first, then the index; integer keys sort several times
    // faster than comparing pairs, which counts with thousands of lights a frame.
    let mut keyed: Vec<u64> = Vec::with_capacity(lights.len());
    for (index, light) in lights.iter().enumerate() {
        let inside = match light.spot {
            Some((axis, outer)) => frustum.intersects_cone(light.position, axis, outer, light.range),
            None => frustum.intersects_sphere(&Sphere { center: light.position, radius: light.range }),
        };
        if inside && light.peak_intensity > 0.0 {
            let rank = !importance(light, eye).to_bits();
            keyed.push(u64::from(rank) << 32 | index as u64);
        } else {
            culled += 1;
        }
    }
    keyed.sort_unstable();
    let dropped = keyed.len().saturating_sub(max_lights);
    keyed.truncate(max_lights);
    LightSelection {
        visible: keyed.into_iter().map(|key| (key & u64::from(u32::MAX)) as usize).collect(),
        dropped,
        culled,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;
    use proptest::prelude::*;

    #[test]
    fn range_window_is_one_at_light_and_zero_at_range() {
        assert_eq!(range_attenuation(0.0, 5.0), 1.0);
        assert_eq!(range_attenuation(25.0, 5.0), 0.0);
        assert_eq!(range_attenuation(30.0, 5.0), 0.0);
        // d = r / 2: (1 - (1/4)^2)^2 = (15/16)^2
        let half = range_attenuation(6.25, 5.0);
        assert!((half - (15.0f32 / 16.0).powi(2)).abs() < 1e-6);
    }

    #[test]
    fn inverse_square_with_clamped_minimum() {
        let far = distance_attenuation(4.0, 1.0e6);
        assert!((far - 0.25).abs() < 1e-6);
        assert_eq!(distance_attenuation(0.0, 10.0), 1.0 / MIN_DISTANCE_SQUARED);
    }

    #[test]
    fn spot_is_full_inside_inner_and_zero_outside_outer() {
        let p = spot_angle_params(20f32.to_radians(), 30f32.to_radians());
        assert_eq!(spot_attenuation(10f32.to_radians().cos(), p), 1.0);
        assert_eq!(spot_attenuation(20f32.to_radians().cos(), p), 1.0);
        assert_eq!(spot_attenuation(31f32.to_radians().cos(), p), 0.0);
        let mid = spot_attenuation(25f32.to_radians().cos(), p);
        assert!(mid > 0.0 && mid < 1.0);
    }

    #[test]
    fn spot_with_equal_angles_stays_finite() {
        let p = spot_angle_params(0.5, 0.5);
        assert!(p.0.is_finite() && p.1.is_finite());
        assert_eq!(spot_attenuation(0.4f32.cos(), p), 1.0);
        assert_eq!(spot_attenuation(0.6f32.cos(), p), 0.0);
    }

    #[test]
    fn derived_range_is_where_illuminance_meets_threshold() {
        let r = derived_range(100.0, 0.01);
        assert!((r - 100.0).abs() < 1e-3);
        assert!((100.0 / (r * r) - 0.01).abs() < 1e-6);
        assert_eq!(derived_range(0.0, 0.01), 0.0);
    }

    #[test]
    fn shaded_range_is_the_lights_own_or_derived_and_bounded() {
        assert_eq!(shaded_range(Some(7.5), 100.0, 0.01), 7.5);
        assert!((shaded_range(None, 100.0, 0.01) - 100.0).abs() < 1e-3);
        // The brightest light at the lowest threshold is derived a range well inside the bound.
        assert!(shaded_range(None, MAX_LIGHT_INTENSITY, MIN_RANGE_THRESHOLD_LUX) < MAX_SHADED_RANGE_M);
        assert_eq!(shaded_range(Some(1.0e20), 1.0, 0.01), MAX_SHADED_RANGE_M);
        assert_eq!(shaded_range(Some(f32::INFINITY), 1.0, 0.01), MAX_SHADED_RANGE_M);
    }

    fn view() -> (Frustum, Vec3) {
        let eye = Vec3::new(0.0, 1.0, 5.0);
        let proj = Mat4::perspective_infinite_reverse_rh(60f32.to_radians(), 1.0, 0.1);
        let view = Mat4::look_at_rh(eye, Vec3::new(0.0, 1.0, 0.0), Vec3::Y);
        (Frustum::from_clip_from_world(&(proj * view)), eye)
    }

    fn point(position: Vec3, range: f32, intensity: f32) -> LocalLightBounds {
        LocalLightBounds { position, range, peak_intensity: intensity, spot: None }
    }

    #[test]
    fn lights_behind_the_camera_are_culled() {
        let (f, eye) = view();
        let lights = [
            point(Vec3::new(0.0, 1.0, 0.0), 2.0, 10.0),
            point(Vec3::new(0.0, 1.0, 20.0), 2.0, 10.0),
            point(Vec3::new(0.0, 1.0, 7.0), 3.0, 10.0),
        ];
        let sel = select_local_lights(&lights, &f, eye, 64);
        assert_eq!(sel.culled, 1);
        assert!(sel.visible.contains(&0) && sel.visible.contains(&2));
    }

    #[test]
    fn spot_pointing_away_is_culled_but_its_range_sphere_would_not_be() {
        let (f, eye) = view();
        let spot = LocalLightBounds {
            position: Vec3::new(0.0, 1.0, 6.0),
            range: 5.0,
            peak_intensity: 10.0,
            spot: Some((Vec3::Z, 20f32.to_radians())),
        };
        let as_point = LocalLightBounds { spot: None, ..spot };
        assert_eq!(select_local_lights(&[spot], &f, eye, 64).culled, 1);
        assert_eq!(select_local_lights(&[as_point], &f, eye, 64).culled, 0);
    }

    #[test]
    fn brightest_at_the_eye_win_and_the_rest_are_counted() {
        let (f, eye) = view();
        let lights: Vec<_> =
            (0..10).map(|i| point(Vec3::new(i as f32 - 5.0, 1.0, 0.0), 50.0, 1.0 + i as f32)).collect();
        let sel = select_local_lights(&lights, &f, eye, 4);
        assert_eq!(sel.visible.len(), 4);
        assert_eq!(sel.dropped, 6);
        for pair in sel.visible.windows(2) {
            assert!(importance(&lights[pair[0]], eye) >= importance(&lights[pair[1]], eye));
        }
        let best = (0..lights.len())
            .max_by(|&a, &b| importance(&lights[a], eye).total_cmp(&importance(&lights[b], eye)))
            .unwrap();
        assert_eq!(sel.visible[0], best);
        for dropped in (0..lights.len()).filter(|i| !sel.visible.contains(i)) {
            assert!(importance(&lights[dropped], eye) <= importance(&lights[sel.visible[3]], eye));
        }
    }

    #[test]
    fn equal_lights_keep_index_order() {
        let (f, eye) = view();
        let lights = vec![point(Vec3::new(0.0, 1.0, 0.0), 10.0, 5.0); 6];
        let sel = select_local_lights(&lights, &f, eye, 3);
        assert_eq!(sel.visible, vec![0, 1, 2]);
    }

    proptest! {
        #[test]
        fn selection_is_stable_under_input_permutation(seed in 0u64..1000) {
            let (f, eye) = view();
            let mut lights: Vec<_> = (0..20)
                .map(|i| {
                    let h = (seed.wrapping_mul(31).wrapping_add(i * 7919)) % 97;
                    point(Vec3::new(h as f32 * 0.2 - 9.0, 1.0, -(h as f32) * 0.1), 30.0, 1.0 + h as f32)
                })
                .collect();
            let a = select_local_lights(&lights, &f, eye, 8);
            let chosen: Vec<_> = a.visible.iter().map(|&i| lights[i]).collect();
            lights.reverse();
            let b = select_local_lights(&lights, &f, eye, 8);
            let chosen_b: Vec<_> = b.visible.iter().map(|&i| lights[i]).collect();
            // Same importance values in the same order, whatever the input order.
            let imp = |v: &[LocalLightBounds]| v.iter().map(|l| importance(l, eye)).collect::<Vec<_>>();
            prop_assert_eq!(imp(&chosen), imp(&chosen_b));
        }

        #[test]
        fn range_attenuation_is_monotonic_and_bounded(d1 in 0.0f32..20.0, d2 in 0.0f32..20.0, r in 0.1f32..15.0) {
            let (near, far) = if d1 < d2 { (d1, d2) } else { (d2, d1) };
            let a = range_attenuation(near * near, r);
            let b = range_attenuation(far * far, r);
            prop_assert!((0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b));
            prop_assert!(a >= b);
            if far >= r { prop_assert_eq!(b, 0.0); }
        }
    }
}
