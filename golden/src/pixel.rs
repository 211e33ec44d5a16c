//! What a pixel came to, on any side of a comparison.

/// One pixel's result as the hardware reports it: the colour bits, the
/// cycles it took and the register-file writes (trace events) it made. The
/// RTL, the micro-op model and a trace file all give one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PixelOutcome {
    /// Raw f32 bits, lanes r, g, b.
    pub rgb: [u32; 3],
    /// Cycles from the start edge to done inclusive.
    pub cycles: u64,
    /// Trace events (register-file writes).
    pub events: u64,
}

impl From<&crate::micro::PixelResult> for PixelOutcome {
    fn from(r: &crate::micro::PixelResult) -> PixelOutcome {
        PixelOutcome {
            rgb: r.rgb.map(f32::to_bits),
            cycles: r.cycles,
            events: r.ops.register_writes,
        }
    }
}
