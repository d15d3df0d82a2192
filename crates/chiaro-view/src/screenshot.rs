//! Screenshots: the 3D view rendered again as `chiaro render` renders it (PNG or EXR, the
//! same renderer, view and settings), or the whole window as the last frame composed it
//! (PNG). Both are written atomically (chiaro-io).

use crate::debug_images::shows_view;
use crate::present;
use crate::viewer::Viewer;
use anyhow::{Result, anyhow};
use chiaro_io::output::{Encoded, output_format, write_group};
use chiaro_render::{DebugView, FrameOptions};
use std::path::Path;

impl Viewer {
    /// Writes the 3D view as `chiaro render` would: the same renderer, view and settings.
    pub(crate) fn screenshot(&mut self, path: &Path) -> Result<()> {
        let state = &self.state;
        let view = state.current_view();
        let gpu = self.gpu.as_mut().ok_or_else(|| anyhow!("no frame was rendered"))?;
        // The debug views `chiaro render --debug` also has are written as it writes them.
        let options = match state.debug {
            Some(d) if d == DebugView::Cascades || d.is_deferred() => d.frame_options(),
            _ => FrameOptions::default(),
        };
        let options = FrameOptions { readback: true, ..options };
        let frame = gpu.renderer.render(&state.scene.scene, &gpu.prepared, &view, &state.settings.current, options)?;
        let (width, height) = (view.width, view.height);
        let rgb: Vec<[f32; 3]> = frame.hdr.iter().map(|p| [p[0], p[1], p[2]]).collect();
        let image = output_format(path)?.frame_image(width, height, &frame.ldr, &rgb);
        write_group(vec![(path.to_path_buf(), image)])?;
        eprintln!("chiaro: wrote {} ({width}x{height}) after {} frames", path.display(), state.stats.frames);
        Ok(())
    }

    /// Writes the window as the last frame composed it: the panel's texture and the view,
    /// copied as they were copied into the surface.
    pub(crate) fn screenshot_window(&mut self, path: &Path) -> Result<()> {
        let show_view = shows_view(self.state.debug, self.state.jobs.disagreement.is_some());
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
        write_group(vec![(path.to_path_buf(), Encoded::Png { width, height, rgba8: &bytes })])?;
        eprintln!("chiaro: wrote {} (the window, {width}x{height})", path.display());
        Ok(())
    }
}
