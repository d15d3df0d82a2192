//! The renderer: a frame is planned (`plan::FramePlan`), its data uploaded, its passes
//! recorded in the plan's order through the frame graph, and submitted. Nothing waits for
//! the GPU unless the caller reads something back; up to two frames are in flight.

use crate::context::GpuContext;
use crate::error::RenderError;
use crate::frame_data::FrameData;
use crate::graph::{
    FramePass, GpuTimer, PassContext, PassStats, PrepareContext, Resource, TargetDesc, Targets, check_order,
};
use crate::output::{Aovs, AtlasImage, FrameOptions, FrameOutput, FrameTimings, GpuFrameTimes, f16_to_f32};
use crate::passes::aov::{AOV_FORMAT, AovPass};
use crate::passes::debug_view::DebugViewPass;
use crate::passes::deferred_lights::DeferredLightsPass;
use crate::passes::depth_prepass::DepthPrepassPass;
use crate::passes::forward::{ForwardPass, HDR_FORMAT};
use crate::passes::gbuffer::{
    GBUFFER_ALBEDO_METALLIC_FORMAT, GBUFFER_PACKED_FORMAT, GBufferPass, LIGHT_BUFFER_LDR_FORMAT,
};
use crate::passes::ldr_decode::LdrDecodePass;
use crate::passes::shadow_aov::{SHADOW_AOV_FORMAT, ShadowAovPass};
use crate::passes::shadows::{SHADOW_FORMAT, ShadowPass};
use crate::passes::tonemap::TonemapPass;
use crate::plan::lights::LightId;
use crate::plan::shadows::ShadowAtlasTiles;
use crate::plan::{FramePlan, PassId, PlanRequest};
use crate::readback::{PendingCopy, copy_texture, finish_copies};
use crate::scene::{GpuScene, material_layout};
use crate::shader_constants::{MAX_UNIFORM_LIGHTS, NO_LIGHT};
use crate::view::View;
use chiaro_math::tonemap::exposure_scale;
use chiaro_scene::{Scene, Settings};
use std::collections::{HashSet, VecDeque};
use std::time::Instant;

/// The tone-mapped image of offscreen frames.
pub const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Frames submitted but not known to be finished before `render` waits for the oldest.
const MAX_FRAMES_IN_FLIGHT: usize = 2;
/// Finished frames' GPU times kept until taken.
const MAX_KEPT_GPU_TIMES: usize = 1024;

/// A scene on the GPU.
pub struct PreparedScene {
    pub gpu: GpuScene,
}

pub struct Renderer {
    pub ctx: GpuContext,
    frame_data: FrameData,
    material_layout: wgpu::BindGroupLayout,
    /// Every pass of the frame graph; the plan says which run and in what order.
    passes: Vec<Box<dyn FramePass>>,
    shadow_aov: ShadowAovPass,
    targets: Targets,
    timer: Option<GpuTimer>,
    atlas_tiles: ShadowAtlasTiles,
    in_flight: VecDeque<wgpu::SubmissionIndex>,
    next_frame: u64,
    gpu_times: VecDeque<GpuFrameTimes>,
}

impl Renderer {
    pub fn new(ctx: GpuContext) -> Result<Renderer, RenderError> {
        let device = &ctx.device;
        let frame_data = FrameData::new(device);
        let material_layout = material_layout(device);
        let scene_layout = || {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("scene pipeline layout"),
                bind_group_layouts: &[Some(&frame_data.layout), Some(&material_layout)],
                immediate_size: 0,
            })
        };
        let passes: Vec<Box<dyn FramePass>> = vec![
            Box::new(ShadowPass::new(&ctx, &material_layout)),
            Box::new(DepthPrepassPass::new(device, scene_layout(), ctx.depth_format)),
            Box::new(ForwardPass::new(device, scene_layout(), ctx.depth_format)),
            Box::new(AovPass::new(device, &scene_layout(), ctx.depth_format)),
            Box::new(TonemapPass::new(device)),
            Box::new(GBufferPass::new(device, &scene_layout(), ctx.depth_format)),
            Box::new(DeferredLightsPass::new(device, &frame_data.layout, ctx.depth_format)),
            Box::new(LdrDecodePass::new(device)),
            Box::new(DebugViewPass::new(device)),
        ];
        let shadow_aov = ShadowAovPass::new(device, &frame_data.layout, &material_layout, ctx.depth_format);
        let timer = ctx.has_timestamps.then(|| GpuTimer::new(device, &ctx.queue));
        ctx.take_error()?;
        Ok(Renderer {
            frame_data,
            material_layout,
            passes,
            shadow_aov,
            targets: Targets::default(),
            timer,
            atlas_tiles: ShadowAtlasTiles::default(),
            in_flight: VecDeque::new(),
            next_frame: 0,
            gpu_times: VecDeque::new(),
            ctx,
        })
    }

    /// Uploads a scene's geometry, objects, materials and textures.
    pub fn prepare(&mut self, scene: &Scene) -> Result<PreparedScene, RenderError> {
        let gpu = GpuScene::upload(&self.ctx.device, &self.ctx.queue, &self.material_layout, scene);
        self.ctx.take_error()?;
        Ok(PreparedScene { gpu })
    }

    /// The plan of the next frame, as `render` would make it (its shadow tiles are
    /// allocated, so the next frame keeps them).
    pub fn plan(
        &mut self,
        scene: &Scene,
        prepared: &PreparedScene,
        view: &View,
        settings: &Settings,
        options: FrameOptions,
    ) -> FramePlan {
        let request = PlanRequest { aovs: options.aovs, debug: options.debug, shadow_aovs: options.shadow_aovs };
        FramePlan::new(scene, &prepared.gpu.draws, view, settings, &mut self.atlas_tiles, request)
    }

    /// Renders one frame of `scene` (already `prepare`d) from `view` into a texture of
    /// the renderer's.
    pub fn render(
        &mut self,
        scene: &Scene,
        prepared: &PreparedScene,
        view: &View,
        settings: &Settings,
        options: FrameOptions,
    ) -> Result<FrameOutput, RenderError> {
        self.run_frame(scene, prepared, view, settings, options, None)
    }

    /// Renders one frame into `output` (a window's surface texture, say), whose format
    /// may be sRGB or linear; the frame is not waited for unless `options` reads back.
    #[allow(clippy::too_many_arguments)]
    pub fn render_to(
        &mut self,
        scene: &Scene,
        prepared: &PreparedScene,
        view: &View,
        settings: &Settings,
        options: FrameOptions,
        output: &wgpu::TextureView,
        output_format: wgpu::TextureFormat,
    ) -> Result<FrameOutput, RenderError> {
        self.run_frame(scene, prepared, view, settings, options, Some((output, output_format)))
    }

    /// GPU pass times of the frames that have finished since the last call, oldest first;
    /// with `wait`, after every submitted frame has finished.
    pub fn gpu_times(&mut self, wait: bool) -> Result<Vec<GpuFrameTimes>, RenderError> {
        if wait {
            self.wait_idle()?;
        } else {
            self.ctx.device.poll(wgpu::PollType::Poll).map_err(|e| RenderError::Gpu(e.to_string()))?;
        }
        self.collect_gpu_times();
        Ok(self.gpu_times.drain(..).collect())
    }

    /// Blocks until every submitted frame has finished.
    pub fn wait_idle(&mut self) -> Result<(), RenderError> {
        self.ctx.wait_idle()?;
        self.in_flight.clear();
        Ok(())
    }

    fn collect_gpu_times(&mut self) {
        let Some(timer) = &mut self.timer else { return };
        for (frame, passes) in timer.collect() {
            if self.gpu_times.len() == MAX_KEPT_GPU_TIMES {
                self.gpu_times.pop_front();
            }
            self.gpu_times.push_back(GpuFrameTimes {
                frame,
                passes: passes.into_iter().map(|(pass, ms)| (pass.name(), ms)).collect(),
            });
        }
    }

    fn pass_mut(passes: &mut [Box<dyn FramePass>], id: PassId) -> &mut Box<dyn FramePass> {
        passes.iter_mut().find(|p| p.id() == id).unwrap_or_else(|| panic!("no {} pass registered", id.name()))
    }

    /// Makes every target the frame writes, sized for the view and the plan's atlases.
    fn ensure_targets(&mut self, plan: &FramePlan, written: &HashSet<Resource>, external_output: bool) {
        let device = &self.ctx.device;
        let (width, height) = (plan.view.width, plan.view.height);
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let sampled = wgpu::TextureUsages::TEXTURE_BINDING;
        for (resource, size) in [
            (Resource::DirectionalShadowAtlas, plan.shadows.directional_atlas_size),
            (Resource::OtherShadowAtlas, plan.shadows.other_atlas_size),
        ] {
            // An atlas no light uses this frame keeps its texture (1 texel until first used).
            if size > 0 || self.targets.texture(resource).is_none() {
                let desc = TargetDesc {
                    width: size.max(1),
                    height: size.max(1),
                    format: SHADOW_FORMAT,
                    usage: attach | sampled,
                    samples: 1,
                };
                self.targets.ensure(device, resource, desc);
            }
        }
        for &resource in written {
            let mut samples = 1;
            let (format, usage) = match resource {
                Resource::Depth => (self.ctx.depth_format, wgpu::TextureUsages::RENDER_ATTACHMENT),
                Resource::DepthMultisampled => {
                    samples = plan.msaa;
                    (self.ctx.depth_format, wgpu::TextureUsages::RENDER_ATTACHMENT)
                }
                Resource::HdrMultisampled => {
                    samples = plan.msaa;
                    (HDR_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT)
                }
                Resource::Hdr => (HDR_FORMAT, attach | sampled),
                Resource::GBufferAlbedoMetallic => (GBUFFER_ALBEDO_METALLIC_FORMAT, attach | sampled),
                Resource::GBufferPacked => (GBUFFER_PACKED_FORMAT, attach | sampled),
                Resource::LightBufferLdr => (LIGHT_BUFFER_LDR_FORMAT, attach | sampled),
                Resource::AovPosition | Resource::AovNormalDepth | Resource::AovBaked => (AOV_FORMAT, attach),
                Resource::AovShadow => (SHADOW_AOV_FORMAT, attach),
                Resource::Output if !external_output => (OUTPUT_FORMAT, attach),
                _ => continue,
            };
            self.targets.ensure(device, resource, TargetDesc { width, height, format, usage, samples });
        }
    }

    fn run_frame(
        &mut self,
        scene: &Scene,
        prepared: &PreparedScene,
        view: &View,
        settings: &Settings,
        options: FrameOptions,
        output: Option<(&wgpu::TextureView, wgpu::TextureFormat)>,
    ) -> Result<FrameOutput, RenderError> {
        let _span = tracing::info_span!("frame", width = view.width, height = view.height).entered();
        let start = Instant::now();
        let max = self.ctx.max_texture_size();
        if view.width == 0 || view.height == 0 || view.width > max || view.height > max {
            return Err(RenderError::OutputSize {
                width: view.width,
                height: view.height,
                reason: format!("each side must be between 1 and {max} (this device's limit)"),
            });
        }
        let frame = self.next_frame;
        self.next_frame += 1;
        let plan = self.plan(scene, prepared, view, settings, options);
        tracing::debug!("{plan}");
        self.ctx
            .check_msaa(plan.msaa)
            .map_err(|e| RenderError::Unsupported(format!("render.msaa = {}: {e}", plan.msaa)))?;

        let mut order = Vec::with_capacity(plan.passes.len() + 1);
        for &id in &plan.passes {
            order.push((id, Self::pass_mut(&mut self.passes, id).io(&plan)));
        }
        if options.shadow_aovs {
            order.push((PassId::ShadowAov, ShadowAovPass::io()));
        }
        let written = check_order(&order)?;
        self.ensure_targets(&plan, &written, output.is_some());
        self.targets.set_external_output(output.map(|(view, _)| view.clone()));
        let output_format = output.map_or(OUTPUT_FORMAT, |(_, format)| format);

        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        self.frame_data.upload(device, queue, &plan, scene, settings);
        let frame_bind_group = self.frame_data.bind_group(device, &prepared.gpu, &self.targets);
        let prepare = PrepareContext { device, queue, plan: &plan, scene: &prepared.gpu, source: scene, output_format };
        for &id in &plan.passes {
            Self::pass_mut(&mut self.passes, id).prepare(&prepare);
        }

        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let mut stats = PassStats::default();
        for &id in &plan.passes {
            let pass = self.passes.iter().find(|p| p.id() == id).expect("registered");
            encoder.push_debug_group(id.name());
            let mut cx = PassContext {
                device,
                encoder: &mut encoder,
                plan: &plan,
                settings,
                scene: &prepared.gpu,
                frame_bind_group: &frame_bind_group,
                targets: &self.targets,
                timestamps: self.timer.as_mut().and_then(|t| t.pass(id)),
                stats: &mut stats,
            };
            pass.record(&mut cx);
            encoder.pop_debug_group();
        }
        if let Some(timer) = &mut self.timer {
            timer.end_frame(device, &mut encoder, frame);
        }

        // Read-backs ride in the frame's own submission.
        let mut copies = Vec::new();
        let mut wanted = Vec::new();
        if options.readback {
            for (resource, bytes_per_pixel) in [
                (Resource::Hdr, 8),
                (Resource::Output, 4),
                (Resource::AovPosition, 16),
                (Resource::AovNormalDepth, 16),
                (Resource::AovBaked, 16),
            ] {
                if written.contains(&resource)
                    && let Some(texture) = self.targets.texture(resource)
                {
                    copies.push(copy_texture(device, &mut encoder, texture, bytes_per_pixel));
                    wanted.push(resource);
                }
            }
        }
        let mut atlases = Vec::new();
        if options.read_shadow_atlas {
            for (name, resource, size) in [
                ("directional", Resource::DirectionalShadowAtlas, plan.shadows.directional_atlas_size),
                ("other", Resource::OtherShadowAtlas, plan.shadows.other_atlas_size),
            ] {
                if size > 0 {
                    let texture = self.targets.texture(resource).expect("atlases are the renderer's");
                    copies.push(copy_texture(device, &mut encoder, texture, 4));
                    atlases.push((name, size));
                }
            }
        }
        let shadow_copies = if options.shadow_aovs {
            self.record_shadow_aovs(scene, prepared, &plan, settings, &frame_bind_group, &mut encoder)
        } else {
            Vec::new()
        };
        let cpu_prepare_ms = start.elapsed().as_secs_f64() * 1e3;

        self.throttle()?;
        let submission = self.ctx.queue.submit([encoder.finish()]);
        self.in_flight.push_back(submission);
        if let Some(timer) = &mut self.timer {
            timer.submitted();
        }

        let mut timings = FrameTimings { frame, cpu_prepare_ms, ..Default::default() };
        let mut out = FrameOutput {
            width: view.width,
            height: view.height,
            hdr: Vec::new(),
            ldr: Vec::new(),
            aovs: None,
            timings: FrameTimings::default(),
            shadow_aovs: Vec::new(),
            shadow_atlases: Vec::new(),
            shadow_tiles: stats.shadow_tiles_rendered,
            shadow_caster_draws: stats.shadow_caster_draws,
            plan,
        };
        if options.reads_back() {
            let shadow_count = shadow_copies.len();
            let mut bytes = finish_copies(&self.ctx, copies.into_iter().chain(shadow_copies).collect())?;
            self.in_flight.clear();
            timings.wall_ms = Some(start.elapsed().as_secs_f64() * 1e3);
            let shadow_bytes = bytes.split_off(bytes.len() - shadow_count);
            let atlas_bytes = bytes.split_off(bytes.len() - atlases.len());
            let exposure = exposure_scale(settings.render.exposure_ev100);
            unpack_images(&mut out, &wanted, bytes, exposure);
            out.shadow_atlases = atlases
                .into_iter()
                .zip(atlas_bytes)
                .map(|((name, size), b)| AtlasImage { name, size, depths: bytemuck::cast_slice(&b).to_vec() })
                .collect();
            out.shadow_aovs = shadow_bytes
                .iter()
                .map(|b| {
                    let pairs: &[[f32; 2]] = bytemuck::cast_slice(b);
                    pairs.iter().map(|p| if p[1] > 0.5 { p[0] } else { f32::NAN }).collect()
                })
                .collect();
            self.collect_gpu_times();
            if let Some(k) = self.gpu_times.iter().position(|t| t.frame == frame) {
                timings.gpu_pass_ms = self.gpu_times.remove(k).expect("found").passes;
            }
        } else {
            self.ctx.device.poll(wgpu::PollType::Poll).map_err(|e| RenderError::Gpu(e.to_string()))?;
            self.collect_gpu_times();
        }
        self.targets.set_external_output(None);
        self.ctx.take_error()?;
        out.timings = timings;
        Ok(out)
    }

    /// Waits for the oldest frames until fewer than `MAX_FRAMES_IN_FLIGHT` are in flight.
    fn throttle(&mut self) -> Result<(), RenderError> {
        while self.in_flight.len() >= MAX_FRAMES_IN_FLIGHT {
            let oldest = self.in_flight.pop_front().expect("non-empty");
            self.ctx
                .device
                .poll(wgpu::PollType::Wait { submission_index: Some(oldest), timeout: None })
                .map_err(|e| RenderError::Gpu(e.to_string()))?;
        }
        Ok(())
    }

    /// One shadow AOV pass per scene light, each followed by a copy of its result.
    fn record_shadow_aovs(
        &mut self,
        scene: &Scene,
        prepared: &PreparedScene,
        plan: &FramePlan,
        settings: &Settings,
        frame_bind_group: &wgpu::BindGroup,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Vec<PendingCopy> {
        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        // Lights past the uniform light buffer cannot be reported.
        let light_indices: Vec<u32> = (0..scene.lights.len())
            .map(|i| {
                plan.light_index(LightId(i as u32))
                    .filter(|&k| k < MAX_UNIFORM_LIGHTS as usize)
                    .map_or(NO_LIGHT, |k| k as u32)
            })
            .collect();
        self.shadow_aov.prepare(device, queue, plan, &prepared.gpu, &light_indices);
        let texture = self.targets.texture(Resource::AovShadow).expect("made for shadow AOVs");
        let mut stats = PassStats::default();
        (0..light_indices.len())
            .map(|k| {
                let mut cx = PassContext {
                    device,
                    encoder,
                    plan,
                    settings,
                    scene: &prepared.gpu,
                    frame_bind_group,
                    targets: &self.targets,
                    timestamps: None,
                    stats: &mut stats,
                };
                self.shadow_aov.record(&mut cx, k);
                copy_texture(device, encoder, texture, 8)
            })
            .collect()
    }
}

/// Fills the output's images from the read-back bytes of `resources`, in order.
fn unpack_images(out: &mut FrameOutput, resources: &[Resource], bytes: Vec<Vec<u8>>, exposure: f32) {
    let mut position = None;
    let mut normal = None;
    let mut baked = None;
    for (resource, b) in resources.iter().zip(bytes) {
        match resource {
            Resource::Hdr => {
                let halves: &[u16] = bytemuck::cast_slice(&b);
                out.hdr = halves
                    .chunks_exact(4)
                    .map(|p| {
                        let c = [p[0], p[1], p[2], p[3]].map(f16_to_f32);
                        [c[0] / exposure, c[1] / exposure, c[2] / exposure, c[3]]
                    })
                    .collect();
            }
            Resource::Output => out.ldr = b,
            Resource::AovPosition => position = Some(b),
            Resource::AovNormalDepth => normal = Some(b),
            Resource::AovBaked => baked = Some(b),
            _ => {}
        }
    }
    if let (Some(position), Some(normal), Some(baked)) = (position, normal, baked) {
        let position: &[[f32; 4]] = bytemuck::cast_slice(&position);
        let normal: &[[f32; 4]] = bytemuck::cast_slice(&normal);
        let baked: &[[f32; 4]] = bytemuck::cast_slice(&baked);
        let mut a = Aovs::default();
        for ((p, n), e) in position.iter().zip(normal).zip(baked) {
            if p[3] > 0.5 {
                a.position_ws.push([p[0], p[1], p[2]]);
                a.normal_ws.push([n[0], n[1], n[2]]);
                a.depth.push(n[3]);
                a.baked_irradiance.push([e[0], e[1], e[2]]);
            } else {
                a.position_ws.push([f32::NAN; 3]);
                a.normal_ws.push([f32::NAN; 3]);
                a.depth.push(f32::INFINITY);
                a.baked_irradiance.push([0.0; 3]);
            }
        }
        out.aovs = Some(a);
    }
}
