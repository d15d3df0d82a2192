//! `chiaro view`: a window (winit) with the 3D view and a settings panel (egui on the
//! renderer's own wgpu device). The 3D view is rendered offscreen by the same renderer
//! `chiaro render` uses and shown as an image in the panel's layout, so `--screenshot`
//! writes exactly what `chiaro render` writes for the same scene, camera, settings and
//! size.

mod orbit;
mod panel;

use crate::bake_arg::BakeUseArgs;
use crate::output::{Inputs, check_outputs, output_format, write_group};
use crate::path_arg::PathArgs;
use crate::scene_source::{DemoArgs, choose_view, load_scene, load_settings};
use crate::shadow_args::ShadowArgs;
use anyhow::{Context, Result, anyhow};
use chiaro_render::{FrameOptions, GpuContext, PreparedScene, Renderer, View};
use chiaro_scene::{Scene, Settings};
use clap::Args;
use orbit::Orbit;
use panel::{Debug, PanelState, cameras_panel, lights_panel, settings_panel};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

/// Width of the settings panel, in logical pixels, beside the 3D view.
const PANEL_WIDTH: f32 = 300.0;
/// Side of each shadow atlas as the atlas debug view shows it.
const ATLAS_VIEW_SIZE: usize = 512;
/// The 3D view's texture: what the tone mapper writes, and egui samples.
const VIEW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

#[derive(Args)]
pub struct ViewArgs {
    /// A .gltf or .glb file; without one, the built-in demo scene.
    pub scene: Option<PathBuf>,
    #[arg(long)]
    pub camera: Option<String>,
    #[arg(long)]
    pub settings: Option<PathBuf>,
    /// The 3D view's width in pixels (render.width without it).
    #[arg(long)]
    pub width: Option<u32>,
    /// The 3D view's height in pixels (render.height without it).
    #[arg(long)]
    pub height: Option<u32>,
    /// After --exit-after-frames frames, write the 3D view (no panel) to this PNG or EXR
    /// file, as `chiaro render` would, and exit.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Frames to show before exiting (1 to 100000).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub exit_after_frames: Option<u32>,
    #[command(flatten)]
    pub demo: DemoArgs,
    #[command(flatten)]
    pub shadow: ShadowArgs,
    #[command(flatten)]
    pub path: PathArgs,
    #[command(flatten)]
    pub bake: BakeUseArgs,
}

pub fn run(args: ViewArgs) -> Result<()> {
    if args.screenshot.is_some() && args.exit_after_frames.is_none() {
        return Err(anyhow!("--screenshot needs --exit-after-frames N (the frames to render first)"));
    }
    if let Some(shot) = &args.screenshot {
        output_format(shot)?;
    }
    let mut settings = load_settings(args.settings.as_deref())?;
    args.shadow.apply(&mut settings)?;
    args.path.apply(&mut settings)?;
    let width = args.width.unwrap_or(settings.render.width);
    let height = args.height.unwrap_or(settings.render.height);
    let mut scene = load_scene(args.scene.as_deref(), &args.demo)?;
    args.bake.apply(&mut scene, args.scene.as_deref(), &settings)?;
    let start_view = choose_view(&scene, args.camera.as_deref(), &settings, width, height)?;
    if let Some(shot) = &args.screenshot {
        check_outputs(std::slice::from_ref(shot), &Inputs::new(&scene.inputs, args.settings.as_deref()))?;
    }
    let event_loop = EventLoop::new().context("cannot open a window (no display?)")?;
    let mut app = App {
        args,
        scene,
        settings,
        start_view,
        opening_view: start_view,
        camera: None,
        orbit: None,
        gpu: None,
        failure: None,
        frames: 0,
        frame_intervals: Vec::new(),
        last_frame: None,
        dragging: false,
        last_cursor: None,
        panel: PanelState::default(),
    };
    event_loop.run_app(&mut app).context("the window's event loop failed")?;
    match app.failure {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Everything that lives on the device, made once the window exists.
struct Gpu {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    renderer: Renderer,
    prepared: PreparedScene,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    view_texture: wgpu::Texture,
    view_texture_id: egui::TextureId,
    /// The atlas debug view's images, directional then point/spot.
    atlas_textures: Vec<egui::TextureHandle>,
}

struct App {
    args: ViewArgs,
    scene: Scene,
    settings: Settings,
    start_view: View,
    /// The view the window opened with, for "reset view".
    opening_view: View,
    /// The glTF camera in use, if one was chosen in the viewer.
    camera: Option<usize>,
    orbit: Option<Orbit>,
    gpu: Option<Gpu>,
    failure: Option<anyhow::Error>,
    frames: u32,
    /// Wall time between the ends of consecutive frames, ms.
    frame_intervals: Vec<f64>,
    last_frame: Option<Instant>,
    dragging: bool,
    last_cursor: Option<(f64, f64)>,
    panel: PanelState,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        self.failure.get_or_insert(error);
        event_loop.exit();
    }

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<Gpu> {
        let (w, h) = (self.start_view.width, self.start_view.height);
        let attributes = Window::default_attributes()
            .with_title(format!(
                "chiaro view: {}",
                self.args.scene.as_ref().map_or("demo".into(), |p| p.display().to_string())
            ))
            .with_inner_size(winit::dpi::PhysicalSize::new(w + PANEL_WIDTH as u32, h));
        let window = Arc::new(event_loop.create_window(attributes).context("cannot open a window")?);
        let (ctx, surface) = GpuContext::for_surface(window.clone())?;
        self.args.path.check_device(&ctx, &self.settings, self.args.settings.as_deref())?;
        let format = ctx
            .surface_formats
            .iter()
            .copied()
            .find(|f| !f.is_srgb())
            .or_else(|| ctx.surface_formats.first().copied())
            .ok_or_else(|| anyhow!("the window's surface offers no format on {}", ctx.adapter_info.name))?;
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: wgpu::CompositeAlphaMode::Auto,
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        surface.configure(&ctx.device, &config);
        let view_texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("3D view"),
            size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: VIEW_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let mut egui_renderer = egui_wgpu::Renderer::new(&ctx.device, format, egui_wgpu::RendererOptions::default());
        let view_texture_id = egui_renderer.register_native_texture(
            &ctx.device,
            &view_texture.create_view(&Default::default()),
            wgpu::FilterMode::Nearest,
        );
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(ctx.max_texture_size() as usize),
        );
        let mut renderer = Renderer::new(ctx)?;
        let prepared = renderer.prepare(&self.scene)?;
        Ok(Gpu {
            window,
            surface,
            config,
            renderer,
            prepared,
            egui_ctx,
            egui_state,
            egui_renderer,
            view_texture,
            view_texture_id,
            atlas_textures: Vec::new(),
        })
    }

    /// One frame: the 3D view into its texture, then the panel and the view into the window.
    fn redraw(&mut self) -> Result<()> {
        // A camera chosen in the panel last frame.
        if let Some(camera) = self.panel.camera_request.take() {
            self.use_camera(camera);
        }
        let Some(gpu) = self.gpu.as_mut() else { return Ok(()) };
        let started = Instant::now();
        let orbit = *self.orbit.get_or_insert_with(|| Orbit::from_view(&self.start_view, self.scene.bounds().center()));
        let view = orbit.view(&self.start_view);
        let target = gpu.view_texture.create_view(&Default::default());
        let options = match self.panel.debug {
            Debug::None => FrameOptions::default(),
            Debug::Cascades => FrameOptions { debug_cascades: true, ..Default::default() },
            Debug::View(v) => FrameOptions { debug_view: Some(v), ..Default::default() },
            // Reading the atlases back waits for the frame: a debug view, not a fast one.
            Debug::Atlases => FrameOptions { readback: true, read_shadow_atlas: true, ..Default::default() },
        };
        let frame =
            gpu.renderer.render_to(&self.scene, &gpu.prepared, &view, &self.settings, options, &target, VIEW_FORMAT)?;
        gpu.atlas_textures = frame
            .shadow_atlases
            .iter()
            .map(|atlas| {
                let image = atlas_image(&crate::render::atlas_grey(&atlas.depths), atlas.size as usize);
                gpu.egui_ctx.load_texture(atlas.name, image, egui::TextureOptions::NEAREST)
            })
            .collect();
        self.panel.shadow_tiles = frame.shadow_tiles;
        self.panel.lights_shaded = frame.plan.lights.len();
        if let Some(latest) = gpu.renderer.gpu_times(false)?.pop() {
            self.panel.gpu = Some(latest);
        }

        let input = gpu.egui_state.take_egui_input(&gpu.window);
        let (w, h) = (self.start_view.width as f32, self.start_view.height as f32);
        let mut settings_changed = false;
        let pixels_per_point = gpu.egui_ctx.pixels_per_point();
        let output = gpu.egui_ctx.run_ui(input, |ui| {
            egui::Panel::right("settings").exact_size(PANEL_WIDTH).show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    ui.heading("Camera");
                    let names: Vec<String> = self.scene.cameras.iter().map(|c| c.name.clone()).collect();
                    cameras_panel(ui, &names, &mut self.panel);
                    settings_changed |= settings_panel(ui, &mut self.settings, &mut self.panel);
                    ui.separator();
                    ui.heading("Lights");
                    lights_panel(ui, &mut self.scene.lights, &mut self.panel);
                });
            });
            egui::CentralPanel::no_frame().show(ui, |ui| {
                if self.panel.debug == Debug::Atlases {
                    ui.horizontal(|ui| {
                        for texture in &gpu.atlas_textures {
                            let side = (w / 2.0).min(h) / pixels_per_point;
                            ui.image(egui::load::SizedTexture::new(texture.id(), egui::vec2(side, side)));
                        }
                    });
                    if gpu.atlas_textures.is_empty() {
                        ui.label("No light casts a shadow.");
                    }
                } else {
                    ui.image(egui::load::SizedTexture::new(
                        gpu.view_texture_id,
                        egui::vec2(w / pixels_per_point, h / pixels_per_point),
                    ));
                }
            });
        });
        gpu.egui_state.handle_platform_output(&gpu.window, output.platform_output);
        if std::mem::take(&mut self.panel.save_requested) {
            let path = self.args.settings.clone().unwrap_or_else(|| PathBuf::from("chiaro-view.toml"));
            self.panel.saved = Some(match save_settings(&path, &self.settings) {
                Ok(()) => format!("saved {}", path.display()),
                Err(e) => format!("not saved: {e:#}"),
            });
        }
        if settings_changed && let Err(e) = self.args.path.check_device(&gpu.renderer.ctx, &self.settings, None) {
            self.panel.error = Some(e.to_string());
            self.settings.render.msaa = 1;
        }
        let jobs = gpu.egui_ctx.tessellate(output.shapes, output.pixels_per_point);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [gpu.config.width, gpu.config.height],
            pixels_per_point: output.pixels_per_point,
        };
        let device = &gpu.renderer.ctx.device;
        let queue = &gpu.renderer.ctx.queue;
        for (id, deltas) in &output.textures_delta.set {
            for delta in deltas {
                gpu.egui_renderer.update_texture(device, queue, *id, delta);
            }
        }
        let surface_texture = match gpu.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            other => {
                // Lost or outdated: configure again and draw next time.
                tracing::debug!("surface: {other:?}");
                gpu.surface.configure(device, &gpu.config);
                return Ok(());
            }
        };
        let surface_view = surface_texture.texture.create_view(&Default::default());
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("panel") });
        let commands = gpu.egui_renderer.update_buffers(device, queue, &mut encoder, &jobs, &screen);
        {
            let mut pass = encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("panel"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &surface_view,
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
        queue.submit(commands.into_iter().chain([encoder.finish()]));
        queue.present(surface_texture);
        for id in &output.textures_delta.free {
            gpu.egui_renderer.free_texture(id);
        }
        self.panel.cpu_frame_ms = started.elapsed().as_secs_f64() * 1e3;
        self.frames += 1;
        let now = Instant::now();
        if let Some(last) = self.last_frame.replace(now) {
            self.frame_intervals.push((now - last).as_secs_f64() * 1e3);
        }
        Ok(())
    }

    /// Starts the view again from glTF camera `index`, or from the view it opened with.
    fn use_camera(&mut self, index: Option<usize>) {
        let (w, h) = (self.start_view.width, self.start_view.height);
        self.start_view = match index {
            Some(i) if i < self.scene.cameras.len() => View::from_camera(&self.scene, i, w, h),
            _ => self.opening_view,
        };
        self.camera = index;
        self.orbit = None;
    }

    /// Writes the 3D view as `chiaro render` would: the same renderer, view and settings.
    fn screenshot(&mut self, path: &std::path::Path) -> Result<()> {
        let gpu = self.gpu.as_mut().ok_or_else(|| anyhow!("no frame was rendered"))?;
        let view = self.orbit.map_or(self.start_view, |o| o.view(&self.start_view));
        let options = FrameOptions { readback: true, ..Default::default() };
        let frame = gpu.renderer.render(&self.scene, &gpu.prepared, &view, &self.settings, options)?;
        let (width, height) = (view.width, view.height);
        let rgb: Vec<[f32; 3]> = frame.hdr.iter().map(|p| [p[0], p[1], p[2]]).collect();
        let image = output_format(path)?.frame_image(width, height, &frame.ldr, &rgb);
        write_group(vec![(path.to_path_buf(), image)])?;
        eprintln!("chiaro: wrote {} ({width}x{height}) after {} frames", path.display(), self.frames);
        Ok(())
    }
}

/// An atlas's grey RGBA8 image (`size` texels a side), sampled down to
/// `ATLAS_VIEW_SIZE` for the panel.
fn atlas_image(grey: &[u8], size: usize) -> egui::ColorImage {
    let side = size.min(ATLAS_VIEW_SIZE);
    let step = size / side;
    let pixels = (0..side * side)
        .map(|k| {
            let (x, y) = ((k % side) * step, (k / side) * step);
            let v = grey[(y * size + x) * 4];
            egui::Color32::from_gray(v)
        })
        .collect();
    egui::ColorImage { size: [side, side], pixels, source_size: egui::vec2(side as f32, side as f32) }
}

/// Writes `settings` as TOML to `path`, whole or not at all (a temporary file renamed
/// over it), so that `chiaro render --settings path` renders what the viewer showed.
fn save_settings(path: &std::path::Path, settings: &Settings) -> Result<()> {
    use std::io::Write;
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(std::path::Path::new("."));
    let mut file = tempfile::NamedTempFile::new_in(dir).with_context(|| format!("{}", dir.display()))?;
    file.write_all(settings.to_toml().as_bytes()).with_context(|| format!("{}", path.display()))?;
    file.persist(path).with_context(|| format!("{}", path.display()))?;
    Ok(())
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gpu.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(gpu) => {
                gpu.window.request_redraw();
                self.gpu = Some(gpu);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(gpu) = self.gpu.as_mut() else { return };
        let consumed = gpu.egui_state.on_window_event(&gpu.window, &event).consumed;
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                gpu.config.width = size.width.max(1);
                gpu.config.height = size.height.max(1);
                gpu.surface.configure(&gpu.renderer.ctx.device, &gpu.config);
            }
            WindowEvent::MouseInput { state, button: MouseButton::Left, .. } => {
                self.dragging = state == ElementState::Pressed && !consumed && !gpu.egui_ctx.is_pointer_over_egui();
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let (true, Some((x, y)), Some(orbit)) = (self.dragging, self.last_cursor, self.orbit.as_mut()) {
                    orbit.drag((position.x - x) as f32, (position.y - y) as f32);
                }
                self.last_cursor = Some((position.x, position.y));
            }
            WindowEvent::MouseWheel { delta, .. } if !gpu.egui_ctx.is_pointer_over_egui() => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                if let Some(orbit) = self.orbit.as_mut() {
                    orbit.zoom(steps);
                }
            }
            WindowEvent::KeyboardInput { event, .. }
                if event.state == ElementState::Pressed && !gpu.egui_ctx.egui_wants_keyboard_input() =>
            {
                match event.logical_key.as_ref() {
                    Key::Character("r") => self.use_camera(None),
                    Key::Character("c") if !self.scene.cameras.is_empty() => {
                        let next = self.camera.map_or(0, |i| (i + 1) % self.scene.cameras.len());
                        self.use_camera(Some(next));
                    }
                    Key::Character("p") => {
                        let path = PathBuf::from("chiaro-view.png");
                        self.panel.saved = Some(match self.screenshot(&path) {
                            Ok(()) => format!("wrote {}", path.display()),
                            Err(e) => format!("no screenshot: {e:#}"),
                        });
                    }
                    Key::Named(NamedKey::Escape) => event_loop.exit(),
                    _ => {}
                }
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw() {
                    return self.fail(event_loop, e);
                }
                if let Some(n) = self.args.exit_after_frames
                    && self.frames >= n
                {
                    if let Some(path) = self.args.screenshot.clone()
                        && let Err(e) = self.screenshot(&path)
                    {
                        return self.fail(event_loop, e);
                    }
                    let mut intervals = self.frame_intervals.clone();
                    intervals.sort_by(f64::total_cmp);
                    if let Some(median) = intervals.get(intervals.len() / 2) {
                        eprintln!("chiaro: {} frames shown, median {median:.1} ms a frame", self.frames);
                    }
                    event_loop.exit();
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        // A real-time view: draw again as soon as the last frame is done.
        if let Some(gpu) = &self.gpu {
            gpu.window.request_redraw();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn saved_settings_read_back_equal() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("viewer.toml");
        let mut settings = Settings::default();
        settings.shadows.max_distance = 42.0;
        settings.lights.culling = chiaro_scene::LightCulling::PerObject;
        save_settings(&path, &settings).unwrap();
        assert_eq!(load_settings(Some(&path)).unwrap(), settings);
    }

    #[test]
    fn atlas_images_are_sampled_down_to_the_view_size() {
        // A 1024-texel atlas, dark in its left half.
        let size = 1024;
        let grey: Vec<u8> =
            (0..size * size).flat_map(|k| if k % size < size / 2 { [0u8; 4] } else { [255; 4] }).collect();
        let image = atlas_image(&grey, size);
        assert_eq!(image.size, [ATLAS_VIEW_SIZE, ATLAS_VIEW_SIZE]);
        assert_eq!(image.pixels[0], egui::Color32::from_gray(0));
        assert_eq!(image.pixels[ATLAS_VIEW_SIZE - 1], egui::Color32::from_gray(255));
        // A small atlas is shown as it is.
        assert_eq!(atlas_image(&[9; 4 * 16], 4).size, [4, 4]);
    }
}
