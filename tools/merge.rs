//! `rtcosim merge`: the shard files of one run (docs/scale.md) into the
//! outputs the unsharded run writes, byte for byte.

use crate::args::ThreadsArgs;
use crate::ui::plural;
use anyhow::{Context, Result};
use rtcosim::campaign::fuzz::summary::{self, Summary};
use rtcosim::campaign::mutation;
use rtcosim::campaign::shard::file::{self as shard_file, ShardFile, ShardSet};
use rtcosim::campaign::sweep::run::{self, RunConfig, ShardResult};
use serde::de::DeserializeOwned;
use serde_json::Value;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct MergeArgs {
    /// Directories of shard files (every *.shard.json in them), or shard
    /// files; together, every shard of one run exactly once.
    #[arg(required = true, value_name = "DIR")]
    pub dirs: Vec<PathBuf>,
    /// Write the merged outputs into DIR (created if missing): a sweep's
    /// sweep.csv, sweep.json and charts, a campaign's fuzz-report.txt.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    #[command(flatten)]
    pub threads: ThreadsArgs,
}

/// Returns whether the merged run passed: the RTL confirmed every front
/// configuration of a sweep, every scene of a campaign kept the promise.
pub fn run(args: MergeArgs) -> Result<bool> {
    let files = shard_file::shard_files(&args.dirs)?;
    let set = shard_file::load_set(&files)?;
    std::fs::create_dir_all(&args.out).with_context(|| format!("--out {}", args.out.display()))?;
    let first = set.files[0].0.clone();
    let count = set.files.len() as u64;
    {
        let mut stdout = std::io::stdout().lock();
        writeln!(
            stdout,
            "merging {count} {} shard{} (configuration {})",
            set.tool,
            plural(count),
            set.files[0].1.config_hash
        )?;
    }
    match set.tool.as_str() {
        run::TOOL => merge_sweep(set, &first, &args),
        summary::TOOL => merge_fuzz(set, &first, &args),
        mutation::TOOL => merge_mutate(set, &first, &args),
        other => anyhow::bail!(
            "{}: a shard of {other:?}: rtcosim merges sweep, fuzz and mutate shards",
            first.display()
        ),
    }
}

/// The run's configuration as `C`, naming `first` if it does not read.
fn config<C: DeserializeOwned>(set: &ShardSet, first: &Path) -> Result<C> {
    serde_json::from_value(set.config.clone())
        .with_context(|| format!("{}: its configuration", first.display()))
}

/// A shard file's result as `R`, naming the file if it does not read.
fn result<R: DeserializeOwned>(path: &Path, file: &ShardFile<Value>) -> Result<R> {
    serde_json::from_value(file.result.clone())
        .with_context(|| format!("{}: damaged: its result", path.display()))
}

fn merge_sweep(set: ShardSet, first: &Path, args: &MergeArgs) -> Result<bool> {
    let config: RunConfig = config(&set, first)?;
    let scenes = config.load_scenes()?;
    let mut measured = Vec::new();
    for (path, file) in &set.files {
        let items = result::<ShardResult>(path, file)?
            .decode(&config, &file.items)
            .map_err(|e| anyhow::anyhow!("{}: damaged: {e}", path.display()))?;
        measured.extend(items);
    }
    let pool = args.threads.pool()?;
    crate::sweep::finish(&config, &scenes, measured, &args.out, &pool)
}

fn merge_fuzz(set: ShardSet, first: &Path, args: &MergeArgs) -> Result<bool> {
    let _: summary::Campaign = config(&set, first)?;
    let mut total: Option<Summary> = None;
    for (path, file) in &set.files {
        let summary: Summary = result(path, file)?;
        if summary.scenes != file.items.len() as u64 {
            anyhow::bail!(
                "{}: damaged: its summary counts {} scenes, its shard holds {}",
                path.display(),
                summary.scenes,
                file.items.len()
            );
        }
        match &mut total {
            Some(t) => t.merge(summary),
            None => total = Some(summary),
        }
    }
    let total = total.expect("a checked set has a shard");
    crate::fuzz::finish(&mut std::io::stdout().lock(), &total, Some(&args.out))?;
    Ok(total.passed())
}

fn merge_mutate(set: ShardSet, first: &Path, args: &MergeArgs) -> Result<bool> {
    let campaign: mutation::Campaign = config(&set, first)?;
    let list = mutation::List::committed(campaign.processor)?;
    if list.rtl_hash != campaign.rtl_hash {
        anyhow::bail!(
            "{}: its mutants were listed on other RTL (fnv1a64 {}, this rtcosim's list {})",
            first.display(),
            campaign.rtl_hash,
            list.rtl_hash
        );
    }
    let mut total: Option<mutation::Summary> = None;
    for (path, file) in &set.files {
        let summary: mutation::Summary = result(path, file)?;
        if summary.outcomes.len() != file.items.len() {
            anyhow::bail!(
                "{}: damaged: it judged {} mutants, its shard holds {}",
                path.display(),
                summary.outcomes.len(),
                file.items.len()
            );
        }
        match &mut total {
            Some(t) => t.merge(summary),
            None => total = Some(summary),
        }
    }
    let total = total.expect("a checked set has a shard");
    crate::mutate::finish(
        &mut std::io::stdout().lock(),
        &total,
        &list,
        Some(&args.out),
    )?;
    Ok(total.passed())
}
