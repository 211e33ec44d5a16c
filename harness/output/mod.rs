//! What runs leave behind.
//!
//! - [`artefacts`]: a co-simulation's frames, difference maps, JSON,
//!   Markdown and JUnit reports.
//! - [`wave`]: the waveform window: a divergence re-run on the design's
//!   `--trace-fst` twin, K cycles either side, as an FST file with a
//!   GTKWave save file and state-name filter.
//! - [`coverage`]: what the runs exercised of the RTL: the coverage
//!   models' counts merged into Verilator's coverage.dat, lcov, HTML and
//!   a summary.
//! - [`chart`]: charts as SVG and PNG, their labels in both.
//! - [`device`]: what a build costs in hardware (rtl/synth/costs.toml),
//!   and the frames a second of a device full of it; [`area`]: the area
//!   model behind it.

pub mod area;
pub mod artefacts;
pub mod chart;
pub mod coverage;
pub mod device;
pub mod wave;
