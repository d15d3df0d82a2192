//! The shadow AOV pass, when the caller asks for it: per scene light, the shadow term the
//! shading used for that light (1 lit, 0 shadowed) and coverage, for the surface the
//! camera passes kept in each pixel, one layer of an array target per light.

use super::targets::DEPTH;
use super::mesh::{DepthTest, MeshPipelines, MeshPipelinesDesc, cleared, scene_depth};
use super::targets::{DIRECTIONAL_ATLAS, LOCAL_ATLAS, SHADOW_TINTS};
use crate::gpu::GpuAovLight;
use crate::graph::target::ATTACHMENT_COPY;
use crate::graph::{FramePass, PassContext, PassInit, PassSetup, PassType, PrepareContext, Target, TargetDesc};
use crate::overrides;
use crate::plan::FramePlan;
use crate::plan::features::ShaderFeatures;
use crate::plan::lights::LightId;
use crate::shader_constants::{MAX_UNIFORM_LIGHTS, NO_LIGHT};
use crate::shaders;
use std::collections::HashMap;

/// Shadow term; 0 where no surface is, else 1 + the shadow map's texels per pixel (1: no
/// map sampled). Two channels: a scene of many lights at a large size makes many layers.
pub const SHADOW_AOV_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;
/// One layer per scene light, in scene order.
pub const SHADOW: Target = Target("aov shadow");

/// Writes each scene light's shadow term into its layer of the shadow AOV array.
pub struct ShadowAovPass {
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    depth_format: wgpu::TextureFormat,
    /// The keys of the override constants the shader declares, read from its source once.
    declared: Vec<&'static str>,
    /// One set per shader specialisation (the override constants of the frame's features
    /// that the shader declares), made when first used: with every feature compiled in,
    /// llvmpipe took seconds and gigabytes to build each pipeline of the benchmark scene.
    pipelines: HashMap<Specialisation, MeshPipelines>,
    light_layout: wgpu::BindGroupLayout,
    /// One `GpuAovLight` per scene light, each at a multiple of `stride`.
    lights: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    stride: u64,
}

/// The override constants of a frame's features that the shadow AOV shader declares, as
/// (key, value bits): frames whose features differ only in what it does not read share
/// pipelines.
type Specialisation = Vec<(&'static str, u64)>;

impl PassType for ShadowAovPass {
    const NAME: &'static str = "shadow aov";

    fn setup(plan: &FramePlan, pass: &mut PassSetup) {
        let lights = plan.scene_light_count() as u32;
        if !plan.request.shadow_aovs || lights == 0 {
            return;
        }
        let desc = TargetDesc::view_sized(SHADOW_AOV_FORMAT, ATTACHMENT_COPY).with_layers(lights);
        pass.read(DIRECTIONAL_ATLAS).read(LOCAL_ATLAS).read(SHADOW_TINTS).modify(DEPTH).create(SHADOW, desc).export(SHADOW);
    }

    fn new(init: &PassInit<'_>) -> ShadowAovPass {
        ShadowAovPass::make(init.device, init.frame_layout, init.material_layout, init.depth_format)
    }
}

impl ShadowAovPass {
    fn make(
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
            module: shaders::module(device, "shadow aov", crate::wgsl!("shadow_aov")),
            layout,
            depth_format,
            declared: overrides::declared_in(crate::wgsl!("shadow_aov")).iter().map(|o| o.key).collect(),
            pipelines: HashMap::new(),
            light_layout,
            lights: None,
            stride: (size_of::<GpuAovLight>() as u64).div_ceil(alignment) * alignment,
        }
    }

    /// The specialisation of the shader to `features`.
    fn specialisation(&self, features: ShaderFeatures) -> Specialisation {
        let constants = features.constants().into_iter().filter(|(key, _)| self.declared.contains(key));
        constants.map(|(key, value)| (key, value.to_bits())).collect()
    }

    /// The pipelines specialised to `key`.
    fn pipelines_for(&self, key: &Specialisation) -> MeshPipelines {
        MeshPipelines::new(MeshPipelinesDesc {
            label: "shadow aov",
            module: self.module.clone(),
            fragment_entry: Some("fs_shadow_aov"),
            layout: self.layout.clone(),
            color_formats: vec![SHADOW_AOV_FORMAT],
            blends: false,
            depth_test: DepthTest::SameSurface,
            depth_format: self.depth_format,
            marks_stencil: false,
            constants: key.iter().map(|&(name, bits)| (name, f64::from_bits(bits))).collect(),
            alpha_test_override: None,
            textured_override: None,
            layered_override: None,
        })
    }
}

impl FramePass for ShadowAovPass {
    /// Uploads the lights to report, one per scene light: its index in the frame's light
    /// buffer (`NO_LIGHT` where the frame does not shade it, or past the uniform light
    /// buffer, which the shader reads). Makes the pipelines.
    fn prepare(&mut self, cx: &PrepareContext<'_>) {
        let (device, plan) = (cx.device, cx.plan);
        let light_indices: Vec<u32> = (0..plan.scene_light_count())
            .map(|i| {
                plan.light_index(LightId(i as u32))
                    .filter(|&k| k < MAX_UNIFORM_LIGHTS as usize)
                    .map_or(NO_LIGHT, |k| k as u32)
            })
            .collect();
        let key = self.specialisation(plan.features);
        if !self.pipelines.contains_key(&key) {
            let made = self.pipelines_for(&key);
            self.pipelines.insert(key.clone(), made);
        }
        let pipelines = self.pipelines.get_mut(&key).expect("made above");
        pipelines.prepare(device, &cx.scene.draws, &plan.camera_draws, 1);
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
        cx.queue.write_buffer(buffer, 0, &bytes);
    }

    /// One wgpu pass per scene light, each into its layer; the first carries the start
    /// timestamp, the last the end.
    fn record(&self, cx: &mut PassContext<'_>) {
        let (_, light_bind_group) = self.lights.as_ref().expect("prepared");
        let count = cx.plan.scene_light_count();
        for k in 0..count {
            let layer = cx.targets.layer_view(SHADOW, k as u32);
            let timestamp_writes = cx.timestamps.as_ref().and_then(|t| t.writes(k == 0, k + 1 == count));
            let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow aov pass"),
                color_attachments: &[cleared(&layer, wgpu::Color::TRANSPARENT)],
                depth_stencil_attachment: Some(scene_depth(cx.targets.view(DEPTH), true)),
                timestamp_writes,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, cx.frame_bind_group, &[]);
            pass.set_bind_group(2, light_bind_group, &[(k as u64 * self.stride) as u32]);
            self.pipelines[&self.specialisation(cx.plan.features)].draw(&mut pass, cx.scene, &cx.plan.camera_draws);
        }
    }
}
