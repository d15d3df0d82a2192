//! A small frame graph. Each pass declares the resources it reads and writes; the graph
//! checks that the plan's order satisfies them, makes the targets the passes need, and
//! runs each pass inside a debug group with its own GPU timestamps. A new pass is a new
//! module implementing `FramePass`, registered with the renderer, plus its `PassId` in
//! the plan.

pub mod targets;
pub mod timer;

use crate::error::RenderError;
use crate::plan::{FramePlan, PassId};
use crate::scene::GpuScene;
use chiaro_scene::{Scene, Settings};
use std::collections::HashSet;
pub use targets::{Resource, TargetDesc, Targets};
pub use timer::{GpuTimer, PassTimestamps};

/// What a pass reads and writes this frame.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PassIo {
    pub reads: Vec<Resource>,
    pub writes: Vec<Resource>,
}

/// Counts passes report, for benchmarks and tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PassStats {
    pub shadow_tiles_rendered: usize,
    pub shadow_caster_draws: usize,
}

/// What a pass may use while it records.
pub struct PassContext<'a> {
    pub device: &'a wgpu::Device,
    pub encoder: &'a mut wgpu::CommandEncoder,
    pub plan: &'a FramePlan,
    pub settings: &'a Settings,
    pub scene: &'a GpuScene,
    /// Group 0 of every scene pass: frame, lights, objects, shadows.
    pub frame_bind_group: &'a wgpu::BindGroup,
    pub targets: &'a Targets,
    pub timestamps: Option<PassTimestamps<'a>>,
    pub stats: &'a mut PassStats,
}

impl<'a> PassContext<'a> {
    /// Timestamp writes for a pass recorded as one wgpu render pass.
    pub fn timestamp_writes(&self) -> Option<wgpu::RenderPassTimestampWrites<'a>> {
        self.timestamps.map(|t| t.writes(true, true))
    }
}

/// What a pass may use to get ready before recording.
pub struct PrepareContext<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub plan: &'a FramePlan,
    pub scene: &'a GpuScene,
    /// The scene the GPU scene mirrors (its lights, for per-light data).
    pub source: &'a Scene,
    /// The format of `Resource::Output` this frame.
    pub output_format: wgpu::TextureFormat,
}

pub trait FramePass {
    fn id(&self) -> PassId;
    fn io(&self, plan: &FramePlan) -> PassIo;
    /// Makes the pipelines and uploads the data the frame will need.
    fn prepare(&mut self, cx: &PrepareContext<'_>);
    fn record(&self, cx: &mut PassContext<'_>);
}

/// Checks that every pass in `order` reads only what an earlier pass of the frame wrote
/// or what persists across frames; returns the resources the frame writes.
pub fn check_order(order: &[(PassId, PassIo)]) -> Result<HashSet<Resource>, RenderError> {
    let mut written = HashSet::new();
    for (pass, io) in order {
        for r in &io.reads {
            if !r.persistent() && !written.contains(r) {
                return Err(RenderError::FrameGraph(format!(
                    "the {} pass reads {r:?}, which no earlier pass writes",
                    pass.name()
                )));
            }
        }
        written.extend(io.writes.iter().copied());
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pass_may_not_read_what_no_earlier_pass_wrote() {
        let forward = (
            PassId::Forward,
            PassIo {
                reads: vec![Resource::DirectionalShadowAtlas, Resource::OtherShadowAtlas],
                writes: vec![Resource::Hdr, Resource::Depth],
            },
        );
        let tonemap = (PassId::Tonemap, PassIo { reads: vec![Resource::Hdr], writes: vec![Resource::Output] });
        let written = check_order(&[forward.clone(), tonemap.clone()]).unwrap();
        assert!(written.contains(&Resource::Output) && written.contains(&Resource::Depth));
        let e = check_order(&[tonemap, forward]).unwrap_err();
        assert!(e.to_string().contains("tonemap pass reads Hdr"), "{e}");
    }
}
