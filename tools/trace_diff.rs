//! `trace-diff A B` (also `rtcosim trace-diff`): two trace files, the first
//! divergent state named in the Verilog and the Rust, the context before
//! it, a summary and, with `--json`, the same for machines.

use crate::args::parse_pixel;
use crate::ui::{plural, progress_spinner};
use anyhow::{Context as _, Result};
use golden::micro::isa;
use golden::trace::{format_event, TraceHeader};
use rtcosim::check::compare::{event_json, Labels, Tolerance};
use rtcosim::check::trace_diff::{self, DiffOptions, TraceDiff};
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

/// Compare two trace files (from `rtcosim cosim --trace` or `rtcosim
/// render --trace`) pixel by pixel and name the first divergent state in
/// the Verilog (rtl/pp/pp_ctrl.v, or rtl/fast/fast_ctrl.v for the fast
/// processor's traces) and in the Rust (golden/src/micro).
///
/// Exits 0 when every pixel in both traces agrees within --max-ulps, 1 on
/// a divergence, 2 on an error (an unreadable, truncated or foreign file,
/// traces of different scenes).
#[derive(clap::Args, Debug)]
#[command(after_help = "Examples:\n  \
    rtcosim cosim --size 80x60 --trace rtl.rtt --trace-window 0,0,79,59\n  \
    rtcosim render --model micro --size 80x60 --trace golden.rtt --trace-window 0,0,79,59\n  \
    trace-diff rtl.rtt golden.rtt --context 5")]
pub struct TraceDiffArgs {
    /// Trace A (side A of the report).
    pub a: PathBuf,
    /// Trace B (side B).
    pub b: PathBuf,
    /// Show the K events before the first divergence, from both sides.
    #[arg(long, value_name = "K", default_value_t = 3)]
    pub context: usize,
    /// Values up to N ULPs apart agree (default 0: bit for bit; NaNs agree
    /// only bit for bit).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub max_ulps: u32,
    /// Compare only pixel X,Y.
    #[arg(long, value_name = "X,Y", value_parser = parse_pixel)]
    pub pixel: Option<(u32, u32)>,
    /// List every divergent pixel with its first divergence, not only the
    /// first.
    #[arg(long)]
    pub all: bool,
    /// Also write the result as JSON to FILE (`-` for stdout, instead of
    /// the text).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

/// What a header says, in a few words.
fn describe(h: &TraceHeader) -> String {
    let mut words = vec![format!("written by the {}", h.side)];
    for key in [
        "simulator",
        "model",
        "processor",
        "scene",
        "size",
        "recip",
        "sqrt",
        "depth",
        "window",
        "fault",
    ] {
        if let Some(v) = h.config_value(key) {
            words.push(format!("{key} {v}"));
        }
    }
    words.join(", ")
}

/// Returns whether the traces agree.
pub fn run(args: TraceDiffArgs) -> Result<bool> {
    let options = DiffOptions {
        tolerance: Tolerance {
            max_ulps: args.max_ulps,
        },
        pixel: args.pixel,
        context: args.context,
        sources_for_all: args.all,
    };
    let json_only = args.json.as_deref() == Some(std::path::Path::new("-"));
    let mut out: Box<dyn Write> = if json_only {
        Box::new(std::io::sink())
    } else {
        Box::new(std::io::stdout().lock())
    };
    let labels = trace_diff::labels(&args.a, &args.b);
    let spinner = progress_spinner("comparing", "{pos} pixels ({per_sec})")?;
    let start = Instant::now();
    let mut listed = Vec::new();
    let result = trace_diff::diff(
        &args.a,
        &args.b,
        &options,
        &mut |v| {
            if args.all {
                if let Some(d) = &v.first {
                    listed.push(d.text(&labels).to_string());
                }
            }
        },
        &|n| spinner.inc(n),
    );
    let seconds = start.elapsed().as_secs_f64();
    spinner.finish_and_clear();
    let diff = result?;
    print_text(&mut out, &args, &labels, &diff, &listed, seconds)?;
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&to_json(&diff, &labels, seconds))?;
        if json_only {
            println!("{text}");
        } else {
            std::fs::write(path, text + "\n")
                .with_context(|| format!("--json {}", path.display()))?;
        }
    }
    Ok(diff.passed())
}

fn print_text(
    out: &mut dyn Write,
    args: &TraceDiffArgs,
    labels: &Labels,
    diff: &TraceDiff,
    listed: &[String],
    seconds: f64,
) -> Result<()> {
    let Labels { a: la, b: lb, .. } = labels;
    writeln!(
        out,
        "A = {}: {}",
        args.a.display(),
        describe(&diff.a_header)
    )?;
    writeln!(
        out,
        "B = {}: {}",
        args.b.display(),
        describe(&diff.b_header)
    )?;
    writeln!(
        out,
        "scene hash {:016x} in both: the same scene",
        diff.a_header.scene_hash
    )?;
    if diff.header_differences.is_empty() {
        writeln!(out, "configurations: the same")?;
    } else {
        writeln!(out, "configurations differ:")?;
        for d in &diff.header_differences {
            let v = |v: &Option<String>| v.clone().unwrap_or_else(|| "-".into());
            writeln!(out, "  {:<10} {la}: {}, {lb}: {}", d.key, v(&d.a), v(&d.b))?;
        }
    }
    writeln!(out)?;
    if args.all {
        for text in listed {
            writeln!(out, "{text}\n")?;
        }
    }
    let r = &diff.report;
    if let Some(d) = &r.first_divergence {
        writeln!(out, "first divergence: {}", d.text(labels))?;
        let context = &diff.context;
        if !context.a.is_empty() || !context.b.is_empty() {
            let width = la.len().max(lb.len());
            let n = context.a.len().max(context.b.len());
            writeln!(out, "the {n} event{} before it:", plural(n as u64))?;
            for (label, events) in [(la, &context.a), (lb, &context.b)] {
                for e in events {
                    writeln!(
                        out,
                        "  {label:<width$} {}",
                        format_event(e, &isa::state_name, &isa::register_name)
                    )?;
                }
            }
        }
        writeln!(out)?;
    }
    let c = &r.counts;
    writeln!(
        out,
        "{} pixel{} compared in {seconds:.2} s ({:.1} M events/s){}",
        c.pixels,
        plural(c.pixels),
        (c.a_events + c.b_events) as f64 / seconds.max(1e-9) / 1e6,
        if diff.only_a + diff.only_b > 0 {
            format!(
                "; {} only in {la}, {} only in {lb} (not compared)",
                diff.only_a, diff.only_b
            )
        } else {
            String::new()
        }
    )?;
    writeln!(out, "{r}")?;
    if r.ulps.total() > 0 {
        writeln!(
            out,
            "ULP distances of the lanes both sides wrote:\n{}",
            r.ulps
        )?;
    }
    // The divergent pixels, by class, in row order.
    const SHOWN: usize = 20;
    let limit = if args.all { usize::MAX } else { SHOWN };
    let mut classes: Vec<(String, Vec<String>, usize)> = Vec::new();
    for (x, y, class) in &diff.divergent {
        let name = class.to_string();
        let at = match classes.iter().position(|(n, _, _)| *n == name) {
            Some(i) => i,
            None => {
                classes.push((name, Vec::new(), 0));
                classes.len() - 1
            }
        };
        let (_, shown, count) = &mut classes[at];
        *count += 1;
        if shown.len() < limit {
            shown.push(format!("({x}, {y})"));
        }
    }
    for (name, shown, count) in &classes {
        let more = count - shown.len();
        writeln!(
            out,
            "{name} ({count} pixel{}): {}{}",
            plural(*count as u64),
            shown.join(", "),
            if more > 0 {
                format!(", and {more} more (--all lists them)")
            } else {
                String::new()
            }
        )?;
    }
    writeln!(out)?;
    if diff.passed() {
        let within = if args.max_ulps == 0 {
            "bit for bit".to_string()
        } else {
            format!("within {} ULP", args.max_ulps)
        };
        writeln!(
            out,
            "PASS: the traces agree on every common pixel, {within}: events, colour and cycles"
        )?;
    } else {
        writeln!(
            out,
            "FAIL: {} of {} pixels diverge",
            c.divergent_pixels, c.pixels
        )?;
    }
    Ok(())
}

fn to_json(diff: &TraceDiff, labels: &Labels, seconds: f64) -> serde_json::Value {
    let header = |h: &TraceHeader| {
        serde_json::json!({
            "side": h.side.key(),
            "scene_hash": format!("{:016x}", h.scene_hash),
            "config_hash": format!("{:016x}", h.config_hash),
            "config": h.config,
        })
    };
    serde_json::json!({
        "a": header(&diff.a_header),
        "b": header(&diff.b_header),
        "header_differences": diff.header_differences.iter().map(|d| serde_json::json!({
            "key": d.key, "a": d.a, "b": d.b,
        })).collect::<Vec<_>>(),
        "passed": diff.passed(),
        "report": diff.report.to_json(),
        "only_a": diff.only_a,
        "only_b": diff.only_b,
        "divergent_pixels": diff.divergent.iter().map(|(x, y, class)| serde_json::json!({
            "pixel": [x, y], "class": class.to_string(),
        })).collect::<Vec<_>>(),
        "sides": [labels.a, labels.b],
        "context": {
            "a": diff.context.a.iter().map(|e| event_json(labels.processor, e, None)).collect::<Vec<_>>(),
            "b": diff.context.b.iter().map(|e| event_json(labels.processor, e, None)).collect::<Vec<_>>(),
        },
        "seconds": seconds,
    })
}
