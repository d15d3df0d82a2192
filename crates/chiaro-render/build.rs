//! Composes the WESL shader sources (real `import`s between files) into one WGSL string
//! per pass at build time; `shaders::*` includes the results.

fn main() {
    let compiler = wesl::Wesl::new("shaders");
    for (root, artifact) in [
        ("package::forward", "forward"),
        ("package::aov", "aov"),
        ("package::shadow_aov", "shadow_aov"),
        ("package::tonemap", "tonemap"),
        ("package::shadow_caster", "shadow_caster"),
    ] {
        compiler.build_artifact(&root.parse().expect("module path"), artifact);
    }
}
