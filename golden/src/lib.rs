//! Golden models for rtcosim.
//!
//! Everything here is pure Rust and builds without Verilator, so anyone can
//! reproduce the numbers the RTL is held to.
//!
//! - [`fp`]: bit-exact models of the float32 units in `rtl/fp/`, and the ULP
//!   distance used to compare float results.
//! - [`trace`]: trace events (one per register-file write) and trace files.

pub mod fp;
pub mod trace;
