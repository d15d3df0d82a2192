//! Draws the area lights' outlines (light_shapes.rs) over the 3D view, after the frame:
//! one-pixel lines, no depth test (a gizmo, as a modelling tool draws its lights, seen
//! through what stands in front), into the view texture only. Screenshots render the
//! view again without them, so they stay what `chiaro render` writes.

use crate::light_shapes::LineVertex;
use wgpu::util::DeviceExt;

const SHADER: &str = "
struct Out { @builtin(position) position: vec4<f32>, @location(0) color: vec4<f32> };
@vertex fn vs(@location(0) clip: vec4<f32>, @location(1) color: vec4<f32>) -> Out {
    return Out(clip, color);
}
@fragment fn fs(in: Out) -> @location(0) vec4<f32> { return in.color; }
";

pub struct LightOverlay {
    pipeline: wgpu::RenderPipeline,
}

impl LightOverlay {
    /// The pipeline for a view texture of `format`.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> LightOverlay {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("light shapes"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<LineVertex>() as wgpu::BufferAddress,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4],
        };
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("light shapes"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[Some(vertex_layout)],
            },
            primitive: wgpu::PrimitiveState { topology: wgpu::PrimitiveTopology::LineList, ..Default::default() },
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        LightOverlay { pipeline }
    }

    /// Draws `lines` (vertex pairs) over `target` and submits; nothing where there are none.
    pub fn draw(&self, device: &wgpu::Device, queue: &wgpu::Queue, target: &wgpu::TextureView, lines: &[LineVertex]) {
        if lines.is_empty() {
            return;
        }
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light shapes"),
            contents: bytemuck::cast_slice(lines),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("light shapes") });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("light shapes"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_vertex_buffer(0, vertices.slice(..));
            pass.draw(0..lines.len() as u32, 0..1);
        }
        queue.submit([encoder.finish()]);
    }
}
