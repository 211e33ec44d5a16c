//! The designs under test, and the one door through which every tool
//! drives them.
//!
//! A [`Design`] names one verilated build: which processor (a row of
//! facts, [`processor::Processor`]), its float methods, whether it has
//! its exponential unit, how many processors sit in `rtl/top.v` (none:
//! the processor alone), and the flavour of the model (plain, waveform,
//! coverage, mutant, synthesized netlist; [`Flavour`]). Its
//! [`Design::open`] gives a [`Dut`]: load a scene, stream pixels into a
//! sink of results and trace events ([`TopPixel`]), inject a fault, set
//! the watchdog. What a design cannot be is said once, by
//! [`Design::refusal`], and a design this build lacks is refused with the
//! cargo feature that builds it ([`Design::check`]).
//!
//! - [`models`]: the table of verilated models, shared with the build
//!   script.
//! - [`processor`]: the processors' rows.
//! - [`pixel_proc`], [`top`]: the two drivers (one pixel at a time;
//!   streams), and [`fast_alu`], [`fp_unit`]: the units verilated alone.
//! - [`rtl_source`]: the Verilog line that decodes each controller state.
//! - `built`: which models of the table this build made.
//! - [`counts`]: where coverage models write their counts.
//! - `bridge`: the cxx bridge to the C++ drivers (`harness/design/cpp/`).

pub(crate) mod bridge;
mod built;
pub mod counts;
mod dut;
mod error;
pub mod fast_alu;
pub mod fp_unit;
pub mod models;
pub mod pixel_proc;
pub mod processor;
pub mod rtl_source;
mod spec;
pub mod top;

pub use dut::Dut;
pub use error::{
    parse_number, scene_port_writes, Fault, HangKind, PpError, ProcessorId, SlotLayout,
    DEFAULT_TIMEOUT_CYCLES,
};
pub use models::Flavour;
pub use spec::Design;
