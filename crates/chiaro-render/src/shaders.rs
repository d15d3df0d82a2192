//! The composed WGSL of each shader artifact (built from `shaders/` by build.rs with WESL
//! imports, one artifact per top-level file that `passes/list.rs` names).

/// The composed WGSL of the artifact named `$name` (a top-level file of `shaders/`).
#[macro_export]
#[doc(hidden)]
macro_rules! wgsl {
    ($name:literal) => {
        include_str!(concat!(env!("OUT_DIR"), "/", $name, ".wgsl"))
    };
}

/// Every composed shader with its name, for validation.
pub fn all() -> Vec<(&'static str, &'static str)> {
    crate::passes::shader_sources()
}

/// A shader module from composed WGSL `source`, labelled `label`.
pub fn module(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

/// The compute pipeline of `module`'s entry point `entry` (labelled so), its bind group
/// layouts derived from what the entry uses.
pub fn compute_pipeline(device: &wgpu::Device, module: &wgpu::ShaderModule, entry: &str) -> wgpu::ComputePipeline {
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: None,
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}
