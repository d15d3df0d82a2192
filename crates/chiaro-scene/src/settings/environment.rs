//! `[environment]`: the light that arrives from every direction at once: none (the
//! constant ambient term), a studio environment Chiaro makes, an analytic daylight sky,
//! or an equirectangular HDR image. TOML values flow in; `EnvironmentSettings` and its
//! validation flow out. The maps themselves are made by `crate::environment`.

use super::bound::Bound;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The `[environment]` section.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct EnvironmentSettings {
    /// "none" (the default: the environment the glTF file carries with
    /// EXT_lights_image_based, else the constant ambient term of `render.ambient`),
    /// "ambient" (the constant ambient term even for such a file), "neutral" (a studio
    /// environment), "sky" (a daylight sky from the first directional light), or the path
    /// of an equirectangular `.hdr` or `.exr` image.
    pub source: EnvironmentSource,
    /// A multiplier of the environment's radiance.
    pub intensity: f32,
    /// Degrees the environment is turned about +Y.
    pub rotation_deg: f32,
    /// Draw the environment behind the scene (true) or keep `render.background`.
    pub background: bool,
    /// "realtime" (unshadowed image-based light) or "baked" (the baker traces the
    /// environment, shadowed, into lightmaps and probes).
    pub mode: EnvironmentMode,
}

impl Default for EnvironmentSettings {
    fn default() -> Self {
        EnvironmentSettings {
            source: EnvironmentSource::None,
            intensity: 1.0,
            rotation_deg: 0.0,
            background: true,
            mode: EnvironmentMode::Realtime,
        }
    }
}

/// Where the environment's radiance comes from.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(try_from = "String", into = "String")]
pub enum EnvironmentSource {
    /// None of its own: the glTF file's EXT_lights_image_based environment where it
    /// carries one, else the constant ambient term.
    #[default]
    None,
    /// The constant ambient term, even for a file that carries an environment.
    Ambient,
    /// A studio-like environment Chiaro makes: soft boxes over a grey room.
    Neutral,
    /// An analytic clear daylight sky for the first directional light's direction.
    Sky,
    /// An equirectangular (2:1) Radiance `.hdr` or OpenEXR image.
    File(PathBuf),
}

/// The names `source` takes besides a path, for messages and the viewer.
pub const SOURCE_NAMES: [&str; 4] = ["none", "ambient", "neutral", "sky"];

impl EnvironmentSource {
    /// The source a settings value or `--environment` argument names: one of
    /// `SOURCE_NAMES`, or a path ending in `.hdr` or `.exr`.
    pub fn parse(text: &str) -> Result<EnvironmentSource, String> {
        match text {
            "none" => Ok(EnvironmentSource::None),
            "ambient" => Ok(EnvironmentSource::Ambient),
            "neutral" => Ok(EnvironmentSource::Neutral),
            "sky" => Ok(EnvironmentSource::Sky),
            path => {
                let extension = Path::new(path).extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
                match extension.as_deref() {
                    Some("hdr" | "exr") => Ok(EnvironmentSource::File(PathBuf::from(path))),
                    _ => Err(format!(
                        "\"{path}\" is not none, ambient, neutral, sky or the path of a .hdr or .exr image"
                    )),
                }
            }
        }
    }

    /// The source as the settings file spells it.
    pub fn name(&self) -> String {
        match self {
            EnvironmentSource::None => "none".into(),
            EnvironmentSource::Ambient => "ambient".into(),
            EnvironmentSource::Neutral => "neutral".into(),
            EnvironmentSource::Sky => "sky".into(),
            EnvironmentSource::File(path) => path.display().to_string(),
        }
    }

    /// A relative image path taken as relative to `dir` (the settings file's folder).
    pub fn relative_to(self, dir: &Path) -> EnvironmentSource {
        match self {
            EnvironmentSource::File(path) if path.is_relative() => EnvironmentSource::File(dir.join(path)),
            other => other,
        }
    }
}

impl TryFrom<String> for EnvironmentSource {
    type Error = String;
    fn try_from(text: String) -> Result<Self, String> {
        EnvironmentSource::parse(&text)
    }
}

impl From<EnvironmentSource> for String {
    fn from(source: EnvironmentSource) -> String {
        source.name()
    }
}

/// How environment light reaches surfaces.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "lowercase")]
pub enum EnvironmentMode {
    /// Image-based light every frame, unshadowed.
    #[default]
    Realtime,
    /// Traced by the baker into lightmaps and probes, shadowed by static objects.
    Baked,
}

/// The interval of `environment.intensity`.
pub const INTENSITY: Bound = Bound::new("environment.intensity", 0.0, 1.0e6);
/// The interval of `environment.rotation_deg`.
pub const ROTATION_DEG: Bound = Bound::new("environment.rotation_deg", -360.0, 360.0);

/// Every interval of the section.
pub(super) const BOUNDS: &[Bound] = &[INTENSITY, ROTATION_DEG];

impl EnvironmentSettings {
    /// Checks every value of the section; the message starts with the dotted key.
    pub fn validate(&self) -> Result<(), String> {
        INTENSITY.check(self.intensity)?;
        ROTATION_DEG.check(self.rotation_deg)
    }

    /// Whether frames of `scene` are lit by an environment rather than the constant
    /// ambient term.
    pub fn enabled_for(&self, scene: &crate::types::Scene) -> bool {
        match self.source {
            EnvironmentSource::None => scene.environment.is_some(),
            EnvironmentSource::Ambient => false,
            _ => true,
        }
    }

    /// The environment `scene` is lit by, for messages: the source's name, or the file's
    /// own environment's label.
    pub fn describe(&self, scene: &crate::types::Scene) -> String {
        match (&self.source, &scene.environment) {
            (EnvironmentSource::None, Some(own)) => own.label.clone(),
            (source, _) => source.name(),
        }
    }
}
