//! Linearly transformed cosines (Heitz, Dupuy, Hill and Neubelt 2016, "Real-time
//! polygonal-light shading with linearly transformed cosines"): the GGX lobe of
//! `crate::brdf` (F = 1) at each view angle and roughness approximated by a cosine lobe
//! seen through a 3x3 matrix, so that its integral over a polygon is Lambert's formula
//! on the polygon transformed by the inverse matrix.
//!
//! The table is ours: `fit_table` fits it with the paper's method (a Nelder-Mead search
//! for the matrix that minimises the cubed difference between lobe and BRDF, sampled
//! from both) against Chiaro's own BRDF, on the grid of the split-sum table, and
//! `cargo run --release -p chiaro-math --example fit_ltc` writes it to
//! `data/ltc_ggx.bin`. The lobe's magnitude and Fresnel terms are the split-sum table's
//! (the same integrals), so the table holds the matrix alone.

use crate::brdf::{d_ggx, v_smith_ggx_correlated};
use crate::environment::ggx_half_vector;
use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::PI;
use std::sync::OnceLock;

/// Cells per side of the table: n.v along X, perceptual roughness along Y, each sampled
/// at its cell's centre (the split-sum table's grid, so one lookup serves both).
pub const LTC_TABLE_SIZE: usize = 64;

/// Strata per side of the samples that measure a fit's error and the lobe's moments.
const FIT_SAMPLES_SIDE: u32 = 32;
/// Nelder-Mead iterations per cell.
const FIT_ITERATIONS: usize = 100;
/// Smallest alpha fitted: a mirror lobe has no finite matrix.
const MIN_ALPHA: f32 = 1.0e-5;

/// The n.v and perceptual roughness of cell (`i`, `j`).
pub fn cell_coordinates(i: usize, j: usize) -> (f32, f32) {
    ((i as f32 + 0.5) / LTC_TABLE_SIZE as f32, (j as f32 + 0.5) / LTC_TABLE_SIZE as f32)
}

/// The view direction in the shading frame (normal +Z, view in the X/Z plane).
pub fn local_view(n_dot_v: f32) -> Vec3 {
    Vec3::new((1.0 - n_dot_v * n_dot_v).max(0.0).sqrt(), 0.0, n_dot_v)
}

/// GGX specular BRDF times cos(theta_l) with F = 1, in the shading frame.
pub fn ggx_cos(v: Vec3, l: Vec3, alpha: f32) -> f32 {
    if l.z <= 0.0 || v.z <= 0.0 {
        return 0.0;
    }
    let h = (v + l).normalize_or_zero();
    d_ggx(h.z.clamp(0.0, 1.0), alpha) * v_smith_ggx_correlated(v.z, l.z, alpha) * l.z
}

/// Density of light directions drawn by `sample_ggx`.
fn ggx_pdf(v: Vec3, l: Vec3, alpha: f32) -> f32 {
    let h = (v + l).normalize_or_zero();
    let v_dot_h = v.dot(h);
    if l.z <= 0.0 || v_dot_h <= 0.0 {
        return 0.0;
    }
    d_ggx(h.z.clamp(0.0, 1.0), alpha) * h.z / (4.0 * v_dot_h)
}

/// A light direction reflected about a GGX half vector.
fn sample_ggx(v: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    let h = ggx_half_vector(u, alpha);
    2.0 * v.dot(h) * h - v
}

/// A clamped cosine lobe about +Z seen through `m`: the density of `m * w / |m * w|` for
/// w drawn from cos / pi.
#[derive(Clone, Copy, Debug)]
pub struct Ltc {
    m: Mat3,
    inverse: Mat3,
    inverse_determinant: f32,
}

impl Ltc {
    /// The lobe of matrix `m` (invertible).
    pub fn new(m: Mat3) -> Ltc {
        let inverse = m.inverse();
        Ltc { m, inverse, inverse_determinant: inverse.determinant().abs() }
    }

    /// Its density at unit direction `l` (integrates to 1 over the sphere).
    pub fn density(&self, l: Vec3) -> f32 {
        let original = self.inverse * l;
        let length = original.length();
        let cosine = (original.z / length).max(0.0);
        cosine / PI * self.inverse_determinant / (length * length * length)
    }

    /// A direction drawn from it for a point of the unit square.
    pub fn sample(&self, u: Vec2) -> Vec3 {
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let w = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u.x).max(0.0).sqrt());
        (self.m * w).normalize()
    }
}

/// One cell of the table.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LtcCell {
    /// The inverse matrix, divided by its middle element (the lobe does not change with
    /// the matrix's scale), as its four other non-zero entries: column 0's x and z,
    /// column 2's x and z. Its middle element is 1 and the rest are zero.
    pub inverse: [f32; 4],
    /// The fitted (m11, m22, m13) of the matrix in the frame of the lobe's mean direction.
    pub params: [f32; 3],
    /// Angle from the normal of the lobe's mean direction, radians (towards +X).
    pub mean_angle: f32,
}

impl LtcCell {
    /// The inverse matrix in the shading frame.
    pub fn inverse_matrix(&self) -> Mat3 {
        let [a, b, c, d] = self.inverse;
        Mat3::from_cols(Vec3::new(a, 0.0, b), Vec3::Y, Vec3::new(c, 0.0, d))
    }
}

/// The matrix of fitted `params` in the frame whose Z is at `mean_angle` from the normal.
fn matrix_of(params: [f32; 3], mean_angle: f32) -> Mat3 {
    let (s, c) = mean_angle.sin_cos();
    let frame = Mat3::from_cols(Vec3::new(c, 0.0, -s), Vec3::Y, Vec3::new(s, 0.0, c));
    let [m11, m22, m13] = params;
    frame
        * Mat3::from_cols(
            Vec3::new(m11.max(1e-7), 0.0, 0.0),
            Vec3::new(0.0, m22.max(1e-7), 0.0),
            Vec3::new(m13, 0.0, 1.0),
        )
}

fn stratum(i: u32, j: u32) -> Vec2 {
    Vec2::new((i as f32 + 0.5) / FIT_SAMPLES_SIDE as f32, (j as f32 + 0.5) / FIT_SAMPLES_SIDE as f32)
}

/// The GGX lobe's albedo (F = 1) and the angle of its mean direction from the normal.
fn lobe_moments(v: Vec3, alpha: f32) -> (f32, f32) {
    let mut albedo = 0.0;
    let mut mean = Vec3::ZERO;
    for j in 0..FIT_SAMPLES_SIDE {
        for i in 0..FIT_SAMPLES_SIDE {
            let l = sample_ggx(v, alpha, stratum(i, j));
            let pdf = ggx_pdf(v, l, alpha);
            if pdf > 0.0 {
                let weight = ggx_cos(v, l, alpha) / pdf;
                albedo += weight;
                mean += l * weight;
            }
        }
    }
    let n = (FIT_SAMPLES_SIDE * FIT_SAMPLES_SIDE) as f32;
    // An isotropic lobe's mean has no Y; what sampling leaves there is noise.
    let angle = mean.x.atan2(mean.z).clamp(0.0, PI * 0.5);
    (albedo / n, angle)
}

/// The paper's fit error: |BRDF - albedo x lobe|^3 over samples drawn from both, weighted
/// by the balance heuristic.
fn fit_error(ltc: &Ltc, v: Vec3, alpha: f32, albedo: f32) -> f64 {
    let mut error = 0.0f64;
    for j in 0..FIT_SAMPLES_SIDE {
        for i in 0..FIT_SAMPLES_SIDE {
            let u = stratum(i, j);
            for l in [ltc.sample(u), sample_ggx(v, alpha, u)] {
                let brdf = ggx_cos(v, l, alpha);
                let pdf_brdf = ggx_pdf(v, l, alpha);
                let lobe = ltc.density(l);
                let difference = (brdf - albedo * lobe).abs() as f64;
                let pdf_sum = (pdf_brdf + lobe) as f64;
                if pdf_sum > 0.0 {
                    error += difference.powi(3) / pdf_sum;
                }
            }
        }
    }
    error / (FIT_SAMPLES_SIDE * FIT_SAMPLES_SIDE) as f64
}

/// Minimises `f` over three parameters from `start` (Nelder and Mead's simplex, with the
/// usual reflection 1, expansion 2, contraction and shrink 1/2).
fn nelder_mead(f: impl Fn([f32; 3]) -> f64, start: [f32; 3], step: f32, iterations: usize) -> [f32; 3] {
    let mut simplex: Vec<([f32; 3], f64)> = (0..4)
        .map(|k| {
            let mut p = start;
            if k > 0 {
                p[k - 1] += step;
            }
            (p, f(p))
        })
        .collect();
    let along = |a: [f32; 3], b: [f32; 3], t: f32| [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * t);
    for _ in 0..iterations {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let centroid = [0, 1, 2].map(|k| (simplex[0].0[k] + simplex[1].0[k] + simplex[2].0[k]) / 3.0);
        let (worst, worst_error) = simplex[3];
        let reflected = along(centroid, worst, -1.0);
        let reflected_error = f(reflected);
        if reflected_error < simplex[0].1 {
            let expanded = along(centroid, worst, -2.0);
            let expanded_error = f(expanded);
            simplex[3] = if expanded_error < reflected_error {
                (expanded, expanded_error)
            } else {
                (reflected, reflected_error)
            };
        } else if reflected_error < simplex[2].1 {
            simplex[3] = (reflected, reflected_error);
        } else {
            let contracted = along(centroid, worst, 0.5);
            let contracted_error = f(contracted);
            if contracted_error < worst_error {
                simplex[3] = (contracted, contracted_error);
            } else {
                let best = simplex[0].0;
                for vertex in simplex.iter_mut().skip(1) {
                    vertex.0 = along(best, vertex.0, 0.5);
                    vertex.1 = f(vertex.0);
                }
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    simplex[0].0
}

/// Fits the cell at `n_dot_v` and perceptual `roughness`, searching from `start`'s
/// (m11, m22, m13).
pub fn fit_cell(n_dot_v: f32, roughness: f32, start: [f32; 3]) -> LtcCell {
    let v = local_view(n_dot_v);
    let alpha = (roughness * roughness).max(MIN_ALPHA);
    let (albedo, mean_angle) = lobe_moments(v, alpha);
    let params =
        nelder_mead(|p| fit_error(&Ltc::new(matrix_of(p, mean_angle)), v, alpha, albedo), start, 0.05, FIT_ITERATIONS);
    let mut inverse = matrix_of(params, mean_angle).inverse();
    inverse *= 1.0 / inverse.y_axis.y;
    LtcCell { inverse: [inverse.x_axis.x, inverse.x_axis.z, inverse.z_axis.x, inverse.z_axis.z], params, mean_angle }
}

/// Where the fit of cell (`i`, `j`) starts: the fit of the cell one step towards normal
/// incidence in the same row, or, for the row's first (n.v nearest 1), the cell one step
/// rougher; the roughest first cell starts from the identity.
pub fn fit_start(table: &[LtcCell], i: usize, j: usize) -> [f32; 3] {
    let n = LTC_TABLE_SIZE;
    if i + 1 < n {
        table[j * n + i + 1].params
    } else if j + 1 < n {
        table[(j + 1) * n + i].params
    } else {
        [1.0, 1.0, 0.0]
    }
}

/// Fits the whole table, row-major (n.v along a row), on `threads` threads: the cells
/// nearest normal incidence first, roughest to smoothest, then each row from there
/// towards grazing. Deterministic.
pub fn fit_table(threads: usize) -> Vec<LtcCell> {
    let n = LTC_TABLE_SIZE;
    let mut table = vec![LtcCell::default(); n * n];
    for j in (0..n).rev() {
        let (n_dot_v, roughness) = cell_coordinates(n - 1, j);
        table[j * n + n - 1] = fit_cell(n_dot_v, roughness, fit_start(&table, n - 1, j));
    }
    let rows: Vec<&mut [LtcCell]> = table.chunks_mut(n).collect();
    let threads = threads.max(1);
    std::thread::scope(|scope| {
        let mut shares: Vec<Vec<(usize, &mut [LtcCell])>> = (0..threads).map(|_| Vec::new()).collect();
        for (j, row) in rows.into_iter().enumerate() {
            shares[j % threads].push((j, row));
        }
        for share in shares {
            scope.spawn(move || {
                for (j, row) in share {
                    for i in (0..n - 1).rev() {
                        let (n_dot_v, roughness) = cell_coordinates(i, j);
                        row[i] = fit_cell(n_dot_v, roughness, row[i + 1].params);
                    }
                }
            });
        }
    });
    table
}

/// Little-endian f32s, eight a cell: `inverse`, `params`, `mean_angle`.
pub fn encode_table(table: &[LtcCell]) -> Vec<u8> {
    table
        .iter()
        .flat_map(|c| c.inverse.into_iter().chain(c.params).chain([c.mean_angle]))
        .flat_map(f32::to_le_bytes)
        .collect()
}

/// The inverse of `encode_table`; `None` where the bytes are not a whole table.
pub fn decode_table(bytes: &[u8]) -> Option<Vec<LtcCell>> {
    if bytes.len() != LTC_TABLE_SIZE * LTC_TABLE_SIZE * 32 {
        return None;
    }
    let floats: Vec<f32> = bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    Some(
        floats
            .chunks_exact(8)
            .map(|f| LtcCell { inverse: [f[0], f[1], f[2], f[3]], params: [f[4], f[5], f[6]], mean_angle: f[7] })
            .collect(),
    )
}

/// The fitted table shipped with the crate (`data/ltc_ggx.bin`), row-major by roughness.
pub fn table() -> &'static [LtcCell] {
    static TABLE: OnceLock<Vec<LtcCell>> = OnceLock::new();
    TABLE.get_or_init(|| {
        decode_table(include_bytes!("../data/ltc_ggx.bin")).expect("data/ltc_ggx.bin holds a whole LTC table")
    })
}

/// The inverse matrix at `n_dot_v` and perceptual `roughness`, interpolated between cell
/// centres and clamped at the edges as the GPU's filtered lookup does.
pub fn inverse_at(n_dot_v: f32, roughness: f32) -> Mat3 {
    let n = LTC_TABLE_SIZE;
    let coordinate = |t: f32| (t.clamp(0.0, 1.0) * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
    let (x, y) = (coordinate(n_dot_v), coordinate(roughness));
    let (i0, j0) = (x.floor() as usize, y.floor() as usize);
    let (i1, j1) = ((i0 + 1).min(n - 1), (j0 + 1).min(n - 1));
    let (tx, ty) = (x - i0 as f32, y - j0 as f32);
    let t = table();
    let value = |k: usize| {
        let at = |i: usize, j: usize| t[j * n + i].inverse[k];
        let top = at(i0, j0) + (at(i1, j0) - at(i0, j0)) * tx;
        let bottom = at(i0, j1) + (at(i1, j1) - at(i0, j1)) * tx;
        top + (bottom - top) * ty
    };
    LtcCell { inverse: [value(0), value(1), value(2), value(3)], ..LtcCell::default() }.inverse_matrix()
}

/// The integral over a polygon (vertices relative to the receiver, in the shading frame)
/// of the lobe whose inverse matrix is `inverse`: the form factor of the transformed
/// polygon clipped to the horizon, the LTC's share of the lobe the polygon covers. The
/// shader's `clipped_form_factor_vector` computes the same.
pub fn polygon_integral(inverse: Mat3, points: &[Vec3]) -> f32 {
    let transformed: Vec<Vec3> = points.iter().map(|&p| inverse * p).collect();
    crate::area_light::projected_solid_angle(&transformed, Vec3::Z) / PI
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn the_shipped_table_is_what_the_fitter_makes() {
        // Refit a spread of cells from the stored starting points: the same numbers.
        let t = table();
        let n = LTC_TABLE_SIZE;
        for (i, j) in [(63, 63), (63, 10), (40, 40), (5, 50), (20, 8), (1, 30), (60, 2), (30, 20)] {
            let (n_dot_v, roughness) = cell_coordinates(i, j);
            let refit = fit_cell(n_dot_v, roughness, fit_start(t, i, j));
            let stored = t[j * n + i];
            for k in 0..4 {
                let tolerance = 1e-3 * stored.inverse[k].abs().max(1.0);
                assert!(
                    (refit.inverse[k] - stored.inverse[k]).abs() <= tolerance,
                    "cell ({i}, {j}) entry {k}: {} vs {}",
                    refit.inverse[k],
                    stored.inverse[k]
                );
            }
        }
    }

    #[test]
    fn a_lobe_density_integrates_to_one() {
        let ltc = Ltc::new(matrix_of([0.4, 0.7, 0.2], 0.5));
        let n = 256;
        let mut sum = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let d = crate::sampling::sphere_direction((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                sum += ltc.density(d) as f64;
            }
        }
        let integral = sum * 4.0 * std::f64::consts::PI / (n * n) as f64;
        assert!((integral - 1.0).abs() < 0.01, "{integral}");
    }

    /// The GGX lobe's integral over a rect by brute force: the rect sampled on a grid.
    fn brute_force(v: Vec3, alpha: f32, corner: Vec3, edge_a: Vec3, edge_b: Vec3) -> f32 {
        let n = 300;
        let area = edge_a.cross(edge_b).length();
        let normal = edge_a.cross(edge_b).normalize();
        let mut sum = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let p = corner + edge_a * ((i as f32 + 0.5) / n as f32) + edge_b * ((j as f32 + 0.5) / n as f32);
                let d2 = p.length_squared();
                let l = p / d2.sqrt();
                let solid_angle = area / (n * n) as f32 * l.dot(normal).abs() / d2;
                sum += (ggx_cos(v, l, alpha) * solid_angle) as f64;
            }
        }
        sum as f32
    }

    #[test]
    fn the_table_reproduces_the_ggx_lobe_over_rects() {
        // A 1 x 1 m rect 2 m away around the mirror direction, and one off to the side:
        // albedo times the LTC integral against the BRDF integrated over the rect.
        for (n_dot_v, roughness) in [(0.9f32, 0.5f32), (0.5, 0.3), (0.7, 0.8), (0.3, 0.6)] {
            let v = local_view(n_dot_v);
            let alpha = roughness * roughness;
            let mirror = Vec3::new(-v.x, 0.0, v.z);
            for offset in [Vec3::ZERO, Vec3::new(0.0, 0.6, 0.0)] {
                let centre = mirror * 2.0 + offset;
                let edge_a = Vec3::Y.cross(mirror).normalize();
                let edge_b = mirror.cross(edge_a).normalize();
                let corner = centre - (edge_a + edge_b) * 0.5;
                let points = [corner, corner + edge_a, corner + edge_a + edge_b, corner + edge_b];
                let albedo = crate::environment::SplitSumTable::shared().terms(n_dot_v, roughness);
                let ltc = (albedo.x + albedo.y) * polygon_integral(inverse_at(n_dot_v, roughness), &points);
                let exact = brute_force(v, alpha, corner, edge_a, edge_b);
                assert!(
                    (ltc / exact - 1.0).abs() < 0.1,
                    "n.v {n_dot_v} roughness {roughness} offset {offset}: {ltc} vs {exact}"
                );
            }
        }
    }
}
