//! `[shadows.other]`: the shadow atlas of point and spot lights (its side, filter and
//! tile count). TOML values flow in; `LocalShadowSettings` and its validation flow out.

use super::{atlas_size_bound, check_atlas_size, check_filter};
use crate::settings::bound::Bound;
use chiaro_math::shadow::ShadowFilter;
use chiaro_math::shadow::local::MAX_LOCAL_SHADOW_TILES;
use serde::{Deserialize, Serialize};

/// The second atlas, for point and spot lights: up to `max_tiles` tiles in the uniform
/// layout, a spot taking one and a point six (one per cube face).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct LocalShadowSettings {
    /// Atlas side in texels (256 to 8192, a power of two). Too small blurs and blocks
    /// shadows; too large costs memory and caster time.
    pub atlas_size: u32,
    /// "pcf2x2", "tent3x3", "tent5x5" or "tent7x7", for lights whose shadows are soft.
    pub filter: String,
    /// Most tiles (1 to 64) the atlas holds: a spot takes one, a point six. Up to 16 the
    /// uniform layout of Catlike Coding's Custom SRP tutorial "Point and Spot Shadows"
    /// (512 texels each at 2048; where room is left, an area light's cube faces towards
    /// the side it emits from get twice that). Past that each light's tiles are
    /// sized by how much of the screen its range covers: a quarter of the atlas side (512
    /// texels at 2048) over a fifth of the screen, an eighth (256) for most, a sixteenth
    /// (128) under 1%. Lights that do not fit get no realtime shadow (their baked shadow
    /// mask, if any).
    pub max_tiles: u32,
}

impl Default for LocalShadowSettings {
    fn default() -> Self {
        LocalShadowSettings { atlas_size: 2048, filter: "pcf2x2".into(), max_tiles: 64 }
    }
}

/// The interval of `shadows.other.atlas_size`, texels (a power of two besides).
pub const ATLAS_SIZE: Bound = atlas_size_bound("shadows.other.atlas_size");
/// The interval of `shadows.other.max_tiles`.
pub const MAX_TILES: Bound = Bound::new("shadows.other.max_tiles", 1.0, MAX_LOCAL_SHADOW_TILES as f32);

/// Every interval of the subsection.
pub(super) const BOUNDS: &[Bound] = &[ATLAS_SIZE, MAX_TILES];

impl LocalShadowSettings {
    /// The filter the name gives (the default for a name validation would refuse).
    pub fn shadow_filter(&self) -> ShadowFilter {
        ShadowFilter::parse(&self.filter).unwrap_or_default()
    }

    /// Checks every value of the subsection; the message starts with the dotted key.
    pub fn validate(&self) -> Result<(), String> {
        check_atlas_size(ATLAS_SIZE, self.atlas_size)?;
        check_filter("shadows.other.filter", &self.filter)?;
        MAX_TILES.check(self.max_tiles as f32)
    }
}
