//! The pictures of docs/shadows.md: a pole and a leaning plank on a floor under a point
//! light of radius 0.25 m with contact-hardening shadows, and under the same light with
//! hard shadows; beside each, the rendered visibility and the traced share of the light's
//! disc. `cargo run --release -p chiaro-compare --example pcss_pictures -- OUT.png` writes
//! one PNG: per row the lit frame, the rendered visibility and the traced visibility.

use chiaro_compare::{compare_rendered, render_shadows};
use chiaro_render::{GpuContext, Renderer, View};
use chiaro_scene::{Settings, ShadowMode};
use chiaro_testkit::pole_and_plank_scene;

const WIDTH: u32 = 360;
const HEIGHT: u32 = 270;

/// A visibility (NaN: nothing to judge) as grey RGBA8.
fn grey(visibility: f32) -> [u8; 4] {
    if !visibility.is_finite() {
        return [0, 0, 0, 255];
    }
    let v = (visibility.clamp(0.0, 1.0) * 255.0).round() as u8;
    [v, v, v, 255]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).ok_or("usage: pcss_pictures OUT.png")?;
    let mut renderer = Renderer::new(GpuContext::new()?)?;
    let mut settings = Settings::default();
    settings.render.msaa = 1;
    let mut rows: Vec<Vec<[u8; 4]>> = Vec::new();
    for mode in [ShadowMode::Pcss, ShadowMode::Hard] {
        let scene = pole_and_plank_scene(mode, WIDTH as f32 / HEIGHT as f32);
        let prepared = renderer.prepare(&scene)?;
        let view = View::from_camera(&scene, 0, WIDTH, HEIGHT);
        // The traced reference of a `hard` light is the point's; judge both as the disc.
        let mut judged = scene.clone();
        judged.lights[0].shadow.mode = ShadowMode::Pcss;
        let rendered = render_shadows(&mut renderer, &scene, &prepared, &view, &settings)?;
        let lit: Vec<[u8; 4]> = rendered.ldr.chunks_exact(4).map(|p| [p[0], p[1], p[2], 255]).collect();
        let result = compare_rendered(&judged, &view, &settings, rendered);
        if let Some(v) = result.reports[0].visibility {
            println!("{mode:?}: mean |dv| {:.4}, p95 {:.4}, > 0.1 on {:.2}%", v.mean_abs, v.p95_abs, 100.0 * v.far_off);
        }
        let rendered_v: Vec<[u8; 4]> = result.rendered[0].iter().map(|&v| grey(v)).collect();
        let traced_v: Vec<[u8; 4]> = result.reference.visibility[0].iter().map(|&v| grey(v)).collect();
        for y in 0..HEIGHT as usize {
            let row = |image: &[[u8; 4]]| image[y * WIDTH as usize..(y + 1) * WIDTH as usize].to_vec();
            rows.push([row(&lit), row(&rendered_v), row(&traced_v)].concat());
        }
    }
    let pixels: Vec<u8> = rows.into_iter().flatten().flatten().collect();
    image::save_buffer(&out, &pixels, 3 * WIDTH, 2 * HEIGHT, image::ColorType::Rgba8)?;
    println!("wrote {out}");
    Ok(())
}
