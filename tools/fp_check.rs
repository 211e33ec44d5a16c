//! `rtcosim fp-check`: the float units of rtl/fp (and the pipelined ones of
//! rtl/fast) against golden::fp.

use crate::args::ThreadsArgs;
use crate::ui::{plural, progress_bar};
use anyhow::Result;
use clap::ValueEnum;
use golden::fp::Method;
use rtcosim::check::fp_check::{self, CheckReport, Operands};
use rtcosim::design::fp_unit::UnitKind;
use std::io::Write;

#[derive(clap::Args, Debug)]
pub struct FpCheckArgs {
    /// Units to check (default: all, the pipelined fast-* ones too).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub unit: Vec<UnitArg>,
    /// Random operands per unit.
    #[arg(long, default_value_t = 1_000_000, allow_negative_numbers = true)]
    pub count: u64,
    /// Seed of the random operand stream.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// Sweep all 2^32 inputs of the unary units instead of random operands
    /// (binary units still get --count random operands).
    #[arg(long)]
    pub exhaustive: bool,
    #[command(flatten)]
    pub threads: ThreadsArgs,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitArg {
    Add,
    Mul,
    Itof,
    RecipExact,
    RecipFast,
    SqrtExact,
    SqrtFast,
    Exp,
    FastAdd,
    FastMul,
    FastItof,
    FastRecipExact,
    FastRecipFast,
    FastSqrtExact,
    FastSqrtFast,
    FastExp,
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
            UnitArg::Exp => UnitKind::Exp,
            UnitArg::FastAdd => UnitKind::FastAdd,
            UnitArg::FastMul => UnitKind::FastMul,
            UnitArg::FastItof => UnitKind::FastItof,
            UnitArg::FastRecipExact => UnitKind::FastRecip(Method::Exact),
            UnitArg::FastRecipFast => UnitKind::FastRecip(Method::Fast),
            UnitArg::FastSqrtExact => UnitKind::FastSqrt(Method::Exact),
            UnitArg::FastSqrtFast => UnitKind::FastSqrt(Method::Fast),
            UnitArg::FastExp => UnitKind::FastExp,
        }
    }
}

/// Returns whether every unit agreed with its golden model.
pub fn run(args: FpCheckArgs) -> Result<bool> {
    let pool = args.threads.pool()?;
    pool.install(|| check(&args))
}

fn check(args: &FpCheckArgs) -> Result<bool> {
    let mut out = std::io::stdout().lock();
    let threads = rayon::current_num_threads();
    let units: Vec<UnitKind> = if args.unit.is_empty() {
        UnitKind::every().collect()
    } else {
        args.unit.iter().map(|&u| u.into()).collect()
    };
    writeln!(
        out,
        "rtcosim fp-check: {} unit{}, {}, seed {}, {threads} thread{}, {}",
        units.len(),
        plural(units.len() as u64),
        if args.exhaustive {
            "all 2^32 inputs (unary)".to_string()
        } else {
            format!("{} random operands", args.count)
        },
        args.seed,
        plural(threads as u64),
        rtcosim::VERILATOR_VERSION
    )?;
    writeln!(out)?;
    writeln!(
        out,
        "{:<20} {:>7} {:>12} {:>10} {:>12} {:>13}",
        "unit", "cycles", "operands", "mismatch", "worst error", "Mevals/s/model"
    )?;
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
        let bar = progress_bar(
            random.count(kind),
            &format!("{:<20}", kind.to_string()),
            "{pos}/{len} ({eta})",
        )?;
        let report = fp_check::run(kind, random, &|n| bar.inc(n))?;
        bar.finish_and_clear();
        let report = edge.merge(report);
        print_row(&mut out, &report)?;
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
    let all_passed = failures.is_empty();
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
        "{:<20} {:>7} {:>12} {:>10} {:>12} {:>13.2}",
        r.unit.to_string(),
        cycles,
        r.operands,
        r.mismatches,
        r.worst_error.to_string(),
        r.evals_per_second() / 1e6
    )
}
