//! `chiaro`: render glTF scenes (or the built-in demo) to images, describe them,
//! benchmark frames, compare shadows with a reference, and bake lightmaps. A thin layer
//! over chiaro-scene, chiaro-bake and chiaro-render.

mod bake;
mod bake_arg;
mod batch;
mod bench;
mod compare;
mod environment_arg;
mod info;
mod path_arg;
mod render;
mod scene_input;
mod shadow_args;
mod time_arg;
mod view;

use chiaro_io::output;
use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "chiaro", version, about = "Real-time light and shadow renderer for glTF scenes")]
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
    /// Compare realtime shadows with a CPU ray-traced reference, per light.
    Compare(compare::CompareArgs),
    /// Bake lightmaps and light probes for a scene's static objects (CPU path tracing).
    Bake(bake::BakeArgs),
    /// Render a job list (JSON Lines: an id, a scene, a camera, a time, outputs,
    /// settings) into one folder per job; shardable across processes, resumable, exit
    /// status the number of failed jobs (see --help).
    Batch(batch::BatchArgs),
    /// Open a window with the live 3D view and a settings panel. Mouse: drag in the view
    /// to orbit (fly: to look around), wheel to zoom, click to select an object. Keys: V
    /// switches orbit and fly; W/A/S/D move and Q/E go down and up when flying (Shift:
    /// faster); F frames the selection (an object, or a light selected in the panel; else
    /// the whole scene); R resets the view; C steps through the glTF cameras; P writes
    /// chiaro-view.png; Escape quits. Drop a .gltf or .glb on the
    /// window to open it; the scene reloads when its files change. `--screenshot FILE
    /// --exit-after-frames N` writes the 3D view after N frames and exits.
    View(view::ViewArgs),
}

/// Mesa's Vulkan drivers load libwayland, which prints "XDG_RUNTIME_DIR is invalid or not
/// set" when the variable is missing, turning a one-line error into three. Where it is
/// missing or not a folder, point it at a private folder made for this run (there is no
/// Wayland session to find then anyway). Returns the folder, removed when dropped.
fn quiet_wayland_probe() -> Option<tempfile::TempDir> {
    let usable = std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir());
    if usable {
        return None;
    }
    let dir = tempfile::Builder::new().prefix("chiaro-runtime-").tempdir().ok()?;
    // SAFETY: called first thing in main, before any other thread exists.
    unsafe { std::env::set_var("XDG_RUNTIME_DIR", dir.path()) };
    Some(dir)
}

fn main() -> ExitCode {
    let _runtime_dir = quiet_wayland_probe();
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_env("CHIARO_LOG")
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("warn")),
        )
        .with_writer(std::io::stderr)
        .with_target(false)
        .init();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage_error(e),
    };
    let result = match cli.command {
        Command::Render(args) => render::run(args),
        Command::Info(args) => info::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Bake(args) => bake::run(args),
        // Its exit status counts failed jobs, so it reports its own errors.
        Command::Batch(args) => return batch::run(args),
        Command::View(args) => view::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("chiaro: error: {}", one_line(&e));
            ExitCode::FAILURE
        }
    }
}

/// Prints clap's message (or the help asked for) and exits as clap would, except that a
/// usage error of `chiaro batch` exits with the batch's "could not run" status: its other
/// statuses count failed jobs, and clap's 2 would read as two.
fn usage_error(error: clap::Error) -> ExitCode {
    let _ = error.print();
    let batch = std::env::args_os().nth(1).is_some_and(|a| a == "batch");
    match error.use_stderr() {
        true if batch => ExitCode::from(batch::FATAL),
        _ => ExitCode::from(error.exit_code().clamp(0, 255) as u8),
    }
}

/// The error and its causes on one line, as chiaro-batch reports a failed job.
fn one_line(error: &anyhow::Error) -> String {
    chiaro_batch::error_line(error)
}
