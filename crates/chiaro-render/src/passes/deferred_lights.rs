//! The deferred path's light pass: one draw per light over the G-buffer, adding its light
//! into the accumulation target (or multiplying exp2(-light) into the LDR buffer). A
//! directional light covers the screen; a point or spot light draws its volume twice:
//! front faces set stencil bit `STENCIL_INSIDE` where the surface lies behind them, then
//! back faces shade where the surface lies in front of them and the bit is set, clearing
//! it for the next light. Where the camera may be inside the volume, its back faces alone
//! shade (the fallback of Catlike Coding's "Rendering 15, Deferred Lights"). Every draw
//! tests `STENCIL_SURFACE`, so the sky is never shaded.

use super::targets::{HDR, HDR_FORMAT};
use super::targets::{GBUFFER_ALBEDO_METALLIC, GBUFFER_PACKED, LIGHT_BUFFER_LDR, LIGHT_BUFFER_LDR_FORMAT};
use super::gbuffer::{light_target, light_target_desc};
use super::targets::DEPTH;
use super::mesh::{STENCIL_SURFACE, scene_depth};
use super::targets::{DIRECTIONAL_ATLAS, LOCAL_ATLAS, SHADOW_TINTS};
use crate::debug_view::DebugView;
use crate::gpu::GpuVolumeLight;
use crate::overrides;
use crate::graph::{FramePass, PassContext, PassInit, PassSetup, PassType, PrepareContext, Target};
use crate::plan::FramePlan;
use crate::plan::features::ShaderFeatures;
use crate::plan::volumes::{VolumeMesh, VolumeShape, unit_pyramid, unit_sphere};
use crate::shaders;
use chiaro_scene::{LightBuffer, RenderPath};
use std::collections::HashMap;
use wgpu::util::DeviceExt;

/// Stencil bit of pixels whose surface lies behind the current volume's front faces.
const STENCIL_INSIDE: u32 = 2;

/// What the pass writes this frame: light (HDR or LDR) or a count of volumes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct Variant {
    ldr: bool,
    overdraw: bool,
    /// What the light shaders compile in (cookies, tent filters, soft cascades).
    features: ShaderFeatures,
}

impl Variant {
    fn of(plan: &FramePlan) -> Variant {
        let overdraw = plan.request.debug == Some(DebugView::LightOverdraw);
        Variant { ldr: !overdraw && plan.light_buffer == LightBuffer::LdrExp2, overdraw, features: plan.features }
    }

    fn target(self) -> Target {
        if self.ldr { LIGHT_BUFFER_LDR } else { HDR }
    }
}

struct Pipelines {
    /// Front faces mark where the surface lies behind them.
    mark: wgpu::RenderPipeline,
    /// Back faces shade the marked pixels whose surface lies in front of them.
    volume: wgpu::RenderPipeline,
    /// Back faces alone, for a camera inside the volume.
    inside: wgpu::RenderPipeline,
    /// A full-screen triangle over every surface.
    directional: wgpu::RenderPipeline,
}

/// A volume mesh on the GPU.
struct MeshBuffers {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
}

impl MeshBuffers {
    fn new(device: &wgpu::Device, label: &str, mesh: &VolumeMesh) -> MeshBuffers {
        let positions: Vec<[f32; 3]> = mesh.positions.iter().map(|p| p.to_array()).collect();
        MeshBuffers {
            vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(&positions),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(&mesh.indices),
                usage: wgpu::BufferUsages::INDEX,
            }),
            index_count: mesh.indices.len() as u32,
        }
    }
}

/// The deferred light pass: its pipelines per variant, the volume meshes and the volume
/// uniforms of the frame.
pub struct DeferredLightsPass {
    module: wgpu::ShaderModule,
    gbuffer_layout: wgpu::BindGroupLayout,
    volume_layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    depth_format: wgpu::TextureFormat,
    /// Depth clipping off, so that back faces past a finite far plane still shade; where
    /// the device cannot, the vertex shader clamps them onto it.
    unclipped_depth: bool,
    pipelines: HashMap<Variant, Pipelines>,
    variant: Variant,
    sphere: MeshBuffers,
    pyramid: MeshBuffers,
    /// One `GpuVolumeLight` per volume, `stride` bytes apart.
    volumes: wgpu::Buffer,
    stride: u64,
    volume_bind_group: wgpu::BindGroup,
}

fn volume_buffer(device: &wgpu::Device, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("light volumes"),
        size,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn volume_bind_group(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, buffer: &wgpu::Buffer) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("light volume bind group"),
        layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer,
                offset: 0,
                size: wgpu::BufferSize::new(size_of::<GpuVolumeLight>() as u64),
            }),
        }],
    })
}

/// A stencil test: `pass_op` where stencil and depth pass, `fail_op` where either fails.
fn stencil(
    compare: wgpu::CompareFunction,
    pass_op: wgpu::StencilOperation,
    fail_op: wgpu::StencilOperation,
    read: u32,
    write: u32,
) -> wgpu::StencilState {
    let face = wgpu::StencilFaceState { compare, fail_op, depth_fail_op: fail_op, pass_op };
    wgpu::StencilState { front: face, back: face, read_mask: read, write_mask: write }
}

impl PassType for DeferredLightsPass {
    const NAME: &'static str = "deferred lights";

    /// Light adds to the G-buffer pass's emissive and ambient light; the overdraw view
    /// counts volumes from zero instead, into the HDR target.
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        if plan.path != RenderPath::Deferred {
            return;
        }
        pass.read(DIRECTIONAL_ATLAS).read(LOCAL_ATLAS).read(SHADOW_TINTS).read(GBUFFER_ALBEDO_METALLIC).read(GBUFFER_PACKED);
        // Stencil marks go into the depth target's stencil.
        pass.modify(DEPTH);
        let target = Variant::of(plan).target();
        if target == light_target(plan.light_buffer) {
            if Variant::of(plan).overdraw {
                pass.write(target);
            } else {
                pass.modify(target);
            }
        } else {
            pass.create(target, light_target_desc(LightBuffer::Hdr));
        }
    }

    fn new(init: &PassInit<'_>) -> DeferredLightsPass {
        DeferredLightsPass::make(init.device, init.frame_layout, init.depth_format)
    }
}

impl DeferredLightsPass {
    fn make(
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        depth_format: wgpu::TextureFormat,
    ) -> DeferredLightsPass {
        let texture = |binding, sample_type| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let gbuffer_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gbuffer layout"),
            entries: &[
                texture(0, wgpu::TextureSampleType::Float { filterable: false }),
                texture(1, wgpu::TextureSampleType::Uint),
            ],
        });
        let volume_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("light volume layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(size_of::<GpuVolumeLight>() as u64),
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("deferred light pipeline layout"),
            bind_group_layouts: &[Some(frame_layout), Some(&gbuffer_layout), Some(&volume_layout)],
            immediate_size: 0,
        });
        let alignment = device.limits().min_uniform_buffer_offset_alignment as u64;
        let stride = (size_of::<GpuVolumeLight>() as u64).div_ceil(alignment) * alignment;
        let volumes = volume_buffer(device, stride * 64);
        DeferredLightsPass {
            module: shaders::module(device, "deferred lights", crate::wgsl!("deferred_light")),
            volume_bind_group: volume_bind_group(device, &volume_layout, &volumes),
            gbuffer_layout,
            volume_layout,
            pipeline_layout,
            depth_format,
            unclipped_depth: device.features().contains(wgpu::Features::DEPTH_CLIP_CONTROL),
            pipelines: HashMap::new(),
            variant: Variant { ldr: false, overdraw: false, features: ShaderFeatures::ALL },
            sphere: MeshBuffers::new(device, "light sphere", unit_sphere()),
            pyramid: MeshBuffers::new(device, "light pyramid", unit_pyramid()),
            volumes,
            stride,
        }
    }

    fn create(&self, device: &wgpu::Device, variant: Variant) -> Pipelines {
        use wgpu::CompareFunction as C;
        use wgpu::StencilOperation as Op;
        let both = STENCIL_SURFACE | STENCIL_INSIDE;
        let pipeline = |draw: LightDraw<'_>| self.light_pipeline(device, variant, draw);
        Pipelines {
            // Reverse-Z: greater is nearer. Front faces nearer than the surface mark it.
            mark: pipeline(LightDraw {
                label: "mark",
                fragment_entry: "fs_mark",
                directional: false,
                cull: Some(wgpu::Face::Back),
                depth_compare: C::Greater,
                stencil: stencil(C::Equal, Op::Replace, Op::Keep, STENCIL_SURFACE, STENCIL_INSIDE),
                writes_color: false,
            }),
            // Back faces farther than the surface shade it; every outcome clears the mark.
            volume: pipeline(LightDraw {
                label: "volume",
                fragment_entry: "fs_volume_light",
                directional: false,
                cull: Some(wgpu::Face::Front),
                depth_compare: C::Less,
                stencil: stencil(C::Equal, Op::Zero, Op::Zero, both, STENCIL_INSIDE),
                writes_color: true,
            }),
            inside: pipeline(LightDraw {
                label: "inside",
                fragment_entry: "fs_volume_light",
                directional: false,
                cull: Some(wgpu::Face::Front),
                depth_compare: C::Less,
                stencil: stencil(C::Equal, Op::Keep, Op::Keep, STENCIL_SURFACE, 0),
                writes_color: true,
            }),
            directional: pipeline(LightDraw {
                label: "directional",
                fragment_entry: "fs_directional_lights",
                directional: true,
                cull: None,
                depth_compare: C::Always,
                stencil: stencil(C::Equal, Op::Keep, Op::Keep, STENCIL_SURFACE, 0),
                writes_color: true,
            }),
        }
    }

    /// One of the four light pipelines of `variant`.
    fn light_pipeline(&self, device: &wgpu::Device, variant: Variant, draw: LightDraw<'_>) -> wgpu::RenderPipeline {
        let (format, blend) = light_blend(variant.ldr);
        let LightDraw { label, fragment_entry, directional, cull, depth_compare, stencil, writes_color } = draw;
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &[wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x3, offset: 0, shader_location: 0 }],
        };
        let vertex_constants = [overrides::CLAMP_FAR.flag(!self.unclipped_depth)];
        // The light shaders read no baked light (the G-buffer carries the shadow mask);
        // PCSS, the local shadow loops' switch and the environment keep their defaults
        // (on) here: these are the features the light volumes specialise on.
        let f = variant.features;
        let fragment_constants = [
            overrides::LDR_EXP2.flag(variant.ldr),
            overrides::COUNT_OVERDRAW.flag(variant.overdraw),
            overrides::COOKIES_ENABLED.flag(f.cookies),
            overrides::TENT_FILTERS.flag(f.tent_filters),
            overrides::SOFT_CASCADES.flag(f.soft_cascades),
            overrides::TINTED_SHADOWS.flag(f.tinted_shadows),
            overrides::CONTACT_SHADOWS.flag(f.contact_shadows),
            overrides::VIRTUAL_SHADOWS.flag(f.virtual_shadows),
            overrides::AREA_LIGHTS.flag(f.area_lights),
        ];
        let buffers = [Some(vertex_layout)];
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&format!("deferred {label} {variant:?}")),
            layout: Some(&self.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some(if directional { "vs_fullscreen" } else { "vs_volume" }),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: if directional { &[] } else { &vertex_constants },
                    ..Default::default()
                },
                buffers: if directional { &[] } else { &buffers },
            },
            primitive: wgpu::PrimitiveState {
                cull_mode: cull,
                unclipped_depth: self.unclipped_depth && !directional,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: self.depth_format,
                depth_write_enabled: Some(false),
                depth_compare: Some(depth_compare),
                stencil,
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &self.module,
                entry_point: Some(fragment_entry),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: if fragment_entry == "fs_mark" { &[] } else { &fragment_constants },
                    ..Default::default()
                },
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: Some(blend),
                    write_mask: if writes_color { wgpu::ColorWrites::ALL } else { wgpu::ColorWrites::empty() },
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// How one light pipeline draws: its shaders, faces, depth and stencil tests.
struct LightDraw<'a> {
    label: &'a str,
    fragment_entry: &'a str,
    /// A full-screen triangle (`vs_fullscreen`) rather than a volume mesh.
    directional: bool,
    cull: Option<wgpu::Face>,
    depth_compare: wgpu::CompareFunction,
    stencil: wgpu::StencilState,
    writes_color: bool,
}

/// The light target's format and blend: HDR light adds (alpha kept); LDR multiplies.
fn light_blend(ldr: bool) -> (wgpu::TextureFormat, wgpu::BlendState) {
    if ldr {
        // dst * src: the exp2(-light) factors multiply, so their exponents add.
        let multiply = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::Zero,
            dst_factor: wgpu::BlendFactor::Src,
            operation: wgpu::BlendOperation::Add,
        };
        (LIGHT_BUFFER_LDR_FORMAT, wgpu::BlendState { color: multiply, alpha: wgpu::BlendComponent::REPLACE })
    } else {
        let add = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let keep = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::Zero,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        (HDR_FORMAT, wgpu::BlendState { color: add, alpha: keep })
    }
}

impl FramePass for DeferredLightsPass {
    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        self.variant = Variant::of(cx.plan);
        if !self.pipelines.contains_key(&self.variant) {
            let pipelines = self.create(cx.device, self.variant);
            self.pipelines.insert(self.variant, pipelines);
        }
        let volumes = cx.plan.gpu_volumes(cx.source);
        let size = (volumes.len().max(1) as u64) * self.stride;
        if size > self.volumes.size() {
            self.volumes = volume_buffer(cx.device, size.next_power_of_two());
            self.volume_bind_group = volume_bind_group(cx.device, &self.volume_layout, &self.volumes);
        }
        let mut bytes = vec![0u8; volumes.len() * self.stride as usize];
        for (k, v) in volumes.iter().enumerate() {
            let at = k * self.stride as usize;
            bytes[at..at + size_of::<GpuVolumeLight>()].copy_from_slice(bytemuck::bytes_of(v));
        }
        if !bytes.is_empty() {
            cx.queue.write_buffer(&self.volumes, 0, &bytes);
        }
    }

    fn record(&self, cx: &mut PassContext<'_>) {
        let gbuffer = cx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gbuffer bind group"),
            layout: &self.gbuffer_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(cx.targets.view(GBUFFER_ALBEDO_METALLIC)),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(cx.targets.view(GBUFFER_PACKED)),
                },
            ],
        });
        let pipelines = &self.pipelines[&self.variant];
        let load =
            if self.variant.overdraw { wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT) } else { wgpu::LoadOp::Load };
        let timestamp_writes = cx.timestamp_writes();
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("deferred light pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: cx.targets.view(self.variant.target()),
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load, store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: Some(scene_depth(cx.targets.view(DEPTH), true)),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, cx.frame_bind_group, &[]);
        pass.set_bind_group(1, &gbuffer, &[]);
        for (k, volume) in cx.plan.volumes.iter().enumerate() {
            pass.set_bind_group(2, &self.volume_bind_group, &[(k as u64 * self.stride) as u32]);
            let mesh = match volume.shape {
                VolumeShape::Screen => {
                    pass.set_pipeline(&pipelines.directional);
                    pass.set_stencil_reference(STENCIL_SURFACE);
                    pass.draw(0..3, 0..1);
                    continue;
                }
                VolumeShape::Sphere => &self.sphere,
                VolumeShape::Pyramid => &self.pyramid,
            };
            pass.set_vertex_buffer(0, mesh.vertices.slice(..));
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            if volume.camera_inside {
                pass.set_pipeline(&pipelines.inside);
                pass.set_stencil_reference(STENCIL_SURFACE);
            } else {
                pass.set_pipeline(&pipelines.mark);
                pass.set_stencil_reference(STENCIL_SURFACE | STENCIL_INSIDE);
                pass.draw_indexed(0..mesh.index_count, 0, 0..1);
                pass.set_pipeline(&pipelines.volume);
            }
            pass.draw_indexed(0..mesh.index_count, 0, 0..1);
        }
    }
}
