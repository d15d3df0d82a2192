//! `[render]`: the output image (size, exposure, ambient and background radiance), the
//! render path and MSAA. TOML values flow in; `RenderSettings` and its validation flow out.

use super::bound::Bound;
use serde::{Deserialize, Serialize};

/// The `[render]` section: what the frame looks like and how it is shaded.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
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
    /// deferred path does with none on lavapipe, docs/performance.md) or "deferred" (a G-buffer, then one
    /// light volume per light; FXAA rather than MSAA, see `deferred_antialiasing`).
    pub path: RenderPath,
    /// The deferred path's light accumulation: "hdr" (half floats, the default) or
    /// "ldr-exp2" (the legacy 8-bit buffer storing exp2(-light) of Catlike Coding's
    /// "Rendering 15, Deferred Lights"), which bands dark tones and clips bright ones.
    pub light_buffer: LightBuffer,
    /// Samples per pixel of the forward path's colour and depth (1, 2, 4 or 8), resolved
    /// before tone mapping. The deferred path, and frames that report AOVs, render one.
    pub msaa: u32,
    /// How the deferred path smooths its edges where `msaa` is above 1 (its G-buffer has
    /// one sample): "fxaa" (the default: a post-process over the lit HDR image, before
    /// tone mapping, as an MSAA resolve blends) or "none".
    pub deferred_antialiasing: DeferredAntialiasing,
    /// The display curve after exposure: "pbr-neutral" (the default: Khronos PBR Neutral,
    /// base colours kept up to 0.8), "aces" (the fitted ACES filmic curve of three.js and
    /// the Khronos render-fidelity renderers), "agx" (Blender's AgX base) or "linear"
    /// (clamped).
    pub tone_mapping: ToneMapping,
}

/// The display curve the tone mapping pass applies (chiaro_math::tonemap).
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum ToneMapping {
    /// Khronos PBR Neutral.
    #[default]
    PbrNeutral,
    /// Stephen Hill's fit of ACES (exposure / 0.6, RRT + sRGB ODT).
    Aces,
    /// Blender's AgX base.
    Agx,
    /// Exposed radiance clamped to [0, 1].
    Linear,
}

/// The deferred path's antialiasing.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "lowercase")]
pub enum DeferredAntialiasing {
    /// Fast approximate antialiasing: edges found from luma contrast, blended along them.
    #[default]
    Fxaa,
    /// None: every edge keeps its staircase.
    None,
}

/// How a frame is shaded.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "lowercase")]
pub enum RenderPath {
    /// A depth prepass, then every draw shaded with its lights (MSAA allowed).
    #[default]
    Forward,
    /// A G-buffer, then one light volume per light (no MSAA).
    Deferred,
}

/// Where the deferred path accumulates light.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq, Hash)]
pub enum LightBuffer {
    /// Half floats: no banding or clipping.
    #[default]
    #[serde(rename = "hdr")]
    Hdr,
    /// The 8-bit buffer storing exp2(-light) of Catlike Coding's "Rendering 15, Deferred
    /// Lights": bands dark tones, clips bright ones.
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
            deferred_antialiasing: DeferredAntialiasing::Fxaa,
            tone_mapping: ToneMapping::PbrNeutral,
        }
    }
}

/// Largest radiance a colour setting may give: far past any exposure, short of overflow.
const MAX_RADIANCE: f32 = 1.0e6;

/// The largest image side in pixels.
const MAX_SIDE_PX: f32 = 16384.0;

/// The interval of `render.width`.
pub const WIDTH: Bound = Bound::new("render.width", 1.0, MAX_SIDE_PX);
/// The interval of `render.height`.
pub const HEIGHT: Bound = Bound::new("render.height", 1.0, MAX_SIDE_PX);
/// The interval of `render.exposure_ev100`.
pub const EXPOSURE_EV100: Bound = Bound::new("render.exposure_ev100", -30.0, 30.0);
/// The interval of each channel of `render.ambient`.
pub const AMBIENT: Bound = Bound::new("render.ambient", 0.0, MAX_RADIANCE);
/// The interval of each channel of `render.background`.
pub const BACKGROUND: Bound = Bound::new("render.background", 0.0, MAX_RADIANCE);
/// The sample counts `render.msaa` may take.
pub const MSAA_CHOICES: [u32; 4] = [1, 2, 4, 8];

/// Every interval of the section.
pub(super) const BOUNDS: &[Bound] = &[WIDTH, HEIGHT, EXPOSURE_EV100, AMBIENT, BACKGROUND];

/// The choices as a sentence: "1, 2, 4 or 8".
pub(super) fn msaa_choices_text() -> String {
    let names: Vec<String> = MSAA_CHOICES.iter().map(u32::to_string).collect();
    let (last, rest) = names.split_last().expect("there are choices");
    format!("{} or {last}", rest.join(", "))
}

impl RenderSettings {
    /// Checks every value of the section; the message starts with the dotted key.
    pub fn validate(&self) -> Result<(), String> {
        WIDTH.check(self.width as f32)?;
        HEIGHT.check(self.height as f32)?;
        EXPOSURE_EV100.check(self.exposure_ev100)?;
        for (bound, values) in [(AMBIENT, self.ambient), (BACKGROUND, self.background)] {
            for v in values {
                bound.check(v)?;
            }
        }
        if !MSAA_CHOICES.contains(&self.msaa) {
            return Err(format!("render.msaa: {} is not one of {}", self.msaa, msaa_choices_text()));
        }
        Ok(())
    }
}
