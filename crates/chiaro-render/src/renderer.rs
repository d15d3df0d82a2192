//! The renderer: a frame is planned (`plan::FramePlan`), its data uploaded, its passes
//! recorded in the plan's order through the frame graph, and submitted. Nothing waits for
//! the GPU unless the caller reads something back; up to two frames are in flight.

use crate::context::GpuContext;
use crate::environment::EnvironmentCache;
use crate::error::RenderError;
use crate::frame_data::FrameData;
use crate::graph::target::ATTACHMENT_COPY;
use crate::graph::{
    FrameGraph, FramePass, GpuTimer, OUTPUT, PassContext, PassInit, PassStats, PrepareContext, Target, TargetDesc,
    Targets,
};
use crate::output::{FrameOptions, FrameOutput, FrameTimings, GpuFrameTimes};
use crate::passes::ambient_occlusion::AMBIENT_OCCLUSION;
use crate::passes::targets::HDR;
use crate::passes::targets::{DIRECTIONAL_ATLAS, LOCAL_ATLAS};
use crate::plan::shadows::{ShadowAtlas, ShadowAtlasTiles};
use crate::plan::{FramePlan, PlanRequest};
use crate::readback::{PendingCopy, copy_buffer, copy_texture, finish_copies_of};
use crate::scene::{GpuScene, material_layout};
use crate::thread_clock::thread_cpu_ms;
use crate::unpack::unpack_images;
use crate::view::View;
use chiaro_math::tonemap::exposure_scale;
use chiaro_scene::{Scene, Settings};
use std::collections::VecDeque;
use web_time::Instant;

/// The tone-mapped image of offscreen frames.
pub const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Frames submitted but not known to be finished before `render` waits for the oldest.
const MAX_FRAMES_IN_FLIGHT: usize = 2;
/// Finished frames' GPU times kept until taken.
const MAX_KEPT_GPU_TIMES: usize = 1024;

/// A frame submitted by [`Renderer::submit`], to be read back by [`Renderer::finish`].
pub struct PendingFrame {
    out: FrameOutput,
    copies: Vec<(Target, PendingCopy)>,
    /// The copies' bytes, once read without blocking (`read_back_async`).
    read: Option<Vec<(Target, Vec<u8>)>>,
    submission: wgpu::SubmissionIndex,
    start: Instant,
    exposure: f32,
    reads_back: bool,
}

impl PendingFrame {
    /// Waits for the frame's read-backs without blocking the page (the browser build's
    /// way); [`Renderer::finish`] then unpacks them at once. Natively `finish` waits itself.
    #[cfg(target_arch = "wasm32")]
    pub async fn read_back_async(mut self) -> Result<PendingFrame, RenderError> {
        if self.reads_back && self.read.is_none() {
            let (targets, copies): (Vec<Target>, Vec<PendingCopy>) =
                std::mem::take(&mut self.copies).into_iter().unzip();
            let bytes = crate::readback::finish_copies_async(copies).await?;
            self.read = Some(targets.into_iter().zip(bytes).collect());
        }
        Ok(self)
    }
}

/// A scene on the GPU.
pub struct PreparedScene {
    /// Its vertex, index, object and material buffers, cookies and bakes.
    pub gpu: GpuScene,
}

/// Renders frames of prepared scenes: owns the passes, frame data, targets, shadow atlas
/// allocation and GPU timer, kept from frame to frame.
pub struct Renderer {
    /// The device it renders with.
    pub ctx: GpuContext,
    frame_data: FrameData,
    /// The environment's maps, made again when its source changes.
    environment: EnvironmentCache,
    material_layout: wgpu::BindGroupLayout,
    /// Every pass of `passes::DECLARATIONS`, in the same order; the frame graph says which
    /// run, and when.
    passes: Vec<Box<dyn FramePass>>,
    targets: Targets,
    timer: Option<GpuTimer>,
    atlas_tiles: ShadowAtlasTiles,
    /// Submitted frames (frame number, submission) not known to be finished, oldest first.
    in_flight: VecDeque<(u64, wgpu::SubmissionIndex)>,
    next_frame: u64,
    gpu_times: VecDeque<GpuFrameTimes>,
    /// The last marking frame's key (`FramePlan::marking_key`) and requests: a frame with
    /// the same key asks for the same pages without marking them again.
    last_marks: Option<(u64, Vec<u32>)>,
}

impl Renderer {
    /// Makes every pass's pipelines on `ctx`; fails on a GPU validation error.
    pub fn new(ctx: GpuContext) -> Result<Renderer, RenderError> {
        let device = &ctx.device;
        let frame_data = FrameData::new(device);
        let environment = EnvironmentCache::new(device, &ctx.queue);
        let material_layout = material_layout(device);
        let passes = crate::passes::make_all(&PassInit {
            ctx: &ctx,
            device,
            frame_layout: &frame_data.layout,
            material_layout: &material_layout,
            depth_format: ctx.depth_format,
        });
        let timer = ctx.has_timestamps.then(|| GpuTimer::new(device, &ctx.queue));
        ctx.take_error()?;
        Ok(Renderer {
            frame_data,
            environment,
            material_layout,
            passes,
            targets: Targets::default(),
            timer,
            atlas_tiles: ShadowAtlasTiles {
                max_texture_side: device.limits().max_texture_dimension_2d,
                ..ShadowAtlasTiles::default()
            },
            in_flight: VecDeque::new(),
            next_frame: 0,
            gpu_times: VecDeque::new(),
            last_marks: None,
            ctx,
        })
    }

    /// Forgets what earlier frames leave to later ones that would change the image: where
    /// each light's shadow tiles sit in the atlases and the coverage tiers' hysteresis. The
    /// next frame then renders exactly as it would on a new renderer, whatever came before:
    /// what a job needs, since a job's pixels must not depend on the jobs before it. A
    /// viewer keeps its history instead (tiles stay put while the lights' order changes).
    /// The cache of drawn tiles stays: its keys hold everything a tile's depths depend on,
    /// so a tile it keeps is the tile a new renderer would draw, and a job that places its
    /// tiles where the last one did draws none again.
    pub fn forget_history(&mut self) {
        let cache = std::mem::take(&mut self.atlas_tiles.cache);
        let max_texture_side = self.atlas_tiles.max_texture_side;
        self.atlas_tiles = ShadowAtlasTiles { cache, max_texture_side, ..ShadowAtlasTiles::default() };
    }

    /// Uploads a scene's geometry, objects, materials and textures.
    pub fn prepare(&mut self, scene: &Scene) -> Result<PreparedScene, RenderError> {
        let gpu = GpuScene::upload(&self.ctx.device, &self.ctx.queue, &self.material_layout, scene);
        self.ctx.take_error()?;
        Ok(PreparedScene { gpu })
    }

    /// The plan of the next frame; the atlases' state after it is in the plan, and kept
    /// once the frame is submitted.
    fn plan(
        &mut self,
        scene: &Scene,
        prepared: &PreparedScene,
        view: &View,
        settings: &Settings,
        options: FrameOptions,
    ) -> FramePlan {
        let request = PlanRequest {
            aovs: options.aovs,
            depth_only: options.aovs && options.depth_only,
            debug: options.debug,
            shadow_aovs: options.shadow_aovs,
            ids: options.ids,
        };
        FramePlan::new(scene, &prepared.gpu.draws, view, settings, &self.atlas_tiles, request)
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
            self.gpu_times.push_back(GpuFrameTimes { frame, passes });
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
        let pending = self.submit_frame(scene, prepared, view, settings, options, output)?;
        self.finish(pending)
    }

    /// Makes the maps of the environment `settings` name for `scene` now, rather than
    /// with the next frame, and waits for the device to finish them: the milliseconds that
    /// took (read, projected, uploaded and prefiltered), or `None` where nothing was made
    /// (no environment, or the same one as before). Errors name the image file.
    pub fn prepare_environment(&mut self, scene: &Scene, settings: &Settings) -> Result<Option<f64>, RenderError> {
        let start = Instant::now();
        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        if !self.environment.update(device, queue, &settings.environment, scene)? {
            return Ok(None);
        }
        device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| RenderError::Gpu(e.to_string()))?;
        self.ctx.take_error()?;
        Ok(Some(start.elapsed().as_secs_f64() * 1e3))
    }

    /// Plans, records and submits one frame of `scene` into a texture of the renderer's,
    /// without waiting for it: [`Renderer::finish`] reads it back. Submitting the next
    /// frame before finishing this one keeps the GPU busy while the CPU unpacks (at most
    /// two frames are in flight; a third submission waits for the oldest).
    pub fn submit(
        &mut self,
        scene: &Scene,
        prepared: &PreparedScene,
        view: &View,
        settings: &Settings,
        options: FrameOptions,
    ) -> Result<PendingFrame, RenderError> {
        self.submit_frame(scene, prepared, view, settings, options, None)
    }

    /// As [`Renderer::submit`], into `output` (a canvas's texture, say) as
    /// [`Renderer::render_to`] draws: for a caller that reads back without blocking.
    #[allow(clippy::too_many_arguments)]
    pub fn submit_to(
        &mut self,
        scene: &Scene,
        prepared: &PreparedScene,
        view: &View,
        settings: &Settings,
        options: FrameOptions,
        output: &wgpu::TextureView,
        output_format: wgpu::TextureFormat,
    ) -> Result<PendingFrame, RenderError> {
        self.submit_frame(scene, prepared, view, settings, options, Some((output, output_format)))
    }

    fn check_output_size(&self, view: &View) -> Result<(), RenderError> {
        let max = self.ctx.max_texture_size();
        if view.width == 0 || view.height == 0 || view.width > max || view.height > max {
            return Err(RenderError::OutputSize {
                width: view.width,
                height: view.height,
                reason: format!("each side must be between 1 and {max} (this device's limit)"),
            });
        }
        Ok(())
    }

    fn submit_frame(
        &mut self,
        scene: &Scene,
        prepared: &PreparedScene,
        view: &View,
        settings: &Settings,
        options: FrameOptions,
        output: Option<(&wgpu::TextureView, wgpu::TextureFormat)>,
    ) -> Result<PendingFrame, RenderError> {
        let _span = tracing::info_span!("frame", width = view.width, height = view.height).entered();
        let start = Instant::now();
        let thread_start = thread_cpu_ms();
        self.check_output_size(view)?;
        let frame = self.next_frame;
        self.next_frame += 1;
        let mut plan = self.plan(scene, prepared, view, settings, options);
        tracing::debug!("{plan}");
        self.ctx
            .check_msaa(plan.msaa)
            .map_err(|e| RenderError::Unsupported(format!("render.msaa = {}: {e}", plan.msaa)))?;
        if plan.wants_pages() {
            self.place_virtual_pages(scene, prepared, settings, &mut plan)?;
        }

        let graph = FrameGraph::compile(crate::passes::DECLARATIONS, &plan, self.ctx.depth_format)?;
        tracing::debug!("{graph}");
        let owned_output = output.is_none().then(|| TargetDesc::view_sized(OUTPUT_FORMAT, ATTACHMENT_COPY));
        self.targets.ensure_for(&self.ctx.device, &graph, (view.width, view.height), owned_output);
        self.targets.set_external_output(output.map(|(view, _)| view.clone()));
        let output_format = output.map_or(OUTPUT_FORMAT, |(_, format)| format);

        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        self.frame_data.upload(device, queue, &plan, scene, settings)?;
        self.environment.update(device, queue, &settings.environment, scene)?;
        let frame_bind_group =
            self.frame_data.bind_group(device, &prepared.gpu, self.environment.maps(), &self.targets);
        let prepare = PrepareContext {
            device,
            queue,
            plan: &plan,
            scene: &prepared.gpu,
            source: scene,
            output_format,
            environment_image: &self.environment.maps().image,
        };
        for &i in &graph.order {
            self.passes[i].prepare(&prepare);
        }

        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let stats = self.record_passes(&mut encoder, &graph, &plan, settings, &prepared.gpu, &frame_bind_group);
        let device = &self.ctx.device;
        if let Some(timer) = &mut self.timer {
            timer.end_frame(device, &mut encoder, frame);
        }

        // Read-backs ride in the frame's own submission.
        let read = read_backs(&graph, &plan, options);
        let mut copies = read
            .iter()
            .filter_map(|&(target, bytes_per_pixel)| {
                let texture = self.targets.texture(target)?;
                Some((target, copy_texture(device, &mut encoder, texture, bytes_per_pixel)))
            })
            .collect::<Vec<_>>();
        if options.ambient_occlusion && plan.features.ambient_occlusion {
            // Within the device's largest storage binding, which upload checked.
            let bytes = (view.width as u64 * view.height as u64 * size_of::<f32>() as u64) as u32;
            let denoised = self.frame_data.occlusion_buffers().denoised;
            copies.push((AMBIENT_OCCLUSION, copy_buffer(device, &mut encoder, denoised, bytes)));
        }
        let cpu_prepare_ms = start.elapsed().as_secs_f64() * 1e3;
        let cpu_prepare_thread_ms = thread_start.zip(thread_cpu_ms()).map(|(a, b)| b - a);

        self.throttle()?;
        let submission = self.ctx.queue.submit([encoder.finish()]);
        // The tiles the frame draws are in the atlases now (in submission order): only
        // now does the renderer remember them.
        self.atlas_tiles = plan.take_atlas_update();
        self.in_flight.push_back((frame, submission.clone()));
        if let Some(timer) = &mut self.timer {
            timer.submitted();
        }

        let timings = FrameTimings { frame, cpu_prepare_ms, cpu_prepare_thread_ms, ..Default::default() };
        let mut out = FrameOutput::before_read_back((view.width, view.height), timings, stats, plan, graph);
        if options.ambient_occlusion && !out.plan.features.ambient_occlusion {
            // The shading used no ambient occlusion: every pixel open.
            out.ambient_occlusion = Some(vec![1.0; view.width as usize * view.height as usize]);
        }
        self.targets.set_external_output(None);
        if !options.reads_back() {
            self.ctx.device.poll(wgpu::PollType::Poll).map_err(|e| RenderError::Gpu(e.to_string()))?;
            self.collect_gpu_times();
        }
        self.ctx.take_error()?;
        let exposure = exposure_scale(settings.render.exposure_ev100);
        Ok(PendingFrame { out, copies, read: None, submission, start, exposure, reads_back: options.reads_back() })
    }

    /// Before a frame shaded from virtual shadow maps: draws its view's depth, marks the
    /// pages its pixels want (a frame of its own, `FramePlan::marking_plan`), waits for
    /// the marks and places the pages in `plan`. The marks are this frame's own, so a
    /// single still image has every page it needs.
    fn place_virtual_pages(
        &mut self,
        scene: &Scene,
        prepared: &PreparedScene,
        settings: &Settings,
        plan: &mut FramePlan,
    ) -> Result<(), RenderError> {
        let _span = tracing::debug_span!("virtual page marking").entered();
        let draws = &prepared.gpu.draws;
        // The scene's geometry is the buffers it was uploaded to.
        let key = {
            use std::hash::{Hash, Hasher};
            let mut h = std::hash::DefaultHasher::new();
            (plan.marking_key(draws), &prepared.gpu.vertices, &prepared.gpu.indices).hash(&mut h);
            h.finish()
        };
        if let Some((last, requests)) = &self.last_marks
            && *last == key
        {
            plan.place_virtual_pages(draws, requests);
            return Ok(());
        }
        let marking = plan.marking_plan(draws);
        let graph = FrameGraph::compile(&crate::passes::marking_declarations(), &marking, self.ctx.depth_format)?;
        let view = marking.view;
        self.targets.ensure_for(&self.ctx.device, &graph, (view.width, view.height), None);
        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        self.frame_data.upload(device, queue, &marking, scene, settings)?;
        let bind_group = self.frame_data.bind_group(device, &prepared.gpu, self.environment.maps(), &self.targets);
        let prepare = PrepareContext {
            device,
            queue,
            plan: &marking,
            scene: &prepared.gpu,
            source: scene,
            output_format: OUTPUT_FORMAT,
            environment_image: &self.environment.maps().image,
        };
        for &i in &graph.order {
            self.passes[i].prepare(&prepare);
        }
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("virtual page marking") });
        // Untimed: the timer's passes are the frame's own.
        let timer = self.timer.take();
        self.record_passes(&mut encoder, &graph, &marking, settings, &prepared.gpu, &bind_group);
        self.timer = timer;
        let bytes = marking.shadows.virtual_maps.request_bytes() as u32;
        let requests = self.frame_data.marking_buffers().page_requests;
        let copy = copy_buffer(&self.ctx.device, &mut encoder, requests, bytes);
        let submission = self.ctx.queue.submit([encoder.finish()]);
        let read = finish_copies_of(&self.ctx, vec![copy], Some(submission))?;
        let requests: Vec<u32> = bytemuck::pod_collect_to_vec(&read[0]);
        // Marks of a frame that failed are not kept for the next.
        self.ctx.take_error()?;
        plan.place_virtual_pages(draws, &requests);
        self.last_marks = Some((key, requests));
        Ok(())
    }

    /// Waits for a submitted frame (and the frames before it, not those after) and reads
    /// it back as `FrameOutput`; a frame that reads nothing back returns at once.
    pub fn finish(&mut self, pending: PendingFrame) -> Result<FrameOutput, RenderError> {
        let PendingFrame { mut out, copies, read, submission, start, exposure, reads_back } = pending;
        if !reads_back {
            return Ok(out);
        }
        let read = match read {
            Some(read) => read,
            None => {
                let (targets, copies): (Vec<Target>, Vec<_>) = copies.into_iter().unzip();
                let bytes = finish_copies_of(&self.ctx, copies, Some(submission))?;
                targets.into_iter().zip(bytes).collect()
            }
        };
        // Submissions finish in order: every frame up to this one is done.
        let frame = out.timings.frame;
        while self.in_flight.front().is_some_and(|(f, _)| *f <= frame) {
            self.in_flight.pop_front();
        }
        out.timings.wall_ms = Some(start.elapsed().as_secs_f64() * 1e3);
        unpack_images(&mut out, read, exposure);
        self.collect_gpu_times();
        if let Some(k) = self.gpu_times.iter().position(|t| t.frame == frame) {
            out.timings.gpu_pass_ms = self.gpu_times.remove(k).expect("found").passes;
        }
        self.ctx.take_error()?;
        Ok(out)
    }

    /// Records every pass the graph kept, in its order, each in a debug group with its
    /// own timestamps.
    fn record_passes(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        graph: &FrameGraph,
        plan: &FramePlan,
        settings: &Settings,
        scene: &GpuScene,
        frame_bind_group: &wgpu::BindGroup,
    ) -> PassStats {
        let mut stats = PassStats::default();
        for (&i, &name) in graph.order.iter().zip(&graph.passes) {
            let _span = tracing::debug_span!("pass", name).entered();
            encoder.push_debug_group(name);
            let mut cx = PassContext {
                device: &self.ctx.device,
                encoder,
                plan,
                settings,
                scene,
                frame_bind_group,
                targets: &self.targets,
                view_depths: self.frame_data.view_depths(),
                occlusion: self.frame_data.occlusion_buffers(),
                marking: self.frame_data.marking_buffers(),
                timestamps: self.timer.as_mut().and_then(|t| t.pass(name)),
                stats: &mut stats,
            };
            self.passes[i].record(&mut cx);
            encoder.pop_debug_group();
        }
        stats
    }

    /// Waits for the oldest frames until fewer than `MAX_FRAMES_IN_FLIGHT` are in flight.
    fn throttle(&mut self) -> Result<(), RenderError> {
        while self.in_flight.len() >= MAX_FRAMES_IN_FLIGHT {
            let (_, oldest) = self.in_flight.pop_front().expect("non-empty");
            self.ctx
                .device
                .poll(wgpu::PollType::Wait { submission_index: Some(oldest), timeout: None })
                .map_err(|e| RenderError::Gpu(e.to_string()))?;
        }
        Ok(())
    }
}

/// The targets a frame reads back, with their bytes per texel: with `readback`, the HDR
/// image and the output (when the renderer owns it) and the exports; the shadow AOVs when
/// asked for; the atlases in use when asked for.
fn read_backs(graph: &FrameGraph, plan: &FramePlan, options: FrameOptions) -> Vec<(Target, u32)> {
    let texel = |target: &Target| {
        let (desc, _) = graph.targets[target];
        desc.format.block_copy_size(None).expect("a colour or depth format")
    };
    let mut read = Vec::new();
    if options.readback {
        if graph.has(HDR) && !options.skip_hdr {
            read.push((HDR, texel(&HDR)));
        }
        read.push((OUTPUT, OUTPUT_FORMAT.block_copy_size(None).expect("colour")));
    }
    if options.reads_back() {
        read.extend(graph.exports.iter().map(|t| (*t, texel(t))));
    }
    if options.read_shadow_atlas {
        for (atlas, target) in [(ShadowAtlas::Directional, DIRECTIONAL_ATLAS), (ShadowAtlas::Local, LOCAL_ATLAS)] {
            if plan.shadows.atlas_size(atlas) > 0 {
                read.push((target, texel(&target)));
            }
        }
    }
    read
}
