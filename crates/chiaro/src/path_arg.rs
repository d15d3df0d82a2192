//! How a frame is shaded, shared by render, bench and compare: `--path forward |
//! deferred`, `--msaa N`, `--culling clustered | per-object | none` and `--tone-mapping
//! pbr-neutral | aces | agx | linear`.

use anyhow::{Result, anyhow};
use chiaro_render::GpuContext;
use chiaro_scene::{LightCulling, RenderPath, Settings, ToneMapping};
use clap::{Args, ValueEnum};
use std::path::Path;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PathChoice {
    /// Every draw lit in one pass by its culled lights (up to 4096 point and spot lights).
    Forward,
    /// A G-buffer, then one light volume per light (up to 4096 point and spot lights).
    Deferred,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CullingChoice {
    /// A froxel grid of light lists.
    Clustered,
    /// Each object's eight most important lights.
    PerObject,
    /// Every light at every pixel (up to 64).
    None,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ToneChoice {
    /// Khronos PBR Neutral: base colours kept up to 0.8, highlights rolled off.
    PbrNeutral,
    /// The fitted ACES filmic curve of three.js and the Khronos render-fidelity renderers.
    Aces,
    /// Blender's AgX base.
    Agx,
    /// Exposed radiance clamped to [0, 1].
    Linear,
}

#[derive(Args, Clone, Debug, Default)]
pub struct PathArgs {
    /// Render path (overrides render.path).
    #[arg(long, value_enum)]
    pub path: Option<PathChoice>,
    /// Samples per pixel on the forward path: 1, 2, 4 or 8 (overrides render.msaa).
    #[arg(long)]
    pub msaa: Option<u32>,
    /// How the forward pass finds its point and spot lights (overrides lights.culling).
    #[arg(long, value_enum)]
    pub culling: Option<CullingChoice>,
    /// The display curve (overrides render.tone_mapping).
    #[arg(long, value_enum)]
    pub tone_mapping: Option<ToneChoice>,
}

impl PathArgs {
    /// Applies the overrides and validates the result, naming the flags (a light cap may
    /// not suit the path or the culling).
    pub fn apply(&self, settings: &mut Settings) -> Result<()> {
        let mut flags = Vec::new();
        if let Some(path) = self.path {
            settings.render.path = match path {
                PathChoice::Forward => RenderPath::Forward,
                PathChoice::Deferred => RenderPath::Deferred,
            };
            flags.push("--path");
        }
        if let Some(msaa) = self.msaa {
            settings.render.msaa = msaa;
            flags.push("--msaa");
        }
        if let Some(culling) = self.culling {
            settings.lights.culling = match culling {
                CullingChoice::Clustered => LightCulling::Clustered,
                CullingChoice::PerObject => LightCulling::PerObject,
                CullingChoice::None => LightCulling::None,
            };
            flags.push("--culling");
        }
        if let Some(curve) = self.tone_mapping {
            settings.render.tone_mapping = match curve {
                ToneChoice::PbrNeutral => ToneMapping::PbrNeutral,
                ToneChoice::Aces => ToneMapping::Aces,
                ToneChoice::Agx => ToneMapping::Agx,
                ToneChoice::Linear => ToneMapping::Linear,
            };
            flags.push("--tone-mapping");
        }
        if !flags.is_empty() {
            settings.validate().map_err(|e| anyhow!("{}: {e}", flags.join(", ")))?;
        }
        Ok(())
    }
}

impl PathArgs {
    /// Checks that the device can render the forward path's MSAA sample count, naming
    /// where the count came from: the flag, or the settings file's key.
    pub fn check_device(&self, ctx: &GpuContext, settings: &Settings, settings_file: Option<&Path>) -> Result<()> {
        chiaro_io::device::check_msaa(ctx, settings, self.msaa, settings_file)
    }
}
