//! Puts the panel and the 3D view in the window. egui draws the panel into a texture of
//! its own, and only when something in it changed; every frame copies that texture and
//! then the 3D view into the window's surface. On lavapipe egui's pass is a large share of
//! a frame (docs/viewer.md has the measurements), so drawing it every frame made the
//! window cost far more than the few percent it may.

/// A plain 2D texture of the window's pictures: the 3D view, the panel, a screenshot.
pub fn window_texture(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    (width, height): (u32, u32),
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// The panel's texture, the size of the window's surface.
pub struct Compositor {
    panel: wgpu::Texture,
}

impl Compositor {
    /// Whether a surface with `usages` can take the copies (else egui draws every frame).
    pub fn supported(usages: wgpu::TextureUsages) -> bool {
        usages.contains(wgpu::TextureUsages::COPY_DST)
    }

    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat, width: u32, height: u32) -> Compositor {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        Compositor { panel: window_texture(device, "panel", format, (width, height), usage) }
    }

    /// Whether the panel texture fits a surface of `width` x `height`.
    pub fn fits(&self, width: u32, height: u32) -> bool {
        self.panel.width() == width && self.panel.height() == height
    }

    /// Where egui draws the panel.
    pub fn panel_target(&self) -> wgpu::TextureView {
        self.panel.create_view(&Default::default())
    }

    /// Records the copies that make the window's image: the panel, then `view` (if shown)
    /// with its top-left corner at `origin`, cut at `limit` (where the panel begins) and at
    /// the surface's edges.
    pub fn compose(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        surface: &wgpu::Texture,
        view: Option<(&wgpu::Texture, [u32; 2], [u32; 2])>,
    ) {
        let whole = wgpu::Extent3d {
            width: self.panel.width().min(surface.width()),
            height: self.panel.height().min(surface.height()),
            depth_or_array_layers: 1,
        };
        encoder.copy_texture_to_texture(self.panel.as_image_copy(), surface.as_image_copy(), whole);
        let Some((texture, [x, y], [limit_x, limit_y])) = view else { return };
        let (right, bottom) = (limit_x.min(surface.width()), limit_y.min(surface.height()));
        if x >= right || y >= bottom {
            return;
        }
        let extent = wgpu::Extent3d {
            width: texture.width().min(right - x),
            height: texture.height().min(bottom - y),
            depth_or_array_layers: 1,
        };
        let destination = wgpu::TexelCopyTextureInfo {
            texture: surface,
            mip_level: 0,
            origin: wgpu::Origin3d { x, y, z: 0 },
            aspect: wgpu::TextureAspect::All,
        };
        encoder.copy_texture_to_texture(texture.as_image_copy(), destination, extent);
    }
}
