//! `chiaro info`: what a scene file holds, and what was ignored and why.

use anyhow::Result;
use chiaro_math::camera::Projection;
use chiaro_scene::{AlphaMode, LightKind, Scene, Topology, load_gltf};
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub struct InfoArgs {
    /// A .gltf or .glb file.
    pub scene: PathBuf,
}

pub fn run(args: InfoArgs) -> Result<()> {
    let scene = load_gltf(&args.scene)?;
    println!("scene: {}", args.scene.display());
    println!(
        "meshes: {} ({} instances, {} static, {} triangles drawn)",
        scene.meshes.len(),
        scene.instances.len(),
        scene.instances.iter().filter(|i| i.is_static).count(),
        scene.triangle_count()
    );
    for (i, m) in scene.meshes.iter().enumerate() {
        let tris: usize = m.primitives.iter().map(|p| p.triangle_count()).sum();
        let lines = m.points_and_lines.iter().filter(|p| p.topology == Topology::Lines).count();
        let points = m.points_and_lines.len() - lines;
        let wires = match (lines, points) {
            (0, 0) => String::new(),
            _ => format!(", {lines} line and {points} point primitives (drawn one pixel wide, casting no shadow)"),
        };
        println!("  mesh {i} '{}': {} primitives, {tris} triangles{wires}", m.name, m.primitives.len());
    }
    print_materials(&scene);
    print_lights(&scene);
    println!("cameras: {}", scene.cameras.len());
    for (i, c) in scene.cameras.iter().enumerate() {
        let lens = match c.projection {
            Projection::Perspective { yfov_rad } => format!("yfov {:.1} deg", yfov_rad.to_degrees()),
            Projection::Orthographic { ymag } => format!("orthographic, ymag {ymag} m"),
        };
        println!(
            "  camera {i} '{}' (node {}): {lens}, near {}, far {}",
            c.name,
            c.node,
            c.znear,
            c.zfar.map(|f| f.to_string()).unwrap_or_else(|| "infinite".into())
        );
    }
    if let Some(own) = &scene.environment {
        println!(
            "environment: {}, {} x {} texels (lights the scene unless the settings name another)",
            own.label, own.map.width, own.map.height
        );
    }
    if !scene.extensions_read.is_empty() {
        println!("extensions read:");
        for line in &scene.extensions_read {
            println!("  {line}");
        }
    }
    let b = scene.bounds();
    if b.is_empty() {
        println!("bounds: empty");
    } else {
        println!("bounds: min {:.3?}, max {:.3?}", b.min.to_array(), b.max.to_array());
    }
    println!("ignored: {}", if scene.ignored.is_empty() { "nothing" } else { "" });
    for reason in &scene.ignored {
        println!("  {reason}");
    }
    Ok(())
}

fn print_materials(scene: &Scene) {
    println!("materials: {}", scene.materials.len());
    for (i, m) in scene.materials.iter().enumerate() {
        let textures = [
            m.base_color_texture.is_some(),
            m.metallic_roughness_texture.is_some(),
            m.normal_texture.is_some(),
            m.occlusion_texture.is_some(),
            m.emissive_texture.is_some(),
        ]
        .iter()
        .filter(|&&t| t)
        .count()
            + m.layers.textures.iter().flatten().count();
        let extensions: String = m.layers.extensions().iter().map(|name| format!(", {name}")).collect();
        let alpha = match m.alpha_mode {
            AlphaMode::Opaque => "opaque".to_string(),
            AlphaMode::Mask => format!("mask {}", m.alpha_cutoff),
            AlphaMode::Blend => "blend".to_string(),
        };
        println!(
            "  material {i} '{}': base {:.3?}, metallic {}, roughness {}, {textures} textures, {alpha}{}{extensions}",
            m.name,
            m.base_color.to_array(),
            m.metallic,
            m.roughness,
            if m.double_sided { ", double-sided" } else { "" }
        );
    }
}

fn print_lights(scene: &Scene) {
    let count = |f: fn(&LightKind) -> bool| scene.lights.iter().filter(|l| f(&l.kind)).count();
    let modes = |mode: chiaro_scene::LightMode| scene.lights.iter().filter(|l| l.mode == mode).count();
    println!(
        "lights: {} ({} directional, {} point, {} spot, {} rect, {} disk; {} realtime, {} mixed, {} baked)",
        scene.lights.len(),
        count(|k| *k == LightKind::Directional),
        count(|k| *k == LightKind::Point),
        count(|k| matches!(k, LightKind::Spot { .. })),
        count(|k| matches!(k, LightKind::Rect { .. })),
        count(|k| matches!(k, LightKind::Disk { .. })),
        modes(chiaro_scene::LightMode::Realtime),
        modes(chiaro_scene::LightMode::Mixed),
        modes(chiaro_scene::LightMode::Baked)
    );
    for l in &scene.lights {
        let range = l.range.map(|r| format!("{r} m")).unwrap_or_else(|| "none (derived)".into());
        let color = l.color.to_array();
        match l.kind {
            LightKind::Rect { width, height } => println!(
                "  node {} '{}': rect, {} nits, color {color:.3?}, {width} x {height} m, range {range}, position {:.3?}, direction {:.3?}",
                l.node,
                l.name,
                l.intensity,
                l.position().to_array(),
                l.direction().to_array()
            ),
            LightKind::Disk { diameter } => println!(
                "  node {} '{}': disk, {} nits, color {color:.3?}, diameter {diameter} m, range {range}, position {:.3?}, direction {:.3?}",
                l.node,
                l.name,
                l.intensity,
                l.position().to_array(),
                l.direction().to_array()
            ),
            LightKind::Directional => println!(
                "  node {} '{}': directional, {} lux, color {color:.3?}, direction {:.3?}",
                l.node,
                l.name,
                l.intensity,
                l.direction().to_array()
            ),
            LightKind::Point => println!(
                "  node {} '{}': point, {} cd, color {color:.3?}, range {range}, position {:.3?}",
                l.node,
                l.name,
                l.intensity,
                l.position().to_array()
            ),
            LightKind::Spot { inner_cone_rad, outer_cone_rad } => println!(
                "  node {} '{}': spot, {} cd, color {color:.3?}, range {range}, cone {:.1}..{:.1} deg, position {:.3?}, direction {:.3?}",
                l.node,
                l.name,
                l.intensity,
                inner_cone_rad.to_degrees(),
                outer_cone_rad.to_degrees(),
                l.position().to_array(),
                l.direction().to_array()
            ),
        }
    }
}
