//! `[shadows.directional]`: the cascaded shadow atlas of directional lights (its side,
//! filter, cascades and how fragments cross between them). TOML values flow in;
//! `DirectionalShadowSettings`, its cascade ratios and its validation flow out.

use super::{atlas_size_bound, check_atlas_size, check_filter};
use crate::settings::bound::Bound;
use chiaro_math::shadow::{MAX_CASCADES, ShadowFilter};
use serde::{Deserialize, Serialize};

/// The `[shadows.directional]` subsection.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct DirectionalShadowSettings {
    /// Atlas side in texels (256 to 8192, a power of two). Too small gives blocky,
    /// aliased shadows; too large costs memory and rendering time.
    pub atlas_size: u32,
    /// "pcf2x2", "tent3x3", "tent5x5" or "tent7x7". Wider filters soften edges and need
    /// more normal bias, which can detach thin casters from their shadows.
    pub filter: String,
    /// Cascades per light (1 to 4). More cascades keep near shadows sharp at the cost of
    /// one shadow pass each.
    pub cascade_count: u32,
    /// Far end of each cascade but the last as fractions of `max_distance`, increasing:
    /// `cascade_count - 1` of them (the last cascade ends at `max_distance`). Unset, they
    /// are the first of 0.1, 0.25, 0.5. Too small a first ratio spends a cascade on a
    /// sliver near the camera; too large blurs near shadows.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cascade_ratios: Option<Vec<f32>>,
    /// Fraction of the last cascade over which shadows fade out (0.001 to 1).
    pub cascade_fade: f32,
    /// "hard", "soft" or "dither": how fragments cross from one cascade to the next.
    pub cascade_blend: CascadeBlend,
}

impl Default for DirectionalShadowSettings {
    fn default() -> Self {
        DirectionalShadowSettings {
            atlas_size: 2048,
            filter: "pcf2x2".into(),
            cascade_count: 4,
            cascade_ratios: None,
            cascade_fade: 0.1,
            cascade_blend: CascadeBlend::Hard,
        }
    }
}

/// How a fragment moves between cascades.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum CascadeBlend {
    /// Switch at the culling sphere's edge.
    #[default]
    Hard,
    /// Blend with the next cascade across the fade band (two lookups there).
    Soft,
    /// Switch at a dithered point in the fade band (one lookup; noise instead of a seam).
    Dither,
}

/// Cascade ratios when the settings give none.
pub const DEFAULT_CASCADE_RATIOS: [f32; MAX_CASCADES - 1] = [0.1, 0.25, 0.5];

/// The interval of `shadows.directional.atlas_size`, texels (a power of two besides).
pub const ATLAS_SIZE: Bound = atlas_size_bound("shadows.directional.atlas_size");
/// The interval of `shadows.directional.cascade_count`.
pub const CASCADE_COUNT: Bound = Bound::new("shadows.directional.cascade_count", 1.0, MAX_CASCADES as f32);
/// The interval of `shadows.directional.cascade_fade`.
pub const CASCADE_FADE: Bound = Bound::new("shadows.directional.cascade_fade", 0.001, 1.0);

/// Every interval of the subsection.
pub(super) const BOUNDS: &[Bound] = &[ATLAS_SIZE, CASCADE_COUNT, CASCADE_FADE];

impl DirectionalShadowSettings {
    /// The filter the name gives (the default for a name validation would refuse).
    pub fn shadow_filter(&self) -> ShadowFilter {
        ShadowFilter::parse(&self.filter).unwrap_or_default()
    }

    /// The ratios the cascades use: the settings' (validated to be `cascade_count - 1`),
    /// the defaults after them.
    pub fn ratios(&self) -> [f32; MAX_CASCADES - 1] {
        let mut ratios = DEFAULT_CASCADE_RATIOS;
        for (r, &given) in ratios.iter_mut().zip(self.cascade_ratios.iter().flatten()) {
            *r = given;
        }
        ratios
    }

    /// Checks every value of the subsection; the message starts with the dotted key.
    pub fn validate(&self) -> Result<(), String> {
        check_atlas_size(ATLAS_SIZE, self.atlas_size)?;
        check_filter("shadows.directional.filter", &self.filter)?;
        CASCADE_COUNT.check(self.cascade_count as f32)?;
        if let Some(ratios) = &self.cascade_ratios {
            check_cascade_ratios(ratios, self.cascade_count as usize - 1)?;
        }
        CASCADE_FADE.check(self.cascade_fade)
    }
}

/// `wanted` ratios, increasing strictly inside (0, 1).
fn check_cascade_ratios(r: &[f32], wanted: usize) -> Result<(), String> {
    if r.len() != wanted {
        return Err(format!(
            "shadows.directional.cascade_ratios: takes cascade_count - 1 = {wanted} entries (the last cascade ends \
             at max_distance), got {}",
            r.len()
        ));
    }
    let increasing = r.windows(2).all(|w| w[0] < w[1]);
    if !(r.iter().all(|v| v.is_finite() && *v > 0.0 && *v < 1.0) && increasing) {
        return Err(format!("shadows.directional.cascade_ratios: {r:?} must increase strictly between 0 and 1"));
    }
    Ok(())
}
