//! Sharding: one long run (a sweep over many scenes, a fuzz campaign of
//! thousands of scenes) split into N fixed, disjoint slices that run as
//! separate processes, on one machine or as the tasks of a cluster's array
//! job, and merged back into the outputs of the unsharded run, byte for
//! byte (docs/scale.md).
//!
//! - [`Shard`]: which slice a process runs, `K/N` with K counted **from 0**
//!   (`0/4` .. `3/4`), from `--shard K/N` or, when that is absent, from the
//!   environment of a Slurm array task or a Kubernetes Indexed Job
//!   ([`Shard::from_env`]).
//! - The slice rule, [`Shard::positions`]: the positions `0..len` of a
//!   run's work list are put in a fixed scrambled order (by [`scatter`], a
//!   bijection of u64, of the position) and dealt out round robin; each
//!   shard gets `len / N` or one more, and does its items in work-list
//!   order. Not plain round robin: a sweep's grid is a product of
//!   power-of-two dimensions, so `i mod N` splits it along one (2 shards
//!   got the shadow shortcut on and off: 20.9 s against 7.1 s,
//!   docs/scale.md), and not blocks, for the same reason (depths grow along
//!   the grid, and costs with them). It depends on nothing but the position
//!   and the length, never on thread counts or timing.
//! - [`file`]: the shard result file each shard writes, and the checks
//!   that a set of them is one whole run (`rtcosim merge`).
//! - [`journal`]: each item's result on disk as soon as it is known, so
//!   that a run killed part way resumes where it stopped.

pub mod file;
pub mod journal;

use std::fmt;
use std::str::FromStr;

/// One slice of a run: shard `index` of `count`, `index` from 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    pub index: u64,
    pub count: u64,
}

/// Why a shard cannot be had.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ShardError {
    #[error("{source_name} {text:?}: expected K/N, shard K (from 0) of N, e.g. 0/4")]
    Syntax { source_name: String, text: String },
    #[error("{source_name}: shard count 0: there must be at least one shard")]
    NoShards { source_name: String },
    #[error(
        "{source_name}: shard {index} of {count}: K counts from 0, so it must be below N = {count}"
    )]
    OutOfRange {
        source_name: String,
        index: u64,
        count: u64,
    },
    #[error("{0}")]
    Environment(String),
}

impl Shard {
    /// The whole run as one shard.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// `index` of `count`, checked; `source_name` says where they came from.
    pub fn new(index: u64, count: u64, source_name: &str) -> Result<Shard, ShardError> {
        if count == 0 {
            return Err(ShardError::NoShards {
                source_name: source_name.into(),
            });
        }
        if index >= count {
            return Err(ShardError::OutOfRange {
                source_name: source_name.into(),
                index,
                count,
            });
        }
        Ok(Shard { index, count })
    }

    /// `K/N` as written after `source_name` (a flag or a variable).
    pub fn parse(text: &str, source_name: &str) -> Result<Shard, ShardError> {
        let syntax = || ShardError::Syntax {
            source_name: source_name.into(),
            text: text.into(),
        };
        let (k, n) = text.split_once('/').ok_or_else(syntax)?;
        let number = |s: &str| s.trim().parse::<u64>().map_err(|_| syntax());
        Shard::new(number(k)?, number(n)?, source_name)
    }

    /// The positions in `0..len` this shard owns, ascending: the
    /// positions sorted by [`scatter`], dealt round robin, shard K taking
    /// the K-th, (K + N)-th, ... of that order.
    pub fn positions(&self, len: u64) -> Vec<u64> {
        let mut order: Vec<u64> = (0..len).collect();
        // A bijection: no ties, so the order is the same on every platform.
        order.sort_unstable_by_key(|&i| scatter(i));
        let step = usize::try_from(self.count).unwrap_or(usize::MAX);
        let skip = usize::try_from(self.index).unwrap_or(usize::MAX);
        let mut mine: Vec<u64> = order.into_iter().skip(skip).step_by(step).collect();
        mine.sort_unstable();
        mine
    }

    /// The shard the environment names, if any, with `count` the shard count
    /// given on the command line (`--shard-count`) for a Kubernetes index.
    ///
    /// - Slurm array task: `SLURM_ARRAY_TASK_ID` minus `SLURM_ARRAY_TASK_MIN`
    ///   (an `--array=a-b` range may start anywhere) of
    ///   `SLURM_ARRAY_TASK_COUNT`. A stepped or listed array
    ///   (`SLURM_ARRAY_TASK_STEP` other than 1, or IDs past MIN + COUNT) is
    ///   refused: its IDs are not 0..N after the shift.
    /// - Kubernetes Indexed Job: `JOB_COMPLETION_INDEX` of `count`, else of
    ///   `RTCOSIM_SHARD_COUNT`.
    ///
    /// Both at once is refused, naming both.
    pub fn from_env(
        get: &dyn Fn(&str) -> Option<String>,
        count: Option<u64>,
    ) -> Result<Option<Shard>, ShardError> {
        let slurm = get("SLURM_ARRAY_TASK_ID");
        let k8s = get("JOB_COMPLETION_INDEX");
        let number = |name: &str, text: &str| {
            text.trim().parse::<u64>().map_err(|_| {
                ShardError::Environment(format!(
                    "{name}={text:?}: expected a whole number, at least 0"
                ))
            })
        };
        match (slurm, k8s) {
            (Some(id), Some(index)) => Err(ShardError::Environment(format!(
                "both SLURM_ARRAY_TASK_ID={id} and JOB_COMPLETION_INDEX={index} are set: \
                 which shard this is is ambiguous; give --shard K/N"
            ))),
            (Some(id), None) => {
                let id = number("SLURM_ARRAY_TASK_ID", &id)?;
                let min = match get("SLURM_ARRAY_TASK_MIN") {
                    Some(min) => number("SLURM_ARRAY_TASK_MIN", &min)?,
                    None => 0,
                };
                let total = get("SLURM_ARRAY_TASK_COUNT").ok_or_else(|| {
                    ShardError::Environment(
                        "SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not".into(),
                    )
                })?;
                let total = number("SLURM_ARRAY_TASK_COUNT", &total)?;
                if let Some(step) = get("SLURM_ARRAY_TASK_STEP") {
                    if number("SLURM_ARRAY_TASK_STEP", &step)? != 1 {
                        return Err(ShardError::Environment(format!(
                            "SLURM_ARRAY_TASK_STEP={step}: a stepped array's IDs are not 0..N; \
                             submit with --array=0-{}",
                            total.saturating_sub(1)
                        )));
                    }
                }
                let index = id.checked_sub(min).ok_or_else(|| {
                    ShardError::Environment(format!(
                        "SLURM_ARRAY_TASK_ID={id} is below SLURM_ARRAY_TASK_MIN={min}"
                    ))
                })?;
                let source = format!(
                    "SLURM_ARRAY_TASK_ID={id} - SLURM_ARRAY_TASK_MIN={min} of SLURM_ARRAY_TASK_COUNT"
                );
                Shard::new(index, total, &source).map(Some)
            }
            (None, Some(index)) => {
                let index = number("JOB_COMPLETION_INDEX", &index)?;
                let (total, source) = match count {
                    Some(n) => (n, "JOB_COMPLETION_INDEX of --shard-count"),
                    None => {
                        let n = get("RTCOSIM_SHARD_COUNT").ok_or_else(|| {
                            ShardError::Environment(
                                "JOB_COMPLETION_INDEX is set but not the shard count: give \
                                 --shard-count N or RTCOSIM_SHARD_COUNT (the Job's completions)"
                                    .into(),
                            )
                        })?;
                        (
                            number("RTCOSIM_SHARD_COUNT", &n)?,
                            "JOB_COMPLETION_INDEX of RTCOSIM_SHARD_COUNT",
                        )
                    }
                };
                Shard::new(index, total, source).map(Some)
            }
            (None, None) => Ok(None),
        }
    }

    /// The shard of a command: `flag` (`--shard K/N`) if given, else the
    /// process environment's ([`Shard::from_env`]); `None` for an unsharded
    /// run. `--shard-count` without an index to go with it is refused.
    pub fn resolve(flag: Option<Shard>, count: Option<u64>) -> Result<Option<Shard>, ShardError> {
        if let Some(shard) = flag {
            if count.is_some_and(|n| n != shard.count) {
                return Err(ShardError::Environment(format!(
                    "--shard {shard} and --shard-count {} disagree",
                    count.unwrap_or_default()
                )));
            }
            return Ok(Some(shard));
        }
        let found = Shard::from_env(&|name| std::env::var(name).ok(), count)?;
        if found.is_none() && count.is_some() {
            return Err(ShardError::Environment(
                "--shard-count is the count of a Kubernetes JOB_COMPLETION_INDEX, \
                 and that is not set (give --shard K/N instead)"
                    .into(),
            ));
        }
        Ok(found)
    }
}

/// SplitMix64's output function: a fixed bijection of u64 that scatters
/// neighbouring positions far apart (the slice rule's order).
pub fn scatter(i: u64) -> u64 {
    let mut z = i.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = ShardError;

    fn from_str(s: &str) -> Result<Shard, ShardError> {
        Shard::parse(s, "--shard")
    }
}

#[cfg(test)]
mod tests;
