//! Which pixel processor the RTL runs: the two microarchitectures of the
//! same ISA, held to the same golden model.
//!
//! - [`ProcessorKind::Compact`]: `rtl/pp/pixel_processor.v`, one pixel at a
//!   time, a float operation in one cycle between the register file and
//!   the next-state decision; its cycles are golden::micro's cycle rule.
//! - [`ProcessorKind::Fast`]: `rtl/fast/fast_pp.v`, 32 pixel contexts taking
//!   turns, pipelined units, one micro-op a cycle; its cycles are the
//!   barrel rule's (`golden::micro::barrel`), and it is driven through its
//!   streams as a top of 32 contexts ([`crate::top::Top::new_fast`]); N of
//!   them through `rtl/top.v` (`FAST = 1`) follow the top's rule
//!   (`golden::micro::barrel::run_top`, [`crate::top::Top::new_fast_procs`]).

use std::fmt;

/// A pixel processor of `rtl/`.
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Hash,
    Default,
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

impl ProcessorKind {
    /// Its name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            ProcessorKind::Compact => "compact",
            ProcessorKind::Fast => "fast",
        }
    }

    /// Its top-level Verilog.
    pub fn rtl(self) -> &'static str {
        match self {
            ProcessorKind::Compact => "rtl/pp/pixel_processor.v",
            ProcessorKind::Fast => "rtl/fast/fast_pp.v",
        }
    }
}

impl fmt::Display for ProcessorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
