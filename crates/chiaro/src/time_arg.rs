//! `--time SECONDS`, shared by render, bench, compare and view: the moment of the glTF
//! animations to pose the scene at.

use anyhow::{Context, Result};
use chiaro_scene::Scene;
use clap::Args;

#[derive(Args, Clone, Copy, Debug, Default)]
pub struct TimeArg {
    /// Pose the scene at this time of its glTF animations, in seconds (each animation holds
    /// its first key before it starts and its last after it ends). Without it: the rest
    /// pose, the file's own node transforms.
    #[arg(long, value_name = "SECONDS", allow_hyphen_values = true)]
    pub time: Option<f32>,
}

impl TimeArg {
    /// Poses `scene` at the time asked for (or at rest).
    pub fn apply(&self, scene: &mut Scene) -> Result<()> {
        if self.time.is_some() && scene.animation_duration().is_none() {
            let name = scene.source.as_ref().map_or("the scene".into(), |p| p.display().to_string());
            tracing::warn!("--time: {name} has no animations; it renders as it rests");
        }
        scene.pose(self.time).context("--time")
    }
}
