//! `chiaro batch`: a job list rendered into one folder per job, a shard of it per process,
//! resumable. The flags become a job list, a shard and base settings; chiaro-batch does
//! the work and reports progress here, as a bar on a terminal or one line per job.

use crate::one_line;
use crate::scene_input::load_settings;
use anyhow::{Context, Result};
use chiaro_batch::{
    BatchRunner, Event, JobOutcome, Shard, Summary, choose_shard, parse_jobs, prepare_output, shard_jobs,
};
use chiaro_render::{GpuContext, Renderer};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

/// The exit status of a batch that could not run at all (its usage errors too).
pub const FATAL: u8 = 101;
/// Failed jobs beyond this many still exit with it.
const MOST_FAILED: usize = 100;

const AFTER_HELP: &str = "\
A job is one JSON object per line (blank lines ignored); every key but id and scene is
optional:
  {\"id\": \"a\", \"scene\": \"s.gltf\", \"camera\": \"Cam\" | 0 | {\"eye\": [x, y, z], \"target\": [x, y, z]},
   \"time\": 1.5, \"width\": 640, \"height\": 480, \"outputs\": [\"rgb\", \"depth\"],
   \"settings\": {\"render\": {\"msaa\": 1}}, \"seed\": 7}
Each job writes OUTPUT/<id>/ (its files and meta.json) whole or not at all; a job whose
folder is current is skipped, so a rerun resumes. A failed job writes OUTPUT/<id>.error.json
and the others go on. See docs/batch.md.

Exit status:
  0        every job done or skipped
  1-100    that many jobs failed (100: 100 or more); see OUTPUT/<id>.error.json
  101      the batch could not run: a usage error (an unknown flag, a missing value),
           a bad job list, shard or settings file, an output folder that cannot be
           written, no GPU";

#[derive(Args)]
#[command(after_help = AFTER_HELP)]
pub struct BatchArgs {
    /// The job list: a JSON Lines file, one job object per line.
    pub jobs: PathBuf,
    /// The folder that receives one folder per job (made if missing).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Run shard I of N: the jobs whose position (from 0, among the non-blank lines)
    /// modulo N is I. Default: from SLURM_ARRAY_TASK_ID (less SLURM_ARRAY_TASK_MIN) of
    /// SLURM_ARRAY_TASK_COUNT, or JOB_COMPLETION_INDEX (a Kubernetes indexed Job) of
    /// --shards; with none of them, every job.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// The number of shards, for an index taken from the environment (required with
    /// JOB_COMPLETION_INDEX; overrides SLURM_ARRAY_TASK_COUNT).
    #[arg(long, value_name = "N")]
    pub shards: Option<String>,
    /// Base settings (TOML, see docs/settings.md); each job's "settings" are merged over
    /// them.
    #[arg(long)]
    pub settings: Option<PathBuf>,
}

pub fn run(args: BatchArgs) -> ExitCode {
    match run_batch(&args) {
        Ok(summary) if summary.failed.is_empty() => ExitCode::SUCCESS,
        Ok(summary) => ExitCode::from(summary.failed.len().min(MOST_FAILED) as u8),
        Err(e) => {
            eprintln!("chiaro: error: {}", one_line(&e));
            ExitCode::from(FATAL)
        }
    }
}

fn run_batch(args: &BatchArgs) -> Result<Summary> {
    let list = args.jobs.display().to_string();
    let text = std::fs::read_to_string(&args.jobs).with_context(|| format!("{list}: cannot read the job list"))?;
    let jobs = parse_jobs(text.lines(), &list)?;
    let shard = choose_shard(args.shard.as_deref(), args.shards.as_deref(), |name| std::env::var(name).ok())?;
    let listed = jobs.len();
    let jobs = shard_jobs(jobs, shard);
    let base = load_settings(args.settings.as_deref())?;
    prepare_output(&args.output)?;
    let start = Instant::now();
    let summary = if jobs.is_empty() {
        Summary::default()
    } else {
        let ctx = GpuContext::new()?;
        chiaro_io::device::check_msaa(&ctx, &base, None, args.settings.as_deref())?;
        let mut renderer = Renderer::new(ctx)?;
        let mut report = Report::new(jobs.len());
        let summary = BatchRunner::new(&mut renderer, base).run_all(&jobs, &args.output, |e| report.event(e));
        report.finish();
        summary
    };
    eprintln!(
        "chiaro: batch: {} done, {} skipped, {} failed of {}{} in {:.1} s, into {}",
        summary.done,
        summary.skipped,
        summary.failed.len(),
        jobs.len(),
        shard_note(shard, listed),
        start.elapsed().as_secs_f64(),
        args.output.display()
    );
    Ok(summary)
}

/// How many jobs the list holds, when a shard ran some of them.
fn shard_note(shard: Option<Shard>, listed: usize) -> String {
    match shard {
        Some(shard) => format!(" jobs (shard {shard} of a list of {listed})"),
        None => " jobs".to_string(),
    }
}

/// A progress bar on a terminal; one line per job otherwise (logs, CI).
enum Report {
    Bar(ProgressBar),
    Lines,
}

impl Report {
    fn new(total: usize) -> Report {
        if !std::io::stderr().is_terminal() {
            return Report::Lines;
        }
        let bar = ProgressBar::new(total as u64);
        bar.set_style(
            ProgressStyle::with_template("{msg:>20!} [{bar:40}] {pos}/{len} {per_sec} {eta} left")
                .expect("valid template")
                .progress_chars("=> "),
        );
        Report::Bar(bar)
    }

    fn event(&mut self, event: Event<'_>) {
        match (self, event) {
            (Report::Bar(bar), Event::Started { job, .. }) => bar.set_message(job.id.clone()),
            (Report::Bar(bar), Event::Finished { job, outcome, .. }) => {
                if let JobOutcome::Failed(message) = outcome {
                    bar.println(format!("chiaro: {} FAILED: {message}", job.id));
                }
                bar.inc(1);
            }
            (Report::Lines, Event::Started { .. }) => {}
            (Report::Lines, Event::Finished { position, total, job, outcome, seconds }) => {
                let id = &job.id;
                match outcome {
                    JobOutcome::Done => eprintln!("chiaro: [{position}/{total}] {id} done in {seconds:.2} s"),
                    JobOutcome::Skipped => eprintln!("chiaro: [{position}/{total}] {id} skipped"),
                    JobOutcome::Failed(message) => eprintln!("chiaro: [{position}/{total}] {id} FAILED: {message}"),
                }
            }
        }
    }

    fn finish(&self) {
        if let Report::Bar(bar) = self {
            bar.finish_and_clear();
        }
    }
}
