//! `--bake DIR` and `--no-bake`, shared by render, bench and compare: which bake lights
//! the scene. By default `<scene stem>.bake/` beside the scene, when it is there and
//! matches the scene; a bake that does not match is ignored with a warning that says why,
//! and baked lights then render realtime.

use anyhow::Result;
use chiaro_io::bake::BakeChoice;
use chiaro_scene::{Scene, Settings};
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
    /// The bake these flags ask for, as chiaro-io applies it.
    pub fn choice(&self) -> BakeChoice {
        BakeChoice { dir: self.bake.clone(), none: self.no_bake }
    }

    /// Attaches the bake to `scene` (read from `scene_path`, if from a file). Returns the
    /// directory used.
    pub fn apply(&self, scene: &mut Scene, scene_path: Option<&Path>, settings: &Settings) -> Result<Option<PathBuf>> {
        self.choice().apply(scene, scene_path, settings)
    }
}
