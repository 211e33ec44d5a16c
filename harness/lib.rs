//! rtcosim: co-simulation of the handwritten Verilog in `rtl/` against the
//! golden models in the `golden` crate.
//!
//! - [`fp_unit`]: the separately verilated float units, driven in batches.
//! - [`operands`]: TestFloat-style edge cases and seeded random operands.
//! - [`fp_check`]: runs operands through a unit and its golden model and
//!   reports every disagreement, measured in ULPs.
//! - [`fast_alu`]: the fast processor's ALU (rtl/fast/fast_alu.v), its
//!   opcodes of interleaved contexts against golden's micro-op ALU.
//! - [`pixel_proc`]: the verilated pixel processor, one pixel per call, with
//!   its trace and fault-injection ports.
//! - [`processor`]: which pixel processor: the compact one or the fast one
//!   (rtl/fast/fast_pp.v, driven through [`top`]).
//! - [`top`]: the verilated top module (rtl/top.v), N pixel processors fed a
//!   coordinate stream, driven in batches of results and trace events.
//! - [`compare`]: the comparison engine: two event streams and two pixel
//!   outcomes per pixel, whatever produced them; verdicts and reports.
//! - [`cosim`]: the live run of the pixel processor (or the top) against the
//!   golden micro-op model, event by event, cycle for cycle, streaming.
//! - [`coverage`]: what the runs exercised of the RTL: the coverage models
//!   (cargo feature `coverage`), their counts merged into Verilator's
//!   coverage.dat, lcov, HTML and a summary.
//! - [`device`]: what a build of the processor costs in hardware
//!   (rtl/synth/costs.toml), and the frames a second of a device full of
//!   it.
//! - [`fuzz`]: random scene files, and campaigns that co-simulate them.
//! - [`scenes`]: scenes as the user names them, with size and method
//!   overrides.
//! - [`sweep`]: speed against accuracy over a grid of configurations.
//! - [`shard`]: one long run split into disjoint slices for a cluster's
//!   array job, and the checks that merge them back (docs/scale.md).
//! - [`trace_files`]: trace-file headers and writers for a window, of the
//!   golden model and of the RTL.
//! - [`trace_diff`]: two trace files through the comparison engine.
//! - [`rtl_source`]: the Verilog line that decodes each controller state.
//! - [`wave`]: the waveform window: one pixel re-run on the model verilated
//!   with `--trace-fst`, K cycles either side of a divergence, as an FST file
//!   with a GTKWave save file and state-name filter.
//! - [`tune`]: the cheapest configuration that meets an error target.

pub mod area;
pub mod artefacts;
mod bridge;
pub mod compare;
pub mod cosim;
pub mod coverage;
pub mod device;
pub mod fast_alu;
pub mod fp_check;
pub mod fp_unit;
pub mod fuzz;
pub mod mutation;
pub mod operands;
pub mod pixel_proc;
pub mod processor;
pub mod rtl_source;
pub mod scenes;
pub mod shard;
pub mod sweep;
pub mod top;
pub mod trace_diff;
pub mod trace_files;
pub mod wave;

// zlib and lz4, for Verilator's FST writer in the C++ (build.rs): named here
// so that rustc links the static libraries libz-sys and lz4-sys build.
use libz_sys as _;
use lz4_sys as _;
pub mod tune;

/// The Verilator that built the models (`verilator --version`).
pub const VERILATOR_VERSION: &str = env!("RTCOSIM_VERILATOR_VERSION");
