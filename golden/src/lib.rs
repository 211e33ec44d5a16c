//! Golden models for rtcosim.
//!
//! Everything here is pure Rust and builds without Verilator, so anyone can
//! reproduce the numbers the RTL is held to.
//!
//! - [`fp`]: bit-exact models of the float32 units in `rtl/fp/`, and the ULP
//!   distance used to compare float results.
//! - [`scene`]: scene files (TOML), their validation, and the constants
//!   derived from them once for every model.
//! - [`reference`](mod@reference): the f64 reference renderer, ground truth for accuracy.
//! - [`frame`]: rendered frames: PNG output, lossless frame files (OpenEXR)
//!   and frame-to-frame comparison.
//! - [`diffmap`]: where two frames differ: heat maps, the thesis' masks
//!   (figure 17) and its table of differences.
//! - [`trace`]: trace events (one per register-file write) and trace files.
//! - [`pixel`]: a pixel's outcome (colour bits, cycles, events), on any side.
//! - [`window`]: a rectangle of pixels, parsed from and written as corners.
//! - [`micro`]: the f32 micro-op model of the RTL pixel processor, one ALU
//!   instruction per line, with its ISA generated from `rtl/pp/isa.vh`.

pub mod diffmap;
pub mod fp;
pub mod frame;
pub mod micro;
pub mod pixel;
pub mod reference;
pub mod scene;
pub mod stability;
pub mod trace;
pub mod window;
