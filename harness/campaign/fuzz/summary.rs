//! What a campaign's report says, in a form that merges exactly: the
//! summaries of disjoint sets of scenes add up to the summary of all of
//! them, whatever the split ([`Summary::merge`]). `rtcosim fuzz` prints a
//! summary; a shard of a campaign writes its summary into its shard file
//! ([`crate::campaign::shard`]), and `rtcosim merge` adds the shards' up and prints
//! the same text the unsharded campaign prints.
//!
//! The work list of a campaign is its scene indices `first..first +
//! count`, item `i` being scene `first + i` ([`Campaign::indices`]).

use super::{Fate, FuzzReport};
use crate::campaign::shard::Shard;
use crate::check::compare::Counts;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The tool name in shard files.
pub const TOOL: &str = "fuzz";

/// Every option of a campaign that affects its report.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Campaign {
    pub seed: u64,
    pub first: u64,
    pub count: u64,
    pub timeout_cycles: u64,
    /// `STATE:XOR`, as `--fault` takes it.
    pub fault: Option<String>,
    /// Where failing scenes are written (their paths are in the report).
    pub failures: String,
    /// The Verilator that built the RTL.
    pub verilator: String,
    /// The pixel processor (`compact` or `fast`); shard files from before
    /// the fast processor name none: the compact one.
    #[serde(default = "compact")]
    pub processor: String,
}

fn compact() -> String {
    crate::design::processor::ProcessorKind::default()
        .name()
        .to_string()
}

impl Campaign {
    /// The scene indices `shard` runs.
    pub fn indices(&self, shard: Shard) -> Vec<u64> {
        shard
            .positions(self.count)
            .into_iter()
            .map(|i| self.first + i)
            .collect()
    }
}

/// A scene that broke the promise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Failure {
    pub seed: u64,
    pub index: u64,
    /// What went wrong: the first divergence, the non-finite channels, or
    /// the run's error.
    pub what: String,
    /// Where the scene was written.
    pub file: Option<String>,
}

/// A campaign's (or a shard's) report, as printed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub scenes: u64,
    pub accepted: u64,
    pub in_limits: u64,
    pub in_limits_accepted: u64,
    /// Refusals by kind of field.
    pub refused_by_field: BTreeMap<String, u64>,
    /// Every co-simulated pixel's counts.
    pub counts: Counts,
    /// Controller states reached, ascending.
    pub states: Vec<u16>,
    /// Each accepted scene's largest colour error, 0..255, ascending.
    pub max_errors: Vec<f64>,
    pub nonfinite: u64,
    /// By scene index.
    pub failures: Vec<Failure>,
}

impl Summary {
    pub fn passed(&self) -> bool {
        self.failures.is_empty()
    }

    /// Whether state `id` was reached.
    pub fn reached(&self, id: u16) -> bool {
        self.states.binary_search(&id).is_ok()
    }

    /// Adds the summary of a disjoint set of scenes.
    pub fn merge(&mut self, other: Summary) {
        self.scenes += other.scenes;
        self.accepted += other.accepted;
        self.in_limits += other.in_limits;
        self.in_limits_accepted += other.in_limits_accepted;
        for (field, n) in other.refused_by_field {
            *self.refused_by_field.entry(field).or_default() += n;
        }
        self.counts += other.counts;
        self.states.extend(other.states);
        self.states.sort_unstable();
        self.states.dedup();
        self.max_errors.extend(other.max_errors);
        self.max_errors.sort_by(f64::total_cmp);
        self.nonfinite += other.nonfinite;
        self.failures.extend(other.failures);
        self.failures.sort_by_key(|f| f.index);
    }
}

impl From<&FuzzReport> for Summary {
    fn from(r: &FuzzReport) -> Summary {
        let states = (0..=u16::MAX)
            .filter(|&id| r.states().contains(id))
            .collect();
        let mut max_errors = r.max_errors.clone();
        max_errors.sort_by(f64::total_cmp);
        let mut failures: Vec<Failure> = r
            .failures
            .iter()
            .map(|(o, path)| Failure {
                seed: o.scene.seed,
                index: o.scene.index,
                what: match &o.fate {
                    Fate::Ran(ran) if !ran.compare.passed() => {
                        match &ran.compare.first_divergence {
                            Some(d) => format!("diverges: {}", d.text(&ran.compare.labels)),
                            None => "no events compared".to_string(),
                        }
                    }
                    Fate::Ran(ran) => format!("{} non-finite colour channels", ran.nonfinite),
                    Fate::Error(e) => format!("the run failed: {e}"),
                    Fate::Refused { .. } => unreachable!("a refusal is not a failure"),
                },
                file: path.as_ref().map(|p| p.display().to_string()),
            })
            .collect();
        failures.sort_by_key(|f| f.index);
        Summary {
            scenes: r.scenes,
            accepted: r.accepted,
            in_limits: r.in_limits,
            in_limits_accepted: r.in_limits_accepted,
            refused_by_field: r.refused_by_field.clone(),
            counts: r.compare.counts,
            states,
            max_errors,
            nonfinite: r.nonfinite,
            failures,
        }
    }
}
