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

/// The deferred path's G-buffer pass: `vs_main`, `fs_gbuffer`.
pub const GBUFFER: &str = include_str!(concat!(env!("OUT_DIR"), "/gbuffer.wgsl"));
/// The deferred path's light volumes: `vs_volume`, `vs_fullscreen`, `fs_mark`, `fs_directional_lights`, `fs_volume_light`.
pub const DEFERRED_LIGHT: &str = include_str!(concat!(env!("OUT_DIR"), "/deferred_light.wgsl"));
/// Debug views of the G-buffer and the light overdraw: `vs_fullscreen`, `fs_debug`.
pub const DEBUG_VIEW: &str = include_str!(concat!(env!("OUT_DIR"), "/debug_view.wgsl"));
/// The LDR light buffer back to radiance: `vs_fullscreen`, `fs_decode`.
pub const LDR_DECODE: &str = include_str!(concat!(env!("OUT_DIR"), "/ldr_decode.wgsl"));

/// Every composed shader with its name, for validation.
pub const ALL: [(&str, &str); 9] = [
    ("forward", FORWARD),
    ("aov", AOV),
    ("shadow_aov", SHADOW_AOV),
    ("tonemap", TONEMAP),
    ("shadow_caster", SHADOW_CASTER),
    ("gbuffer", GBUFFER),
    ("deferred_light", DEFERRED_LIGHT),
    ("debug_view", DEBUG_VIEW),
    ("ldr_decode", LDR_DECODE),
];

pub fn module(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}
