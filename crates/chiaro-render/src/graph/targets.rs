//! The textures behind a frame's targets, kept from frame to frame: a compiled graph's
//! target descriptions flow in, views flow out to the passes. A texture is made again
//! only when its description (at this view size) changes, so transient targets are
//! reused by the next frame and persistent ones (the shadow atlases) keep their contents.
//! The output may be a texture of the caller's, such as a window's surface.

use super::compile::FrameGraph;
use super::setup::Lifetime;
use super::target::{OUTPUT, Size, Target, TargetDesc};
use std::collections::HashMap;

/// A description resolved to texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Made {
    width: u32,
    height: u32,
    desc: TargetDesc,
}

struct Texture {
    made: Made,
    texture: wgpu::Texture,
    view: wgpu::TextureView,
}

/// The frame's textures by target, and an output view the caller may lend instead.
#[derive(Default)]
pub struct Targets {
    owned: HashMap<Target, Texture>,
    external_output: Option<wgpu::TextureView>,
}

impl Targets {
    /// Makes every target of `graph` for a `width` x `height` view, and the output (in
    /// `output_format`) unless the caller lends one.
    pub fn ensure_for(
        &mut self,
        device: &wgpu::Device,
        graph: &FrameGraph,
        (width, height): (u32, u32),
        output: Option<TargetDesc>,
    ) {
        for (&target, &(desc, lifetime)) in &graph.targets {
            if lifetime == Lifetime::Persistent && desc.size == Size::Square(0) {
                // Unused this frame: keep what it holds, or make a placeholder to bind.
                if !self.owned.contains_key(&target) {
                    self.ensure(device, target, Made { width: 1, height: 1, desc });
                }
                continue;
            }
            let (w, h) = desc.extent(width, height);
            self.ensure(device, target, Made { width: w, height: h, desc });
        }
        if let Some(desc) = output {
            self.ensure(device, OUTPUT, Made { width, height, desc });
        }
    }

    fn ensure(&mut self, device: &wgpu::Device, target: Target, made: Made) {
        if self.owned.get(&target).is_some_and(|t| t.made == made) {
            return;
        }
        let desc = made.desc;
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(target.0),
            size: wgpu::Extent3d { width: made.width, height: made.height, depth_or_array_layers: desc.layers },
            mip_level_count: 1,
            sample_count: desc.samples,
            dimension: wgpu::TextureDimension::D2,
            format: desc.format,
            usage: desc.usage,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(if desc.layers > 1 {
                wgpu::TextureViewDimension::D2Array
            } else {
                wgpu::TextureViewDimension::D2
            }),
            ..Default::default()
        });
        self.owned.insert(target, Texture { made, texture, view });
    }

    /// Renders the output into `view` (owned by the caller) until set back to `None`.
    pub fn set_external_output(&mut self, view: Option<wgpu::TextureView>) {
        self.external_output = view;
    }

    /// The whole of `target` (every layer).
    pub fn view(&self, target: Target) -> &wgpu::TextureView {
        if target == OUTPUT
            && let Some(view) = &self.external_output
        {
            return view;
        }
        &self.owned.get(&target).unwrap_or_else(|| panic!("{target} was never made")).view
    }

    /// One layer of an array target, to render into.
    pub fn layer_view(&self, target: Target, layer: u32) -> wgpu::TextureView {
        let texture = self.texture(target).unwrap_or_else(|| panic!("{target} was never made"));
        texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(target.0),
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_array_layer: layer,
            array_layer_count: Some(1),
            ..Default::default()
        })
    }

    /// The texture of an owned target (the external output has none to read back).
    pub fn texture(&self, target: Target) -> Option<&wgpu::Texture> {
        if target == OUTPUT && self.external_output.is_some() {
            return None;
        }
        self.owned.get(&target).map(|t| &t.texture)
    }
}
