//! The shadow atlases on the GPU, one for directional cascades and one for point and spot
//! lights: depth textures, the caster pipelines (one per slope bias, cull mode and depth
//! clamping, since those are pipeline state in wgpu), and the passes that draw each
//! tile's casters into its viewport.

use crate::context::GpuContext;
use crate::gpu_scene::{Draw, GpuScene};
use crate::gpu_types::{GpuCasterView, GpuVertex, MAX_DIRECTIONAL_SHADOW_TILES, MAX_OTHER_SHADOW_TILES};
use crate::shaders;
use crate::shadow_plan::{CasterTile, ShadowPlan};
use chiaro_math::shadow::culling::{caster_in_range, caster_in_tile};
use chiaro_scene::CastShadows;
use std::collections::HashMap;

pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
const VIEW_STRIDE: u64 = std::mem::size_of::<GpuCasterView>() as u64;
const TOTAL_TILES: usize = MAX_DIRECTIONAL_SHADOW_TILES + MAX_OTHER_SHADOW_TILES;
const DIRECTIONAL_LABEL: &str = "directional shadow atlas";
const OTHER_LABEL: &str = "other shadow atlas";

#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
struct CasterKey {
    slope_bias_bits: u32,
    cull_back: bool,
    front_cw: bool,
    /// Clamp depth (directional cascades); perspective tiles must not flatten casters
    /// behind the light.
    clamp_depth: bool,
}

/// One atlas: its texture and a view of it.
pub struct Atlas {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
}

impl Atlas {
    fn new(device: &wgpu::Device, label: &str, size: u32) -> Atlas {
        let texture = atlas_texture(device, label, size);
        Atlas { view: texture.create_view(&Default::default()), texture }
    }

    /// Makes the atlas `size` texels square (1 when nothing casts into it).
    fn ensure(&mut self, device: &wgpu::Device, label: &str, size: u32) {
        let size = size.max(1);
        if self.texture.width() != size {
            *self = Atlas::new(device, label, size);
        }
    }
}

pub struct ShadowPass {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    pipelines: HashMap<CasterKey, wgpu::RenderPipeline>,
    views: wgpu::Buffer,
    /// Depth clamping by the rasterizer (DEPTH_CLIP_CONTROL); else in the vertex shader.
    unclipped_depth: bool,
    pub directional: Atlas,
    pub other: Atlas,
    pub sampler: wgpu::Sampler,
}

fn atlas_texture(device: &wgpu::Device, label: &str, size: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: SHADOW_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

impl ShadowPass {
    pub fn new(ctx: &GpuContext) -> ShadowPass {
        let device = &ctx.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("caster layout"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: true,
                        min_binding_size: wgpu::BufferSize::new(VIEW_STRIDE),
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::VERTEX,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("caster pipeline layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        ShadowPass {
            module: shaders::module(device, "shadow caster", shaders::SHADOW_CASTER),
            views: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("caster views"),
                size: VIEW_STRIDE * TOTAL_TILES as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            unclipped_depth: ctx.device.features().contains(wgpu::Features::DEPTH_CLIP_CONTROL),
            directional: Atlas::new(device, DIRECTIONAL_LABEL, 1),
            other: Atlas::new(device, OTHER_LABEL, 1),
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("shadow comparison sampler"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                compare: Some(wgpu::CompareFunction::LessEqual),
                ..Default::default()
            }),
            layout,
            pipeline_layout,
            pipelines: HashMap::new(),
        }
    }

    /// Sizes both atlases for this frame's plan.
    pub fn ensure_atlases(&mut self, device: &wgpu::Device, plan: &ShadowPlan) {
        self.directional.ensure(device, DIRECTIONAL_LABEL, plan.atlas_size);
        self.other.ensure(device, OTHER_LABEL, plan.other_atlas_size);
    }

    fn pipeline(&mut self, device: &wgpu::Device, key: CasterKey) -> &wgpu::RenderPipeline {
        let (module, layout, unclipped) = (&self.module, &self.pipeline_layout, self.unclipped_depth);
        self.pipelines.entry(key).or_insert_with(|| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&format!("caster pipeline {key:?}")),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some("vs_caster"),
                    compilation_options: Default::default(),
                    buffers: &[Some(GpuVertex::layout())],
                },
                primitive: wgpu::PrimitiveState {
                    front_face: if key.front_cw { wgpu::FrontFace::Cw } else { wgpu::FrontFace::Ccw },
                    cull_mode: key.cull_back.then_some(wgpu::Face::Back),
                    unclipped_depth: unclipped && key.clamp_depth,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: SHADOW_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::LessEqual),
                    stencil: Default::default(),
                    bias: wgpu::DepthBiasState {
                        constant: 0,
                        slope_scale: f32::from_bits(key.slope_bias_bits),
                        clamp: 0.0,
                    },
                }),
                multisample: Default::default(),
                fragment: None,
                multiview_mask: None,
                cache: None,
            })
        })
    }

    /// Draws every tile's casters into both atlases (the directional pass carries the
    /// start timestamp, the other-light pass the end). Returns how many draws were issued.
    pub fn record(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        plan: &ShadowPlan,
        scene: &GpuScene,
        timestamps: Option<(&wgpu::QuerySet, u32)>,
    ) -> usize {
        // Directional tiles first, then other-light tiles, each at its own view slot.
        let tiles: Vec<(&CasterTile, bool)> =
            plan.tiles.iter().map(|t| (t, true)).chain(plan.other_tiles.iter().map(|t| (t, false))).collect();
        debug_assert!(tiles.len() <= TOTAL_TILES);
        for (i, (tile, directional)) in tiles.iter().enumerate() {
            let clamp_in_shader = *directional && !self.unclipped_depth;
            let view = GpuCasterView {
                clip_from_world: tile.clip_from_world,
                flags: [u32::from(clamp_in_shader), 0, 0, 0],
                _pad: Default::default(),
            };
            ctx.queue.write_buffer(&self.views, i as u64 * VIEW_STRIDE, bytemuck::bytes_of(&view));
        }
        let mut tile_draws: Vec<Vec<(&Draw, CasterKey)>> = Vec::with_capacity(tiles.len());
        for (tile, directional) in &tiles {
            let list: Vec<(&Draw, CasterKey)> = scene
                .draws
                .iter()
                .filter(|d| {
                    d.casts_shadows()
                        && match &tile.light_sphere {
                            Some(sphere) => caster_in_range(&d.bounds_ws, sphere),
                            None => caster_in_tile(&tile.clip_from_world, &d.bounds_ws, true),
                        }
                })
                .map(|d| {
                    let key = CasterKey {
                        slope_bias_bits: tile.slope_bias.to_bits(),
                        cull_back: d.cast_shadows != CastShadows::TwoSided && !d.double_sided,
                        front_cw: d.mirrored,
                        clamp_depth: *directional,
                    };
                    (d, key)
                })
                .collect();
            for (_, key) in &list {
                self.pipeline(&ctx.device, *key);
            }
            tile_draws.push(list);
        }
        let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("caster bind group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &self.views,
                        offset: 0,
                        size: wgpu::BufferSize::new(VIEW_STRIDE),
                    }),
                },
                wgpu::BindGroupEntry { binding: 1, resource: scene.objects.as_entire_binding() },
            ],
        });
        let directional_count = plan.tiles.len();
        let mut count = 0;
        for (pass_index, atlas) in [&self.directional, &self.other].into_iter().enumerate() {
            let range = if pass_index == 0 { 0..directional_count } else { directional_count..tiles.len() };
            let timestamp_writes = timestamps.map(|(query_set, first)| wgpu::RenderPassTimestampWrites {
                query_set,
                beginning_of_pass_write_index: (pass_index == 0).then_some(first),
                end_of_pass_write_index: (pass_index == 1).then_some(first + 1),
            });
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(if pass_index == 0 { "directional shadow pass" } else { "other shadow pass" }),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &atlas.view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if range.is_empty() {
                continue;
            }
            pass.set_vertex_buffer(0, scene.vertices.slice(..));
            pass.set_index_buffer(scene.indices.slice(..), wgpu::IndexFormat::Uint32);
            for i in range {
                let (x, y, size) = tiles[i].0.viewport;
                pass.push_debug_group(&format!("shadow tile {i}"));
                pass.set_viewport(x as f32, y as f32, size as f32, size as f32, 0.0, 1.0);
                pass.set_scissor_rect(x, y, size, size);
                pass.set_bind_group(0, &bind_group, &[(i as u64 * VIEW_STRIDE) as u32]);
                let mut bound = None;
                for (d, key) in &tile_draws[i] {
                    if bound != Some(*key) {
                        pass.set_pipeline(&self.pipelines[key]);
                        bound = Some(*key);
                    }
                    pass.draw_indexed(
                        d.first_index..d.first_index + d.index_count,
                        d.base_vertex,
                        d.object..d.object + 1,
                    );
                    count += 1;
                }
                pass.pop_debug_group();
            }
        }
        count
    }
}
