//! `[shadows]`: how far shadows reach, how they fade, whether tiles are cached, and the
//! two atlases' subsections (`directional` for cascaded sun shadows, `other` for point
//! and spot lights). TOML values flow in; `ShadowSettings` and its validation flow out.

pub mod directional;
pub mod other;

pub use directional::{CascadeBlend, DEFAULT_CASCADE_RATIOS, DirectionalShadowSettings};
pub use other::LocalShadowSettings;

use super::bound::{Bound, number};
use chiaro_math::shadow::ShadowFilter;
use serde::{Deserialize, Serialize};

/// The `[shadows]` section, with its two atlases' subsections.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct ShadowSettings {
    /// Metres from the camera beyond which no shadow is sampled (0.1 to 10000). Too short
    /// loses distant shadows; too long spreads the cascades' texels thin and blurs them.
    pub max_distance: f32,
    /// Keep shadow tiles from frame to frame and draw a tile again only when its light,
    /// its projection or a caster in it changed (true, the default); false draws every
    /// tile every frame.
    pub cache: bool,
    /// Fraction of `max_distance` over which shadows fade out (0.001 to 1). Too small
    /// shows a hard line where shadows end; too large fades shadows that should be there.
    pub distance_fade: f32,
    /// Depth samples a `pcss` light's blocker search takes per pixel (4 to 64): fewer are
    /// cheaper and find small blockers less reliably (the penumbra's width is noisier).
    pub pcss_blocker_samples: u32,
    /// Comparison samples a `pcss` light's penumbra is filtered with per pixel (4 to 64):
    /// fewer are cheaper and grainier.
    pub pcss_filter_samples: u32,
    /// Screen-space contact shadows for every shadowed light (false, the default): a
    /// short march through the depth buffer towards the light finds the casters, a few
    /// centimetres from the surface, that a shadow texel is too coarse to resolve.
    pub contact: bool,
    /// Metres a contact shadow's march reaches towards the light (0.001 to 10).
    pub contact_length: f32,
    /// Depth samples along that march per pixel (1 to 64): fewer miss thin casters.
    pub contact_steps: u32,
    /// Metres behind the depth buffer's surface that a march still counts as inside its
    /// caster (0.001 to 10): the depth buffer sees only fronts, so a thin caster (a pole)
    /// would shade everything behind it without this limit.
    pub contact_thickness: f32,
    /// Where realtime shadow maps live: `atlas` (the default: a tile per cascade, spot and
    /// cube face in the two atlases) or `virtual` (each light a 16k virtual map of
    /// 128-texel pages, drawn only where the frame's pixels need them, from a pool of
    /// `virtual_pool_mb`; docs/shadows.md).
    pub technique: ShadowTechnique,
    /// Megabytes of the virtual technique's page pool (16 to 2048): 32-bit depth pages
    /// with their borders; when it is full, coarser pages serve the pixels that want more.
    pub virtual_pool_mb: u32,
    /// `[shadows.directional]`: the cascaded atlas of directional lights.
    pub directional: DirectionalShadowSettings,
    /// `[shadows.other]`: the atlas of point and spot lights.
    pub other: LocalShadowSettings,
}

impl Default for ShadowSettings {
    fn default() -> Self {
        ShadowSettings {
            max_distance: 100.0,
            cache: true,
            distance_fade: 0.1,
            pcss_blocker_samples: 16,
            pcss_filter_samples: 16,
            contact: false,
            contact_length: 0.2,
            contact_steps: 16,
            contact_thickness: 0.05,
            technique: ShadowTechnique::Atlas,
            virtual_pool_mb: 128,
            directional: DirectionalShadowSettings::default(),
            other: LocalShadowSettings::default(),
        }
    }
}

/// The interval of `shadows.max_distance`, metres.
pub const MAX_DISTANCE: Bound = Bound::new("shadows.max_distance", 0.1, 10000.0);
/// The interval of `shadows.distance_fade`.
pub const DISTANCE_FADE: Bound = Bound::new("shadows.distance_fade", 0.001, 1.0);

/// The interval of `shadows.pcss_blocker_samples`.
pub const PCSS_BLOCKER_SAMPLES: Bound = Bound::new("shadows.pcss_blocker_samples", 4.0, 64.0);
/// The interval of `shadows.pcss_filter_samples`.
pub const PCSS_FILTER_SAMPLES: Bound = Bound::new("shadows.pcss_filter_samples", 4.0, 64.0);
/// The interval of `shadows.contact_length`, metres.
pub const CONTACT_LENGTH: Bound = Bound::new("shadows.contact_length", 0.001, 10.0);
/// The interval of `shadows.contact_steps`.
pub const CONTACT_STEPS: Bound = Bound::new("shadows.contact_steps", 1.0, 64.0);
/// The interval of `shadows.contact_thickness`, metres.
pub const CONTACT_THICKNESS: Bound = Bound::new("shadows.contact_thickness", 0.001, 10.0);

/// The interval of `shadows.virtual_pool_mb`.
pub const VIRTUAL_POOL_MB: Bound = Bound::new("shadows.virtual_pool_mb", 16.0, 2048.0);

/// Where realtime shadow maps live (`shadows.technique`).
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ShadowTechnique {
    /// Tiles in the two atlases, sized by each light's share of the screen.
    #[default]
    Atlas,
    /// Virtual maps whose pages are drawn where the depth buffer asks for them.
    Virtual,
}

/// Every interval of the section and its subsections.
pub(super) fn bounds() -> impl Iterator<Item = Bound> {
    [
        MAX_DISTANCE,
        DISTANCE_FADE,
        PCSS_BLOCKER_SAMPLES,
        PCSS_FILTER_SAMPLES,
        CONTACT_LENGTH,
        CONTACT_STEPS,
        CONTACT_THICKNESS,
        VIRTUAL_POOL_MB,
    ]
    .into_iter()
    .chain(directional::BOUNDS.iter().copied())
    .chain(other::BOUNDS.iter().copied())
}

/// The interval of an atlas side for `key`, texels: both atlases take the same.
pub(super) const fn atlas_size_bound(key: &'static str) -> Bound {
    Bound::new(key, 256.0, 8192.0)
}

impl ShadowSettings {
    /// Checks every value of the section and its subsections; the message starts with the
    /// dotted key.
    pub fn validate(&self) -> Result<(), String> {
        MAX_DISTANCE.check(self.max_distance)?;
        DISTANCE_FADE.check(self.distance_fade)?;
        PCSS_BLOCKER_SAMPLES.check(self.pcss_blocker_samples as f32)?;
        PCSS_FILTER_SAMPLES.check(self.pcss_filter_samples as f32)?;
        CONTACT_LENGTH.check(self.contact_length)?;
        CONTACT_STEPS.check(self.contact_steps as f32)?;
        CONTACT_THICKNESS.check(self.contact_thickness)?;
        VIRTUAL_POOL_MB.check(self.virtual_pool_mb as f32)?;
        self.directional.validate()?;
        self.other.validate()
    }
}

/// An atlas side must lie in `bound` and be a power of two.
fn check_atlas_size(bound: Bound, atlas_size: u32) -> Result<(), String> {
    if bound.contains(atlas_size as f32) && atlas_size.is_power_of_two() {
        return Ok(());
    }
    Err(format!(
        "{}: {atlas_size} must be a power of two from {} to {}",
        bound.key,
        number(bound.min),
        number(bound.max)
    ))
}

/// A filter must be one `ShadowFilter` knows; `key` is the dotted key it was set by.
fn check_filter(key: &str, filter: &str) -> Result<(), String> {
    match ShadowFilter::parse(filter) {
        Some(_) => Ok(()),
        None => Err(format!("{key}: unknown filter '{filter}' (pcf2x2, tent3x3, tent5x5, tent7x7)")),
    }
}
