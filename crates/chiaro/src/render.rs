//! `chiaro render`: one frame to an image, with optional AOVs beside it.

use crate::output::{OutputFormat, aov_path, output_format, sibling_path, write_exr_rgb, write_exr_single, write_png};
use crate::scene_source::{DemoArgs, choose_view, load_scene, load_settings};
use crate::shadow_args::ShadowArgs;
use anyhow::Result;
use chiaro_render::{FrameOptions, GpuContext, Renderer};
use clap::{Args, ValueEnum};
use std::path::PathBuf;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Aov {
    /// World-space position, RGB float32.
    Position,
    /// World-space shading normal, RGB float32.
    Normal,
    /// Linear view depth, one float32 channel.
    Depth,
    /// Per light, `<stem>.shadow.<node>.exr`: the realtime shadow attenuation used.
    Shadow,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Debug {
    /// Tint the image by directional shadow cascade.
    Cascades,
    /// Also write the shadow atlases as `<stem>.shadow-atlas.png` (directional) and
    /// `<stem>.other-shadow-atlas.png` (point and spot).
    ShadowAtlas,
}

#[derive(Args)]
pub struct RenderArgs {
    /// A .gltf or .glb file; without one, the built-in demo scene.
    pub scene: Option<PathBuf>,
    /// Output image: .png (tone-mapped sRGB) or .exr (linear HDR radiance).
    #[arg(short, long, default_value = "chiaro.png")]
    pub output: PathBuf,
    /// Output width in pixels (default: the settings file's, 1280).
    #[arg(long)]
    pub width: Option<u32>,
    /// Output height in pixels (default: the settings file's, 720).
    #[arg(long)]
    pub height: Option<u32>,
    /// Camera by name or index; default: the scene's first camera, or one that frames it.
    #[arg(long)]
    pub camera: Option<String>,
    /// Pipeline settings (TOML); see docs/settings.md.
    #[arg(long)]
    pub settings: Option<PathBuf>,
    /// Camera exposure in EV100, overriding the settings file.
    #[arg(long, allow_hyphen_values = true)]
    pub exposure: Option<f32>,
    /// Also write `<stem>.<aov>.exr` beside the output (repeatable).
    #[arg(long, value_enum)]
    pub aov: Vec<Aov>,
    #[command(flatten)]
    pub demo: DemoArgs,
    /// Debug views (repeatable).
    #[arg(long, value_enum)]
    pub debug: Vec<Debug>,
    #[command(flatten)]
    pub shadow: ShadowArgs,
}

pub fn run(args: RenderArgs) -> Result<()> {
    let format = output_format(&args.output)?;
    let mut settings = load_settings(args.settings.as_deref())?;
    if let Some(ev) = args.exposure {
        settings.render.exposure_ev100 = ev;
        settings.validate().map_err(|e| anyhow::anyhow!("--exposure: {e}"))?;
    }
    args.shadow.apply(&mut settings)?;
    let width = args.width.unwrap_or(settings.render.width);
    let height = args.height.unwrap_or(settings.render.height);
    let scene = load_scene(args.scene.as_deref(), &args.demo)?;
    let view = choose_view(&scene, args.camera.as_deref(), &settings, width, height)?;
    let mut renderer = Renderer::new(GpuContext::new()?)?;
    let prepared = renderer.prepare(&scene)?;
    let wants = |aov: Aov| args.aov.contains(&aov);
    let options = FrameOptions {
        aovs: wants(Aov::Position) || wants(Aov::Normal) || wants(Aov::Depth),
        shadow_aovs: wants(Aov::Shadow),
        readback: true,
        debug_cascades: args.debug.contains(&Debug::Cascades),
        read_shadow_atlas: args.debug.contains(&Debug::ShadowAtlas),
    };
    let frame = renderer.render(&scene, &prepared, &view, &settings, options)?;
    match format {
        OutputFormat::Png => write_png(&args.output, width, height, &frame.ldr)?,
        OutputFormat::Exr => {
            let rgb: Vec<[f32; 3]> = frame.hdr.iter().map(|p| [p[0], p[1], p[2]]).collect();
            write_exr_rgb(&args.output, width, height, &rgb)?
        }
    }
    if let Some(aovs) = &frame.aovs {
        for aov in &args.aov {
            match aov {
                Aov::Position => write_exr_rgb(&aov_path(&args.output, "position"), width, height, &aovs.position_ws)?,
                Aov::Normal => write_exr_rgb(&aov_path(&args.output, "normal"), width, height, &aovs.normal_ws)?,
                Aov::Depth => write_exr_single(&aov_path(&args.output, "depth"), width, height, &aovs.depth)?,
                Aov::Shadow => {}
            }
        }
    }
    for (light, shadow) in scene.lights.iter().zip(&frame.shadow_aovs) {
        let path = aov_path(&args.output, &format!("shadow.{}", light.node));
        write_exr_single(&path, width, height, shadow)?;
    }
    for atlas in &frame.shadow_atlases {
        let grey: Vec<u8> = atlas
            .depths
            .iter()
            .flat_map(|d| {
                let v = (d.clamp(0.0, 1.0) * 255.0).round() as u8;
                [v, v, v, 255]
            })
            .collect();
        let file = if atlas.name == "directional" {
            "shadow-atlas.png".to_string()
        } else {
            format!("{}-shadow-atlas.png", atlas.name)
        };
        write_png(&sibling_path(&args.output, &file), atlas.size, atlas.size, &grey)?;
    }
    if args.debug.contains(&Debug::ShadowAtlas) && frame.shadow_atlases.is_empty() {
        tracing::warn!("no light casts a shadow: no atlas to write");
    }
    eprintln!(
        "chiaro: wrote {} ({width}x{height}, {} point/spot lights shaded, {:.1} ms)",
        args.output.display(),
        frame.other_lights_shaded(),
        frame.timings.wall_ms.unwrap_or_default()
    );
    Ok(())
}
