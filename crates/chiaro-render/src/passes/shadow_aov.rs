//! The shadow AOV pass, run once per scene light after the frame: the shadow term the
//! shading used for that light (1 lit, 0 shadowed) and coverage, for the surface the
//! forward pass kept in each pixel. Not part of the frame's pass list: the renderer runs
//! it per light when shadow AOVs are asked for.

use super::mesh::{DepthTest, MeshPipelines, MeshPipelinesDesc, cleared, scene_depth};
use crate::gpu::GpuAovLight;
use crate::graph::{PassContext, PassIo, Resource};
use crate::plan::FramePlan;
use crate::scene::GpuScene;
use crate::shaders;

/// Shadow term, coverage.
pub const SHADOW_AOV_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;

pub struct ShadowAovPass {
    pipelines: MeshPipelines,
    light_layout: wgpu::BindGroupLayout,
    /// One `GpuAovLight` per scene light, each at a multiple of `stride`.
    lights: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    stride: u64,
}

impl ShadowAovPass {
    pub fn new(
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        material_layout: &wgpu::BindGroupLayout,
        depth_format: wgpu::TextureFormat,
    ) -> ShadowAovPass {
        let light_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("aov light layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(size_of::<GpuAovLight>() as u64),
                },
                count: None,
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow aov pipeline layout"),
            bind_group_layouts: &[Some(frame_layout), Some(material_layout), Some(&light_layout)],
            immediate_size: 0,
        });
        let alignment = device.limits().min_uniform_buffer_offset_alignment as u64;
        ShadowAovPass {
            pipelines: MeshPipelines::new(MeshPipelinesDesc {
                label: "shadow aov",
                module: shaders::module(device, "shadow aov", shaders::SHADOW_AOV),
                fragment_entry: Some("fs_shadow_aov"),
                layout,
                color_formats: vec![SHADOW_AOV_FORMAT],
                blends: false,
                depth_test: DepthTest::SameSurface,
                depth_format,
                marks_stencil: false,
                constants: Vec::new(),
                alpha_test_override: None,
            }),
            light_layout,
            lights: None,
            stride: (size_of::<GpuAovLight>() as u64).div_ceil(alignment) * alignment,
        }
    }

    pub fn io() -> PassIo {
        PassIo {
            reads: vec![Resource::Depth, Resource::DirectionalShadowAtlas, Resource::OtherShadowAtlas],
            writes: vec![Resource::AovShadow, Resource::Depth],
        }
    }

    /// Uploads the lights to report, one per scene light: its index in the frame's light
    /// buffer (`NO_LIGHT` where the frame does not shade it). Makes the pipelines.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        plan: &FramePlan,
        scene: &GpuScene,
        light_indices: &[u32],
    ) {
        self.pipelines.prepare(device, &scene.draws, &plan.camera_draws, 1);
        let size = self.stride * light_indices.len().max(1) as u64;
        if self.lights.as_ref().is_none_or(|(buffer, _)| buffer.size() < size) {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("aov lights"),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("aov light bind group"),
                layout: &self.light_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &buffer,
                        offset: 0,
                        size: wgpu::BufferSize::new(size_of::<GpuAovLight>() as u64),
                    }),
                }],
            });
            self.lights = Some((buffer, bind_group));
        }
        let (buffer, _) = self.lights.as_ref().expect("made above");
        let mut bytes = vec![0u8; size as usize];
        for (k, &light_index) in light_indices.iter().enumerate() {
            let at = k * self.stride as usize;
            let value = GpuAovLight { light_index, _pad: [0; 3] };
            bytes[at..at + size_of::<GpuAovLight>()].copy_from_slice(bytemuck::bytes_of(&value));
        }
        queue.write_buffer(buffer, 0, &bytes);
    }

    /// Records the pass for the `k`th of the prepared lights.
    pub fn record(&self, cx: &mut PassContext<'_>, k: usize) {
        let (_, light_bind_group) = self.lights.as_ref().expect("prepared");
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow aov pass"),
            color_attachments: &[cleared(cx.targets.view(Resource::AovShadow), wgpu::Color::TRANSPARENT)],
            depth_stencil_attachment: Some(scene_depth(cx.targets.view(Resource::Depth), true)),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, cx.frame_bind_group, &[]);
        pass.set_bind_group(2, light_bind_group, &[(k as u64 * self.stride) as u32]);
        self.pipelines.draw(&mut pass, cx.scene, &cx.plan.camera_draws);
    }
}
