//! A rendered ambient occlusion against the traced one.
//!
//! The rendered AO per pixel (1 open, 0 enclosed), the rendered world positions and a
//! `chiaro_trace::OcclusionReference` flow in; an `OcclusionReport` flows out: how far the
//! rendered AO is from the traced one over the surfaces both see at the same place (all of
//! them, and the occluded ones alone, where a screen-space AO's misses show), which way it
//! errs, and a signed difference picture.
//!
//! Pixels are matched as the shadow verdicts match them (`verdict::same_surface`): the
//! reference sees a surface and the rendered position lies within `POSITION_TOLERANCE_M`
//! of it. A non-finite rendered AO on such a pixel is counted, as off by 1.

use crate::verdict::{same_surface, signed_difference_color};
use chiaro_trace::OcclusionReference;
use glam::Vec3;
use rayon::prelude::*;

/// Traced AO below this marks an occluded pixel (the definition).
pub const OCCLUDED_BELOW: f32 = 0.9;

/// How far a rendered AO is from the traced one.
#[derive(Clone, Debug)]
pub struct OcclusionReport {
    /// Pixels compared: both see a surface, at the same place.
    pub surfaces: usize,
    /// Compared pixels whose traced AO is below `OCCLUDED_BELOW`.
    pub occluded: usize,
    /// Mean |rendered - traced| over surfaces both see at the same place.
    pub mean_error: f32,
    /// The same over the pixels whose traced AO is below `OCCLUDED_BELOW` (0 where none).
    pub mean_error_occluded: f32,
    /// 95th percentile of |rendered - traced| over surfaces.
    pub p95_error: f32,
    /// Mean signed rendered - traced over surfaces (positive: too bright).
    pub mean_signed_error: f32,
    /// RGBA8 picture of the signed difference per pixel (`signed_difference_color`: red
    /// too dark, blue too bright, black not compared), for `compare --diff`.
    pub difference: Vec<[u8; 4]>,
}

/// One compared pixel: rendered - traced, and the traced AO.
#[derive(Clone, Copy)]
struct Compared {
    signed_error: f32,
    traced: f32,
}

/// Judges `rendered_ao` (with the world positions the renderer shaded, `None` on the
/// sky), row-major like `reference`, against the traced AO. Pixels missing from the
/// rendered arrays are not compared; a reference whose arrays do not match its size
/// compares nothing.
pub fn compare_occlusion(
    rendered_ao: &[f32],
    rendered_position: &[Option<Vec3>],
    reference: &OcclusionReference,
) -> OcclusionReport {
    let compared = compared_pixels(rendered_ao, rendered_position, reference);
    // The colour depends on the difference only, so the traced value can stand at 0.
    let difference: Vec<[u8; 4]> =
        compared.iter().map(|pixel| signed_difference_color(pixel.map(|c| (c.signed_error, 0.0)))).collect();
    let compared: Vec<Compared> = compared.into_iter().flatten().collect();
    let mut errors: Vec<f32> = compared.iter().map(|c| c.signed_error.abs()).collect();
    let occluded: Vec<f32> =
        compared.iter().filter(|c| c.traced < OCCLUDED_BELOW).map(|c| c.signed_error.abs()).collect();
    errors.sort_by(f32::total_cmp);
    let n = errors.len();
    OcclusionReport {
        surfaces: n,
        occluded: occluded.len(),
        mean_error: mean(&errors),
        mean_error_occluded: mean(&occluded),
        // The smallest error at least 95% of the pixels stay within, as soft shadows count it.
        p95_error: if n == 0 { 0.0 } else { errors[((n as f64 * 0.95).ceil() as usize).clamp(1, n) - 1] },
        mean_signed_error: mean(&compared.iter().map(|c| c.signed_error).collect::<Vec<_>>()),
        difference,
    }
}

/// Per reference pixel, the comparison where both see the same surface, `None` elsewhere.
fn compared_pixels(
    rendered_ao: &[f32],
    rendered_position: &[Option<Vec3>],
    reference: &OcclusionReference,
) -> Vec<Option<Compared>> {
    let pixels = reference.width as usize * reference.height as usize;
    if reference.ao.len() != pixels || reference.position.len() != pixels {
        return vec![None; pixels];
    }
    (0..pixels)
        .into_par_iter()
        .map(|i| {
            let (Some(position), Some(&rendered), Some(Some(shaded))) =
                (reference.position[i], rendered_ao.get(i), rendered_position.get(i))
            else {
                return None;
            };
            let traced = reference.ao[i];
            if !traced.is_finite() || !same_surface(*shaded, position) {
                return None;
            }
            // A NaN or infinite AO shades the pixel with nothing sensible: counted as wholly
            // wrong. Its sign is a choice: too dark, as such a pixel usually shows black.
            let signed_error = if rendered.is_finite() { rendered - traced } else { -1.0 };
            Some(Compared { signed_error, traced })
        })
        .collect()
}

/// The mean of `values` in double precision, 0 for none.
fn mean(values: &[f32]) -> f32 {
    if values.is_empty() {
        return 0.0;
    }
    (values.iter().map(|&v| v as f64).sum::<f64>() / values.len() as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::verdict::POSITION_TOLERANCE_M;

    /// A one-row reference with traced `ao`: pixel i at (i, 0, 0) where its AO is finite,
    /// sky where it is NaN.
    fn reference(ao: &[f32]) -> OcclusionReference {
        let position = ao.iter().enumerate().map(|(i, a)| a.is_finite().then(|| Vec3::new(i as f32, 0.0, 0.0)));
        OcclusionReference {
            width: ao.len() as u32,
            height: 1,
            radius: 0.5,
            rays: 256,
            ao: ao.to_vec(),
            position: position.collect(),
        }
    }

    const GREY: [u8; 4] = [128, 128, 128, 255];
    const BLACK: [u8; 4] = [0, 0, 0, 255];

    #[test]
    fn identical_occlusion_has_no_error() {
        let traced = [1.0, 0.5, 0.2, f32::NAN, 0.95];
        let reference = reference(&traced);
        let report = compare_occlusion(&traced, &reference.position, &reference);
        assert_eq!((report.surfaces, report.occluded), (4, 2));
        assert_eq!(
            [report.mean_error, report.mean_error_occluded, report.p95_error, report.mean_signed_error],
            [0.0; 4]
        );
        assert_eq!(report.difference, vec![GREY, GREY, GREY, BLACK, GREY]);
    }

    #[test]
    fn a_uniform_offset_is_the_mean_and_the_percentile() {
        let traced = [0.1, 0.3, 0.5, 0.7, 0.85, 0.0];
        let rendered: Vec<f32> = traced.iter().map(|t| t + 0.1).collect();
        let reference = reference(&traced);
        let report = compare_occlusion(&rendered, &reference.position, &reference);
        assert_eq!(report.surfaces, 6);
        for (name, value) in
            [("mean", report.mean_error), ("p95", report.p95_error), ("signed", report.mean_signed_error)]
        {
            assert!((value - 0.1).abs() < 1e-5, "{name}: {report:?}");
        }
        assert!(report.difference.iter().all(|c| c[2] == 255 && c[0] < 128), "too bright is blue: {report:?}");
    }

    #[test]
    fn only_pixels_traced_as_occluded_enter_the_occluded_mean() {
        let traced = [1.0, 0.95, 0.5, 0.2];
        let rendered = [0.8, 0.95, 0.6, 0.2];
        let reference = reference(&traced);
        let report = compare_occlusion(&rendered, &reference.position, &reference);
        assert_eq!((report.surfaces, report.occluded), (4, 2));
        assert!((report.mean_error_occluded - 0.05).abs() < 1e-6, "{report:?}");
        assert!((report.mean_error - 0.075).abs() < 1e-6, "{report:?}");
        assert!((report.mean_signed_error - -0.025).abs() < 1e-6, "{report:?}");
        let open = compare_occlusion(&[0.5], &[Some(Vec3::ZERO)], &self::reference(&[1.0]));
        assert_eq!((open.occluded, open.mean_error_occluded), (0, 0.0), "no occluded pixel: {open:?}");
    }

    #[test]
    fn pixels_whose_surfaces_disagree_are_left_out() {
        let traced = [0.5, 0.5, 0.5];
        let reference = reference(&traced);
        let mut positions = reference.position.clone();
        // Pixel 1 sees another surface, pixel 2 sky: their wildly wrong AO is not judged.
        positions[1] = positions[1].map(|p| p + Vec3::Y * (2.0 * POSITION_TOLERANCE_M));
        positions[2] = None;
        let report = compare_occlusion(&[0.5, 0.0, 1.0], &positions, &reference);
        assert_eq!(report.surfaces, 1);
        assert_eq!(report.mean_error, 0.0);
        assert_eq!(report.difference, vec![GREY, BLACK, BLACK]);
    }

    #[test]
    fn a_non_finite_rendered_ao_counts_as_off_by_one() {
        let traced = [0.5, 0.5];
        let reference = reference(&traced);
        let report = compare_occlusion(&[f32::NAN, 0.5], &reference.position, &reference);
        assert_eq!(report.surfaces, 2);
        assert!((report.mean_error - 0.5).abs() < 1e-6 && report.p95_error == 1.0, "{report:?}");
        assert_eq!(report.difference[0], [255, 0, 0, 255]);
    }

    #[test]
    fn the_difference_picture_has_one_colour_per_pixel() {
        let reference = OcclusionReference {
            width: 4,
            height: 2,
            radius: 0.5,
            rays: 256,
            ao: vec![0.5; 8],
            position: (0..8).map(|i| Some(Vec3::new(i as f32, 0.0, 0.0))).collect(),
        };
        // Rendered arrays shorter than the picture: the missing pixels are not compared.
        let report = compare_occlusion(&[0.5; 3], &reference.position[..3], &reference);
        assert_eq!(report.difference.len(), 8);
        assert_eq!(report.surfaces, 3);
        assert_eq!(report.difference[..3], [GREY; 3]);
        assert!(report.difference[3..].iter().all(|&c| c == BLACK));
        let broken = OcclusionReference { ao: vec![0.5; 5], ..reference };
        let report = compare_occlusion(&[0.5; 8], &broken.position, &broken);
        assert_eq!((report.difference.len(), report.surfaces), (8, 0));
    }
}
