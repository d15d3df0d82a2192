//! The depth prepass: opaque draws into depth alone. On the forward path, so that the
//! forward pass, testing for equal depth, shades each pixel once however much the
//! scene's surfaces overlap; on the deferred path where the depth is copied before the
//! G-buffer pass (ambient occlusion, which that pass's indirect light reads, and contact
//! shadows: `FramePlan::has_depth_prepass`). Alpha-tested and blended draws are left to
//! the shading passes.

use super::mesh::{DepthTest, MeshPipelines, MeshPipelinesDesc, depth_desc, forward_depth, scene_depth};
use crate::graph::{FramePass, PassContext, PassInit, PassSetup, PassType, PrepareContext};
use crate::plan::FramePlan;
use crate::shaders;

/// The forward path's depth prepass: opaque draws into depth alone.
pub struct DepthPrepassPass {
    pipelines: MeshPipelines,
}

impl PassType for DepthPrepassPass {
    const NAME: &'static str = "depth prepass";

    /// The forward path's depth target is made here, and the deferred path's where it has
    /// a prepass (`FramePlan::has_depth_prepass`; the G-buffer pass then draws over it).
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        if plan.has_depth_prepass() {
            pass.create(forward_depth(plan), depth_desc(pass.depth_format, plan.msaa, plan.samples_scene_depth()));
        }
    }

    fn new(init: &PassInit<'_>) -> DepthPrepassPass {
        DepthPrepassPass {
            pipelines: MeshPipelines::new(MeshPipelinesDesc {
                label: "depth prepass",
                // The forward pass's own vertex stage, whose position is invariant.
                module: shaders::module(init.device, "forward", crate::wgsl!("forward")),
                fragment_entry: None,
                layout: init.scene_layout(),
                color_formats: Vec::new(),
                blends: false,
                depth_test: DepthTest::Nearest,
                depth_format: init.depth_format,
                marks_stencil: false,
                constants: Vec::new(),
                alpha_test_override: None,
                textured_override: None,
                layered_override: None,
            }),
        }
    }
}

impl FramePass for DepthPrepassPass {
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
