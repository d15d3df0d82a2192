//! `--path forward | deferred`, shared by render, bench and compare.

use anyhow::{Result, anyhow};
use chiaro_scene::{RenderPath, Settings};
use clap::{Args, ValueEnum};

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PathChoice {
    /// Every light in one pass per draw (up to 64 point and spot lights).
    Forward,
    /// A G-buffer, then one light volume per light (up to 4096 point and spot lights).
    Deferred,
}

#[derive(Args, Clone, Debug, Default)]
pub struct PathArgs {
    /// Render path (overrides render.path).
    #[arg(long, value_enum)]
    pub path: Option<PathChoice>,
}

impl PathArgs {
    /// Applies the override and validates the result (a light cap may not suit the path).
    pub fn apply(&self, settings: &mut Settings) -> Result<()> {
        if let Some(path) = self.path {
            settings.render.path = match path {
                PathChoice::Forward => RenderPath::Forward,
                PathChoice::Deferred => RenderPath::Deferred,
            };
            settings.validate().map_err(|e| anyhow!("--path: {e}"))?;
        }
        Ok(())
    }
}
