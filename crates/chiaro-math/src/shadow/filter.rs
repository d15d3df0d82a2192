//! Shadow filters: hardware 2x2 PCF, and tent filters over 3x3, 5x5 and 7x7 texels taken
//! with 4, 9 and 16 bilinear comparison taps, with the weights of Unity's
//! `SampleShadow_ComputeSamples_Tent_*` (Core RP, ShadowSamplingTent.hlsl). The WGSL in
//! `shaders/shadows/filter.wesl` computes the same; the tests here check the weights.

use glam::Vec2;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShadowFilter {
    #[default]
    Pcf2x2,
    Tent3x3,
    Tent5x5,
    Tent7x7,
}

impl ShadowFilter {
    pub const ALL: [ShadowFilter; 4] =
        [ShadowFilter::Pcf2x2, ShadowFilter::Tent3x3, ShadowFilter::Tent5x5, ShadowFilter::Tent7x7];

    /// The tutorial's `filter + 1`: how many texels the filter reaches, for normal bias
    /// and for shrinking culling spheres.
    pub fn footprint_texels(self) -> f32 {
        self.index() as f32 + 1.0
    }

    /// The value the shader switches on (`SHADOW_FILTER_*` in its constants).
    pub const fn index(self) -> u32 {
        match self {
            ShadowFilter::Pcf2x2 => 0,
            ShadowFilter::Tent3x3 => 1,
            ShadowFilter::Tent5x5 => 2,
            ShadowFilter::Tent7x7 => 3,
        }
    }

    /// Bilinear comparison taps the filter takes.
    pub fn taps(self) -> usize {
        match self {
            ShadowFilter::Pcf2x2 => 1,
            ShadowFilter::Tent3x3 => 4,
            ShadowFilter::Tent5x5 => 9,
            ShadowFilter::Tent7x7 => 16,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            ShadowFilter::Pcf2x2 => "pcf2x2",
            ShadowFilter::Tent3x3 => "tent3x3",
            ShadowFilter::Tent5x5 => "tent5x5",
            ShadowFilter::Tent7x7 => "tent7x7",
        }
    }

    pub fn parse(name: &str) -> Option<ShadowFilter> {
        ShadowFilter::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// Areas under the 3-texel tent of each of the four texels it touches, for a tent centred
/// `offset` (in [-0.5, 0.5]) from the centre of the fetch group: (cut, uncut).
fn texel_areas_tent_3x3(offset: f32) -> ([f32; 4], [f32; 4]) {
    let offset01_squared_halved = (offset + 0.5) * (offset + 0.5) * 0.5;
    let mut area = [0.0; 4];
    let mut uncut = [0.0; 4];
    area[0] = offset01_squared_halved - offset;
    uncut[0] = area[0];
    area[3] = offset01_squared_halved;
    uncut[3] = area[3];
    uncut[1] = (1.5 - offset) - 0.5;
    let left = offset.min(0.0);
    area[1] = uncut[1] - left * left;
    uncut[2] = (1.5 + offset) - 0.5;
    let right = offset.max(0.0);
    area[2] = uncut[2] - right * right;
    (area, uncut)
}

/// Per-texel weights along one axis: 4 for 3x3, 6 for 5x5, 8 for 7x7 (2x2: a single tap).
pub fn tent_texel_weights(filter: ShadowFilter, offset: f32) -> Vec<f32> {
    let (a, u) = texel_areas_tent_3x3(offset);
    match filter {
        ShadowFilter::Pcf2x2 => vec![1.0],
        ShadowFilter::Tent3x3 => a.iter().map(|w| w * 0.44444).collect(),
        ShadowFilter::Tent5x5 => [a[0], u[1], a[1] + 1.0, a[2] + 1.0, u[2], a[3]].iter().map(|w| w * 0.16).collect(),
        ShadowFilter::Tent7x7 => [a[0], u[1], u[1] + 1.0, a[1] + 2.0, a[2] + 2.0, u[2] + 1.0, u[2], a[3]]
            .iter()
            .map(|w| w * 0.081632)
            .collect(),
    }
}

/// One axis of the fetches: (weight, offset in texels from the fetch origin) per bilinear
/// tap, pairing neighbouring texels so one hardware-filtered tap covers both.
pub fn tent_fetches_1d(filter: ShadowFilter, offset: f32) -> Vec<(f32, f32)> {
    let w = tent_texel_weights(filter, offset);
    if filter == ShadowFilter::Pcf2x2 {
        return vec![(1.0, 0.0)];
    }
    let first = -(w.len() as f32) / 2.0 + 0.5;
    w.chunks(2)
        .enumerate()
        .map(|(k, pair)| {
            let weight = pair[0] + pair[1];
            (weight, pair[1] / weight + first + 2.0 * k as f32)
        })
        .collect()
}

/// The 2D taps for a shadow-map position `uv_texels` (in texels): (weight, position in
/// texels) for each bilinear comparison fetch, as the shader takes them.
pub fn tent_fetches(filter: ShadowFilter, uv_texels: Vec2) -> Vec<(f32, Vec2)> {
    if filter == ShadowFilter::Pcf2x2 {
        return vec![(1.0, uv_texels)];
    }
    let center = (uv_texels + 0.5).floor();
    let offset = uv_texels - center;
    let u = tent_fetches_1d(filter, offset.x);
    let v = tent_fetches_1d(filter, offset.y);
    let mut taps = Vec::with_capacity(u.len() * v.len());
    for &(wv, ov) in &v {
        for &(wu, ou) in &u {
            taps.push((wu * wv, center + Vec2::new(ou, ov)));
        }
    }
    taps
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn tap_counts_match_the_issue() {
        for f in ShadowFilter::ALL {
            assert_eq!(tent_fetches(f, Vec2::new(10.3, 20.7)).len(), f.taps());
            assert_eq!(ShadowFilter::parse(f.name()), Some(f));
        }
    }

    #[test]
    fn centred_3x3_tent_has_the_tent_shape() {
        // Offset 0: texel weights (1/8, 3/8, 3/8, 1/8) x (8/9) normalised... the tent of
        // base 3 centred on a texel corner covers 4 texels symmetrically.
        let w = tent_texel_weights(ShadowFilter::Tent3x3, 0.0);
        assert!((w[0] - w[3]).abs() < 1e-6 && (w[1] - w[2]).abs() < 1e-6);
        assert!(w[1] > w[0]);
    }

    proptest! {
        #[test]
        fn weights_are_non_negative_and_sum_to_one(offset in -0.5f32..0.5, x in 0.0f32..512.0, y in 0.0f32..512.0) {
            for f in ShadowFilter::ALL {
                let w = tent_texel_weights(f, offset);
                prop_assert!(w.iter().all(|&v| v >= -1e-6), "{:?} {:?}", f, w);
                let sum: f32 = w.iter().sum();
                prop_assert!((sum - 1.0).abs() < 1e-3, "{:?} sums to {}", f, sum);
                let taps = tent_fetches(f, Vec2::new(x, y));
                let total: f32 = taps.iter().map(|t| t.0).sum();
                prop_assert!((total - 1.0).abs() < 2e-3, "{:?} taps sum to {}", f, total);
                // Taps stay within the filter's reach of the sample.
                let reach = f.footprint_texels() + 1.0;
                for (_, p) in taps {
                    prop_assert!((p - Vec2::new(x, y)).abs().max_element() <= reach);
                }
            }
        }

        #[test]
        fn tent_taps_reproduce_the_tent_centroid(x in 8.0f32..500.0, y in 8.0f32..500.0) {
            // A symmetric filter's weighted tap positions average to the sample position.
            for f in [ShadowFilter::Tent3x3, ShadowFilter::Tent5x5, ShadowFilter::Tent7x7] {
                let taps = tent_fetches(f, Vec2::new(x, y));
                let centroid: Vec2 = taps.iter().map(|(w, p)| *p * *w).sum::<Vec2>()
                    / taps.iter().map(|t| t.0).sum::<f32>();
                prop_assert!((centroid - Vec2::new(x, y)).length() < 0.02, "{:?}: {} vs {},{}", f, centroid, x, y);
            }
        }
    }
}
