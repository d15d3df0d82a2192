//! Which jobs of a list one process runs: shard I of N takes the jobs whose position
//! (0-based, among the list's non-blank lines) modulo N is I, so N processes given
//! I = 0..N run every job once. The shard comes from `--shard I/N`, else from the
//! scheduler's environment: a Slurm job array (`SLURM_ARRAY_TASK_ID`, less
//! `SLURM_ARRAY_TASK_MIN`, of `SLURM_ARRAY_TASK_COUNT`) or a Kubernetes indexed Job
//! (`JOB_COMPLETION_INDEX`, of `--shards N`). Flags and an environment flow in (the
//! environment as a lookup function, so tests pass a map); a shard, or none, flows out.

use std::fmt;

/// One shard of a job list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// This shard, from 0.
    pub index: usize,
    /// How many shards split the list, at least 1.
    pub count: usize,
}

/// Why no shard could be chosen; the message names the flag or variable at fault.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct ShardError(pub String);

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    /// Shard `index` of `count`, checked; `source` says where they came from.
    pub fn new(index: usize, count: usize, source: &str) -> Result<Shard, ShardError> {
        if count == 0 {
            return Err(ShardError(format!("{source}: the shard count must be at least 1")));
        }
        if index >= count {
            return Err(ShardError(format!(
                "{source}: shard {index} of {count} does not exist (shards are numbered 0 to {})",
                count - 1
            )));
        }
        Ok(Shard { index, count })
    }

    /// Reads `I/N`, as `--shard` takes it.
    pub fn parse(text: &str) -> Result<Shard, ShardError> {
        let source = format!("--shard {text}");
        let (index, count) = text
            .split_once('/')
            .and_then(|(i, n)| Some((i.trim().parse().ok()?, n.trim().parse().ok()?)))
            .ok_or_else(|| ShardError(format!("{source}: expected I/N, such as 0/4 (shard I of N, from 0)")))?;
        Shard::new(index, count, &source)
    }

    /// Whether the job at `position` (0-based among the non-blank lines) is this shard's.
    pub fn contains(&self, position: usize) -> bool {
        position % self.count == self.index
    }
}

/// Environment variables that choose a shard.
pub const SLURM_ID: &str = "SLURM_ARRAY_TASK_ID";
pub const SLURM_MIN: &str = "SLURM_ARRAY_TASK_MIN";
pub const SLURM_COUNT: &str = "SLURM_ARRAY_TASK_COUNT";
pub const K8S_INDEX: &str = "JOB_COMPLETION_INDEX";

/// The shard a process runs: `--shard I/N` (`shard`), else the scheduler's index from
/// `env` with `--shards N` (`shards`) or the scheduler's count; `None` runs every job.
pub fn choose_shard(
    shard: Option<&str>,
    shards: Option<&str>,
    env: impl Fn(&str) -> Option<String>,
) -> Result<Option<Shard>, ShardError> {
    let shards = match shards {
        None => None,
        Some(text) => Some(
            text.trim()
                .parse::<usize>()
                .map_err(|_| ShardError(format!("--shards {text}: expected the number of shards, such as 4")))?,
        ),
    };
    if let Some(text) = shard {
        let chosen = Shard::parse(text)?;
        if let Some(n) = shards.filter(|n| *n != chosen.count) {
            return Err(ShardError(format!("--shard {text} and --shards {n} disagree on the number of shards")));
        }
        return Ok(Some(chosen));
    }
    let number = |name: &str| -> Result<Option<usize>, ShardError> {
        match env(name) {
            None => Ok(None),
            Some(text) => text
                .trim()
                .parse::<usize>()
                .map(Some)
                .map_err(|_| ShardError(format!("{name}={text}: expected a whole number from 0"))),
        }
    };
    if let Some(id) = number(SLURM_ID)? {
        let min = number(SLURM_MIN)?.unwrap_or(0);
        let index =
            id.checked_sub(min).ok_or_else(|| ShardError(format!("{SLURM_ID}={id} is below {SLURM_MIN}={min}")))?;
        let count = match (shards, number(SLURM_COUNT)?) {
            (Some(n), _) => n,
            (None, Some(n)) => n,
            (None, None) => {
                return Err(ShardError(format!(
                    "{SLURM_ID} is set but not {SLURM_COUNT}: give the number of shards with --shards N"
                )));
            }
        };
        let source =
            if min > 0 { format!("{SLURM_ID}={id} (less {SLURM_MIN}={min})") } else { format!("{SLURM_ID}={id}") };
        return Shard::new(index, count, &source).map(Some).map_err(|ShardError(m)| {
            // An array with a step (--array=0-15:4) numbers its tasks 0, 4, 8, 12.
            ShardError(format!("{m}; a Slurm array for sharding must number its tasks without gaps (no step)"))
        });
    }
    if let Some(index) = number(K8S_INDEX)? {
        let count = shards.ok_or_else(|| {
            ShardError(format!("{K8S_INDEX} is set: give the number of shards (the Job's completions) with --shards N"))
        })?;
        return Shard::new(index, count, &format!("{K8S_INDEX}={index}")).map(Some);
    }
    match shards {
        Some(n) => Err(ShardError(format!(
            "--shards {n} without a shard: give --shard I/{n}, or run under a Slurm array or an indexed Job"
        ))),
        None => Ok(None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn env(pairs: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
        let map: HashMap<String, String> = pairs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect();
        move |name| map.get(name).cloned()
    }

    fn shard(index: usize, count: usize) -> Option<Shard> {
        Some(Shard { index, count })
    }

    #[test]
    fn the_flag_is_read_and_checked() {
        assert_eq!(choose_shard(Some("1/3"), None, env(&[])).unwrap(), shard(1, 3));
        assert_eq!(choose_shard(Some(" 0 / 1 "), Some("1"), env(&[])).unwrap(), shard(0, 1));
        let error = |flag: &str| choose_shard(Some(flag), None, env(&[])).unwrap_err().to_string();
        assert_eq!(error("3/3"), "--shard 3/3: shard 3 of 3 does not exist (shards are numbered 0 to 2)");
        assert_eq!(error("0/0"), "--shard 0/0: the shard count must be at least 1");
        assert_eq!(error("1"), "--shard 1: expected I/N, such as 0/4 (shard I of N, from 0)");
        assert_eq!(error("-1/3"), "--shard -1/3: expected I/N, such as 0/4 (shard I of N, from 0)");
        let e = choose_shard(Some("1/3"), Some("4"), env(&[])).unwrap_err().to_string();
        assert_eq!(e, "--shard 1/3 and --shards 4 disagree on the number of shards");
    }

    #[test]
    fn the_flag_wins_over_the_environment() {
        let slurm = env(&[(SLURM_ID, "2"), (SLURM_COUNT, "4")]);
        assert_eq!(choose_shard(Some("0/2"), None, slurm).unwrap(), shard(0, 2));
    }

    #[test]
    fn a_slurm_array_gives_index_and_count() {
        assert_eq!(choose_shard(None, None, env(&[(SLURM_ID, "2"), (SLURM_COUNT, "4")])).unwrap(), shard(2, 4));
        // --array=1-4: tasks 1 to 4 are shards 0 to 3.
        let from_one = env(&[(SLURM_ID, "4"), (SLURM_MIN, "1"), (SLURM_COUNT, "4")]);
        assert_eq!(choose_shard(None, None, from_one).unwrap(), shard(3, 4));
        assert_eq!(choose_shard(None, Some("8"), env(&[(SLURM_ID, "5")])).unwrap(), shard(5, 8));
        let e = choose_shard(None, None, env(&[(SLURM_ID, "1")])).unwrap_err().to_string();
        assert!(e.contains("SLURM_ARRAY_TASK_COUNT") && e.contains("--shards N"), "{e}");
        let stepped = env(&[(SLURM_ID, "8"), (SLURM_COUNT, "4")]);
        let e = choose_shard(None, None, stepped).unwrap_err().to_string();
        assert!(e.starts_with("SLURM_ARRAY_TASK_ID=8: shard 8 of 4 does not exist") && e.contains("no step"), "{e}");
        let e = choose_shard(None, None, env(&[(SLURM_ID, "x"), (SLURM_COUNT, "4")])).unwrap_err().to_string();
        assert_eq!(e, "SLURM_ARRAY_TASK_ID=x: expected a whole number from 0");
    }

    #[test]
    fn an_indexed_job_takes_its_count_from_the_flag() {
        assert_eq!(choose_shard(None, Some("3"), env(&[(K8S_INDEX, "1")])).unwrap(), shard(1, 3));
        let e = choose_shard(None, None, env(&[(K8S_INDEX, "1")])).unwrap_err().to_string();
        assert!(e.starts_with("JOB_COMPLETION_INDEX is set: give the number of shards"), "{e}");
        let e = choose_shard(None, Some("2"), env(&[(K8S_INDEX, "2")])).unwrap_err().to_string();
        assert_eq!(e, "JOB_COMPLETION_INDEX=2: shard 2 of 2 does not exist (shards are numbered 0 to 1)");
    }

    #[test]
    fn nothing_set_runs_every_job_and_a_lone_count_is_refused() {
        assert_eq!(choose_shard(None, None, env(&[])).unwrap(), None);
        let e = choose_shard(None, Some("4"), env(&[])).unwrap_err().to_string();
        assert!(e.starts_with("--shards 4 without a shard"), "{e}");
        assert!(choose_shard(None, Some("four"), env(&[])).unwrap_err().to_string().contains("--shards four"));
    }

    #[test]
    fn shards_split_positions_once_each() {
        let count = 3;
        for position in 0..20 {
            let owners = (0..count).filter(|&i| Shard { index: i, count }.contains(position)).count();
            assert_eq!(owners, 1);
        }
    }
}
