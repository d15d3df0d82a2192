//! `chiaro view`: the flags checked and turned into the plain values chiaro-view opens
//! with (the scene, settings and view they choose, what to write when, and how files
//! opened later are read); the viewer itself is chiaro-view.

use crate::output::{OutputFormat, check_outputs, output_format};
use crate::scene_input::{SceneInput, load_scene};
use anyhow::{Result, anyhow};
use chiaro_render::DebugView;
use chiaro_view::{Script, ViewerConfig};
use clap::Args;
use std::path::PathBuf;
use std::sync::Arc;

/// `--debug`'s value: a debug view, or none (a newtype, since clap reads a nested
/// `Option` as an optional value).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DebugArg(pub Option<DebugView>);

#[derive(Args)]
pub struct ViewArgs {
    #[command(flatten)]
    pub input: SceneInput,
    /// The 3D view's width in pixels (render.width without it).
    #[arg(long)]
    pub width: Option<u32>,
    /// The 3D view's height in pixels (render.height without it).
    #[arg(long)]
    pub height: Option<u32>,
    /// After --exit-after-frames frames, write the 3D view (no panel) to this PNG or EXR
    /// file, as `chiaro render` would, and exit.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// After --exit-after-frames frames, write the whole window (3D view and panel) as the
    /// screen shows it to this PNG file, and exit.
    #[arg(long)]
    pub screenshot_window: Option<PathBuf>,
    /// The debug view to open with: none, cascades, gbuffer-albedo, gbuffer-normal,
    /// light-overdraw, aov-position, aov-normal, aov-depth, aov-lightmap, clusters,
    /// shadow-atlases, reference (compared at once). With --screenshot, cascades and the
    /// G-buffer and overdraw views are written as `chiaro render --debug` writes them.
    #[arg(long, value_parser = |text: &str| chiaro_view::parse_debug(text).map(DebugArg))]
    pub debug: Option<DebugArg>,
    /// Frames to show before exiting (1 to 100000).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub exit_after_frames: Option<u32>,
}

pub fn run(args: ViewArgs) -> Result<()> {
    if (args.screenshot.is_some() || args.screenshot_window.is_some()) && args.exit_after_frames.is_none() {
        return Err(anyhow!("--screenshot needs --exit-after-frames N (the frames to render first)"));
    }
    if let Some(shot) = &args.screenshot {
        output_format(shot)?;
    }
    if let Some(shot) = &args.screenshot_window
        && !matches!(output_format(shot)?, OutputFormat::Png)
    {
        return Err(anyhow!("--screenshot-window {}: the window is written as PNG only", shot.display()));
    }
    let mut settings = args.input.settings()?;
    // The view's size is render.width and height, so that saved settings keep it.
    settings.render.width = args.width.unwrap_or(settings.render.width);
    settings.render.height = args.height.unwrap_or(settings.render.height);
    settings.validate().map_err(|e| anyhow!("--width/--height: {e}"))?;
    // The panel shows the variant --variant picked.
    if let Some(variant) = &args.input.variant {
        settings.scene.variant = Some(variant.clone());
    }
    let (width, height) = (settings.render.width, settings.render.height);
    let scene = args.input.scene(&settings)?;
    let start_view = args.input.view(&scene, &settings, width, height)?;
    let shots: Vec<PathBuf> = args.screenshot.iter().chain(&args.screenshot_window).cloned().collect();
    check_outputs(&shots, &args.input.inputs(&scene))?;
    let (demo, bake) = (args.input.demo.clone(), args.input.bake.clone());
    let load_scene = Arc::new(move |path: &std::path::Path, settings: &chiaro_scene::Settings| {
        let mut scene = load_scene(Some(path), &demo)?;
        // A reloaded file keeps the variant the settings hold: --variant's, or the panel's.
        if let Some(name) = settings.scene.variant.as_deref() {
            scene.select_variant(Some(name)).map_err(|e| anyhow!("{}: {e}", path.display()))?;
        }
        bake.apply(&mut scene, Some(path), settings)?;
        Ok(scene)
    });
    let script = args.exit_after_frames.map(|frames| Script {
        frames,
        screenshot: args.screenshot.clone(),
        screenshot_window: args.screenshot_window.clone(),
    });
    chiaro_view::run(ViewerConfig {
        scene_path: args.input.scene.clone(),
        settings_file: args.input.settings.clone(),
        msaa_flag: args.input.path.msaa,
        camera_key: args.input.camera.clone(),
        debug: args.debug.and_then(|d| d.0),
        compare_at_start: args.debug == Some(DebugArg(Some(DebugView::Reference))),
        script,
        load_scene,
        time: args.input.time.time,
        ..ViewerConfig::new(scene, settings, start_view)
    })
}
