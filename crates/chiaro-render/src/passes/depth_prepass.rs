//! The forward path's depth prepass: its opaque draws into depth alone, so that the
//! forward pass, testing for equal depth, shades each pixel once however much the
//! scene's surfaces overlap. Alpha-tested and blended draws are left to the forward pass.

use super::mesh::{DepthTest, MeshPipelines, MeshPipelinesDesc, scene_depth};
use crate::graph::{FramePass, PassContext, PassIo, PrepareContext, Resource};
use crate::plan::{FramePlan, PassId};
use crate::shaders;

pub struct DepthPrepassPass {
    pipelines: MeshPipelines,
}

impl DepthPrepassPass {
    pub fn new(
        device: &wgpu::Device,
        layout: wgpu::PipelineLayout,
        depth_format: wgpu::TextureFormat,
    ) -> DepthPrepassPass {
        DepthPrepassPass {
            pipelines: MeshPipelines::new(MeshPipelinesDesc {
                label: "depth prepass",
                // The forward pass's own vertex stage, whose position is invariant.
                module: shaders::module(device, "forward", shaders::FORWARD),
                fragment_entry: None,
                layout,
                color_formats: Vec::new(),
                blends: false,
                depth_test: DepthTest::Nearest,
                depth_format,
                marks_stencil: false,
                constants: Vec::new(),
                alpha_test_override: None,
            }),
        }
    }
}

/// The depth target the forward path draws into: multisampled with MSAA.
pub fn forward_depth(plan: &FramePlan) -> Resource {
    if plan.msaa > 1 { Resource::DepthMultisampled } else { Resource::Depth }
}

impl FramePass for DepthPrepassPass {
    fn id(&self) -> PassId {
        PassId::DepthPrepass
    }

    fn io(&self, plan: &FramePlan) -> PassIo {
        PassIo { reads: Vec::new(), writes: vec![forward_depth(plan)] }
    }

    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        self.pipelines.prepare(cx.device, &cx.scene.draws, &cx.plan.prepass_draws, cx.plan.msaa);
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        let timestamp_writes = cx.timestamp_writes();
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("depth prepass"),
            color_attachments: &[],
            depth_stencil_attachment: Some(scene_depth(cx.targets.view(forward_depth(cx.plan)), false)),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, cx.frame_bind_group, &[]);
        self.pipelines.draw(&mut pass, cx.scene, &cx.plan.prepass_draws);
    }
}
