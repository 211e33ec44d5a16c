//! The comparison in words: a divergence with both sides' values and the
//! golden source line, and a report's counts.

use super::{
    lane_distance, CompareReport, Divergence, DivergenceClass, DivergenceKind, Labels, SourceLine,
    UlpHistogram,
};
use crate::design::processor::ProcessorKind;
use crate::design::rtl_source::state_line;
use golden::micro::isa::{lanes_label, register_label, state_label};
use golden::trace::TraceEvent;
use std::fmt;

fn value_label(bits: u32) -> String {
    format!("{bits:#010x} ({:e})", f32::from_bits(bits))
}

fn rgb_label(rgb: [u32; 3]) -> String {
    let [r, g, b] = rgb.map(value_label);
    format!("[{r}, {g}, {b}]")
}

/// A state's label and the Verilog line that decodes it:
/// `SPH_BD (40) [rtl/pp/pp_ctrl.v:640]`, on the compact processor.
pub fn state_with_line(processor: ProcessorKind, state: u16) -> String {
    match state_line(processor, state) {
        Some(at) => format!("{} [{at}]", state_label(state)),
        None => state_label(state),
    }
}

/// `file:line` of a golden source line.
fn rust_line(at: SourceLine) -> String {
    format!("{}:{}", at.file(), at.line())
}

/// One side's event: state with its Verilog line, destination and lanes,
/// and the golden source line when known.
fn event_line(processor: ProcessorKind, e: &TraceEvent, at: Option<SourceLine>) -> String {
    let mut line = format!(
        "state {}, dst {}.{}",
        state_with_line(processor, e.state),
        register_label(e.dst),
        lanes_label(e.lanes)
    );
    if let Some(at) = at {
        line += &format!(", issued by {}", rust_line(at));
    }
    line
}

/// The lanes either event wrote: both values, hex and decimal, and their
/// ULP distance.
fn lane_lines(
    f: &mut fmt::Formatter<'_>,
    labels: &Labels,
    a: &TraceEvent,
    b: &TraceEvent,
) -> fmt::Result {
    let Labels { a: la, b: lb, .. } = labels;
    for i in 0..3 {
        let (wa, wb) = (a.lanes >> i & 1 == 1, b.lanes >> i & 1 == 1);
        if !wa && !wb {
            continue;
        }
        let side = |wrote: bool, bits: u32| {
            if wrote {
                value_label(bits)
            } else {
                "(not written)".to_string()
            }
        };
        write!(
            f,
            "\n    lane {}: {la} {}, {lb} {}",
            ['x', 'y', 'z'][i],
            side(wa, a.values[i]),
            side(wb, b.values[i])
        )?;
        if let Some(dist) = lane_distance(a, b, i) {
            write!(f, ": {dist}")?;
        }
    }
    Ok(())
}

/// A divergence with the names of its sides; see [`Divergence::text`].
pub struct DivergenceText<'a> {
    d: &'a Divergence,
    labels: &'a Labels,
}

impl Divergence {
    /// The divergence in words, the sides named by `labels`.
    pub fn text<'a>(&'a self, labels: &'a Labels) -> DivergenceText<'a> {
        DivergenceText { d: self, labels }
    }
}

impl fmt::Display for DivergenceClass {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            DivergenceClass::NumericDrift => "numeric drift",
            DivergenceClass::ControlFlow(_) => "control-flow divergence",
            DivergenceClass::Timing => "timing only",
        })
    }
}

impl fmt::Display for DivergenceText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Labels { a: la, b: lb, .. } = self.labels;
        let p = self.labels.processor;
        let d = self.d;
        let (x, y) = (d.x, d.y);
        let width = la.len().max(lb.len());
        match &d.kind {
            DivergenceKind::Event { a, b } => {
                write!(f, "pixel ({x}, {y}) event #{} ({}):", b.seq, d.class)?;
                write!(f, "\n  {la:<width$} {}", event_line(p, a, d.a_at))?;
                write!(f, "\n  {lb:<width$} {}", event_line(p, b, d.b_at))?;
                lane_lines(f, self.labels, a, b)?;
            }
            DivergenceKind::MissingEvent { b } => {
                write!(
                    f,
                    "pixel ({x}, {y}) event #{} ({}): the {la} wrote only {} events; {lb} goes on:",
                    b.seq, d.class, d.a.events
                )?;
                write!(f, "\n  {lb:<width$} {}", event_line(p, b, d.b_at))?;
            }
            DivergenceKind::ExtraEvent { a } => {
                write!(
                    f,
                    "pixel ({x}, {y}) event #{} ({}): {lb} wrote only {} events; the {la} goes on:",
                    a.seq, d.class, d.b.events
                )?;
                write!(f, "\n  {la:<width$} {}", event_line(p, a, d.a_at))?;
            }
            DivergenceKind::Rgb => {
                write!(
                    f,
                    "pixel ({x}, {y}) ({}): every event agrees, but the colour does not: {la} {}, {lb} {}",
                    d.class,
                    rgb_label(d.a.rgb),
                    rgb_label(d.b.rgb)
                )?;
            }
            DivergenceKind::Cycles => {
                write!(
                    f,
                    "pixel ({x}, {y}) ({}): every event and the colour agree, but not the cycle count",
                    d.class
                )?;
            }
        }
        if let DivergenceClass::ControlFlow(split) = &d.class {
            match &split.after {
                Some(after) => write!(
                    f,
                    "\n  the state sequences split at event #{}: the branch after event #{} in state {} went another way",
                    split.seq,
                    after.seq,
                    state_with_line(p, after.state)
                )?,
                None => write!(f, "\n  the state sequences split at the first event")?,
            }
            if split.seq != d.seq().unwrap_or(u32::MAX) {
                for (label, e) in [(la, &split.a), (lb, &split.b)] {
                    match e {
                        Some(e) => write!(
                            f,
                            "\n  {label:<width$} goes on with {}",
                            event_line(p, e, None)
                        )?,
                        None => write!(f, "\n  {label:<width$} had ended")?,
                    }
                }
            }
            match &split.cause {
                Some((a, _)) if Some(a.seq) == d.seq() => {
                    write!(f, "\n  caused by the values apart at the event above")?
                }
                Some((a, b)) => {
                    write!(
                        f,
                        "\n  the first value apart before it, event #{} in state {}, dst {}:",
                        a.seq,
                        state_with_line(p, a.state),
                        register_label(a.dst)
                    )?;
                    lane_lines(f, self.labels, a, b)?;
                }
                None => write!(
                    f,
                    "\n  no written value was apart before the split: the branch condition differs without a traced cause"
                )?,
            }
        }
        write!(
            f,
            "\n  cycles: {la} {}, {lb} {}; events: {la} {}, {lb} {}",
            d.a.cycles, d.b.cycles, d.a.events, d.b.events
        )
    }
}

impl fmt::Display for CompareReport {
    /// The counts, one line each (the first divergence is
    /// [`Divergence::text`]).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Labels { a: la, b: lb, .. } = &self.labels;
        let c = &self.counts;
        writeln!(
            f,
            "  events: {} compared, {} differ; {la} wrote {}, {lb} {} ({} pixels with other counts)",
            c.events_compared, c.event_mismatches, c.a_events, c.b_events, c.event_count_mismatches
        )?;
        writeln!(
            f,
            "  cycles: {la} {}, {lb} {} ({} pixels differ)",
            c.a_cycles, c.b_cycles, c.cycle_mismatches
        )?;
        writeln!(f, "  colour: {} pixels differ", c.rgb_mismatches)?;
        write!(
            f,
            "  divergent pixels: {} ({} control-flow, {} numeric drift)",
            c.divergent_pixels, c.control_flow_pixels, c.numeric_drift_pixels
        )?;
        Ok(())
    }
}

impl fmt::Display for UlpHistogram {
    /// One line per non-empty bucket: distance, lanes, share.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let total = self.total().max(1) as f64;
        let mut first = true;
        for (k, &n) in self.buckets.iter().enumerate().filter(|(_, &n)| n > 0) {
            if !first {
                writeln!(f)?;
            }
            first = false;
            write!(
                f,
                "  {:>23} ulp {n:>12} {:>7.3}%",
                UlpHistogram::bucket_label(k),
                100.0 * n as f64 / total
            )?;
        }
        Ok(())
    }
}
