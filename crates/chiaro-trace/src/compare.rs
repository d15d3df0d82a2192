//! Judging a rendered shadow against the traced reference, one light at a time.
//!
//! A rendered per-pixel shadow term (1 lit, 0 shadowed) and the rendered world positions
//! flow in with a `ShadowReference`; out come counts of false shadows (acne: shadow where
//! the reference is lit) and missed shadows (peter-panning and leaks: light where the
//! reference is shadowed), and an RGBA difference image.
//!
//! Only pixels where the question is fair are compared: the reference and the renderer
//! see the same surface, the surface receives shadows and the light reaches it, and no
//! reference shadow edge is near, since a shadow map's texels and filter move edges by a
//! pixel or two without being wrong.

use crate::reference::ShadowReference;
use chiaro_math::light::{spot_angle_params, spot_attenuation};
use chiaro_scene::{Light, LightKind};
use glam::Vec3;
use rayon::prelude::*;

/// Farthest the rendered position may be from the reference's for the pixel to count as
/// the same surface. Too small and depth-buffer reconstruction error drops fair pixels;
/// too large and silhouettes, where the two see different objects, are judged.
pub const POSITION_TOLERANCE_M: f32 = 0.01;

/// Pixels within this Chebyshev distance of a change in reference visibility are not
/// compared. Too narrow and filtered or texel-snapped edges count as errors; too wide and
/// thin shadows (and the acne or leaks inside them) are never judged.
pub const EDGE_BAND_PX: usize = 3;

/// Rendered and reference visibility disagree when they differ by more than this.
pub const DISAGREEMENT_THRESHOLD: f32 = 0.5;

/// What one pixel says about one light's shadow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixelVerdict {
    NotCompared,
    AgreeLit,
    AgreeShadowed,
    /// Rendered darker than the reference: acne, or shadow where there should be light.
    FalseShadow,
    /// Rendered brighter than the reference: peter-panning, or light leaking.
    MissedShadow,
}

impl PixelVerdict {
    /// The difference image's colour: black not compared, grey (128) agreeing and lit,
    /// dark grey (48) agreeing and shadowed, red false shadow, blue missed shadow.
    pub fn color(self) -> [u8; 4] {
        match self {
            PixelVerdict::NotCompared => [0, 0, 0, 255],
            PixelVerdict::AgreeLit => [128, 128, 128, 255],
            PixelVerdict::AgreeShadowed => [48, 48, 48, 255],
            PixelVerdict::FalseShadow => [255, 0, 0, 255],
            PixelVerdict::MissedShadow => [0, 0, 255, 255],
        }
    }
}

/// Pixel counts of one light's comparison.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LightComparison {
    pub compared: usize,
    pub false_shadow: usize,
    pub missed_shadow: usize,
}

impl LightComparison {
    /// Share of compared pixels that disagree, 0 when none were compared.
    pub fn disagreement(&self) -> f64 {
        self.share(self.false_shadow + self.missed_shadow)
    }

    /// Share of compared pixels rendered in shadow that the reference has lit.
    pub fn false_share(&self) -> f64 {
        self.share(self.false_shadow)
    }

    /// Share of compared pixels rendered lit that the reference has shadowed.
    pub fn missed_share(&self) -> f64 {
        self.share(self.missed_shadow)
    }

    /// Counts the verdicts of `classify_pixels`.
    pub fn from_verdicts(verdicts: &[PixelVerdict]) -> LightComparison {
        let mut comparison = LightComparison::default();
        for verdict in verdicts {
            match verdict {
                PixelVerdict::NotCompared => continue,
                PixelVerdict::FalseShadow => comparison.false_shadow += 1,
                PixelVerdict::MissedShadow => comparison.missed_shadow += 1,
                PixelVerdict::AgreeLit | PixelVerdict::AgreeShadowed => {}
            }
            comparison.compared += 1;
        }
        comparison
    }

    fn share(&self, count: usize) -> f64 {
        if self.compared == 0 { 0.0 } else { count as f64 / self.compared as f64 }
    }
}

/// Compares the rendered shadow of `scene.lights[light_index]` (`light`, with the range
/// the renderer used; infinity for none) with the reference. `rendered_shadow` is the
/// light's visibility per pixel (1 lit, 0 shadowed) and `rendered_position` the world
/// position the renderer shaded, both row-major like the reference.
pub fn compare_light(
    rendered_shadow: &[f32],
    rendered_position: &[Option<Vec3>],
    reference: &ShadowReference,
    light_index: usize,
    light: &Light,
    range: f32,
) -> LightComparison {
    LightComparison::from_verdicts(&classify_pixels(
        rendered_shadow,
        rendered_position,
        reference,
        light_index,
        light,
        range,
    ))
}

/// The comparison as an RGBA8 image of the reference's size, colours as in
/// `PixelVerdict::color`.
pub fn difference_image(
    rendered_shadow: &[f32],
    rendered_position: &[Option<Vec3>],
    reference: &ShadowReference,
    light_index: usize,
    light: &Light,
    range: f32,
) -> Vec<[u8; 4]> {
    classify_pixels(rendered_shadow, rendered_position, reference, light_index, light, range)
        .into_iter()
        .map(PixelVerdict::color)
        .collect()
}

/// Each pixel's verdict, row-major, one per reference pixel. Pixels missing from the
/// rendered arrays, or with a non-finite rendered shadow, are not compared; a reference
/// whose arrays do not match its size compares nothing.
pub fn classify_pixels(
    rendered_shadow: &[f32],
    rendered_position: &[Option<Vec3>],
    reference: &ShadowReference,
    light_index: usize,
    light: &Light,
    range: f32,
) -> Vec<PixelVerdict> {
    let (width, height) = (reference.width as usize, reference.height as usize);
    let pixels = width * height;
    let mut verdicts = vec![PixelVerdict::NotCompared; pixels];
    let Some(visibility) = reference.visibility.get(light_index) else {
        return verdicts;
    };
    let consistent = [visibility.len(), reference.position.len(), reference.normal.len(), reference.receives.len()]
        .iter()
        .all(|&len| len == pixels);
    if !consistent {
        return verdicts;
    }
    let near_edge = shadow_edge_band(visibility, width, height, EDGE_BAND_PX);

    verdicts.par_iter_mut().enumerate().for_each(|(i, verdict)| {
        let (Some(position), Some(&rendered), Some(Some(rendered_position))) =
            (reference.position[i], rendered_shadow.get(i), rendered_position.get(i))
        else {
            return;
        };
        let compared = reference.receives[i]
            && !near_edge[i]
            && rendered.is_finite()
            && rendered_position.distance(position) <= POSITION_TOLERANCE_M
            && light_reaches(light, range, position, reference.normal[i]);
        if !compared {
            return;
        }
        let expected = visibility[i];
        *verdict = if (rendered - expected).abs() <= DISAGREEMENT_THRESHOLD {
            if expected >= 0.5 { PixelVerdict::AgreeLit } else { PixelVerdict::AgreeShadowed }
        } else if rendered < expected {
            PixelVerdict::FalseShadow
        } else {
            PixelVerdict::MissedShadow
        };
    });
    verdicts
}

/// Whether `light` can light a surface at `position` facing `normal`: the surface faces
/// it, and for point and spot lights lies within `range` (and the cone).
fn light_reaches(light: &Light, range: f32, position: Vec3, normal: Vec3) -> bool {
    let (to_light, in_range) = match light.kind {
        LightKind::Directional => (-light.direction(), true),
        LightKind::Point | LightKind::Spot { .. } => {
            let offset = light.position() - position;
            let distance = offset.length();
            // At the light itself `to_light` is NaN and every test below fails.
            (offset / distance, distance < range)
        }
    };
    let in_cone = match light.kind {
        LightKind::Spot { inner_cone_rad, outer_cone_rad } => {
            let params = spot_angle_params(inner_cone_rad, outer_cone_rad);
            spot_attenuation(light.direction().dot(-to_light), params) > 0.0
        }
        LightKind::Directional | LightKind::Point => true,
    };
    in_range && in_cone && normal.dot(to_light) > 0.0
}

/// Marks pixels with a finite value that have a different finite value within Chebyshev
/// distance `radius`. Non-finite values (sky) neither mark nor are marked, so a shadow
/// meeting the sky is no edge.
///
/// Separable: the window's minimum and maximum are the minimum and maximum over its rows
/// of each row's minimum and maximum, so two passes of `2 * radius + 1` reads replace
/// `(2 * radius + 1)²` (14 instead of 49 for a radius of 3).
fn shadow_edge_band(values: &[f32], width: usize, height: usize, radius: usize) -> Vec<bool> {
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

    const W: usize = 20;
    const H: usize = 12;

    fn sun() -> Light {
        Light::new(LightKind::Directional, Vec3::ZERO, Vec3::NEG_Y)
    }

    /// A floor seen from above: pixel (x, y) at (x, 0, y) decimetres, facing up; all lit.
    fn floor_reference() -> ShadowReference {
        let position: Vec<_> = (0..W * H).map(|i| Some(Vec3::new((i % W) as f32, 0.0, (i / W) as f32) * 0.1)).collect();
        ShadowReference {
            width: W as u32,
            height: H as u32,
            position,
            normal: vec![Vec3::Y; W * H],
            receives: vec![true; W * H],
            visibility: vec![vec![1.0; W * H]],
            ranges: vec![f32::INFINITY],
        }
    }

    fn compare(rendered: &[f32], reference: &ShadowReference, light: &Light, range: f32) -> LightComparison {
        compare_light(rendered, &reference.position, reference, 0, light, range)
    }

    #[test]
    fn counts_false_and_missed_shadows() {
        let mut reference = floor_reference();
        let mut rendered = vec![1.0; W * H];
        rendered[5] = 0.0;
        rendered[6] = 0.4;
        rendered[7] = 0.6; // within the threshold
        let result = compare(&rendered, &reference, &sun(), f32::INFINITY);
        assert_eq!(result, LightComparison { compared: W * H, false_shadow: 2, missed_shadow: 0 });
        assert!((result.disagreement() - 2.0 / (W * H) as f64).abs() < 1e-12);
        assert_eq!(result.missed_share(), 0.0);

        reference.visibility[0] = vec![0.0; W * H];
        let mut rendered = vec![0.0; W * H];
        rendered[..3].fill(1.0);
        let result = compare(&rendered, &reference, &sun(), f32::INFINITY);
        assert_eq!((result.false_shadow, result.missed_shadow), (0, 3));
        assert!((result.missed_share() - 3.0 / (W * H) as f64).abs() < 1e-12);
        assert_eq!(LightComparison::default().disagreement(), 0.0);
    }

    #[test]
    fn positions_must_agree_within_a_centimetre() {
        let reference = floor_reference();
        let rendered = vec![0.0; W * H];
        let mut positions = reference.position.clone();
        for (i, p) in positions.iter_mut().enumerate() {
            let offset = match i % 3 {
                0 => 0.009,
                1 => 0.011,
                _ => f32::NAN,
            };
            *p = if offset.is_nan() { None } else { p.map(|p| p + Vec3::Y * offset) };
        }
        let result = compare_light(&rendered, &positions, &reference, 0, &sun(), f32::INFINITY);
        assert_eq!(result.compared, (0..W * H).filter(|i| i % 3 == 0).count());
        assert_eq!(result.false_shadow, result.compared);
    }

    #[test]
    fn unlit_surfaces_and_non_receivers_are_not_compared() {
        let mut reference = floor_reference();
        let rendered = vec![1.0; W * H];
        // The sun from below lights nothing.
        let under = Light::new(LightKind::Directional, Vec3::ZERO, Vec3::Y);
        assert_eq!(compare(&rendered, &reference, &under, f32::INFINITY).compared, 0);
        reference.receives[..W].fill(false);
        assert_eq!(compare(&rendered, &reference, &sun(), f32::INFINITY).compared, W * (H - 1));
        reference.position[W] = None;
        assert_eq!(compare(&rendered, &reference, &sun(), f32::INFINITY).compared, W * (H - 1) - 1);
        // Out of range: the light index, and short rendered arrays.
        assert_eq!(compare_light(&rendered, &reference.position, &reference, 1, &sun(), 1.0).compared, 0);
        // Row 0 does not receive and pixel W is sky: W - 1 of the first two rows count.
        assert_eq!(compare(&rendered[..W * 2], &reference, &sun(), f32::INFINITY).compared, W - 1);
    }

    #[test]
    fn point_lights_reach_only_within_range() {
        let reference = floor_reference();
        let rendered = vec![1.0; W * H];
        let centre = Vec3::new(1.0, 0.5, 0.5);
        let point = Light::new(LightKind::Point, centre, Vec3::NEG_Y);
        let range = 1.0;
        let expected = reference.position.iter().filter(|p| p.unwrap().distance(centre) < range).count();
        assert!(expected > 10 && expected < W * H);
        assert_eq!(compare(&rendered, &reference, &point, range).compared, expected);
        assert_eq!(compare(&rendered, &reference, &point, f32::INFINITY).compared, W * H);
    }

    #[test]
    fn spot_lights_reach_only_inside_the_cone() {
        let reference = floor_reference();
        let rendered = vec![1.0; W * H];
        let apex = Vec3::new(1.0, 0.5, 0.5);
        let (inner, outer) = (0.3f32, 0.6f32);
        let spot = Light::new(LightKind::Spot { inner_cone_rad: inner, outer_cone_rad: outer }, apex, Vec3::NEG_Y);
        // Inside the outer cone: the angle from straight down is below `outer`.
        let expected = reference
            .position
            .iter()
            .filter(|p| {
                let to_surface = (p.unwrap() - apex).normalize();
                to_surface.dot(Vec3::NEG_Y).acos() < outer - 1e-3
            })
            .count();
        let near_rim = reference
            .position
            .iter()
            .filter(|p| {
                let angle = (p.unwrap() - apex).normalize().dot(Vec3::NEG_Y).acos();
                (angle - outer).abs() <= 1e-3
            })
            .count();
        assert_eq!(near_rim, 0, "no pixel sits on the rim");
        assert!(expected > 10 && expected < W * H);
        assert_eq!(compare(&rendered, &reference, &spot, 10.0).compared, expected);
    }

    #[test]
    fn shadow_edges_are_banded_but_sky_edges_are_not() {
        let mut reference = floor_reference();
        // Left half (x < 10) shadowed.
        for (i, v) in reference.visibility[0].iter_mut().enumerate() {
            *v = if i % W < 10 { 0.0 } else { 1.0 };
        }
        // Sky in the top row's right half, bordering lit floor.
        for x in 10..W {
            reference.position[x] = None;
            reference.normal[x] = Vec3::ZERO;
            reference.visibility[0][x] = f32::NAN;
        }
        // Everything rendered wrong, so every compared pixel counts.
        let rendered: Vec<f32> = reference.visibility[0].iter().map(|v| 1.0 - v).collect();
        let verdicts = classify_pixels(&rendered, &reference.position, &reference, 0, &sun(), f32::INFINITY);
        for y in 0..H {
            for x in 0..W {
                let verdict = verdicts[y * W + x];
                let expected = if (7..13).contains(&x) || (y == 0 && x >= 10) {
                    PixelVerdict::NotCompared
                } else if x < 10 {
                    PixelVerdict::MissedShadow
                } else {
                    PixelVerdict::FalseShadow
                };
                assert_eq!(verdict, expected, "pixel ({x}, {y})");
            }
        }
        let result = compare(&rendered, &reference, &sun(), f32::INFINITY);
        assert_eq!(result.missed_shadow, 7 * H);
        assert_eq!(result.false_shadow, 7 * (H - 1));
    }

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

    #[test]
    fn difference_image_colours() {
        let mut reference = floor_reference();
        reference.visibility[0][W * H - 1] = 0.0;
        reference.receives[0] = false;
        let mut rendered = vec![1.0; W * H];
        rendered[W * 6 + 10] = 0.0;
        rendered[W * H - 1] = 0.0;
        let image = difference_image(&rendered, &reference.position, &reference, 0, &sun(), 1.0);
        assert_eq!(image.len(), W * H);
        assert_eq!(image[0], [0, 0, 0, 255]);
        assert_eq!(image[W * 6 + 10], [255, 0, 0, 255]);
        assert_eq!(image[W * 6 + 2], [128, 128, 128, 255]);
        // The lone shadowed corner pixel is inside its own edge band.
        assert_eq!(image[W * H - 1], [0, 0, 0, 255]);
        let mut dark = floor_reference();
        dark.visibility[0].fill(0.0);
        rendered.fill(0.0);
        rendered[3] = 1.0;
        let image = difference_image(&rendered, &dark.position, &dark, 0, &sun(), 1.0);
        assert_eq!(image[3], [0, 0, 255, 255]);
        assert_eq!(image[4], [48, 48, 48, 255]);
    }
}
