//! Judging a soft (contact-hardening) shadow: the reference is the share of the light's
//! disc each pixel sees, so the question is not "lit or shadowed" but how far the
//! rendered visibility is from it. Over the same pixels as the verdicts, but with the
//! reference's edges kept in (the penumbra is what is judged): the mean absolute
//! difference, its 95th percentile and the share of pixels off by more than
//! `FAR_OFF`; and a signed difference picture.

use super::{JudgedLight, compared_pairs};

/// A pixel whose visibility is off by more than this counts in `VisibilityError::far_off`.
pub const FAR_OFF: f32 = 0.1;

/// A pixel is in the reference's penumbra where the traced visibility is strictly between
/// these: neither lit nor shadowed by the whole light.
pub const PENUMBRA: (f32, f32) = (0.02, 0.98);

/// How far one light's rendered visibility is from the reference's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VisibilityError {
    /// Pixels compared.
    pub compared: usize,
    /// Mean of |rendered - reference|.
    pub mean_abs: f64,
    /// 95th percentile of |rendered - reference|.
    pub p95_abs: f64,
    /// Share of compared pixels with |rendered - reference| > FAR_OFF.
    pub far_off: f64,
    /// Compared pixels in the reference's penumbra (`PENUMBRA`): what an area light's
    /// shadow is judged by, since most pixels are wholly lit or shadowed.
    pub penumbra_compared: usize,
    /// Mean of |rendered - reference| over the penumbra's pixels.
    pub penumbra_mean_abs: f64,
    /// Share of the penumbra's pixels with |rendered - reference| > FAR_OFF.
    pub penumbra_far_off: f64,
}

/// The visibility error of the judged light's rendered shadow, over the fairly compared
/// pixels without the edge band.
pub fn visibility_error(judged: &JudgedLight) -> VisibilityError {
    error_of(&compared_pairs(judged, false))
}

/// `visibility_error` and `signed_difference_image` together, from one pass over the
/// light's pixels: what `compare` reports for a contact-hardening light.
pub fn soft_shadow_report(judged: &JudgedLight) -> (VisibilityError, Vec<[u8; 4]>) {
    let pairs = compared_pairs(judged, false);
    (error_of(&pairs), pairs.into_iter().map(signed_difference_color).collect())
}

fn error_of(pairs: &[Option<(f32, f32)>]) -> VisibilityError {
    let mut errors: Vec<f32> =
        pairs.iter().flatten().map(|&(rendered, expected)| (rendered - expected).abs()).collect();
    if errors.is_empty() {
        return VisibilityError::default();
    }
    let penumbra: Vec<f32> = pairs
        .iter()
        .flatten()
        .filter(|&&(_, expected)| expected > PENUMBRA.0 && expected < PENUMBRA.1)
        .map(|&(rendered, expected)| (rendered - expected).abs())
        .collect();
    let share = |values: &[f32], of: usize| values.iter().filter(|&&e| e > FAR_OFF).count() as f64 / of.max(1) as f64;
    errors.sort_by(f32::total_cmp);
    let n = errors.len();
    VisibilityError {
        compared: n,
        mean_abs: errors.iter().map(|&e| e as f64).sum::<f64>() / n as f64,
        p95_abs: errors[((n as f64 * 0.95).ceil() as usize).clamp(1, n) - 1] as f64,
        far_off: share(&errors, n),
        penumbra_compared: penumbra.len(),
        penumbra_mean_abs: penumbra.iter().map(|&e| e as f64).sum::<f64>() / penumbra.len().max(1) as f64,
        penumbra_far_off: share(&penumbra, penumbra.len()),
    }
}

/// The signed difference picture of a soft shadow, one RGBA8 pixel per reference pixel:
/// black not compared, grey (128) where rendered and reference agree, shading to red
/// where the render is darker and to blue where it is lighter, fully red or blue from
/// FAR_OFF on (so the viewer's overlay, which paints pure red and blue, shows those).
pub fn signed_difference_color(pair: Option<(f32, f32)>) -> [u8; 4] {
    let Some((rendered, expected)) = pair else {
        return [0, 0, 0, 255];
    };
    let t = ((rendered - expected).abs() / FAR_OFF).min(1.0);
    let fade = (128.0 * (1.0 - t)).round() as u8;
    let strong = (128.0 + 127.0 * t).round() as u8;
    if rendered < expected { [strong, fade, fade, 255] } else { [fade, fade, strong, 255] }
}

/// The signed difference picture of one light (see `signed_difference_color`).
pub fn signed_difference_image(judged: &JudgedLight) -> Vec<[u8; 4]> {
    compared_pairs(judged, false).into_iter().map(signed_difference_color).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_penumbra_columns_see_only_the_references_partial_pixels() {
        let pairs = [Some((1.0, 1.0)), Some((0.0, 0.0)), Some((0.5, 0.3)), Some((0.6, 0.62)), None, Some((0.2, 0.99))];
        let e = error_of(&pairs);
        assert_eq!((e.compared, e.penumbra_compared), (5, 2));
        assert!((e.penumbra_mean_abs - 0.11).abs() < 1e-6, "{e:?}");
        assert!((e.penumbra_far_off - 0.5).abs() < 1e-9 && (e.far_off - 0.4).abs() < 1e-9, "{e:?}");
    }

    #[test]
    fn signed_colours_run_from_grey_to_red_and_blue() {
        assert_eq!(signed_difference_color(None), [0, 0, 0, 255]);
        assert_eq!(signed_difference_color(Some((0.5, 0.5))), [128, 128, 128, 255]);
        assert_eq!(signed_difference_color(Some((0.2, 0.5))), [255, 0, 0, 255]);
        assert_eq!(signed_difference_color(Some((0.9, 0.5))), [0, 0, 255, 255]);
        let slightly_dark = signed_difference_color(Some((0.45, 0.5)));
        assert!(slightly_dark[0] > 128 && slightly_dark[1] < 128 && slightly_dark[1] > 0, "{slightly_dark:?}");
    }
}
