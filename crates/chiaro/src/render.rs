//! `chiaro render`: one frame to an image, with optional AOVs beside it.

use crate::output::{Encoded, aov_path, atlas_grey, check_outputs, output_format, sibling_path, write_group};
use crate::scene_input::SceneInput;
use anyhow::Result;
use anyhow::bail;
use chiaro_render::output::AtlasImage;
use chiaro_render::{DebugView, FrameOptions, GpuContext, Renderer};
use chiaro_scene::RenderPath;
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};

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
    /// `<stem>.lightmap.exr`: the baked irradiance (lux, RGB float32) each pixel used,
    /// from its lightmap or the light probes; zero where no bake lights it.
    Lightmap,
    /// `<stem>.instance.exr`: the glTF node index of the mesh each pixel shows, one uint32
    /// channel, 4294967295 on the sky; exact (one sample a pixel).
    Instance,
    /// `<stem>.label.exr`: that node's `extras.label` (an integer class id), one uint32
    /// channel, 0 where none.
    Label,
    /// `<stem>.ao.exr`: the ambient occlusion the shading used, one float32 channel, 1
    /// open (everywhere without `[ambient_occlusion] enabled`).
    Ao,
}

/// The debug views `render --debug` takes, with their help.
fn debug_values() -> impl TypedValueParser<Value = DebugView> {
    let values = [
        PossibleValue::new("cascades").help("Tint the image by directional shadow cascade"),
        PossibleValue::new("shadow-atlas").help(
            "Also write the shadow atlases as `<stem>.shadow-atlas.png` (directional) and \
             `<stem>.other-shadow-atlas.png` (point and spot), depth as grey stretched from the \
             nearest caster (black) to the far plane (white)",
        ),
        PossibleValue::new("virtual-pages").help(
            "Also write the virtual shadow maps' page table as `<stem>.virtual-pages.png` (with \
             shadows.technique = \"virtual\"): each map's pages, white where the pool holds the finest, \
             through yellow and green to blue for coarser mips, grey where none",
        ),
        PossibleValue::new("gbuffer-albedo").help("The deferred path's G-buffer base colour, instead of the image"),
        PossibleValue::new("gbuffer-normal")
            .help("The deferred path's G-buffer shading normal as n * 0.5 + 0.5, instead of the image"),
        PossibleValue::new("light-overdraw").help(
            "How many light volumes shaded each pixel, as a heat map (blue 1, green 2, yellow 4, red 8 or \
             more), instead of the image",
        ),
    ];
    PossibleValuesParser::new(values).map(|name| DebugView::parse(&name).expect("a debug view's name"))
}

/// The debug view the frame's passes draw in place of the image, if any (at most one;
/// the shadow atlases are written beside it).
fn drawn_debug_view(debug: &[DebugView]) -> Result<Option<DebugView>> {
    let mut drawn: Vec<DebugView> = Vec::new();
    for &d in debug {
        if !matches!(d, DebugView::ShadowAtlases | DebugView::VirtualPages) && !drawn.contains(&d) {
            drawn.push(d);
        }
    }
    match drawn[..] {
        [] => Ok(None),
        [view] => Ok(Some(view)),
        _ => bail!(
            "--debug: gbuffer-albedo, gbuffer-normal, light-overdraw and cascades each replace the image; \
             choose one"
        ),
    }
}

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub input: SceneInput,
    /// Output image: .png (tone-mapped sRGB) or .exr (linear HDR radiance).
    #[arg(short, long, default_value = "chiaro.png")]
    pub output: PathBuf,
    /// Output width in pixels (default: the settings file's, 1280).
    #[arg(long)]
    pub width: Option<u32>,
    /// Output height in pixels (default: the settings file's, 720).
    #[arg(long)]
    pub height: Option<u32>,
    /// Camera exposure in EV100, overriding the settings file.
    #[arg(long, allow_hyphen_values = true)]
    pub exposure: Option<f32>,
    /// Also write `<stem>.<aov>.exr` beside the output (repeatable).
    #[arg(long, value_enum)]
    pub aov: Vec<Aov>,
    /// Debug views (repeatable).
    #[arg(long, value_parser = debug_values())]
    pub debug: Vec<DebugView>,
}

/// Every file the render will write, known before it runs.
fn planned_outputs(args: &RenderArgs, scene: &chiaro_scene::Scene) -> Vec<PathBuf> {
    let mut outputs = vec![args.output.clone()];
    for (aov, name) in [
        (Aov::Position, "position"),
        (Aov::Normal, "normal"),
        (Aov::Depth, "depth"),
        (Aov::Lightmap, "lightmap"),
        (Aov::Instance, "instance"),
        (Aov::Label, "label"),
        (Aov::Ao, "ao"),
    ] {
        if args.aov.contains(&aov) {
            outputs.push(aov_path(&args.output, name));
        }
    }
    if args.aov.contains(&Aov::Shadow) {
        outputs.extend(scene.lights.iter().map(|l| aov_path(&args.output, &format!("shadow.{}", l.node))));
    }
    if args.debug.contains(&DebugView::ShadowAtlases) {
        for file in ["shadow-atlas.png", "other-shadow-atlas.png"] {
            outputs.push(sibling_path(&args.output, file));
        }
    }
    if args.debug.contains(&DebugView::VirtualPages) {
        outputs.push(sibling_path(&args.output, "virtual-pages.png"));
    }
    outputs
}

pub fn run(args: RenderArgs) -> Result<()> {
    let format = output_format(&args.output)?;
    let mut settings = args.input.settings()?;
    if let Some(ev) = args.exposure {
        settings.render.exposure_ev100 = ev;
        settings.validate().map_err(|e| anyhow::anyhow!("--exposure: {e}"))?;
    }
    let debug = drawn_debug_view(&args.debug)?;
    if debug == Some(DebugView::Cascades) && settings.render.path == RenderPath::Deferred {
        tracing::info!("--debug cascades tints the forward path's image: rendering forward");
        settings.render.path = RenderPath::Forward;
        settings.lights.max_other_lights = None;
    }
    let width = args.width.unwrap_or(settings.render.width);
    let height = args.height.unwrap_or(settings.render.height);
    let scene = args.input.scene(&settings)?;
    let view = args.input.view(&scene, &settings, width, height)?;
    check_outputs(&planned_outputs(&args, &scene), &args.input.inputs(&scene))?;
    let ctx = GpuContext::new()?;
    args.input.path.check_device(&ctx, &settings, args.input.settings.as_deref())?;
    let mut renderer = Renderer::new(ctx)?;
    let prepared = renderer.prepare(&scene)?;
    if args.aov.contains(&Aov::Ao) && !settings.ambient_occlusion.enabled {
        tracing::warn!("--aov ao: [ambient_occlusion] enabled is false, so the AOV is 1 everywhere");
    }
    let options = frame_options(&args, debug);
    let frame = renderer.render(&scene, &prepared, &view, &settings, options)?;
    warn_if_clipped(&frame.hdr, settings.render.exposure_ev100);
    warn_if_not_finite(&frame.hdr);

    let rgb: Vec<[f32; 3]> = frame.hdr.iter().map(|p| [p[0], p[1], p[2]]).collect();
    let atlases = atlas_images(&args.output, &frame.shadow_atlases);
    let mut files = vec![(args.output.clone(), format.frame_image(width, height, &frame.ldr, &rgb))];
    if let Some(aovs) = &frame.aovs {
        for aov in &args.aov {
            let (name, image) = match aov {
                Aov::Position => ("position", Encoded::ExrRgb { width, height, rgb: &aovs.position_ws }),
                Aov::Normal => ("normal", Encoded::ExrRgb { width, height, rgb: &aovs.normal_ws }),
                Aov::Depth => ("depth", Encoded::ExrSingle { width, height, values: &aovs.depth }),
                Aov::Lightmap => ("lightmap", Encoded::ExrRgb { width, height, rgb: &aovs.baked_irradiance }),
                Aov::Shadow | Aov::Instance | Aov::Label | Aov::Ao => continue,
            };
            files.push((aov_path(&args.output, name), image));
        }
    }
    if let Some(ids) = &frame.ids {
        for aov in &args.aov {
            let (name, values) = match aov {
                Aov::Instance => ("instance", &ids.instance),
                Aov::Label => ("label", &ids.label),
                _ => continue,
            };
            files.push((aov_path(&args.output, name), Encoded::ExrU32 { width, height, values }));
        }
    }
    if let Some(ao) = &frame.ambient_occlusion {
        files.push((aov_path(&args.output, "ao"), Encoded::ExrSingle { width, height, values: ao }));
    }
    for (light, shadow) in scene.lights.iter().zip(&frame.shadow_aovs) {
        let path = aov_path(&args.output, &format!("shadow.{}", light.node));
        files.push((path, Encoded::ExrSingle { width, height, values: shadow }));
    }
    for (path, size, grey) in &atlases {
        files.push((path.clone(), Encoded::Png { width: *size, height: *size, rgba8: grey }));
    }
    if args.debug.contains(&DebugView::ShadowAtlases) && frame.shadow_atlases.is_empty() {
        tracing::warn!("no light casts a shadow: no atlas to write");
    }
    let pages =
        args.debug.contains(&DebugView::VirtualPages).then(|| frame.plan.shadows.virtual_maps.page_table_image());
    let page_bytes: Option<(u32, u32, Vec<u8>)> = match pages {
        Some(Some((w, h, pixels))) => Some((w as u32, h as u32, pixels.concat())),
        Some(None) => {
            tracing::warn!("shadows.technique is not \"virtual\" (or no light casts a shadow): no page table to write");
            None
        }
        None => None,
    };
    if let Some((w, h, rgba8)) = &page_bytes {
        let path = sibling_path(&args.output, "virtual-pages.png");
        files.push((path, Encoded::Png { width: *w, height: *h, rgba8 }));
    }
    write_group(files)?;
    eprintln!(
        "chiaro: wrote {} ({width}x{height}, {} point/spot lights shaded, {:.1} ms)",
        args.output.display(),
        frame.local_lights_shaded(),
        frame.timings.wall_ms.unwrap_or_default()
    );
    Ok(())
}

/// What the frame reads back: the image always, the AOVs and atlases the flags ask for.
fn frame_options(args: &RenderArgs, debug: Option<DebugView>) -> FrameOptions {
    let wants = |aov: Aov| args.aov.contains(&aov);
    FrameOptions {
        aovs: wants(Aov::Position) || wants(Aov::Normal) || wants(Aov::Depth) || wants(Aov::Lightmap),
        depth_only: !(wants(Aov::Position) || wants(Aov::Normal) || wants(Aov::Lightmap)),
        shadow_aovs: wants(Aov::Shadow),
        ids: wants(Aov::Instance) || wants(Aov::Label),
        ambient_occlusion: wants(Aov::Ao),
        readback: true,
        skip_hdr: false,
        read_shadow_atlas: args.debug.contains(&DebugView::ShadowAtlases),
        debug,
    }
}

/// Each shadow atlas as a grey image, and the file beside the output it goes to.
fn atlas_images(output: &Path, atlases: &[AtlasImage]) -> Vec<(PathBuf, u32, Vec<u8>)> {
    atlases
        .iter()
        .map(|atlas| {
            let grey = atlas_grey(&atlas.depths);
            let file = if atlas.name == "directional" {
                "shadow-atlas.png".to_string()
            } else {
                format!("{}-shadow-atlas.png", atlas.name)
            };
            (sibling_path(output, &file), atlas.size, grey)
        })
        .collect()
}

/// The HDR target holds half floats: shading clamps pre-exposed radiance to
/// `MAX_EXPOSED_RADIANCE`. Says so when pixels reached it, with the exposure that would
/// keep them.
fn warn_if_clipped(hdr: &[[f32; 4]], exposure_ev100: f32) {
    let limit = chiaro_math::tonemap::MAX_EXPOSED_RADIANCE / chiaro_math::tonemap::exposure_scale(exposure_ev100);
    let clipped = hdr.iter().filter(|p| p[..3].iter().any(|c| *c >= limit * 0.999)).count();
    if clipped > 0 {
        let brightest = hdr.iter().flat_map(|p| p[..3].iter().copied()).filter(|c| c.is_finite()).fold(0.0, f32::max);
        tracing::warn!(
            "{clipped} pixels reached the HDR target's limit ({limit:e} at EV100 {exposure_ev100}): their radiance \
             is clipped there (brightest kept: {brightest:e}); raise --exposure to keep more"
        );
    }
}

/// Shading keeps every pixel finite; should a frame hold a NaN or infinite pixel anyway
/// (a driver's rounding no test met), one warning says how many, so that it is seen and
/// reported rather than passed on silently into images and datasets.
fn warn_if_not_finite(hdr: &[[f32; 4]]) {
    let count = non_finite_pixels(hdr);
    if count > 0 {
        tracing::warn!(
            "{count} pixels of the frame hold a non-finite radiance (NaN or infinity): please report the scene and              settings"
        );
    }
}

/// Pixels with a NaN or infinite colour channel.
fn non_finite_pixels(hdr: &[[f32; 4]]) -> usize {
    hdr.iter().filter(|p| !p[..3].iter().all(|c| c.is_finite())).count()
}

#[cfg(test)]
mod tests {
    use super::non_finite_pixels;

    #[test]
    fn non_finite_pixels_are_counted() {
        let hdr = [[0.0, 1.0, 2.0, 1.0], [f32::NAN, 0.0, 0.0, 1.0], [0.0, f32::INFINITY, 0.0, 1.0], [1.0; 4]];
        assert_eq!(non_finite_pixels(&hdr), 2);
        assert_eq!(non_finite_pixels(&hdr[3..]), 0);
    }
}
