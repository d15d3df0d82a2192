//! Every composed shader parses and validates with naga, and every `Gpu*` struct has the
//! size naga lays its WGSL twin out with, so CPU and GPU agree on each byte (and on the
//! light-count constants, which size the light arrays).

use chiaro_render::gpu_types::*;
use chiaro_render::shaders;

fn module(source: &str) -> naga::Module {
    naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)))
}

#[test]
fn every_shader_validates() {
    for (name, source) in shaders::ALL {
        let m = module(source);
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
            .validate(&m)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
        assert!(!m.entry_points.is_empty(), "{name} has entry points");
    }
}

/// Size of the struct whose (possibly WESL-mangled) name ends with `_<name>` or is `name`.
fn wgsl_size(m: &naga::Module, name: &str) -> u32 {
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(m.to_ctx()).unwrap();
    let suffix = format!("_{name}");
    let (handle, _) = m
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref().is_some_and(|n| n == name || n.ends_with(&suffix)))
        .unwrap_or_else(|| panic!("struct {name} not found"));
    layouter[handle].size
}

#[test]
fn gpu_structs_match_wgsl_layout() {
    let forward = module(shaders::FORWARD);
    let checks: [(&str, usize); 7] = [
        ("Frame", size_of::<GpuFrame>()),
        ("DirectionalLight", size_of::<GpuDirectionalLight>()),
        ("OtherLight", size_of::<GpuOtherLight>()),
        ("Lights", size_of::<GpuLights>()),
        ("Object", size_of::<GpuObject>()),
        ("Material", size_of::<GpuMaterial>()),
        ("TextureTransform", size_of::<GpuTextureTransform>()),
    ];
    for (name, rust_size) in checks {
        assert_eq!(wgsl_size(&forward, name) as usize, rust_size, "{name}");
    }
}

#[test]
fn light_limits_match_the_shader_constants() {
    let forward = module(shaders::FORWARD);
    for (name, value) in [
        ("MAX_DIRECTIONAL_LIGHTS", chiaro_math::light::MAX_DIRECTIONAL_LIGHTS),
        ("MAX_OTHER_LIGHTS", chiaro_math::light::MAX_OTHER_LIGHTS),
    ] {
        let (_, c) = forward
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref().is_some_and(|n| n.ends_with(name)))
            .unwrap_or_else(|| panic!("constant {name} not found"));
        match forward.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => {
                assert_eq!(v as usize, value, "{name}")
            }
            ref other => panic!("{name} is {other:?}"),
        }
    }
}
