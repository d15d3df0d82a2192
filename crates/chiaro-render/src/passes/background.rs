//! The environment behind the scene, drawn by the passes that make the lit image (the
//! forward pass after its opaque draws, the G-buffer pass after its draws): one triangle
//! at the far plane, depth-tested, so that it covers only what no surface
//! did, sample by sample under MSAA. Shader: `shaders/background.wesl`.

use super::fullscreen;
use crate::overrides;
use crate::shaders;
use std::collections::HashMap;

/// What a background pipeline must match in the pass that draws it.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct BackgroundTargets {
    /// The colour attachments' formats; the first takes the background, the others are
    /// left as they are.
    pub color_formats: Vec<wgpu::TextureFormat>,
    /// Samples per pixel.
    pub samples: u32,
    /// The light buffer stores exp2(-light).
    pub ldr_exp2: bool,
}

/// Background pipelines, made per attachment set when first used.
pub struct BackgroundPipelines {
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    /// Group 1: the environment's image, which group 0 has no room for.
    image_layout: wgpu::BindGroupLayout,
    /// The image bound, and its group, made again when the image changes.
    image_group: Option<(wgpu::TextureView, wgpu::BindGroup)>,
    depth_format: wgpu::TextureFormat,
    pipelines: HashMap<BackgroundTargets, wgpu::RenderPipeline>,
}

impl BackgroundPipelines {
    /// Pipelines with group 0 (the frame's) and the environment's image as group 1,
    /// over depth of `depth_format`.
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout, depth_format: wgpu::TextureFormat) -> Self {
        let filterable = wgpu::TextureSampleType::Float { filterable: true };
        let image_layout = fullscreen::texture_layout(device, "background image layout", &[filterable]);
        BackgroundPipelines {
            module: shaders::module(device, "background", crate::wgsl!("background")),
            layout: device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("background layout"),
                bind_group_layouts: &[Some(frame_layout), Some(&image_layout)],
                immediate_size: 0,
            }),
            image_layout,
            image_group: None,
            depth_format,
            pipelines: HashMap::new(),
        }
    }

    /// Makes the pipeline for `targets` if it is new, and binds `environment_image`.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        targets: &BackgroundTargets,
        environment_image: &wgpu::TextureView,
    ) {
        if self.image_group.as_ref().is_none_or(|(view, _)| view != environment_image) {
            let group = fullscreen::texture_bind_group(device, &self.image_layout, &[environment_image]);
            self.image_group = Some((environment_image.clone(), group));
        }
        if self.pipelines.contains_key(targets) {
            return;
        }
        let color_targets: Vec<Option<wgpu::ColorTargetState>> = targets
            .color_formats
            .iter()
            .enumerate()
            .map(|(i, &format)| {
                let write_mask = if i == 0 { wgpu::ColorWrites::ALL } else { wgpu::ColorWrites::empty() };
                Some(wgpu::ColorTargetState { format, blend: None, write_mask })
            })
            .collect();
        let constants = [overrides::LDR_EXP2.flag(targets.ldr_exp2)];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("background"),
            layout: Some(&self.layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some("vs_background"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: self.depth_format,
                depth_write_enabled: Some(false),
                // Reverse Z: the far plane is 0, where the depth was cleared, and no surface
                // is farther (0 >= depth only where nothing was drawn).
                depth_compare: Some(wgpu::CompareFunction::GreaterEqual),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            }),
            multisample: wgpu::MultisampleState { count: targets.samples, ..Default::default() },
            fragment: Some(wgpu::FragmentState {
                module: &self.module,
                entry_point: Some("fs_background"),
                compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
                targets: &color_targets,
            }),
            multiview_mask: None,
            cache: None,
        });
        self.pipelines.insert(targets.clone(), pipeline);
    }

    /// Draws the background into `pass` (group 0 bound), with the pipeline and image
    /// group `prepare` made; group 1 is left holding the image.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, targets: &BackgroundTargets) {
        pass.set_pipeline(&self.pipelines[targets]);
        let (_, group) = self.image_group.as_ref().expect("prepared");
        pass.set_bind_group(1, group, &[]);
        pass.draw(0..3, 0..1);
    }
}
