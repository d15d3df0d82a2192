//! The contact depth pass, when a frame has contact shadows (`[shadows] contact`), marks
//! virtual pages or has ambient occlusion (`FramePlan::copies_scene_depth`): after
//! the scene depth is drawn (the forward path's prepass, the deferred path's G-buffer)
//! and before anything is lit, a compute pass copies it, one float per pixel, into the
//! storage buffer of group 0 that the contact shadows' march reads
//! (`shaders/shadows/contact.wesl`). A buffer rather than the depth texture itself: the
//! passes that march keep the depth target attached, and the forward shader already binds
//! the 16 sampled textures every device has.

use super::mesh::forward_depth;
use crate::graph::{FramePass, PassContext, PassInit, PassSetup, PassType, PrepareContext};
use crate::plan::FramePlan;
use crate::shaders;

/// The compute pipelines' workgroup side (`@workgroup_size(8, 8)`).
const WORKGROUP_SIDE: u32 = 8;

/// Copies the scene depth into group 0's view depth buffer.
pub struct ContactDepthPass {
    single: wgpu::ComputePipeline,
    multisampled: wgpu::ComputePipeline,
}

impl PassType for ContactDepthPass {
    const NAME: &'static str = "contact depth";

    /// Reads the depth every later pass of the frame tests against; what it writes is a
    /// buffer outside the graph, so it declares a side effect (it is listed before the
    /// passes that read the buffer, which run after it).
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        if plan.copies_scene_depth() {
            pass.read(forward_depth(plan)).side_effect();
        }
    }

    fn new(init: &PassInit<'_>) -> ContactDepthPass {
        let module = shaders::module(init.device, "contact depth", crate::wgsl!("contact_depth"));
        let pipeline = |entry: &str| shaders::compute_pipeline(init.device, &module, entry);
        ContactDepthPass { single: pipeline("cs_single"), multisampled: pipeline("cs_multisampled") }
    }
}

impl FramePass for ContactDepthPass {
    fn prepare(&mut self, _cx: &PrepareContext<'_>) {}

    fn record(&self, cx: &mut PassContext<'_>) {
        let Some(depth) = cx.targets.texture(forward_depth(cx.plan)) else {
            return;
        };
        let multisampled = depth.sample_count() > 1;
        let (pipeline, texture_binding) = if multisampled { (&self.multisampled, 2) } else { (&self.single, 0) };
        let depth_only = depth.create_view(&wgpu::TextureViewDescriptor {
            label: Some("contact depth source"),
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        });
        let bind_group = cx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("contact depth bind group"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: texture_binding, resource: wgpu::BindingResource::TextureView(&depth_only) },
                wgpu::BindGroupEntry { binding: 1, resource: cx.view_depths.as_entire_binding() },
            ],
        });
        let timestamp_writes = cx.timestamps.map(|t| t.compute_writes());
        let mut pass =
            cx.encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("contact depth pass"), timestamp_writes });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        let size = depth.size();
        pass.dispatch_workgroups(size.width.div_ceil(WORKGROUP_SIDE), size.height.div_ceil(WORKGROUP_SIDE), 1);
    }
}
