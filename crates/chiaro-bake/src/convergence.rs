//! How far a bake's lightmaps are from a reference bake of the same scene and layout (one
//! with many more samples): the relative error of every texel a surface wholly covers.
//! Used by the tests and `examples/bake_error.rs` to measure noise and denoising.

use chiaro_scene::baked::Lightmap;

fn luminance(t: &[f32; 4]) -> f32 {
    chiaro_math::tonemap::luminance(glam::Vec3::new(t[0], t[1], t[2]))
}

/// Texels darker than this share of the reference's mean are left out: they look black
/// beside the rest, and their relative error is mostly the reference's own noise.
pub const DARK_SHARE: f32 = 0.01;

/// Each wholly covered, lit texel's relative error against `reference`, sorted: the sum
/// of the RGB differences over the sum of the reference's RGB (colour noise counts as
/// much as brightness noise). Both bakes must share their layout.
pub fn texel_errors(test: &[Lightmap], reference: &[Lightmap]) -> Vec<f32> {
    let covered = |t: &&[f32; 4]| t[3] >= 0.999;
    let (sum, count) = reference
        .iter()
        .flat_map(|m| m.texels.iter())
        .filter(covered)
        .fold((0.0f64, 0u64), |(s, n), t| (s + luminance(t) as f64, n + 1));
    let floor = DARK_SHARE * (sum / count.max(1) as f64) as f32;
    let mut errors: Vec<f32> = test
        .iter()
        .zip(reference)
        .flat_map(|(a, b)| a.texels.iter().zip(&b.texels))
        .filter(|(_, r)| covered(r) && luminance(r) > floor)
        .map(|(t, r)| ((t[0] - r[0]).abs() + (t[1] - r[1]).abs() + (t[2] - r[2]).abs()) / (r[0] + r[1] + r[2]))
        .collect();
    errors.sort_by(f32::total_cmp);
    errors
}

/// The `p` quantile (0 to 1) of sorted `values`; 0 for none.
pub fn quantile(sorted: &[f32], p: f32) -> f32 {
    if sorted.is_empty() {
        return 0.0;
    }
    sorted[((sorted.len() - 1) as f32 * p.clamp(0.0, 1.0)).round() as usize]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(texels: Vec<[f32; 4]>) -> Lightmap {
        Lightmap { width: texels.len() as u32, height: 1, texels }
    }

    #[test]
    fn errors_are_relative_and_skip_uncovered_and_dark_texels() {
        let reference = [map(vec![[1.0; 4], [2.0, 2.0, 2.0, 1.0], [5.0, 5.0, 5.0, 0.5], [0.0, 0.0, 0.0, 1.0]])];
        let test = [map(vec![[1.1, 1.0, 1.0, 1.0], [2.0, 2.0, 2.6, 1.0], [0.0; 4], [3.0; 4]])];
        let e = texel_errors(&test, &reference);
        assert_eq!(e.len(), 2);
        assert!((e[0] - 0.1 / 3.0).abs() < 1e-6 && (e[1] - 0.1).abs() < 1e-6, "{e:?}");
        assert_eq!(quantile(&e, 0.0), e[0]);
        assert_eq!(quantile(&e, 1.0), e[1]);
    }
}
