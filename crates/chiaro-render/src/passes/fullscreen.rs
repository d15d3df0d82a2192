//! What the full-screen passes share: a pipeline that draws one triangle over the target
//! from `vs_fullscreen`, and a layout of unfilterable 2D textures read with textureLoad.

/// A bind group layout of 2D textures of `sample_types` (unfilterable for the full-screen
/// passes' textureLoad; the background's filterable environment image), binding 0 up,
/// read by the fragment shader.
pub fn texture_layout(
    device: &wgpu::Device,
    label: &str,
    sample_types: &[wgpu::TextureSampleType],
) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = sample_types
        .iter()
        .enumerate()
        .map(|(binding, &sample_type)| wgpu::BindGroupLayoutEntry {
            binding: binding as u32,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        })
        .collect();
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries: &entries })
}

/// A bind group over `views` in `layout`, binding 0 up.
pub fn texture_bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    views: &[&wgpu::TextureView],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = views
        .iter()
        .enumerate()
        .map(|(binding, view)| wgpu::BindGroupEntry {
            binding: binding as u32,
            resource: wgpu::BindingResource::TextureView(view),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout, entries: &entries })
}

/// What differs between full-screen pipelines.
pub struct FullscreenDesc<'a> {
    /// The pipeline's label.
    pub label: &'a str,
    /// A module with `vs_fullscreen` and the fragment entry point.
    pub module: &'a wgpu::ShaderModule,
    /// The pipeline layout.
    pub layout: &'a wgpu::PipelineLayout,
    /// The fragment shader's entry point.
    pub fragment_entry: &'a str,
    /// Pipeline-overridable constants of the fragment shader.
    pub constants: &'a [(&'a str, f64)],
    /// The format of the one colour target.
    pub format: wgpu::TextureFormat,
}

/// A pipeline drawing one triangle over the whole target, no depth, no blending.
pub fn pipeline(device: &wgpu::Device, desc: FullscreenDesc<'_>) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(desc.label),
        layout: Some(desc.layout),
        vertex: wgpu::VertexState {
            module: desc.module,
            entry_point: Some("vs_fullscreen"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: desc.module,
            entry_point: Some(desc.fragment_entry),
            compilation_options: wgpu::PipelineCompilationOptions { constants: desc.constants, ..Default::default() },
            targets: &[Some(desc.format.into())],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// Records one full-screen triangle into `target`, cleared first.
pub fn draw(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    target: &wgpu::TextureView,
    pipeline: &wgpu::RenderPipeline,
    bind_group: &wgpu::BindGroup,
    timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[super::mesh::cleared(target, wgpu::Color::BLACK)],
        depth_stencil_attachment: None,
        timestamp_writes,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, bind_group, &[]);
    pass.draw(0..3, 0..1);
}
