//! `chiaro view`: a window (winit) with the 3D view and a settings panel (egui on the
//! renderer's own wgpu device). The 3D view is rendered offscreen by the same renderer
//! `chiaro render` uses and copied into the window beside the panel, so `--screenshot`
//! writes exactly what `chiaro render` writes for the same scene, camera, settings and
//! size, and the window costs little more than the frame itself.

mod camera;
mod debug_images;
mod lights_panel;
mod loader;
mod panel;
#[cfg(test)]
mod panel_tests;
mod pick;
mod present;
mod reference;
mod save_scene;
mod settings_panel;

use crate::bake_arg::BakeUseArgs;
use crate::output::{Inputs, check_outputs, output_format, write_group};
use crate::path_arg::PathArgs;
use crate::scene_source::{DemoArgs, choose_view, load_scene, load_settings};
use crate::shadow_args::ShadowArgs;
use anyhow::{Context, Result, anyhow};
use camera::{CameraRig, Navigation};
use chiaro_render::{AovView, DebugView, FrameOptions, FrameOutput, GpuContext, PreparedScene, Renderer, View};
use chiaro_scene::{LightKind, Scene, Settings};
use clap::Args;
use glam::Vec3;
use lights_panel::Selection;
use loader::Loader;
use panel::{FrameSample, PanelState};
use pick::Picker;
use present::Compositor;
use reference::{Disagreement, ReferenceJob};
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key, KeyCode, NamedKey, PhysicalKey};
use winit::window::{Window, WindowId};

/// Width of the settings panel, in logical pixels, beside the 3D view.
const PANEL_WIDTH: f32 = 340.0;
/// Side of each shadow atlas as the atlas debug view shows it.
const ATLAS_VIEW_SIZE: usize = 512;
/// How often the panel's numbers are brought up to date when nothing else redraws it:
/// after this long and this many frames (drawing the panel costs a software device as
/// much as a tenth of a heavy frame).
const PANEL_REFRESH: Duration = Duration::from_secs(1);
const PANEL_REFRESH_FRAMES: u32 = 10;
/// The window's size for a `w` x `h` view: the panel is PANEL_WIDTH logical pixels.
fn window_size(w: u32, h: u32, scale_factor: f64) -> winit::dpi::PhysicalSize<u32> {
    winit::dpi::PhysicalSize::new(w + (f64::from(PANEL_WIDTH) * scale_factor).ceil() as u32, h)
}

/// How a frame the renderer refused is reported in the panel.
const FRAME_FAILED: &str = "frame not rendered";
/// Fly speed, in scene radii per second (x4 with Shift).
const FLY_SPEED: f32 = 0.4;

/// `--debug`'s value: a debug view, or none (a newtype, since clap reads a nested
/// `Option` as an optional value).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DebugArg(pub Option<DebugView>);

#[derive(Args)]
pub struct ViewArgs {
    /// A .gltf or .glb file; without one, the built-in demo scene.
    pub scene: Option<PathBuf>,
    /// The glTF camera to open with, by name or index (the first, or a framing camera,
    /// without it).
    #[arg(long)]
    pub camera: Option<String>,
    /// settings.toml to open with; "Save settings" writes back to it.
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
    /// After --exit-after-frames frames, write the whole window (3D view and panel) as the
    /// screen shows it to this PNG file, and exit.
    #[arg(long)]
    pub screenshot_window: Option<PathBuf>,
    /// The debug view to open with: none, cascades, gbuffer-albedo, gbuffer-normal,
    /// light-overdraw, aov-position, aov-normal, aov-depth, aov-lightmap, clusters,
    /// shadow-atlases, reference (compared at once). With --screenshot, cascades and the
    /// G-buffer and overdraw views are written as `chiaro render --debug` writes them.
    #[arg(long, value_parser = |text: &str| panel::parse_debug(text).map(DebugArg))]
    pub debug: Option<DebugArg>,
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
    if (args.screenshot.is_some() || args.screenshot_window.is_some()) && args.exit_after_frames.is_none() {
        return Err(anyhow!("--screenshot needs --exit-after-frames N (the frames to render first)"));
    }
    if let Some(shot) = &args.screenshot {
        output_format(shot)?;
    }
    if let Some(shot) = &args.screenshot_window
        && !matches!(output_format(shot)?, crate::output::OutputFormat::Png)
    {
        return Err(anyhow!("--screenshot-window {}: the window is written as PNG only", shot.display()));
    }
    let mut settings = load_settings(args.settings.as_deref())?;
    args.shadow.apply(&mut settings)?;
    args.path.apply(&mut settings)?;
    // The view's size is render.width and height, so that saved settings keep it.
    settings.render.width = args.width.unwrap_or(settings.render.width);
    settings.render.height = args.height.unwrap_or(settings.render.height);
    settings.validate().map_err(|e| anyhow!("--width/--height: {e}"))?;
    let (width, height) = (settings.render.width, settings.render.height);
    let mut scene = load_scene(args.scene.as_deref(), &args.demo)?;
    args.bake.apply(&mut scene, args.scene.as_deref(), &settings)?;
    let start_view = choose_view(&scene, args.camera.as_deref(), &settings, width, height)?;
    let shots: Vec<PathBuf> = args.screenshot.iter().chain(&args.screenshot_window).cloned().collect();
    check_outputs(&shots, &Inputs::new(&scene.inputs, args.settings.as_deref()))?;
    let event_loop = EventLoop::new().context("cannot open a window (no display?)")?;
    let mut loader = Loader::new(args.demo.clone(), args.bake.clone());
    loader.watch(&scene);
    let panel = PanelState {
        debug: args.debug.and_then(|d| d.0),
        compare_requested: args.debug == Some(DebugArg(Some(DebugView::Reference))),
        ..Default::default()
    };
    let mut app = App {
        scene_path: args.scene.clone(),
        camera_key: args.camera.clone(),
        view_settings: (width, height, settings.camera.auto_yfov_deg),
        args,
        scene,
        settings,
        start_view,
        opening_view: start_view,
        camera: None,
        rig: None,
        gpu: None,
        failure: None,
        frames: 0,
        frame_intervals: Vec::new(),
        gpu_frame_ms: Vec::new(),
        last_frame: None,
        dragging: false,
        pressed_at: None,
        picker: Picker::default(),
        cursor: None,
        keys: HashSet::new(),
        panel,
        panel_dirty: true,
        panel_drawn: None,
        panel_draws: 0,
        egui_repaint_at: None,
        loader,
        reference: ReferenceJob::default(),
        disagreement: None,
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
    /// The 3D view: the surface's format with sRGB encoding, so that it copies into the
    /// surface as it is.
    view_texture: wgpu::Texture,
    view_format: wgpu::TextureFormat,
    /// The 3D view as egui sees it, where egui draws it (no compositor).
    view_texture_id: egui::TextureId,
    /// Copies the panel and the view into the window; `None` where the surface takes no
    /// copies, and egui draws everything every frame.
    compositor: Option<Compositor>,
    /// Images a debug view shows in place of the 3D view, and the view they belong to.
    debug_textures: Vec<egui::TextureHandle>,
    debug_textures_for: Option<DebugView>,
    /// The 3D view's top-left corner in the window, in physical pixels.
    view_origin: [u32; 2],
    /// Where the panel begins (and the window ends below): the view is cut there.
    view_limit: [u32; 2],
}

struct App {
    args: ViewArgs,
    scene: Scene,
    /// The file the scene came from (`None`: the demo).
    scene_path: Option<PathBuf>,
    settings: Settings,
    /// The view the rig starts from: the chosen camera's, at the view's size.
    start_view: View,
    /// The view the window opened with, for "reset view".
    opening_view: View,
    /// The glTF camera in use, if one was chosen in the viewer.
    camera: Option<usize>,
    /// `--camera`, while the file it names is open.
    camera_key: Option<String>,
    /// The view's size and automatic field of view the start view was made for.
    view_settings: (u32, u32, f32),
    rig: Option<CameraRig>,
    gpu: Option<Gpu>,
    failure: Option<anyhow::Error>,
    frames: u32,
    /// Wall time between the ends of consecutive frames, ms.
    frame_intervals: Vec<f64>,
    /// GPU time of each frame whose timestamps came back, ms.
    gpu_frame_ms: Vec<f64>,
    last_frame: Option<Instant>,
    dragging: bool,
    /// Where the left button went down in the view: released near it, it is a click.
    pressed_at: Option<(f64, f64)>,
    picker: Picker,
    /// Last cursor position, physical pixels.
    cursor: Option<(f64, f64)>,
    /// Keys held down (fly movement).
    keys: HashSet<KeyCode>,
    panel: PanelState,
    /// Something the panel shows changed: egui draws it again this frame.
    panel_dirty: bool,
    /// When the panel was last drawn, and at which frame.
    panel_drawn: Option<(Instant, u32)>,
    /// Frames on which egui drew the panel.
    panel_draws: u32,
    /// When egui asked to be run again (animations, tooltips).
    egui_repaint_at: Option<Instant>,
    loader: Loader,
    reference: ReferenceJob,
    disagreement: Option<Disagreement>,
}

fn view_texture(device: &wgpu::Device, format: wgpu::TextureFormat, width: u32, height: u32) -> wgpu::Texture {
    use wgpu::TextureUsages as U;
    let usage = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC;
    present::window_texture(device, "3D view", format, (width, height), usage)
}

/// What a frame shows in place of the lit 3D view, as images egui draws.
fn debug_images(debug: Option<DebugView>, frame: &FrameOutput, scene: &Scene) -> Vec<([usize; 2], Vec<[u8; 4]>)> {
    let size = [frame.width as usize, frame.height as usize];
    let aovs = frame.aovs.as_ref();
    let image = |pixels: Vec<[u8; 4]>| vec![(size, pixels)];
    match debug {
        Some(DebugView::ShadowAtlases) => frame
            .shadow_atlases
            .iter()
            .map(|atlas| {
                let grey = crate::render::atlas_grey(&atlas.depths);
                let (side, pixels) = debug_images::atlas_image(&grey, atlas.size as usize, ATLAS_VIEW_SIZE);
                ([side, side], pixels)
            })
            .collect(),
        Some(DebugView::Aov(aov)) => {
            let Some(a) = aovs else { return Vec::new() };
            match aov {
                AovView::Position => image(debug_images::position_image(&a.position_ws, &scene.bounds())),
                AovView::Normal => image(debug_images::normal_image(&a.normal_ws, &a.depth)),
                AovView::Depth => image(debug_images::depth_image(&a.depth)),
                AovView::Lightmap => image(debug_images::lightmap_image(&a.baked_irradiance, &a.depth)),
                AovView::Shadow(i) => match frame.shadow_aovs.get(i) {
                    Some(shadow) => image(debug_images::shadow_image(shadow, &a.depth)),
                    None => Vec::new(),
                },
            }
        }
        Some(DebugView::Clusters) => match (aovs, &frame.plan.culled.grid) {
            (Some(a), Some(grid)) => {
                let most = (frame.plan.lights.len() as u32).clamp(1, 32);
                image(debug_images::cluster_image(grid, &frame.plan.culled.lists, &a.depth, most))
            }
            _ => Vec::new(),
        },
        _ => Vec::new(),
    }
}

/// What the frame renders and reads back for the view shown.
fn frame_options(debug: Option<DebugView>) -> FrameOptions {
    debug.map_or_else(FrameOptions::default, DebugView::frame_options)
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        self.failure.get_or_insert(error);
        event_loop.exit();
    }

    fn title(&self) -> String {
        format!("chiaro view: {}", self.scene_path.as_ref().map_or("demo".into(), |p| p.display().to_string()))
    }

    fn view_size(&self) -> (u32, u32) {
        (self.start_view.width, self.start_view.height)
    }

    fn view_texture_size(&self) -> (u32, u32) {
        self.gpu.as_ref().map_or(self.view_size(), |g| (g.view_texture.width(), g.view_texture.height()))
    }

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<Gpu> {
        let (w, h) = self.view_size();
        let attributes = Window::default_attributes().with_title(self.title()).with_inner_size(window_size(w, h, 1.0));
        let window = Arc::new(event_loop.create_window(attributes).context("cannot open a window")?);
        if window.scale_factor() != 1.0 {
            let _ = window.request_inner_size(window_size(w, h, window.scale_factor()));
        }
        let (ctx, surface) = GpuContext::for_surface(window.clone())?;
        self.args.path.check_device(&ctx, &self.settings, self.args.settings.as_deref())?;
        let format = ctx
            .surface_formats
            .iter()
            .copied()
            .find(|f| !f.is_srgb() && f.add_srgb_suffix().is_srgb())
            .or_else(|| ctx.surface_formats.first().copied())
            .ok_or_else(|| anyhow!("the window's surface offers no format on {}", ctx.adapter_info.name))?;
        let copies = Compositor::supported(ctx.surface_usages);
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | if copies { wgpu::TextureUsages::COPY_DST } else { wgpu::TextureUsages::empty() },
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
        let view_format = format.add_srgb_suffix();
        let view_texture = view_texture(&ctx.device, view_format, w, h);
        let compositor = copies.then(|| Compositor::new(&ctx.device, format, config.width, config.height));
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
            view_format,
            view_texture_id,
            compositor,
            debug_textures: Vec::new(),
            debug_textures_for: None,
            view_origin: [0, 0],
            view_limit: [w, h],
        })
    }

    /// The view of glTF camera `camera` (or the one the viewer opened with) at `w` x `h`.
    fn base_view(&self, camera: Option<usize>, w: u32, h: u32) -> Result<View> {
        match camera {
            Some(i) if i < self.scene.cameras.len() => Ok(View::from_camera(&self.scene, i, w, h)),
            _ => choose_view(&self.scene, self.camera_key.as_deref(), &self.settings, w, h),
        }
    }

    /// Starts the view again from glTF camera `index`, or from the view it opened with.
    fn use_camera(&mut self, index: Option<usize>) {
        let (w, h) = self.view_size();
        self.start_view = match index {
            Some(i) if i < self.scene.cameras.len() => View::from_camera(&self.scene, i, w, h),
            _ => self.opening_view,
        };
        self.camera = index;
        self.rig = None;
    }

    fn rig(&mut self) -> &mut CameraRig {
        let (start, center) = (self.start_view, self.scene.bounds().center());
        self.rig.get_or_insert_with(|| CameraRig::from_view(&start, center))
    }

    fn current_view(&self) -> View {
        self.rig.map_or(self.start_view, |r| r.view(&self.start_view, self.scene.bounds().bounding_sphere()))
    }

    /// Looks at the selected light (its range, at most the scene's size), or the whole
    /// scene.
    fn frame_selected(&mut self) {
        let scene_sphere = self.scene.bounds().bounding_sphere();
        let (center, radius) = match self.panel.lights.selected {
            Some(Selection::Light(i)) if self.scene.lights.get(i).is_some_and(|l| l.kind != LightKind::Directional) => {
                let light = &self.scene.lights[i];
                let reach = light.range.unwrap_or(scene_sphere.radius).min(scene_sphere.radius);
                (light.position(), reach.max(0.05))
            }
            Some(Selection::Object(i)) if i < self.scene.instances.len() => {
                let sphere = pick::instance_bounds(&self.scene, i).bounding_sphere();
                (sphere.center, sphere.radius.max(0.05))
            }
            _ => (scene_sphere.center, scene_sphere.radius),
        };
        let yfov = self.start_view.yfov_rad;
        self.rig().frame(center, radius, yfov);
    }

    /// Moves a flying camera by the keys held, for `seconds` since the last frame.
    fn fly(&mut self, seconds: f32) {
        if self.panel.navigation != Navigation::Fly || self.keys.is_empty() {
            return;
        }
        let held = |k: KeyCode| if self.keys.contains(&k) { 1.0 } else { 0.0 };
        let input = Vec3::new(
            held(KeyCode::KeyD) - held(KeyCode::KeyA),
            held(KeyCode::KeyE) - held(KeyCode::KeyQ),
            held(KeyCode::KeyS) - held(KeyCode::KeyW),
        );
        let fast =
            if self.keys.contains(&KeyCode::ShiftLeft) || self.keys.contains(&KeyCode::ShiftRight) { 4.0 } else { 1.0 };
        let metres = FLY_SPEED * fast * self.scene.bounds().bounding_sphere().radius * seconds.min(0.25);
        self.rig().fly(input, metres);
    }

    /// A scene read by the loader: shown if it loads, else its error in the panel.
    fn take_loaded(&mut self) {
        let Some(loaded) = self.loader.poll() else { return };
        self.panel_dirty = true;
        let scene = match loaded.scene {
            Ok(scene) => scene,
            Err(e) => {
                self.panel.error = Some(format!("{e:#}"));
                return;
            }
        };
        let Some(gpu) = self.gpu.as_mut() else { return };
        let prepared = match gpu.renderer.prepare(&scene) {
            Ok(p) => p,
            Err(e) => {
                self.panel.error = Some(format!("{}: {e}", loaded.path.display()));
                return;
            }
        };
        let old = std::mem::replace(&mut self.scene, scene);
        gpu.prepared = prepared;
        gpu.debug_textures.clear();
        self.picker.reset();
        // The light list shows the file's lights as they now are.
        self.panel.lights = Default::default();
        // A comparison under way was of the old scene.
        self.reference = ReferenceJob::default();
        self.panel.reference_lines.clear();
        if !loaded.reload {
            // --camera named a camera of the first file.
            self.camera_key = None;
        }
        self.loader.watch(&self.scene);
        self.disagreement = None;
        self.panel.error = None;
        let status = format!("{} {}", if loaded.reload { "reloaded" } else { "opened" }, loaded.path.display());
        eprintln!("chiaro: {status}");
        self.panel.status = Some(status);
        if matches!(self.panel.debug, Some(DebugView::Aov(AovView::Shadow(i))) if i >= self.scene.lights.len()) {
            self.panel.debug = None;
        }
        let keep_camera = loaded.reload && old.cameras.len() == self.scene.cameras.len();
        self.scene_path = Some(loaded.path);
        let title = self.title();
        if let Some(gpu) = &self.gpu {
            gpu.window.set_title(&title);
        }
        if !keep_camera {
            let (w, h) = self.view_size();
            self.camera = None;
            match choose_view(&self.scene, None, &self.settings, w, h) {
                Ok(view) => {
                    self.start_view = view;
                    self.opening_view = view;
                    self.rig = None;
                }
                Err(e) => self.panel.error = Some(format!("{e:#}")),
            }
        }
    }

    /// Follows render.width and height (a new view texture and window size) and
    /// camera.auto_yfov_deg (the framing camera's field of view).
    fn follow_view_size(&mut self) -> Result<()> {
        let (w, h) = (self.settings.render.width, self.settings.render.height);
        let yfov = self.settings.camera.auto_yfov_deg;
        if (w, h, yfov) == self.view_settings {
            return Ok(());
        }
        self.view_settings = (w, h, yfov);
        self.start_view = self.base_view(self.camera, w, h)?;
        self.opening_view = self.base_view(None, w, h)?;
        self.panel_dirty = true;
        if (w, h) == self.view_texture_size() {
            return Ok(());
        }
        let Some(gpu) = self.gpu.as_mut() else { return Ok(()) };
        let device = &gpu.renderer.ctx.device;
        gpu.view_texture = view_texture(device, gpu.view_format, w, h);
        gpu.egui_renderer.update_egui_texture_from_wgpu_texture(
            device,
            &gpu.view_texture.create_view(&Default::default()),
            wgpu::FilterMode::Nearest,
            gpu.view_texture_id,
        );
        let _ = gpu.window.request_inner_size(window_size(w, h, gpu.window.scale_factor()));
        Ok(())
    }

    /// Renders the frame of the current camera and compares it with the reference on
    /// another thread.
    fn start_comparison(&mut self) {
        let view = self.current_view();
        let Some(gpu) = self.gpu.as_mut() else { return };
        match chiaro_compare::render_shadows(&mut gpu.renderer, &self.scene, &gpu.prepared, &view, &self.settings) {
            Ok(rendered) => {
                self.reference.start(&self.scene, view, &self.settings, rendered);
                self.panel.reference_lines = vec!["tracing the reference for this camera...".into()];
            }
            Err(e) => self.panel.error = Some(format!("comparison: {e}")),
        }
        self.panel_dirty = true;
    }

    /// Panel requests of the last frame, files to load, finished comparisons.
    fn handle_requests(&mut self) -> Result<()> {
        if let Some(camera) = self.panel.camera_request.take() {
            self.use_camera(camera);
        }
        if std::mem::take(&mut self.panel.frame_requested) {
            self.frame_selected();
        }
        if std::mem::take(&mut self.panel.open_requested) {
            let path = PathBuf::from(self.panel.open_path.trim());
            self.loader.open(path, &self.settings, false);
        }
        if std::mem::take(&mut self.panel.compare_requested) {
            self.start_comparison();
        }
        if let Some(path) = self.scene_path.clone()
            && self.loader.changed()
        {
            self.loader.open(path, &self.settings, true);
            self.panel_dirty = true;
        }
        self.take_loaded();
        match self.reference.poll() {
            Some(Ok(done)) => self.show_disagreement(done),
            Some(Err(e)) => {
                self.panel.reference_lines = vec![e];
                self.panel_dirty = true;
            }
            None => {}
        }
        if let Err(e) = self.follow_view_size() {
            self.panel.error = Some(format!("{e:#}"));
        }
        Ok(())
    }

    /// A finished comparison: its lines in the panel, its image in the view.
    fn show_disagreement(&mut self, done: Disagreement) {
        let mut lines = done.lines.clone();
        lines.push(format!("traced in {:.1} s", done.seconds));
        self.panel.reference_lines = lines;
        self.disagreement = Some(done);
        self.panel_dirty = true;
        if let Some(gpu) = self.gpu.as_mut() {
            gpu.debug_textures.clear();
        }
    }
}

/// Whether the 3D view itself is shown (else a debug image is, or nothing yet).
fn shows_view(debug: Option<DebugView>, has_disagreement: bool) -> bool {
    match debug {
        None
        | Some(DebugView::Cascades | DebugView::GbufferAlbedo | DebugView::GbufferNormal | DebugView::LightOverdraw) => {
            true
        }
        Some(DebugView::Reference) => !has_disagreement,
        Some(DebugView::Aov(_) | DebugView::Clusters | DebugView::ShadowAtlases) => false,
    }
}

impl App {
    /// One frame: the 3D view into its texture, the panel if it changed, then both into
    /// the window.
    fn redraw(&mut self) -> Result<()> {
        self.handle_requests()?;
        let now = Instant::now();
        let seconds = self.last_frame.map_or(0.0, |t| (now - t).as_secs_f32());
        self.fly(seconds);
        let Some(mut gpu) = self.gpu.take() else { return Ok(()) };
        let result = self.frame(&mut gpu);
        self.gpu = Some(gpu);
        result?;
        self.frames += 1;
        let now = Instant::now();
        let interval = self.last_frame.replace(now).map(|last| (now - last).as_secs_f64() * 1e3);
        if let Some(ms) = interval {
            self.frame_intervals.push(ms);
        }
        if let Some(sample) = self.panel.history.back_mut() {
            sample.interval_ms = interval;
        }
        Ok(())
    }

    fn frame(&mut self, gpu: &mut Gpu) -> Result<()> {
        let view = self.current_view();
        let debug = self.panel.debug;
        // Images belong to the debug view that made them.
        if gpu.debug_textures_for != debug {
            gpu.debug_textures.clear();
            gpu.debug_textures_for = debug;
        }
        let target = gpu.view_texture.create_view(&Default::default());
        let options = frame_options(debug);
        match gpu.renderer.render_to(
            &self.scene,
            &gpu.prepared,
            &view,
            &self.settings,
            options,
            &target,
            gpu.view_format,
        ) {
            Ok(frame) => {
                if self.panel.error.as_deref().is_some_and(|e| e.starts_with(FRAME_FAILED)) {
                    self.panel.error = None;
                    self.panel_dirty = true;
                }
                self.take_frame(gpu, debug, &frame)?
            }
            Err(e) => {
                // Shown, not fatal: the panel can undo what caused it.
                let message = format!("{FRAME_FAILED}: {e}");
                if self.panel.error.as_ref() != Some(&message) {
                    self.panel.error = Some(message);
                    self.panel_dirty = true;
                }
            }
        }
        let show_view = shows_view(debug, self.disagreement.is_some());
        if debug == Some(DebugView::Reference)
            && gpu.debug_textures.is_empty()
            && let Some(d) = &self.disagreement
        {
            let image = egui::ColorImage::from_rgba_unmultiplied([d.width, d.height], &d.overlay);
            gpu.debug_textures = vec![gpu.egui_ctx.load_texture("disagreement", image, egui::TextureOptions::NEAREST)];
            self.panel_dirty = true;
        }

        let refresh_due = self
            .panel_drawn
            .is_none_or(|(t, frame)| t.elapsed() >= PANEL_REFRESH && self.frames >= frame + PANEL_REFRESH_FRAMES);
        let egui_due = self.egui_repaint_at.is_some_and(|t| Instant::now() >= t);
        let draw_panel = gpu.compositor.is_none() || self.panel_dirty || refresh_due || egui_due;
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
            let output = self.run_panel(gpu, show_view);
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
            commands = gpu.egui_renderer.update_buffers(&device, &queue, &mut encoder, &jobs, &screen);
            let panel_target = match &gpu.compositor {
                Some(c) => c.panel_target(),
                None => surface_texture.texture.create_view(&Default::default()),
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
        }
        if let Some(compositor) = &gpu.compositor {
            let view = show_view.then_some((&gpu.view_texture, gpu.view_origin, gpu.view_limit));
            compositor.compose(&mut encoder, &surface_texture.texture, view);
        }
        queue.submit(commands.into_iter().chain([encoder.finish()]));
        queue.present(surface_texture);
        Ok(())
    }

    /// What the frame tells the panel, and the debug view's images.
    fn take_frame(&mut self, gpu: &mut Gpu, debug: Option<DebugView>, frame: &FrameOutput) -> Result<()> {
        let images = debug_images(debug, frame, &self.scene);
        if !matches!(debug, Some(DebugView::Reference)) {
            gpu.debug_textures = images
                .into_iter()
                .enumerate()
                .map(|(i, (size, pixels))| {
                    let image = egui::ColorImage::from_rgba_unmultiplied(size, pixels.as_flattened());
                    gpu.egui_ctx.load_texture(format!("debug {i}"), image, egui::TextureOptions::NEAREST)
                })
                .collect();
            if !shows_view(debug, false) {
                self.panel_dirty = true;
            }
        }
        self.panel.shadow_tiles = frame.shadow_tiles;
        self.panel.lights_shaded = frame.plan.lights.len();
        self.panel.lights.tiles = lights_panel::tiles_by_light(&frame.plan, self.scene.lights.len());
        let finished = gpu.renderer.gpu_times(false)?;
        self.gpu_frame_ms.extend(finished.iter().map(|t| t.total_ms()));
        if let Some(latest) = finished.into_iter().last() {
            self.panel.gpu = Some(latest);
        }
        self.panel.record(FrameSample {
            cpu_ms: frame.timings.cpu_prepare_ms,
            passes: self.panel.gpu.as_ref().map(|g| g.passes.clone()).unwrap_or_default(),
            interval_ms: None,
        });
        Ok(())
    }

    /// Runs egui over the panel; applies what was edited in it.
    fn run_panel(&mut self, gpu: &mut Gpu, show_view: bool) -> egui::FullOutput {
        let input = gpu.egui_state.take_egui_input(&gpu.window);
        let (w, h) = self.view_size();
        let ppp = gpu.egui_ctx.pixels_per_point();
        let view_size = egui::vec2(w as f32 / ppp, h as f32 / ppp);
        let camera_names: Vec<String> = self.scene.cameras.iter().map(|c| c.name.clone()).collect();
        let loading = self.loader.loading().map(Path::to_path_buf);
        let comparing = self.reference.running();
        let stale =
            self.disagreement.as_ref().is_some_and(|d| d.view.world_from_view != self.current_view().world_from_view);
        let textures: Vec<(egui::TextureId, egui::Vec2)> =
            gpu.debug_textures.iter().map(|t| (t.id(), t.size_vec2())).collect();
        let compositor = gpu.compositor.is_some();
        let view_texture_id = gpu.view_texture_id;
        let debug = self.panel.debug;
        let mut edit = None;
        let mut view_rect = None;
        let mut central = egui::Rect::NOTHING;
        let output = gpu.egui_ctx.run_ui(input, |ui| {
            // egui's separator line lands inside the panel, across its text.
            egui::Panel::right("settings").exact_size(PANEL_WIDTH).resizable(false).show_separator_line(false).show(
                ui,
                |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| {
                        ui.heading("Scene");
                        panel::open_panel(ui, &mut self.panel, loading.as_deref());
                        ui.heading("Camera");
                        panel::cameras_panel(ui, &camera_names, &mut self.panel);
                        ui.label(match self.panel.lights.selected {
                            Some(Selection::Object(i)) if i < self.scene.instances.len() => {
                                let instance = &self.scene.instances[i];
                                format!("selected: {} (node {})", instance.name, instance.node)
                            }
                            Some(Selection::Light(i)) if i < self.scene.lights.len() => {
                                format!("selected: light {}", self.scene.lights[i].name)
                            }
                            _ => "selected: nothing (click an object)".to_string(),
                        });
                        ui.heading("View");
                        panel::debug_panel(ui, &mut self.panel, self.scene.lights.len(), comparing);
                        if stale && debug == Some(DebugView::Reference) {
                            ui.colored_label(egui::Color32::YELLOW, "the camera moved since: compare again");
                        }
                        ui.separator();
                        ui.heading("Frame");
                        panel::timings_panel(ui, &self.panel);
                        ui.separator();
                        ui.horizontal(|ui| {
                            self.panel.save_requested = ui.button("Save settings").clicked();
                            self.panel.save_scene_requested = ui
                                .button("Save scene")
                                .on_hover_text("the glTF with the lights as edited and this view as a camera")
                                .clicked();
                        });
                        if let Some(status) = &self.panel.status {
                            ui.label(status);
                        }
                        if let Some(e) = &self.panel.error {
                            ui.colored_label(egui::Color32::LIGHT_RED, e);
                        }
                        edit = settings_panel::settings_panel(ui, &self.settings);
                        ui.separator();
                        ui.heading("Lights");
                        lights_panel::lights_panel(ui, &mut self.scene.lights, &mut self.panel.lights);
                        ui.separator();
                        ui.label(panel::HELP);
                    });
                },
            );
            egui::CentralPanel::no_frame().show(ui, |ui| {
                central = ui.max_rect();
                if show_view {
                    view_rect = Some(if compositor {
                        ui.allocate_exact_size(view_size, egui::Sense::hover()).0
                    } else {
                        ui.image(egui::load::SizedTexture::new(view_texture_id, view_size)).rect
                    });
                    return;
                }
                ui.horizontal(|ui| {
                    for &(id, size) in &textures {
                        // Atlases side by side; any other image at the view's size.
                        let shown = if debug == Some(DebugView::ShadowAtlases) {
                            let side = (view_size.x / 2.0).min(view_size.y);
                            egui::vec2(side, side)
                        } else {
                            size * (view_size.x / size.x.max(1.0))
                        };
                        ui.image(egui::load::SizedTexture::new(id, shown));
                    }
                });
                if textures.is_empty() {
                    ui.label(match debug {
                        Some(DebugView::ShadowAtlases) => "No light casts a shadow.",
                        Some(DebugView::Clusters) => "No clusters: lights.culling is not clustered on this path.",
                        _ => "Nothing to show yet.",
                    });
                }
            });
        });
        gpu.egui_state.handle_platform_output(&gpu.window, output.platform_output.clone());
        if let Some(rect) = view_rect {
            let pixel = |v: f32| (v * ppp).round().max(0.0) as u32;
            gpu.view_origin = [pixel(rect.min.x), pixel(rect.min.y)];
            gpu.view_limit = [pixel(central.max.x), pixel(central.max.y)];
        }
        let delay = output.viewport_output.get(&egui::ViewportId::ROOT).map(|v| v.repaint_delay);
        self.egui_repaint_at = delay.filter(|d| *d < Duration::from_secs(3600)).map(|d| Instant::now() + d);
        self.panel_dirty = false;
        self.panel_drawn = Some((Instant::now(), self.frames));
        self.panel_draws += 1;
        match edit {
            Some(Ok(settings)) => match self.args.path.check_device(&gpu.renderer.ctx, &settings, None) {
                Ok(()) => {
                    self.settings = settings;
                    self.panel.error = None;
                    self.panel_dirty = true;
                }
                Err(e) => {
                    self.panel.error = Some(format!("{e:#}"));
                    self.panel_dirty = true;
                }
            },
            Some(Err(e)) => {
                self.panel.error = Some(e);
                self.panel_dirty = true;
            }
            None => {}
        }
        if std::mem::take(&mut self.panel.save_scene_requested) {
            self.panel.status = Some(match &self.scene_path {
                None => "not saved: the demo scene has no file".to_string(),
                Some(source) => {
                    let target = save_scene::saved_path(source);
                    match save_scene::save_scene(source, &self.scene, &self.current_view(), &target) {
                        Ok(()) => format!(
                            "saved {}: chiaro render it with --camera \"{}\"",
                            target.display(),
                            save_scene::VIEW_CAMERA
                        ),
                        Err(e) => format!("not saved: {e:#}"),
                    }
                }
            });
            self.panel_dirty = true;
        }
        if std::mem::take(&mut self.panel.save_requested) {
            let path = self.args.settings.clone().unwrap_or_else(|| PathBuf::from("chiaro-view.toml"));
            self.panel.status = Some(match save_settings(&path, &self.settings) {
                Ok(()) => format!("saved {}", path.display()),
                Err(e) => format!("not saved: {e:#}"),
            });
            self.panel_dirty = true;
        }
        output
    }

    /// Writes the 3D view as `chiaro render` would: the same renderer, view and settings.
    fn screenshot(&mut self, path: &Path) -> Result<()> {
        let view = self.current_view();
        let gpu = self.gpu.as_mut().ok_or_else(|| anyhow!("no frame was rendered"))?;
        // The debug views `chiaro render --debug` also has are written as it writes them.
        let options = match self.panel.debug {
            Some(d) if d == DebugView::Cascades || d.is_deferred() => d.frame_options(),
            _ => FrameOptions::default(),
        };
        let options = FrameOptions { readback: true, ..options };
        let frame = gpu.renderer.render(&self.scene, &gpu.prepared, &view, &self.settings, options)?;
        let (width, height) = (view.width, view.height);
        let rgb: Vec<[f32; 3]> = frame.hdr.iter().map(|p| [p[0], p[1], p[2]]).collect();
        let image = output_format(path)?.frame_image(width, height, &frame.ldr, &rgb);
        write_group(vec![(path.to_path_buf(), image)])?;
        eprintln!("chiaro: wrote {} ({width}x{height}) after {} frames", path.display(), self.frames);
        Ok(())
    }

    /// Writes the window as the last frame composed it: the panel's texture and the view,
    /// copied as they were copied into the surface.
    fn screenshot_window(&mut self, path: &Path) -> Result<()> {
        let debug = self.panel.debug;
        let show_view = shows_view(debug, self.disagreement.is_some());
        let gpu = self.gpu.as_mut().ok_or_else(|| anyhow!("no frame was rendered"))?;
        let compositor = gpu.compositor.as_ref().ok_or_else(|| {
            anyhow!("--screenshot-window: this window's surface takes no copies, so the window is drawn in place")
        })?;
        let ctx = &gpu.renderer.ctx;
        let (width, height) = (gpu.config.width, gpu.config.height);
        let usage = wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::COPY_SRC;
        let window =
            present::window_texture(&ctx.device, "window screenshot", gpu.config.format, (width, height), usage);
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        compositor.compose(
            &mut encoder,
            &window,
            show_view.then_some((&gpu.view_texture, gpu.view_origin, gpu.view_limit)),
        );
        let copy = chiaro_render::readback::copy_texture(&ctx.device, &mut encoder, &window, 4);
        ctx.queue.submit([encoder.finish()]);
        let mut bytes = chiaro_render::readback::finish_copies(ctx, vec![copy])?.remove(0);
        if matches!(gpu.config.format, wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb) {
            bytes.chunks_exact_mut(4).for_each(|px| px.swap(0, 2));
        } else if !matches!(gpu.config.format, wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Rgba8UnormSrgb) {
            return Err(anyhow!("--screenshot-window: the window's format {:?} is not 8-bit RGBA", gpu.config.format));
        }
        bytes.chunks_exact_mut(4).for_each(|px| px[3] = 255);
        write_group(vec![(path.to_path_buf(), crate::output::Encoded::Png { width, height, rgba8: &bytes })])?;
        eprintln!("chiaro: wrote {} (the window, {width}x{height})", path.display());
        Ok(())
    }

    /// Whether the pointer at `(x, y)` (physical pixels) is over the panel or a popup,
    /// rather than the 3D view.
    fn over_ui(&self, (x, y): (f64, f64)) -> bool {
        let Some(gpu) = &self.gpu else { return true };
        let [ox, oy] = gpu.view_origin.map(f64::from);
        let [lx, ly] = gpu.view_limit.map(f64::from);
        let (w, h) = self.view_size();
        let in_view = x >= ox && y >= oy && x < (ox + f64::from(w)).min(lx) && y < (oy + f64::from(h)).min(ly);
        let ppp = f64::from(gpu.egui_ctx.pixels_per_point());
        let pos = egui::pos2((x / ppp) as f32, (y / ppp) as f32);
        !in_view || gpu.egui_ctx.layer_id_at(pos).is_some_and(|l| l.order != egui::Order::Background)
    }

    /// A click in the view at `(x, y)` (window pixels) selects what it shows there.
    fn click(&mut self, x: f64, y: f64) {
        let Some(gpu) = &self.gpu else { return };
        let [ox, oy] = gpu.view_origin.map(f64::from);
        let view = self.current_view();
        let picked = self.picker.pick(&self.scene, &view, (x - ox) as f32, (y - oy) as f32);
        self.panel.lights.selected = picked.map(Selection::Object);
        self.panel_dirty = true;
    }

    fn key_pressed(&mut self, event_loop: &ActiveEventLoop, key: &Key) {
        match key.as_ref() {
            Key::Character("r") => self.use_camera(None),
            Key::Character("c") if !self.scene.cameras.is_empty() => {
                let next = self.camera.map_or(0, |i| (i + 1) % self.scene.cameras.len());
                self.use_camera(Some(next));
            }
            Key::Character("f") => self.frame_selected(),
            Key::Character("v") => {
                self.panel.navigation = match self.panel.navigation {
                    Navigation::Orbit => Navigation::Fly,
                    Navigation::Fly => Navigation::Orbit,
                };
            }
            Key::Character("p") => {
                let path = PathBuf::from("chiaro-view.png");
                self.panel.status = Some(match self.screenshot(&path) {
                    Ok(()) => format!("wrote {}", path.display()),
                    Err(e) => format!("no screenshot: {e:#}"),
                });
            }
            Key::Named(NamedKey::Escape) => event_loop.exit(),
            _ => return,
        }
        self.panel_dirty = true;
    }
}

/// Writes `settings` as TOML to `path`, whole or not at all (a temporary file renamed
/// over it), so that `chiaro render --settings path` renders what the viewer showed.
fn save_settings(path: &Path, settings: &Settings) -> Result<()> {
    crate::output::write_file(path, settings.to_toml().as_bytes())
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gpu.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(gpu) => {
                let (w, h) = self.view_size();
                let adapter = &gpu.renderer.ctx.adapter_info.name;
                eprintln!(
                    "chiaro: viewing {} ({w}x{h}) on {adapter}",
                    self.title().trim_start_matches("chiaro view: ")
                );
                gpu.window.request_redraw();
                self.gpu = Some(gpu);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(gpu) = self.gpu.as_mut() else { return };
        let response = gpu.egui_state.on_window_event(&gpu.window, &event);
        let wants_keyboard = gpu.egui_ctx.egui_wants_keyboard_input();
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                gpu.config.width = size.width.max(1);
                gpu.config.height = size.height.max(1);
                gpu.surface.configure(&gpu.renderer.ctx.device, &gpu.config);
                if let Some(c) = &mut gpu.compositor
                    && !c.fits(gpu.config.width, gpu.config.height)
                {
                    *c = Compositor::new(
                        &gpu.renderer.ctx.device,
                        gpu.config.format,
                        gpu.config.width,
                        gpu.config.height,
                    );
                }
                self.panel_dirty = true;
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let (true, Some((x, y))) = (self.dragging, self.cursor) {
                    let navigation = self.panel.navigation;
                    self.rig().drag(navigation, (now.0 - x) as f32, (now.1 - y) as f32);
                }
                let was_over_ui = self.cursor.is_none_or(|c| self.over_ui(c));
                if response.repaint && (was_over_ui || self.over_ui(now)) {
                    self.panel_dirty = true;
                }
                self.cursor = Some(now);
            }
            WindowEvent::MouseInput { state, button: MouseButton::Left, .. } => {
                let on_ui = self.cursor.is_none_or(|c| self.over_ui(c));
                self.dragging = state == ElementState::Pressed && !on_ui;
                // Over the view too while a panel field has the keyboard: egui sees the
                // click and lets go of it, so that keys move the camera again.
                self.panel_dirty |= on_ui || wants_keyboard;
                match state {
                    ElementState::Pressed => self.pressed_at = self.cursor.filter(|_| !on_ui),
                    ElementState::Released => {
                        if let (Some((px, py)), Some((x, y))) = (self.pressed_at.take(), self.cursor)
                            && (x - px).hypot(y - py) < 4.0
                        {
                            self.click(x, y);
                        }
                    }
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                if self.cursor.is_none_or(|c| self.over_ui(c)) {
                    self.panel_dirty = true;
                } else {
                    let steps = match delta {
                        MouseScrollDelta::LineDelta(_, y) => y,
                        MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                    };
                    self.rig().zoom(steps);
                }
            }
            WindowEvent::KeyboardInput { event, .. } => {
                // A release always counts, or a key held into a text field flies on.
                if let PhysicalKey::Code(code) = event.physical_key
                    && event.state == ElementState::Released
                {
                    self.keys.remove(&code);
                }
                if wants_keyboard {
                    self.panel_dirty = true;
                    return;
                }
                if let PhysicalKey::Code(code) = event.physical_key
                    && event.state == ElementState::Pressed
                {
                    self.keys.insert(code);
                }
                if event.state == ElementState::Pressed && !event.repeat {
                    self.key_pressed(event_loop, &event.logical_key);
                }
            }
            WindowEvent::Focused(false) => {
                self.keys.clear();
                self.dragging = false;
            }
            WindowEvent::ScaleFactorChanged { scale_factor, .. } => {
                let (w, h) = (self.start_view.width, self.start_view.height);
                let _ = gpu.window.request_inner_size(window_size(w, h, scale_factor));
                self.panel_dirty = true;
            }
            WindowEvent::DroppedFile(path) => {
                self.loader.open(path, &self.settings, false);
                self.panel_dirty = true;
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
                    if let Some(path) = self.args.screenshot_window.clone()
                        && let Err(e) = self.screenshot_window(&path)
                    {
                        return self.fail(event_loop, e);
                    }
                    let median = |mut v: Vec<f64>| {
                        v.sort_by(f64::total_cmp);
                        v.get(v.len() / 2).copied()
                    };
                    if let Some(frame) = median(self.frame_intervals.clone()) {
                        let gpu = median(self.gpu_frame_ms.clone())
                            .map_or(String::new(), |g| format!(" (GPU {g:.1} ms by timestamps)"));
                        eprintln!(
                            "chiaro: {} frames shown (the panel drawn on {}), median {frame:.1} ms a frame{gpu}",
                            self.frames, self.panel_draws
                        );
                    }
                    event_loop.exit();
                }
            }
            _ => self.panel_dirty |= response.repaint,
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
}
