//! The frame graph, after Filament's FrameGraph. Each pass declares in its `setup`
//! (`PassType::setup`, from the plan alone) the targets it creates with their full
//! descriptions, the targets it reads, writes and modifies, what it exports to the caller
//! and any side effect; `compile` derives from those the passes that run, in order, and
//! culls the ones whose outputs nobody reads; `Targets` makes and reuses the textures;
//! `GpuTimer` times each pass. A pass's `prepare` and `record` only act on what the plan
//! and its declarations say. A new pass is a module implementing `PassType` and
//! `FramePass`, plus its line in `passes/list.rs`.

pub mod compile;
pub mod setup;
pub mod target;
pub mod targets;
pub mod timer;

use crate::context::GpuContext;
use crate::plan::FramePlan;
use crate::scene::GpuScene;
use chiaro_scene::{Scene, Settings};
pub use compile::FrameGraph;
pub use setup::{Access, Lifetime, PassDeclaration, PassSetup};
pub use target::{OUTPUT, Size, Target, TargetDesc};
pub use targets::Targets;
pub use timer::{GpuTimer, PassTimestamps};

/// Counts passes report, for benchmarks and tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PassStats {
    pub shadow_tiles_rendered: usize,
    pub shadow_caster_draws: usize,
}

/// What every pass is made from.
pub struct PassInit<'a> {
    pub ctx: &'a GpuContext,
    pub device: &'a wgpu::Device,
    /// Group 0 of the scene passes: frame, lights, objects, shadows.
    pub frame_layout: &'a wgpu::BindGroupLayout,
    /// Group 1 of the scene passes: a material.
    pub material_layout: &'a wgpu::BindGroupLayout,
    pub depth_format: wgpu::TextureFormat,
}

impl PassInit<'_> {
    /// The pipeline layout of passes that draw the scene's meshes (frame, material).
    pub fn scene_layout(&self) -> wgpu::PipelineLayout {
        self.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene pipeline layout"),
            bind_group_layouts: &[Some(self.frame_layout), Some(self.material_layout)],
            immediate_size: 0,
        })
    }
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
        self.timestamps.and_then(|t| t.writes(true, true))
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
    /// The format of `OUTPUT` this frame.
    pub output_format: wgpu::TextureFormat,
}

/// A pass at work: the part the renderer calls each frame it runs.
pub trait FramePass {
    /// Makes the pipelines and uploads the data the frame will need.
    fn prepare(&mut self, cx: &PrepareContext<'_>);
    fn record(&self, cx: &mut PassContext<'_>);
}

/// A pass as the pass list knows it: its name, its declarations and how it is made.
pub trait PassType: FramePass + Sized + 'static {
    /// The name in timings, debug groups and the printed graph.
    const NAME: &'static str;
    /// Declares what the pass makes, reads and writes for `plan` (nothing: it does not run).
    fn setup(plan: &FramePlan, pass: &mut PassSetup);
    fn new(init: &PassInit<'_>) -> Self;
}
