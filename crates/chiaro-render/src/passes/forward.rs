//! The forward pass: every visible draw lit by the point and spot lights its culling
//! mode lists (clustered, per object, or all), into the pre-exposed HDR target, over the
//! depth prepass's depth; with MSAA into multisampled targets resolved into the HDR
//! target. On the deferred path it draws only the transparent draws, over the lit
//! G-buffer's image and depth.

use super::background::{BackgroundPipelines, BackgroundTargets};
use super::mesh::{DepthTest, MeshPipelines, MeshPipelinesDesc, forward_depth, scene_depth};
use super::targets::{DIRECTIONAL_ATLAS, LOCAL_ATLAS};
use crate::graph::target::ATTACHMENT_SAMPLED;
use crate::graph::{FramePass, PassContext, PassInit, PassSetup, PassType, PrepareContext, Target, TargetDesc};
use crate::overrides;
use crate::plan::FramePlan;
use crate::plan::features::ShaderFeatures;
use crate::shader_constants::{LIGHT_CULLING_CLUSTERED, LIGHT_CULLING_NONE, LIGHT_CULLING_PER_OBJECT};
use crate::shaders;
use chiaro_math::tonemap::exposure_scale;
use chiaro_scene::{LightCulling, RenderPath};
use std::collections::HashMap;
use super::targets::{HDR, HDR_FORMAT};

/// The forward path's multisampled radiance, resolved into `HDR`.
pub const HDR_MULTISAMPLED: Target = Target("hdr multisampled");

/// The forward pass: its shader module, layout and mesh pipelines per shader variant.
pub struct ForwardPass {
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    depth_format: wgpu::TextureFormat,
    /// One set per shader specialisation, made when first used.
    pipelines: HashMap<Variant, MeshPipelines>,
    background: BackgroundPipelines,
}

impl PassType for ForwardPass {
    const NAME: &'static str = "forward";

    /// The forward path makes the HDR image (through multisampled targets with MSAA) over
    /// the prepass's depth; the deferred path adds its transparent draws, if any, to the
    /// lit G-buffer's image.
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        if forward_draws(plan).is_empty() && plan.path == RenderPath::Deferred {
            return;
        }
        pass.read(DIRECTIONAL_ATLAS).read(LOCAL_ATLAS).modify(forward_depth(plan));
        match plan.path {
            RenderPath::Deferred => {
                pass.modify(HDR);
            }
            RenderPath::Forward => {
                let hdr = TargetDesc::view_sized(HDR_FORMAT, ATTACHMENT_SAMPLED);
                pass.create(HDR, hdr);
                if plan.msaa > 1 {
                    let samples = hdr.with_samples(plan.msaa);
                    pass.create(HDR_MULTISAMPLED, TargetDesc { usage: wgpu::TextureUsages::RENDER_ATTACHMENT, ..samples });
                }
            }
        }
    }

    fn new(init: &PassInit<'_>) -> ForwardPass {
        ForwardPass {
            module: shaders::module(init.device, "forward", crate::wgsl!("forward")),
            layout: init.scene_layout(),
            depth_format: init.depth_format,
            pipelines: HashMap::new(),
            background: BackgroundPipelines::new(init.device, init.frame_layout, init.depth_format),
        }
    }
}

impl ForwardPass {
    fn pipelines_for(&self, variant: Variant) -> MeshPipelines {
        let mode = match variant.culling {
            LightCulling::None => LIGHT_CULLING_NONE,
            LightCulling::Clustered => LIGHT_CULLING_CLUSTERED,
            LightCulling::PerObject => LIGHT_CULLING_PER_OBJECT,
        };
        MeshPipelines::new(MeshPipelinesDesc {
            label: "forward",
            module: self.module.clone(),
            fragment_entry: Some("fs_main"),
            layout: self.layout.clone(),
            color_formats: vec![HDR_FORMAT],
            blends: true,
            depth_test: DepthTest::AfterPrepass,
            depth_format: self.depth_format,
            marks_stencil: false,
            constants: [overrides::LIGHT_CULLING.value(mode as f64), overrides::LIGHTS_IN_TABLE.flag(variant.lights_in_table)]
                .into_iter()
                .chain(variant.features.constants())
                .collect(),
            alpha_test_override: Some(overrides::ALPHA_TESTED),
            textured_override: Some(overrides::MATERIAL_TEXTURED),
        })
    }
}

impl FramePass for ForwardPass {
    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        let key = Variant::of(cx.plan);
        if !self.pipelines.contains_key(&key) {
            let made = self.pipelines_for(key);
            self.pipelines.insert(key, made);
        }
        let pipelines = self.pipelines.get_mut(&key).expect("made above");
        pipelines.prepare(cx.device, &cx.scene.draws, forward_draws(cx.plan), cx.plan.msaa);
        if let Some(targets) = background_targets(cx.plan) {
            self.background.prepare(cx.device, &targets);
        }
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        let background =
            glam::Vec3::from(cx.settings.render.background) * exposure_scale(cx.settings.render.exposure_ev100);
        let clear = wgpu::Color { r: background.x as f64, g: background.y as f64, b: background.z as f64, a: 0.0 };
        let deferred = cx.plan.path == RenderPath::Deferred;
        let hdr = cx.targets.view(HDR);
        let color = if deferred {
            wgpu::RenderPassColorAttachment {
                view: hdr,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
            }
        } else if cx.plan.msaa > 1 {
            // The samples are resolved (averaged) into the HDR target, before tone mapping.
            wgpu::RenderPassColorAttachment {
                view: cx.targets.view(HDR_MULTISAMPLED),
                depth_slice: None,
                resolve_target: Some(hdr),
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(clear), store: wgpu::StoreOp::Discard },
            }
        } else {
            wgpu::RenderPassColorAttachment {
                view: hdr,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(clear), store: wgpu::StoreOp::Store },
            }
        };
        let timestamp_writes = cx.timestamp_writes();
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("forward pass"),
            color_attachments: &[Some(color)],
            // Both paths draw over depth an earlier pass wrote: the prepass or the G-buffer.
            depth_stencil_attachment: Some(scene_depth(cx.targets.view(forward_depth(cx.plan)), true)),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, cx.frame_bind_group, &[]);
        let pipelines = &self.pipelines[&Variant::of(cx.plan)];
        match background_targets(cx.plan) {
            // Behind the transparent draws, over what the opaque ones left uncovered.
            Some(targets) => {
                let (opaque, transparent) = cx.plan.camera_draws.split_at(cx.plan.transparent_from);
                pipelines.draw(&mut pass, cx.scene, opaque);
                self.background.draw(&mut pass, &targets);
                pipelines.draw(&mut pass, cx.scene, transparent);
            }
            None => pipelines.draw(&mut pass, cx.scene, forward_draws(cx.plan)),
        }
    }
}

/// The forward path's background pipeline, where it draws the environment behind the
/// scene (the deferred path's G-buffer pass draws it there).
fn background_targets(plan: &FramePlan) -> Option<BackgroundTargets> {
    (plan.environment_background && plan.path == RenderPath::Forward).then(|| BackgroundTargets {
        color_formats: vec![HDR_FORMAT],
        samples: plan.msaa,
        ldr_exp2: false,
    })
}

/// The shader's override constants for a frame: how it finds its lights, where it reads
/// them, and the features it compiles in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct Variant {
    culling: LightCulling,
    lights_in_table: bool,
    features: ShaderFeatures,
}

impl Variant {
    fn of(plan: &FramePlan) -> Variant {
        Variant { culling: plan.culling, lights_in_table: plan.lights_in_table(), features: plan.features }
    }
}

/// Every camera draw, or on the deferred path the transparent ones the G-buffer left.
fn forward_draws(plan: &FramePlan) -> &[u32] {
    match plan.path {
        RenderPath::Forward => &plan.camera_draws,
        RenderPath::Deferred => &plan.camera_draws[plan.transparent_from..],
    }
}
