//! `rtcosim trace-dump`: a trace file as text.

use anyhow::{Context, Result};
use golden::micro::isa;
use golden::trace::{format_event, TraceReader};
use std::io::Write;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct TraceDumpArgs {
    /// The trace file.
    pub file: PathBuf,
}

pub fn run(args: TraceDumpArgs) -> Result<()> {
    let path = args.file.display();
    let file = std::fs::File::open(&args.file).with_context(|| format!("{path}"))?;
    let reader =
        TraceReader::new(std::io::BufReader::new(file)).with_context(|| format!("{path}"))?;
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    writeln!(
        out,
        "# {path}: rtcosim trace version {}, scene hash {:016x}",
        golden::trace::VERSION,
        reader.header().scene_hash
    )?;
    writeln!(out, "# {}", reader.header().config)?;
    let mut events = 0u64;
    for event in reader {
        let event = event.with_context(|| format!("{path}"))?;
        writeln!(
            out,
            "{}",
            format_event(&event, &isa::state_name, &isa::register_name)
        )?;
        events += 1;
    }
    writeln!(out, "# {events} events")?;
    out.flush()?;
    Ok(())
}
