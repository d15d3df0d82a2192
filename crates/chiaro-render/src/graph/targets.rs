//! The textures a frame's passes read and write, named by `Resource` and kept from frame
//! to frame: a target is made again only when its size or format changes. Transient
//! targets live for one frame's work but are reused by the next; the shadow atlases
//! persist (so that tiles can later be cached); the output may be a texture of the
//! caller's, such as a window's surface.

use std::collections::HashMap;

/// A texture of the frame, as passes declare what they read and write.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Resource {
    DirectionalShadowAtlas,
    OtherShadowAtlas,
    /// Reverse-Z depth with stencil.
    Depth,
    /// Pre-exposed linear radiance.
    Hdr,
    /// The forward path's multisampled depth and radiance (`FramePlan::msaa` samples);
    /// the radiance resolves into `Hdr`.
    DepthMultisampled,
    HdrMultisampled,
    /// The deferred path's base colour and metallic.
    GBufferAlbedoMetallic,
    /// The deferred path's normals, view depth, roughness and flags.
    GBufferPacked,
    /// The deferred path's legacy LDR light buffer, exp2(-light).
    LightBufferLdr,
    /// World position, alpha 1 where a surface is.
    AovPosition,
    /// World normal and linear view depth.
    AovNormalDepth,
    /// Baked irradiance (RGB) and whether a bake lights the pixel (A).
    AovBaked,
    /// One light's shadow term and coverage.
    AovShadow,
    /// The tone-mapped, display-encoded image.
    Output,
}

impl Resource {
    /// Lives across frames rather than being written afresh by each.
    pub fn persistent(self) -> bool {
        matches!(self, Resource::DirectionalShadowAtlas | Resource::OtherShadowAtlas)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TargetDesc {
    pub width: u32,
    pub height: u32,
    pub format: wgpu::TextureFormat,
    pub usage: wgpu::TextureUsages,
    pub samples: u32,
}

struct Target {
    desc: TargetDesc,
    texture: wgpu::Texture,
    view: wgpu::TextureView,
}

/// The frame's textures by resource, and an output view the caller may lend instead.
#[derive(Default)]
pub struct Targets {
    owned: HashMap<Resource, Target>,
    external_output: Option<wgpu::TextureView>,
}

impl Targets {
    /// Makes `resource` match `desc`; returns whether it was (re)created, so its old
    /// contents are gone.
    pub fn ensure(&mut self, device: &wgpu::Device, resource: Resource, desc: TargetDesc) -> bool {
        if self.owned.get(&resource).is_some_and(|t| t.desc == desc) {
            return false;
        }
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(&format!("{resource:?}")),
            size: wgpu::Extent3d { width: desc.width, height: desc.height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: desc.samples,
            dimension: wgpu::TextureDimension::D2,
            format: desc.format,
            usage: desc.usage,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        self.owned.insert(resource, Target { desc, texture, view });
        true
    }

    /// Renders the output into `view` (owned by the caller) until `clear_external_output`.
    pub fn set_external_output(&mut self, view: Option<wgpu::TextureView>) {
        self.external_output = view;
    }

    pub fn view(&self, resource: Resource) -> &wgpu::TextureView {
        if resource == Resource::Output
            && let Some(view) = &self.external_output
        {
            return view;
        }
        &self.owned.get(&resource).unwrap_or_else(|| panic!("{resource:?} was never made")).view
    }

    /// The texture of an owned target (the external output has none to read back).
    pub fn texture(&self, resource: Resource) -> Option<&wgpu::Texture> {
        if resource == Resource::Output && self.external_output.is_some() {
            return None;
        }
        self.owned.get(&resource).map(|t| &t.texture)
    }
}
