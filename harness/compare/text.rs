//! The comparison in words: a divergence with both sides' values and the
//! golden source line, and a report's counts.

use super::{lane_distance, CompareReport, Divergence, DivergenceKind, Labels, UlpHistogram};
use golden::micro::isa::{lanes_label, register_label, state_label};
use std::fmt;

fn value_label(bits: u32) -> String {
    format!("{bits:#010x} ({:e})", f32::from_bits(bits))
}

fn rgb_label(rgb: [u32; 3]) -> String {
    let [r, g, b] = rgb.map(value_label);
    format!("[{r}, {g}, {b}]")
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

impl fmt::Display for DivergenceText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Labels { a: la, b: lb } = self.labels;
        let d = self.d;
        let (x, y) = (d.x, d.y);
        let source = |f: &mut fmt::Formatter<'_>, at: &Option<super::SourceLine>| match at {
            Some(at) => write!(f, "\n  {lb} source: {}:{}", at.file(), at.line()),
            None => Ok(()),
        };
        match &d.kind {
            DivergenceKind::Event { a, b, at } => {
                write!(
                    f,
                    "pixel ({x}, {y}) event #{}: {la} state {} vs {lb} {}, dst {} vs {}, lanes {} vs {}",
                    b.seq,
                    state_label(a.state),
                    state_label(b.state),
                    register_label(a.dst),
                    register_label(b.dst),
                    lanes_label(a.lanes),
                    lanes_label(b.lanes),
                )?;
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
                        "\n  lane {}: {la} {}, {lb} {}",
                        ['x', 'y', 'z'][i],
                        side(wa, a.values[i]),
                        side(wb, b.values[i])
                    )?;
                    if let Some(dist) = lane_distance(a, b, i) {
                        write!(f, ": {dist}")?;
                    }
                }
                source(f, at)?;
            }
            DivergenceKind::MissingEvent { b, at } => {
                write!(
                    f,
                    "pixel ({x}, {y}) event #{}: the {la} wrote only {} events; {lb} goes on with state {}, dst {}",
                    b.seq,
                    d.a.events,
                    state_label(b.state),
                    register_label(b.dst),
                )?;
                source(f, at)?;
            }
            DivergenceKind::ExtraEvent { a } => {
                write!(
                    f,
                    "pixel ({x}, {y}) event #{}: {lb} wrote only {} events; the {la} goes on with state {}, dst {}",
                    a.seq,
                    d.b.events,
                    state_label(a.state),
                    register_label(a.dst),
                )?;
            }
            DivergenceKind::Rgb => {
                write!(
                    f,
                    "pixel ({x}, {y}): every event agrees, but the colour does not: {la} {}, {lb} {}",
                    rgb_label(d.a.rgb),
                    rgb_label(d.b.rgb)
                )?;
            }
            DivergenceKind::Cycles => {
                write!(
                    f,
                    "pixel ({x}, {y}): every event and the colour agree, but not the cycle count"
                )?;
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
    /// The counts, one line each, and the first divergence.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Labels { a: la, b: lb } = &self.labels;
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
        write!(f, "  divergent pixels: {}", c.divergent_pixels)?;
        if let Some(d) = &self.first_divergence {
            write!(f, "\nfirst divergence: {}", d.text(&self.labels))?;
        }
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
                "  {:>15} ulp {n:>12} {:>7.3}%",
                UlpHistogram::bucket_label(k),
                100.0 * n as f64 / total
            )?;
        }
        Ok(())
    }
}
