//! rtcosim: co-simulation of the handwritten Verilog in `rtl/` against the
//! golden models in the `golden` crate.
//!
//! The library is four layers, each importing only from those above it in
//! this list (and from `golden`):
//!
//! - [`design`]: the designs under test. A [`design::Design`] names one
//!   verilated build (processor, float methods, exponential unit,
//!   processors in the top, flavour); [`design::Design::open`] builds its
//!   driver, a [`design::Dut`], which loads a scene, streams pixels into a
//!   sink of results and trace events, takes a fault and a watchdog. The
//!   facts of each processor (its RTL, controller, wave scope, mutant
//!   list, cycle rule) are one row of [`design::processor`]; the
//!   verilated models are one table ([`design::models`]) that the build
//!   script builds from. The cxx bridge and the C++ drivers live here.
//! - [`check`]: holding a design to golden. The comparison engine
//!   ([`check::compare`]), the live co-simulation ([`check::cosim`]), the
//!   float units alone ([`check::fp_check`], [`check::operands`]), trace
//!   files and `trace-diff`.
//! - [`campaign`]: many runs: random scenes ([`campaign::fuzz`]),
//!   mutation testing ([`campaign::mutation`]), speed against accuracy
//!   ([`campaign::sweep`], [`campaign::tune`]), and shards of any of them
//!   for a cluster's array job ([`campaign::shard`]).
//! - [`output`]: what runs leave behind: frames, maps and reports
//!   ([`output::artefacts`]), waveform windows ([`output::wave`]),
//!   coverage ([`output::coverage`]), and the hardware cost of a build
//!   ([`output::device`], [`output::area`]).
//!
//! [`scenes`] turns what the user names (`--scene`, `--size`, methods)
//! into a scene for any layer.

pub mod campaign;
pub mod check;
pub mod design;
pub mod output;
pub mod scenes;

// zlib and lz4, for Verilator's FST writer in the C++ (build/main.rs): named
// here so that rustc links the static libraries libz-sys and lz4-sys build.
use libz_sys as _;
use lz4_sys as _;

/// The Verilator that built the models (`verilator --version`).
pub const VERILATOR_VERSION: &str = env!("RTCOSIM_VERILATOR_VERSION");
