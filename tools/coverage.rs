//! `rtcosim coverage`: the counts of several coverage runs or shards
//! (`cosim --coverage`, `fuzz --coverage`, `RTCOSIM_COVERAGE=DIR cargo
//! test --features coverage`) merged into one report.

use anyhow::{Context, Result};
use rtcosim::output::coverage;
use std::io::Write;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct CoverageArgs {
    /// Coverage directories (their raw/*.dat, else their coverage.dat) or
    /// coverage.dat files: runs or shards to sum.
    #[arg(required = true, value_name = "DIR")]
    pub inputs: Vec<PathBuf>,
    /// Write the merged coverage.dat, coverage.info, html/, summary.json and
    /// summary.md into DIR (default: the input, when there is one).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Skip the HTML report (genhtml).
    #[arg(long)]
    pub no_html: bool,
}

pub fn run(args: CoverageArgs) -> Result<bool> {
    let out_dir = match (&args.out, args.inputs.as_slice()) {
        (Some(o), _) => o.clone(),
        (None, [one]) if one.is_dir() => one.clone(),
        _ => anyhow::bail!(
            "several inputs (or a file): say where the merged report goes with --out DIR"
        ),
    };
    let done = coverage::finish(&args.inputs, &out_dir, !args.no_html)
        .with_context(|| format!("merging coverage into {}", out_dir.display()))?;
    let mut out = std::io::stdout().lock();
    write!(out, "{}", done.report())?;
    Ok(true)
}
