//! Composes the WESL shader sources (real `import`s between files) into one WGSL string
//! per artifact at build time; the passes include the results (`wgsl!`). The artifacts
//! are those the pass list (`src/passes/list.rs`) names; the constants the shaders share
//! with Rust come from `src/shader_constants.rs`, group 0's binding numbers from
//! `src/frame_bindings.rs`, and the override ids from `src/overrides.rs`, through WESL's
//! `constants` module.

#[path = "src/shader_constants.rs"]
#[allow(dead_code)]
mod shader_constants;

#[path = "src/frame_bindings.rs"]
#[allow(dead_code)]
mod frame_bindings;

#[path = "src/overrides.rs"]
#[allow(dead_code)]
mod overrides;

include!("src/passes/list.rs");

macro_rules! artifacts {
    ($($module:ident: $ty:ident [$($artifact:literal),*],)*) => {
        &[$($($artifact,)*)*]
    };
}

const ARTIFACTS: &[&str] = frame_passes!(artifacts);

fn main() {
    let mut compiler = wesl::Wesl::new("shaders");
    for &(name, value) in shader_constants::U32_CONSTANTS {
        compiler.add_constant(name, value.into());
    }
    for &(name, value) in shader_constants::F32_CONSTANTS {
        compiler.add_constant(name, value.into());
    }
    // Each group-0 binding's number, for the shaders' `@binding(BINDING_<NAME>)`.
    for (i, b) in frame_bindings::FRAME_BINDINGS.iter().enumerate() {
        compiler.add_constant(format!("BINDING_{}", b.name), (i as u32).into());
    }
    // Each override's id, for the shaders' `@id(OVERRIDE_<NAME>)`.
    for o in overrides::ALL {
        compiler.add_constant(format!("OVERRIDE_{}", o.name), o.id.into());
    }
    let mut done: Vec<&str> = Vec::new();
    for &artifact in ARTIFACTS.iter().chain(SETUP_ARTIFACTS) {
        if done.contains(&artifact) {
            continue;
        }
        done.push(artifact);
        let root = format!("package::{artifact}");
        compiler.build_artifact(&root.parse().expect("module path"), artifact);
    }
    println!("cargo::rerun-if-changed=src/shader_constants.rs");
    println!("cargo::rerun-if-changed=src/overrides.rs");
    println!("cargo::rerun-if-changed=src/frame_bindings.rs");
    println!("cargo::rerun-if-changed=src/passes/list.rs");
}
