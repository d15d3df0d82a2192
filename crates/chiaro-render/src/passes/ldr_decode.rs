//! The LDR light buffer's decoding: exp2(-light) in 8 bits back to pre-exposed radiance
//! in the HDR target, which transparent draws and tone mapping then use.

use super::forward::HDR_FORMAT;
use super::fullscreen::{self, FullscreenDesc, texture_bind_group, texture_layout};
use crate::graph::{FramePass, PassContext, PassIo, PrepareContext, Resource};
use crate::plan::{FramePlan, PassId};
use crate::shaders;

pub struct LdrDecodePass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl LdrDecodePass {
    pub fn new(device: &wgpu::Device) -> LdrDecodePass {
        let layout =
            texture_layout(device, "ldr decode layout", &[wgpu::TextureSampleType::Float { filterable: false }]);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("ldr decode pipeline layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = shaders::module(device, "ldr decode", shaders::LDR_DECODE);
        let pipeline = fullscreen::pipeline(
            device,
            FullscreenDesc {
                label: "ldr decode",
                module: &module,
                layout: &pipeline_layout,
                fragment_entry: "fs_decode",
                constants: &[],
                format: HDR_FORMAT,
            },
        );
        LdrDecodePass { layout, pipeline }
    }
}

impl FramePass for LdrDecodePass {
    fn id(&self) -> PassId {
        PassId::LdrDecode
    }

    fn io(&self, _plan: &FramePlan) -> PassIo {
        PassIo { reads: vec![Resource::LightBufferLdr], writes: vec![Resource::Hdr] }
    }

    fn prepare(&mut self, _cx: &PrepareContext<'_>) {}

    fn record(&self, cx: &mut PassContext<'_>) {
        let bind_group = texture_bind_group(cx.device, &self.layout, &[cx.targets.view(Resource::LightBufferLdr)]);
        let timestamp_writes = cx.timestamp_writes();
        fullscreen::draw(
            cx.encoder,
            "ldr decode pass",
            cx.targets.view(Resource::Hdr),
            &self.pipeline,
            &bind_group,
            timestamp_writes,
        );
    }
}
