//! `[lights]`: how many point and spot lights a frame shades, where lights without a range
//! are cut off, and how the forward pass culls them. TOML values flow in; `LightSettings`
//! and its validation flow out.

use super::bound::Bound;
use super::render::RenderPath;
use chiaro_math::light::{MAX_DEFERRED_LOCAL_LIGHTS, MAX_LOCAL_LIGHTS, MIN_RANGE_THRESHOLD_LUX};
use serde::{Deserialize, Serialize};

/// The `[lights]` section.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct LightSettings {
    /// Most point and spot lights shaded per frame: 1 to 4096, or to 64 on the forward
    /// path with `culling = "none"` (with which the deferred path's transparent surfaces
    /// see the 64 most important); unset, the most. The most important visible ones are
    /// kept; a lower cap is faster but drops distant lights.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_other_lights: Option<u32>,
    /// Illuminance (lux, 1e-6 to 1e6) at which a light with no range in its file is cut
    /// off: `range = sqrt(intensity / threshold)`. Too high cuts lights off visibly early;
    /// too low gives huge volumes that touch everything and cost shading time.
    pub range_threshold_lux: f32,
    /// Which point and spot lights each forward-shaded pixel loops over: "clustered" (a
    /// froxel grid's lists, the default), "per-object" (each object's eight most
    /// important lights) or "none" (every light, up to 64).
    pub culling: LightCulling,
}

impl Default for LightSettings {
    fn default() -> Self {
        LightSettings { max_other_lights: None, range_threshold_lux: 0.01, culling: LightCulling::Clustered }
    }
}

/// How the forward pass finds the point and spot lights that reach a pixel.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum LightCulling {
    /// Screen tiles x exponential depth slices, each with the list of lights whose range
    /// reaches it, built every frame.
    #[default]
    Clustered,
    /// Up to `MAX_LIGHTS_PER_OBJECT` lights per object, the most important first.
    PerObject,
    /// Every shaded light at every pixel (up to 64).
    None,
}

/// The interval of `lights.max_other_lights` with culled light lists (or deferred).
pub const MAX_LOCAL_LIGHTS_CULLED: Bound = Bound::new("lights.max_other_lights", 1.0, MAX_DEFERRED_LOCAL_LIGHTS as f32);
/// The interval of `lights.max_other_lights` on the forward path without culling.
pub const MAX_LOCAL_LIGHTS_UNCULLED: Bound = Bound::new("lights.max_other_lights", 1.0, MAX_LOCAL_LIGHTS as f32);
/// The interval of `lights.range_threshold_lux`.
pub const RANGE_THRESHOLD_LUX: Bound = Bound::new("lights.range_threshold_lux", MIN_RANGE_THRESHOLD_LUX, 1.0e6);

/// Every interval of the section.
pub(super) const BOUNDS: &[Bound] = &[MAX_LOCAL_LIGHTS_CULLED, MAX_LOCAL_LIGHTS_UNCULLED, RANGE_THRESHOLD_LUX];

/// The interval `lights.max_other_lights` must lie in on `path` with `culling`: the
/// forward path without culling loops over every light at every pixel, so it takes fewer.
pub fn max_other_lights_bound(path: RenderPath, culling: LightCulling) -> Bound {
    match (path, culling) {
        (RenderPath::Forward, LightCulling::None) => MAX_LOCAL_LIGHTS_UNCULLED,
        _ => MAX_LOCAL_LIGHTS_CULLED,
    }
}

impl LightSettings {
    /// Checks every value of the section for frames on `path`; the message starts with
    /// the dotted key.
    pub fn validate(&self, path: RenderPath) -> Result<(), String> {
        if let Some(most) = self.max_other_lights {
            max_other_lights_bound(path, self.culling).check(most as f32)?;
        }
        RANGE_THRESHOLD_LUX.check(self.range_threshold_lux)
    }
}
