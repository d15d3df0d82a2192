//! Debug views of the deferred path, straight to the output: the G-buffer's base colour
//! or shading normal, or the light overdraw count (the light pass's target in its
//! counting variant) as a heat map.

use super::fullscreen::{self, FullscreenDesc, texture_bind_group, texture_layout};
use crate::debug_view::DebugView;
use super::targets::HDR;
use super::targets::{GBUFFER_ALBEDO_METALLIC, GBUFFER_PACKED};
use crate::graph::{FramePass, OUTPUT, PassContext, PassInit, PassSetup, PassType, PrepareContext};
use crate::overrides;
use crate::plan::FramePlan;
use crate::shaders;
use std::collections::HashMap;

/// Draws a deferred debug view (G-buffer colour or normal, light overdraw) to the output.
pub struct DebugViewPass {
    module: wgpu::ShaderModule,
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: HashMap<(DebugView, wgpu::TextureFormat), wgpu::RenderPipeline>,
    key: Option<(DebugView, wgpu::TextureFormat)>,
}

/// The shader's `view` override.
fn view_index(view: DebugView) -> f64 {
    match view {
        DebugView::GbufferAlbedo => 0.0,
        DebugView::GbufferNormal => 1.0,
        DebugView::LightOverdraw => 2.0,
        other => unreachable!("{other:?} is not drawn by the debug view pass"),
    }
}

impl PassType for DebugViewPass {
    const NAME: &'static str = "debug view";

    /// Writes the output after tone mapping would, so a deferred debug view replaces the
    /// image (and the passes only the image needed are culled).
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        let Some(view) = plan.request.deferred_view() else { return };
        pass.read(GBUFFER_ALBEDO_METALLIC).read(GBUFFER_PACKED).write(OUTPUT);
        if view == DebugView::LightOverdraw {
            pass.read(HDR);
        }
    }

    fn new(init: &PassInit<'_>) -> DebugViewPass {
        let device = init.device;
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let layout =
            texture_layout(device, "debug view layout", &[unfilterable, wgpu::TextureSampleType::Uint, unfilterable]);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("debug view pipeline layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        DebugViewPass {
            module: shaders::module(device, "debug view", crate::wgsl!("debug_view")),
            layout,
            pipeline_layout,
            pipelines: HashMap::new(),
            key: None,
        }
    }
}

impl FramePass for DebugViewPass {
    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        let view = cx.plan.request.deferred_view().expect("planned for a debug view");
        let key = (view, cx.output_format);
        if !self.pipelines.contains_key(&key) {
            let constants = [overrides::DEBUG_VIEW.value(view_index(view))];
            let pipeline = fullscreen::pipeline(
                cx.device,
                FullscreenDesc {
                    label: "debug view",
                    module: &self.module,
                    layout: &self.pipeline_layout,
                    fragment_entry: "fs_debug",
                    constants: &constants,
                    format: cx.output_format,
                },
            );
            self.pipelines.insert(key, pipeline);
        }
        self.key = Some(key);
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        let key = self.key.expect("prepared");
        // The albedo target (same format) stands in for the count the view does not read.
        let count = if key.0 == DebugView::LightOverdraw { HDR } else { GBUFFER_ALBEDO_METALLIC };
        let bind_group = texture_bind_group(
            cx.device,
            &self.layout,
            &[
                cx.targets.view(GBUFFER_ALBEDO_METALLIC),
                cx.targets.view(GBUFFER_PACKED),
                cx.targets.view(count),
            ],
        );
        let timestamp_writes = cx.timestamp_writes();
        fullscreen::draw(
            cx.encoder,
            "debug view pass",
            cx.targets.view(OUTPUT),
            &self.pipelines[&key],
            &bind_group,
            timestamp_writes,
        );
    }
}
