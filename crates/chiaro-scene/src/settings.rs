//! Pipeline settings, read from a TOML file in which every field is optional.
//!
//! Unknown keys and out-of-range values are errors that name the key: a typo must never
//! fall back to a default silently. Later stages (shadows, baking, the deferred path) add
//! their own sections here.

use crate::settings_text::{key_at, line_of_key};
use chiaro_math::light::MIN_RANGE_THRESHOLD_LUX;
use chiaro_math::shadow::{MAX_CASCADES, ShadowFilter};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// All settings; `Settings::default()` is what a missing file means.
#[derive(Clone, Debug, Default, Deserialize, serde::Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    pub render: RenderSettings,
    pub lights: LightSettings,
    pub camera: CameraSettings,
    pub shadows: ShadowSettings,
    pub bake: BakeSettings,
    pub lighting: LightingSettings,
}

/// How mixed lights' realtime and baked shadows combine (Unity's mixed lighting modes).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, Hash, serde::Serialize)]
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

#[derive(Clone, Debug, Default, Deserialize, serde::Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct LightingSettings {
    /// "distance-shadowmask" (the default), "shadowmask" or "baked-indirect": how mixed
    /// lights' baked shadows (the shadow mask) and realtime shadows combine.
    pub mixed_mode: MixedMode,
}

/// The lightmap baker's settings (`chiaro bake`; its flags override these).
#[derive(Clone, Debug, Deserialize, PartialEq, serde::Serialize)]
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

#[derive(Clone, Debug, Deserialize, serde::Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct RenderSettings {
    /// Output width in pixels (1 to 16384) when the command line gives none.
    pub width: u32,
    /// Output height in pixels (1 to 16384) when the command line gives none.
    pub height: u32,
    /// Camera exposure in EV100: `scale = 1 / (1.2 * 2^ev100)`. Too low a value blows
    /// highlights out to white, too high a value crushes the image to black. Scenes in
    /// daylight units (a 100,000 lux sun) want about 15.
    pub exposure_ev100: f32,
    /// Constant ambient radiance added as `ambient * base colour * occlusion`; set it to
    /// zero to see only the punctual lights (the tests do).
    pub ambient: [f32; 3],
    /// Linear RGB radiance behind the scene.
    pub background: [f32; 3],
    /// "forward" (a depth prepass, then each draw lit by its culled lights, with MSAA; the
    /// default, since with 4x MSAA it renders the shared benchmark scene faster than the
    /// deferred path does with none, see the README) or "deferred" (a G-buffer, then one
    /// light volume per light; no MSAA).
    pub path: RenderPath,
    /// The deferred path's light accumulation: "hdr" (half floats, the default) or
    /// "ldr-exp2" (the seeds' legacy 8-bit buffer storing exp2(-light)), which bands dark
    /// tones and clips bright ones.
    pub light_buffer: LightBuffer,
    /// Samples per pixel of the forward path's colour and depth (1, 2, 4 or 8), resolved
    /// before tone mapping. The deferred path, and frames that report AOVs, render one.
    pub msaa: u32,
}

/// How a frame is shaded.
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "lowercase")]
pub enum RenderPath {
    #[default]
    Forward,
    Deferred,
}

/// Where the deferred path accumulates light.
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq, Hash)]
pub enum LightBuffer {
    #[default]
    #[serde(rename = "hdr")]
    Hdr,
    #[serde(rename = "ldr-exp2")]
    LdrExp2,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 1280,
            height: 720,
            exposure_ev100: 0.0,
            ambient: [0.02, 0.02, 0.025],
            background: [0.0, 0.0, 0.0],
            path: RenderPath::Forward,
            light_buffer: LightBuffer::Hdr,
            msaa: 4,
        }
    }
}

#[derive(Clone, Debug, Deserialize, serde::Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct LightSettings {
    /// Most point and spot lights shaded per frame: 1 to 4096, or to 64 on the forward
    /// path with `culling = "none"` (with which the deferred path's transparent surfaces
    /// see the 64 most important); unset, the most. The most important visible ones are kept; a lower cap is faster
    /// but drops distant lights.
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
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq, Hash)]
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

#[derive(Clone, Debug, Deserialize, serde::Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CameraSettings {
    /// Vertical field of view (degrees, 1 to 179) of the camera made when a scene has none.
    pub auto_yfov_deg: f32,
}

impl Default for CameraSettings {
    fn default() -> Self {
        CameraSettings { auto_yfov_deg: 45.0 }
    }
}

/// How a fragment moves between cascades.
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
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

#[derive(Clone, Debug, Deserialize, serde::Serialize, PartialEq)]
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
    pub directional: DirectionalShadowSettings,
    pub other: OtherShadowSettings,
}

impl Default for ShadowSettings {
    fn default() -> Self {
        ShadowSettings {
            max_distance: 100.0,
            cache: true,
            distance_fade: 0.1,
            directional: DirectionalShadowSettings::default(),
            other: OtherShadowSettings::default(),
        }
    }
}

/// The second atlas, for point and spot lights: up to `max_tiles` tiles in the uniform
/// layout, a spot taking one and a point six (one per cube face).
#[derive(Clone, Debug, Deserialize, serde::Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct OtherShadowSettings {
    /// Atlas side in texels (256 to 8192, a power of two). Too small blurs and blocks
    /// shadows; too large costs memory and caster time.
    pub atlas_size: u32,
    /// "pcf2x2", "tent3x3", "tent5x5" or "tent7x7", for lights whose shadows are soft.
    pub filter: String,
    /// Most tiles (1 to 64) the atlas holds: a spot takes one, a point six. Up to 16 the
    /// seeds' uniform layout (512 texels each at 2048). Past that each light's tiles are
    /// sized by how much of the screen its range covers: a quarter of the atlas side (512
    /// texels at 2048) over a fifth of the screen, an eighth (256) for most, a sixteenth
    /// (128) under 1%. Lights that do not fit get no realtime shadow (their baked shadow
    /// mask, if any).
    pub max_tiles: u32,
}

impl Default for OtherShadowSettings {
    fn default() -> Self {
        OtherShadowSettings { atlas_size: 2048, filter: "pcf2x2".into(), max_tiles: 64 }
    }
}

impl OtherShadowSettings {
    pub fn shadow_filter(&self) -> ShadowFilter {
        ShadowFilter::parse(&self.filter).unwrap_or_default()
    }
}

#[derive(Clone, Debug, Deserialize, serde::Serialize, PartialEq)]
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

/// Cascade ratios when the settings give none.
pub const DEFAULT_CASCADE_RATIOS: [f32; MAX_CASCADES - 1] = [0.1, 0.25, 0.5];

impl DirectionalShadowSettings {
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
}

#[derive(Debug, thiserror::Error)]
pub enum SettingsError {
    #[error("{path}: cannot read settings: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}: {message}")]
    Invalid { path: PathBuf, message: String },
}

impl Settings {
    pub fn load(path: &Path) -> Result<Settings, SettingsError> {
        let text = crate::files::read_regular_file(path)
            .map_err(|source| SettingsError::Io { path: path.to_path_buf(), source })?;
        let text = String::from_utf8(text)
            .map_err(|_| SettingsError::Invalid { path: path.to_path_buf(), message: "not UTF-8 text".into() })?;
        Settings::parse(&text).map_err(|message| SettingsError::Invalid { path: path.to_path_buf(), message })
    }

    /// Parses and validates TOML text; the error starts with the offending key and the
    /// line it is on: `render.width (line 2): invalid type: string "64", expected u32`.
    pub fn parse(text: &str) -> Result<Settings, String> {
        let settings: Settings = toml::from_str(text).map_err(|e| {
            // toml's message spans several lines with a source excerpt; keep it on one.
            let message = e.message().trim().replace('\n', " ");
            match e.span().map(|span| key_at(text, span.start)) {
                Some((Some(key), line)) => format!("{key} (line {line}): {message}"),
                Some((None, line)) => format!("line {line}: {message}"),
                None => message,
            }
        })?;
        settings.validate().map_err(|message| {
            // Validation messages start with `key: `; say where the file sets the key.
            let located = message
                .split_once(": ")
                .and_then(|(key, rest)| Some(format!("{key} (line {}): {rest}", line_of_key(text, key)?)));
            located.unwrap_or(message)
        })?;
        Ok(settings)
    }

    /// The settings as a TOML file that `parse` reads back equal: what the viewer's "save
    /// settings" writes.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("settings are plain TOML values")
    }

    /// The most point and spot lights the render path can shade in a frame.
    pub fn most_other_lights(&self) -> u32 {
        (match (self.render.path, self.lights.culling) {
            (RenderPath::Forward, LightCulling::None) => chiaro_math::light::MAX_OTHER_LIGHTS,
            _ => chiaro_math::light::MAX_DEFERRED_OTHER_LIGHTS,
        }) as u32
    }

    /// Point and spot lights shaded per frame: `lights.max_other_lights`, or the path's
    /// most.
    pub fn max_other_lights(&self) -> u32 {
        self.lights.max_other_lights.unwrap_or_else(|| self.most_other_lights())
    }

    /// Checks every range; the message starts with the dotted key.
    pub fn validate(&self) -> Result<(), String> {
        let r = &self.render;
        check_range("render.width", r.width as f32, 1.0, 16384.0)?;
        check_range("render.height", r.height as f32, 1.0, 16384.0)?;
        check_range("render.exposure_ev100", r.exposure_ev100, -30.0, 30.0)?;
        for (key, values) in [("render.ambient", r.ambient), ("render.background", r.background)] {
            for v in values {
                check_range(key, v, 0.0, 1.0e6)?;
            }
        }
        if ![1, 2, 4, 8].contains(&r.msaa) {
            return Err(format!("render.msaa: {} is not one of 1, 2, 4 or 8", r.msaa));
        }
        let l = &self.lights;
        if let Some(most) = l.max_other_lights {
            check_range("lights.max_other_lights", most as f32, 1.0, self.most_other_lights() as f32)?;
        }
        check_range("lights.range_threshold_lux", l.range_threshold_lux, MIN_RANGE_THRESHOLD_LUX, 1.0e6)?;
        check_range("camera.auto_yfov_deg", self.camera.auto_yfov_deg, 1.0, 179.0)?;
        let sh = &self.shadows;
        check_range("shadows.max_distance", sh.max_distance, 0.1, 10000.0)?;
        check_range("shadows.distance_fade", sh.distance_fade, 0.001, 1.0)?;
        let d = &sh.directional;
        check_atlas_and_filter("shadows.directional", d.atlas_size, &d.filter)?;
        check_range("shadows.directional.cascade_count", d.cascade_count as f32, 1.0, MAX_CASCADES as f32)?;
        if let Some(r) = &d.cascade_ratios {
            let wanted = d.cascade_count as usize - 1;
            if r.len() != wanted {
                return Err(format!(
                    "shadows.directional.cascade_ratios: takes cascade_count - 1 = {wanted} entries (the last \
                     cascade ends at max_distance), got {}",
                    r.len()
                ));
            }
            let increasing = r.windows(2).all(|w| w[0] < w[1]);
            if !(r.iter().all(|v| v.is_finite() && *v > 0.0 && *v < 1.0) && increasing) {
                return Err(format!(
                    "shadows.directional.cascade_ratios: {r:?} must increase strictly between 0 and 1"
                ));
            }
        }
        check_range("shadows.directional.cascade_fade", d.cascade_fade, 0.001, 1.0)?;
        check_atlas_and_filter("shadows.other", sh.other.atlas_size, &sh.other.filter)?;
        check_range(
            "shadows.other.max_tiles",
            sh.other.max_tiles as f32,
            1.0,
            chiaro_math::shadow::other::MAX_OTHER_SHADOW_TILES as f32,
        )?;
        let b = &self.bake;
        check_range("bake.samples", b.samples as f32, 1.0, 65536.0)?;
        check_range("bake.bounces", b.bounces as f32, 0.0, 64.0)?;
        check_range("bake.texels_per_metre", b.texels_per_metre, 0.01, 1000.0)?;
        check_range("bake.probe_spacing", b.probe_spacing, 0.05, 1000.0)?;
        check_range("bake.probe_samples", b.probe_samples as f32, 1.0, 65536.0)?;
        Ok(())
    }
}

fn check_atlas_and_filter(section: &str, atlas_size: u32, filter: &str) -> Result<(), String> {
    if !(256..=8192).contains(&atlas_size) || !atlas_size.is_power_of_two() {
        return Err(format!("{section}.atlas_size: {atlas_size} must be a power of two from 256 to 8192"));
    }
    if ShadowFilter::parse(filter).is_none() {
        return Err(format!("{section}.filter: unknown filter '{filter}' (pcf2x2, tent3x3, tent5x5, tent7x7)"));
    }
    Ok(())
}

fn check_range(key: &str, value: f32, min: f32, max: f32) -> Result<(), String> {
    if value.is_finite() && (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(format!("{key}: {} is out of range ({} to {})", number(value), number(min), number(max)))
    }
}

/// A number as a reader would write it: 1e-40, not forty zeros.
fn number(v: f32) -> String {
    if v != 0.0 && v.is_finite() && !(1.0e-4..1.0e7).contains(&v.abs()) { format!("{v:e}") } else { format!("{v}") }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_file_gives_defaults() {
        assert_eq!(Settings::parse("").unwrap(), Settings::default());
    }

    #[test]
    fn fields_override_defaults() {
        let s = Settings::parse("[render]\nexposure_ev100 = 2.5\nambient = [0, 0, 0]\n").unwrap();
        assert_eq!(s.render.exposure_ev100, 2.5);
        assert_eq!(s.render.ambient, [0.0; 3]);
        assert_eq!(s.render.width, 1280);
    }

    #[test]
    fn unknown_keys_are_named() {
        let e = Settings::parse("[render]\nexposure = 2\n").unwrap_err();
        assert!(e.contains("exposure"), "{e}");
        let e = Settings::parse("[shadowz]\n").unwrap_err();
        assert!(e.contains("shadowz"), "{e}");
    }

    #[test]
    fn settings_written_as_toml_read_back_equal() {
        let mut s = Settings::default();
        assert_eq!(Settings::parse(&s.to_toml()).unwrap(), s);
        s.render.msaa = 1;
        s.render.path = RenderPath::Deferred;
        s.lights.culling = LightCulling::PerObject;
        s.lights.max_other_lights = Some(300);
        s.shadows.directional.cascade_count = 3;
        s.shadows.directional.cascade_ratios = Some(vec![0.2, 0.6]);
        s.shadows.directional.cascade_blend = CascadeBlend::Dither;
        s.shadows.other.filter = "tent5x5".into();
        s.lighting.mixed_mode = MixedMode::Shadowmask;
        s.render.light_buffer = LightBuffer::LdrExp2;
        let text = s.to_toml();
        assert_eq!(Settings::parse(&text).unwrap(), s, "{text}");
    }

    #[test]
    fn out_of_range_values_are_named() {
        let e = Settings::parse("[lights]\nmax_other_lights = 4097\n").unwrap_err();
        assert!(e.starts_with("lights.max_other_lights"), "{e}");
        // The forward path without culling shades at most 64; culled lists up to 4096.
        let no_culling = "[render]\npath = \"forward\"\n[lights]\nculling = \"none\"\nmax_other_lights = 65\n";
        let e = Settings::parse(no_culling).unwrap_err();
        assert!(e.starts_with("lights.max_other_lights"), "{e}");
        let clustered = "[render]\npath = \"forward\"\n[lights]\nmax_other_lights = 4096\n";
        assert!(Settings::parse(clustered).is_ok(), "clustered forward shades up to 4096");
        assert!(Settings::parse("[lights]\nmax_other_lights = 65\n").is_ok(), "deferred shades up to 4096");
        for bad in ["[render]\nmsaa = 3\n", "[render]\nmsaa = 16\n", "[render]\nmsaa = 0\n"] {
            let e = Settings::parse(bad).unwrap_err();
            assert!(e.starts_with("render.msaa"), "{e}");
        }
        let e = Settings::parse("[lights]\nculling = \"tiled\"\n").unwrap_err();
        assert!(e.starts_with("lights.culling"), "{e}");
        let e = Settings::parse("[render]\nwidth = 0\n").unwrap_err();
        assert!(e.starts_with("render.width"), "{e}");
        let e = Settings::parse("[lights]\nrange_threshold_lux = 0.0\n").unwrap_err();
        assert!(e.starts_with("lights.range_threshold_lux"), "{e}");
        let e = Settings::parse("[render]\nambient = [0, -1, 0]\n").unwrap_err();
        assert!(e.starts_with("render.ambient"), "{e}");
    }

    #[test]
    fn shadow_settings_parse_and_validate() {
        let s = Settings::parse(
            "[shadows]\nmax_distance = 40\n[shadows.directional]\nfilter = \"tent5x5\"\ncascade_count = 2\ncascade_blend = \"dither\"\n",
        )
        .unwrap();
        assert_eq!(s.shadows.max_distance, 40.0);
        assert_eq!(s.shadows.directional.shadow_filter(), ShadowFilter::Tent5x5);
        assert_eq!(s.shadows.directional.cascade_blend, CascadeBlend::Dither);
        for (text, key) in [
            ("[shadows.directional]\natlas_size = 3000\n", "shadows.directional.atlas_size"),
            ("[shadows.directional]\nfilter = \"gauss\"\n", "shadows.directional.filter"),
            ("[shadows.directional]\ncascade_count = 5\n", "shadows.directional.cascade_count"),
            ("[shadows.directional]\ncascade_ratios = [0.5, 0.2, 0.7]\n", "shadows.directional.cascade_ratios"),
            ("[shadows.directional]\ncascade_ratios = [0.1, 0.2, 0.3, 0.4]\n", "shadows.directional.cascade_ratios"),
            (
                "[shadows.directional]\ncascade_count = 3\ncascade_ratios = [0.1]\n",
                "shadows.directional.cascade_ratios",
            ),
            ("[shadows]\nmax_distance = -1\n", "shadows.max_distance"),
            ("[shadows.other]\natlas_size = 100\n", "shadows.other.atlas_size"),
            ("[shadows.other]\nfilter = \"box\"\n", "shadows.other.filter"),
        ] {
            let e = Settings::parse(text).unwrap_err();
            assert!(e.starts_with(key), "{e}");
        }
        let e = Settings::parse("[shadows.directional]\ncascade_blend = \"smooth\"\n").unwrap_err();
        assert!(e.contains("smooth"), "{e}");
    }

    #[test]
    fn messages_name_the_key_and_its_line() {
        for (text, expected) in [
            ("[render]\nwidth = \"64\"\n", "render.width (line 2): invalid type: string \"64\", expected u32"),
            ("[render]\nwidth = 64\nwidth = 65\n", "render.width (line 3): duplicate key"),
            (
                "\n[shadows.directional]\nfilter = 3\n",
                "shadows.directional.filter (line 3): invalid type: integer `3`, expected a string",
            ),
            (
                "[shadows.directional]\ncascade_blend = \"smooth\"\n",
                "shadows.directional.cascade_blend (line 2): unknown variant `smooth`, expected one of `hard`, \
                 `soft`, `dither`",
            ),
            ("[render]\n\nwidth = 0\n", "render.width (line 3): 0 is out of range (1 to 16384)"),
            (
                "[shadows.directional]\ncascade_ratios = [0.1, 0.2, 0.3, 0.4]\n",
                "shadows.directional.cascade_ratios (line 2): takes cascade_count - 1 = 3 entries (the last \
                 cascade ends at max_distance), got 4",
            ),
            (
                "[lights]\nrange_threshold_lux = 1e-40\n",
                "lights.range_threshold_lux (line 2): 1e-40 is out of range (1e-6 to 1000000)",
            ),
        ] {
            let e = Settings::parse(text).unwrap_err();
            assert!(e.starts_with(expected), "{text:?}: {e}");
        }
    }

    #[test]
    fn cascade_ratios_take_one_fewer_than_the_cascades() {
        let s = Settings::parse("[shadows.directional]\ncascade_count = 2\ncascade_ratios = [0.3]\n").unwrap();
        assert_eq!(s.shadows.directional.ratios()[0], 0.3);
        // Unset, the defaults serve any count.
        let s = Settings::parse("[shadows.directional]\ncascade_count = 2\n").unwrap();
        assert_eq!(s.shadows.directional.ratios(), DEFAULT_CASCADE_RATIOS);
    }
}
