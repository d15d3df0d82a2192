//! `chiaro bake`: lightmaps and light probes for a scene, written as a bake directory.

use crate::output::Inputs;
use crate::scene_input::load_settings;
use anyhow::{Context, Result, bail};
use chiaro_bake::{BakeError, Progress, bake, default_bake_dir, write_bake_dir};
use chiaro_scene::load_gltf;
use chiaro_scene::settings::BakeQuality;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

#[derive(Args)]
pub struct BakeArgs {
    /// A .gltf or .glb file.
    pub scene: PathBuf,
    /// Bake directory to write (default: `<scene stem>.bake/` beside the scene).
    #[arg(short, long, value_name = "DIR")]
    pub output: Option<PathBuf>,
    /// Pipeline settings (TOML); the `[bake]` section and the ambient term matter here.
    #[arg(long)]
    pub settings: Option<PathBuf>,
    /// Paths per lightmap texel (overrides bake.samples).
    #[arg(long)]
    pub samples: Option<u32>,
    /// Bounces of indirect light (overrides bake.bounces).
    #[arg(long)]
    pub bounces: Option<u32>,
    /// Lightmap texels per metre (overrides bake.texels_per_metre).
    #[arg(long)]
    pub texels_per_metre: Option<f32>,
    /// Random seed (overrides bake.seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Metres between light probes (overrides bake.probe_spacing).
    #[arg(long)]
    pub probe_spacing: Option<f32>,
    /// Directions per light probe (overrides bake.probe_samples).
    #[arg(long)]
    pub probe_samples: Option<u32>,
    /// Samples and denoising: draft, default or high (overrides bake.quality; explicit
    /// sample counts still win).
    #[arg(long, value_name = "QUALITY", value_parser = parse_quality)]
    pub quality: Option<BakeQuality>,
    /// Keep the lightmaps' bounced light as traced, noise and all (bake.denoise = false).
    #[arg(long)]
    pub no_denoise: bool,
}

fn parse_quality(s: &str) -> Result<BakeQuality, String> {
    s.parse()
}

/// A progress bar on a terminal; plain lines every tenth otherwise (logs, CI). Both
/// show the stage's rays per second.
struct Report {
    kind: ReportKind,
    /// Rays traced in the current stage, and when it began.
    rays: AtomicU64,
    since: Mutex<Instant>,
}

enum ReportKind {
    Bar(Mutex<Option<ProgressBar>>),
    Lines { stage: Mutex<(String, u64)>, done: AtomicU64 },
}

impl Report {
    fn new(kind: ReportKind) -> Report {
        Report { kind, rays: AtomicU64::new(0), since: Mutex::new(Instant::now()) }
    }

    /// The current stage's rays per second, without decimals.
    fn rate(&self) -> String {
        let seconds = self.since.lock().expect("progress lock").elapsed().as_secs_f64().max(1e-3);
        format!("{:.0} rays/s", self.rays.load(Ordering::Relaxed) as f64 / seconds)
    }
}

impl Progress for Report {
    fn stage(&self, name: &str, total: u64) {
        self.rays.store(0, Ordering::Relaxed);
        *self.since.lock().expect("progress lock") = Instant::now();
        match &self.kind {
            ReportKind::Bar(bar) => {
                let mut bar = bar.lock().expect("progress lock");
                if let Some(old) = bar.take() {
                    old.finish();
                }
                let b = ProgressBar::new(total);
                b.set_style(
                    ProgressStyle::with_template("{prefix:>14} [{bar:40}] {pos}/{len} {msg} {eta} left")
                        .expect("valid template")
                        .progress_chars("=> "),
                );
                b.set_prefix(name.to_string());
                *bar = Some(b);
            }
            ReportKind::Lines { stage, done } => {
                *stage.lock().expect("progress lock") = (name.to_string(), total);
                done.store(0, Ordering::Relaxed);
                eprintln!("chiaro: bake: {name}: 0 of {total}");
            }
        }
    }

    fn advance(&self, units: u64, rays: u64) {
        self.rays.fetch_add(rays, Ordering::Relaxed);
        match &self.kind {
            ReportKind::Bar(bar) => {
                if let Some(b) = bar.lock().expect("progress lock").as_ref() {
                    b.set_message(self.rate());
                    b.inc(units);
                }
            }
            ReportKind::Lines { stage, done } => {
                let now = done.fetch_add(units, Ordering::Relaxed) + units;
                let (name, total) = stage.lock().expect("progress lock").clone();
                let tenth = (total / 10).max(1);
                if now / tenth != (now - units) / tenth || now == total {
                    eprintln!("chiaro: bake: {name}: {now} of {total}, {}", self.rate());
                }
            }
        }
    }
}

impl Report {
    fn finish(&self) {
        if let ReportKind::Bar(bar) = &self.kind
            && let Some(b) = bar.lock().expect("progress lock").take()
        {
            b.finish();
        }
    }
}

/// The estimated error, and what it was before denoising.
fn error_summary(s: &chiaro_bake::BakeStats, denoised: bool) -> String {
    let percent = |e: f32| format!("{:.1}%", 100.0 * e);
    if denoised {
        format!("{} ({} before denoising)", percent(s.noise), percent(s.noise_traced))
    } else {
        format!("{} (not denoised)", percent(s.noise))
    }
}

pub fn run(args: BakeArgs) -> Result<()> {
    let mut settings = load_settings(args.settings.as_deref())?;
    let b = &mut settings.bake;
    let overrides = [
        ("--samples", args.samples.map(|v| b.samples = Some(v)).is_some()),
        ("--bounces", args.bounces.map(|v| b.bounces = v).is_some()),
        ("--texels-per-metre", args.texels_per_metre.map(|v| b.texels_per_metre = v).is_some()),
        ("--seed", args.seed.map(|v| b.seed = v).is_some()),
        ("--probe-spacing", args.probe_spacing.map(|v| b.probe_spacing = v).is_some()),
        ("--probe-samples", args.probe_samples.map(|v| b.probe_samples = Some(v)).is_some()),
        ("--quality", args.quality.map(|v| b.quality = v).is_some()),
    ];
    if args.no_denoise {
        b.denoise = false;
    }
    if let Err(e) = settings.validate() {
        let flag = overrides.iter().filter(|(_, given)| *given).map(|(f, _)| *f).collect::<Vec<_>>().join(", ");
        bail!("{}{e}", if flag.is_empty() { String::new() } else { format!("{flag}: ") });
    }
    let mut scene = load_gltf(&args.scene)?;
    scene.source = Some(args.scene.clone());
    let output = args.output.clone().unwrap_or_else(|| default_bake_dir(&args.scene));
    let inputs = Inputs::new(&scene.inputs, args.settings.as_deref());
    if inputs.contains(&output) {
        bail!("{}: is an input of this command; choose another bake directory", output.display());
    }
    if output.is_file() {
        bail!("{}: is a file, not a bake directory", output.display());
    }
    // A bake replaces the directory it is written to: only ever an older bake, never a
    // folder holding the scene or anything else.
    if let Some(input) = inputs.inside(&output) {
        bail!(
            "{}: holds {}, an input of this command; choose another bake directory",
            output.display(),
            input.display()
        );
    }
    if output.is_dir()
        && !chiaro_bake::bake_dir::is_bake_dir(&output)
        && std::fs::read_dir(&output).is_ok_and(|mut entries| entries.next().is_some())
    {
        bail!(
            "{}: exists and is not a bake directory (no bake {}); refusing to replace it",
            output.display(),
            chiaro_bake::bake_dir::MANIFEST
        );
    }

    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    // A second handler cannot be set (tests run several commands in one process); the
    // first one's flag is then the one that counts, so ignore the error.
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    let report = Report::new(if std::io::stderr().is_terminal() {
        ReportKind::Bar(Mutex::new(None))
    } else {
        ReportKind::Lines { stage: Mutex::new((String::new(), 0)), done: AtomicU64::new(0) }
    });
    let result = bake(&scene, &settings, &report, &cancel);
    report.finish();
    let result = result.map_err(|e| match e {
        BakeError::Invalid(message) => anyhow::anyhow!("{}: {message}", args.scene.display()),
        other => anyhow::anyhow!(other),
    })?;
    write_bake_dir(&output, &scene, &settings, &result, &cancel)
        .with_context(|| format!("{}: cannot write the bake", output.display()))?;
    let s = result.stats;
    eprintln!(
        "chiaro: baked {} into {}: {} lightmap atlases of {}x{} ({} texels), {} probes, {:.1} M rays in {:.1} s \
         ({:.2} M rays/s); estimated error {}",
        args.scene.display(),
        output.display(),
        result.layout.atlas_count,
        result.layout.size,
        result.layout.size,
        s.texels,
        s.probes,
        s.rays as f64 / 1e6,
        s.seconds,
        s.rays_per_second / 1e6,
        error_summary(&s, settings.bake.denoise)
    );
    Ok(())
}
