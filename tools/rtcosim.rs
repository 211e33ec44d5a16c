//! `rtcosim`: co-simulate the handwritten RTL against the golden models.
//!
//! This file parses the command line, dispatches to one module per
//! subcommand and maps the outcome to an exit status: 0 when every check
//! passed, 1 when a check failed (a divergence, a mismatch), 2 on an error.

mod args;
mod cosim;
mod coverage;
mod diffmap;
mod exit;
mod fp_check;
mod fuzz;
mod merge;
mod mutate;
mod render;
mod sweep;
mod trace_diff;
mod trace_dump;
mod tune;
mod ui;
mod wave;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Co-simulate the verilated RTL pixel processor against the golden
    /// micro-op model, pixel by pixel (the main job).
    ///
    /// Every register-file write (state, destination, lanes, bits), every
    /// pixel's colour and cycle count is compared. Exits 0 when everything
    /// agrees, 1 on any divergence, 2 on an error (a hung RTL is one).
    Cosim(cosim::CosimArgs),
    /// Merge the RTL coverage of several runs or shards (`cosim --coverage`,
    /// `fuzz --coverage`, `RTCOSIM_COVERAGE=DIR cargo test --features
    /// coverage`) into one report: coverage.dat, lcov, HTML and a summary
    /// naming every state and transition never taken. Exits 0 when written,
    /// 2 on an error.
    Coverage(coverage::CoverageArgs),
    /// Where two renders differ: heat maps (ULPs, 0..255 scale), the
    /// thesis' masks at thresholds (figure 17) and its table of differences.
    ///
    /// A and B are each a model rendered here (reference, micro, rtl) or a
    /// frame file (.exr); per-side methods with --a-recip, --b-sqrt, ...
    /// Exits 0 when the maps are written, 2 on an error.
    Diffmap(diffmap::DiffMapArgs),
    /// Co-simulate the float units of rtl/fp, and the fast processor's
    /// pipelined ones of rtl/fast, against golden::fp: edge cases, then seeded
    /// random operands (or every input, for unary units).
    FpCheck(fp_check::FpCheckArgs),
    /// Generate random scene files and co-simulate each one that loads;
    /// each must be refused at load or agree everywhere, with finite
    /// colours. Exits 0 when every scene kept that promise, 1 otherwise.
    Fuzz(fuzz::FuzzArgs),
    /// Merge the shard files of a sharded sweep or fuzz campaign (written
    /// by `--shard K/N`, or by the tasks of a Slurm array or Kubernetes
    /// Indexed Job) into the outputs of the unsharded run, byte for byte;
    /// a sweep's front is confirmed on the RTL here. Refuses, naming them,
    /// shards of different runs, missing shards, duplicates and damaged
    /// files. Exits as the unsharded run would (0 passed, 1 failed, 2 error).
    Merge(merge::MergeArgs),
    /// Mutation testing: judge mutants of the pixel processor (Yosys'
    /// `mutate`, rtl/mutate/pixel_processor.mutants; one verilated netlist
    /// carries them all) against golden on every builtin scene at a small
    /// size and seeded fuzz scenes, and report the killed, the survivors
    /// and the first check that killed each. Needs a build with `--features
    /// mutation`. Exits 0 when every mutant was killed or proved equivalent
    /// (--equiv), 1 otherwise, 2 on an error.
    Mutate(mutate::MutateArgs),
    /// Render a scene to a PNG with a golden model (and, with --trace, write
    /// the micro-op model's trace of a window of pixels).
    Render(render::RenderArgs),
    /// Speed against accuracy: every configuration (methods, stack depth,
    /// speed-ups) of scenes, the Pareto front confirmed on the RTL, CSV,
    /// JSON and a chart. Exits 0 when the RTL confirmed every front point.
    Sweep(sweep::SweepArgs),
    /// Print a trace file (rtcosim render --trace, rtcosim cosim --trace) as
    /// text: one line per register-file write, with state and register
    /// names, and one per pixel's end.
    TraceDump(trace_dump::TraceDumpArgs),
    /// Compare two trace files and name the first divergent state in the
    /// Verilog and the Rust (the same as the `trace-diff` binary).
    TraceDiff(trace_diff::TraceDiffArgs),
    /// Find the cheapest configuration (processor, stack depth, float
    /// methods, weight cutoff, with every speed-up whose precondition
    /// holds) whose frame is within --max-error of the f64 reference, by
    /// device frames/s, area or cycles; say why; co-simulate the build it
    /// runs on before recommending it. Exits 0 with a recommendation, 1 if
    /// nothing meets the target or the RTL disagrees, 2 on an error (a bad
    /// --max-error is one).
    Tune(tune::TuneArgs),
}

fn main() -> ExitCode {
    exit::status(match Cli::parse().command {
        Command::Cosim(args) => cosim::run(args),
        Command::Coverage(args) => coverage::run(args),
        Command::Diffmap(args) => diffmap::run(args).map(|()| true),
        Command::FpCheck(args) => fp_check::run(args),
        Command::Fuzz(args) => fuzz::run(args),
        Command::Merge(args) => merge::run(args),
        Command::Mutate(args) => mutate::run(args),
        Command::Render(args) => render::run(args).map(|()| true),
        Command::Sweep(args) => sweep::run(args),
        Command::TraceDump(args) => trace_dump::run(args).map(|()| true),
        Command::TraceDiff(args) => trace_diff::run(args),
        Command::Tune(args) => tune::run(args),
    })
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod doc_commands;
