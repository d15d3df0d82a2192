//! Every composed shader parses and validates with naga; every `Gpu*` struct a shader
//! reads has the size and field offsets naga lays its WGSL twin out with, so CPU and GPU
//! agree on each byte; and the constants the shaders import are Rust's.

use chiaro_render::gpu::GPU_STRUCT_LAYOUTS;
use chiaro_render::shader_constants::{F32_CONSTANTS, U32_CONSTANTS};
use chiaro_render::shaders;

fn module(source: &str) -> naga::Module {
    naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)))
}

fn modules() -> Vec<(&'static str, naga::Module)> {
    shaders::all().into_iter().map(|(name, source)| (name, module(source))).collect()
}

/// Whether a (possibly WESL-mangled) declaration name is `name`: `package_common_frame_Frame`
/// for a struct, `constants__1MAX_CASCADES` for a constant of WESL's `constants` module.
fn is_named(declared: Option<&str>, name: &str) -> bool {
    declared.is_some_and(|n| {
        let unmangled_constant =
            n.strip_prefix("constants__").map(|rest| rest.trim_start_matches(|c: char| c.is_ascii_digit()));
        n == name || n.ends_with(&format!("_{name}")) || unmangled_constant == Some(name)
    })
}

#[test]
fn every_shader_validates() {
    for (name, source) in shaders::all() {
        let m = module(source);
        // Point cookies live in a cube array, which every Vulkan, Metal and DX12 device has.
        let capabilities = naga::valid::Capabilities::CUBE_ARRAY_TEXTURES;
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), capabilities)
            .validate(&m)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
        assert!(!m.entry_points.is_empty(), "{name} has entry points");
    }
}

#[test]
fn every_gpu_struct_is_checked() {
    // The `Gpu*` structs declared in src/gpu, except the vertex (read as attributes; its
    // offsets are checked against the attribute list in src/gpu/vertex.rs).
    let sources = [
        include_str!("../src/gpu/environment.rs"),
        include_str!("../src/gpu/frame.rs"),
        include_str!("../src/gpu/light.rs"),
        include_str!("../src/gpu/material.rs"),
        include_str!("../src/gpu/shadow.rs"),
    ];
    let declared: Vec<&str> = sources
        .iter()
        .flat_map(|s| s.lines())
        .filter_map(|l| l.trim().strip_prefix("pub struct "))
        .map(|rest| rest.split(|c: char| !c.is_alphanumeric()).next().unwrap())
        .collect();
    assert!(declared.len() >= 10, "{declared:?}");
    for name in declared {
        assert!(GPU_STRUCT_LAYOUTS.iter().any(|l| l.rust_name == name), "{name} is missing from GPU_STRUCT_LAYOUTS");
    }
}

#[test]
fn gpu_structs_match_the_wgsl_layout_field_by_field() {
    let modules = modules();
    for layout in GPU_STRUCT_LAYOUTS {
        let wgsl_name = layout.rust_name.strip_prefix("Gpu").expect("Gpu prefix");
        let (shader, m, handle) = modules
            .iter()
            .find_map(|(shader, m)| {
                m.types.iter().find(|(_, t)| is_named(t.name.as_deref(), wgsl_name)).map(|(h, _)| (shader, m, h))
            })
            .unwrap_or_else(|| panic!("no shader declares struct {wgsl_name}"));
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(m.to_ctx()).unwrap();
        assert_eq!(layouter[handle].size as usize, layout.size, "size of {wgsl_name} ({shader})");
        let naga::TypeInner::Struct { members, .. } = &m.types[handle].inner else {
            panic!("{wgsl_name} is not a struct");
        };
        for (field, offset) in layout.fields {
            let member = members
                .iter()
                .find(|member| member.name.as_deref() == Some(field))
                .unwrap_or_else(|| panic!("{wgsl_name} has no field {field}"));
            assert_eq!(member.offset as usize, *offset, "offset of {wgsl_name}.{field} ({shader})");
        }
        for member in members {
            let name = member.name.as_deref().unwrap_or_default();
            assert!(
                name.starts_with('_') || layout.fields.iter().any(|(f, _)| *f == name),
                "{wgsl_name}.{name} is not listed for {}",
                layout.rust_name
            );
        }
    }
}

#[test]
fn the_shaders_constants_are_rusts() {
    let modules = modules();
    let mut seen = 0;
    for (shader, m) in &modules {
        for (_, c) in m.constants.iter() {
            let value = &m.global_expressions[c.init];
            if let Some((name, expected)) = U32_CONSTANTS.iter().find(|(n, _)| is_named(c.name.as_deref(), n)) {
                assert!(
                    matches!(value, naga::Expression::Literal(naga::Literal::U32(v)) if v == expected),
                    "{shader}: {name} is {value:?}, Rust says {expected}"
                );
                seen += 1;
            }
            if let Some((name, expected)) = F32_CONSTANTS.iter().find(|(n, _)| is_named(c.name.as_deref(), n)) {
                assert!(
                    matches!(value, naga::Expression::Literal(naga::Literal::F32(v)) if v == expected),
                    "{shader}: {name} is {value:?}, Rust says {expected}"
                );
                seen += 1;
            }
        }
    }
    assert!(seen >= 10, "only {seen} shared constants found in the shaders");
}

#[test]
fn override_ids_come_from_the_rust_table_alone() {
    // Every `@id` names a constant of the table (`@id(OVERRIDE_<NAME>)`), never a number.
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders");
    let mut files = vec![std::path::PathBuf::from(dir)];
    while let Some(path) = files.pop() {
        if path.is_dir() {
            files.extend(std::fs::read_dir(&path).unwrap().map(|e| e.unwrap().path()));
        } else if path.extension().is_some_and(|e| e == "wesl") {
            let text = std::fs::read_to_string(&path).unwrap();
            for (at, _) in text.match_indices("@id(") {
                let argument = &text[at + 4..];
                assert!(argument.starts_with("OVERRIDE_"), "{}: a literal override id", path.display());
            }
        }
    }
    // And the composed shaders declare exactly the table's ids.
    let mut declared: Vec<u32> = modules()
        .iter()
        .flat_map(|(_, m)| m.overrides.iter().filter_map(|(_, o)| o.id.map(u32::from)).collect::<Vec<_>>())
        .collect();
    declared.sort();
    declared.dedup();
    let mut table: Vec<u32> = chiaro_render::overrides::ALL.iter().map(|o| o.id).collect();
    table.sort();
    assert_eq!(declared, table);
}
