//! Composes the WESL shader sources (real `import`s between files) into one WGSL string
//! per pass at build time; `shaders::*` includes the results. The constants the shaders
//! share with Rust come from `src/shader_constants.rs` through WESL's `constants` module.

#[path = "src/shader_constants.rs"]
#[allow(dead_code)]
mod shader_constants;

fn main() {
    let mut compiler = wesl::Wesl::new("shaders");
    for &(name, value) in shader_constants::U32_CONSTANTS {
        compiler.add_constant(name, value.into());
    }
    for &(name, value) in shader_constants::F32_CONSTANTS {
        compiler.add_constant(name, value.into());
    }
    for (root, artifact) in [
        ("package::forward", "forward"),
        ("package::aov", "aov"),
        ("package::shadow_aov", "shadow_aov"),
        ("package::tonemap", "tonemap"),
        ("package::shadow_caster", "shadow_caster"),
        ("package::gbuffer", "gbuffer"),
        ("package::deferred_light", "deferred_light"),
        ("package::debug_view", "debug_view"),
        ("package::ldr_decode", "ldr_decode"),
    ] {
        compiler.build_artifact(&root.parse().expect("module path"), artifact);
    }
    println!("cargo::rerun-if-changed=src/shader_constants.rs");
}
