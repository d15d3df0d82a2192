//! `[ambient_occlusion]`: screen-space ambient occlusion of the indirect light (ambient,
//! environment and baked), never of direct light. TOML values flow in;
//! `AmbientOcclusionSettings` and its validation flow out. The renderer's AO passes
//! read it (docs/ambient-occlusion.md).

use super::bound::Bound;
use serde::{Deserialize, Serialize};

/// The `[ambient_occlusion]` section.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct AmbientOcclusionSettings {
    /// Darken indirect light where nearby surfaces hide the sky of a surface.
    pub enabled: bool,
    /// Metres: geometry farther than this from a surface does not occlude it (the traced
    /// reference's ray length).
    pub radius: f32,
    /// "low", "medium" (the default) or "high": how many directions and depth samples
    /// each pixel takes.
    pub quality: AoQuality,
    /// The AO used is the measured one raised to this power: 1 is the measured occlusion,
    /// 0 none, above 1 darker.
    pub intensity: f32,
    /// Metres a surface seen in the depth buffer is taken to reach behind itself: thin
    /// objects (poles, leaves) occlude only within it, not everything behind them.
    pub thickness: f32,
}

impl Default for AmbientOcclusionSettings {
    fn default() -> Self {
        AmbientOcclusionSettings {
            enabled: false,
            radius: 0.5,
            quality: AoQuality::Medium,
            intensity: 1.0,
            thickness: 0.5,
        }
    }
}

/// How many screen directions (slices) and depth samples per direction a pixel takes.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AoQuality {
    /// 2 directions, 3 samples each way.
    Low,
    /// 2 directions, 8 samples each way.
    #[default]
    Medium,
    /// 4 directions, 10 samples each way.
    High,
}

impl AoQuality {
    /// Every quality, lowest first.
    pub const ALL: [AoQuality; 3] = [AoQuality::Low, AoQuality::Medium, AoQuality::High];

    /// The quality as the settings file spells it.
    pub fn name(self) -> &'static str {
        match self {
            AoQuality::Low => "low",
            AoQuality::Medium => "medium",
            AoQuality::High => "high",
        }
    }

    /// Slices (screen directions, each searched both ways) per pixel.
    pub fn slices(self) -> u32 {
        match self {
            AoQuality::Low => 2,
            AoQuality::Medium => 2,
            AoQuality::High => 4,
        }
    }

    /// Depth samples on each side of a slice.
    pub fn steps(self) -> u32 {
        match self {
            AoQuality::Low => 3,
            AoQuality::Medium => 8,
            AoQuality::High => 10,
        }
    }
}

/// The interval of `ambient_occlusion.radius`.
pub const RADIUS: Bound = Bound::new("ambient_occlusion.radius", 0.01, 100.0);
/// The interval of `ambient_occlusion.intensity`.
pub const INTENSITY: Bound = Bound::new("ambient_occlusion.intensity", 0.0, 8.0);
/// The interval of `ambient_occlusion.thickness`.
pub const THICKNESS: Bound = Bound::new("ambient_occlusion.thickness", 0.001, 100.0);

/// Every interval of the section.
pub(super) const BOUNDS: &[Bound] = &[RADIUS, INTENSITY, THICKNESS];

impl AmbientOcclusionSettings {
    /// Checks every value of the section; the message starts with the dotted key.
    pub fn validate(&self) -> Result<(), String> {
        RADIUS.check(self.radius)?;
        INTENSITY.check(self.intensity)?;
        THICKNESS.check(self.thickness)
    }
}
