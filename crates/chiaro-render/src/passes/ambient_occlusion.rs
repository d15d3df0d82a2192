//! The ambient occlusion pass, where a frame has it (`[ambient_occlusion] enabled`): after
//! the contact depth pass has copied the scene depth to group 0's view depth buffer and
//! before anything is shaded, compute passes estimate the AO of every 2x2 pixels from
//! the depth (`shaders/ambient_occlusion.wesl`), denoise it and upsample it into group
//! 0's `AMBIENT_OCCLUSION` buffer, which indirect light reads
//! (`shaders/lighting/occlusion.wesl`).

use super::mesh::forward_depth;
use crate::frame_bindings::binding_of;
use crate::graph::{FramePass, PassContext, PassInit, PassSetup, PassType, PrepareContext, Target};
use crate::plan::FramePlan;
use crate::shaders;
use bytemuck::{Pod, Zeroable};
use chiaro_scene::AmbientOcclusionSettings;

/// What a frame reads back of the pass: its AO buffer, one float a pixel (not a target of
/// the graph; the name keys it among the read-backs).
pub const AMBIENT_OCCLUSION: Target = Target("ambient occlusion");

/// The compute pipelines' workgroup side (`@workgroup_size(8, 8)`).
const WORKGROUP_SIDE: u32 = 8;
/// The bindings of the pass's own resources, past group 0's.
const PARAMS_BINDING: u32 = 101;
const RAW_OUT_BINDING: u32 = 102;
const RAW_IN_BINDING: u32 = 103;
const DENOISED_OUT_BINDING: u32 = 104;
const DENOISED_IN_BINDING: u32 = 105;
const UPSAMPLED_BINDING: u32 = 106;

/// `OcclusionParams` in the shader.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct GpuOcclusionParams {
    radius_m: f32,
    thickness_m: f32,
    intensity: f32,
    slices: u32,
    steps: u32,
    _pad: [u32; 3],
}

impl GpuOcclusionParams {
    /// The shader's parameters for `settings`.
    pub fn new(settings: &AmbientOcclusionSettings) -> GpuOcclusionParams {
        GpuOcclusionParams {
            radius_m: settings.radius,
            thickness_m: settings.thickness,
            intensity: settings.intensity,
            slices: settings.quality.slices(),
            steps: settings.quality.steps(),
            _pad: [0; 3],
        }
    }
}

/// Estimates and denoises each pixel's ambient occlusion.
pub struct AmbientOcclusionPass {
    estimate: wgpu::ComputePipeline,
    denoise: wgpu::ComputePipeline,
    upsample: wgpu::ComputePipeline,
    params: wgpu::Buffer,
}

impl PassType for AmbientOcclusionPass {
    const NAME: &'static str = "ambient occlusion";

    /// Reads the depth the contact depth pass copied (it is listed after that pass); what
    /// it writes is a buffer group 0 binds, outside the graph: a side effect.
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        if plan.features.ambient_occlusion {
            pass.read(forward_depth(plan)).side_effect();
        }
    }

    fn new(init: &PassInit<'_>) -> AmbientOcclusionPass {
        let module = shaders::module(init.device, "ambient occlusion", crate::wgsl!("ambient_occlusion"));
        let pipeline = |entry: &str| shaders::compute_pipeline(init.device, &module, entry);
        let params = init.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ambient occlusion parameters"),
            size: size_of::<GpuOcclusionParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        AmbientOcclusionPass {
            estimate: pipeline("cs_estimate"),
            denoise: pipeline("cs_denoise"),
            upsample: pipeline("cs_upsample"),
            params,
        }
    }
}

impl FramePass for AmbientOcclusionPass {
    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        if cx.plan.features.ambient_occlusion {
            let params = GpuOcclusionParams::new(&cx.plan.ambient_occlusion);
            cx.queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        }
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        fn binding(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
        }
        let frame = cx.marking.frame;
        let buffers = cx.occlusion;
        let estimate_group = cx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ambient occlusion estimate"),
            layout: &self.estimate.get_bind_group_layout(0),
            entries: &[
                binding(binding_of("FRAME"), frame),
                binding(binding_of("VIEW_DEPTHS"), cx.view_depths),
                binding(PARAMS_BINDING, &self.params),
                binding(RAW_OUT_BINDING, buffers.raw),
            ],
        });
        let denoise_group = cx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ambient occlusion denoise"),
            layout: &self.denoise.get_bind_group_layout(0),
            entries: &[
                binding(binding_of("FRAME"), frame),
                binding(PARAMS_BINDING, &self.params),
                binding(RAW_IN_BINDING, buffers.raw),
                binding(DENOISED_OUT_BINDING, buffers.half),
            ],
        });
        let upsample_group = cx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ambient occlusion upsample"),
            layout: &self.upsample.get_bind_group_layout(0),
            entries: &[
                binding(binding_of("FRAME"), frame),
                binding(binding_of("VIEW_DEPTHS"), cx.view_depths),
                binding(PARAMS_BINDING, &self.params),
                binding(RAW_IN_BINDING, buffers.raw),
                binding(DENOISED_IN_BINDING, buffers.half),
                binding(UPSAMPLED_BINDING, buffers.denoised),
            ],
        });
        let timestamp_writes = cx.timestamps.map(|t| t.compute_writes());
        let mut pass = cx
            .encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("ambient occlusion"), timestamp_writes });
        let (width, height) = (cx.plan.view.width, cx.plan.view.height);
        // The estimate and the denoise at half resolution, a texel per 2x2 pixels.
        let (half_width, half_height) = (width.div_ceil(2), height.div_ceil(2));
        pass.set_pipeline(&self.estimate);
        pass.set_bind_group(0, &estimate_group, &[]);
        pass.dispatch_workgroups(half_width.div_ceil(WORKGROUP_SIDE), half_height.div_ceil(WORKGROUP_SIDE), 1);
        pass.set_pipeline(&self.denoise);
        pass.set_bind_group(0, &denoise_group, &[]);
        pass.dispatch_workgroups(half_width.div_ceil(WORKGROUP_SIDE), half_height.div_ceil(WORKGROUP_SIDE), 1);
        pass.set_pipeline(&self.upsample);
        pass.set_bind_group(0, &upsample_group, &[]);
        pass.dispatch_workgroups(width.div_ceil(WORKGROUP_SIDE), height.div_ceil(WORKGROUP_SIDE), 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_match_the_shader_layout() {
        // A uniform struct is rounded up to 16 bytes; five scalars and padding.
        assert_eq!(size_of::<GpuOcclusionParams>(), 32);
    }
}
