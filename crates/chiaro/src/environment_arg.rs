//! `--environment`: the light from every direction, shared by render, compare, bench and
//! view; overrides `[environment] source`.

use anyhow::{Result, anyhow};
use chiaro_scene::Settings;
use chiaro_scene::settings::EnvironmentSource;
use clap::Args;

#[derive(Args, Clone, Debug, Default)]
pub struct EnvironmentArg {
    /// none (the file's EXT_lights_image_based light if any), ambient (the constant term),
    /// neutral (a studio), sky (daylight from the first directional light) or an
    /// equirectangular .hdr/.exr image (overrides environment.source).
    #[arg(long, value_name = "SOURCE")]
    pub environment: Option<String>,
}

impl EnvironmentArg {
    /// Applies the override; a name that is no source is an error naming the flag.
    pub fn apply(&self, settings: &mut Settings) -> Result<()> {
        if let Some(text) = &self.environment {
            settings.environment.source = EnvironmentSource::parse(text).map_err(|e| anyhow!("--environment: {e}"))?;
        }
        Ok(())
    }
}
