//! Directions drawn from points of the unit square, for the CPU tracers (the baker and the
//! reference): cosine-weighted about a normal, or uniform on the sphere, and an
//! orthonormal basis around a unit vector.

use glam::Vec3;
use std::f32::consts::PI;

/// Unit vectors perpendicular to unit `n` and to each other (Duff et al. 2017).
pub fn basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// A cosine-weighted direction about `n` from a point of the unit square.
pub fn cosine_direction(n: Vec3, u: f32, v: f32) -> Vec3 {
    let (t, b) = basis(n);
    let r = u.sqrt();
    let phi = 2.0 * PI * v;
    (t * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u).max(0.0).sqrt()).normalize_or_zero()
}

/// A uniform direction on the sphere from a point of the unit square.
pub fn sphere_direction(u: f32, v: f32) -> Vec3 {
    let z = 1.0 - 2.0 * u;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * v;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cosine_directions_have_the_cosine_mean() {
        // E[cos] under a cosine-weighted pdf is 2/3.
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        let mut sum = 0.0;
        let m = 64;
        for i in 0..m {
            for j in 0..m {
                let d = cosine_direction(n, (i as f32 + 0.5) / m as f32, (j as f32 + 0.5) / m as f32);
                assert!((d.length() - 1.0).abs() < 1e-4);
                sum += d.dot(n);
            }
        }
        let mean = sum / (m * m) as f32;
        assert!((mean - 2.0 / 3.0).abs() < 1e-3, "{mean}");
    }

    #[test]
    fn basis_is_orthonormal_for_any_normal() {
        for n in [Vec3::Z, Vec3::NEG_Z, Vec3::X, Vec3::new(0.2, 0.9, -0.1).normalize()] {
            let (t, b) = basis(n);
            assert!(t.dot(n).abs() < 1e-5 && b.dot(n).abs() < 1e-5 && t.dot(b).abs() < 1e-5);
            assert!((t.length() - 1.0).abs() < 1e-5 && (b.length() - 1.0).abs() < 1e-5);
        }
    }
}
