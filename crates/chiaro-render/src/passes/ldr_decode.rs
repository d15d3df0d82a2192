//! The LDR light buffer's decoding: exp2(-light) in 8 bits back to pre-exposed radiance
//! in the HDR target, which transparent draws and tone mapping then use.

use super::targets::{HDR, HDR_FORMAT};
use super::fullscreen::{self, FullscreenDesc, texture_bind_group, texture_layout};
use super::targets::LIGHT_BUFFER_LDR;
use super::gbuffer::light_target_desc;
use crate::debug_view::DebugView;
use crate::graph::{FramePass, PassContext, PassInit, PassSetup, PassType, PrepareContext};
use crate::plan::FramePlan;
use crate::shaders;
use chiaro_scene::{LightBuffer, RenderPath};

/// Decodes the LDR light buffer into the HDR target, full screen.
pub struct LdrDecodePass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl PassType for LdrDecodePass {
    const NAME: &'static str = "ldr decode";

    /// Makes the HDR target from the LDR light buffer (the overdraw view counts volumes
    /// into the HDR target itself, so there is nothing to decode).
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        let ldr = plan.path == RenderPath::Deferred && plan.light_buffer == LightBuffer::LdrExp2;
        if ldr && plan.request.debug != Some(DebugView::LightOverdraw) {
            pass.read(LIGHT_BUFFER_LDR).create(HDR, light_target_desc(LightBuffer::Hdr));
        }
    }

    fn new(init: &PassInit<'_>) -> LdrDecodePass {
        let device = init.device;
        let layout =
            texture_layout(device, "ldr decode layout", &[wgpu::TextureSampleType::Float { filterable: false }]);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("ldr decode pipeline layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = shaders::module(device, "ldr decode", crate::wgsl!("ldr_decode"));
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
    fn prepare(&mut self, _cx: &PrepareContext<'_>) {}

    fn record(&self, cx: &mut PassContext<'_>) {
        let bind_group = texture_bind_group(cx.device, &self.layout, &[cx.targets.view(LIGHT_BUFFER_LDR)]);
        let timestamp_writes = cx.timestamp_writes();
        fullscreen::draw(
            cx.encoder,
            "ldr decode pass",
            cx.targets.view(HDR),
            &self.pipeline,
            &bind_group,
            timestamp_writes,
        );
    }
}
