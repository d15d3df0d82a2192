//! Whether the device renders what the settings ask, with errors that say where the
//! asking came from (a flag, a settings file's key, or the defaults).

use anyhow::{Result, anyhow};
use chiaro_render::GpuContext;
use chiaro_scene::{RenderPath, Settings};
use std::path::Path;

/// Checks that the device can render the forward path's MSAA sample count, naming where
/// the count came from: `--msaa` (when `msaa_flag` holds it), the settings file's key, or
/// the default.
pub fn check_msaa(
    ctx: &GpuContext,
    settings: &Settings,
    msaa_flag: Option<u32>,
    settings_file: Option<&Path>,
) -> Result<()> {
    let msaa = settings.render.msaa;
    if settings.render.path == RenderPath::Deferred {
        return Ok(());
    }
    ctx.check_msaa(msaa).map_err(|e| {
        let source = match (msaa_flag, settings_file) {
            (Some(_), _) => format!("--msaa {msaa}"),
            (None, Some(file)) => format!("{}: render.msaa = {msaa}", file.display()),
            (None, None) => format!("render.msaa = {msaa}"),
        };
        anyhow!("{source}: {e}")
    })
}
