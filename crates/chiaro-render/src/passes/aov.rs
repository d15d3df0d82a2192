//! The AOV pass: world position, shading normal, linear view depth and baked irradiance
//! of the surface the forward pass kept in each pixel (it tests against its depth).

use super::targets::DEPTH;
use super::mesh::{DepthTest, MeshPipelines, MeshPipelinesDesc, cleared};
use crate::graph::target::ATTACHMENT_COPY;
use crate::graph::{FramePass, PassContext, PassInit, PassSetup, PassType, PrepareContext, Target, TargetDesc};
use crate::plan::FramePlan;
use crate::shaders;

/// The AOV targets' format: 32-bit floats, so positions and depths are not rounded.
pub const AOV_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// World position, alpha 1 where a surface is.
pub const POSITION: Target = Target("aov position");
/// World normal and linear view depth.
pub const NORMAL_DEPTH: Target = Target("aov normal depth");
/// Baked irradiance (RGB) and whether a bake lights the pixel (A).
pub const BAKED: Target = Target("aov baked");
/// Linear view depth alone, 0 where no surface is (a depth-only request).
pub const VIEW_DEPTH: Target = Target("aov view depth");
/// The depth-only target's format.
pub const VIEW_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// Draws the AOV targets over the forward pass's depth: one mesh pass for position, normal
/// and depth, one for baked irradiance when a bake is applied.
pub struct AovPass {
    pipelines: MeshPipelines,
    /// The baked irradiance, in a pass of its own.
    baked: MeshPipelines,
    /// The view depth alone, for depth-only requests.
    depth_only: MeshPipelines,
}

impl PassType for AovPass {
    const NAME: &'static str = "aov";

    /// Asked for by the caller (AOVs test against single-sampled depth, which the plan
    /// then gives the frame).
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        if !plan.request.aovs {
            return;
        }
        pass.modify(DEPTH);
        if plan.request.depth_only {
            pass.create(VIEW_DEPTH, TargetDesc::view_sized(VIEW_DEPTH_FORMAT, ATTACHMENT_COPY)).export(VIEW_DEPTH);
            return;
        }
        for target in [POSITION, NORMAL_DEPTH] {
            pass.create(target, TargetDesc::view_sized(AOV_FORMAT, ATTACHMENT_COPY)).export(target);
        }
        // Without a bake the irradiance is zero everywhere: no pass, no target, no read-back.
        if plan.features.baked {
            pass.create(BAKED, TargetDesc::view_sized(AOV_FORMAT, ATTACHMENT_COPY)).export(BAKED);
        }
    }

    fn new(init: &PassInit<'_>) -> AovPass {
        AovPass::make(init.device, &init.scene_layout(), init.depth_format)
    }
}

impl AovPass {
    fn make(device: &wgpu::Device, layout: &wgpu::PipelineLayout, depth_format: wgpu::TextureFormat) -> AovPass {
        let module = shaders::module(device, "aov", crate::wgsl!("aov"));
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
            textured_override: None,
            layered_override: None,
        };
        AovPass {
            pipelines: MeshPipelines::new(desc("aov", "fs_aov", vec![AOV_FORMAT, AOV_FORMAT])),
            baked: MeshPipelines::new(desc("aov baked", "fs_aov_baked", vec![AOV_FORMAT])),
            depth_only: MeshPipelines::new(desc("aov view depth", "fs_aov_view_depth", vec![VIEW_DEPTH_FORMAT])),
        }
    }
}

impl FramePass for AovPass {
    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        if cx.plan.request.depth_only {
            self.depth_only.prepare(cx.device, &cx.scene.draws, &cx.plan.camera_draws, 1);
            return;
        }
        self.pipelines.prepare(cx.device, &cx.scene.draws, &cx.plan.camera_draws, 1);
        if cx.plan.features.baked {
            self.baked.prepare(cx.device, &cx.scene.draws, &cx.plan.camera_draws, 1);
        }
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        let timestamp_writes = cx.timestamp_writes();
        let targets = cx.targets;
        let clear = |target| cleared(targets.view(target), wgpu::Color::TRANSPARENT);
        if cx.plan.request.depth_only {
            self.depth_only.draw_over_scene_depth(cx, "aov view depth pass", &[clear(VIEW_DEPTH)], timestamp_writes);
            return;
        }
        self.pipelines.draw_over_scene_depth(cx, "aov pass", &[clear(POSITION), clear(NORMAL_DEPTH)], timestamp_writes);
        if cx.plan.features.baked {
            self.baked.draw_over_scene_depth(cx, "aov baked pass", &[clear(BAKED)], None);
        }
    }
}
