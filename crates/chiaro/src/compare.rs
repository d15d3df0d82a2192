//! `chiaro compare`: realtime shadows against the ray-traced reference, per light, as the
//! share of compared pixels where they disagree, split into false and missed shadow.

use crate::output::{Encoded, check_outputs, sibling_path, write_group};
use crate::scene_input::SceneInput;
use anyhow::{Result, bail};
use chiaro_compare::{
    CompareOptions, EDGE_BAND_PX, EnvironmentReport, FAR_OFF, MAX_EDGE_BAND_PX, OCCLUDED_BELOW, compare_shadows_with,
    not_compared_because,
};
use chiaro_render::{GpuContext, Renderer, ShadowStatus};
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub struct CompareArgs {
    #[command(flatten)]
    pub input: SceneInput,
    #[arg(long, default_value_t = 256)]
    pub width: u32,
    #[arg(long, default_value_t = 256)]
    pub height: u32,
    /// Write a difference image per light, `<stem>.<node>.png` (black: not compared,
    /// grey: agree, red: false shadow, blue: missed shadow), and with ambient occlusion on
    /// `<stem>.ao.png`, the signed AO error (red: too dark, blue: too bright).
    #[arg(long)]
    pub diff: Option<PathBuf>,
    /// Exit with an error when any light disagrees on more than this percentage (0 to 100).
    #[arg(long, value_parser = percentage, allow_hyphen_values = true)]
    pub fail_above: Option<f64>,
    /// Leave out of the disagreement counts the pixels within this many pixels (Chebyshev
    /// distance) of a traced shadow edge, where a shadow map's texels move an edge
    /// without being wrong; 0 judges every pixel (0 to 64).
    #[arg(long, default_value_t = EDGE_BAND_PX, value_parser = edge_band, allow_hyphen_values = true)]
    pub edge_band: usize,
}

/// An edge band from 0 to MAX_EDGE_BAND_PX pixels.
fn edge_band(text: &str) -> Result<usize, String> {
    let value: usize = text.parse().map_err(|_| format!("'{text}' is not a whole number of pixels"))?;
    if value <= MAX_EDGE_BAND_PX {
        Ok(value)
    } else {
        Err(format!("{value} pixels is wider than the {MAX_EDGE_BAND_PX} an edge band may be"))
    }
}

/// A percentage from 0 to 100 (NaN and infinities are not).
fn percentage(text: &str) -> Result<f64, String> {
    let value: f64 = text.parse().map_err(|_| format!("'{text}' is not a number"))?;
    if (0.0..=100.0).contains(&value) { Ok(value) } else { Err(format!("{text} is not a percentage from 0 to 100")) }
}

pub fn run(args: CompareArgs) -> Result<()> {
    let settings = args.input.settings()?;
    let scene = args.input.scene(&settings)?;
    let view = args.input.view(&scene, &settings, args.width, args.height)?;
    let diff_path = |node: usize| args.diff.as_ref().map(|diff| sibling_path(diff, &format!("{node}.png")));
    let ao_diff_path =
        args.diff.as_ref().filter(|_| settings.ambient_occlusion.enabled).map(|d| sibling_path(d, "ao.png"));
    let outputs: Vec<PathBuf> =
        scene.lights.iter().filter_map(|l| diff_path(l.node)).chain(ao_diff_path.clone()).collect();
    check_outputs(&outputs, &args.input.inputs(&scene))?;
    let mut renderer = Renderer::new(GpuContext::new()?)?;
    let prepared = renderer.prepare(&scene)?;
    let options = CompareOptions { edge_band_px: args.edge_band };
    let result = compare_shadows_with(&mut renderer, &scene, &prepared, &view, &settings, options)?;
    println!(
        "scene: {}; {}x{}; filter {}, {} cascades, max distance {} m; edge band {} px",
        args.input.name(),
        args.width,
        args.height,
        settings.shadows.directional.filter,
        settings.shadows.directional.cascade_count,
        settings.shadows.max_distance,
        args.edge_band
    );
    println!(
        "{:<6} {:<24} {:<12} {:>9} {:>12} {:>9} {:>9}",
        "node", "light", "type", "compared", "disagree %", "false %", "missed %"
    );
    let mut worst: f64 = 0.0;
    let mut diffs: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    for report in &result.reports {
        let light = &scene.lights[report.light];
        let kind = light.kind.name();
        let c = &report.comparison;
        let why = not_compared_because(result.status[report.light]);
        if let Some(why) = why {
            println!("{:<6} {:<24} {:<12} {why}", light.node, light.name.chars().take(24).collect::<String>(), kind);
            continue;
        }
        let source = match result.status[report.light] {
            ShadowStatus::MaskOnly => "  shadow mask only (no atlas tile)",
            _ => "",
        };
        // Contact-hardening lights: how far the soft visibility is from the traced disc's.
        // Area lights also by their penumbra alone (docs/shadows.md).
        let soft = report.visibility.map_or(String::new(), |v| {
            let penumbra = if light.is_area() {
                format!(
                    "; area: penumbra mean |dv| {:.4}, penumbra |dv| > {FAR_OFF} {:.3}% ({} px)",
                    v.penumbra_mean_abs,
                    100.0 * v.penumbra_far_off,
                    v.penumbra_compared
                )
            } else {
                String::new()
            };
            format!(
                "  {}: mean |dv| {:.4}, p95 |dv| {:.4}, |dv| > {FAR_OFF} {:.3}%{penumbra}",
                if light.is_area() { "soft" } else { "pcss" },
                v.mean_abs,
                v.p95_abs,
                100.0 * v.far_off
            )
        });
        println!(
            "{:<6} {:<24} {:<12} {:>9} {:>12.3} {:>9.3} {:>9.3}{source}{soft}",
            light.node,
            light.name.chars().take(24).collect::<String>(),
            kind,
            c.compared,
            100.0 * c.disagreement(),
            100.0 * c.false_share(),
            100.0 * c.missed_share()
        );
        worst = worst.max(100.0 * c.disagreement());
        if let Some(path) = diff_path(light.node) {
            diffs.push((path, report.difference.iter().flatten().copied().collect()));
        }
    }
    match &result.environment {
        Some(EnvironmentReport::Compared { pixels, median, p10, p90 }) => println!(
            "environment ({}, baked): baked / traced irradiance over {pixels} pixels: median {median:.4}, 10th \
             percentile {p10:.4}, 90th {p90:.4}",
            settings.environment.describe(&scene)
        ),
        Some(EnvironmentReport::NotCompared(why)) => {
            println!("environment ({}): {why}", settings.environment.describe(&scene))
        }
        None => {}
    }
    if let Some(ao) = &result.occlusion {
        let a = &settings.ambient_occlusion;
        println!(
            "ambient occlusion (radius {} m, quality {}, thickness {} m): mean |dAO| {:.4} over {} surface pixels, \
             {:.4} over {} occluded (traced AO < {OCCLUDED_BELOW}), p95 |dAO| {:.4}, mean signed {:+.4}",
            a.radius,
            a.quality.name(),
            a.thickness,
            ao.mean_error,
            ao.surfaces,
            ao.mean_error_occluded,
            ao.occluded,
            ao.p95_error,
            ao.mean_signed_error
        );
        if let Some(path) = &ao_diff_path {
            diffs.push((path.clone(), ao.difference.iter().flatten().copied().collect()));
        }
    }
    let (width, height) = (args.width, args.height);
    write_group(diffs.iter().map(|(path, rgba8)| (path.clone(), Encoded::Png { width, height, rgba8 })).collect())?;
    if let Some(limit) = args.fail_above
        && worst > limit
    {
        bail!("shadows disagree with the reference on {worst:.3}% of pixels for some light (limit {limit}%)");
    }
    Ok(())
}
