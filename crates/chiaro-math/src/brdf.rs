//! The glTF metallic-roughness BRDF on the CPU, twin of `shaders/lighting/brdf.wesl`: the
//! GPU tests predict rendered radiance with it, and the baker will shade with it. Its
//! specular lobe takes the multiple-scattering compensation the environment light's does
//! (Fdez-Aguera), so a rough metal is as bright under a lamp as under a sky.

use glam::Vec3;
use std::f32::consts::PI;

/// For n.h in [0, 1] the denominator's root is at least `a2`; rounding can take it below
/// (to zero for a mirror lobe seen head-on), so it is held there.
pub(crate) fn d_ggx(n_dot_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let f = (n_dot_h * n_dot_h * (a2 - 1.0) + 1.0).max(a2);
    a2 / (PI * f * f)
}

/// Schlick's Fresnel weight (1 - v.h)^5, with v.h clamped to [0, 1].
pub fn schlick_weight(v_dot_h: f32) -> f32 {
    let m = 1.0 - v_dot_h.clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// The height-correlated Smith visibility term, G / (4 n.v n.l).
pub fn v_smith_ggx_correlated(n_dot_v: f32, n_dot_l: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let gv = n_dot_l * (n_dot_v * n_dot_v * (1.0 - a2) + a2).sqrt();
    let gl = n_dot_v * (n_dot_l * n_dot_l * (1.0 - a2) + a2).sqrt();
    0.5 / (gv + gl).max(1e-6)
}

/// Dielectrics reflect 4% at normal incidence (glTF's fixed IOR of 1.5).
pub const DIELECTRIC_F0: f32 = 0.04;

/// Fresnel's reflectance at normal incidence: `DIELECTRIC_F0` for dielectrics, the base
/// colour for metals.
pub fn f0_of(base_color: Vec3, metallic: f32) -> Vec3 {
    Vec3::splat(DIELECTRIC_F0).lerp(base_color, metallic)
}

/// The albedo of the diffuse lobe for light whose direction is not kept (baked light,
/// bounces in the baker): the diffuse term of `brdf_cos` at normal incidence,
/// `(1 - F0)(1 - metallic) base`. The renderer applies the same factor to the lightmaps,
/// so a light switched from realtime to baked keeps its brightness.
pub fn diffuse_albedo(base_color: Vec3, metallic: f32) -> Vec3 {
    (Vec3::ONE - f0_of(base_color, metallic)) * (1.0 - metallic) * base_color
}

/// The energy a GGX lobe at `n_dot_v` and perceptual `roughness` loses to single
/// scattering: `1 - E_ss`, where `E_ss` is its albedo at F0 = 1 (the split sum's scale
/// plus bias). Twin of the shader's `multiple_scattering_energy`.
pub fn multiple_scattering_energy(n_dot_v: f32, roughness: f32) -> f32 {
    let terms = crate::environment::SplitSumTable::shared().terms(n_dot_v.clamp(1e-4, 1.0), roughness);
    (1.0 - (terms.x + terms.y)).clamp(0.0, 0.95)
}

/// What multiple scattering between microfacets adds to a GGX lobe of reflectance `f0`
/// that loses `multiple_energy` to single scattering, as a factor on the single-scattering
/// lobe: Fdez-Aguera's (2019) series with Fresnel's hemispherical mean, as
/// `environment::ibl_weights` applies it, so lamps and environments agree.
pub fn multiple_scattering_compensation(f0: Vec3, multiple_energy: f32) -> Vec3 {
    let mean_fresnel = f0 + (Vec3::ONE - f0) / 21.0;
    Vec3::ONE + mean_fresnel * multiple_energy / (Vec3::ONE - multiple_energy * mean_fresnel)
}

/// BRDF times cos(theta_l) for unit `n`, `v` (towards the eye) and `l` (towards the light).
/// Roughness is clamped to 0.03 as the shader clamps it. Cosines are clamped to [0, 1]
/// (unit vectors' dot products round past 1) and the half vector of `l = -v` is zero, as
/// in the shader, so that every term stays finite.
pub fn brdf_cos(base_color: Vec3, metallic: f32, roughness: f32, n: Vec3, v: Vec3, l: Vec3) -> Vec3 {
    let n_dot_l = n.dot(l).min(1.0);
    if n_dot_l <= 0.0 {
        return Vec3::ZERO;
    }
    let roughness = roughness.clamp(0.03, 1.0);
    let n_dot_v = n.dot(v).clamp(1e-4, 1.0);
    let h = (l + v).normalize_or_zero();
    let n_dot_h = n.dot(h).clamp(0.0, 1.0);
    let v_dot_h = v.dot(h).clamp(0.0, 1.0);
    let alpha = roughness * roughness;
    let f0 = f0_of(base_color, metallic);
    let f = f0 + (Vec3::ONE - f0) * schlick_weight(v_dot_h);
    let diffuse = (Vec3::ONE - f) * (1.0 - metallic) * base_color / PI;
    let compensation = multiple_scattering_compensation(f0, multiple_scattering_energy(n_dot_v, roughness));
    let specular = f * d_ggx(n_dot_h, alpha) * v_smith_ggx_correlated(n_dot_v, n_dot_l, alpha) * compensation;
    (diffuse + specular) * n_dot_l
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The specular lobe of `brdf_cos` integrated over the hemisphere of light
    /// directions (uniform incoming radiance 1), seen from `n_dot_v`.
    fn punctual_albedo(base: Vec3, metallic: f32, roughness: f32, n_dot_v: f32) -> Vec3 {
        let v = Vec3::new((1.0 - n_dot_v * n_dot_v).sqrt(), n_dot_v, 0.0);
        let (steps_theta, steps_phi) = (256, 256);
        let mut sum = Vec3::ZERO;
        for i in 0..steps_theta {
            // Uniform in cos(theta): each ring holds an equal solid angle.
            let cos_t = (i as f32 + 0.5) / steps_theta as f32;
            let sin_t = (1.0 - cos_t * cos_t).sqrt();
            for j in 0..steps_phi {
                let phi = (j as f32 + 0.5) / steps_phi as f32 * std::f32::consts::TAU;
                let l = Vec3::new(sin_t * phi.cos(), cos_t, sin_t * phi.sin());
                sum += brdf_cos(base, metallic, roughness, Vec3::Y, v, l);
            }
        }
        sum * (std::f32::consts::TAU / (steps_theta * steps_phi) as f32)
    }

    #[test]
    fn rough_metals_reflect_as_much_of_lamps_as_of_the_sky() {
        // The environment's weights are what a multiple-scattering path tracer gives in a
        // furnace (within 1%); lamps all around must add up to the same.
        let table = crate::environment::SplitSumTable::shared();
        let gold = Vec3::new(1.0, 0.78, 0.34);
        for (roughness, n_dot_v) in [(1.0, 0.7), (0.8, 0.5), (0.6, 0.9), (1.0, 0.2)] {
            let lamps = punctual_albedo(gold, 1.0, roughness, n_dot_v);
            let sky = crate::environment::directional_albedo(gold, 1.0, table.terms(n_dot_v, roughness));
            let ratio = lamps / sky;
            assert!((ratio - Vec3::ONE).abs().max_element() < 0.03, "roughness {roughness}, n.v {n_dot_v}: {ratio}");
            // Without the compensation the rough lobe loses a visible share.
            assert!(multiple_scattering_energy(n_dot_v, roughness) > 0.1, "{roughness} {n_dot_v}");
        }
        // A mirror-like lobe loses almost nothing.
        assert!(multiple_scattering_energy(0.9, 0.05) < 0.01);
    }

    #[test]
    fn rough_white_dielectric_is_close_to_lambert() {
        let n = Vec3::Y;
        let l = Vec3::new(0.3, 1.0, 0.1).normalize();
        let v = Vec3::new(-0.2, 1.0, 0.4).normalize();
        let f = brdf_cos(Vec3::ONE, 0.0, 1.0, n, v, l);
        let lambert = n.dot(l) / PI;
        assert!((f.x / lambert - 1.0).abs() < 0.1, "{} vs {}", f.x, lambert);
    }

    #[test]
    fn diffuse_albedo_is_the_diffuse_term_at_normal_incidence() {
        let base = Vec3::new(0.8, 0.5, 0.2);
        for metallic in [0.0, 0.3, 1.0] {
            // Roughness 1 and n = v = l: the specular part is F0 D V times the multiple
            // scattering compensation of F0, found apart.
            let whole = brdf_cos(base, metallic, 1.0, Vec3::Y, Vec3::Y, Vec3::Y);
            let energy = multiple_scattering_energy(1.0, 1.0);
            let compensation = |f0: Vec3| multiple_scattering_compensation(f0, energy);
            let lobe = brdf_cos(Vec3::ZERO, 0.0, 1.0, Vec3::Y, Vec3::Y, Vec3::Y)
                / (DIELECTRIC_F0 * compensation(Vec3::splat(DIELECTRIC_F0)));
            let f0 = f0_of(base, metallic);
            let specular = lobe * f0 * compensation(f0);
            let diffuse = (whole - specular) * PI;
            assert!((diffuse - diffuse_albedo(base, metallic)).abs().max_element() < 1e-5, "{metallic}: {diffuse}");
        }
        assert_eq!(diffuse_albedo(Vec3::ONE, 0.0), Vec3::splat(0.96));
    }

    #[test]
    fn coinciding_and_opposite_directions_stay_finite() {
        // A flashlight: view and light along the same unit vector, whose cosines round past
        // 1; and light arriving exactly against the view, where the half vector vanishes.
        let n = Vec3::new(0.3, 0.9, 0.1).normalize();
        for v in [n, Vec3::new(0.21, 0.97, 0.13).normalize(), Vec3::new(-0.7, 0.7, 0.1).normalize()] {
            for roughness in [0.0, 0.03, 0.5, 1.0] {
                for l in [v, -v, n] {
                    let f = brdf_cos(Vec3::new(0.9, 0.5, 0.2), 1.0, roughness, n, v, l);
                    assert!(f.is_finite() && f.min_element() >= 0.0, "{v} {l} {roughness}: {f}");
                }
            }
        }
        assert_eq!(schlick_weight(1.0 + 1e-7), 0.0);
        assert_eq!(schlick_weight(-0.5), 1.0);
    }

    #[test]
    fn no_light_from_below() {
        assert_eq!(brdf_cos(Vec3::ONE, 0.0, 0.5, Vec3::Y, Vec3::Y, Vec3::NEG_Y), Vec3::ZERO);
    }

    #[test]
    fn energy_is_bounded_for_a_white_furnace() {
        // Integrate brdf_cos over the hemisphere for a fixed view: at most 1 (no gain).
        let n = Vec3::Y;
        let v = Vec3::new(0.5, 1.0, 0.0).normalize();
        for (metallic, roughness) in [(0.0, 1.0), (0.0, 0.3), (1.0, 0.5)] {
            let mut sum = 0.0;
            let steps = 200;
            for i in 0..steps {
                for j in 0..steps * 2 {
                    let theta = (i as f32 + 0.5) / steps as f32 * PI / 2.0;
                    let phi = (j as f32 + 0.5) / (steps * 2) as f32 * 2.0 * PI;
                    let l = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
                    let d_omega = theta.sin() * (PI / 2.0 / steps as f32) * (PI / steps as f32);
                    sum += brdf_cos(Vec3::ONE, metallic, roughness, n, v, l).x * d_omega;
                }
            }
            assert!(sum <= 1.02 && sum > 0.5, "albedo {sum} for {metallic} {roughness}");
        }
    }
}
