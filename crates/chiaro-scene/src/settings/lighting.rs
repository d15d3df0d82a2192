//! `[lighting]`: how mixed lights' baked and realtime shadows combine. TOML values flow
//! in; `LightingSettings` flows out (every value it can hold is valid).

use serde::{Deserialize, Serialize};

/// The `[lighting]` section.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct LightingSettings {
    /// "distance-shadowmask" (the default), "shadowmask" or "baked-indirect": how mixed
    /// lights' baked shadows (the shadow mask) and realtime shadows combine.
    pub mixed_mode: MixedMode,
}

/// How mixed lights' realtime and baked shadows combine (Unity's mixed lighting modes).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, Hash, Serialize)]
pub enum MixedMode {
    /// Realtime shadows only, none past the shadow distance; the baker writes no mask.
    #[serde(rename = "baked-indirect")]
    BakedIndirect,
    /// The baked mask at every distance; realtime shadows within the shadow distance add
    /// to it (the darker of the two).
    #[serde(rename = "shadowmask")]
    Shadowmask,
    /// Realtime shadows within the shadow distance, the baked mask beyond, blended
    /// across the fade.
    #[default]
    #[serde(rename = "distance-shadowmask")]
    DistanceShadowmask,
}

impl MixedMode {
    /// The mode as the settings file spells it.
    pub fn name(self) -> &'static str {
        match self {
            MixedMode::BakedIndirect => "baked-indirect",
            MixedMode::Shadowmask => "shadowmask",
            MixedMode::DistanceShadowmask => "distance-shadowmask",
        }
    }

    /// Whether the baker writes shadow masks for mixed lights.
    pub fn uses_shadow_mask(self) -> bool {
        self != MixedMode::BakedIndirect
    }
}
