//! What every pass that draws the scene's meshes from the camera shares: the pipelines
//! (one per cull mode, winding, blending and topology, since those are pipeline state in
//! wgpu) and
//! the loop that binds materials and issues the draws in the plan's order.

use super::targets::DEPTH;
use crate::gpu::GpuVertex;
use crate::graph::{PassContext, Target, TargetDesc};
use crate::overrides::Override;
use crate::plan::FramePlan;
use crate::plan::draws::{Draw, instanced_runs};
use crate::scene::GpuScene;
use chiaro_scene::{AlphaMode, Topology};
use std::collections::HashMap;

/// The forward path's multisampled depth (`FramePlan::msaa` samples).
pub const DEPTH_MULTISAMPLED: Target = Target("depth multisampled");

/// The depth target the forward path draws into: multisampled with MSAA.
pub fn forward_depth(plan: &FramePlan) -> Target {
    if plan.msaa > 1 { DEPTH_MULTISAMPLED } else { DEPTH }
}

/// A scene depth target of `samples` per pixel in the device's `format`; `sampled` where
/// the contact depth pass reads it (else a GPU may keep it compressed).
pub fn depth_desc(format: wgpu::TextureFormat, samples: u32, sampled: bool) -> TargetDesc {
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
    let usage = if sampled { usage | wgpu::TextureUsages::TEXTURE_BINDING } else { usage };
    TargetDesc::view_sized(format, usage).with_samples(samples)
}

/// What picks one pipeline of a mesh pass: culling, winding, blending, depth test, alpha
/// test and samples.
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
pub struct MeshPipelineKey {
    cull_back: bool,
    front_cw: bool,
    blend: bool,
    /// An opaque draw whose depth a prepass already wrote: tests for equality, no write.
    prepassed: bool,
    /// An alpha-tested draw, where the pipelines have an `alpha_test_override`.
    alpha_tested: bool,
    /// A draw whose material has a texture, where the pipelines have a
    /// `textured_override`.
    textured: bool,
    /// A draw whose material has KHR_materials_* extensions, where the pipelines have a
    /// `layered_override`.
    layered: bool,
    samples: u32,
    topology: Topology,
}

/// How a pass tests depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthTest {
    /// Keeps the nearest surface (reverse-Z: greater is nearer); transparent draws test
    /// but do not write.
    Nearest,
    /// Passes where the surface is the one an earlier pass kept (GreaterEqual on its
    /// depth), so each pixel is shaded once; every draw writes, so the nearest
    /// transparent surface is the one reported.
    SameSurface,
    /// After a depth prepass of the opaque draws: those pass only where they are the
    /// surface the prepass kept (shading each pixel once); the others as `Nearest`.
    AfterPrepass,
    /// After the G-buffer pass wrote the opaque and masked draws' depth: those pass only
    /// where they are that surface (the deferred path's forward-shaded layered draws);
    /// transparent draws as `Nearest`.
    OverGBuffer,
}

/// A mesh pass's pipelines, made on first use for each `MeshPipelineKey`.
pub struct MeshPipelines {
    label: &'static str,
    module: wgpu::ShaderModule,
    /// None: depth only.
    fragment_entry: Option<&'static str>,
    layout: wgpu::PipelineLayout,
    color_formats: Vec<wgpu::TextureFormat>,
    /// Transparent draws blend (pre-multiplied) into the targets.
    blends: bool,
    depth_test: DepthTest,
    depth_format: wgpu::TextureFormat,
    marks_stencil: bool,
    constants: Vec<(&'static str, f64)>,
    alpha_test_override: Option<Override>,
    textured_override: Option<Override>,
    layered_override: Option<Override>,
    pipelines: HashMap<MeshPipelineKey, wgpu::RenderPipeline>,
    /// Samples per pixel of the targets of the frame being drawn (set by `prepare`).
    samples: u32,
}

/// What a mesh pass's pipelines share: shaders, layout, targets and depth test.
pub struct MeshPipelinesDesc {
    /// The pipelines' label.
    pub label: &'static str,
    /// The shader module with `vs_main` and the fragment entry point.
    pub module: wgpu::ShaderModule,
    /// None: depth only.
    pub fragment_entry: Option<&'static str>,
    /// The pipeline layout (group 0 the frame, group 1 the material).
    pub layout: wgpu::PipelineLayout,
    /// The colour targets' formats, in attachment order.
    pub color_formats: Vec<wgpu::TextureFormat>,
    /// Transparent draws blend (pre-multiplied) into the targets.
    pub blends: bool,
    /// How draws test and write depth.
    pub depth_test: DepthTest,
    /// The depth target's format.
    pub depth_format: wgpu::TextureFormat,
    /// Sets stencil bit `STENCIL_SURFACE` wherever a surface is drawn (the deferred
    /// path's light volumes shade only those pixels).
    pub marks_stencil: bool,
    /// Pipeline-overridable constants of the module.
    pub constants: Vec<(&'static str, f64)>,
    /// A boolean override set only for alpha-tested draws' pipelines, so that the others
    /// run a shader that never discards.
    pub alpha_test_override: Option<Override>,
    /// A boolean override set only for textured draws' pipelines, so that the others
    /// sample no texture: lavapipe pays for every sample, even of a 1x1 default.
    pub textured_override: Option<Override>,
    /// A boolean override set only for layered (KHR_materials_*) draws' pipelines, so
    /// that the others compile the layered BRDF out.
    pub layered_override: Option<Override>,
}

/// Stencil bit of pixels that hold a surface (set by the G-buffer pass).
pub const STENCIL_SURFACE: u32 = 1;

/// Replaces the `STENCIL_SURFACE` bit wherever a fragment passes the depth test.
fn stencil_marking() -> wgpu::StencilState {
    let face = wgpu::StencilFaceState {
        compare: wgpu::CompareFunction::Always,
        fail_op: wgpu::StencilOperation::Keep,
        depth_fail_op: wgpu::StencilOperation::Keep,
        pass_op: wgpu::StencilOperation::Replace,
    };
    wgpu::StencilState { front: face, back: face, read_mask: 0, write_mask: STENCIL_SURFACE }
}

impl MeshPipelines {
    /// Pipelines made from `desc`, none yet (each is made on first use).
    pub fn new(desc: MeshPipelinesDesc) -> MeshPipelines {
        MeshPipelines {
            label: desc.label,
            module: desc.module,
            fragment_entry: desc.fragment_entry,
            layout: desc.layout,
            color_formats: desc.color_formats,
            blends: desc.blends,
            depth_test: desc.depth_test,
            depth_format: desc.depth_format,
            marks_stencil: desc.marks_stencil,
            constants: desc.constants,
            alpha_test_override: desc.alpha_test_override,
            textured_override: desc.textured_override,
            layered_override: desc.layered_override,
            pipelines: HashMap::new(),
            samples: 1,
        }
    }

    fn key(&self, d: &Draw) -> MeshPipelineKey {
        MeshPipelineKey {
            cull_back: !d.double_sided,
            front_cw: d.mirrored,
            blend: self.blends && d.alpha_mode == AlphaMode::Blend,
            prepassed: match self.depth_test {
                DepthTest::AfterPrepass => d.alpha_mode == AlphaMode::Opaque,
                DepthTest::OverGBuffer => d.alpha_mode != AlphaMode::Blend,
                DepthTest::Nearest | DepthTest::SameSurface => false,
            },
            alpha_tested: self.alpha_test_override.is_some() && d.alpha_mode == AlphaMode::Mask,
            textured: self.textured_override.is_none() || d.textured,
            layered: self.layered_override.is_some() && d.layered,
            samples: self.samples,
            topology: d.topology,
        }
    }

    /// Makes the pipelines the draws in `order` need, for targets of `samples` samples
    /// per pixel.
    pub fn prepare(&mut self, device: &wgpu::Device, draws: &[Draw], order: &[u32], samples: u32) {
        self.samples = samples;
        for &i in order {
            let key = self.key(&draws[i as usize]);
            if !self.pipelines.contains_key(&key) {
                let pipeline = self.create(device, key);
                self.pipelines.insert(key, pipeline);
            }
        }
    }

    fn create(&self, device: &wgpu::Device, key: MeshPipelineKey) -> wgpu::RenderPipeline {
        let targets: Vec<Option<wgpu::ColorTargetState>> = self
            .color_formats
            .iter()
            .map(|&format| {
                Some(wgpu::ColorTargetState {
                    format,
                    blend: key.blend.then_some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
                    write_mask: wgpu::ColorWrites::ALL,
                })
            })
            .collect();
        let (depth_compare, depth_write) = match self.depth_test {
            _ if key.prepassed => (wgpu::CompareFunction::GreaterEqual, false),
            DepthTest::Nearest | DepthTest::AfterPrepass | DepthTest::OverGBuffer => {
                (wgpu::CompareFunction::Greater, !key.blend)
            }
            DepthTest::SameSurface => (wgpu::CompareFunction::GreaterEqual, true),
        };
        let mut constants = self.constants.clone();
        if let Some(alpha_tested) = self.alpha_test_override {
            constants.push(alpha_tested.flag(key.alpha_tested));
        }
        if let Some(textured) = self.textured_override {
            constants.push(textured.flag(key.textured));
        }
        if let Some(layered) = self.layered_override {
            constants.push(layered.flag(key.layered));
        }
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&format!("{} {key:?}", self.label)),
            layout: Some(&self.layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(GpuVertex::layout())],
            },
            primitive: wgpu::PrimitiveState {
                topology: match key.topology {
                    Topology::Triangles => wgpu::PrimitiveTopology::TriangleList,
                    Topology::Lines => wgpu::PrimitiveTopology::LineList,
                    Topology::Points => wgpu::PrimitiveTopology::PointList,
                },
                front_face: if key.front_cw { wgpu::FrontFace::Cw } else { wgpu::FrontFace::Ccw },
                cull_mode: key.cull_back.then_some(wgpu::Face::Back),
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: self.depth_format,
                depth_write_enabled: Some(depth_write),
                depth_compare: Some(depth_compare),
                stencil: if self.marks_stencil { stencil_marking() } else { Default::default() },
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState { count: key.samples, ..Default::default() },
            fragment: self.fragment_entry.map(|entry| wgpu::FragmentState {
                module: &self.module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }

    /// Draws the camera's draws into `colors` in a pass of its own, tested against the
    /// scene depth the frame left (loaded, not cleared), with the frame's bind group: the
    /// passes that read out what the image shows (AOVs, ids).
    pub fn draw_over_scene_depth(
        &self,
        cx: &mut PassContext<'_>,
        label: &str,
        colors: &[Option<wgpu::RenderPassColorAttachment<'_>>],
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: colors,
            depth_stencil_attachment: Some(scene_depth(cx.targets.view(DEPTH), true)),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, cx.frame_bind_group, &[]);
        self.draw(&mut pass, cx.scene, &cx.plan.camera_draws);
    }

    /// Issues the draws in `order` (pipelines `prepare`d), binding each material once
    /// per run of draws that share it. Group 0 must be bound by the caller.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, scene: &GpuScene, order: &[u32]) {
        pass.set_vertex_buffer(0, scene.vertices.slice(..));
        pass.set_index_buffer(scene.indices.slice(..), wgpu::IndexFormat::Uint32);
        let mut bound_material = usize::MAX;
        let mut bound_key = None;
        for (d, instances) in instanced_runs(&scene.draws, order) {
            let key = self.key(d);
            if bound_key != Some(key) {
                pass.set_pipeline(&self.pipelines[&key]);
                bound_key = Some(key);
            }
            if bound_material != d.material {
                pass.set_bind_group(1, &scene.materials[d.material], &[]);
                bound_material = d.material;
            }
            pass.draw_indexed(
                d.first_index..d.first_index + d.index_count,
                d.base_vertex,
                d.object..d.object + instances,
            );
        }
    }
}

/// A colour attachment that clears to `clear` and keeps what the pass writes.
pub fn cleared(view: &wgpu::TextureView, clear: wgpu::Color) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations { load: wgpu::LoadOp::Clear(clear), store: wgpu::StoreOp::Store },
    })
}

/// The scene depth target, kept from the forward pass (`load`) or cleared to the far
/// plane (reverse-Z: 0) with stencil 0.
pub fn scene_depth(view: &wgpu::TextureView, load: bool) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    let (depth_load, stencil_load) = if load {
        (wgpu::LoadOp::Load, wgpu::LoadOp::Load)
    } else {
        (wgpu::LoadOp::Clear(0.0), wgpu::LoadOp::Clear(0))
    };
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations { load: depth_load, store: wgpu::StoreOp::Store }),
        stencil_ops: Some(wgpu::Operations { load: stencil_load, store: wgpu::StoreOp::Store }),
    }
}
