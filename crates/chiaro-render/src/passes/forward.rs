//! The forward pass: every visible draw lit by every light of the frame's lists, into the
//! pre-exposed HDR target, over a cleared depth and stencil target. On the deferred path
//! it draws only the transparent draws, over the lit G-buffer's image and depth.

use super::mesh::{DepthTest, MeshPipelines, MeshPipelinesDesc, cleared, scene_depth};
use crate::graph::{FramePass, PassContext, PassIo, PrepareContext, Resource};
use crate::plan::{FramePlan, PassId};
use crate::shaders;
use chiaro_math::tonemap::exposure_scale;
use chiaro_scene::RenderPath;

pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

pub struct ForwardPass {
    pipelines: MeshPipelines,
}

impl ForwardPass {
    pub fn new(device: &wgpu::Device, layout: wgpu::PipelineLayout, depth_format: wgpu::TextureFormat) -> ForwardPass {
        ForwardPass {
            pipelines: MeshPipelines::new(MeshPipelinesDesc {
                label: "forward",
                module: shaders::module(device, "forward", shaders::FORWARD),
                fragment_entry: "fs_main",
                layout,
                color_formats: vec![HDR_FORMAT],
                blends: true,
                depth_test: DepthTest::Nearest,
                depth_format,
                marks_stencil: false,
                constants: Vec::new(),
            }),
        }
    }
}

impl FramePass for ForwardPass {
    fn id(&self) -> PassId {
        PassId::Forward
    }

    fn io(&self, plan: &FramePlan) -> PassIo {
        let mut reads = vec![Resource::DirectionalShadowAtlas, Resource::OtherShadowAtlas];
        if plan.path == RenderPath::Deferred {
            reads.extend([Resource::Hdr, Resource::Depth]);
        }
        PassIo { reads, writes: vec![Resource::Hdr, Resource::Depth] }
    }

    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        self.pipelines.prepare(cx.device, &cx.scene.draws, forward_draws(cx.plan));
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        let background =
            glam::Vec3::from(cx.settings.render.background) * exposure_scale(cx.settings.render.exposure_ev100);
        let clear = wgpu::Color { r: background.x as f64, g: background.y as f64, b: background.z as f64, a: 0.0 };
        let deferred = cx.plan.path == RenderPath::Deferred;
        let color = if deferred {
            Some(wgpu::RenderPassColorAttachment {
                view: cx.targets.view(Resource::Hdr),
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
            })
        } else {
            cleared(cx.targets.view(Resource::Hdr), clear)
        };
        let timestamp_writes = cx.timestamp_writes();
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("forward pass"),
            color_attachments: &[color],
            depth_stencil_attachment: Some(scene_depth(cx.targets.view(Resource::Depth), deferred)),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, cx.frame_bind_group, &[]);
        self.pipelines.draw(&mut pass, cx.scene, forward_draws(cx.plan));
    }
}

/// Every camera draw, or on the deferred path the transparent ones the G-buffer left.
fn forward_draws(plan: &FramePlan) -> &[u32] {
    match plan.path {
        RenderPath::Forward => &plan.camera_draws,
        RenderPath::Deferred => &plan.camera_draws[plan.transparent_from..],
    }
}
