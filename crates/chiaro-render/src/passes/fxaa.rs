//! The deferred path's antialiasing: FXAA (shaders/fxaa.wesl) over the lit HDR image,
//! transparent draws included, before tone mapping, where the forward path resolves its
//! MSAA samples. The image is copied aside first and filtered back into `HDR`, so every
//! later pass and the read-back see the smoothed frame.

use super::targets::{HDR, HDR_FORMAT};
use super::fullscreen::{self, FullscreenDesc};
use crate::graph::{FramePass, PassContext, PassInit, PassSetup, PassType, PrepareContext, Target, TargetDesc};
use crate::plan::FramePlan;
use crate::shaders;

/// The lit image before antialiasing, which the filter reads.
pub const HDR_BEFORE_FXAA: Target = Target("hdr before fxaa");

/// FXAA over the deferred path's HDR image.
pub struct FxaaPass {
    layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    pipeline: wgpu::RenderPipeline,
}

impl PassType for FxaaPass {
    const NAME: &'static str = "fxaa";

    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        if plan.fxaa {
            let usage = wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::TEXTURE_BINDING;
            pass.modify(HDR).create(HDR_BEFORE_FXAA, TargetDesc::view_sized(HDR_FORMAT, usage));
        }
    }

    fn new(init: &PassInit<'_>) -> FxaaPass {
        let device = init.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fxaa layout"),
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
        });
        // Bilinear between texels: the walk and the blend read between pixel centres.
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("fxaa bilinear"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("fxaa pipeline layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = shaders::module(device, "fxaa", crate::wgsl!("fxaa"));
        let pipeline = fullscreen::pipeline(
            device,
            FullscreenDesc {
                label: "fxaa",
                module: &module,
                layout: &pipeline_layout,
                fragment_entry: "fs_fxaa",
                constants: &[],
                format: HDR_FORMAT,
            },
        );
        FxaaPass { layout, sampler, pipeline }
    }
}

impl FramePass for FxaaPass {
    fn prepare(&mut self, _cx: &PrepareContext<'_>) {}

    fn record(&self, cx: &mut PassContext<'_>) {
        let (Some(hdr), Some(before)) = (cx.targets.texture(HDR), cx.targets.texture(HDR_BEFORE_FXAA)) else {
            return;
        };
        cx.encoder.copy_texture_to_texture(hdr.as_image_copy(), before.as_image_copy(), hdr.size());
        let bind_group = cx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("fxaa bind group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(cx.targets.view(HDR_BEFORE_FXAA)),
                },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&self.sampler) },
            ],
        });
        let timestamp_writes = cx.timestamp_writes();
        fullscreen::draw(cx.encoder, "fxaa pass", cx.targets.view(HDR), &self.pipeline, &bind_group, timestamp_writes);
    }
}
