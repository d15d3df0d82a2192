//! The shadow pass: casters drawn into their tiles of both atlases, depth only, from the
//! tiles and caster lists the plan made. The atlases persist from frame to frame; the plan
//! says which tiles are drawn again (`plan::shadow_cache`), and the pass runs only when
//! some are. Pipelines vary by slope bias, cull mode, winding, depth clamping and how the
//! material casts (solid, alpha-tested or dithered: the last two sample the material's
//! base colour alpha), since those are pipeline state in wgpu.
//!
//! Casters that let light through (`Draw::tints_shadows`) write no depth: where a tile has
//! any, they are drawn into the shadow tints instead (shaders/shadows/tint.wesl), every
//! tile every frame (they are few, and the layers then need no cache of their own).

use crate::gpu::{GpuCasterView, GpuVertex};
use crate::graph::target::ATTACHMENT_SAMPLED;
use crate::graph::{
    FramePass, PassContext, PassInit, PassSetup, PassStats, PassType, PrepareContext, Target, TargetDesc,
};
use crate::plan::FramePlan;
use crate::plan::draws::{Draw, instanced_runs};
use crate::scene::GpuScene;
use crate::plan::shadows::{CasterTile, ShadowAtlas};
use crate::shader_constants::{CASTER_CLAMP_DEPTH, MAX_DIRECTIONAL_SHADOW_TILES, MAX_LOCAL_SHADOW_TILES};
use crate::shaders;
use chiaro_scene::{CastShadows, ShadowCasting};
use std::collections::HashMap;
use super::targets::{DIRECTIONAL_ATLAS, LOCAL_ATLAS, SHADOW_FORMAT, SHADOW_TINTS, SHADOW_TINTS_FORMAT};


/// The atlas target of each atlas.
fn atlas_target(atlas: ShadowAtlas) -> Target {
    match atlas {
        ShadowAtlas::Directional => DIRECTIONAL_ATLAS,
        ShadowAtlas::Local => LOCAL_ATLAS,
    }
}
/// The layer of the shadow tints that holds each atlas's tiles (shadows/tint.wesl's
/// TINT_LAYER_*).
fn tint_layer(atlas: ShadowAtlas) -> u32 {
    match atlas {
        ShadowAtlas::Directional => 0,
        ShadowAtlas::Local => 1,
    }
}

const TOTAL_TILES: u64 = (MAX_DIRECTIONAL_SHADOW_TILES + MAX_LOCAL_SHADOW_TILES) as u64;

#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
struct CasterKey {
    slope_bias_bits: u32,
    cull_back: bool,
    front_cw: bool,
    /// Clamp depth (directional cascades); perspective tiles must not flatten casters
    /// behind the light.
    clamp_depth: bool,
    /// On (no fragment stage), Clip or Dither.
    casting: ShadowCasting,
}

/// The shadow pass: caster pipelines per pipeline state, and the caster views of the
/// frame's tiles.
pub struct ShadowPass {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// With the material as group 1, for casters that test their alpha.
    alpha_pipeline_layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    pipelines: HashMap<CasterKey, wgpu::RenderPipeline>,
    /// One `GpuCasterView` per tile of the frame, at multiples of `stride`.
    views: wgpu::Buffer,
    stride: u64,
    bind_group: Option<wgpu::BindGroup>,
    /// Depth clamping by the rasterizer (DEPTH_CLIP_CONTROL); else in the vertex shader.
    unclipped_depth: bool,
    /// Writes the far plane over one tile: a cleared tile inside a pass that keeps the rest.
    clear_tile: wgpu::RenderPipeline,
    /// Tinting casters' pipelines, by `tint_key`.
    tint_pipelines: HashMap<CasterKey, wgpu::RenderPipeline>,
    /// Per tile of the frame, its depth casters in batches (empty for tiles not drawn).
    batches: Vec<Vec<CasterBatch>>,
    /// Every batch's draws (`wgpu::util::DrawIndexedIndirectArgs`), for multi-draw
    /// indirect; grown when a frame has more.
    indirect: wgpu::Buffer,
    /// The device draws a batch with one multi-draw indirect call (it has
    /// INDIRECT_FIRST_INSTANCE, which the casters' object index needs); else one draw
    /// call per run.
    multi_draw: bool,
}

/// Caster runs of one tile that draw with one pipeline state and one material binding:
/// one multi-draw indirect call.
#[derive(Clone, Debug)]
struct CasterBatch {
    key: CasterKey,
    /// The material bound as group 1, for casters that read one.
    material: Option<usize>,
    /// The batch's first draw in the indirect buffer, and its draws.
    first: u32,
    draws: Vec<wgpu::util::DrawIndexedIndirectArgs>,
}

/// A tile's depth casters as batches (`instanced_runs`, then runs of the same state and
/// material together), their draws numbered from `first`.
fn caster_batches(tile: &CasterTile, draws: &[Draw], mut first: u32) -> Vec<CasterBatch> {
    let mut batches: Vec<CasterBatch> = Vec::new();
    for (draw, instances) in instanced_runs(draws, &tile.casters) {
        let key = caster_key(tile, draw);
        let material = (key.casting != ShadowCasting::On).then_some(draw.material);
        let args = wgpu::util::DrawIndexedIndirectArgs {
            index_count: draw.index_count,
            instance_count: instances,
            first_index: draw.first_index,
            base_vertex: draw.base_vertex,
            first_instance: draw.object,
        };
        match batches.last_mut() {
            Some(batch) if batch.key == key && batch.material == material => batch.draws.push(args),
            _ => batches.push(CasterBatch { key, material, first, draws: vec![args] }),
        }
        first += 1;
    }
    batches
}

fn caster_key(tile: &CasterTile, draw: &Draw) -> CasterKey {
    CasterKey {
        slope_bias_bits: tile.slope_bias.to_bits(),
        cull_back: draw.cast_shadows != CastShadows::TwoSided && !draw.double_sided,
        front_cw: draw.mirrored,
        clamp_depth: tile.orthographic,
        casting: draw.shadow_casting,
    }
}

/// A tinting caster's pipeline state: winding and depth clamping as for its depth (no
/// bias: it writes no depth), and the faces its material shows the camera: a
/// single-sided one tints where its front faces the light, one wall of a closed object,
/// as the camera sees one wall of it; the instance's two-sided casting (glTF's default,
/// for open meshes' depth) does not make it tint twice.
fn tint_key(tile: &CasterTile, draw: &Draw) -> CasterKey {
    CasterKey { slope_bias_bits: 0, casting: ShadowCasting::On, cull_back: !draw.double_sided, ..caster_key(tile, draw) }
}

impl PassType for ShadowPass {
    const NAME: &'static str = "shadows";

    /// Both atlases persist; they are written (and the pass runs) only when the plan
    /// draws a tile again, which later frames then trust: a side effect.
    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        let shadows = &plan.shadows;
        for atlas in [ShadowAtlas::Directional, ShadowAtlas::Local] {
            let desc = TargetDesc::square(shadows.atlas_size(atlas), SHADOW_FORMAT, ATTACHMENT_SAMPLED);
            pass.persistent(atlas_target(atlas), desc);
            if shadows.redrawn_tiles().any(|(_, t)| t.atlas == atlas) {
                pass.modify(atlas_target(atlas)).side_effect();
            }
        }
        // Two layers the size of the larger atlas while any caster tints; else a 1x1
        // texel made anew (zero, which tints nothing) so that no stale tint survives for
        // a shader that reads the tints unspecialised (the shadow AOV).
        let tinted = plan.features.tinted_shadows;
        let size = if tinted {
            shadows.atlas_size(ShadowAtlas::Directional).max(shadows.atlas_size(ShadowAtlas::Local))
        } else {
            1
        };
        pass.persistent(SHADOW_TINTS, TargetDesc::square(size, SHADOW_TINTS_FORMAT, ATTACHMENT_SAMPLED).with_layers(2));
        if tinted {
            pass.modify(SHADOW_TINTS).side_effect();
        }
    }

    fn new(init: &PassInit<'_>) -> ShadowPass {
        let device = init.device;
        let material_layout = init.material_layout;
        let alignment = device.limits().min_uniform_buffer_offset_alignment as u64;
        let stride = (size_of::<GpuCasterView>() as u64).div_ceil(alignment) * alignment;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("caster layout"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: true,
                        min_binding_size: wgpu::BufferSize::new(size_of::<GpuCasterView>() as u64),
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
        let alpha_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("alpha caster pipeline layout"),
            bind_group_layouts: &[Some(&layout), Some(material_layout)],
            immediate_size: 0,
        });
        let module = shaders::module(device, "shadow caster", crate::wgsl!("shadow_caster"));
        let clear_tile = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("clear shadow tile"),
            layout: Some(&device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("clear shadow tile layout"),
                bind_group_layouts: &[],
                immediate_size: 0,
            })),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_clear_tile"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: SHADOW_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        ShadowPass {
            module,
            clear_tile,
            views: caster_views(device, stride * TOTAL_TILES),
            stride,
            bind_group: None,
            unclipped_depth: device.features().contains(wgpu::Features::DEPTH_CLIP_CONTROL),
            layout,
            pipeline_layout,
            alpha_pipeline_layout,
            pipelines: HashMap::new(),
            tint_pipelines: HashMap::new(),
            batches: Vec::new(),
            indirect: indirect_buffer(device, 64 * INDIRECT_ARGS_BYTES),
            multi_draw: device.features().contains(wgpu::Features::INDIRECT_FIRST_INSTANCE),
        }
    }
}

/// Bytes of one `DrawIndexedIndirectArgs`.
const INDIRECT_ARGS_BYTES: u64 = size_of::<wgpu::util::DrawIndexedIndirectArgs>() as u64;

/// The buffer of the casters' indirect draws, `size` bytes.
fn indirect_buffer(device: &wgpu::Device, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("caster indirect draws"),
        size,
        usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// The buffer of one `GpuCasterView` per tile, `size` bytes.
fn caster_views(device: &wgpu::Device, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("caster views"),
        size,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl ShadowPass {
    fn create(&self, device: &wgpu::Device, key: CasterKey) -> wgpu::RenderPipeline {
        let (layout, vertex_entry, fragment_entry) = match key.casting {
            ShadowCasting::Clip => (&self.alpha_pipeline_layout, "vs_caster_alpha", Some("fs_caster_clip")),
            ShadowCasting::Dither => (&self.alpha_pipeline_layout, "vs_caster_alpha", Some("fs_caster_dither")),
            _ => (&self.pipeline_layout, "vs_caster", None),
        };
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&format!("caster pipeline {key:?}")),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some(vertex_entry),
                compilation_options: Default::default(),
                buffers: &[Some(GpuVertex::layout())],
            },
            primitive: wgpu::PrimitiveState {
                front_face: if key.front_cw { wgpu::FrontFace::Cw } else { wgpu::FrontFace::Ccw },
                cull_mode: key.cull_back.then_some(wgpu::Face::Back),
                unclipped_depth: self.unclipped_depth && key.clamp_depth,
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
            fragment: fragment_entry.map(|entry| wgpu::FragmentState {
                module: &self.module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                targets: &[],
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

impl ShadowPass {
    /// A tinting caster pipeline: the faces its material shows (`tint_key`; the
    /// reference counts them alike), no depth, colours multiplied and the nearest depth
    /// kept.
    fn create_tint(&self, device: &wgpu::Device, key: CasterKey) -> wgpu::RenderPipeline {
        let multiply = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::Zero,
            dst_factor: wgpu::BlendFactor::Src,
            operation: wgpu::BlendOperation::Add,
        };
        let nearest = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Max,
        };
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("tinting caster pipeline"),
            layout: Some(&self.alpha_pipeline_layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some("vs_caster_tint"),
                compilation_options: Default::default(),
                buffers: &[Some(GpuVertex::layout())],
            },
            primitive: wgpu::PrimitiveState {
                front_face: if key.front_cw { wgpu::FrontFace::Cw } else { wgpu::FrontFace::Ccw },
                cull_mode: key.cull_back.then_some(wgpu::Face::Back),
                unclipped_depth: self.unclipped_depth && key.clamp_depth,
                ..Default::default()
            },
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &self.module,
                entry_point: Some("fs_caster_tint"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: SHADOW_TINTS_FORMAT,
                    blend: Some(wgpu::BlendState { color: multiply, alpha: nearest }),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
    }

    /// Draws every tile's tinting casters into its layer of the shadow tints, cleared
    /// first; `timestamps` as for a depth pass.
    fn record_tints(&self, cx: &mut PassContext<'_>, atlas: ShadowAtlas, first: bool, last: bool) {
        let bind_group = self.bind_group.as_ref().expect("prepared");
        let shadows = &cx.plan.shadows;
        let view = cx.targets.layer_view(SHADOW_TINTS, tint_layer(atlas));
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow tint pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color { r: 1.0, g: 1.0, b: 1.0, a: 0.0 }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: cx.timestamps.as_ref().and_then(|t| t.writes(first, last)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_vertex_buffer(0, cx.scene.vertices.slice(..));
        pass.set_index_buffer(cx.scene.indices.slice(..), wgpu::IndexFormat::Uint32);
        for (i, tile) in shadows.tiles.iter().enumerate().filter(|(_, t)| t.atlas == atlas && !t.tint_casters.is_empty()) {
            let (x, y, size) = tile.viewport;
            pass.set_viewport(x as f32, y as f32, size as f32, size as f32, 0.0, 1.0);
            pass.set_scissor_rect(x, y, size, size);
            pass.set_bind_group(0, bind_group, &[(i as u64 * self.stride) as u32]);
            // Every tinting caster reads its material's transmittance.
            let casters = TileCasters { list: &tile.tint_casters, key_of: tint_key, reads_material: |_| true };
            draw_casters(&mut pass, cx.scene, cx.stats, tile, &self.tint_pipelines, casters);
        }
    }
}

/// One of a tile's caster lists and how it is drawn.
struct TileCasters<'a> {
    /// Indices into the scene's draws.
    list: &'a [u32],
    /// Each caster's pipeline state.
    key_of: fn(&CasterTile, &Draw) -> CasterKey,
    /// Whether a caster of that state reads its material (group 1).
    reads_material: fn(CasterKey) -> bool,
}

/// Draws `casters` of `tile` into `pass` (group 0 bound at the tile's view) with
/// `pipelines`, as instanced runs, binding each caster's material where it reads one.
fn draw_casters(
    pass: &mut wgpu::RenderPass<'_>,
    scene: &GpuScene,
    stats: &mut PassStats,
    tile: &CasterTile,
    pipelines: &HashMap<CasterKey, wgpu::RenderPipeline>,
    casters: TileCasters<'_>,
) {
    let mut bound = None;
    let mut bound_material = usize::MAX;
    for (draw, instances) in instanced_runs(&scene.draws, casters.list) {
        let key = (casters.key_of)(tile, draw);
        if bound != Some(key) {
            pass.set_pipeline(&pipelines[&key]);
            bound = Some(key);
        }
        if (casters.reads_material)(key) && bound_material != draw.material {
            pass.set_bind_group(1, &scene.materials[draw.material], &[]);
            bound_material = draw.material;
        }
        pass.draw_indexed(
            draw.first_index..draw.first_index + draw.index_count,
            draw.base_vertex,
            draw.object..draw.object + instances,
        );
        stats.shadow_caster_draws += 1;
    }
}

impl ShadowPass {
    /// Draws a tile's depth casters: a multi-draw indirect call per batch where the
    /// device has what it needs, else a draw call per run. Alpha-tested and dithered
    /// casters bind their material.
    fn draw_batches(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        scene: &GpuScene,
        stats: &mut PassStats,
        batches: &[CasterBatch],
    ) {
        for batch in batches {
            pass.set_pipeline(&self.pipelines[&batch.key]);
            if let Some(material) = batch.material {
                pass.set_bind_group(1, &scene.materials[material], &[]);
            }
            if self.multi_draw {
                pass.multi_draw_indexed_indirect(
                    &self.indirect,
                    batch.first as u64 * INDIRECT_ARGS_BYTES,
                    batch.draws.len() as u32,
                );
            } else {
                for a in &batch.draws {
                    let instances = a.first_instance..a.first_instance + a.instance_count;
                    pass.draw_indexed(a.first_index..a.first_index + a.index_count, a.base_vertex, instances);
                }
            }
            stats.shadow_caster_draws += batch.draws.len();
        }
    }
}

impl FramePass for ShadowPass {
    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        let tiles = &cx.plan.shadows.tiles;
        // Atlas tiles fit the buffer made at first; virtual pages (a slot each) may not.
        let needed = self.stride * tiles.len() as u64;
        if needed > self.views.size() {
            self.views = caster_views(cx.device, needed.next_power_of_two());
        }
        let mut bytes = vec![0u8; (self.stride * tiles.len() as u64) as usize];
        for (i, tile) in tiles.iter().enumerate() {
            let clamp_in_shader = tile.orthographic && !self.unclipped_depth;
            let view = GpuCasterView {
                clip_from_world: tile.clip_from_world,
                flags: if clamp_in_shader { CASTER_CLAMP_DEPTH } else { 0 },
                _pad: [0; 3],
            };
            let at = i * self.stride as usize;
            bytes[at..at + size_of::<GpuCasterView>()].copy_from_slice(bytemuck::bytes_of(&view));
            for &d in &tile.casters {
                let key = caster_key(tile, &cx.scene.draws[d as usize]);
                if !self.pipelines.contains_key(&key) {
                    let pipeline = self.create(cx.device, key);
                    self.pipelines.insert(key, pipeline);
                }
            }
        }
        for tile in tiles {
            for &d in &tile.tint_casters {
                let key = tint_key(tile, &cx.scene.draws[d as usize]);
                if !self.tint_pipelines.contains_key(&key) {
                    let pipeline = self.create_tint(cx.device, key);
                    self.tint_pipelines.insert(key, pipeline);
                }
            }
        }
        if !bytes.is_empty() {
            cx.queue.write_buffer(&self.views, 0, &bytes);
        }
        // The depth casters of the tiles drawn this frame, batched, their draws in one
        // indirect buffer.
        let mut first = 0;
        self.batches = tiles
            .iter()
            .zip(&cx.plan.shadows.redraw)
            .map(|(tile, &drawn)| {
                let batches = if drawn { caster_batches(tile, &cx.scene.draws, first) } else { Vec::new() };
                first += batches.iter().map(|b| b.draws.len() as u32).sum::<u32>();
                batches
            })
            .collect();
        if self.multi_draw && first > 0 {
            let args: Vec<u8> =
                self.batches.iter().flatten().flat_map(|b| &b.draws).flat_map(|a| a.as_bytes().to_vec()).collect();
            if args.len() as u64 > self.indirect.size() {
                self.indirect = indirect_buffer(cx.device, (args.len() as u64).next_power_of_two());
            }
            cx.queue.write_buffer(&self.indirect, 0, &args);
        }
        self.bind_group = Some(cx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("caster bind group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &self.views,
                        offset: 0,
                        size: wgpu::BufferSize::new(size_of::<GpuCasterView>() as u64),
                    }),
                },
                wgpu::BindGroupEntry { binding: 1, resource: cx.scene.objects.as_entire_binding() },
            ],
        }));
    }

    /// One wgpu pass per atlas that has tiles to draw this frame. Without the cache, each
    /// is cleared and every tile drawn; with it, the atlas is kept and only the tiles the
    /// plan draws again are cleared and drawn. Then, where casters tint, one pass per
    /// layer of the shadow tints. The first carries the start timestamp, the last the end.
    fn record(&self, cx: &mut PassContext<'_>) {
        let bind_group = self.bind_group.as_ref().expect("prepared");
        let shadows = &cx.plan.shadows;
        let atlases: Vec<ShadowAtlas> = [ShadowAtlas::Directional, ShadowAtlas::Local]
            .into_iter()
            .filter(|&atlas| shadows.redrawn_tiles().any(|(_, t)| t.atlas == atlas))
            .collect();
        let tinted: Vec<ShadowAtlas> = [ShadowAtlas::Directional, ShadowAtlas::Local]
            .into_iter()
            .filter(|_| cx.plan.features.tinted_shadows)
            .collect();
        let passes = atlases.len() + tinted.len();
        for (k, &atlas) in atlases.iter().enumerate() {
            let timestamp_writes = cx.timestamps.as_ref().and_then(|t| t.writes(k == 0, k + 1 == passes));
            let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(match atlas {
                    ShadowAtlas::Directional => "directional shadow pass",
                    ShadowAtlas::Local => "local shadow pass",
                }),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: cx.targets.view(atlas_target(atlas)),
                    depth_ops: Some(wgpu::Operations {
                        load: if cx.plan.shadow_cache { wgpu::LoadOp::Load } else { wgpu::LoadOp::Clear(1.0) },
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_vertex_buffer(0, cx.scene.vertices.slice(..));
            pass.set_index_buffer(cx.scene.indices.slice(..), wgpu::IndexFormat::Uint32);
            for (i, tile) in shadows.redrawn_tiles().filter(|(_, t)| t.atlas == atlas) {
                let (x, y, size) = tile.viewport;
                pass.push_debug_group(&format!("shadow tile {} of light {}", tile.tile, tile.light.0));
                pass.set_viewport(x as f32, y as f32, size as f32, size as f32, 0.0, 1.0);
                pass.set_scissor_rect(x, y, size, size);
                if cx.plan.shadow_cache {
                    pass.set_pipeline(&self.clear_tile);
                    pass.draw(0..3, 0..1);
                }
                pass.set_bind_group(0, bind_group, &[(i as u64 * self.stride) as u32]);
                self.draw_batches(&mut pass, cx.scene, cx.stats, &self.batches[i]);
                pass.pop_debug_group();
                cx.stats.shadow_tiles_rendered += 1;
            }
        }
        for (k, &atlas) in tinted.iter().enumerate() {
            let index = atlases.len() + k;
            self.record_tints(cx, atlas, index == 0, index + 1 == passes);
        }
    }
}
