//! `[bake]`: the lightmap and light probe baker's quality and seed (`chiaro bake`; its
//! flags override these). TOML values flow in; `BakeSettings` and its validation flow out.

use super::bound::Bound;
use serde::{Deserialize, Serialize};

/// The lightmap baker's settings (`chiaro bake`; its flags override these).
#[derive(Clone, Debug, Deserialize, PartialEq, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct BakeSettings {
    /// Paths traced per lightmap texel (1 to 65536), on a stratified grid over the texel.
    /// Too few leave noise in the bounced light; the time grows in proportion.
    pub samples: u32,
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
    /// Directions traced per light probe (1 to 65536).
    pub probe_samples: u32,
}

impl Default for BakeSettings {
    fn default() -> Self {
        BakeSettings { samples: 64, bounces: 3, texels_per_metre: 8.0, seed: 0, probe_spacing: 2.0, probe_samples: 256 }
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
    /// Checks every value of the section; the message starts with the dotted key.
    pub fn validate(&self) -> Result<(), String> {
        SAMPLES.check(self.samples as f32)?;
        BOUNCES.check(self.bounces as f32)?;
        TEXELS_PER_METRE.check(self.texels_per_metre)?;
        PROBE_SPACING.check(self.probe_spacing)?;
        PROBE_SAMPLES.check(self.probe_samples as f32)
    }
}
