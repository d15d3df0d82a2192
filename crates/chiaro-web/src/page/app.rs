//! The page's renderer and what it shows: the scene, the settings, the camera rig and the
//! debug view; one frame rendered into the canvas and timed to GPU completion.

use super::dom::now_ms;
use chiaro_render::camera_rig::{CameraRig, FlyInput, Navigation};
use chiaro_render::debug_images::{frame_images, shows_view};
use chiaro_render::{DebugView, FrameOptions, GpuContext, PendingFrame, PreparedScene, Renderer, View};
use chiaro_scene::{Scene, Settings};
use std::cell::RefCell;

pub struct App {
    renderer: Renderer,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    pub scene: Scene,
    prepared: PreparedScene,
    pub settings: Settings,
    /// The glTF camera shown, or `None` for the view that frames the scene.
    pub camera: Option<usize>,
    start_view: View,
    pub rig: CameraRig,
    pub navigation: Navigation,
    pub debug: Option<DebugView>,
    /// Something changed since the last frame.
    pub dirty: bool,
    /// Frames finished since the scene was opened (`window.chiaro.scene_frames`).
    pub scene_frames: u32,
    /// Counts the scenes opened, so that a frame of the previous scene finishing after a
    /// new one opened is not taken for the new scene's.
    scene_generation: u64,
}

/// The debug views the page offers for a scene of `lights` lights: all of the native
/// viewer's but the comparison with the CPU reference (no tracer in the browser build) and
/// the virtual shadow page table (virtual shadow maps read back while they render).
pub fn page_debug_views(lights: usize) -> Vec<DebugView> {
    DebugView::all(lights)
        .into_iter()
        .filter(|d| !matches!(d, DebugView::Reference | DebugView::VirtualPages))
        .collect()
}

impl App {
    /// Sets up the canvas's surface at `width` x `height` and prepares `scene`, looking
    /// through `camera` (a name or index; `None`: the first camera, else the framing view).
    pub fn new(
        ctx: GpuContext,
        surface: wgpu::Surface<'static>,
        scene: Scene,
        settings: Settings,
        camera: Option<&str>,
        (width, height): (u32, u32),
    ) -> Result<App, String> {
        ctx.check_msaa(settings.render.msaa).map_err(|e| format!("render.msaa: {e}"))?;
        let format = surface_format(&ctx)?;
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width,
            height,
            present_mode: wgpu::PresentMode::Fifo,
            desired_maximum_frame_latency: 2,
            alpha_mode: wgpu::CompositeAlphaMode::Opaque,
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        surface.configure(&ctx.device, &config);
        let camera = match camera {
            Some(key) => Some(scene.find_camera(key).ok_or_else(|| no_camera(&scene, key))?),
            None => (!scene.cameras.is_empty()).then_some(0),
        };
        let mut renderer = Renderer::new(ctx).map_err(|e| e.to_string())?;
        let prepared = renderer.prepare(&scene).map_err(|e| e.to_string())?;
        let start_view = start_view(&scene, camera, &settings, width, height);
        let rig = CameraRig::from_view(&start_view, scene.bounds().bounding_sphere().center);
        Ok(App {
            renderer,
            surface,
            config,
            scene,
            prepared,
            settings,
            camera,
            start_view,
            rig,
            navigation: Navigation::Orbit,
            debug: None,
            dirty: true,
            scene_frames: 0,
            scene_generation: 0,
        })
    }

    /// The adapter as the stats name it: wgpu's name, else what the page read of the
    /// browser's adapter info (`window.chiaro.adapter_info`), with the backend and type.
    pub fn adapter(&self) -> String {
        let info = &self.renderer.ctx.adapter_info;
        let name = if info.name.is_empty() { super::dom::published_string("adapter_info") } else { info.name.clone() };
        format!("{name} ({:?}, {:?})", info.backend, info.device_type)
    }

    /// Shows `scene` instead, through its first camera (or framing it).
    pub fn set_scene(&mut self, scene: Scene) -> Result<(), String> {
        let prepared = self.renderer.prepare(&scene).map_err(|e| e.to_string())?;
        self.renderer.forget_history();
        self.scene = scene;
        self.prepared = prepared;
        self.scene_frames = 0;
        self.scene_generation += 1;
        self.use_camera((!self.scene.cameras.is_empty()).then_some(0));
        Ok(())
    }

    /// Looks through glTF camera `index`, or frames the scene; the rig starts there.
    pub fn use_camera(&mut self, index: Option<usize>) {
        self.camera = index;
        self.start_view = start_view(&self.scene, index, &self.settings, self.config.width, self.config.height);
        self.rig = CameraRig::from_view(&self.start_view, self.scene.bounds().bounding_sphere().center);
        self.dirty = true;
    }

    /// New settings (checked against the device), shown from the next frame. A new
    /// `scene.variant` gives the scene that variant's materials (none: the file's) and
    /// uploads it again.
    pub fn set_settings(&mut self, settings: Settings) -> Result<(), String> {
        self.renderer.ctx.check_msaa(settings.render.msaa).map_err(|e| format!("render.msaa: {e}"))?;
        if settings.scene.variant != self.settings.scene.variant {
            self.scene.select_variant(settings.scene.variant.as_deref()).map_err(|e| e.to_string())?;
            self.prepared = self.renderer.prepare(&self.scene).map_err(|e| e.to_string())?;
        }
        self.settings = settings;
        // The framing view's field of view is a setting.
        self.use_camera(self.camera);
        Ok(())
    }

    /// Moves a flying camera by `input` for `seconds`.
    pub fn fly(&mut self, input: FlyInput, fast: bool, seconds: f32) {
        if input == FlyInput::ZERO {
            return;
        }
        let radius = self.scene.bounds().bounding_sphere().radius.max(1e-3);
        self.rig.fly_for(input, fast, seconds, radius);
        self.dirty = true;
    }

    /// The first GPU error reported since the last call.
    pub fn take_error(&mut self) -> Result<(), String> {
        self.renderer.ctx.take_error().map_err(|e| e.to_string())
    }

    fn view(&self) -> View {
        self.rig.view(&self.start_view, self.scene.bounds().bounding_sphere())
    }

    /// Renders and presents one frame, and returns once the GPU has finished it: the
    /// milliseconds from the start of its preparation to the GPU's completion, or `None`
    /// if another scene was opened meanwhile (the frame was the old scene's). A debug view
    /// computed from read-backs is shown beside, once they arrive (not timed), unless the
    /// view or the scene changed meanwhile (the next frame shows the new one).
    pub async fn frame(app: &RefCell<App>) -> Result<Option<f64>, String> {
        let start = now_ms();
        let (pending, done, generation, debug) = {
            let mut app = app.borrow_mut();
            app.dirty = false;
            let (pending, done) = app.record_and_present()?;
            (pending, done, app.scene_generation, app.debug)
        };
        done.await.map_err(|_| "the GPU device was lost before the frame finished".to_string())?;
        let ms = now_ms() - start;
        // No borrow is held while the read-backs are awaited: the page's events go on.
        let pending = pending.read_back_async().await.map_err(|e| e.to_string())?;
        let mut app = app.borrow_mut();
        let frame = app.renderer.finish(pending).map_err(|e| e.to_string())?;
        if app.scene_generation != generation {
            return Ok(None);
        }
        if app.debug == debug {
            let images = if shows_view(debug, false) { Vec::new() } else { frame_images(debug, &frame, &app.scene) };
            super::debug_images::show(&images)?;
        }
        Ok(Some(ms))
    }

    #[allow(clippy::type_complexity)]
    fn record_and_present(&mut self) -> Result<(PendingFrame, futures_channel::oneshot::Receiver<()>), String> {
        let texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            other => {
                self.surface.configure(&self.renderer.ctx.device, &self.config);
                return Err(format!("the canvas gave no texture to draw into ({other:?})"));
            }
        };
        let target = texture.texture.create_view(&Default::default());
        let view = self.view();
        let options = self.debug.map_or_else(FrameOptions::default, DebugView::frame_options);
        let mut settings = self.settings.clone();
        if self.debug == Some(DebugView::Cascades) {
            // The cascade tint is the forward path's, as `chiaro render --debug cascades`.
            settings.render.path = chiaro_scene::RenderPath::Forward;
            settings.lights.max_other_lights = None;
        }
        let pending = self
            .renderer
            .submit_to(&self.scene, &self.prepared, &view, &settings, options, &target, self.config.format)
            .map_err(|e| e.to_string())?;
        let queue = &self.renderer.ctx.queue;
        queue.present(texture);
        let (sender, receiver) = futures_channel::oneshot::channel();
        queue.on_submitted_work_done(move || {
            let _ = sender.send(());
        });
        Ok((pending, receiver))
    }
}

/// The view `chiaro render` starts from: camera `index`, or one framing the scene.
fn start_view(scene: &Scene, index: Option<usize>, settings: &Settings, width: u32, height: u32) -> View {
    match index {
        Some(i) => View::from_camera(scene, i, width, height),
        None => View::framing(scene, settings.camera.auto_yfov_deg.to_radians(), width, height),
    }
}

fn no_camera(scene: &Scene, key: &str) -> String {
    let names: Vec<String> = scene.cameras.iter().enumerate().map(|(i, c)| format!("{i}: {}", c.name)).collect();
    format!(
        "no camera '{key}' in the scene (cameras: {})",
        if names.is_empty() { "none".to_string() } else { names.join(", ") }
    )
}

/// The first 8-bit format without sRGB encoding the canvas offers (canvases offer no sRGB
/// format; the tone mapping pass encodes). The browser lists its preferred format first:
/// any other costs a copy each frame.
fn surface_format(ctx: &GpuContext) -> Result<wgpu::TextureFormat, String> {
    let eight_bit = [wgpu::TextureFormat::Rgba8Unorm, wgpu::TextureFormat::Bgra8Unorm];
    ctx.surface_formats
        .iter()
        .copied()
        .find(|f| eight_bit.contains(f))
        .or_else(|| ctx.surface_formats.first().copied())
        .ok_or_else(|| "the canvas offers no texture format".to_string())
}
