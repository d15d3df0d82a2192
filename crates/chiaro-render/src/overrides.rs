//! The shaders' pipeline-overridable constants (WGSL `override`s), named in one table:
//! each entry's id flows to WESL as the constant `OVERRIDE_<NAME>` (build.rs), which the
//! shader uses in its `@id(..)`, and to the passes as the key wgpu's pipeline constants
//! take. No id is written twice: a test refuses a literal `@id` in the shaders.

/// A pipeline-overridable constant of the shaders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Override {
    /// The WGSL `@id`.
    pub id: u32,
    /// The id as wgpu's `PipelineCompilationOptions::constants` keys it.
    pub key: &'static str,
    /// The name after `OVERRIDE_` in WESL's `constants` module.
    pub name: &'static str,
}

impl Override {
    /// A numeric value for this override.
    pub fn value(self, value: f64) -> (&'static str, f64) {
        (self.key, value)
    }

    /// A boolean value for this override.
    pub fn flag(self, on: bool) -> (&'static str, f64) {
        (self.key, if on { 1.0 } else { 0.0 })
    }
}

macro_rules! overrides {
    ($($(#[doc = $doc:literal])* $name:ident = $id:literal;)*) => {
        $($(#[doc = $doc])* pub const $name: Override = Override { id: $id, key: stringify!($id), name: stringify!($name) };)*

        /// Every override, for build.rs and the tests.
        pub const ALL: &[Override] = &[$($name),*];
    };
}

overrides! {
    /// Tone mapping: the target's format is not sRGB, so the shader encodes.
    ENCODE_SRGB = 0;
    /// G-buffer and light volumes: light goes to the LDR buffer as exp2(-light).
    LDR_EXP2 = 2;
    /// Light volumes count themselves instead of shading (the overdraw view).
    COUNT_OVERDRAW = 4;
    /// The debug view pass's view: 0 albedo, 1 normal, 2 overdraw.
    DEBUG_VIEW = 5;
    /// Light volumes clamp to the far plane in the vertex shader (no depth-clip control).
    CLAMP_FAR = 6;
    /// The forward pass's light culling (`LIGHT_CULLING_*`).
    LIGHT_CULLING = 7;
    /// Culled lists read their lights from their texel table, not the uniform buffer.
    LIGHTS_IN_TABLE = 8;
    /// Light cookies are compiled in.
    COOKIES_ENABLED = 9;
    /// Baked light (lightmaps, probes, shadow masks) is compiled in.
    BAKED_ENABLED = 10;
    /// Tent filters wider than 2x2 are compiled in.
    TENT_FILTERS = 11;
    /// Soft blending between cascades is compiled in.
    SOFT_CASCADES = 12;
    /// The draw is alpha-tested (its fragment discards).
    ALPHA_TESTED = 13;
    /// The draw's material has a texture; without one its fragments sample none.
    MATERIAL_TEXTURED = 14;
    /// Contact-hardening (PCSS) shadows are compiled in.
    PCSS_SHADOWS = 15;
    /// Image-based environment light is compiled in (else the constant ambient term).
    ENVIRONMENT_ENABLED = 16;
    /// The forward pass's loops over shadowed point and spot lights are compiled in.
    LOCAL_SHADOWS = 17;
    /// Tone mapping: the display curve (`TONE_MAPPING_*`).
    TONE_MAPPING = 18;
    /// The draw's material has KHR_materials_* extensions: the layered BRDF shades it.
    MATERIAL_LAYERED = 19;
    /// Shadows are tinted by casters that let light through (the shadow tints).
    TINTED_SHADOWS = 20;
    /// Screen-space contact shadows march the view's depths (`[shadows] contact`).
    CONTACT_SHADOWS = 21;
    /// A light is shadowed from virtual maps (`[shadows] technique = "virtual"`).
    VIRTUAL_SHADOWS = 22;
    /// Rect and disk lights (EXT_lights_area) are compiled in: their LTC shading and
    /// shape-following shadows.
    AREA_LIGHTS = 23;
    /// Screen-space ambient occlusion darkens indirect light (`[ambient_occlusion]`).
    AMBIENT_OCCLUSION = 24;
}

/// The overrides the composed WGSL `source` declares (as `@id(..OVERRIDE_<NAME>)`): a
/// module keeps only the overrides it reads, and wgpu refuses a constant its shader lacks.
pub fn declared_in(source: &str) -> Vec<Override> {
    ALL.iter().copied().filter(|o| source.contains(&format!("OVERRIDE_{})", o.name))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shadow_aov_declares_the_shadow_overrides_and_not_the_shading_ones() {
        let declared = declared_in(crate::wgsl!("shadow_aov"));
        let asked = [CONTACT_SHADOWS, PCSS_SHADOWS, COOKIES_ENABLED, ENVIRONMENT_ENABLED];
        let kept: Vec<Override> = asked.into_iter().filter(|o| declared.contains(o)).collect();
        assert_eq!(kept, [CONTACT_SHADOWS, PCSS_SHADOWS]);
    }

    #[test]
    fn ids_are_distinct_and_keys_spell_them() {
        for (i, a) in ALL.iter().enumerate() {
            assert_eq!(a.key, a.id.to_string());
            assert!(ALL[i + 1..].iter().all(|b| b.id != a.id && b.name != a.name), "{a:?}");
        }
    }
}
