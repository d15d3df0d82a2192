//! What a frame's shading actually uses (cookies, baked light, tent filters, soft cascade
//! blending), so that the forward pass can run a shader specialised to it. On llvmpipe a
//! shader pays for code it branches around, whether or not any pixel takes the branch
//! (docs/forward.md measures what compiling each feature out saves). Each feature is a
//! pipeline-overridable constant.

use super::lights::FrameLight;
use super::shadows::ShadowSlot;
use crate::overrides;
use chiaro_math::shadow::ShadowFilter;
use chiaro_scene::{CascadeBlend, Scene, Settings};

/// What a frame's shading uses; each false feature is compiled out of its shaders.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShaderFeatures {
    /// A light the frame shades has a cookie.
    pub cookies: bool,
    /// The scene has a bake applied: lightmaps, probes and shadow masks.
    pub baked: bool,
    /// A realtime shadow is filtered with a tent (3x3 to 7x7) rather than one 2x2 tap.
    pub tent_filters: bool,
    /// Cascades blend softly, so a fragment may sample two of them.
    pub soft_cascades: bool,
    /// A realtime shadow is contact-hardening (`"shadows": "pcss"`).
    pub pcss: bool,
    /// An environment lights the frame (`EnvironmentSettings::enabled_for` the scene).
    pub environment: bool,
    /// A point or spot light the frame shades has a shadow lookup (a realtime shadow or a
    /// shadow mask): else the forward loops over shadowed lights are compiled out, which
    /// lavapipe otherwise runs, masked, once per block of pixels.
    pub local_shadows: bool,
    /// A shadow tile of the frame has a caster that lets light through: shadows are
    /// tinted by the shadow tints (`Draw::tints_shadows`).
    pub tinted_shadows: bool,
    /// Screen-space contact shadows (`[shadows] contact`) darken a realtime shadow the
    /// frame shades: the contact depth pass runs and the shadow lookups march.
    pub contact_shadows: bool,
    /// A light the frame shades is shadowed from virtual maps (`[shadows] technique =
    /// "virtual"`).
    pub virtual_shadows: bool,
    /// A light the frame shades is a rect or disk (EXT_lights_area): else their LTC
    /// shading and area shadows are compiled out, which doubled the benchmark scene's
    /// forward pass on lavapipe while no area light was in it.
    pub area_lights: bool,
    /// Screen-space ambient occlusion (`[ambient_occlusion] enabled`): the AO passes run
    /// and indirect light reads their result.
    pub ambient_occlusion: bool,
}

impl ShaderFeatures {
    /// Everything on: what the shaders do when nothing is overridden.
    pub const ALL: ShaderFeatures = ShaderFeatures {
        cookies: true,
        baked: true,
        tent_filters: true,
        soft_cascades: true,
        pcss: true,
        environment: true,
        local_shadows: true,
        tinted_shadows: true,
        contact_shadows: true,
        virtual_shadows: true,
        area_lights: true,
        ambient_occlusion: true,
    };

    /// The features the frame's `lights`, the scene's bake and the settings call for;
    /// `local_shadowed` says, per point and spot light, whether its loop needs a shadow
    /// lookup.
    pub fn of(scene: &Scene, settings: &Settings, lights: &[FrameLight], local_shadowed: &[bool]) -> ShaderFeatures {
        ShaderFeatures {
            cookies: lights.iter().any(|l| scene.lights[l.id.index()].cookie.is_some()),
            baked: scene.baked.is_some(),
            tent_filters: lights
                .iter()
                .any(|l| matches!(l.shadow, ShadowSlot::Realtime { filter, .. } if filter != ShadowFilter::Pcf2x2)),
            soft_cascades: settings.shadows.directional.cascade_blend == CascadeBlend::Soft,
            pcss: lights.iter().any(|l| matches!(l.shadow, ShadowSlot::Realtime { pcss: true, .. })),
            environment: settings.environment.enabled_for(scene),
            local_shadows: local_shadowed.contains(&true),
            // Set by the plan once it knows each tile's casters.
            tinted_shadows: false,
            contact_shadows: settings.shadows.contact
                && lights.iter().any(|l| matches!(l.shadow, ShadowSlot::Realtime { .. })),
            virtual_shadows: lights.iter().any(|l| matches!(l.shadow, ShadowSlot::Realtime { virtual_map: true, .. })),
            area_lights: lights.iter().any(|l| scene.lights[l.id.index()].is_area()),
            ambient_occlusion: settings.ambient_occlusion.enabled,
        }
    }

    /// The override constants that select this specialisation.
    pub fn constants(self) -> [(&'static str, f64); 12] {
        [
            overrides::COOKIES_ENABLED.flag(self.cookies),
            overrides::BAKED_ENABLED.flag(self.baked),
            overrides::TENT_FILTERS.flag(self.tent_filters),
            overrides::SOFT_CASCADES.flag(self.soft_cascades),
            overrides::PCSS_SHADOWS.flag(self.pcss),
            overrides::ENVIRONMENT_ENABLED.flag(self.environment),
            overrides::LOCAL_SHADOWS.flag(self.local_shadows),
            overrides::TINTED_SHADOWS.flag(self.tinted_shadows),
            overrides::CONTACT_SHADOWS.flag(self.contact_shadows),
            overrides::VIRTUAL_SHADOWS.flag(self.virtual_shadows),
            overrides::AREA_LIGHTS.flag(self.area_lights),
            overrides::AMBIENT_OCCLUSION.flag(self.ambient_occlusion),
        ]
    }
}
