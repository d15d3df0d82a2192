//! The lightmap denoiser: an edge-aware a-trous wavelet filter (in the spirit of SVGF)
//! over one atlas's noisy light, guided by each texel's position, normal and chart.
//!
//! Every texel is baked as two independent half estimates (even and odd samples). Their
//! difference measures the noise where it is, which steers the filter (texels whose light
//! differs by more than the noise are not blended, so contact shadows in the bounced light
//! stay) and, filtered with the same weights, measures the noise left afterwards. The
//! filter never reads across charts, across a crease (normals apart) or off the texel's
//! plane. Pure: guides and estimates flow in, filtered estimates flow out.

use chiaro_math::tonemap::luminance;
use glam::Vec3;
use rayon::prelude::*;

/// What the denoiser knows of a texel a surface covers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelGuide {
    /// Mean world position of the texel's samples.
    pub position: Vec3,
    /// Unit geometric normal.
    pub normal: Vec3,
    /// The chart the texel belongs to; texels of other charts are never blended in.
    pub chart: u32,
    /// World size of one texel here, metres.
    pub metres_per_texel: f32,
    /// The harmonic mean distance (metres) to the surfaces the texel's paths first met
    /// (infinite where all escaped). Bounced light changes over about this distance
    /// (Ward's irradiance caching), so the filter reaches only a share of it.
    pub reach: f32,
}

/// A texel's two independent half estimates of the same light (even and odd samples).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Halves {
    pub even: Vec3,
    pub odd: Vec3,
}

impl Halves {
    /// The whole estimate, `even_share` being the even half's share of the samples.
    pub fn whole(&self, even_share: f32) -> Vec3 {
        self.even * even_share + self.odd * (1.0 - even_share)
    }
}

/// How hard the filter smooths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Strength {
    /// A-trous passes; pass `k` reads texels `2^k` apart, so 5 passes reach 62 texels.
    pub passes: u32,
    /// Light differences, in standard errors of the noise, that still blend.
    pub noise_sigmas: f32,
}

/// The strength each bake quality denoises with: a draft's few samples need wider and
/// more forgiving filtering, a high bake's many samples less.
pub fn strength_for(quality: chiaro_scene::settings::BakeQuality) -> Strength {
    use chiaro_scene::settings::BakeQuality;
    match quality {
        BakeQuality::Draft => Strength { passes: 5, noise_sigmas: 6.0 },
        BakeQuality::Default => Strength { passes: 5, noise_sigmas: 4.0 },
        BakeQuality::High => Strength { passes: 4, noise_sigmas: 3.0 },
    }
}

/// Each covered texel's standard error and light, over one or more atlases, for the
/// bake's estimate of its noise: the median relative standard error of the lit texels.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NoiseEstimate {
    /// (standard error, light) of every covered texel, luminance.
    texels: Vec<(f32, f32)>,
}

impl NoiseEstimate {
    /// Adds the covered texels of `guides`, with their standard `errors` and whole light
    /// `values`.
    pub fn add(&mut self, guides: &[Option<TexelGuide>], errors: &[f32], values: &[Vec3]) {
        for ((g, e), v) in guides.iter().zip(errors).zip(values) {
            if g.is_some() {
                self.texels.push((*e, luminance(*v)));
            }
        }
    }

    /// The median of standard error over light among texels brighter than `DARK_SHARE`
    /// of the mean (as `convergence::texel_errors` leaves dark texels out); 0 for none.
    pub fn median_relative(&self) -> f32 {
        let mean = self.texels.iter().map(|t| t.1 as f64).sum::<f64>() / self.texels.len().max(1) as f64;
        let floor = (crate::convergence::DARK_SHARE as f64 * mean) as f32;
        let mut relative: Vec<f32> =
            self.texels.iter().filter(|t| t.1 > floor && t.1 > 0.0).map(|(e, l)| e / l).collect();
        relative.sort_by(f32::total_cmp);
        crate::convergence::quantile(&relative, 0.5)
    }
}

/// One atlas of noisy light to filter: `size` x `size` texels, row major.
pub struct NoisyAtlas<'a> {
    pub size: u32,
    /// `None` where no surface covers the texel (left alone).
    pub guides: &'a [Option<TexelGuide>],
    pub halves: &'a [Halves],
    /// The even half's share of the samples (0.5 for an even count).
    pub even_share: f32,
}

/// The share of a texel's reach the filter blends over (a Gaussian of this width): the
/// best of the shares tried on tests/denoise.rs's scene (docs/performance.md). Too little
/// leaves noise beside surfaces; too much blurs the bounced light's gradients.
const REACH_SHARE: f32 = 0.5;

/// The least reach, in texels: the texels beside a contact still blend with their
/// neighbours (a lone firefly there would stay), but not across the contact's gradient.
const MIN_REACH_TEXELS: f32 = 2.5;

/// B3 spline weights of the 5-tap a-trous kernel.
const KERNEL: [f32; 5] = [1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0];
/// Exponent of the normal weight: normals 10 degrees apart keep 12% weight, 20 degrees
/// apart 0.05%; curved charts still blend their near texels.
const NORMAL_POWER: i32 = 128;

/// The filtered half estimates of every texel; uncovered texels unchanged.
pub fn denoise(atlas: &NoisyAtlas, strength: Strength) -> Vec<Halves> {
    let mut halves = atlas.halves.to_vec();
    for pass in 0..strength.passes {
        let step = 1i64 << pass;
        let noise = local_noise(atlas.size, atlas.guides, &halves, atlas.even_share, 2, step);
        halves = (0..halves.len())
            .into_par_iter()
            .map(|i| filter_texel(atlas, &halves, &noise, i, step, strength.noise_sigmas))
            .collect();
    }
    halves
}

/// One texel of one a-trous pass at `step` texels.
fn filter_texel(atlas: &NoisyAtlas, halves: &[Halves], noise: &[f32], i: usize, step: i64, sigmas: f32) -> Halves {
    let Some(g) = atlas.guides[i] else { return halves[i] };
    let n = atlas.size as i64;
    let (x, y) = (i as i64 % n, i as i64 / n);
    let centre = luminance(halves[i].whole(atlas.even_share));
    let tolerance = sigmas * noise[i];
    // Even a texel in a corner blends with the texels beside it (as the light test
    // allows): a single firefly there would otherwise stay.
    let reach = (REACH_SHARE * g.reach).max(MIN_REACH_TEXELS * g.metres_per_texel);
    let (mut even, mut odd, mut total) = (Vec3::ZERO, Vec3::ZERO, 0.0f32);
    for (ky, hy) in KERNEL.iter().enumerate() {
        let ny = y + (ky as i64 - 2) * step;
        if !(0..n).contains(&ny) {
            continue;
        }
        for (kx, hx) in KERNEL.iter().enumerate() {
            let nx = x + (kx as i64 - 2) * step;
            if !(0..n).contains(&nx) {
                continue;
            }
            let j = (ny * n + nx) as usize;
            let Some(other) = atlas.guides[j] else { continue };
            if other.chart != g.chart {
                continue;
            }
            let facing = g.normal.dot(other.normal).max(0.0).powi(NORMAL_POWER);
            let off_plane = g.normal.dot(other.position - g.position).abs() / g.metres_per_texel.max(1e-9);
            let difference = (luminance(halves[j].whole(atlas.even_share)) - centre).abs();
            let alike = if difference == 0.0 { 1.0 } else { (-difference / tolerance.max(1e-20)).exp() };
            let far = other.position.distance(g.position) / reach;
            let w = hx * hy * facing * (-off_plane).exp() * alike * (-far * far).exp();
            even += halves[j].even * w;
            odd += halves[j].odd * w;
            total += w;
        }
    }
    // The texel itself always weighs in (facing 1, on its plane, alike 1).
    Halves { even: even / total, odd: odd / total }
}

/// Each covered texel's standard error of its whole estimate's luminance, from the
/// difference of its halves, smoothed over its 3x3 neighbours of the same chart (one
/// difference alone is a poor estimate); 0 for uncovered texels.
pub fn standard_errors(size: u32, guides: &[Option<TexelGuide>], halves: &[Halves], even_share: f32) -> Vec<f32> {
    local_noise(size, guides, halves, even_share, 1, 1)
}

/// `standard_errors` smoothed over `(2 radius + 1)^2` texels `step` apart: the filter's
/// own footprint at each pass, so that a texel whose samples all missed the light (no
/// difference, no noise seen) learns the noise of its surroundings.
fn local_noise(
    size: u32,
    guides: &[Option<TexelGuide>],
    halves: &[Halves],
    even_share: f32,
    radius: i64,
    step: i64,
) -> Vec<f32> {
    // Var(whole) = E[(even - odd)^2] * n_even * n_odd / n^2.
    let scale = even_share * (1.0 - even_share);
    let squared: Vec<f32> = halves
        .iter()
        .map(|h| {
            let d = luminance(h.even) - luminance(h.odd);
            d * d * scale
        })
        .collect();
    let n = size as i64;
    (0..guides.len())
        .into_par_iter()
        .map(|i| {
            let Some(g) = guides[i] else { return 0.0 };
            let (x, y) = (i as i64 % n, i as i64 / n);
            let (mut sum, mut total) = (0.0f32, 0.0f32);
            for dy in -radius..=radius {
                for dx in -radius..=radius {
                    let (nx, ny) = (x + dx * step, y + dy * step);
                    if !(0..n).contains(&nx) || !(0..n).contains(&ny) {
                        continue;
                    }
                    let j = (ny * n + nx) as usize;
                    if guides[j].is_some_and(|o| o.chart == g.chart) {
                        let w = ((radius + 1 - dx.abs()) * (radius + 1 - dy.abs())) as f32;
                        sum += squared[j] * w;
                        total += w;
                    }
                }
            }
            (sum / total).sqrt()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    const SIZE: u32 = 32;

    fn flat_guides(chart_of: impl Fn(u32, u32) -> u32) -> Vec<Option<TexelGuide>> {
        (0..SIZE * SIZE)
            .map(|i| {
                let (x, y) = (i % SIZE, i / SIZE);
                Some(TexelGuide {
                    position: Vec3::new(x as f32 * 0.1, 0.0, y as f32 * 0.1),
                    normal: Vec3::Y,
                    chart: chart_of(x, y),
                    metres_per_texel: 0.1,
                    reach: f32::INFINITY,
                })
            })
            .collect()
    }

    /// `truth(x, y)` plus noise of relative size `noise`, independently in each half.
    fn noisy(truth: impl Fn(u32, u32) -> f32, noise: f32, seed: u64) -> Vec<Halves> {
        let mut rng = Rng::new(seed, 9, 0);
        (0..SIZE * SIZE)
            .map(|i| {
                let t = truth(i % SIZE, i / SIZE);
                let mut draw = || Vec3::splat(t * (1.0 + noise * (2.0 * rng.next_f32() - 1.0) * 3f32.sqrt()));
                Halves { even: draw(), odd: draw() }
            })
            .collect()
    }

    fn rms_relative_error(halves: &[Halves], truth: impl Fn(u32, u32) -> f32) -> f32 {
        let sum: f32 = halves
            .iter()
            .enumerate()
            .map(|(i, h)| {
                let t = truth(i as u32 % SIZE, i as u32 / SIZE);
                ((h.whole(0.5).x - t) / t).powi(2)
            })
            .sum();
        (sum / halves.len() as f32).sqrt()
    }

    const DEFAULT: Strength = Strength { passes: 5, noise_sigmas: 4.0 };

    #[test]
    fn noise_on_a_flat_chart_is_filtered_away_and_the_estimate_says_so() {
        let truth = |_, _| 2.0;
        let guides = flat_guides(|_, _| 0);
        let halves = noisy(truth, 0.3, 1);
        let atlas = NoisyAtlas { size: SIZE, guides: &guides, halves: &halves, even_share: 0.5 };
        let before = rms_relative_error(&halves, truth);
        let after_halves = denoise(&atlas, DEFAULT);
        let after = rms_relative_error(&after_halves, truth);
        assert!(after < before / 5.0, "rms relative error {before} -> {after}");
        // The estimated error follows the measured one, before and after.
        let values: Vec<Vec3> = halves.iter().map(|h| h.whole(0.5)).collect();
        let estimate = |halves: &[Halves]| {
            let mut e = NoiseEstimate::default();
            e.add(&guides, &standard_errors(SIZE, &guides, halves, 0.5), &values);
            e.median_relative()
        };
        let (estimated_before, estimated_after) = (estimate(&halves), estimate(&after_halves));
        assert!((estimated_before / before - 1.0).abs() < 0.35, "{estimated_before} vs measured {before}");
        assert!(estimated_after < estimated_before / 4.0, "{estimated_after} vs {estimated_before}");
    }

    /// The mean of column `x` of `out`.
    fn column_mean(out: &[Halves], x: u32) -> f32 {
        (0..SIZE).map(|y| out[(y * SIZE + x) as usize].whole(0.5).x).sum::<f32>() / SIZE as f32
    }

    #[test]
    fn light_never_crosses_a_chart_border() {
        // Two charts side by side, one 1.6 times brighter, a difference the noise hides
        // from the luminance test: only the chart ids keep them apart. The columns at the
        // border keep their own level.
        let truth = |x: u32, _| if x < SIZE / 2 { 1.0 } else { 1.6 };
        let guides = flat_guides(|x, _| (x >= SIZE / 2) as u32);
        let halves = noisy(truth, 0.3, 2);
        let atlas = NoisyAtlas { size: SIZE, guides: &guides, halves: &halves, even_share: 0.5 };
        let out = denoise(&atlas, DEFAULT);
        let (dim, bright) = (column_mean(&out, SIZE / 2 - 1), column_mean(&out, SIZE / 2));
        assert!((dim - 1.0).abs() < 0.05 && (bright - 1.6).abs() < 0.08, "{dim} beside {bright}");
    }

    #[test]
    fn a_step_larger_than_the_noise_stays_a_step_within_a_chart() {
        // One chart, a dark band (a contact shadow in bounced light) five times darker:
        // the luminance test keeps it, within what the noise allows.
        let truth = |x: u32, _| if (12..20).contains(&x) { 0.4 } else { 2.0 };
        let guides = flat_guides(|_, _| 0);
        let halves = noisy(truth, 0.1, 3);
        let atlas = NoisyAtlas { size: SIZE, guides: &guides, halves: &halves, even_share: 0.5 };
        let out = denoise(&atlas, DEFAULT);
        for y in 0..SIZE {
            for x in [12, 15, 19] {
                let v = out[(y * SIZE + x) as usize].whole(0.5).x;
                assert!((v - 0.4).abs() < 0.4 * 0.25, "({x}, {y}): {v}");
            }
            for x in [11, 20] {
                let v = out[(y * SIZE + x) as usize].whole(0.5).x;
                assert!((v - 2.0).abs() < 2.0 * 0.25, "({x}, {y}): {v}");
            }
        }
    }

    #[test]
    fn a_crease_and_an_uncovered_texel_stop_the_filter() {
        // The right half faces another way (a wall meeting the floor in one chart) and is
        // 1.6 times brighter; the left half's last column keeps its level.
        let truth = |x: u32, _| if x < SIZE / 2 { 1.0 } else { 1.6 };
        let mut guides = flat_guides(|_, _| 0);
        for (i, g) in guides.iter_mut().enumerate() {
            if (i as u32 % SIZE) >= SIZE / 2 {
                g.as_mut().unwrap().normal = Vec3::X;
            }
        }
        guides[0] = None;
        let halves = noisy(truth, 0.3, 4);
        let atlas = NoisyAtlas { size: SIZE, guides: &guides, halves: &halves, even_share: 0.5 };
        let out = denoise(&atlas, DEFAULT);
        assert_eq!(out[0], halves[0], "an uncovered texel is left alone");
        let dim = column_mean(&out, SIZE / 2 - 1);
        assert!((dim - 1.0).abs() < 0.05, "{dim}");
    }

    #[test]
    fn light_beside_near_surfaces_keeps_its_shape_and_far_from_them_blends_wide() {
        // One period of a wave across the chart, under 30% noise. Texels whose paths met
        // surfaces 0.2 m away (a texel is 0.1 m) blend over a few texels and keep the
        // wave; texels that saw only distant surfaces blend over the whole chart and
        // flatten it as far as the light test lets them (right for them: their light
        // cannot change that fast).
        let truth = |x: u32, _| 1.0 + 0.5 * (x as f32 / SIZE as f32 * std::f32::consts::TAU).sin();
        let halves = noisy(truth, 0.3, 6);
        let run = |reach: f32| {
            let mut guides = flat_guides(|_, _| 0);
            for g in guides.iter_mut().flatten() {
                g.reach = reach;
            }
            let atlas = NoisyAtlas { size: SIZE, guides: &guides, halves: &halves, even_share: 0.5 };
            let out = denoise(&atlas, DEFAULT);
            // The wave's swing: the peak column's mean less the trough column's.
            (column_mean(&out, SIZE / 4) - column_mean(&out, 3 * SIZE / 4), rms_relative_error(&out, truth))
        };
        let ((near_swing, near_error), (far_swing, far_error)) = (run(0.2), run(f32::INFINITY));
        println!("swing (truth 1.0): near {near_swing}, far {far_swing}; rms error near {near_error}, far {far_error}");
        // Without the reach both would be the far case.
        assert!(near_swing > 0.95 && far_swing < 0.92, "near {near_swing}, far {far_swing}");
        assert!(near_error < far_error, "{near_error} against {far_error}");
    }

    #[test]
    fn noise_free_light_passes_unchanged() {
        let truth = |x: u32, y: u32| 1.0 + (x * 7 + y * 3) as f32 * 0.01;
        let guides = flat_guides(|_, _| 0);
        let halves = noisy(truth, 0.0, 5);
        let atlas = NoisyAtlas { size: SIZE, guides: &guides, halves: &halves, even_share: 0.5 };
        for (out, h) in denoise(&atlas, DEFAULT).iter().zip(&halves) {
            assert!((out.even - h.even).abs().max_element() < 1e-6 * h.even.x, "{out:?} vs {h:?}");
        }
    }
}
