//! The forward pass: every visible draw lit by the point and spot lights its culling
//! mode lists (clustered, per object, or all), into the pre-exposed HDR target, over the
//! depth prepass's depth; with MSAA into multisampled targets resolved into the HDR
//! target. On the deferred path it draws the layered (KHR_materials_*) solids again,
//! replacing the G-buffer's light where they are the surface, and the transparent draws,
//! over the lit G-buffer's image and depth. Where a frame has transmissive solids
//! (KHR_materials_transmission), the pass ends after the other solids, the lit image is
//! copied into a mip chain (`opaque_copy`), and a second render pass draws the
//! transmissive solids, refracting that copy, then the transparent draws.

use super::background::{BackgroundPipelines, BackgroundTargets};
use super::mesh::{DepthTest, MeshPipelines, MeshPipelinesDesc, forward_depth, scene_depth};
use super::opaque_copy::OpaqueCopy;
use super::targets::{DIRECTIONAL_ATLAS, LOCAL_ATLAS, SHADOW_TINTS};
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
    /// The opaque image's copy and the layout that binds it, where the device binds the
    /// 17 sampled textures the refracting shader reads (else transmissive draws are
    /// shaded as plain layered solids).
    transmission: Option<Transmission>,
    /// The transmissive draws' pipelines per variant: refracting the copy, or not.
    transmissive_pipelines: HashMap<Variant, MeshPipelines>,
}

/// The opaque image's copy and the pipeline layout that binds it as group 2.
struct Transmission {
    copy: OpaqueCopy,
    layout: wgpu::PipelineLayout,
}

/// Sampled textures the transmissive draws' fragment shader binds: the frame's ten, the
/// material's six, the opaque image.
const TRANSMISSION_SAMPLED_TEXTURES: u32 = 17;

impl PassType for ForwardPass {
    const NAME: &'static str = "forward";

    /// The forward path makes the HDR image (through multisampled targets with MSAA) over
    /// the prepass's depth; the deferred path adds its transparent draws, if any, to the
    /// lit G-buffer's image.
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        let draws_nothing = forward_draws(plan).is_empty() && plan.transmissive_from == plan.camera_draws.len();
        if draws_nothing && plan.path == RenderPath::Deferred {
            return;
        }
        pass.read(DIRECTIONAL_ATLAS).read(LOCAL_ATLAS).read(SHADOW_TINTS).modify(forward_depth(plan));
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
        let binds_enough = init.device.limits().max_sampled_textures_per_shader_stage >= TRANSMISSION_SAMPLED_TEXTURES;
        if !binds_enough {
            tracing::warn!(
                "the device binds fewer than {TRANSMISSION_SAMPLED_TEXTURES} textures per shader: transmissive \
                 materials are drawn without the scene behind them"
            );
        }
        let transmission = binds_enough.then(|| {
            let copy = OpaqueCopy::new(init.device);
            let layout = init.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("transmission pipeline layout"),
                bind_group_layouts: &[Some(init.frame_layout), Some(init.material_layout), Some(&copy.group_layout)],
                immediate_size: 0,
            });
            Transmission { copy, layout }
        });
        ForwardPass {
            module: shaders::module(init.device, "forward", crate::wgsl!("forward")),
            layout: init.scene_layout(),
            depth_format: init.depth_format,
            pipelines: HashMap::new(),
            background: BackgroundPipelines::new(init.device, init.frame_layout, init.depth_format),
            transmission,
            transmissive_pipelines: HashMap::new(),
        }
    }
}

impl ForwardPass {
    /// The forward pipelines of `variant`, or with `transmissive` the transmissive draws'
    /// (testing depth as the nearest surface, since no earlier pass wrote theirs; with
    /// the copy's layout, refracting it).
    fn pipelines_for(&self, variant: Variant, transmissive: bool) -> MeshPipelines {
        let transmission = self.transmission.as_ref().filter(|_| transmissive).map(|t| &t.layout);
        let mode = match variant.culling {
            LightCulling::None => LIGHT_CULLING_NONE,
            LightCulling::Clustered => LIGHT_CULLING_CLUSTERED,
            LightCulling::PerObject => LIGHT_CULLING_PER_OBJECT,
        };
        let depth_test = match (transmissive, variant.deferred) {
            (true, _) => DepthTest::Nearest,
            (false, true) => DepthTest::OverGBuffer,
            (false, false) => DepthTest::AfterPrepass,
        };
        MeshPipelines::new(MeshPipelinesDesc {
            label: if transmissive { "forward, transmissive" } else { "forward" },
            module: self.module.clone(),
            fragment_entry: Some(if transmission.is_some() { "fs_transmission" } else { "fs_main" }),
            layout: transmission.unwrap_or(&self.layout).clone(),
            color_formats: vec![HDR_FORMAT],
            blends: true,
            depth_test,
            depth_format: self.depth_format,
            marks_stencil: false,
            constants: [overrides::LIGHT_CULLING.value(mode as f64), overrides::LIGHTS_IN_TABLE.flag(variant.lights_in_table)]
                .into_iter()
                .chain(variant.features.constants())
                .collect(),
            alpha_test_override: Some(overrides::ALPHA_TESTED),
            textured_override: Some(overrides::MATERIAL_TEXTURED),
            layered_override: Some(overrides::MATERIAL_LAYERED),
        })
    }
}

impl FramePass for ForwardPass {
    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        let key = Variant::of(cx.plan);
        if !self.pipelines.contains_key(&key) {
            let made = self.pipelines_for(key, false);
            self.pipelines.insert(key, made);
        }
        if !self.transmissive_pipelines.contains_key(&key) {
            let made = self.pipelines_for(key, true);
            self.transmissive_pipelines.insert(key, made);
        }
        let pipelines = self.pipelines.get_mut(&key).expect("made above");
        pipelines.prepare(cx.device, &cx.scene.draws, forward_draws(cx.plan), cx.plan.msaa);
        pipelines.prepare(cx.device, &cx.scene.draws, transparent_draws(cx.plan), cx.plan.msaa);
        let transmissive = transmissive_draws(cx.plan);
        let pipelines = self.transmissive_pipelines.get_mut(&key).expect("made above");
        pipelines.prepare(cx.device, &cx.scene.draws, transmissive, cx.plan.msaa);
        if let Some(t) = self.transmission.as_mut().filter(|_| !transmissive.is_empty()) {
            t.copy.prepare(cx.device, cx.plan.view.width, cx.plan.view.height);
        }
        if let Some(targets) = background_targets(cx.plan) {
            self.background.prepare(cx.device, &targets, cx.environment_image);
        }
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        let background =
            glam::Vec3::from(cx.settings.render.background) * exposure_scale(cx.settings.render.exposure_ev100);
        let clear = wgpu::Color { r: background.x as f64, g: background.y as f64, b: background.z as f64, a: 0.0 };
        let key = Variant::of(cx.plan);
        let transmission = self.transmission.as_ref().filter(|_| !transmissive_draws(cx.plan).is_empty());
        let first = self.color_attachment(cx, wgpu::LoadOp::Clear(clear), transmission.is_some());
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("forward pass"),
            color_attachments: &[Some(first)],
            // Both paths draw over depth an earlier pass wrote: the prepass or the G-buffer.
            depth_stencil_attachment: Some(scene_depth(cx.targets.view(forward_depth(cx.plan)), true)),
            timestamp_writes: cx.timestamps.and_then(|t| t.writes(true, transmission.is_none())),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, cx.frame_bind_group, &[]);
        let pipelines = &self.pipelines[&key];
        pipelines.draw(&mut pass, cx.scene, forward_draws(cx.plan));
        // Behind the transmissive and transparent draws, over what the solids left.
        if let Some(targets) = background_targets(cx.plan) {
            self.background.draw(&mut pass, &targets);
        }
        let transmissive_pipelines = &self.transmissive_pipelines[&key];
        let Some(transmission) = transmission else {
            transmissive_pipelines.draw(&mut pass, cx.scene, transmissive_draws(cx.plan));
            pipelines.draw(&mut pass, cx.scene, transparent_draws(cx.plan));
            return;
        };
        drop(pass);
        transmission.copy.record(cx.device, cx.encoder, cx.targets.view(HDR));
        let second = self.color_attachment(cx, wgpu::LoadOp::Load, false);
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("forward pass, transmission"),
            color_attachments: &[Some(second)],
            depth_stencil_attachment: Some(scene_depth(cx.targets.view(forward_depth(cx.plan)), true)),
            timestamp_writes: cx.timestamps.and_then(|t| t.writes(false, true)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, cx.frame_bind_group, &[]);
        pass.set_bind_group(2, transmission.copy.group(), &[]);
        transmissive_pipelines.draw(&mut pass, cx.scene, transmissive_draws(cx.plan));
        pipelines.draw(&mut pass, cx.scene, transparent_draws(cx.plan));
    }
}

impl ForwardPass {
    /// The pass's colour attachment: the HDR target on the deferred path (loaded, as the
    /// light volumes left it), else the HDR target or, with MSAA, the multisampled one
    /// resolved into it. `load` applies on the forward path; `keep_samples` stores the
    /// multisampled target for a second render pass.
    fn color_attachment<'a>(
        &self,
        cx: &PassContext<'a>,
        load: wgpu::LoadOp<wgpu::Color>,
        keep_samples: bool,
    ) -> wgpu::RenderPassColorAttachment<'a> {
        let hdr = cx.targets.view(HDR);
        let (view, resolve_target, load, store) = match cx.plan.path {
            RenderPath::Deferred => (hdr, None, wgpu::LoadOp::Load, wgpu::StoreOp::Store),
            // The samples are resolved (averaged) into the HDR target, before tone mapping.
            RenderPath::Forward if cx.plan.msaa > 1 => {
                let store = if keep_samples { wgpu::StoreOp::Store } else { wgpu::StoreOp::Discard };
                (cx.targets.view(HDR_MULTISAMPLED), Some(hdr), load, store)
            }
            RenderPath::Forward => (hdr, None, load, wgpu::StoreOp::Store),
        };
        wgpu::RenderPassColorAttachment { view, depth_slice: None, resolve_target, ops: wgpu::Operations { load, store } }
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
    /// On the deferred path: over the G-buffer's depth.
    deferred: bool,
    culling: LightCulling,
    lights_in_table: bool,
    features: ShaderFeatures,
}

impl Variant {
    fn of(plan: &FramePlan) -> Variant {
        Variant { deferred: plan.path == RenderPath::Deferred, culling: plan.culling, lights_in_table: plan.lights_in_table(), features: plan.features }
    }
}

/// The solids the pass draws first: every one but the transmissive on the forward path,
/// the layered ones on the deferred path (`FramePlan::forward_draws`).
fn forward_draws(plan: &FramePlan) -> &[u32] {
    &plan.forward_draws
}

/// The transmissive solids, near to far.
fn transmissive_draws(plan: &FramePlan) -> &[u32] {
    &plan.camera_draws[plan.transmissive_from..plan.transparent_from]
}

/// The alpha-blended draws, far to near.
fn transparent_draws(plan: &FramePlan) -> &[u32] {
    &plan.camera_draws[plan.transparent_from..]
}
