//! Targets as passes declare them: a name (a constant in the module of the pass that
//! makes it) and a full description (format, size rule, usages, samples, layers). The
//! graph turns declarations into textures (`targets::Targets`).

use std::fmt;

/// A texture of the frame, named by the pass module that declares it
/// (`targets::HDR`, `aov::POSITION`, ...).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Target(pub &'static str);

impl fmt::Display for Target {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
}

/// The tone-mapped, display-encoded image: the renderer's texture or a caller's (a
/// window's surface). Every frame writes it.
pub const OUTPUT: Target = Target("output");

/// How big a target is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Size {
    /// The view's width and height.
    View,
    /// A square of this many texels a side (the shadow atlases). For a persistent target,
    /// 0 means "unused this frame": it keeps the texture it has (1 texel if none yet).
    Square(u32),
}

/// Everything needed to make a target's texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TargetDesc {
    /// Its width and height, fixed or the view's.
    pub size: Size,
    /// The texel format.
    pub format: wgpu::TextureFormat,
    /// What the texture is used for.
    pub usage: wgpu::TextureUsages,
    /// Samples per texel (1 unless multisampled).
    pub samples: u32,
    /// Array layers (1 for a plain 2D target).
    pub layers: u32,
}

impl TargetDesc {
    /// A single-sampled, single-layer target the size of the view.
    pub fn view_sized(format: wgpu::TextureFormat, usage: wgpu::TextureUsages) -> TargetDesc {
        TargetDesc { size: Size::View, format, usage, samples: 1, layers: 1 }
    }

    /// A square target `texels` a side.
    pub fn square(texels: u32, format: wgpu::TextureFormat, usage: wgpu::TextureUsages) -> TargetDesc {
        TargetDesc { size: Size::Square(texels), format, usage, samples: 1, layers: 1 }
    }

    /// The same target with `samples` samples per texel.
    pub fn with_samples(self, samples: u32) -> TargetDesc {
        TargetDesc { samples, ..self }
    }

    /// The same target with `layers` array layers.
    pub fn with_layers(self, layers: u32) -> TargetDesc {
        TargetDesc { layers, ..self }
    }

    /// Width and height in texels for a view of `width` x `height` pixels.
    pub fn extent(&self, width: u32, height: u32) -> (u32, u32) {
        match self.size {
            Size::View => (width, height),
            Size::Square(texels) => (texels, texels),
        }
    }
}

/// Drawn into, and read back.
pub const ATTACHMENT_COPY: wgpu::TextureUsages =
    wgpu::TextureUsages::RENDER_ATTACHMENT.union(wgpu::TextureUsages::COPY_SRC);
/// Drawn into, sampled by a later pass, and read back.
pub const ATTACHMENT_SAMPLED: wgpu::TextureUsages = ATTACHMENT_COPY.union(wgpu::TextureUsages::TEXTURE_BINDING);
