//! Frames: lights chosen on the CPU, then the forward, AOV and tone-mapping passes, with
//! GPU timestamps around each pass where the device has them.

use crate::context::GpuContext;
use crate::error::RenderError;
use crate::frame_lights::{FrameLights, prepare_lights};
use crate::gpu_scene::{Draw, GpuScene, material_layout};
use crate::gpu_types::{GpuAovLight, GpuFrame, GpuLights, GpuOtherLight, GpuVertex};
use crate::readback::{read_buffer, read_texture};
use crate::shaders;
use crate::shadow_pass::ShadowPass;
use crate::shadow_plan::{ShadowPlan, plan_shadows};
use crate::view::View;
use chiaro_math::tonemap::exposure_scale;
use chiaro_scene::{AlphaMode, Scene, Settings};
use glam::Vec3;
use std::collections::HashMap;
use std::time::Instant;

const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
const LDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
const AOV_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Shadow AOV: attenuation, coverage.
const SHADOW_AOV_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;
/// Passes with timestamps, in order; two queries each.
const TIMED_PASSES: [&str; 4] = ["shadows", "forward", "aov", "tonemap"];
const AOV_LIGHT_STRIDE: u64 = std::mem::size_of::<GpuAovLight>() as u64;
/// What the shadow AOV pass writes for a light without a directional slot.
const NO_LIGHT: u32 = u32::MAX;

fn timed_index(pass: &str) -> u32 {
    TIMED_PASSES.iter().position(|p| *p == pass).expect("timed pass") as u32
}

#[derive(Clone, Copy, Debug, Default)]
pub struct FrameOptions {
    /// Also render world position, normal and view depth.
    pub aovs: bool,
    /// Also render each light's shadow attenuation (needs `readback`).
    pub shadow_aovs: bool,
    /// Copy the images back to the CPU (off for benchmarking).
    pub readback: bool,
    /// Tint the image by cascade.
    pub debug_cascades: bool,
    /// Copy the directional shadow atlas back to the CPU.
    pub read_shadow_atlas: bool,
}

#[derive(Clone, Debug, Default)]
pub struct FrameTimings {
    /// CPU time to choose lights, fill uniforms and record commands.
    pub cpu_prepare_ms: f64,
    /// GPU time of each pass that ran, from timestamp queries.
    pub gpu_pass_ms: Vec<(&'static str, f64)>,
    /// Wall time from the start of preparation until the GPU finished.
    pub wall_ms: f64,
}

impl FrameTimings {
    pub fn gpu_total_ms(&self) -> Option<f64> {
        (!self.gpu_pass_ms.is_empty()).then(|| self.gpu_pass_ms.iter().map(|(_, t)| t).sum())
    }
}

/// World-space AOVs; `NaN` where no surface covers the pixel.
#[derive(Clone, Debug, Default)]
pub struct Aovs {
    pub position_ws: Vec<[f32; 3]>,
    pub normal_ws: Vec<[f32; 3]>,
    /// Linear depth along the view axis, metres.
    pub depth: Vec<f32>,
}

#[derive(Clone, Debug, Default)]
pub struct FrameOutput {
    pub width: u32,
    pub height: u32,
    /// Linear radiance (not exposed), RGBA, row-major from the top-left.
    pub hdr: Vec<[f32; 4]>,
    /// Tone-mapped sRGB, RGBA8.
    pub ldr: Vec<u8>,
    pub aovs: Option<Aovs>,
    pub timings: FrameTimings,
    /// Number of point/spot lights shaded, and how many visible ones were dropped.
    pub other_lights_shaded: u32,
    pub other_lights_dropped: usize,
    /// Per scene light (by index in `Scene::lights`): the shadow attenuation the shading
    /// used, 1 where no shadow map covers the pixel, NaN where no surface is.
    pub shadow_aovs: Vec<Vec<f32>>,
    /// The shadow atlases ("directional", "other") that were in use, side length and
    /// depths, if asked for.
    pub shadow_atlases: Vec<(&'static str, u32, Vec<f32>)>,
    /// Per scene light: whether it had a realtime shadow map this frame, and if not why.
    pub shadow_status: Vec<ShadowStatus>,
    /// Shadow tiles rendered and caster draws issued into them.
    pub shadow_tiles: usize,
    pub shadow_caster_draws: usize,
}

/// Whether a light's shadows came from a shadow map this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadowStatus {
    /// Sampled from its atlas tiles.
    Mapped,
    /// The light casts no shadows (extras `shadows: none` or strength 0).
    Off,
    /// The light was not shaded this frame (culled, or over the light limits).
    NotShaded,
    /// It casts shadows but found no free atlas tiles.
    NoTile,
}

#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
enum PassKind {
    Forward,
    Aov,
    ShadowAov,
}

#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
struct PipelineKey {
    pass: PassKind,
    cull_back: bool,
    front_cw: bool,
    blend: bool,
}

struct Targets {
    width: u32,
    height: u32,
    hdr: wgpu::Texture,
    ldr: wgpu::Texture,
    depth: wgpu::Texture,
    aov_position: wgpu::Texture,
    aov_normal: wgpu::Texture,
    aov_shadow: wgpu::Texture,
    tonemap_bind_group: wgpu::BindGroup,
}

struct Timestamps {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    period_ns: f64,
}

/// A scene on the GPU.
pub struct PreparedScene {
    pub gpu: GpuScene,
}

pub struct Renderer {
    pub ctx: GpuContext,
    frame_layout: wgpu::BindGroupLayout,
    material_layout: wgpu::BindGroupLayout,
    tonemap_layout: wgpu::BindGroupLayout,
    scene_pipeline_layout: wgpu::PipelineLayout,
    shadow_aov_pipeline_layout: wgpu::PipelineLayout,
    aov_light_layout: wgpu::BindGroupLayout,
    aov_lights: wgpu::Buffer,
    shadow_pass: ShadowPass,
    forward_module: wgpu::ShaderModule,
    aov_module: wgpu::ShaderModule,
    shadow_aov_module: wgpu::ShaderModule,
    tonemap_pipeline: wgpu::RenderPipeline,
    pipelines: HashMap<PipelineKey, wgpu::RenderPipeline>,
    frame_buffer: wgpu::Buffer,
    lights_buffer: wgpu::Buffer,
    shadows_buffer: wgpu::Buffer,
    targets: Option<Targets>,
    timestamps: Option<Timestamps>,
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn texture_2d(
    ctx: &GpuContext,
    label: &str,
    w: u32,
    h: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

impl Renderer {
    pub fn new(ctx: GpuContext) -> Result<Renderer, RenderError> {
        let device = &ctx.device;
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame layout"),
            entries: &[
                uniform_entry(0),
                uniform_entry(1),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::VERTEX,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                uniform_entry(3),
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 5,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 6,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
            ],
        });
        let aov_light_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("aov light layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(AOV_LIGHT_STRIDE),
                },
                count: None,
            }],
        });
        let material_layout = material_layout(device);
        let tonemap_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tonemap layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let scene_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene pipeline layout"),
            bind_group_layouts: &[Some(&frame_layout), Some(&material_layout)],
            immediate_size: 0,
        });
        let shadow_aov_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow aov pipeline layout"),
            bind_group_layouts: &[Some(&frame_layout), Some(&material_layout), Some(&aov_light_layout)],
            immediate_size: 0,
        });
        let tonemap_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("tonemap pipeline layout"),
            bind_group_layouts: &[Some(&tonemap_layout)],
            immediate_size: 0,
        });
        let tonemap_module = shaders::module(device, "tonemap", shaders::TONEMAP);
        let tonemap_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("tonemap"),
            layout: Some(&tonemap_pipeline_layout),
            vertex: wgpu::VertexState {
                module: &tonemap_module,
                entry_point: Some("vs_fullscreen"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &tonemap_module,
                entry_point: Some("fs_tonemap"),
                compilation_options: Default::default(),
                targets: &[Some(LDR_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame uniform"),
            size: std::mem::size_of::<GpuFrame>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let lights_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lights uniform"),
            size: std::mem::size_of::<GpuLights>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let shadows_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("shadows uniform"),
            size: std::mem::size_of::<crate::gpu_types::GpuShadows>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let aov_lights = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("aov lights"),
            size: AOV_LIGHT_STRIDE,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let shadow_pass = ShadowPass::new(&ctx);
        let timestamps = ctx.has_timestamps.then(|| {
            let count = 2 * TIMED_PASSES.len() as u32;
            Timestamps {
                queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("pass timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count,
                }),
                resolve: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamp resolve"),
                    size: 8 * count as u64,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
                readback: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamp readback"),
                    size: 8 * count as u64,
                    usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                    mapped_at_creation: false,
                }),
                period_ns: ctx.queue.get_timestamp_period() as f64,
            }
        });
        let forward_module = shaders::module(device, "forward", shaders::FORWARD);
        let aov_module = shaders::module(device, "aov", shaders::AOV);
        let shadow_aov_module = shaders::module(device, "shadow aov", shaders::SHADOW_AOV);
        let renderer = Renderer {
            frame_layout,
            material_layout,
            tonemap_layout,
            scene_pipeline_layout,
            shadow_aov_pipeline_layout,
            aov_light_layout,
            aov_lights,
            shadow_pass,
            shadows_buffer,
            forward_module,
            aov_module,
            shadow_aov_module,
            tonemap_pipeline,
            pipelines: HashMap::new(),
            frame_buffer,
            lights_buffer,
            targets: None,
            timestamps,
            ctx,
        };
        renderer.ctx.take_error()?;
        Ok(renderer)
    }

    /// Uploads a scene.
    pub fn prepare(&self, scene: &Scene) -> Result<PreparedScene, RenderError> {
        let gpu = GpuScene::upload(&self.ctx.device, &self.ctx.queue, &self.material_layout, scene);
        self.ctx.take_error()?;
        Ok(PreparedScene { gpu })
    }

    /// Binds the per-frame buffers, the scene's objects and the current shadow atlas.
    fn frame_bind_group(&self, prepared: &PreparedScene) -> wgpu::BindGroup {
        self.ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame bind group"),
            layout: &self.frame_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: self.frame_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: self.lights_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: prepared.gpu.objects.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 3, resource: self.shadows_buffer.as_entire_binding() },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&self.shadow_pass.directional.view),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: wgpu::BindingResource::Sampler(&self.shadow_pass.sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::TextureView(&self.shadow_pass.other.view),
                },
            ],
        })
    }

    fn pipeline(&mut self, key: PipelineKey) -> &wgpu::RenderPipeline {
        let device = &self.ctx.device;
        type Targets = Vec<Option<wgpu::ColorTargetState>>;
        let (module, entry, targets, layout): (&wgpu::ShaderModule, &str, Targets, &wgpu::PipelineLayout) =
            match key.pass {
                PassKind::Aov => (
                    &self.aov_module,
                    "fs_aov",
                    vec![Some(AOV_FORMAT.into()), Some(AOV_FORMAT.into())],
                    &self.scene_pipeline_layout,
                ),
                PassKind::ShadowAov => (
                    &self.shadow_aov_module,
                    "fs_shadow_aov",
                    vec![Some(SHADOW_AOV_FORMAT.into())],
                    &self.shadow_aov_pipeline_layout,
                ),
                PassKind::Forward => (
                    &self.forward_module,
                    "fs_main",
                    vec![Some(wgpu::ColorTargetState {
                        format: HDR_FORMAT,
                        blend: key.blend.then_some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                    &self.scene_pipeline_layout,
                ),
            };
        self.pipelines.entry(key).or_insert_with(|| {
            let label = format!("{key:?}");
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(GpuVertex::layout())],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: if key.front_cw { wgpu::FrontFace::Cw } else { wgpu::FrontFace::Ccw },
                    cull_mode: key.cull_back.then_some(wgpu::Face::Back),
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    // Transparent surfaces are tested against depth but do not write it.
                    depth_write_enabled: Some(!key.blend),
                    // Reverse-Z: nearer is greater.
                    depth_compare: Some(wgpu::CompareFunction::Greater),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        })
    }

    fn ensure_targets(&mut self, width: u32, height: u32) -> Result<(), RenderError> {
        let max = self.ctx.max_texture_size();
        if width == 0 || height == 0 || width > max || height > max {
            return Err(RenderError::OutputSize {
                width,
                height,
                reason: format!("each side must be between 1 and {max} (this device's limit)"),
            });
        }
        if self.targets.as_ref().is_some_and(|t| t.width == width && t.height == height) {
            return Ok(());
        }
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let ctx = &self.ctx;
        let hdr = texture_2d(ctx, "hdr", width, height, HDR_FORMAT, attach | wgpu::TextureUsages::TEXTURE_BINDING);
        let tonemap_bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("tonemap bind group"),
            layout: &self.tonemap_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&hdr.create_view(&Default::default())),
            }],
        });
        self.targets = Some(Targets {
            width,
            height,
            ldr: texture_2d(ctx, "ldr", width, height, LDR_FORMAT, attach),
            depth: texture_2d(ctx, "depth", width, height, DEPTH_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT),
            aov_position: texture_2d(ctx, "aov position", width, height, AOV_FORMAT, attach),
            aov_normal: texture_2d(ctx, "aov normal depth", width, height, AOV_FORMAT, attach),
            aov_shadow: texture_2d(ctx, "aov shadow", width, height, SHADOW_AOV_FORMAT, attach),
            hdr,
            tonemap_bind_group,
        });
        Ok(())
    }

    /// Renders one frame of `scene` (already `prepare`d) from `view`.
    pub fn render(
        &mut self,
        scene: &Scene,
        prepared: &PreparedScene,
        view: &View,
        settings: &Settings,
        options: FrameOptions,
    ) -> Result<FrameOutput, RenderError> {
        let _span = tracing::info_span!("frame", width = view.width, height = view.height).entered();
        let start = Instant::now();
        self.ensure_targets(view.width, view.height)?;
        let mut lights = prepare_lights(scene, view, settings);
        let directional: Vec<&chiaro_scene::Light> =
            lights.directional_scene_index.iter().map(|&i| &scene.lights[i]).collect();
        let other: Vec<(&chiaro_scene::Light, f32)> = lights
            .other_scene_index
            .iter()
            .zip(&lights.gpu.other)
            .map(|(&i, gpu)| (&scene.lights[i], gpu.range))
            .collect();
        let mut plan = plan_shadows(view, settings, &directional, &other);
        for (slot, shadow) in lights.gpu.directional.iter_mut().zip(plan.directional) {
            slot.shadow = shadow;
        }
        let shadowed_other_light_count = shadowed_first(&mut lights, &mut plan);
        self.shadow_pass.ensure_atlases(&self.ctx.device, &plan);
        let exposure = exposure_scale(settings.render.exposure_ev100);
        let frame = GpuFrame {
            clip_from_world: view.clip_from_world(),
            view_from_world: view.view_from_world(),
            camera_position_ws: view.eye(),
            exposure_scale: exposure,
            ambient: Vec3::from(settings.render.ambient),
            directional_light_count: lights.directional_count,
            background: Vec3::from(settings.render.background),
            other_light_count: lights.other_count,
            debug_view: u32::from(options.debug_cascades),
            shadowed_other_light_count,
            _pad: [0; 2],
        };
        let queue = &self.ctx.queue;
        queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&frame));
        queue.write_buffer(&self.lights_buffer, 0, bytemuck::bytes_of(&lights.gpu));
        queue.write_buffer(&self.shadows_buffer, 0, bytemuck::bytes_of(&plan.gpu));

        let draws = ordered_draws(&prepared.gpu.draws, view);
        let passes =
            [(PassKind::Forward, true), (PassKind::Aov, options.aovs), (PassKind::ShadowAov, options.shadow_aovs)];
        for d in &draws {
            for (pass, wanted) in passes {
                if wanted {
                    self.pipeline(pipeline_key(d, pass));
                }
            }
        }
        let frame_bind_group = self.frame_bind_group(prepared);
        let mut encoder =
            self.ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let shadow_timestamps = self.timestamps.as_ref().map(|ts| (&ts.queries, 2 * timed_index("shadows")));
        let shadow_caster_draws =
            self.shadow_pass.record(&self.ctx, &mut encoder, &plan, &prepared.gpu, shadow_timestamps);
        let background = Vec3::from(settings.render.background) * exposure;
        self.record_scene_pass(&mut encoder, prepared, &frame_bind_group, &draws, PassKind::Forward, background, None);
        if options.aovs {
            self.record_scene_pass(&mut encoder, prepared, &frame_bind_group, &draws, PassKind::Aov, Vec3::ZERO, None);
        }
        self.record_tonemap(&mut encoder);
        if let Some(ts) = &self.timestamps {
            encoder.resolve_query_set(&ts.queries, 0..2 * TIMED_PASSES.len() as u32, &ts.resolve, 0);
            encoder.copy_buffer_to_buffer(&ts.resolve, 0, &ts.readback, 0, ts.resolve.size());
        }
        let cpu_prepare_ms = start.elapsed().as_secs_f64() * 1e3;
        self.ctx.queue.submit([encoder.finish()]);
        self.ctx.wait_idle()?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;
        self.ctx.take_error()?;

        let mut timings = FrameTimings { cpu_prepare_ms, gpu_pass_ms: Vec::new(), wall_ms };
        if let Some(ts) = &self.timestamps {
            let bytes = read_buffer(&self.ctx, &ts.readback)?;
            let stamps: &[u64] = bytemuck::cast_slice(&bytes);
            for (i, name) in TIMED_PASSES.iter().enumerate() {
                let skipped = (*name == "aov" && !options.aovs)
                    || (*name == "shadows" && plan.tiles.is_empty() && plan.other_tiles.is_empty());
                if skipped {
                    continue;
                }
                let ticks = stamps[2 * i + 1].saturating_sub(stamps[2 * i]);
                timings.gpu_pass_ms.push((name, ticks as f64 * ts.period_ns * 1e-6));
            }
        }
        let mut out = FrameOutput {
            width: view.width,
            height: view.height,
            timings,
            other_lights_shaded: lights.other_count,
            other_lights_dropped: lights.selection.dropped,
            shadow_status: shadow_status(scene, &lights, &plan),
            shadow_tiles: plan.tiles.len() + plan.other_tiles.len(),
            shadow_caster_draws,
            ..Default::default()
        };
        if options.readback {
            self.read_images(&mut out, exposure, options.aovs)?;
        }
        if options.shadow_aovs {
            out.shadow_aovs = self.render_shadow_aovs(scene, prepared, &frame_bind_group, &draws, &lights, &plan)?;
        }
        if options.read_shadow_atlas {
            for (name, size, atlas) in [
                ("directional", plan.atlas_size, &self.shadow_pass.directional),
                ("other", plan.other_atlas_size, &self.shadow_pass.other),
            ] {
                if size > 0 {
                    let bytes = read_texture(&self.ctx, &atlas.texture, 4)?;
                    out.shadow_atlases.push((name, size, bytemuck::cast_slice(&bytes).to_vec()));
                }
            }
        }
        Ok(out)
    }

    /// One pass per scene light writing the shadow attenuation the shading used for it.
    fn render_shadow_aovs(
        &mut self,
        scene: &Scene,
        prepared: &PreparedScene,
        frame_bind_group: &wgpu::BindGroup,
        draws: &[&Draw],
        lights: &FrameLights,
        _plan: &ShadowPlan,
    ) -> Result<Vec<Vec<f32>>, RenderError> {
        let mut out = Vec::with_capacity(scene.lights.len());
        let aov_bind_group = self.ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("aov light bind group"),
            layout: &self.aov_light_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &self.aov_lights,
                    offset: 0,
                    size: wgpu::BufferSize::new(AOV_LIGHT_STRIDE),
                }),
            }],
        });
        for light_index in 0..scene.lights.len() {
            let slot_of = |slots: &[usize]| slots.iter().position(|&i| i == light_index).map_or(NO_LIGHT, |s| s as u32);
            let value = GpuAovLight {
                directional_index: slot_of(&lights.directional_scene_index),
                other_index: slot_of(&lights.other_scene_index),
                _pad: [0; 62],
            };
            self.ctx.queue.write_buffer(&self.aov_lights, 0, bytemuck::bytes_of(&value));
            let mut encoder =
                self.ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("shadow aov") });
            self.record_scene_pass(
                &mut encoder,
                prepared,
                frame_bind_group,
                draws,
                PassKind::ShadowAov,
                Vec3::ZERO,
                Some(&aov_bind_group),
            );
            self.ctx.queue.submit([encoder.finish()]);
            let targets = self.targets.as_ref().expect("targets exist");
            let bytes = read_texture(&self.ctx, &targets.aov_shadow, 8)?;
            let pairs: &[[f32; 2]] = bytemuck::cast_slice(&bytes);
            out.push(pairs.iter().map(|p| if p[1] > 0.5 { p[0] } else { f32::NAN }).collect());
        }
        self.ctx.take_error()?;
        Ok(out)
    }

    #[allow(clippy::too_many_arguments)]
    fn record_scene_pass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        prepared: &PreparedScene,
        frame_bind_group: &wgpu::BindGroup,
        draws: &[&Draw],
        pass_kind: PassKind,
        clear: Vec3,
        aov_light: Option<&wgpu::BindGroup>,
    ) {
        let targets = self.targets.as_ref().expect("targets exist");
        let color_views: Vec<wgpu::TextureView> = match pass_kind {
            PassKind::Aov => vec![
                targets.aov_position.create_view(&Default::default()),
                targets.aov_normal.create_view(&Default::default()),
            ],
            PassKind::ShadowAov => vec![targets.aov_shadow.create_view(&Default::default())],
            PassKind::Forward => vec![targets.hdr.create_view(&Default::default())],
        };
        let depth_view = targets.depth.create_view(&Default::default());
        let clear_color = wgpu::Color { r: clear.x as f64, g: clear.y as f64, b: clear.z as f64, a: 0.0 };
        let attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = color_views
            .iter()
            .map(|view| {
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Clear(clear_color), store: wgpu::StoreOp::Store },
                })
            })
            .collect();
        let timestamp_writes = match pass_kind {
            PassKind::Forward => timestamp_writes(&self.timestamps, "forward"),
            PassKind::Aov => timestamp_writes(&self.timestamps, "aov"),
            PassKind::ShadowAov => None,
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(match pass_kind {
                PassKind::Forward => "forward pass",
                PassKind::Aov => "aov pass",
                PassKind::ShadowAov => "shadow aov pass",
            }),
            color_attachments: &attachments,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, frame_bind_group, &[]);
        if let Some(group) = aov_light {
            pass.set_bind_group(2, group, &[0]);
        }
        pass.set_vertex_buffer(0, prepared.gpu.vertices.slice(..));
        pass.set_index_buffer(prepared.gpu.indices.slice(..), wgpu::IndexFormat::Uint32);
        let mut bound_material = usize::MAX;
        let mut bound_key = None;
        for d in draws {
            let key = pipeline_key(d, pass_kind);
            if bound_key != Some(key) {
                pass.set_pipeline(&self.pipelines[&key]);
                bound_key = Some(key);
            }
            if bound_material != d.material {
                pass.set_bind_group(1, &prepared.gpu.materials[d.material], &[]);
                bound_material = d.material;
            }
            pass.draw_indexed(d.first_index..d.first_index + d.index_count, d.base_vertex, d.object..d.object + 1);
        }
    }

    fn record_tonemap(&self, encoder: &mut wgpu::CommandEncoder) {
        let targets = self.targets.as_ref().expect("targets exist");
        let view = targets.ldr.create_view(&Default::default());
        let timestamp_writes = timestamp_writes(&self.timestamps, "tonemap");
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("tonemap pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: None,
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.tonemap_pipeline);
        pass.set_bind_group(0, &targets.tonemap_bind_group, &[]);
        pass.draw(0..3, 0..1);
    }

    fn read_images(&self, out: &mut FrameOutput, exposure: f32, aovs: bool) -> Result<(), RenderError> {
        let targets = self.targets.as_ref().expect("targets exist");
        let hdr_bytes = read_texture(&self.ctx, &targets.hdr, 8)?;
        let halves: &[u16] = bytemuck::cast_slice(&hdr_bytes);
        out.hdr = halves
            .chunks_exact(4)
            .map(|p| {
                let c = [p[0], p[1], p[2], p[3]].map(f16_to_f32);
                [c[0] / exposure, c[1] / exposure, c[2] / exposure, c[3]]
            })
            .collect();
        out.ldr = read_texture(&self.ctx, &targets.ldr, 4)?;
        if aovs {
            let position = read_texture(&self.ctx, &targets.aov_position, 16)?;
            let normal = read_texture(&self.ctx, &targets.aov_normal, 16)?;
            let position: &[[f32; 4]] = bytemuck::cast_slice(&position);
            let normal: &[[f32; 4]] = bytemuck::cast_slice(&normal);
            let mut a = Aovs::default();
            for (p, n) in position.iter().zip(normal) {
                if p[3] > 0.5 {
                    a.position_ws.push([p[0], p[1], p[2]]);
                    a.normal_ws.push([n[0], n[1], n[2]]);
                    a.depth.push(n[3]);
                } else {
                    a.position_ws.push([f32::NAN; 3]);
                    a.normal_ws.push([f32::NAN; 3]);
                    a.depth.push(f32::INFINITY);
                }
            }
            out.aovs = Some(a);
        }
        Ok(())
    }
}

/// Moves the other lights that have shadow maps to the front of the upload (keeping each
/// group's importance order), sets their shadow data, and returns how many there are.
fn shadowed_first(lights: &mut FrameLights, plan: &mut ShadowPlan) -> u32 {
    let n = lights.other_scene_index.len();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&slot| plan.other[slot].x <= 0.0);
    let gpu: Vec<_> =
        order.iter().map(|&slot| GpuOtherLight { shadow: plan.other[slot], ..lights.gpu.other[slot] }).collect();
    lights.gpu.other[..n].copy_from_slice(&gpu);
    lights.other_scene_index = order.iter().map(|&slot| lights.other_scene_index[slot]).collect();
    plan.other = order.iter().map(|&slot| plan.other[slot]).collect();
    plan.other.iter().filter(|s| s.x > 0.0).count() as u32
}

fn shadow_status(scene: &Scene, lights: &FrameLights, plan: &ShadowPlan) -> Vec<ShadowStatus> {
    scene
        .lights
        .iter()
        .enumerate()
        .map(|(i, light)| {
            let packed = lights
                .directional_scene_index
                .iter()
                .position(|&s| s == i)
                .map(|slot| plan.directional[slot])
                .or_else(|| lights.other_scene_index.iter().position(|&s| s == i).map(|slot| plan.other[slot]));
            match packed {
                _ if !light.shadow.casts() => ShadowStatus::Off,
                None => ShadowStatus::NotShaded,
                Some(shadow) if shadow.x > 0.0 => ShadowStatus::Mapped,
                Some(_) => ShadowStatus::NoTile,
            }
        })
        .collect()
}

fn timestamp_writes<'a>(timestamps: &'a Option<Timestamps>, pass: &str) -> Option<wgpu::RenderPassTimestampWrites<'a>> {
    let index = timed_index(pass);
    timestamps.as_ref().map(|ts| wgpu::RenderPassTimestampWrites {
        query_set: &ts.queries,
        beginning_of_pass_write_index: Some(2 * index),
        end_of_pass_write_index: Some(2 * index + 1),
    })
}

fn pipeline_key(d: &Draw, pass: PassKind) -> PipelineKey {
    PipelineKey {
        pass,
        cull_back: !d.double_sided,
        front_cw: d.mirrored,
        blend: d.alpha_mode == AlphaMode::Blend && pass == PassKind::Forward,
    }
}

/// Opaque and masked draws first, grouped by pipeline and material; then transparent
/// draws from far to near, so blending composes correctly.
fn ordered_draws<'a>(draws: &'a [Draw], view: &View) -> Vec<&'a Draw> {
    let eye = view.eye();
    let (mut blended, mut solid): (Vec<&Draw>, Vec<&Draw>) =
        draws.iter().filter(|d| d.visible()).partition(|d| d.alpha_mode == AlphaMode::Blend);
    solid.sort_by_key(|d| (d.double_sided, d.mirrored, d.material));
    blended.sort_by(|a, b| b.center_ws.distance_squared(eye).total_cmp(&a.center_ws.distance_squared(eye)));
    solid.extend(blended);
    solid
}

/// IEEE half to single precision (the HDR target is Rgba16Float).
fn f16_to_f32(h: u16) -> f32 {
    let sign = ((h >> 15) as u32) << 31;
    let exponent = ((h >> 10) & 0x1f) as u32;
    let mantissa = (h & 0x3ff) as u32;
    let bits = match (exponent, mantissa) {
        (0, 0) => sign,
        (0, m) => {
            // Subnormal: renormalise.
            let shift = m.leading_zeros() - 21;
            sign | ((127 - 15 - shift + 1) << 23) | ((m << shift) & 0x3ff) << 13
        }
        (0x1f, m) => sign | 0x7f80_0000 | (m << 13),
        (e, m) => sign | ((e + 127 - 15) << 23) | (m << 13),
    };
    f32::from_bits(bits)
}

#[cfg(test)]
mod tests {
    use super::f16_to_f32;

    #[test]
    fn half_floats_convert() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x7bff), 65504.0);
        assert!(f16_to_f32(0x7c00).is_infinite());
        assert!((f16_to_f32(0x0001) - 5.960_464_5e-8).abs() < 1e-12);
        assert!((f16_to_f32(0x0200) - 3.051_757_8e-5).abs() < 1e-10);
        assert_eq!(f16_to_f32(0x3555), 0.333_251_95);
    }
}
