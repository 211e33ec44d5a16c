//! `rtcosim trace-dump`: a trace file as text.

use anyhow::{Context, Result};
use golden::micro::isa;
use golden::trace::{format_record, TraceReader, TraceRecord};
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
    let h = reader.header();
    writeln!(
        out,
        "# {path}: rtcosim trace version {}, written by the {}, scene hash {:016x}, configuration hash {:016x}",
        golden::trace::VERSION,
        h.side,
        h.scene_hash,
        h.config_hash
    )?;
    writeln!(out, "# {}", h.config)?;
    let (mut events, mut pixels) = (0u64, 0u64);
    for record in reader {
        let record = record.with_context(|| format!("{path}"))?;
        writeln!(
            out,
            "{}",
            format_record(&record, &isa::state_name, &isa::register_name)
        )?;
        match record {
            TraceRecord::Event(_) => events += 1,
            TraceRecord::PixelEnd { .. } => pixels += 1,
        }
    }
    writeln!(out, "# {events} events, {pixels} pixels")?;
    out.flush()?;
    Ok(())
}
