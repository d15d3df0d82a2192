//! Everything that lives on the device, made once the window exists: the window and its
//! surface, the renderer and the prepared scene, egui's renderer, the 3D view's texture
//! and the compositor. In: the viewer's state (scene, settings, view size). Out: a `Gpu`
//! that follows the window's size and the view's.

use crate::light_overlay::LightOverlay;
use crate::present::{self, Compositor};
use crate::state::ViewerState;
use anyhow::{Context, Result, anyhow};
use chiaro_render::{DebugView, GpuContext, PreparedScene, Renderer};
use std::sync::Arc;
use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

/// Width of the settings panel, in logical pixels, beside the 3D view.
pub const PANEL_WIDTH: f32 = 340.0;

/// The window's size for a `w` x `h` view: the panel is PANEL_WIDTH logical pixels.
pub fn window_size(w: u32, h: u32, scale_factor: f64) -> winit::dpi::PhysicalSize<u32> {
    winit::dpi::PhysicalSize::new(w + (f64::from(PANEL_WIDTH) * scale_factor).ceil() as u32, h)
}

pub struct Gpu {
    pub window: Arc<Window>,
    pub surface: wgpu::Surface<'static>,
    pub config: wgpu::SurfaceConfiguration,
    pub renderer: Renderer,
    pub prepared: PreparedScene,
    pub egui_ctx: egui::Context,
    pub egui_state: egui_winit::State,
    pub egui_renderer: egui_wgpu::Renderer,
    /// The 3D view: the surface's format with sRGB encoding, so that it copies into the
    /// surface as it is.
    pub view_texture: wgpu::Texture,
    pub view_format: wgpu::TextureFormat,
    /// Draws the area lights' outlines over the view.
    pub light_overlay: LightOverlay,
    /// The 3D view as egui sees it, where egui draws it (no compositor).
    pub view_texture_id: egui::TextureId,
    /// Copies the panel and the view into the window; `None` where the surface takes no
    /// copies, and egui draws everything every frame.
    pub compositor: Option<Compositor>,
    /// Images a debug view shows in place of the 3D view, and the view they belong to.
    pub debug_textures: Vec<egui::TextureHandle>,
    pub debug_textures_for: Option<DebugView>,
    /// The 3D view's top-left corner in the window, in physical pixels.
    pub view_origin: [u32; 2],
    /// Where the panel begins (and the window ends below): the view is cut there.
    pub view_limit: [u32; 2],
}

fn view_texture(device: &wgpu::Device, format: wgpu::TextureFormat, width: u32, height: u32) -> wgpu::Texture {
    use wgpu::TextureUsages as U;
    let usage = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC;
    present::window_texture(device, "3D view", format, (width, height), usage)
}

/// The surface's format: one with an sRGB twin for the view, else the first offered.
fn surface_format(ctx: &GpuContext) -> Result<wgpu::TextureFormat> {
    ctx.surface_formats
        .iter()
        .copied()
        .find(|f| !f.is_srgb() && f.add_srgb_suffix().is_srgb())
        .or_else(|| ctx.surface_formats.first().copied())
        .ok_or_else(|| anyhow!("the window's surface offers no format on {}", ctx.adapter_info.name))
}

impl Gpu {
    /// Opens the window for `state`'s view and sets up the device behind it.
    pub fn open(event_loop: &ActiveEventLoop, state: &ViewerState) -> Result<Gpu> {
        let (w, h) = state.camera.view_size();
        let attributes =
            Window::default_attributes().with_title(state.scene.title()).with_inner_size(window_size(w, h, 1.0));
        let window = Arc::new(event_loop.create_window(attributes).context("cannot open a window")?);
        if window.scale_factor() != 1.0 {
            let _ = window.request_inner_size(window_size(w, h, window.scale_factor()));
        }
        let (ctx, surface) = GpuContext::for_surface(window.clone())?;
        let settings = &state.settings;
        chiaro_io::device::check_msaa(&ctx, &settings.current, settings.msaa_flag, settings.file.as_deref())?;
        let format = surface_format(&ctx)?;
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
        let light_overlay = LightOverlay::new(&ctx.device, view_format);
        let mut renderer = Renderer::new(ctx)?;
        let prepared = renderer.prepare(&state.scene.scene)?;
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
            light_overlay,
            view_texture_id,
            compositor,
            debug_textures: Vec::new(),
            debug_textures_for: None,
            view_origin: [0, 0],
            view_limit: [w, h],
        })
    }

    /// Follows the window's new size: the surface and the panel's texture.
    pub fn resize(&mut self, width: u32, height: u32) {
        self.config.width = width.max(1);
        self.config.height = height.max(1);
        self.surface.configure(&self.renderer.ctx.device, &self.config);
        if let Some(c) = &mut self.compositor
            && !c.fits(self.config.width, self.config.height)
        {
            *c = Compositor::new(&self.renderer.ctx.device, self.config.format, self.config.width, self.config.height);
        }
    }

    /// A view texture of `w` x `h` (if it is not that size already), and a window to fit.
    pub fn fit_view(&mut self, w: u32, h: u32) {
        if (w, h) == (self.view_texture.width(), self.view_texture.height()) {
            return;
        }
        let device = &self.renderer.ctx.device;
        self.view_texture = view_texture(device, self.view_format, w, h);
        self.egui_renderer.update_egui_texture_from_wgpu_texture(
            device,
            &self.view_texture.create_view(&Default::default()),
            wgpu::FilterMode::Nearest,
            self.view_texture_id,
        );
        let _ = self.window.request_inner_size(window_size(w, h, self.window.scale_factor()));
    }

    /// Whether the pointer at `(x, y)` (physical pixels) is over the panel or a popup,
    /// rather than the 3D view of `w` x `h`.
    pub fn over_ui(&self, (x, y): (f64, f64), (w, h): (u32, u32)) -> bool {
        let [ox, oy] = self.view_origin.map(f64::from);
        let [lx, ly] = self.view_limit.map(f64::from);
        let in_view = x >= ox && y >= oy && x < (ox + f64::from(w)).min(lx) && y < (oy + f64::from(h)).min(ly);
        let ppp = f64::from(self.egui_ctx.pixels_per_point());
        let pos = egui::pos2((x / ppp) as f32, (y / ppp) as f32);
        !in_view || self.egui_ctx.layer_id_at(pos).is_some_and(|l| l.order != egui::Order::Background)
    }
}
