//! `chiaro-fuzz`: long fuzzing runs by hand. Prints what ran and what crashed, keeps each
//! crashing input in `--crashes`, and exits with status 1 when anything crashed.

use anyhow::{Context, Result};
use chiaro_fuzz::{Target, fuzz};
use clap::Parser;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

#[derive(Parser)]
#[command(name = "chiaro-fuzz", about = "Fuzz Chiaro's glTF importer or settings parser")]
struct Args {
    target: Target,
    /// Inputs to run, the seeds included.
    #[arg(long, default_value_t = 100_000)]
    inputs: u64,
    /// Seed of the mutations: the same seed runs the same inputs.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Stop after this many seconds, whatever `--inputs` says.
    #[arg(long)]
    seconds: Option<u64>,
    /// Folder to keep crashing inputs in.
    #[arg(long, default_value = "fuzz-crashes")]
    crashes: PathBuf,
}

fn main() -> Result<ExitCode> {
    let args = Args::parse();
    let report = fuzz(args.target, args.inputs, args.seed, args.seconds.map(Duration::from_secs))?;
    println!(
        "{:?}: {} inputs ({} accepted, {} refused) in {:.1} s, slowest {:.1} ms, {} crashes",
        args.target,
        report.inputs,
        report.accepted,
        report.refused,
        report.elapsed.as_secs_f64(),
        report.slowest.as_secs_f64() * 1e3,
        report.crashes.len()
    );
    if report.crashes.is_empty() {
        return Ok(ExitCode::SUCCESS);
    }
    std::fs::create_dir_all(&args.crashes).with_context(|| format!("{}", args.crashes.display()))?;
    for (i, crash) in report.crashes.iter().enumerate() {
        let path = args.crashes.join(format!("crash-{i}"));
        std::fs::write(&path, &crash.input).with_context(|| format!("{}", path.display()))?;
        println!("  {}: {}", path.display(), crash.message);
    }
    Ok(ExitCode::FAILURE)
}
