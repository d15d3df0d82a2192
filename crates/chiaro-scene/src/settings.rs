//! Pipeline settings, read from a TOML file in which every field is optional.
//!
//! Unknown keys and out-of-range values are errors that name the key: a typo must never
//! fall back to a default silently. Later stages (shadows, baking, the deferred path) add
//! their own sections here.

use serde::Deserialize;
use std::path::{Path, PathBuf};

/// All settings; `Settings::default()` is what a missing file means.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    pub render: RenderSettings,
    pub lights: LightSettings,
    pub camera: CameraSettings,
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
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
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 1280,
            height: 720,
            exposure_ev100: 0.0,
            ambient: [0.02, 0.02, 0.025],
            background: [0.0, 0.0, 0.0],
        }
    }
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct LightSettings {
    /// Most point and spot lights shaded per frame (1 to 64). The most important visible
    /// ones are kept; a lower cap is faster but drops distant lights.
    pub max_other_lights: u32,
    /// Illuminance (lux) at which a light with no range in its file is cut off:
    /// `range = sqrt(intensity / threshold)`. Too high cuts lights off visibly early; too
    /// low gives huge volumes that touch everything and cost shading time.
    pub range_threshold_lux: f32,
}

impl Default for LightSettings {
    fn default() -> Self {
        LightSettings {
            max_other_lights: chiaro_math::light::MAX_OTHER_LIGHTS as u32,
            range_threshold_lux: 0.01,
        }
    }
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CameraSettings {
    /// Vertical field of view (degrees, 1 to 179) of the camera made when a scene has none.
    pub auto_yfov_deg: f32,
}

impl Default for CameraSettings {
    fn default() -> Self {
        CameraSettings {
            auto_yfov_deg: 45.0,
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum SettingsError {
    #[error("{path}: cannot read settings: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: {message}")]
    Invalid { path: PathBuf, message: String },
}

impl Settings {
    pub fn load(path: &Path) -> Result<Settings, SettingsError> {
        let text = std::fs::read_to_string(path).map_err(|source| SettingsError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Settings::parse(&text).map_err(|message| SettingsError::Invalid {
            path: path.to_path_buf(),
            message,
        })
    }

    /// Parses and validates TOML text; the error names the offending key.
    pub fn parse(text: &str) -> Result<Settings, String> {
        let settings: Settings = toml::from_str(text).map_err(|e| {
            // toml's message spans several lines with a source excerpt; keep it on one.
            e.message().trim().replace('\n', " ")
        })?;
        settings.validate()?;
        Ok(settings)
    }

    /// Checks every range; the message starts with the dotted key.
    pub fn validate(&self) -> Result<(), String> {
        let r = &self.render;
        check_range("render.width", r.width as f32, 1.0, 16384.0)?;
        check_range("render.height", r.height as f32, 1.0, 16384.0)?;
        check_range("render.exposure_ev100", r.exposure_ev100, -30.0, 30.0)?;
        for (key, values) in [
            ("render.ambient", r.ambient),
            ("render.background", r.background),
        ] {
            for v in values {
                check_range(key, v, 0.0, 1.0e6)?;
            }
        }
        let l = &self.lights;
        check_range(
            "lights.max_other_lights",
            l.max_other_lights as f32,
            1.0,
            chiaro_math::light::MAX_OTHER_LIGHTS as f32,
        )?;
        if !(l.range_threshold_lux.is_finite() && l.range_threshold_lux > 0.0) {
            return Err(format!(
                "lights.range_threshold_lux: must be a positive number, got {}",
                l.range_threshold_lux
            ));
        }
        check_range(
            "camera.auto_yfov_deg",
            self.camera.auto_yfov_deg,
            1.0,
            179.0,
        )?;
        Ok(())
    }
}

fn check_range(key: &str, value: f32, min: f32, max: f32) -> Result<(), String> {
    if value.is_finite() && (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(format!("{key}: {value} is out of range ({min} to {max})"))
    }
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
    fn out_of_range_values_are_named() {
        let e = Settings::parse("[lights]\nmax_other_lights = 65\n").unwrap_err();
        assert!(e.starts_with("lights.max_other_lights"), "{e}");
        let e = Settings::parse("[render]\nwidth = 0\n").unwrap_err();
        assert!(e.starts_with("render.width"), "{e}");
        let e = Settings::parse("[lights]\nrange_threshold_lux = 0.0\n").unwrap_err();
        assert!(e.starts_with("lights.range_threshold_lux"), "{e}");
        let e = Settings::parse("[render]\nambient = [0, -1, 0]\n").unwrap_err();
        assert!(e.starts_with("render.ambient"), "{e}");
    }

    #[test]
    fn wrong_types_are_errors() {
        let e = Settings::parse("[render]\nwidth = \"wide\"\n").unwrap_err();
        assert!(e.contains("width") || e.contains("invalid type"), "{e}");
    }
}
