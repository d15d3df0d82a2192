//! Pipeline settings, read from a TOML file in which every field is optional.
//!
//! TOML text flows in; a validated `Settings` flows out, or a message that starts with
//! the offending key and its line. Unknown keys and out-of-range values are errors that
//! name the key: a typo must never fall back to a default silently.
//!
//! One module per section of the file (`render`, `lights`, `camera`, `shadows` with its
//! `directional` and `other` subsections, `lighting`, `bake`, `environment`, `scene`,
//! `ambient_occlusion`),
//! each holding its struct, defaults, ranges and validation. Every numeric range is a `Bound` written once, which
//! validation checks and a test compares with docs/settings.md.

pub mod ambient_occlusion;
pub mod bake;
pub mod bound;
pub mod camera;
pub mod environment;
pub mod lighting;
pub mod lights;
pub mod render;
pub mod scene;
pub mod shadows;
mod text;

#[cfg(test)]
mod doc_tests;
#[cfg(test)]
mod tests;

pub use ambient_occlusion::{AmbientOcclusionSettings, AoQuality};
pub use bake::{BakeQuality, BakeSettings};
pub use bound::Bound;
pub use camera::CameraSettings;
pub use environment::{EnvironmentMode, EnvironmentSettings, EnvironmentSource};
pub use lighting::{LightingSettings, MixedMode};
pub use lights::{LightCulling, LightSettings};
pub use render::{DeferredAntialiasing, LightBuffer, RenderPath, RenderSettings, ToneMapping};
pub use scene::SceneSettings;
pub use shadows::{
    CascadeBlend, DEFAULT_CASCADE_RATIOS, DirectionalShadowSettings, LocalShadowSettings, ShadowSettings,
    ShadowTechnique,
};

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use text::{key_at, line_of_key};

/// All settings; `Settings::default()` is what a missing file means.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    /// `[render]`: image size, exposure, render path, MSAA.
    pub render: RenderSettings,
    /// `[lights]`: how many point and spot lights are shaded, and how they are culled.
    pub lights: LightSettings,
    /// `[camera]`: the camera made for scenes without one.
    pub camera: CameraSettings,
    /// `[shadows]`: shadow distance, fading, caching and the two atlases.
    pub shadows: ShadowSettings,
    /// `[bake]`: the lightmap and probe baker.
    pub bake: BakeSettings,
    /// `[lighting]`: how mixed lights' baked and realtime shadows combine.
    pub lighting: LightingSettings,
    /// `[environment]`: image-based light from a studio, a sky or an HDR image.
    pub environment: EnvironmentSettings,
    /// `[scene]`: which material variant of the file to render.
    pub scene: SceneSettings,
    /// `[ambient_occlusion]`: screen-space occlusion of indirect light.
    pub ambient_occlusion: AmbientOcclusionSettings,
}

/// Why a settings file could not be used; both variants name the file.
#[derive(Debug, thiserror::Error)]
pub enum SettingsError {
    /// The file could not be read.
    #[error("{path}: cannot read settings: {source}")]
    Io {
        /// The settings file.
        path: PathBuf,
        /// What the file system said.
        source: std::io::Error,
    },
    /// The file is not valid settings; `message` names the key and its line.
    #[error("{path}: {message}")]
    Invalid {
        /// The settings file.
        path: PathBuf,
        /// What is wrong, starting with the dotted key.
        message: String,
    },
}

/// Every numeric range a setting has, section by section.
pub fn bounds() -> Vec<Bound> {
    let sections =
        [render::BOUNDS, lights::BOUNDS, camera::BOUNDS, bake::BOUNDS, environment::BOUNDS, ambient_occlusion::BOUNDS];
    sections.into_iter().flatten().copied().chain(shadows::bounds()).collect()
}

impl Settings {
    /// Reads and validates the settings file at `path`.
    pub fn load(path: &Path) -> Result<Settings, SettingsError> {
        let text = crate::files::read_regular_file(path)
            .map_err(|source| SettingsError::Io { path: path.to_path_buf(), source })?;
        let text = String::from_utf8(text)
            .map_err(|_| SettingsError::Invalid { path: path.to_path_buf(), message: "not UTF-8 text".into() })?;
        let mut settings =
            Settings::parse(&text).map_err(|message| SettingsError::Invalid { path: path.to_path_buf(), message })?;
        // An environment image named in the file is found beside the file.
        let dir = path.parent().unwrap_or(Path::new(""));
        settings.environment.source = std::mem::take(&mut settings.environment.source).relative_to(dir);
        Ok(settings)
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
        lights::max_other_lights_bound(self.render.path, self.lights.culling).max as u32
    }

    /// Point and spot lights shaded per frame: `lights.max_other_lights`, or the path's
    /// most.
    pub fn max_other_lights(&self) -> u32 {
        self.lights.max_other_lights.unwrap_or_else(|| self.most_other_lights())
    }

    /// Checks every range, section by section; the message starts with the dotted key.
    pub fn validate(&self) -> Result<(), String> {
        self.render.validate()?;
        self.lights.validate(self.render.path)?;
        self.camera.validate()?;
        self.shadows.validate()?;
        self.bake.validate()?;
        self.environment.validate()?;
        self.ambient_occlusion.validate()?;
        self.scene.validate()
    }
}
