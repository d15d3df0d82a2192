//! Renders into a texture of the caller's, on the caller's own wgpu device, as an engine
//! or a viewer embedding Chiaro would, then reads that texture back:
//!
//! ```sh
//! cargo run --release -p chiaro-render --example into_texture
//! ```

use chiaro_render::readback::{copy_texture, finish_copies};
use chiaro_render::wgpu;
use chiaro_render::{FrameOptions, GpuContext, Renderer, View};
use chiaro_scene::{Settings, demo::demo_scene};

const WIDTH: u32 = 256;
const HEIGHT: u32 = 256;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The caller's device. Chiaro uses what it was made with: timestamps, 32-bit depth
    // with stencil, depth clipping control, when enabled here.
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))?;
    let wanted = wgpu::Features::DEPTH32FLOAT_STENCIL8 | wgpu::Features::DEPTH_CLIP_CONTROL;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("the caller's device"),
        required_features: adapter.features() & wanted,
        ..Default::default()
    }))?;

    // The caller's texture: any format a render pass can write (sRGB or linear).
    let format = wgpu::TextureFormat::Rgba8UnormSrgb;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("the caller's texture"),
        size: wgpu::Extent3d { width: WIDTH, height: HEIGHT, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });

    // The renderer borrows nothing else: it makes its own targets on the same device.
    let mut renderer = Renderer::new(GpuContext::from_device(&adapter, device, queue))?;
    let scene = demo_scene(8);
    let prepared = renderer.prepare(&scene)?;
    let view = View::from_camera(&scene, 0, WIDTH, HEIGHT);
    let target = texture.create_view(&Default::default());
    // Nothing waits for the GPU here: a window would present the texture next.
    renderer.render_to(&scene, &prepared, &view, &Settings::default(), FrameOptions::default(), &target, format)?;

    let pixels = read_back(&renderer.ctx, &texture)?;
    let lit = pixels.chunks_exact(4).filter(|p| p[0] > 16 || p[1] > 16 || p[2] > 16).count();
    println!("rendered {WIDTH}x{HEIGHT} into the caller's texture; {lit} of {} pixels are lit", WIDTH * HEIGHT);
    Ok(())
}

/// Copies `texture` to the CPU with the renderer's read-back helpers (one wait).
fn read_back(ctx: &GpuContext, texture: &wgpu::Texture) -> Result<Vec<u8>, chiaro_render::RenderError> {
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    let copy = copy_texture(&ctx.device, &mut encoder, texture, 4);
    ctx.queue.submit([encoder.finish()]);
    Ok(finish_copies(ctx, vec![copy])?.remove(0))
}
