//! Counting one light's verdicts: how many pixels were compared, how many show a false
//! shadow and how many a missed one; and the verdicts as a difference picture.

use super::{JudgedLight, PixelVerdict, classify_pixels};

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

/// Compares the judged light's rendered shadow with the reference.
pub fn compare_light(judged: &JudgedLight) -> LightComparison {
    LightComparison::from_verdicts(&classify_pixels(judged))
}

/// The comparison as an RGBA8 image of the reference's size, colours as in
/// `PixelVerdict::color`.
pub fn difference_image(judged: &JudgedLight) -> Vec<[u8; 4]> {
    classify_pixels(judged).into_iter().map(PixelVerdict::color).collect()
}
