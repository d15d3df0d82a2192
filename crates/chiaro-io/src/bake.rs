//! Which bake lights a scene: a bake directory named outright, none at all, or by default
//! `<scene stem>.bake/` beside the scene when it is there and matches the scene. A bake
//! that does not match is ignored with a warning that says why, and baked lights then
//! render realtime.

use anyhow::{Result, bail};
use chiaro_bake::{apply_bake_dir, default_bake_dir};
use chiaro_scene::{LightMode, Scene, Settings};
use std::path::{Path, PathBuf};

/// The bake a command was asked to use.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BakeChoice {
    /// `--bake DIR`: this directory, which must hold a bake.
    pub dir: Option<PathBuf>,
    /// `--no-bake`: every light renders realtime.
    pub none: bool,
}

impl BakeChoice {
    /// Attaches the bake to `scene` (read from `scene_path`, if from a file). Returns the
    /// directory used.
    pub fn apply(&self, scene: &mut Scene, scene_path: Option<&Path>, settings: &Settings) -> Result<Option<PathBuf>> {
        if self.none {
            return Ok(None);
        }
        let dir = match (&self.dir, scene_path) {
            (Some(dir), _) => {
                if !dir.join(chiaro_bake::bake_dir::MANIFEST).is_file() {
                    bail!("--bake {}: not a bake directory (no {})", dir.display(), chiaro_bake::bake_dir::MANIFEST);
                }
                dir.clone()
            }
            (None, Some(path)) => default_bake_dir(path),
            (None, None) => return Ok(warn_baked_lights(scene)),
        };
        if !dir.exists() {
            return Ok(warn_baked_lights(scene));
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
                Ok(warn_baked_lights(scene))
            }
        }
    }
}

fn warn_baked_lights(scene: &Scene) -> Option<PathBuf> {
    let baked = scene.lights.iter().filter(|l| l.mode != LightMode::Realtime).count();
    if baked > 0 {
        tracing::warn!(
            "{baked} lights are baked or mixed but no bake lights the scene: they render realtime (run chiaro \
             bake)"
        );
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bake_directory_named_outright_must_hold_a_bake() {
        let dir = tempfile::tempdir().unwrap();
        let choice = BakeChoice { dir: Some(dir.path().to_path_buf()), none: false };
        let mut scene = Scene::default();
        let error = choice.apply(&mut scene, None, &Settings::default()).unwrap_err().to_string();
        let expected =
            format!("--bake {}: not a bake directory (no {})", dir.path().display(), chiaro_bake::bake_dir::MANIFEST);
        assert_eq!(error, expected);
        let none = BakeChoice { dir: Some(dir.path().to_path_buf()), none: true };
        assert_eq!(none.apply(&mut scene, None, &Settings::default()).unwrap(), None, "--no-bake reads nothing");
    }
}
