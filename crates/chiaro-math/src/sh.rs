//! Order-2 (L2, nine coefficients) real spherical harmonics for light probes: projecting
//! incoming radiance, and turning it into irradiance for a normal with the clamped-cosine
//! convolution of Ramamoorthi and Hanrahan. The shader (`shaders/lighting/baked.wesl`)
//! evaluates the same basis and bands.

use glam::Vec3;
use std::f32::consts::PI;

pub const SH_COEFFICIENTS: usize = 9;

/// The clamped-cosine lobe's weight per band (0, 1, 2): irradiance is radiance's
/// coefficients times these.
pub const COSINE_BANDS: [f32; 3] = [PI, 2.0 * PI / 3.0, PI / 4.0];

/// The nine basis functions at unit direction `d`, in the order (l, m) = (0,0), (1,-1),
/// (1,0), (1,1), (2,-2), (2,-1), (2,0), (2,1), (2,2).
pub fn basis(d: Vec3) -> [f32; SH_COEFFICIENTS] {
    let Vec3 { x, y, z } = d;
    [
        0.282_094_8,
        0.488_602_5 * y,
        0.488_602_5 * z,
        0.488_602_5 * x,
        1.092_548_4 * x * y,
        1.092_548_4 * y * z,
        0.315_391_57 * (3.0 * z * z - 1.0),
        1.092_548_4 * x * z,
        0.546_274_2 * (x * x - y * y),
    ]
}

/// The band of each coefficient.
const BAND: [usize; SH_COEFFICIENTS] = [0, 1, 1, 1, 2, 2, 2, 2, 2];

/// RGB radiance over the sphere in nine coefficients.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShRgb {
    pub coefficients: [Vec3; SH_COEFFICIENTS],
}

impl ShRgb {
    /// Adds radiance `value` arriving from unit direction `d` for a sample of solid angle
    /// `weight` (4 pi / N for N uniform directions).
    pub fn add_sample(&mut self, d: Vec3, value: Vec3, weight: f32) {
        for (c, y) in self.coefficients.iter_mut().zip(basis(d)) {
            *c += value * (y * weight);
        }
    }

    /// Adds a light that arrives from unit direction `d` alone (a punctual light), giving
    /// illuminance `irradiance` on a surface facing it.
    pub fn add_delta(&mut self, d: Vec3, irradiance: Vec3) {
        self.add_sample(d, irradiance, 1.0);
    }

    pub fn scaled(&self, factor: f32) -> ShRgb {
        ShRgb { coefficients: self.coefficients.map(|c| c * factor) }
    }

    pub fn lerp(&self, other: &ShRgb, t: f32) -> ShRgb {
        let mut out = *self;
        for (o, b) in out.coefficients.iter_mut().zip(other.coefficients) {
            *o = o.lerp(b, t);
        }
        out
    }

    /// The radiance the coefficients reconstruct in direction `d`.
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        self.coefficients.iter().zip(basis(d)).map(|(c, y)| *c * y).sum()
    }

    /// Irradiance on a surface with unit normal `n`, never negative (L2 rings below zero
    /// opposite strong lights).
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        let e: Vec3 =
            self.coefficients.iter().zip(basis(n)).zip(BAND).map(|((c, y), band)| *c * (y * COSINE_BANDS[band])).sum();
        e.max(Vec3::ZERO)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Directions on a Fibonacci sphere, nearly uniform.
    fn sphere(n: usize) -> Vec<Vec3> {
        let golden = PI * (3.0 - 5f32.sqrt());
        (0..n)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
                let r = (1.0 - z * z).sqrt();
                let phi = golden * i as f32;
                Vec3::new(r * phi.cos(), r * phi.sin(), z)
            })
            .collect()
    }

    fn project(f: impl Fn(Vec3) -> Vec3) -> ShRgb {
        let directions = sphere(20_000);
        let weight = 4.0 * PI / directions.len() as f32;
        let mut sh = ShRgb::default();
        for d in directions {
            sh.add_sample(d, f(d), weight);
        }
        sh
    }

    #[test]
    fn basis_is_orthonormal() {
        let directions = sphere(20_000);
        let weight = 4.0 * PI / directions.len() as f32;
        for i in 0..SH_COEFFICIENTS {
            for j in 0..SH_COEFFICIENTS {
                let dot: f32 = directions.iter().map(|&d| basis(d)[i] * basis(d)[j] * weight).sum();
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((dot - expected).abs() < 2e-3, "<Y{i}, Y{j}> = {dot}");
            }
        }
    }

    #[test]
    fn constant_radiance_gives_pi_times_it_everywhere() {
        let sh = project(|_| Vec3::new(1.0, 2.0, 0.5));
        for n in sphere(50) {
            let error = (sh.irradiance(n) - Vec3::new(PI, 2.0 * PI, 0.5 * PI)).abs().max_element();
            // Quadrature error of 20,000 Fibonacci points: 0.05% of 2 pi.
            assert!(error < 3e-3, "{n}: {error}");
            assert!((sh.radiance(n) - Vec3::new(1.0, 2.0, 0.5)).abs().max_element() < 1e-3);
        }
    }

    #[test]
    fn quadratic_functions_are_reconstructed_exactly() {
        // Any polynomial of degree two on the sphere lies in the first three bands.
        let f = |d: Vec3| Vec3::splat(1.0 + 0.5 * d.x - 0.25 * d.z + 0.75 * d.x * d.y + 0.3 * d.z * d.z);
        let sh = project(f);
        for d in sphere(40) {
            assert!((sh.radiance(d) - f(d)).abs().max_element() < 2e-3, "{d}");
        }
    }

    #[test]
    fn irradiance_of_a_linear_sky_is_analytic() {
        // Radiance 1 + z: E(n) = pi + (2 pi / 3) n.z, exactly (bands 0 and 1).
        let sh = project(|d| Vec3::splat(1.0 + d.z));
        for n in sphere(40) {
            let expected = PI + 2.0 * PI / 3.0 * n.z;
            assert!((sh.irradiance(n).x - expected).abs() < 2e-3, "{n}: {} vs {expected}", sh.irradiance(n).x);
        }
    }

    #[test]
    fn a_delta_light_gives_close_to_cosine_irradiance() {
        // L2 approximates max(0, cos) with a known error: 1.0625 head-on, 0.5 at 90 degrees
        // would be exact for the band-limited cosine; check the shape within 0.1 of E0.
        let mut sh = ShRgb::default();
        sh.add_delta(Vec3::Z, Vec3::ONE);
        assert!((sh.irradiance(Vec3::Z).x - 1.0625).abs() < 1e-3);
        for n in sphere(200) {
            let exact = n.z.max(0.0);
            assert!((sh.irradiance(n).x - exact).abs() < 0.1, "{n}");
        }
    }
}
