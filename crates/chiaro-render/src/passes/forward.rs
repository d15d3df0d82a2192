//! The forward pass: every visible draw lit by every light of the frame's lists, into the
//! pre-exposed HDR target, over a cleared depth and stencil target.

use super::mesh::{DepthTest, MeshPipelines, MeshPipelinesDesc, cleared, scene_depth};
use crate::graph::{FramePass, PassContext, PassIo, PrepareContext, Resource};
use crate::plan::{FramePlan, PassId};
use crate::shaders;
use chiaro_math::tonemap::exposure_scale;

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
            }),
        }
    }
}

impl FramePass for ForwardPass {
    fn id(&self) -> PassId {
        PassId::Forward
    }

    fn io(&self, _plan: &FramePlan) -> PassIo {
        PassIo {
            reads: vec![Resource::DirectionalShadowAtlas, Resource::OtherShadowAtlas],
            writes: vec![Resource::Hdr, Resource::Depth],
        }
    }

    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        self.pipelines.prepare(cx.device, &cx.scene.draws, &cx.plan.camera_draws);
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        let background =
            glam::Vec3::from(cx.settings.render.background) * exposure_scale(cx.settings.render.exposure_ev100);
        let clear = wgpu::Color { r: background.x as f64, g: background.y as f64, b: background.z as f64, a: 0.0 };
        let timestamp_writes = cx.timestamp_writes();
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("forward pass"),
            color_attachments: &[cleared(cx.targets.view(Resource::Hdr), clear)],
            depth_stencil_attachment: Some(scene_depth(cx.targets.view(Resource::Depth), false)),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, cx.frame_bind_group, &[]);
        self.pipelines.draw(&mut pass, cx.scene, &cx.plan.camera_draws);
    }
}
