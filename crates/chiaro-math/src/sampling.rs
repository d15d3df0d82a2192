//! Directions drawn from points of the unit square, for the CPU tracers (the baker and the
//! reference): cosine-weighted about a normal, or uniform on the sphere, an orthonormal
//! basis around a unit vector, and the stratified points of the square they start from.

use glam::{Vec2, Vec3};
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

/// Chiu, Shirley and Wang's multi-jittered points of the unit square (1994): `side` x
/// `side` points, one in each cell of a `side` x `side` grid and at the same time one in
/// each of `side`^2 columns and `side`^2 rows. A straight edge along either axis thus
/// splits them `side`^2 ways (a shadow edge along a light's side is judged as finely as
/// if every sample had a strip of its own), and an edge at any angle at least `side`
/// ways. `random` gives floats in [0, 1): the jitter and the shuffles.
pub fn multi_jittered(side: usize, random: &mut impl FnMut() -> f32) -> Vec<Vec2> {
    let strips = side * side;
    // The canonical arrangement, as fine column and row indices: point (i, j) in cell
    // (i, j), at sub-column j of column i and sub-row i of row j.
    let mut columns: Vec<usize> = (0..strips).map(|k| (k % side) * side + k / side).collect();
    let mut rows: Vec<usize> = (0..strips).map(|k| (k / side) * side + k % side).collect();
    let pick = |from: usize, random: &mut dyn FnMut() -> f32| {
        from + ((random() * (side - from) as f32) as usize).min(side - from - 1)
    };
    // Shuffling the sub-columns within each column (and sub-rows within each row) keeps
    // every cell, column and row holding one point.
    for i in 0..side {
        for j in 0..side {
            columns.swap(j * side + i, pick(j, random) * side + i);
        }
    }
    for j in 0..side {
        for i in 0..side {
            rows.swap(j * side + i, j * side + pick(i, random));
        }
    }
    // Jittered within its strip, and below the strip's end even after rounding.
    let n = strips as f32;
    let below_one = 1.0 - n * f32::EPSILON;
    let mut at = |strip: usize| (strip as f32 + random().min(below_one)) / n;
    columns.iter().zip(&rows).map(|(&column, &row)| Vec2::new(at(column), at(row))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multi_jittered_points_fill_every_cell_column_and_row_once() {
        let mut state = 12345u32;
        let mut random = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        let side = 8;
        let points = multi_jittered(side, &mut random);
        assert_eq!(points.len(), 64);
        let fine = |v: f32| (v * 64.0) as usize;
        let coarse = |v: f32| (v * 8.0) as usize;
        let mut columns: Vec<usize> = points.iter().map(|p| fine(p.x)).collect();
        let mut rows: Vec<usize> = points.iter().map(|p| fine(p.y)).collect();
        let mut cells: Vec<usize> = points.iter().map(|p| coarse(p.y) * side + coarse(p.x)).collect();
        for list in [&mut columns, &mut rows, &mut cells] {
            list.sort_unstable();
            assert_eq!(*list, (0..64).collect::<Vec<_>>());
        }
        // Shuffled: not the canonical arrangement, whose sub-column follows the row.
        let canonical_x = points.iter().filter(|p| fine(p.x) % side == coarse(p.y)).count();
        let canonical_y = points.iter().filter(|p| fine(p.y) % side == coarse(p.x)).count();
        assert!(canonical_x < 32, "{canonical_x} points where the canonical arrangement puts their x");
        assert!(canonical_y < 32, "{canonical_y} points where the canonical arrangement puts their y");
        // The largest float below 1 as every draw: each point stays inside its strip.
        let edge = multi_jittered(side, &mut || 1.0 - f32::EPSILON / 2.0);
        let mut strips: Vec<usize> = edge.iter().map(|p| fine(p.x)).collect();
        strips.sort_unstable();
        assert_eq!(strips, (0..64).collect::<Vec<_>>());
        assert!(edge.iter().all(|p| p.x < 1.0 && p.y < 1.0));
    }

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
