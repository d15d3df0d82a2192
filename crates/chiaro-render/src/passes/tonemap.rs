//! Tone mapping: the pre-exposed HDR target to the display-referred output, an sRGB
//! texture of the renderer's or a surface the caller lends (pipelines per output format
//! and display curve; a linear format gets the sRGB encoding in the shader).

use super::targets::HDR;
use crate::graph::{FramePass, OUTPUT, PassContext, PassInit, PassSetup, PassType, PrepareContext};
use crate::overrides;
use crate::plan::FramePlan;
use crate::shader_constants::{TONE_MAPPING_ACES, TONE_MAPPING_AGX, TONE_MAPPING_LINEAR, TONE_MAPPING_PBR_NEUTRAL};
use crate::shaders;
use chiaro_scene::ToneMapping;
use std::collections::HashMap;

/// Tone maps the HDR target into the output, with a pipeline per output format.
pub struct TonemapPass {
    module: wgpu::ShaderModule,
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: HashMap<(wgpu::TextureFormat, ToneMapping), wgpu::RenderPipeline>,
    key: Option<(wgpu::TextureFormat, ToneMapping)>,
}

impl PassType for TonemapPass {
    const NAME: &'static str = "tonemap";

    /// Always declared: a debug view that writes the output after it culls it.
    fn setup(_plan: &FramePlan, pass: &mut PassSetup) {
        pass.read(HDR).write(OUTPUT);
    }

    fn new(init: &PassInit<'_>) -> TonemapPass {
        let device = init.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tonemap layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("tonemap pipeline layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        TonemapPass {
            module: shaders::module(device, "tonemap", crate::wgsl!("tonemap")),
            layout,
            pipeline_layout,
            pipelines: HashMap::new(),
            key: None,
        }
    }
}

impl TonemapPass {
    fn create(&self, device: &wgpu::Device, format: wgpu::TextureFormat, curve: ToneMapping) -> wgpu::RenderPipeline {
        let curve_id = match curve {
            ToneMapping::PbrNeutral => TONE_MAPPING_PBR_NEUTRAL,
            ToneMapping::Aces => TONE_MAPPING_ACES,
            ToneMapping::Agx => TONE_MAPPING_AGX,
            ToneMapping::Linear => TONE_MAPPING_LINEAR,
        };
        let constants =
            [overrides::ENCODE_SRGB.flag(!format.is_srgb()), overrides::TONE_MAPPING.value(f64::from(curve_id))];
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&format!("tonemap {format:?} {curve:?}")),
            layout: Some(&self.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some("vs_fullscreen"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &self.module,
                entry_point: Some("fs_tonemap"),
                compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

impl FramePass for TonemapPass {
    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        let key = (cx.output_format, cx.plan.tone_mapping);
        if !self.pipelines.contains_key(&key) {
            let pipeline = self.create(cx.device, key.0, key.1);
            self.pipelines.insert(key, pipeline);
        }
        self.key = Some(key);
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        let bind_group = cx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("tonemap bind group"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(cx.targets.view(HDR)),
            }],
        });
        let pipeline = &self.pipelines[&self.key.expect("prepared")];
        let timestamp_writes = cx.timestamp_writes();
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("tonemap pass"),
            color_attachments: &[super::mesh::cleared(cx.targets.view(OUTPUT), wgpu::Color::BLACK)],
            depth_stencil_attachment: None,
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
}
