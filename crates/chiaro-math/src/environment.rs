//! Image-based light: where an equirectangular image keeps each direction, its texels'
//! solid angles, and the split-sum approximation of the GGX BRDF under an environment
//! (Karis, "Real Shading in Unreal Engine 4", 2013) with the multiple-scattering energy
//! compensation of Fdez-Agüera ("A Multiple-Scattering Microfacet Model for Real-Time
//! Image-based Lighting", 2019). The shaders (`shaders/environment/`) are the GPU twins.

use crate::sh::ShRgb;
use glam::{Vec2, Vec3};
use std::f32::consts::{PI, TAU};

/// The equirectangular texture coordinate of unit direction `d`: u turns about +Y, with the
/// image's centre (u = 0.5) towards -Z (where an unrotated glTF camera looks); v runs from
/// +Y (v = 0, the top row) to -Y.
pub fn equirect_uv(d: Vec3) -> Vec2 {
    Vec2::new(0.5 + d.x.atan2(-d.z) / TAU, d.y.clamp(-1.0, 1.0).acos() / PI)
}

/// The unit direction at equirectangular coordinate `uv`; inverse of `equirect_uv`.
pub fn equirect_direction(uv: Vec2) -> Vec3 {
    let phi = (uv.x - 0.5) * TAU;
    let theta = uv.y * PI;
    let (sin_t, cos_t) = theta.sin_cos();
    Vec3::new(sin_t * phi.sin(), cos_t, -sin_t * phi.cos())
}

/// The solid angle (steradians) of row `y` of a `width` x `height` equirectangular image's
/// texels: exact for the band between its two latitudes.
pub fn equirect_texel_solid_angle(y: u32, width: u32, height: u32) -> f32 {
    let top = (y as f32 / height as f32 * PI).cos();
    let bottom = ((y + 1) as f32 / height as f32 * PI).cos();
    TAU / width as f32 * (top - bottom)
}

/// Turns world direction `d` into the environment image's frame, for an environment
/// turned `rotation_deg` about +Y (the inverse turn).
pub fn environment_direction(d: Vec3, rotation_deg: f32) -> Vec3 {
    let (s, c) = (-rotation_deg.to_radians()).sin_cos();
    Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
}

/// The radiance of an equirectangular image (`texels` row by row from the top) projected
/// onto nine spherical harmonic coefficients, each texel weighted by its solid angle.
pub fn project_equirect(texels: &[Vec3], width: u32, height: u32) -> ShRgb {
    let mut sh = ShRgb::default();
    for y in 0..height {
        let weight = equirect_texel_solid_angle(y, width, height);
        for x in 0..width {
            let uv = Vec2::new((x as f32 + 0.5) / width as f32, (y as f32 + 0.5) / height as f32);
            sh.add_sample(equirect_direction(uv), texels[(y * width + x) as usize], weight);
        }
    }
    sh
}

/// Point `i` of `n` of the Hammersley set on the unit square.
pub fn hammersley(i: u32, n: u32) -> Vec2 {
    Vec2::new((i as f32 + 0.5) / n as f32, i.reverse_bits() as f32 * (1.0 / 4_294_967_296.0))
}

/// A GGX half vector about +Z for square sample `xi` and alpha = roughness².
pub fn ggx_half_vector(xi: Vec2, alpha: f32) -> Vec3 {
    let phi = TAU * xi.x;
    let cos_t = ((1.0 - xi.y) / (1.0 + (alpha * alpha - 1.0) * xi.y)).max(0.0).sqrt();
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}

/// The split-sum BRDF terms (scale, bias) at `n_dot_v` and perceptual `roughness`: the
/// directional albedo of the glTF GGX lobe is `f0 * scale + bias` (Schlick's Fresnel).
/// Integrated with `samples` GGX-distributed half vectors; the device's table is made the
/// same way (`shaders/environment/brdf_table.wesl`).
pub fn split_sum(n_dot_v: f32, roughness: f32, samples: u32) -> Vec2 {
    let n_dot_v = n_dot_v.clamp(1e-4, 1.0);
    let v = Vec3::new((1.0 - n_dot_v * n_dot_v).sqrt(), 0.0, n_dot_v);
    let alpha = roughness * roughness;
    let mut sum = Vec2::ZERO;
    for i in 0..samples {
        let h = ggx_half_vector(hammersley(i, samples), alpha);
        let l = 2.0 * v.dot(h) * h - v;
        let (n_dot_l, n_dot_h, v_dot_h) = (l.z, h.z.max(0.0), v.dot(h).max(0.0));
        if n_dot_l > 0.0 {
            // pdf(l) = D n.h / (4 v.h); BRDF x cos / pdf with D cancelled.
            let g_vis = crate::brdf::v_smith_ggx_correlated(n_dot_v, n_dot_l, alpha) * 4.0 * n_dot_l * v_dot_h
                / n_dot_h.max(1e-6);
            let fc = (1.0 - v_dot_h).powi(5);
            sum += Vec2::new((1.0 - fc) * g_vis, fc * g_vis);
        }
    }
    sum / samples as f32
}

/// What a surface reflects of an environment, per unit of its incoming light: `specular`
/// multiplies the prefiltered radiance and `diffuse` the irradiance over pi (the cosine-
/// weighted mean radiance). Single scattering from the split sum `terms`, plus the energy
/// multiple scattering between microfacets returns, which keeps rough metals from
/// darkening; the diffuse lobe takes what the specular lobes leave.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IblWeights {
    pub specular: Vec3,
    pub diffuse: Vec3,
}

/// The weights of a glTF metallic-roughness surface under an environment, from the
/// split-sum `terms` at its n.v and roughness.
pub fn ibl_weights(base_color: Vec3, metallic: f32, terms: Vec2) -> IblWeights {
    let f0 = crate::brdf::f0_of(base_color, metallic);
    let single = f0 * terms.x + Vec3::splat(terms.y);
    let single_energy = terms.x + terms.y;
    let multiple_energy = 1.0 - single_energy;
    let mean_fresnel = f0 + (Vec3::ONE - f0) / 21.0;
    let multiple = single * mean_fresnel / (Vec3::ONE - multiple_energy * mean_fresnel);
    let diffuse_color = base_color * (1.0 - metallic);
    let left = (Vec3::ONE - single - multiple * multiple_energy).max(Vec3::ZERO);
    IblWeights { specular: single, diffuse: multiple * multiple_energy + diffuse_color * left }
}

/// The albedo of a glTF metallic-roughness surface seen from `n_dot_v`: of light arriving
/// evenly from every direction, the share it sends towards the eye, diffuse and specular
/// lobes together (`ibl_weights`' two weights summed, from the split-sum `terms` at that
/// n.v and roughness). It is what an environment light gives the surface, and what the
/// baker's bounces carry, so that baked bounced light and the realtime environment agree.
pub fn directional_albedo(base_color: Vec3, metallic: f32, terms: Vec2) -> Vec3 {
    let w = ibl_weights(base_color, metallic, terms);
    w.specular + w.diffuse
}

/// The hemispherical albedo of a glTF metallic-roughness surface: its `directional_albedo`
/// averaged over the cosine-weighted directions light leaves in, the split sum integrated
/// afresh (`samples` GGX samples) at each of `steps` angles. Of all the light a surface
/// receives, the share it reflects in all, what a closed room's energy balance turns on.
pub fn hemispherical_albedo(base_color: Vec3, metallic: f32, roughness: f32, steps: u32, samples: u32) -> Vec3 {
    (0..steps)
        .map(|k| {
            let mu = (k as f32 + 0.5) / steps as f32;
            directional_albedo(base_color, metallic, split_sum(mu, roughness, samples)) * (2.0 * mu / steps as f32)
        })
        .sum()
}

/// `split_sum` tabulated over n.v and roughness (both 0 to 1 in `SIZE` steps, ends
/// included) and read bilinearly: the baker looks it up at every bounce.
#[derive(Clone, Debug)]
pub struct SplitSumTable {
    terms: Vec<Vec2>,
}

impl SplitSumTable {
    /// Grid points along each axis.
    pub const SIZE: usize = 32;
    /// GGX samples per grid point.
    pub const SAMPLES: u32 = 1024;

    /// The table, integrated once per process (about a million GGX samples).
    pub fn shared() -> &'static SplitSumTable {
        static TABLE: std::sync::OnceLock<SplitSumTable> = std::sync::OnceLock::new();
        TABLE.get_or_init(SplitSumTable::new)
    }

    fn new() -> SplitSumTable {
        let step = 1.0 / (Self::SIZE - 1) as f32;
        let terms = (0..Self::SIZE * Self::SIZE)
            .map(|k| {
                let (i, j) = (k % Self::SIZE, k / Self::SIZE);
                split_sum(i as f32 * step, j as f32 * step, Self::SAMPLES)
            })
            .collect();
        SplitSumTable { terms }
    }

    /// The split-sum terms at `n_dot_v` and perceptual `roughness` (each clamped to 0..1).
    pub fn terms(&self, n_dot_v: f32, roughness: f32) -> Vec2 {
        let last = (Self::SIZE - 1) as f32;
        let x = n_dot_v.clamp(0.0, 1.0) * last;
        let y = roughness.clamp(0.0, 1.0) * last;
        let (i, j) = ((x as usize).min(Self::SIZE - 2), (y as usize).min(Self::SIZE - 2));
        let (fx, fy) = (x - i as f32, y - j as f32);
        let at = |i: usize, j: usize| self.terms[j * Self::SIZE + i];
        let top = at(i, j).lerp(at(i + 1, j), fx);
        let bottom = at(i, j + 1).lerp(at(i + 1, j + 1), fx);
        top.lerp(bottom, fy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_reads_the_split_sum_between_its_grid_points() {
        let table = SplitSumTable::shared();
        for (n_dot_v, roughness) in [(0.05, 0.1), (0.5, 0.5), (0.93, 0.77), (1.0, 1.0), (0.2, 0.97)] {
            let direct = split_sum(n_dot_v, roughness, 4096);
            let read = table.terms(n_dot_v, roughness);
            assert!((direct - read).abs().max_element() < 0.01, "{n_dot_v} {roughness}: {direct} vs {read}");
        }
    }

    #[test]
    fn the_directional_albedo_conserves_energy_and_whites_reflect_all() {
        let table = SplitSumTable::shared();
        for n_dot_v in [0.02, 0.3, 0.7, 1.0] {
            for roughness in [0.03, 0.4, 1.0] {
                let terms = table.terms(n_dot_v, roughness);
                // A white dielectric loses nothing: what the specular lobe leaves, the
                // diffuse lobe sends.
                let white = directional_albedo(Vec3::ONE, 0.0, terms);
                assert!((white - Vec3::ONE).abs().max_element() < 1e-4, "{white}");
                for (base, metallic) in [(Vec3::splat(0.5), 0.0), (Vec3::new(1.0, 0.8, 0.3), 1.0)] {
                    let a = directional_albedo(base, metallic, terms);
                    assert!(a.max_element() <= 1.0 + 1e-4 && a.min_element() > 0.0, "{a}");
                    // More than the diffuse share alone: the specular lobe reflects too.
                    assert!(a.x > crate::brdf::diffuse_albedo(base, metallic).x, "{a}");
                }
            }
        }
    }

    #[test]
    fn equirect_round_trips_and_centres_on_minus_z() {
        assert!(equirect_direction(Vec2::new(0.5, 0.5)).abs_diff_eq(Vec3::NEG_Z, 1e-6));
        assert!(equirect_direction(Vec2::new(0.75, 0.5)).abs_diff_eq(Vec3::X, 1e-6));
        assert!(equirect_direction(Vec2::new(0.3, 0.0)).abs_diff_eq(Vec3::Y, 1e-6));
        for d in [Vec3::new(0.3, 0.5, -0.8), Vec3::new(-0.9, -0.2, 0.1), Vec3::new(0.1, 0.2, 0.97)] {
            let d = d.normalize();
            assert!(equirect_direction(equirect_uv(d)).abs_diff_eq(d, 1e-5), "{d}");
        }
    }

    #[test]
    fn texel_solid_angles_cover_the_sphere() {
        let (w, h) = (64, 32);
        let total: f32 = (0..h).map(|y| equirect_texel_solid_angle(y, w, h) * w as f32).sum();
        assert!((total - 4.0 * PI).abs() < 1e-4, "{total}");
    }

    #[test]
    fn rotation_turns_the_image_about_y() {
        // The image turns with the angle (right-handed about +Y): turned 90 degrees, what
        // was towards +X is towards -Z.
        let d = environment_direction(Vec3::NEG_Z, 90.0);
        assert!(d.abs_diff_eq(Vec3::X, 1e-6), "{d}");
        assert!(environment_direction(Vec3::Y, 37.0).abs_diff_eq(Vec3::Y, 1e-6));
    }

    #[test]
    fn a_uniform_image_projects_to_its_irradiance() {
        let (w, h) = (64, 32);
        let texels = vec![Vec3::splat(2.0); (w * h) as usize];
        let sh = project_equirect(&texels, w, h);
        for n in [Vec3::Y, Vec3::NEG_X, Vec3::new(0.6, 0.0, 0.8)] {
            let e = sh.irradiance(n);
            assert!(e.abs_diff_eq(Vec3::splat(2.0 * PI), 2.0 * PI * 1e-3), "{e}");
        }
    }

    #[test]
    fn a_bright_upper_half_lights_upward_faces() {
        // Radiance 1 above the horizon, 0 below: irradiance pi facing up, 0 facing down,
        // pi / 2 on a wall; L2 gets within 10% of those.
        let (w, h) = (128, 64);
        let texels: Vec<Vec3> = (0..w * h).map(|i| if i / w < h / 2 { Vec3::ONE } else { Vec3::ZERO }).collect();
        let sh = project_equirect(&texels, w, h);
        assert!((sh.irradiance(Vec3::Y).x - PI).abs() < 0.1 * PI);
        assert!(sh.irradiance(Vec3::NEG_Y).x < 0.1 * PI);
        assert!((sh.irradiance(Vec3::X).x - PI / 2.0).abs() < 0.05 * PI);
    }

    #[test]
    fn split_sum_matches_known_limits() {
        // Smooth: the lobe is a mirror, so scale + bias = 1 (no energy lost) and the bias
        // is Schlick's (1 - n.v)^5.
        let smooth = split_sum(0.5, 0.02, 512);
        assert!((smooth.x + smooth.y - 1.0).abs() < 0.01, "{smooth}");
        assert!((smooth.y - 0.5f32.powi(5)).abs() < 0.01, "{smooth}");
        // Rough: single scattering loses energy (about 40% at grazing-to-normal averages).
        let rough = split_sum(0.5, 1.0, 4096);
        assert!(rough.x + rough.y < 0.9 && rough.x + rough.y > 0.4, "{rough}");
    }

    #[test]
    fn a_white_dielectric_and_a_white_metal_reflect_everything() {
        // The furnace: with energy compensation nothing is lost, whatever the roughness.
        for roughness in [0.1, 0.5, 1.0] {
            for n_dot_v in [0.2, 0.6, 1.0] {
                let terms = split_sum(n_dot_v, roughness, 1024);
                for metallic in [0.0, 1.0] {
                    let w = ibl_weights(Vec3::ONE, metallic, terms);
                    let total = w.specular + w.diffuse;
                    assert!(total.abs_diff_eq(Vec3::ONE, 1e-4), "{roughness} {n_dot_v} {metallic}: {total}");
                }
            }
        }
    }
}
