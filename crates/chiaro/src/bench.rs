//! `chiaro bench`: frames rendered back to back after a warm-up, timed by the wall clock
//! and by GPU timestamp queries where the device has them, with the CPU time spent
//! preparing each frame.

use crate::scene_input::SceneInput;
use anyhow::Result;
use chiaro_render::{
    FrameOptions, FrameOutput, FrameTimings, GpuContext, GpuFrameTimes, Renderer, View, VirtualPageStats,
};
use chiaro_scene::{Scene, Settings};
use clap::Args;
use std::time::Instant;

#[derive(Args)]
pub struct BenchArgs {
    #[command(flatten)]
    pub input: SceneInput,
    #[arg(long, default_value_t = 1280)]
    pub width: u32,
    #[arg(long, default_value_t = 720)]
    pub height: u32,
    /// Timed frames (1 to 100000).
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub frames: u32,
    /// Untimed frames first, for pipelines and caches (0 to 100000).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(0..=100_000))]
    pub warmup: u32,
    /// Print one JSON object (frame_ms, gpu_ms, passes, lights_shaded, width, height,
    /// msaa, ...) instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// What the report reads from a timed frame. The frames themselves are dropped as they
/// come, as a viewer drops them: holding every frame's plan (tens of thousands of cluster
/// lists each) made each frame prepare in fresh memory, and its page faults counted as
/// preparation.
struct TimedFrame {
    timings: FrameTimings,
    shadow_tiles: usize,
    virtual_pages: Option<VirtualPageStats>,
}

struct Stats {
    median: f64,
    min: f64,
    max: f64,
}

/// The `--json` object. Medians over the timed frames; `passes` by the names the table
/// uses; GPU figures are null on devices without timestamp queries.
fn json_report(
    args: &BenchArgs,
    settings: &chiaro_scene::Settings,
    first: &FrameOutput,
    frames: &[TimedFrame],
    intervals: &[f64],
    gpu: &[GpuFrameTimes],
    device: &str,
) -> serde_json::Value {
    let median = |v: Vec<f64>| stats(v).median;
    let last = frames.last().expect("at least one timed frame");
    let passes: serde_json::Map<String, serde_json::Value> =
        pass_times(gpu).into_iter().map(|(pass, times)| (pass.to_string(), median(times).into())).collect();
    serde_json::json!({
        "scene": args.input.scene.as_ref().map(|p| p.display().to_string()),
        "device": device,
        "path": format!("{:?}", first.plan.path).to_lowercase(),
        "culling": match settings.lights.culling {
            chiaro_scene::LightCulling::Clustered => "clustered",
            chiaro_scene::LightCulling::PerObject => "per-object",
            chiaro_scene::LightCulling::None => "none",
        },
        "width": args.width,
        "height": args.height,
        "msaa": first.plan.msaa,
        "frames": args.frames,
        "frame_ms": median(intervals.to_vec()),
        "gpu_ms": (!gpu.is_empty()).then(|| median(gpu.iter().map(GpuFrameTimes::total_ms).collect())),
        "cpu_prepare_ms": median(frames.iter().map(|f| f.timings.cpu_prepare_ms).collect()),
        "cpu_prepare_thread_ms": thread_times(frames).map(median),
        "passes": passes,
        "lights_shaded": first.plan.lights.len(),
        "other_lights_shaded": first.local_lights_shaded(),
        "other_lights_dropped": first.local_lights_dropped(),
        "shadow_tiles_rendered": frames.iter().map(|f| f.shadow_tiles).collect::<Vec<_>>(),
        "shadow_technique": if last.virtual_pages.is_some() { "virtual" } else { "atlas" },
        "shadow_pages_drawn": last.shadow_tiles,
        "shadow_pages_resident": last.virtual_pages.map(|p| p.resident),
        "shadow_pages_dropped": last.virtual_pages.map(|p| p.dropped),
        "shadow_pool_mb": shadow_map_megabytes(first, last),
    })
}

/// Megabytes of shadow-map depth: the virtual technique's pool, or both atlases.
fn shadow_map_megabytes(first: &FrameOutput, last: &TimedFrame) -> f64 {
    match last.virtual_pages {
        Some(pages) => pages.pool_mb,
        None => {
            let shadows = &first.plan.shadows;
            let texels = [shadows.directional_atlas_size, shadows.local_atlas_size].map(|s| s as f64 * s as f64);
            (texels[0] + texels[1]) * 4.0 / (1 << 20) as f64
        }
    }
}

/// Each pass that ran in any of the frames (in the order it first ran), with its time in
/// every frame: 0 where the frame graph did not run it (a shadow pass with every tile
/// cached, say).
fn pass_times(gpu: &[GpuFrameTimes]) -> Vec<(&'static str, Vec<f64>)> {
    let mut names: Vec<&'static str> = Vec::new();
    for (pass, _) in gpu.iter().flat_map(|f| &f.passes) {
        if !names.contains(pass) {
            names.push(pass);
        }
    }
    names
        .into_iter()
        .map(|name| {
            let times = gpu.iter().map(|f| f.passes.iter().find(|(p, _)| *p == name).map_or(0.0, |(_, ms)| *ms));
            (name, times.collect())
        })
        .collect()
}

/// Each frame's preparation on the preparing thread's own clock, where there is one.
fn thread_times(frames: &[TimedFrame]) -> Option<Vec<f64>> {
    frames.iter().map(|f| f.timings.cpu_prepare_thread_ms).collect()
}

fn stats(mut v: Vec<f64>) -> Stats {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) };
    Stats { median, min: v[0], max: v[n - 1] }
}

pub fn run(args: BenchArgs) -> Result<()> {
    let settings = args.input.settings()?;
    let scene = args.input.scene(&settings)?;
    let view = args.input.view(&scene, &settings, args.width, args.height)?;
    let ctx = GpuContext::new()?;
    args.input.path.check_device(&ctx, &settings, args.input.settings.as_deref())?;
    let mut renderer = Renderer::new(ctx)?;
    let prepared = renderer.prepare(&scene)?;
    let environment_setup_ms = renderer.prepare_environment(&scene, &settings)?;
    let options = FrameOptions::default();
    for _ in 0..args.warmup {
        renderer.render(&scene, &prepared, &view, &settings, options)?;
    }
    renderer.gpu_times(true)?;
    // Frames back to back, as a viewer renders them: the renderer keeps two in flight, so
    // the time between two returns is the steady frame time.
    let mut first = None;
    let mut frames = Vec::with_capacity(args.frames as usize);
    let mut intervals = Vec::with_capacity(args.frames as usize);
    let mut last = Instant::now();
    for _ in 0..args.frames {
        let frame = renderer.render(&scene, &prepared, &view, &settings, options)?;
        let now = Instant::now();
        intervals.push((now - last).as_secs_f64() * 1e3);
        last = now;
        frames.push(TimedFrame {
            timings: frame.timings.clone(),
            shadow_tiles: frame.shadow_tiles,
            virtual_pages: frame.virtual_pages(),
        });
        first.get_or_insert(frame);
    }
    let first = first.expect("at least one timed frame");
    let gpu: Vec<GpuFrameTimes> =
        renderer.gpu_times(true)?.into_iter().filter(|t| t.frame >= first.timings.frame).collect();
    let texel_ratios = shadow_texel_ratios(&mut renderer, &scene, &view, &settings)?;
    let info = &renderer.ctx.adapter_info;
    if args.json {
        let mut report = json_report(&args, &settings, &first, &frames, &intervals, &gpu, &info.name);
        report["environment"] = settings.environment.describe(&scene).into();
        report["environment_setup_ms"] = environment_setup_ms.into();
        for (k, key) in
            ["shadow_texel_ratio_p10", "shadow_texel_ratio_p50", "shadow_texel_ratio_p90"].iter().enumerate()
        {
            report[*key] = texel_ratios.map(|r| r[k]).into();
        }
        println!("{report}");
        return Ok(());
    }
    let name = args
        .input
        .scene
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| format!("demo ({} local lights)", args.input.demo.demo_lights));
    println!(
        "scene: {name}; {:?} path, {:?} light culling, {}x MSAA",
        first.plan.path, settings.lights.culling, first.plan.msaa
    );
    println!(
        "device: {} ({:?}, {:?}); {}x{}; {} frames after {} warm-up; {} triangles; {} point/spot lights shaded",
        info.name,
        info.backend,
        info.device_type,
        args.width,
        args.height,
        args.frames,
        args.warmup,
        scene.triangle_count(),
        first.local_lights_shaded()
    );
    let ds = &settings.shadows.directional;
    match frames.last().and_then(|f| f.virtual_pages.map(|p| (f.shadow_tiles, p))) {
        Some((drawn, pages)) => println!(
            "shadows: virtual maps, {drawn} pages drawn in the last frame, {} resident in a {:.0} MB pool ({} asked \
             for, {} left to coarser pages)",
            pages.resident, pages.pool_mb, pages.requested, pages.dropped
        ),
        None => println!(
            "shadows: {} tiles in a {} atlas ({} cascades, {}), {} caster draws",
            first.shadow_tiles, ds.atlas_size, ds.cascade_count, ds.filter, first.shadow_caster_draws
        ),
    }
    if let Some([p10, p50, p90]) = texel_ratios {
        println!("shadow texels per pixel: p10 {p10:.3}, p50 {p50:.3}, p90 {p90:.3}");
    }
    if let Some(ms) = environment_setup_ms {
        println!("environment: {} made in {ms:.1} ms (once, before the frames)", settings.environment.describe(&scene));
    }
    let rows = timing_rows(intervals, &gpu, &frames);
    println!("{:<28} {:>10} {:>10} {:>10}", "ms", "median", "min", "max");
    for (label, s) in rows {
        println!("{label:<28} {:>10.3} {:>10.3} {:>10.3}", s.median, s.min, s.max);
    }
    Ok(())
}

/// Shadow texels per pixel (10th, 50th, 90th percentiles), from one more frame after
/// the timed ones with the shadow AOVs, of the scene with only the lights that cast
/// shadows: the AOVs keep a layer per light, which for a scene of thousands of lights at
/// a large size would not fit.
fn shadow_texel_ratios(
    renderer: &mut Renderer,
    scene: &Scene,
    view: &View,
    settings: &Settings,
) -> Result<Option<[f32; 3]>> {
    let mut shadowed = scene.clone();
    shadowed.lights.retain(|light| light.shadow.casts());
    if shadowed.lights.is_empty() {
        return Ok(None);
    }
    let prepared = renderer.prepare(&shadowed)?;
    let options = FrameOptions { shadow_aovs: true, ..Default::default() };
    Ok(renderer.render(&shadowed, &prepared, view, settings, options)?.shadow_texel_ratio_percentiles())
}

/// The table's rows: the frame interval, GPU times per pass where the device has
/// timestamps, and the CPU's preparation.
fn timing_rows(intervals: Vec<f64>, gpu: &[GpuFrameTimes], frames: &[TimedFrame]) -> Vec<(String, Stats)> {
    let mut rows: Vec<(String, Stats)> = vec![("frame (back to back)".into(), stats(intervals))];
    if !gpu.is_empty() {
        rows.push(("gpu frame (timestamps)".into(), stats(gpu.iter().map(GpuFrameTimes::total_ms).collect())));
        for (pass, times) in pass_times(gpu) {
            rows.push((format!("  gpu {pass} pass"), stats(times)));
        }
        let shadow_share: Vec<f64> = gpu
            .iter()
            .filter_map(|f| Some(100.0 * f.passes.iter().find(|(p, _)| *p == "shadows")?.1 / f.total_ms()))
            .collect();
        if !shadow_share.is_empty() {
            rows.push(("  shadow passes, % of gpu".into(), stats(shadow_share)));
        }
    }
    rows.push(("cpu prepare".into(), stats(frames.iter().map(|f| f.timings.cpu_prepare_ms).collect())));
    if let Some(times) = thread_times(frames) {
        rows.push(("cpu prepare (thread clock)".into(), stats(times)));
    }
    rows
}
