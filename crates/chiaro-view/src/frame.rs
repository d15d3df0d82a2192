//! One frame of the window: the jobs' news and the fly keys as actions, the 3D view
//! rendered into its texture, the debug view's images, the panel drawn by egui when
//! something in it changed (its actions applied), and both composed into the surface.

use crate::action::{Action, FrameReport};
use crate::apply::FRAME_FAILED;
use crate::debug_images::{frame_images, shows_view};
use crate::gpu::Gpu;
use crate::light_shapes::area_light_lines;
use crate::panel::{self, ViewArea};
use crate::state::{FrameSample, Selection, ViewerState};
use crate::viewer::Viewer;
use anyhow::Result;
use chiaro_render::{DebugView, FrameOutput};
use std::time::{Duration, Instant};

/// How often the panel's numbers are brought up to date when nothing else redraws it:
/// after this long and this many frames. A lavapipe choice: drawing the panel costs a
/// software device a good share of a heavy frame (docs/performance.md).
const PANEL_REFRESH: Duration = Duration::from_secs(1);
/// See `PANEL_REFRESH`.
const PANEL_REFRESH_FRAMES: u32 = 10;

/// When egui draws the panel again.
pub struct PanelSchedule {
    /// Something the panel shows changed: egui draws it again this frame.
    pub dirty: bool,
    /// When the panel was last drawn, and at which frame.
    pub drawn: Option<(Instant, u32)>,
    /// When egui asked to be run again (animations, tooltips).
    pub egui_repaint_at: Option<Instant>,
}

impl Default for PanelSchedule {
    fn default() -> Self {
        PanelSchedule { dirty: true, drawn: None, egui_repaint_at: None }
    }
}

impl PanelSchedule {
    /// Whether this frame draws the panel (always, where nothing composes it).
    fn due(&self, frames: u32, composed: bool) -> bool {
        let refresh_due =
            self.drawn.is_none_or(|(t, frame)| t.elapsed() >= PANEL_REFRESH && frames >= frame + PANEL_REFRESH_FRAMES);
        let egui_due = self.egui_repaint_at.is_some_and(|t| Instant::now() >= t);
        !composed || self.dirty || refresh_due || egui_due
    }
}

impl Viewer {
    /// One frame: the 3D view into its texture, the panel if it changed, then both into
    /// the window.
    pub(crate) fn redraw(&mut self) -> Result<()> {
        let pending = std::mem::take(&mut self.pending);
        self.apply_all(pending);
        let news = self.job_news();
        self.apply_all(news);
        let now = Instant::now();
        let seconds = self.last_frame.map_or(0.0, |t| (now - t).as_secs_f32());
        let fly = self.input.fly(self.state.camera.navigation, seconds);
        self.apply_all(fly);
        let timeline = self.state.timeline;
        if let Some(duration) = self.state.scene.scene.animation_duration().filter(|_| timeline.playing) {
            self.apply(Action::SetTime(Some(timeline.advanced(seconds, duration))));
        }
        self.render_frame()?;
        let now = Instant::now();
        let interval_ms = self.last_frame.replace(now).map(|last| (now - last).as_secs_f64() * 1e3);
        self.apply(Action::FrameShown { interval_ms });
        Ok(())
    }

    /// What the jobs have to say: a changed file to reload, a scene read, a comparison
    /// finished.
    fn job_news(&mut self) -> Vec<Action> {
        let jobs = &mut self.state.jobs;
        let mut news = Vec::new();
        if self.state.scene.path.is_some() && jobs.loader.changed() {
            news.push(Action::Reload);
        }
        news.extend(jobs.loader.poll().map(|loaded| Action::SceneLoaded(Box::new(loaded))));
        news.extend(jobs.reference.poll().map(|done| Action::ComparisonDone(done.map(Box::new))));
        news
    }

    fn render_frame(&mut self) -> Result<()> {
        let Some(gpu) = self.gpu.as_mut() else { return Ok(()) };
        let debug = self.state.debug;
        // Images belong to the debug view that made them.
        if gpu.debug_textures_for != debug {
            gpu.debug_textures.clear();
            gpu.debug_textures_for = debug;
        }
        let rendered = render_view(gpu, &self.state);
        let report = match rendered {
            Ok(frame) => {
                if set_debug_textures(gpu, &self.state, &frame) {
                    self.panel.dirty = true;
                }
                Action::FrameRendered(Box::new(frame_report(gpu, &self.state, &frame)?))
            }
            Err(e) => Action::FrameFailed(format!("{FRAME_FAILED}: {e}")),
        };
        self.apply(report);
        let Some(gpu) = self.gpu.as_mut() else { return Ok(()) };
        if debug == Some(DebugView::Reference)
            && gpu.debug_textures.is_empty()
            && let Some(d) = &self.state.jobs.disagreement
        {
            let image = egui::ColorImage::from_rgba_unmultiplied([d.width, d.height], &d.overlay);
            gpu.debug_textures = vec![gpu.egui_ctx.load_texture("disagreement", image, egui::TextureOptions::NEAREST)];
            self.panel.dirty = true;
        }
        self.present()
    }

    /// Draws the panel if it is due and copies it and the view into the window.
    fn present(&mut self) -> Result<()> {
        let Some(gpu) = self.gpu.as_mut() else { return Ok(()) };
        let show_view = shows_view(self.state.debug, self.state.jobs.disagreement.is_some());
        let draw_panel = self.panel.due(self.state.stats.frames, gpu.compositor.is_some());
        let surface_texture = match gpu.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            other => {
                // Lost or outdated: configure again and draw next time.
                tracing::debug!("surface: {other:?}");
                gpu.surface.configure(&gpu.renderer.ctx.device, &gpu.config);
                return Ok(());
            }
        };
        let device = gpu.renderer.ctx.device.clone();
        let queue = gpu.renderer.ctx.queue.clone();
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("window") });
        let mut commands = Vec::new();
        if draw_panel {
            let actions;
            (commands, actions) = self.draw_panel(&mut encoder, &surface_texture.texture, show_view);
            self.apply_all(actions);
        }
        let Some(gpu) = self.gpu.as_mut() else { return Ok(()) };
        if let Some(compositor) = &gpu.compositor {
            let view = show_view.then_some((&gpu.view_texture, gpu.view_origin, gpu.view_limit));
            compositor.compose(&mut encoder, &surface_texture.texture, view);
        }
        queue.submit(commands.into_iter().chain([encoder.finish()]));
        queue.present(surface_texture);
        Ok(())
    }

    /// Runs egui over the panel and records its drawing; returns egui's command buffers
    /// and the panel's actions.
    fn draw_panel(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        surface: &wgpu::Texture,
        show_view: bool,
    ) -> (Vec<wgpu::CommandBuffer>, Vec<Action>) {
        let Some(gpu) = self.gpu.as_mut() else { return (Vec::new(), Vec::new()) };
        let input = gpu.egui_state.take_egui_input(&gpu.window);
        let area = ViewArea {
            size_px: self.state.camera.view_size(),
            show_view,
            composed: gpu.compositor.is_some(),
            view_texture: gpu.view_texture_id,
            images: gpu.debug_textures.iter().map(|t| (t.id(), t.size_vec2())).collect(),
        };
        let run = panel::run(&gpu.egui_ctx, input, &self.state, &area);
        let output = run.output;
        gpu.egui_state.handle_platform_output(&gpu.window, output.platform_output.clone());
        if let Some((origin, limit)) = run.view_pixels {
            gpu.view_origin = origin;
            gpu.view_limit = limit;
        }
        let delay = output.viewport_output.get(&egui::ViewportId::ROOT).map(|v| v.repaint_delay);
        self.panel.egui_repaint_at = delay.filter(|d| *d < Duration::from_secs(3600)).map(|d| Instant::now() + d);
        self.panel.dirty = false;
        self.panel.drawn = Some((Instant::now(), self.state.stats.frames));
        self.state.stats.panel_draws += 1;
        let commands = record_egui(gpu, encoder, surface, output);
        (commands, run.actions)
    }
}

/// Renders the current view into the view texture, and the area lights' outlines over it.
fn render_view(gpu: &mut Gpu, state: &ViewerState) -> Result<FrameOutput, chiaro_render::RenderError> {
    let target = gpu.view_texture.create_view(&Default::default());
    let view = state.current_view();
    let (scene, settings) = (&state.scene.scene, &state.settings.current);
    let frame = gpu.renderer.render_to(
        scene,
        &gpu.prepared,
        &view,
        settings,
        state.frame_options(),
        &target,
        gpu.view_format,
    )?;
    let lights = &state.panel.lights;
    if !lights.shapes_hidden {
        let selected = match lights.selected {
            Some(Selection::Light(i)) => Some(i),
            _ => None,
        };
        let lines = area_light_lines(&scene.lights, &view, selected);
        let ctx = &gpu.renderer.ctx;
        gpu.light_overlay.draw(&ctx.device, &ctx.queue, &target, &lines);
    }
    Ok(frame)
}

/// The debug view's images of `frame` as egui textures; returns whether the panel must
/// be drawn again to show them.
fn set_debug_textures(gpu: &mut Gpu, state: &ViewerState, frame: &FrameOutput) -> bool {
    let debug = state.debug;
    if matches!(debug, Some(DebugView::Reference)) {
        return false;
    }
    gpu.debug_textures = frame_images(debug, frame, &state.scene.scene)
        .into_iter()
        .enumerate()
        .map(|(i, (size, pixels))| {
            let image = egui::ColorImage::from_rgba_unmultiplied(size, pixels.as_flattened());
            gpu.egui_ctx.load_texture(format!("debug {i}"), image, egui::TextureOptions::NEAREST)
        })
        .collect();
    !shows_view(debug, false)
}

/// What the frame tells the panel.
fn frame_report(gpu: &mut Gpu, state: &ViewerState, frame: &FrameOutput) -> Result<FrameReport> {
    Ok(FrameReport {
        shadow_tiles: frame.shadow_tiles,
        lights_shaded: frame.plan.lights.len(),
        tiles: panel::lights::tiles_by_light(&frame.plan, state.scene.scene.lights.len()),
        gpu_times: gpu.renderer.gpu_times(false)?,
        sample: FrameSample { cpu_ms: frame.timings.cpu_prepare_ms, passes: Vec::new(), interval_ms: None },
    })
}

/// Records egui's drawing of the panel: into the compositor's panel texture, or straight
/// into the surface where nothing composes the window.
fn record_egui(
    gpu: &mut Gpu,
    encoder: &mut wgpu::CommandEncoder,
    surface: &wgpu::Texture,
    output: egui::FullOutput,
) -> Vec<wgpu::CommandBuffer> {
    let device = gpu.renderer.ctx.device.clone();
    let queue = gpu.renderer.ctx.queue.clone();
    let jobs = gpu.egui_ctx.tessellate(output.shapes, output.pixels_per_point);
    let screen = egui_wgpu::ScreenDescriptor {
        size_in_pixels: [gpu.config.width, gpu.config.height],
        pixels_per_point: output.pixels_per_point,
    };
    for (id, deltas) in &output.textures_delta.set {
        for delta in deltas {
            gpu.egui_renderer.update_texture(&device, &queue, *id, delta);
        }
    }
    let commands = gpu.egui_renderer.update_buffers(&device, &queue, encoder, &jobs, &screen);
    let panel_target = match &gpu.compositor {
        Some(c) => c.panel_target(),
        None => surface.create_view(&Default::default()),
    };
    {
        let mut pass = encoder
            .begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("panel"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &panel_target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            })
            .forget_lifetime();
        gpu.egui_renderer.render(&mut pass, &jobs, &screen);
    }
    for id in &output.textures_delta.free {
        gpu.egui_renderer.free_texture(id);
    }
    commands
}
