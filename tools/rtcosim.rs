//! `rtcosim`: co-simulate the handwritten RTL against the golden models.

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use golden::fp::Method;
use indicatif::{ProgressBar, ProgressStyle};
use rtcosim::fp_check::{self, CheckReport, Operands};
use rtcosim::fp_unit::UnitKind;
use std::io::Write;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Co-simulate the float units of rtl/fp against golden::fp: edge cases,
    /// then seeded random operands (or every input, for unary units).
    FpCheck(FpCheckArgs),
}

#[derive(clap::Args, Debug)]
struct FpCheckArgs {
    /// Units to check (default: all).
    #[arg(long, value_enum, value_delimiter = ',')]
    unit: Vec<UnitArg>,
    /// Random operands per unit.
    #[arg(long, default_value_t = 1_000_000)]
    count: u64,
    /// Seed of the random operand stream.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Sweep all 2^32 inputs of the unary units instead of random operands
    /// (binary units still get --count random operands).
    #[arg(long)]
    exhaustive: bool,
    /// Worker threads, one verilated model each (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum UnitArg {
    Add,
    Mul,
    Itof,
    RecipExact,
    RecipFast,
    SqrtExact,
    SqrtFast,
}

impl From<UnitArg> for UnitKind {
    fn from(u: UnitArg) -> UnitKind {
        match u {
            UnitArg::Add => UnitKind::Add,
            UnitArg::Mul => UnitKind::Mul,
            UnitArg::Itof => UnitKind::Itof,
            UnitArg::RecipExact => UnitKind::Recip(Method::Exact),
            UnitArg::RecipFast => UnitKind::Recip(Method::Fast),
            UnitArg::SqrtExact => UnitKind::Sqrt(Method::Exact),
            UnitArg::SqrtFast => UnitKind::Sqrt(Method::Fast),
        }
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        // The reader went away (`rtcosim ... | head`): nothing left to say.
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Returns whether every check passed.
fn run(cli: Cli) -> Result<bool> {
    match cli.command {
        Command::FpCheck(args) => fp_check_command(args),
    }
}

fn fp_check_command(args: FpCheckArgs) -> Result<bool> {
    let mut out = std::io::stdout().lock();
    if let Some(threads) = args.threads {
        if threads == 0 {
            bail!("--threads must be at least 1");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build_global()
            .context("starting the worker threads")?;
    }
    let units: Vec<UnitKind> = if args.unit.is_empty() {
        UnitKind::ALL.to_vec()
    } else {
        args.unit.iter().map(|&u| u.into()).collect()
    };
    writeln!(
        out,
        "rtcosim fp-check: {} units, {}, seed {}, {} threads, {}",
        units.len(),
        if args.exhaustive {
            "all 2^32 inputs (unary)".to_string()
        } else {
            format!("{} random operands", args.count)
        },
        args.seed,
        rayon::current_num_threads(),
        rtcosim::VERILATOR_VERSION
    )?;
    writeln!(out)?;
    writeln!(
        out,
        "{:<16} {:>7} {:>12} {:>10} {:>12} {:>13}",
        "unit", "cycles", "operands", "mismatch", "worst error", "Mevals/s/model"
    )?;
    let mut all_passed = true;
    let mut failures = Vec::new();
    for kind in units {
        let random = if args.exhaustive && !kind.is_binary() {
            Operands::Exhaustive
        } else {
            Operands::Random {
                seed: args.seed,
                count: args.count,
            }
        };
        let edge = fp_check::run(kind, Operands::Edge, &|_| {})?;
        let bar = ProgressBar::new(random.count(kind)).with_style(
            ProgressStyle::with_template("{prefix:<16} [{bar:30}] {pos}/{len} ({eta})")
                .context("progress bar template")?
                .progress_chars("=> "),
        );
        bar.set_prefix(kind.to_string());
        let report = fp_check::run(kind, random, &|n| bar.inc(n))?;
        bar.finish_and_clear();
        let report = edge.merge(report);
        print_row(&mut out, &report)?;
        all_passed &= report.passed();
        if !report.passed() {
            failures.push(report);
        }
    }
    for report in &failures {
        writeln!(out)?;
        writeln!(
            out,
            "{}: {} mismatches, {} cycle-count violations (promised {} cycles)",
            report.unit,
            report.mismatches,
            report.latency_violations,
            report.unit.latency()
        )?;
        for m in &report.first_mismatches {
            writeln!(out, "  {m}")?;
        }
    }
    writeln!(out)?;
    writeln!(
        out,
        "{}",
        if all_passed {
            "all units agree with golden::fp"
        } else {
            "MISMATCHES FOUND"
        }
    )?;
    Ok(all_passed)
}

fn print_row(out: &mut impl Write, r: &CheckReport) -> std::io::Result<()> {
    let cycles = match r.cycles {
        Some((0, 0)) | None => "comb".to_string(),
        Some((lo, hi)) if lo == hi => lo.to_string(),
        Some((lo, hi)) => format!("{lo}-{hi}"),
    };
    writeln!(
        out,
        "{:<16} {:>7} {:>12} {:>10} {:>12} {:>13.2}",
        r.unit.to_string(),
        cycles,
        r.operands,
        r.mismatches,
        r.worst_error.to_string(),
        r.evals_per_second() / 1e6
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_definition_is_consistent() {
        Cli::command().debug_assert();
    }
}
