//! Command-line overrides of the shadow settings, shared by render, compare and bench.

use anyhow::{Result, anyhow};
use chiaro_scene::Settings;
use clap::Args;

#[derive(Args, Clone, Debug, Default)]
pub struct ShadowArgs {
    /// Max shadow distance in metres (overrides shadows.max_distance).
    #[arg(long, allow_hyphen_values = true)]
    pub shadow_distance: Option<f32>,
    /// pcf2x2, tent3x3, tent5x5 or tent7x7 (overrides shadows.directional.filter).
    #[arg(long)]
    pub shadow_filter: Option<String>,
    /// Cascades per directional light, 1 to 4 (overrides shadows.directional.cascade_count).
    #[arg(long)]
    pub cascades: Option<u32>,
    /// Directional shadow atlas size (overrides shadows.directional.atlas_size).
    #[arg(long)]
    pub shadow_atlas_size: Option<u32>,
    /// Point/spot shadow atlas size (overrides shadows.other.atlas_size).
    #[arg(long)]
    pub other_shadow_atlas_size: Option<u32>,
    /// Point/spot shadow filter (overrides shadows.other.filter).
    #[arg(long)]
    pub other_shadow_filter: Option<String>,
}

impl ShadowArgs {
    /// Applies the overrides and validates the result, naming the flag on error.
    pub fn apply(&self, settings: &mut Settings) -> Result<()> {
        if let Some(d) = self.shadow_distance {
            settings.shadows.max_distance = d;
        }
        if let Some(f) = &self.shadow_filter {
            settings.shadows.directional.filter = f.clone();
        }
        if let Some(c) = self.cascades {
            settings.shadows.directional.cascade_count = c;
        }
        if let Some(s) = self.shadow_atlas_size {
            settings.shadows.directional.atlas_size = s;
        }
        if let Some(s) = self.other_shadow_atlas_size {
            settings.shadows.other.atlas_size = s;
        }
        if let Some(f) = &self.other_shadow_filter {
            settings.shadows.other.filter = f.clone();
        }
        settings.validate().map_err(|e| anyhow!("command-line shadow option: {e}"))
    }
}
