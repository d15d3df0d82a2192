//! Fuzzing on stable Rust: seeded, structure-aware mutation of a corpus (`seeds`),
//! each input fed to a target (the glTF importer, the settings parser) inside
//! `catch_unwind`, every panic kept with the input that caused it. An input that makes a
//! target panic is a crash; one that returns an error is a refusal, which is the point.
//!
//! `chiaro-fuzz gltf --inputs 100000` runs by hand for as long as wanted; the tests run a
//! short fixed-seed pass in CI.

pub mod mutate;
pub mod rng;
pub mod seeds;
pub mod spec_seeds;

use rng::Rng;
use serde_json::Value;
use std::panic::AssertUnwindSafe;
use std::path::Path;
use std::time::{Duration, Instant};

/// What is fuzzed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Target {
    /// `chiaro_scene::load_gltf_bytes`: .gltf JSON and .glb containers.
    Gltf,
    /// `chiaro_scene::Settings::parse`.
    Settings,
}

impl Target {
    /// Runs the target on `input`; `true` when it accepted the input.
    pub fn run(self, input: &[u8]) -> bool {
        match self {
            // External URIs point into a folder that does not exist: the inputs stand alone.
            Target::Gltf => chiaro_scene::load_gltf_bytes(Path::new("chiaro-fuzz-inputs/input.gltf"), input).is_ok(),
            Target::Settings => {
                std::str::from_utf8(input).is_ok_and(|text| chiaro_scene::Settings::parse(text).is_ok())
            }
        }
    }

    fn seeds(self) -> anyhow::Result<Vec<Vec<u8>>> {
        match self {
            Target::Gltf => seeds::gltf_seeds(),
            Target::Settings => Ok(seeds::settings_seeds()),
        }
    }
}

/// An input that made the target panic.
#[derive(Clone, Debug)]
pub struct Crash {
    pub input: Vec<u8>,
    pub message: String,
}

#[derive(Clone, Debug, Default)]
pub struct Report {
    pub inputs: u64,
    pub accepted: u64,
    pub refused: u64,
    pub crashes: Vec<Crash>,
    pub slowest: Duration,
    pub elapsed: Duration,
}

/// Runs `inputs` mutated inputs (or until `time_limit`), deterministically for `seed`.
pub fn fuzz(target: Target, inputs: u64, seed: u64, time_limit: Option<Duration>) -> anyhow::Result<Report> {
    let corpus = target.seeds()?;
    let parsed: Vec<Option<Value>> = corpus.iter().map(|s| serde_json::from_slice(s).ok()).collect();
    let mut rng = Rng::new(seed);
    let mut report = Report::default();
    let start = Instant::now();
    let previous_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    for n in 0..inputs {
        if time_limit.is_some_and(|limit| start.elapsed() > limit) {
            break;
        }
        // The seeds themselves first, then mutants.
        let k = rng.below(corpus.len());
        let input = if (n as usize) < corpus.len() {
            corpus[n as usize].clone()
        } else {
            match (target, &parsed[k]) {
                (Target::Gltf, Some(doc)) if !rng.chance(4) => mutate::mutate_json(&mut rng, doc),
                (Target::Settings, _) if !rng.chance(4) => mutate::mutate_toml(&mut rng, &corpus[k]),
                _ => {
                    let other = &corpus[rng.below(corpus.len())];
                    mutate::mutate_bytes(&mut rng, &corpus[k], other)
                }
            }
        };
        let began = Instant::now();
        let outcome = std::panic::catch_unwind(AssertUnwindSafe(|| target.run(&input)));
        report.slowest = report.slowest.max(began.elapsed());
        report.inputs += 1;
        match outcome {
            Ok(true) => report.accepted += 1,
            Ok(false) => report.refused += 1,
            Err(payload) => {
                let message = payload
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| payload.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "(no message)".into());
                report.crashes.push(Crash { input, message });
            }
        }
    }
    std::panic::set_hook(previous_hook);
    report.elapsed = start.elapsed();
    Ok(report)
}
