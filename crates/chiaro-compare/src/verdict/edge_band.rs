//! The band around the reference's shadow edges where pixels are not judged: visibility
//! values flow in, a mask of pixels near a change in visibility flows out.

/// Marks pixels with a finite value that have a different finite value within Chebyshev
/// distance `radius`. Non-finite values (sky) neither mark nor are marked, so a shadow
/// meeting the sky is no edge.
///
/// Separable: the window's minimum and maximum are the minimum and maximum over its rows
/// of each row's minimum and maximum, so two passes of `2 * radius + 1` reads replace
/// `(2 * radius + 1)²` (14 instead of 49 for a radius of 3).
pub(super) fn shadow_edge_band(values: &[f32], width: usize, height: usize, radius: usize) -> Vec<bool> {
    debug_assert_eq!(values.len(), width * height);
    let window = |centre: usize, len: usize| centre.saturating_sub(radius)..(centre + radius + 1).min(len);
    let mut row_min = vec![f32::INFINITY; values.len()];
    let mut row_max = vec![f32::NEG_INFINITY; values.len()];
    for y in 0..height {
        let row = &values[y * width..(y + 1) * width];
        for x in 0..width {
            for &v in row[window(x, width)].iter().filter(|v| v.is_finite()) {
                row_min[y * width + x] = row_min[y * width + x].min(v);
                row_max[y * width + x] = row_max[y * width + x].max(v);
            }
        }
    }
    let mut band = vec![false; values.len()];
    for y in 0..height {
        for x in 0..width {
            let value = values[y * width + x];
            if !value.is_finite() {
                continue;
            }
            let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
            for yy in window(y, height) {
                lo = lo.min(row_min[yy * width + x]);
                hi = hi.max(row_max[yy * width + x]);
            }
            band[y * width + x] = lo < value || hi > value;
        }
    }
    band
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::verdict::EDGE_BAND_PX;

    #[test]
    fn edge_band_matches_brute_force() {
        let (width, height) = (17, 11);
        let mut state = 12345u32;
        let values: Vec<f32> = (0..width * height)
            .map(|_| {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                match state >> 29 {
                    0 => f32::NAN,
                    1..=5 => 1.0,
                    _ => 0.0,
                }
            })
            .collect();
        let band = shadow_edge_band(&values, width, height, EDGE_BAND_PX);
        for y in 0..height {
            for x in 0..width {
                let value = values[y * width + x];
                let r = EDGE_BAND_PX as i64;
                let differs = (-r..=r).flat_map(|dy| (-r..=r).map(move |dx| (dx, dy))).any(|(dx, dy)| {
                    let (xx, yy) = (x as i64 + dx, y as i64 + dy);
                    let inside = (0..width as i64).contains(&xx) && (0..height as i64).contains(&yy);
                    inside && {
                        let other = values[yy as usize * width + xx as usize];
                        other.is_finite() && other != value
                    }
                });
                assert_eq!(band[y * width + x], value.is_finite() && differs, "({x}, {y})");
            }
        }
    }
}
