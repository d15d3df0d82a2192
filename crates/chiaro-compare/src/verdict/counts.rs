//! Counting one light's verdicts: how many pixels were compared, how many show a false
//! shadow and how many a missed one; and the verdicts as a difference picture.

use super::{PixelVerdict, classify_pixels};
use chiaro_scene::Light;
use chiaro_trace::ShadowReference;
use glam::Vec3;

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
