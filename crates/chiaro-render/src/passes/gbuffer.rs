//! The deferred path's G-buffer pass: every opaque and masked draw's surface into the
//! G-buffer (layout in shaders/common/gbuffer.wesl), its emissive and ambient light into
//! the light accumulation target, and stencil bit `STENCIL_SURFACE` where a surface is,
//! so that the light volumes never shade the sky.

use super::background::{BackgroundPipelines, BackgroundTargets};
use super::targets::{HDR, HDR_FORMAT};
use super::targets::DEPTH;
use super::mesh::{DepthTest, MeshPipelines, MeshPipelinesDesc, STENCIL_SURFACE, cleared, depth_desc, scene_depth};
use crate::graph::target::ATTACHMENT_SAMPLED;
use crate::graph::{FramePass, PassContext, PassInit, PassSetup, PassType, PrepareContext, Target, TargetDesc};
use crate::overrides;
use crate::plan::FramePlan;
use crate::shaders;
use chiaro_math::tonemap::exposure_scale;
use chiaro_scene::{LightBuffer, RenderPath};
use std::collections::HashMap;
use super::targets::{GBUFFER_ALBEDO_METALLIC, GBUFFER_ALBEDO_METALLIC_FORMAT, GBUFFER_PACKED, GBUFFER_PACKED_FORMAT, LIGHT_BUFFER_LDR, LIGHT_BUFFER_LDR_FORMAT};


/// Where the deferred path accumulates light.
pub fn light_target(light_buffer: LightBuffer) -> Target {
    match light_buffer {
        LightBuffer::Hdr => HDR,
        LightBuffer::LdrExp2 => LIGHT_BUFFER_LDR,
    }
}

/// The light target's description.
pub fn light_target_desc(light_buffer: LightBuffer) -> TargetDesc {
    let format = match light_buffer {
        LightBuffer::Hdr => HDR_FORMAT,
        LightBuffer::LdrExp2 => LIGHT_BUFFER_LDR_FORMAT,
    };
    TargetDesc::view_sized(format, ATTACHMENT_SAMPLED)
}

/// The deferred path's G-buffer pass: its mesh pipelines per shader variant.
pub struct GBufferPass {
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    depth_format: wgpu::TextureFormat,
    /// By light buffer and whether baked light and the environment are compiled in; made
    /// when first used.
    pipelines: HashMap<PipelineKey, MeshPipelines>,
    background: BackgroundPipelines,
}

/// The light buffer, whether baked light, the environment and ambient occlusion are
/// compiled in, and whether a depth prepass drew the depth first.
type PipelineKey = (LightBuffer, bool, bool, bool, bool);

impl PassType for GBufferPass {
    const NAME: &'static str = "gbuffer";

    /// The deferred path's G-buffer, depth and light target are made here.
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        if plan.path != RenderPath::Deferred {
            return;
        }
        let gbuffer = |format| TargetDesc::view_sized(format, ATTACHMENT_SAMPLED);
        pass.create(light_target(plan.light_buffer), light_target_desc(plan.light_buffer))
            .create(GBUFFER_ALBEDO_METALLIC, gbuffer(GBUFFER_ALBEDO_METALLIC_FORMAT))
            .create(GBUFFER_PACKED, gbuffer(GBUFFER_PACKED_FORMAT));
        if plan.has_depth_prepass() {
            pass.modify(DEPTH);
        } else {
            pass.create(DEPTH, depth_desc(pass.depth_format, 1, plan.samples_scene_depth()));
        }
    }

    fn new(init: &PassInit<'_>) -> GBufferPass {
        GBufferPass {
            module: shaders::module(init.device, "gbuffer", crate::wgsl!("gbuffer")),
            layout: init.scene_layout(),
            depth_format: init.depth_format,
            pipelines: HashMap::new(),
            background: BackgroundPipelines::new(init.device, init.frame_layout, init.depth_format),
        }
    }
}

impl GBufferPass {
    fn create(&self, (light_buffer, baked, environment, occlusion, prepassed): PipelineKey) -> MeshPipelines {
        let ldr_exp2 = light_buffer == LightBuffer::LdrExp2;
        MeshPipelines::new(MeshPipelinesDesc {
            label: "gbuffer",
            module: self.module.clone(),
            fragment_entry: Some("fs_gbuffer"),
            layout: self.layout.clone(),
            color_formats: vec![
                if ldr_exp2 { LIGHT_BUFFER_LDR_FORMAT } else { HDR_FORMAT },
                GBUFFER_ALBEDO_METALLIC_FORMAT,
                GBUFFER_PACKED_FORMAT,
            ],
            blends: false,
            depth_test: if prepassed { DepthTest::AfterPrepass } else { DepthTest::Nearest },
            depth_format: self.depth_format,
            marks_stencil: true,
            constants: vec![
                overrides::LDR_EXP2.flag(ldr_exp2),
                overrides::BAKED_ENABLED.flag(baked),
                overrides::ENVIRONMENT_ENABLED.flag(environment),
                overrides::AMBIENT_OCCLUSION.flag(occlusion),
            ],
            alpha_test_override: Some(overrides::ALPHA_TESTED),
            textured_override: Some(overrides::MATERIAL_TEXTURED),
            layered_override: None,
        })
    }
}

fn pipeline_key(plan: &FramePlan) -> PipelineKey {
    let f = &plan.features;
    (plan.light_buffer, f.baked, f.environment, f.ambient_occlusion, plan.has_depth_prepass())
}

/// The G-buffer's attachments, for the background pipeline, where it draws one.
fn background_targets(plan: &FramePlan) -> Option<BackgroundTargets> {
    let ldr_exp2 = plan.light_buffer == LightBuffer::LdrExp2;
    plan.environment_background.then(|| BackgroundTargets {
        color_formats: vec![
            if ldr_exp2 { LIGHT_BUFFER_LDR_FORMAT } else { HDR_FORMAT },
            GBUFFER_ALBEDO_METALLIC_FORMAT,
            GBUFFER_PACKED_FORMAT,
        ],
        samples: 1,
        ldr_exp2,
    })
}

/// The opaque and masked draws, which the G-buffer takes.
fn opaque_draws(plan: &FramePlan) -> &[u32] {
    &plan.camera_draws[..plan.transmissive_from]
}

impl FramePass for GBufferPass {
    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        let key = pipeline_key(cx.plan);
        if !self.pipelines.contains_key(&key) {
            let made = self.create(key);
            self.pipelines.insert(key, made);
        }
        let pipelines = self.pipelines.get_mut(&key).expect("made above");
        pipelines.prepare(cx.device, &cx.scene.draws, opaque_draws(cx.plan), 1);
        if let Some(targets) = background_targets(cx.plan) {
            self.background.prepare(cx.device, &targets, cx.environment_image);
        }
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        let background =
            glam::Vec3::from(cx.settings.render.background) * exposure_scale(cx.settings.render.exposure_ev100);
        let light_clear = match cx.plan.light_buffer {
            LightBuffer::Hdr => background,
            LightBuffer::LdrExp2 => (-background).exp2(),
        };
        let light_clear =
            wgpu::Color { r: light_clear.x as f64, g: light_clear.y as f64, b: light_clear.z as f64, a: 0.0 };
        let timestamp_writes = cx.timestamp_writes();
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer pass"),
            color_attachments: &[
                cleared(cx.targets.view(light_target(cx.plan.light_buffer)), light_clear),
                cleared(cx.targets.view(GBUFFER_ALBEDO_METALLIC), wgpu::Color::TRANSPARENT),
                // View depth 0 marks "no surface".
                cleared(cx.targets.view(GBUFFER_PACKED), wgpu::Color::TRANSPARENT),
            ],
            depth_stencil_attachment: Some(scene_depth(cx.targets.view(DEPTH), cx.plan.has_depth_prepass())),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_stencil_reference(STENCIL_SURFACE);
        pass.set_bind_group(0, cx.frame_bind_group, &[]);
        self.pipelines[&pipeline_key(cx.plan)].draw(&mut pass, cx.scene, opaque_draws(cx.plan));
        if let Some(targets) = background_targets(cx.plan) {
            self.background.draw(&mut pass, &targets);
        }
    }
}
