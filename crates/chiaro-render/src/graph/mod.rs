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
    /// Shadow atlas tiles the shadow pass drew this frame.
    pub shadow_tiles_rendered: usize,
    /// Caster draw calls issued into those tiles (an instanced draw counts once).
    pub shadow_caster_draws: usize,
}

/// What every pass is made from.
pub struct PassInit<'a> {
    /// The device and what it offers (depth format, MSAA counts, timestamps).
    pub ctx: &'a GpuContext,
    /// The device to make pipelines and buffers on (`ctx.device`).
    pub device: &'a wgpu::Device,
    /// Group 0 of the scene passes: frame, lights, objects, shadows.
    pub frame_layout: &'a wgpu::BindGroupLayout,
    /// Group 1 of the scene passes: a material.
    pub material_layout: &'a wgpu::BindGroupLayout,
    /// The scene depth targets' depth-stencil format.
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
    /// The device, for bind groups made while recording.
    pub device: &'a wgpu::Device,
    /// The frame's command encoder the pass records into.
    pub encoder: &'a mut wgpu::CommandEncoder,
    /// What the frame draws.
    pub plan: &'a FramePlan,
    /// The settings the frame was planned with.
    pub settings: &'a Settings,
    /// The scene's buffers, materials and draws.
    pub scene: &'a GpuScene,
    /// Group 0 of every scene pass: frame, lights, objects, shadows.
    pub frame_bind_group: &'a wgpu::BindGroup,
    /// The frame's targets, by name.
    pub targets: &'a Targets,
    /// Group 0's buffer of each pixel's scene depth, which the contact depth pass fills.
    pub view_depths: &'a wgpu::Buffer,
    /// The ambient occlusion pass's buffers; group 0 binds the denoised one.
    pub occlusion: crate::frame_data::OcclusionBuffers<'a>,
    /// What the virtual page marking pass binds.
    pub marking: crate::frame_data::MarkingBuffers<'a>,
    /// Where to write the pass's timestamps, when the frame is timed.
    pub timestamps: Option<PassTimestamps<'a>>,
    /// Counts the pass adds to (shadow tiles, caster draws).
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
    /// The device to make pipelines and buffers on.
    pub device: &'a wgpu::Device,
    /// The queue uploads go to.
    pub queue: &'a wgpu::Queue,
    /// What the frame draws.
    pub plan: &'a FramePlan,
    /// The scene's buffers, materials and draws.
    pub scene: &'a GpuScene,
    /// The scene the GPU scene mirrors (its lights, for per-light data).
    pub source: &'a Scene,
    /// The format of `OUTPUT` this frame.
    pub output_format: wgpu::TextureFormat,
    /// The environment's image (a placeholder without one), for the background.
    pub environment_image: &'a wgpu::TextureView,
}

/// A pass at work: the part the renderer calls each frame it runs. `Send` on native
/// targets, so that a renderer may move between threads (the Python package shares one
/// among them); the browser's wgpu objects are not `Send`, and there is one thread there.
pub trait FramePass: wgpu::WasmNotSend {
    /// Makes the pipelines and uploads the data the frame will need.
    fn prepare(&mut self, cx: &PrepareContext<'_>);
    /// Records the pass's commands, reading and writing the targets its setup declared.
    fn record(&self, cx: &mut PassContext<'_>);
}

/// A pass as the pass list knows it: its name, its declarations and how it is made.
pub trait PassType: FramePass + Sized + 'static {
    /// The name in timings, debug groups and the printed graph.
    const NAME: &'static str;
    /// Declares what the pass makes, reads and writes for `plan` (nothing: it does not run).
    fn setup(plan: &FramePlan, pass: &mut PassSetup);
    /// Makes the pass's pipelines and layouts once per renderer.
    fn new(init: &PassInit<'_>) -> Self;
}
