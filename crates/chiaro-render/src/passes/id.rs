//! The id pass: per pixel, the glTF node whose mesh the forward pass kept there and that
//! node's `extras.label`, for datasets. One sample a pixel, tested against the frame's
//! depth, so every id is exact at every pixel.

use super::targets::DEPTH;
use super::mesh::{DepthTest, MeshPipelines, MeshPipelinesDesc};
use crate::graph::target::ATTACHMENT_COPY;
use crate::graph::{FramePass, PassContext, PassInit, PassSetup, PassType, PrepareContext, Target, TargetDesc};
use crate::plan::FramePlan;
use crate::shader_constants::NO_NODE;
use crate::shaders;

/// Two 32-bit unsigned integers a pixel: (node, label).
pub const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;
/// The node and label per pixel; (`NO_NODE`, 0) where no surface is.
pub const IDS: Target = Target("ids");

/// Draws the ids over the forward pass's depth.
pub struct IdPass {
    pipelines: MeshPipelines,
}

impl PassType for IdPass {
    const NAME: &'static str = "ids";

    /// Asked for by the caller (like the AOVs, the ids test against single-sampled depth,
    /// which the plan then gives the frame).
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        if !plan.request.ids {
            return;
        }
        pass.modify(DEPTH);
        pass.create(IDS, TargetDesc::view_sized(ID_FORMAT, ATTACHMENT_COPY)).export(IDS);
    }

    fn new(init: &PassInit<'_>) -> IdPass {
        let module = shaders::module(init.device, "id", crate::wgsl!("id"));
        let pipelines = MeshPipelines::new(MeshPipelinesDesc {
            label: "ids",
            module,
            fragment_entry: Some("fs_id"),
            layout: init.scene_layout(),
            color_formats: vec![ID_FORMAT],
            blends: false,
            depth_test: DepthTest::SameSurface,
            depth_format: init.depth_format,
            marks_stencil: false,
            constants: Vec::new(),
            alpha_test_override: None,
            textured_override: None,
            layered_override: None,
        });
        IdPass { pipelines }
    }
}

impl FramePass for IdPass {
    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        self.pipelines.prepare(cx.device, &cx.scene.draws, &cx.plan.camera_draws, 1);
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        let timestamp_writes = cx.timestamp_writes();
        let sky = wgpu::Color { r: f64::from(NO_NODE), g: 0.0, b: 0.0, a: 0.0 };
        let ids = super::mesh::cleared(cx.targets.view(IDS), sky);
        self.pipelines.draw_over_scene_depth(cx, "id pass", &[ids], timestamp_writes);
    }
}
