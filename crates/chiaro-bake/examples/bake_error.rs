//! How close a bake's lightmaps come to a bake with many more samples, and what that
//! costs: `cargo run --release -p chiaro-bake --example bake_error -- SCENE [FACTOR]
//! [--quality Q]` bakes SCENE at the default settings (or quality Q) denoised and not,
//! and a reference with FACTOR (16) times the samples and no denoising, then prints each
//! bake's time and the median and 90th percentile relative texel error.

use chiaro_bake::convergence::{quantile, texel_errors};
use chiaro_bake::{BakeResult, Silent, bake};
use chiaro_scene::settings::BakeQuality;
use chiaro_scene::{Settings, load_gltf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        return Err("usage: bake_error SCENE [FACTOR] [--quality draft|default|high]".into());
    };
    let factor: u32 = args.get(1).filter(|a| !a.starts_with("--")).map_or(Ok(16), |f| f.parse())?;
    let quality: BakeQuality = match args.iter().position(|a| a == "--quality") {
        Some(k) => args.get(k + 1).ok_or("--quality needs a value")?.parse()?,
        None => BakeQuality::Default,
    };
    let scene = load_gltf(std::path::Path::new(path))?;
    let mut settings = Settings::default();
    settings.bake.quality = quality;
    let timed = |s: &Settings| -> Result<(BakeResult, f64), Box<dyn std::error::Error>> {
        let start = Instant::now();
        let result = bake(&scene, s, &Silent, &AtomicBool::new(false))?;
        Ok((result, start.elapsed().as_secs_f64()))
    };
    let (denoised, t_denoised) = timed(&settings)?;
    let mut noisy_settings = settings.clone();
    noisy_settings.bake.denoise = false;
    let (noisy, t_noisy) = timed(&noisy_settings)?;
    let mut reference_settings = noisy_settings.clone();
    reference_settings.bake.samples = Some(factor * settings.bake.texel_samples());
    let (reference, t_reference) = timed(&reference_settings)?;
    let samples = settings.bake.texel_samples();
    println!("{path}: {} texels, quality {}", denoised.stats.texels, quality.name());
    for (name, result, seconds) in [("denoised", &denoised, t_denoised), ("not denoised", &noisy, t_noisy)] {
        let e = texel_errors(&result.lighting.lightmaps, &reference.lighting.lightmaps);
        println!(
            "  {samples} samples, {name}: {seconds:.2} s; error median {:.1}%, p90 {:.1}% over {} texels; \
             estimated {:.1}%",
            100.0 * quantile(&e, 0.5),
            100.0 * quantile(&e, 0.9),
            e.len(),
            100.0 * result.stats.noise
        );
    }
    println!("  reference, {} samples, not denoised: {t_reference:.2} s", factor * samples);
    Ok(())
}
