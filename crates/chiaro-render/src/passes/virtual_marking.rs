//! The virtual page marking pass, in the frame that marks another's pages
//! (`FramePlan::marks_pages`, `[shadows] technique = "virtual"`): after the contact depth
//! pass has copied the scene depth to group 0's view depth buffer, a compute pass sets,
//! per pixel, the bits of the pages each virtual-shadowed light's lookup will want
//! (`shaders/virtual_marking.wesl`). The renderer reads the bits back and places the pages
//! before it plans the frame's shadow tiles.

use super::mesh::forward_depth;
use crate::frame_bindings::binding_of;
use crate::graph::{FramePass, PassContext, PassInit, PassSetup, PassType, PrepareContext};
use crate::plan::FramePlan;
use crate::shaders;

/// The compute pipeline's workgroup side (`@workgroup_size(8, 8)`).
const WORKGROUP_SIDE: u32 = 8;
/// The request bits' binding in the marking shader's own group.
const REQUESTS_BINDING: u32 = 100;

/// Marks the pages the frame's pixels want.
pub struct VirtualMarkingPass {
    pipeline: wgpu::ComputePipeline,
}

impl PassType for VirtualMarkingPass {
    const NAME: &'static str = "virtual page marking";

    /// Reads the depth the contact depth pass copied (it is listed after that pass); what
    /// it writes is a buffer the renderer reads back: a side effect.
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        if plan.marks_pages {
            pass.read(forward_depth(plan)).side_effect();
        }
    }

    fn new(init: &PassInit<'_>) -> VirtualMarkingPass {
        let module = shaders::module(init.device, "virtual page marking", crate::wgsl!("virtual_marking"));
        VirtualMarkingPass { pipeline: shaders::compute_pipeline(init.device, &module, "cs_mark") }
    }
}

impl FramePass for VirtualMarkingPass {
    fn prepare(&mut self, _cx: &PrepareContext<'_>) {}

    fn record(&self, cx: &mut PassContext<'_>) {
        let buffers = cx.marking;
        let bytes = cx.plan.shadows.virtual_maps.request_bytes();
        cx.encoder.clear_buffer(buffers.page_requests, 0, Some(bytes));
        fn binding(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
        }
        let bind_group = cx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("virtual page marking bind group"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &[
                binding(binding_of("FRAME"), buffers.frame),
                binding(binding_of("SHADOWS"), buffers.shadows),
                binding(binding_of("VIEW_DEPTHS"), cx.view_depths),
                binding(REQUESTS_BINDING, buffers.page_requests),
            ],
        });
        let timestamp_writes = cx.timestamps.map(|t| t.compute_writes());
        let mut pass = cx
            .encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("virtual page marking"), timestamp_writes });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        let (width, height) = (cx.plan.view.width, cx.plan.view.height);
        pass.dispatch_workgroups(width.div_ceil(WORKGROUP_SIDE), height.div_ceil(WORKGROUP_SIDE), 1);
    }
}
