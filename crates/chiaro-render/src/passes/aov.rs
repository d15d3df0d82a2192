//! The AOV pass: world position, shading normal, linear view depth and baked irradiance
//! of the surface the forward pass kept in each pixel (it tests against its depth).

use super::mesh::{DepthTest, MeshPipelines, MeshPipelinesDesc, cleared, scene_depth};
use crate::graph::{FramePass, PassContext, PassIo, PrepareContext, Resource};
use crate::plan::{FramePlan, PassId};
use crate::shaders;

pub const AOV_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

pub struct AovPass {
    pipelines: MeshPipelines,
    /// The baked irradiance, in a pass of its own.
    baked: MeshPipelines,
}

impl AovPass {
    pub fn new(device: &wgpu::Device, layout: &wgpu::PipelineLayout, depth_format: wgpu::TextureFormat) -> AovPass {
        let module = shaders::module(device, "aov", shaders::AOV);
        let desc = |label, fragment_entry, color_formats| MeshPipelinesDesc {
            label,
            module: module.clone(),
            fragment_entry: Some(fragment_entry),
            layout: layout.clone(),
            color_formats,
            blends: false,
            depth_test: DepthTest::SameSurface,
            depth_format,
            marks_stencil: false,
            constants: Vec::new(),
            alpha_test_override: None,
        };
        AovPass {
            pipelines: MeshPipelines::new(desc("aov", "fs_aov", vec![AOV_FORMAT, AOV_FORMAT])),
            baked: MeshPipelines::new(desc("aov baked", "fs_aov_baked", vec![AOV_FORMAT])),
        }
    }
}

impl FramePass for AovPass {
    fn id(&self) -> PassId {
        PassId::Aov
    }

    fn io(&self, _plan: &FramePlan) -> PassIo {
        PassIo {
            reads: vec![Resource::Depth],
            writes: vec![Resource::AovPosition, Resource::AovNormalDepth, Resource::AovBaked, Resource::Depth],
        }
    }

    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        self.pipelines.prepare(cx.device, &cx.scene.draws, &cx.plan.camera_draws, 1);
        self.baked.prepare(cx.device, &cx.scene.draws, &cx.plan.camera_draws, 1);
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        let timestamp_writes = cx.timestamp_writes();
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("aov pass"),
            color_attachments: &[
                cleared(cx.targets.view(Resource::AovPosition), wgpu::Color::TRANSPARENT),
                cleared(cx.targets.view(Resource::AovNormalDepth), wgpu::Color::TRANSPARENT),
            ],
            depth_stencil_attachment: Some(scene_depth(cx.targets.view(Resource::Depth), true)),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, cx.frame_bind_group, &[]);
        self.pipelines.draw(&mut pass, cx.scene, &cx.plan.camera_draws);
        drop(pass);
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("aov baked pass"),
            color_attachments: &[cleared(cx.targets.view(Resource::AovBaked), wgpu::Color::TRANSPARENT)],
            depth_stencil_attachment: Some(scene_depth(cx.targets.view(Resource::Depth), true)),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, cx.frame_bind_group, &[]);
        self.baked.draw(&mut pass, cx.scene, &cx.plan.camera_draws);
    }
}
