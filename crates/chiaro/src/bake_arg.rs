//! `--bake DIR` and `--no-bake`, shared by render, bench and compare: which bake lights
//! the scene. By default `<scene stem>.bake/` beside the scene, when it is there and
//! matches the scene; a bake that does not match is ignored with a warning that says why,
//! and baked lights then render realtime.

use anyhow::{Result, bail};
use chiaro_bake::{apply_bake_dir, default_bake_dir};
use chiaro_scene::{LightMode, Scene, Settings};
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Args, Clone, Debug, Default)]
pub struct BakeUseArgs {
    /// Bake directory to light the scene with (default: `<scene stem>.bake/` beside the
    /// scene, when it is there).
    #[arg(long, value_name = "DIR", conflicts_with = "no_bake")]
    pub bake: Option<PathBuf>,
    /// Ignore any bake: every light renders realtime.
    #[arg(long)]
    pub no_bake: bool,
}

impl BakeUseArgs {
    /// Attaches the bake to `scene` (read from `scene_path`, if from a file). Returns the
    /// directory used.
    pub fn apply(&self, scene: &mut Scene, scene_path: Option<&Path>, settings: &Settings) -> Result<Option<PathBuf>> {
        if self.no_bake {
            return Ok(None);
        }
        let dir = match (&self.bake, scene_path) {
            (Some(dir), _) => {
                if !dir.join(chiaro_bake::bake_dir::MANIFEST).is_file() {
                    bail!("--bake {}: not a bake directory (no {})", dir.display(), chiaro_bake::bake_dir::MANIFEST);
                }
                dir.clone()
            }
            (None, Some(path)) => default_bake_dir(path),
            (None, None) => return Ok(self.warn_baked_lights(scene)),
        };
        if !dir.exists() {
            return Ok(self.warn_baked_lights(scene));
        }
        match apply_bake_dir(&dir, scene) {
            Ok(manifest) => {
                let mode = settings.lighting.mixed_mode;
                let has_masks = !manifest.shadow_masks.is_empty();
                if manifest.mixed_mode != mode && (has_masks || mode.uses_shadow_mask()) {
                    tracing::warn!(
                        "{}: baked for lighting.mixed_mode {}, rendering with {}: {}",
                        dir.display(),
                        manifest.mixed_mode.name(),
                        mode.name(),
                        if mode.uses_shadow_mask() && !has_masks {
                            "the bake has no shadow masks, so mixed lights have realtime shadows only"
                        } else if !mode.uses_shadow_mask() {
                            "its shadow masks are not used"
                        } else {
                            "its shadow masks are mixed the new way"
                        }
                    );
                }
                tracing::info!(
                    "{}: lit by {} lightmap atlases and {} probes",
                    dir.display(),
                    manifest.lightmaps.len(),
                    manifest.stats.probes
                );
                Ok(Some(dir))
            }
            Err(why) => {
                tracing::warn!("ignoring the bake: {why}");
                Ok(self.warn_baked_lights(scene))
            }
        }
    }

    fn warn_baked_lights(&self, scene: &Scene) -> Option<PathBuf> {
        let baked = scene.lights.iter().filter(|l| l.mode != LightMode::Realtime).count();
        if baked > 0 {
            tracing::warn!(
                "{baked} lights are baked or mixed but no bake lights the scene: they render realtime (run chiaro \
                 bake)"
            );
        }
        None
    }
}
