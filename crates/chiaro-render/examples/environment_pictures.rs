//! The pictures of docs/environment.md: glTF scenes side by side under an environment,
//! each from its first camera (or one that frames it), in a grid of `COLUMNS`.
//!
//! ```sh
//! cargo run --release -p chiaro-render --example environment_pictures -- \
//!     OUT.png SOURCE [EXPOSURE_EV100] SCENE.gltf...
//! ```
//!
//! SOURCE is an `[environment] source` (none, neutral, sky or an image's path).

use chiaro_render::{FrameOptions, GpuContext, Renderer, View};
use chiaro_scene::settings::EnvironmentSource;
use chiaro_scene::{Settings, load_gltf};

const WIDTH: u32 = 400;
const HEIGHT: u32 = 300;
const COLUMNS: usize = 3;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let usage = "usage: environment_pictures OUT.png SOURCE [EXPOSURE_EV100] SCENE.gltf...";
    let mut args = std::env::args().skip(1).peekable();
    let out = args.next().ok_or(usage)?;
    let mut settings = Settings::default();
    settings.environment.source = EnvironmentSource::parse(&args.next().ok_or(usage)?)?;
    if let Some(ev) = args.peek().and_then(|a| a.parse::<f32>().ok()) {
        settings.render.exposure_ev100 = ev;
        args.next();
    }
    let scenes: Vec<String> = args.collect();
    if scenes.is_empty() {
        return Err(usage.into());
    }
    let mut renderer = Renderer::new(GpuContext::new()?)?;
    let mut tiles = Vec::new();
    for path in &scenes {
        let scene = load_gltf(std::path::Path::new(path))?;
        let view = if scene.cameras.is_empty() {
            View::framing(&scene, settings.camera.auto_yfov_deg.to_radians(), WIDTH, HEIGHT)
        } else {
            View::from_camera(&scene, 0, WIDTH, HEIGHT)
        };
        let prepared = renderer.prepare(&scene)?;
        let options = FrameOptions { readback: true, ..Default::default() };
        let frame = renderer.render(&scene, &prepared, &view, &settings, options)?;
        println!("{path}");
        tiles.push(frame.ldr);
    }
    let rows = tiles.len().div_ceil(COLUMNS);
    let (w, h) = (WIDTH as usize, HEIGHT as usize);
    let mut pixels = [0u8, 0, 0, 255].repeat(COLUMNS * w * rows * h);
    for (k, tile) in tiles.iter().enumerate() {
        let (cx, cy) = (k % COLUMNS, k / COLUMNS);
        for y in 0..h {
            let from = &tile[y * w * 4..(y + 1) * w * 4];
            let at = ((cy * h + y) * COLUMNS * w + cx * w) * 4;
            pixels[at..at + w * 4].copy_from_slice(from);
        }
    }
    image::save_buffer(&out, &pixels, (COLUMNS * w) as u32, (rows * h) as u32, image::ColorType::Rgba8)?;
    println!("wrote {out}");
    Ok(())
}
