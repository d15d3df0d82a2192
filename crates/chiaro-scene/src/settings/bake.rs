//! `[bake]`: the lightmap and light probe baker's quality and seed (`chiaro bake`; its
//! flags override these). TOML values flow in; `BakeSettings` and its validation flow out.
//! `quality` picks the sample counts that are not given, and how hard the denoiser works.

use super::bound::Bound;
use serde::{Deserialize, Serialize};

/// The lightmap baker's settings (`chiaro bake`; its flags override these).
#[derive(Clone, Debug, Deserialize, PartialEq, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct BakeSettings {
    /// Paths traced per lightmap texel (1 to 65536), on a stratified grid over the texel;
    /// absent: `quality` picks (192 at the default quality). Too few leave noise in the
    /// bounced light; the time grows in proportion. With the denoiser on, texels it would
    /// leave noisy (beside contacts, in corners) take up to four times as many.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub samples: Option<u32>,
    /// Bounces of indirect light (0 to 64). 0 bakes direct light alone; each bounce adds
    /// what one more reflection carries (albedo times the last).
    pub bounces: u32,
    /// Lightmap texels per metre (0.01 to 1000) where the baker makes lightmap UVs. Too
    /// few blur shadows; too many cost bake time and memory quadratically.
    pub texels_per_metre: f32,
    /// Seed of the random numbers: the same seed bakes the same lightmaps.
    pub seed: u64,
    /// Metres between light probes (0.05 to 1000) in the grid over the scene bounds.
    /// Too wide misses light changes; too fine costs bake time (at most 262144 probes).
    pub probe_spacing: f32,
    /// Directions traced per light probe (1 to 65536); absent: `quality` picks (4096 at
    /// the default quality: probes are not denoised, so they take enough stratified
    /// directions that two seeds' probes agree closely; docs/baking.md).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub probe_samples: Option<u32>,
    /// Filter the noisy (bounced and emitted) light of the lightmaps, guided by each
    /// texel's position, normal and chart; the direct light of baked lights stays sharp.
    pub denoise: bool,
    /// `"draft"`, `"default"` or `"high"`: the samples per texel and probe when those keys
    /// are absent, and the denoiser's strength.
    pub quality: BakeQuality,
}

/// How finished a bake should be, for its time.
#[derive(Clone, Copy, Debug, Default, Deserialize, Eq, PartialEq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BakeQuality {
    /// A quarter of the default's samples, denoised harder: for a first look.
    Draft,
    /// 192 paths per texel (more where the denoiser cannot blend), 4096 directions per
    /// probe: within 5% of a converged bake at the median texel, beside contacts too, for
    /// under a tenth of its rays (chiaro-bake/tests/quality.rs).
    #[default]
    Default,
    /// Four times the default's samples, denoised more gently.
    High,
}

impl BakeQuality {
    /// Every quality, lowest first.
    pub const ALL: [BakeQuality; 3] = [BakeQuality::Draft, BakeQuality::Default, BakeQuality::High];

    /// The name settings and `--quality` use.
    pub fn name(self) -> &'static str {
        match self {
            BakeQuality::Draft => "draft",
            BakeQuality::Default => "default",
            BakeQuality::High => "high",
        }
    }

    /// Paths per lightmap texel at this quality.
    pub fn texel_samples(self) -> u32 {
        match self {
            BakeQuality::Draft => 48,
            BakeQuality::Default => 192,
            BakeQuality::High => 768,
        }
    }

    /// Directions per light probe at this quality.
    pub fn probe_samples(self) -> u32 {
        match self {
            BakeQuality::Draft => 1024,
            BakeQuality::Default => 4096,
            BakeQuality::High => 16384,
        }
    }
}

impl std::str::FromStr for BakeQuality {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        BakeQuality::ALL
            .into_iter()
            .find(|q| q.name() == s)
            .ok_or_else(|| format!("bake.quality: {s:?} is not one of \"draft\", \"default\", \"high\""))
    }
}

impl Default for BakeSettings {
    fn default() -> Self {
        BakeSettings {
            samples: None,
            bounces: 3,
            texels_per_metre: 8.0,
            seed: 0,
            probe_spacing: 2.0,
            probe_samples: None,
            denoise: true,
            quality: BakeQuality::Default,
        }
    }
}

/// The interval of `bake.samples`.
pub const SAMPLES: Bound = Bound::new("bake.samples", 1.0, 65536.0);
/// The interval of `bake.bounces`.
pub const BOUNCES: Bound = Bound::new("bake.bounces", 0.0, 64.0);
/// The interval of `bake.texels_per_metre`.
pub const TEXELS_PER_METRE: Bound = Bound::new("bake.texels_per_metre", 0.01, 1000.0);
/// The interval of `bake.probe_spacing`, metres.
pub const PROBE_SPACING: Bound = Bound::new("bake.probe_spacing", 0.05, 1000.0);
/// The interval of `bake.probe_samples`.
pub const PROBE_SAMPLES: Bound = Bound::new("bake.probe_samples", 1.0, 65536.0);

/// Every interval of the section.
pub(super) const BOUNDS: &[Bound] = &[SAMPLES, BOUNCES, TEXELS_PER_METRE, PROBE_SPACING, PROBE_SAMPLES];

impl BakeSettings {
    /// Paths per lightmap texel: `samples`, or what `quality` picks.
    pub fn texel_samples(&self) -> u32 {
        self.samples.unwrap_or(self.quality.texel_samples())
    }

    /// Directions per light probe: `probe_samples`, or what `quality` picks.
    pub fn probe_samples(&self) -> u32 {
        self.probe_samples.unwrap_or(self.quality.probe_samples())
    }

    /// Checks every value of the section; the message starts with the dotted key.
    pub fn validate(&self) -> Result<(), String> {
        SAMPLES.check(self.texel_samples() as f32)?;
        BOUNCES.check(self.bounces as f32)?;
        TEXELS_PER_METRE.check(self.texels_per_metre)?;
        PROBE_SPACING.check(self.probe_spacing)?;
        PROBE_SAMPLES.check(self.probe_samples() as f32)
    }
}
