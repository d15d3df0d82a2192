//! The lit opaque image as a mip chain, made in the forward pass between its solid and
//! its transmissive draws, which refract it (KHR_materials_transmission): mip 0 copies
//! the HDR target, each later mip averages the one before (`shaders/opaque_copy.wesl`).
//! Rough transmissive surfaces read the blurrier mips. Bound as group 2 of the
//! transmissive draws' pipelines.

use super::fullscreen::{FullscreenDesc, pipeline};
use super::targets::HDR_FORMAT;
use crate::shaders;

/// The copy's texture at one size, its per-mip views and bind groups.
struct CopyImage {
    size: (u32, u32),
    mip_views: Vec<wgpu::TextureView>,
    /// Group 2 of the transmissive pipelines: the whole chain and its sampler.
    group: wgpu::BindGroup,
}

/// The copy's pipelines, layouts and (once a frame needs it) its image.
pub struct OpaqueCopy {
    copy: wgpu::RenderPipeline,
    downsample: wgpu::RenderPipeline,
    source_layout: wgpu::BindGroupLayout,
    /// Group 2 of the transmissive draws' pipelines: the chain and its sampler.
    pub group_layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    image: Option<CopyImage>,
}

/// A layout of one filterable 2D texture (binding 0) and its sampler (binding 1).
fn texture_and_sampler_layout(device: &wgpu::Device, label: &str) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ],
    })
}

impl OpaqueCopy {
    /// The pipelines; the image is made by `prepare` when a frame has transmissive draws.
    pub fn new(device: &wgpu::Device) -> OpaqueCopy {
        let module = shaders::module(device, "opaque copy", crate::wgsl!("opaque_copy"));
        let source_layout = texture_and_sampler_layout(device, "opaque copy source");
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("opaque copy"),
            bind_group_layouts: &[Some(&source_layout)],
            immediate_size: 0,
        });
        let make = |entry: &str| {
            pipeline(
                device,
                FullscreenDesc {
                    label: entry,
                    module: &module,
                    layout: &layout,
                    fragment_entry: entry,
                    constants: &[],
                    format: HDR_FORMAT,
                },
            )
        };
        OpaqueCopy {
            copy: make("fs_copy"),
            downsample: make("fs_downsample"),
            source_layout,
            group_layout: texture_and_sampler_layout(device, "opaque image"),
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("opaque image"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                ..Default::default()
            }),
            image: None,
        }
    }

    /// Makes the chain for a `width` x `height` image, unless it has it already.
    pub fn prepare(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        if self.image.as_ref().is_some_and(|i| i.size == (width, height)) {
            return;
        }
        let mip_level_count = 32 - width.max(height).max(1).leading_zeros();
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("opaque image"),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: HDR_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let mip_views = (0..mip_level_count)
            .map(|mip| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    base_mip_level: mip,
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let whole = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let group = self.bind_group(device, &self.group_layout, &whole);
        self.image = Some(CopyImage { size: (width, height), mip_views, group });
    }

    fn bind_group(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        view: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("opaque image"),
            layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(view) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&self.sampler) },
            ],
        })
    }

    /// Records the copy of `hdr` and its mips. `prepare` must have made the chain.
    pub fn record(&self, device: &wgpu::Device, encoder: &mut wgpu::CommandEncoder, hdr: &wgpu::TextureView) {
        let image = self.image.as_ref().expect("prepared before recording");
        let mut source = self.bind_group(device, &self.source_layout, hdr);
        for (mip, target) in image.mip_views.iter().enumerate() {
            let pipeline = if mip == 0 { &self.copy } else { &self.downsample };
            super::fullscreen::draw(encoder, "opaque copy", target, pipeline, &source, None);
            source = self.bind_group(device, &self.source_layout, target);
        }
    }

    /// Group 2 of the transmissive draws. `prepare` must have made the chain.
    pub fn group(&self) -> &wgpu::BindGroup {
        &self.image.as_ref().expect("prepared before recording").group
    }
}
