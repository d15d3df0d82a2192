//! Renders a glTF scene, or the built-in demo scene, to a PNG with no window:
//!
//! ```sh
//! cargo run --release -p chiaro-render --example render_png -- [SCENE.gltf|.glb] [OUT.png]
//! ```
//!
//! The scene's first camera is used, or one that frames the scene.

use chiaro_render::{FrameOptions, GpuContext, Renderer, View};
use chiaro_scene::{Settings, demo::demo_scene, load_gltf};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let scene_path = args.next().map(PathBuf::from);
    let output = args.next().map_or_else(|| PathBuf::from("render_png.png"), PathBuf::from);
    let (width, height) = (640, 360);

    // The scene is plain data: meshes, materials, lights and cameras.
    let scene = match &scene_path {
        Some(path) => load_gltf(path)?,
        None => demo_scene(8),
    };
    // Every setting has a default; `Settings::load` reads a settings.toml.
    let settings = Settings::default();
    let view = if scene.cameras.is_empty() {
        View::framing(&scene, settings.camera.auto_yfov_deg.to_radians(), width, height)
    } else {
        View::from_camera(&scene, 0, width, height)
    };

    // A device (a GPU, or Mesa's software Vulkan), the scene uploaded to it, one frame.
    let mut renderer = Renderer::new(GpuContext::new()?)?;
    let prepared = renderer.prepare(&scene)?;
    let options = FrameOptions { readback: true, ..Default::default() };
    let frame = renderer.render(&scene, &prepared, &view, &settings, options)?;

    // `ldr` is the tone-mapped sRGB image, RGBA8 from the top-left; `hdr` the radiance.
    let rgb: Vec<u8> = frame.ldr.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    image::save_buffer(&output, &rgb, width, height, image::ExtendedColorType::Rgb8)?;
    println!(
        "{} ({} lights, {} triangles) -> {}",
        scene_name(&scene_path),
        scene.lights.len(),
        scene.triangle_count(),
        output.display()
    );
    Ok(())
}

fn scene_name(path: &Option<PathBuf>) -> String {
    path.as_ref().map_or_else(|| "the demo scene".into(), |p| p.display().to_string())
}
