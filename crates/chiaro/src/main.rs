//! `chiaro`: render glTF scenes (or the built-in demo) to images, describe them, and
//! benchmark frames. A thin layer over chiaro-scene and chiaro-render.

mod bench;
mod info;
mod output;
mod render;
mod scene_source;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "chiaro",
    version,
    about = "Real-time light and shadow renderer for glTF scenes"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene (or the built-in demo scene) to a PNG or OpenEXR image.
    Render(render::RenderArgs),
    /// Print what a scene file holds: meshes, materials, lights, cameras, bounds.
    Info(info::InfoArgs),
    /// Time frames of a scene (or the demo) and print a table.
    Bench(bench::BenchArgs),
}

fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_env("CHIARO_LOG")
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("warn")),
        )
        .with_writer(std::io::stderr)
        .with_target(false)
        .init();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render::run(args),
        Command::Info(args) => info::run(args),
        Command::Bench(args) => bench::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("chiaro: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
