//! `trace-diff A B`: the `rtcosim trace-diff` subcommand as a binary of its
//! own (the same code: see trace_diff.rs).

#[allow(dead_code)] // the parsers other commands use
mod args;
mod exit;
mod trace_diff;
#[allow(dead_code)]
mod ui;

use clap::Parser;
use std::process::ExitCode;

/// Compare two rtcosim trace files pixel by pixel and name the first
/// divergent state in the Verilog and the Rust.
#[derive(Parser, Debug)]
#[command(name = "trace-diff", version)]
struct Cli {
    #[command(flatten)]
    args: trace_diff::TraceDiffArgs,
}

fn main() -> ExitCode {
    exit::status(trace_diff::run(Cli::parse().args))
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    #[test]
    fn the_command_line_is_well_formed() {
        super::Cli::command().debug_assert();
    }
}
