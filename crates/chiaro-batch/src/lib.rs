//! Chiaro's job lists, shared by `chiaro batch` and the Python package's `render_jobs`.
//!
//! A job is data: an id, a scene, a camera, a time, a size, outputs, settings and a seed
//! (`job`). A list is checked whole before anything renders; a shard of it is chosen from
//! flags or a scheduler's environment (`shard`); each job of the shard renders on a
//! borrowed renderer (`runner`) into its own folder, written whole or not at all
//! (`folder`) with a record of what it read and made (`meta`), so that a scheduler may
//! retry, shard or resume a list freely: a rerun skips every job that is current. Chiaro
//! does not schedule; Slurm, Kubernetes or Ray do.

pub mod camera;
pub mod folder;
pub mod job;
pub mod meta;
pub mod outputs;
pub mod runner;
pub mod settings;
pub mod shard;

pub use job::{Job, JobListError, JobSpec, parse_jobs};
pub use outputs::{Output, Outputs};
pub use runner::{BatchRunner, Event, JobOutcome, Summary};
pub use shard::{Shard, ShardError, choose_shard};

use std::path::{Path, PathBuf};

/// Why a batch could not run at all (a job's own failure is its error.json instead).
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    /// The job list is not a list of jobs.
    #[error(transparent)]
    JobList(#[from] JobListError),
    /// No shard could be chosen.
    #[error(transparent)]
    Shard(#[from] ShardError),
    /// The output folder cannot be made or written in.
    #[error("{}: cannot write the jobs' folders there: {source}", dir.display())]
    Output { dir: PathBuf, source: std::io::Error },
}

/// The jobs of `jobs` that `shard` runs (all of them without one), in order.
pub fn shard_jobs(jobs: Vec<Job>, shard: Option<Shard>) -> Vec<Job> {
    match shard {
        None => jobs,
        Some(shard) => jobs.into_iter().enumerate().filter(|(i, _)| shard.contains(*i)).map(|(_, j)| j).collect(),
    }
}

/// Makes the output folder `dir` if it is missing and checks that files can be made in it.
pub fn prepare_output(dir: &Path) -> Result<(), BatchError> {
    let fail = |source| BatchError::Output { dir: dir.to_path_buf(), source };
    std::fs::create_dir_all(dir).map_err(fail)?;
    let probe = dir.join(format!(".chiaro-batch-probe-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(fail)?;
    std::fs::remove_file(&probe).map_err(fail)?;
    Ok(())
}

/// An error and its causes on one line, leaving out causes whose text the line already
/// holds (chiaro-io's errors often quote their source): how the CLI prints every error.
pub fn error_line(error: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in error.chain() {
        let text = cause.to_string();
        if line.contains(&text) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    line.replace('\n', " ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shard_takes_every_nth_job_from_its_index() {
        let lines: Vec<String> = (0..7).map(|i| format!(r#"{{"id": "j{i}", "scene": "s.gltf"}}"#)).collect();
        let jobs = parse_jobs(lines.iter().map(String::as_str), "j").unwrap();
        let ids = |shard| shard_jobs(jobs.clone(), shard).into_iter().map(|j| j.id).collect::<Vec<_>>();
        assert_eq!(ids(Some(Shard { index: 1, count: 3 })), ["j1", "j4"]);
        assert_eq!(ids(None).len(), 7);
    }

    #[test]
    fn an_output_folder_is_made_or_refused_naming_it() {
        let dir = tempfile::tempdir().unwrap();
        prepare_output(&dir.path().join("a/b")).unwrap();
        assert!(dir.path().join("a/b").is_dir());
        std::fs::write(dir.path().join("file"), b"").unwrap();
        let e = prepare_output(&dir.path().join("file")).unwrap_err().to_string();
        assert!(e.contains("file: cannot write the jobs' folders there"), "{e}");
    }
}
