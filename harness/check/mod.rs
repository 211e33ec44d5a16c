//! Holding a design under test to golden: the comparison engine, the live
//! co-simulation, the float units alone, trace files and trace-diff.
//!
//! - [`compare`]: two event streams and two pixel outcomes per pixel,
//!   whatever produced them; verdicts and reports.
//! - [`cosim`]: a design against the golden micro-op model, event by
//!   event, cycle for cycle, streaming.
//! - [`alu_check`]: the fast processor's ALU alone, seeded schedules of
//!   interleaved contexts' opcodes against golden's ALU.
//! - [`fp_check`]: operands through a float unit and its golden model,
//!   every disagreement measured in ULPs; [`operands`]: TestFloat-style
//!   edge cases and seeded random operands.
//! - [`trace_files`]: trace-file headers and writers for a window, of the
//!   golden model and of the RTL; [`trace_diff`]: two trace files through
//!   the comparison engine.

pub mod alu_check;
pub mod compare;
pub mod cosim;
pub mod fp_check;
pub mod operands;
pub mod trace_diff;
pub mod trace_files;
