//! The pixel processors of `rtl/`: two microarchitectures of one ISA, held
//! to one golden model. Each is a row of facts ([`Processor`]); everything
//! outside the design layer asks the row instead of asking which processor
//! it is, so that a third processor is a third row (and its driver).
//!
//! - [`ProcessorKind::Compact`]: `rtl/pp/pixel_processor.v`, one pixel at a
//!   time, a float operation in one cycle between the register file and
//!   the next-state decision; its cycles are golden::micro's cycle rule.
//! - [`ProcessorKind::Fast`]: `rtl/fast/fast_pp.v`, 32 pixel contexts taking
//!   turns, pipelined units, one micro-op a cycle; its cycles are the
//!   barrel rule's (`golden::micro::barrel`), and it is driven through its
//!   streams; N of them through `rtl/top.v` (`FAST = 1`) follow the top's
//!   rule (`golden::micro::barrel::run_top`).

use crate::design::error::DEFAULT_TIMEOUT_CYCLES;
use crate::design::fp_unit::UnitKind;
use crate::design::models::Rtl;
use std::fmt;

// PP_CTRL_STATE_LINES and FAST_CTRL_STATE_LINES: (state name, line) of
// every item of each controller's `case` on the state, read by the build
// (build/rtl.rs).
include!(concat!(env!("OUT_DIR"), "/rtl_state_lines.rs"));

/// A pixel processor of `rtl/`, by name.
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Hash,
    Default,
    PartialOrd,
    Ord,
    clap::ValueEnum,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum ProcessorKind {
    /// rtl/pp/pixel_processor.v: one pixel at a time.
    #[default]
    Compact,
    /// rtl/fast/fast_pp.v: 32 pixels in flight, pipelined.
    Fast,
}

/// The fast processor's pixel contexts (`rtl/fast/fast_pp.v`, `CTX_BITS`
/// = 5): the barrel's K.
pub const FAST_CONTEXTS: u32 = 32;

/// How a processor alone is driven.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Driver {
    /// One pixel at a time through `start`/`done`
    /// ([`crate::design::pixel_proc::PixelProcessor`]).
    OnePixel,
    /// Through its coordinate and result streams, as a top whose slots are
    /// its contexts ([`crate::design::top::Top`]).
    Streams,
}

/// Whose cycles golden predicts for a pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CycleRule {
    /// golden::micro's own count: every cycle of the pixel, one pixel at a
    /// time (`PixelResult::cycles`).
    Micro,
    /// The barrel rule (`golden::micro::barrel`): `contexts` pixels take
    /// turns, one micro-op a turn; a frame's cycles are the rule's plus
    /// `overhead` (the streams' registers), and a top of N follows
    /// `barrel::run_top`.
    Barrel { contexts: u32, overhead: u64 },
}

/// A group of signals in the waveform window's save file: its title and
/// its signals (name under the scope, bits, radix).
pub type WaveGroup = (&'static str, &'static [(&'static str, WaveBits, Radix)]);

/// A signal's width in a save file: a number, or one of the ISA's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WaveBits {
    Bits(usize),
    /// A state (`ISA_ST_BITS`), shown through the state-name filter.
    State,
    /// A register address.
    Reg,
    /// A lane mask.
    Lanes,
    /// Three lanes of 32 bits.
    Value,
    /// A coordinate.
    Coord,
    /// An opcode.
    Op,
    /// The ray stack's pointer.
    StackPointer,
    /// A context number.
    Context,
}

/// How a save file shows a signal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Radix {
    Bin,
    Dec,
    Hex,
}

/// Where one processor's mutants are committed: the list its mutant
/// netlist is built from and its survivors' classification
/// (`rtl/mutate/<design>.mutants`, `.survivors`), as built into this
/// rtcosim, with their paths in the checkout for messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MutantFiles {
    pub processor: ProcessorKind,
    /// `mutants.sh`'s name for the design (`MUTATE_DESIGN`): the module it
    /// mutates.
    pub design: &'static str,
    pub list_path: &'static str,
    pub list_text: &'static str,
    pub survivors_path: &'static str,
    pub survivors_text: &'static str,
}

/// Everything the harness knows of one processor.
#[derive(Debug, Clone, Copy)]
pub struct Processor {
    pub kind: ProcessorKind,
    /// Its name on the command line and in reports.
    pub name: &'static str,
    /// Its top-level Verilog.
    pub rtl: &'static str,
    /// Its models in the build's table.
    pub models: Rtl,
    /// Pixel contexts in one processor.
    pub contexts: u32,
    /// How it is driven alone; in `rtl/top.v` every processor is streamed.
    pub alone: Driver,
    /// The largest N of `rtl/top.v` with it.
    pub max_procs: u32,
    /// Whether it has a build without its exponential (`EXPOSURE = 0`).
    pub exp_optional: bool,
    pub cycle_rule: CycleRule,
    /// Its controller, and the line of each state's item in its `case` on
    /// the state (read by the build): trace-diff's line map.
    pub controller: &'static str,
    pub state_lines: &'static [(&'static str, u32)],
    /// Its instance's scope in the waveform twin's FST, and the save
    /// file's signals.
    pub wave_scope: &'static str,
    pub wave_signals: &'static [WaveGroup],
    /// Its mutants.
    pub mutants: MutantFiles,
    /// The float units cut from its mutant netlist.
    pub units: [UnitKind; 8],
    /// Whether a mutant of `module` sits in the float units those cuts
    /// carry (a mutant of another module passes their checks).
    pub in_float_unit: fn(&str) -> bool,
    /// The transitions its controller cannot take beyond the table's
    /// (rtl/cover/), with their arguments.
    pub unreachable_path: &'static str,
    pub unreachable_text: &'static str,
    /// Its colour in charts (RGB).
    pub colour: (u8, u8, u8),
}

use Radix::{Bin, Dec, Hex};
use WaveBits::{Bits, Context, Coord, Lanes, Op, Reg, StackPointer, State, Value};

/// The trace port and the fault port, every processor's.
const TRACE_PORT: &[(&str, WaveBits, Radix)] = &[
    ("trace_valid", Bits(1), Bin),
    ("trace_state", State, Hex),
    ("trace_dst", Reg, Hex),
    ("trace_lanes", Lanes, Bin),
    ("trace_value", Value, Hex),
];

/// `kind`'s [`MutantFiles`], named by its `MUTATE_DESIGN`.
macro_rules! mutant_files {
    ($kind:expr, $design:literal) => {
        MutantFiles {
            processor: $kind,
            design: $design,
            list_path: concat!("rtl/mutate/", $design, ".mutants"),
            list_text: include_str!(concat!("../../rtl/mutate/", $design, ".mutants")),
            survivors_path: concat!("rtl/mutate/", $design, ".survivors"),
            survivors_text: include_str!(concat!("../../rtl/mutate/", $design, ".survivors")),
        }
    };
}

/// The rows, in [`ProcessorKind`] order.
pub const PROCESSORS: [Processor; 2] = [
    Processor {
        kind: ProcessorKind::Compact,
        name: "compact",
        rtl: "rtl/pp/pixel_processor.v",
        models: Rtl::Compact,
        contexts: 1,
        alone: Driver::OnePixel,
        max_procs: 8,
        exp_optional: false,
        cycle_rule: CycleRule::Micro,
        controller: "rtl/pp/pp_ctrl.v",
        state_lines: PP_CTRL_STATE_LINES,
        wave_scope: "TOP.pixel_processor",
        wave_signals: &[
            (
                "pixel",
                &[
                    ("clk", Bits(1), Bin),
                    ("start", Bits(1), Bin),
                    ("ready", Bits(1), Bin),
                    ("done", Bits(1), Bin),
                    ("px", Coord, Dec),
                    ("py", Coord, Dec),
                ],
            ),
            (
                "controller",
                &[
                    ("u_ctrl.st_q", State, Hex),
                    ("op", Op, Hex),
                    ("u_ctrl.sp_q", StackPointer, Dec),
                ],
            ),
            ("trace port", TRACE_PORT),
            (
                "fault port, colour",
                &[
                    ("fault_state", State, Hex),
                    ("fault_xor", Bits(32), Hex),
                    ("rgb", Value, Hex),
                ],
            ),
        ],
        mutants: mutant_files!(ProcessorKind::Compact, "pixel_processor"),
        units: UnitKind::ALL,
        in_float_unit: |module| module.starts_with("fp_"),
        unreachable_path: "rtl/cover/pp_ctrl.unreachable",
        unreachable_text: include_str!("../../rtl/cover/pp_ctrl.unreachable"),
        colour: (150, 150, 150),
    },
    Processor {
        kind: ProcessorKind::Fast,
        name: "fast",
        rtl: "rtl/fast/fast_pp.v",
        models: Rtl::Fast,
        contexts: FAST_CONTEXTS,
        alone: Driver::Streams,
        max_procs: 64,
        exp_optional: true,
        // One cycle into the coordinate queue, two of the register file's
        // read, one into the result queue.
        cycle_rule: CycleRule::Barrel {
            contexts: FAST_CONTEXTS,
            overhead: 4,
        },
        controller: "rtl/fast/fast_ctrl.v",
        state_lines: FAST_CTRL_STATE_LINES,
        wave_scope: "TOP.fast_pp",
        wave_signals: &[
            (
                "streams",
                &[
                    ("clk", Bits(1), Bin),
                    ("in_valid", Bits(1), Bin),
                    ("in_ready", Bits(1), Bin),
                    ("in_x", Coord, Dec),
                    ("in_y", Coord, Dec),
                    ("out_valid", Bits(1), Bin),
                    ("out_ready", Bits(1), Bin),
                    ("out_x", Coord, Dec),
                    ("out_y", Coord, Dec),
                    ("out_ctx", Context, Dec),
                ],
            ),
            (
                "controller: the turn",
                &[
                    ("turn_ctx", Context, Dec),
                    ("take", Bits(1), Bin),
                    ("issue", Bits(1), Bin),
                    ("done", Bits(1), Bin),
                    ("state", State, Hex),
                    ("op", Op, Hex),
                ],
            ),
            (
                "trace port",
                &[
                    ("trace_valid", Bits(1), Bin),
                    ("trace_ctx", Context, Dec),
                    ("trace_state", State, Hex),
                    ("trace_dst", Reg, Hex),
                    ("trace_lanes", Lanes, Bin),
                    ("trace_value", Value, Hex),
                ],
            ),
            (
                "fault port, colour",
                &[
                    ("fault_state", State, Hex),
                    ("fault_xor", Bits(32), Hex),
                    ("out_rgb", Value, Hex),
                ],
            ),
        ],
        mutants: mutant_files!(ProcessorKind::Fast, "fast_pp"),
        units: UnitKind::PIPELINED,
        // Its own units, the fp_* they share and the fast_delays their
        // pipelines are built of (some of which are the controller's).
        in_float_unit: |module| {
            module.starts_with("fp_") || module.starts_with("fast_fp_") || module == "fast_delay"
        },
        unreachable_path: "rtl/cover/fast_ctrl.unreachable",
        unreachable_text: include_str!("../../rtl/cover/fast_ctrl.unreachable"),
        colour: (40, 170, 170),
    },
];

impl Processor {
    /// Cycles a pixel may take before the RTL counts as hung, unless told
    /// otherwise: [`DEFAULT_TIMEOUT_CYCLES`] for each of the processor's
    /// contexts, since its contexts take turns (a pixel of the fast
    /// processor gets one micro-op in 32 cycles when all are busy).
    pub fn default_timeout_cycles(&self) -> u64 {
        DEFAULT_TIMEOUT_CYCLES * u64::from(self.contexts)
    }
}

impl ProcessorKind {
    /// Every processor, in row order.
    pub const ALL: [ProcessorKind; 2] = [ProcessorKind::Compact, ProcessorKind::Fast];

    /// Its row of facts.
    pub fn row(self) -> &'static Processor {
        &PROCESSORS[self as usize]
    }

    /// Its name on the command line and in reports.
    pub fn name(self) -> &'static str {
        self.row().name
    }

    /// Its top-level Verilog.
    pub fn rtl(self) -> &'static str {
        self.row().rtl
    }
}

impl fmt::Display for ProcessorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_row_is_its_kinds() {
        for kind in ProcessorKind::ALL {
            assert_eq!(kind.row().kind, kind);
            assert_eq!(
                <ProcessorKind as clap::ValueEnum>::to_possible_value(&kind)
                    .unwrap()
                    .get_name(),
                kind.name()
            );
        }
    }
}
