//! The composed WGSL of each pass (built from `shaders/` by build.rs with WESL imports).

/// Forward lighting: `vs_main`, `fs_main`.
pub const FORWARD: &str = include_str!(concat!(env!("OUT_DIR"), "/forward.wgsl"));
/// Position, normal and depth AOVs: `vs_main`, `fs_aov`.
pub const AOV: &str = include_str!(concat!(env!("OUT_DIR"), "/aov.wgsl"));
/// Tone mapping: `vs_fullscreen`, `fs_tonemap`.
pub const TONEMAP: &str = include_str!(concat!(env!("OUT_DIR"), "/tonemap.wgsl"));

/// Per-light shadow attenuation: `vs_main`, `fs_shadow_aov`.
pub const SHADOW_AOV: &str = include_str!(concat!(env!("OUT_DIR"), "/shadow_aov.wgsl"));
/// Shadow casters, depth only: `vs_caster`.
pub const SHADOW_CASTER: &str = include_str!(concat!(env!("OUT_DIR"), "/shadow_caster.wgsl"));

/// Every composed shader with its name, for validation.
pub const ALL: [(&str, &str); 5] = [
    ("forward", FORWARD),
    ("aov", AOV),
    ("shadow_aov", SHADOW_AOV),
    ("tonemap", TONEMAP),
    ("shadow_caster", SHADOW_CASTER),
];

pub fn module(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}
