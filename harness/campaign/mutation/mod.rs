//! Mutation testing, MCY-style: how many small faults planted in the RTL
//! would our checks notice (docs/mutation.md)?
//!
//! - The mutants: `rtl/mutate/pixel_processor.mutants` (the compact
//!   processor) and `rtl/mutate/fast_pp.mutants` (the fast one), each
//!   sampled over every module of its processor by Yosys' `mutate -list`
//!   (through `rtl/mutate/mutants.sh list`), numbered from 1, with the hash
//!   of the RTL they were listed on ([`List`], [`Files`]).
//! - The build: with the cargo feature `mutation`, the build script has
//!   `mutants.sh netlist` write one netlist per processor carrying every
//!   mutant behind the input `mutsel` and verilates each once;
//!   [`mutant_design`] opens it and `Dut::set_mutant` selects one (0: the
//!   design as written).
//! - The judge ([`Judge`]): a fixed list of checks, each a co-simulation of
//!   a scene against golden's micro-op model, bit for bit and cycle for
//!   cycle ([`cosim::run_on`], the cycles its processor's rule's): every builtin
//!   scene at a small size, the directed scenes, then seeded fuzz scenes,
//!   all with the exact methods the netlist has; and, for a mutant of the
//!   compact processor's float units, those units cut from its netlist on
//!   their edge cases and random operands. A mutant is killed by the first
//!   check that diverges or errs (a hang counts), and survives if none
//!   does.
//! - [`run`] judges mutants in parallel on the current rayon pool, a fresh
//!   model per mutant (nothing a previous mutant left in the register file
//!   can matter); its [`Summary`] merges across shards like a fuzz
//!   campaign's ([`crate::campaign::shard`]).
//! - [`prove_equivalent`] runs `mutants.sh equiv`: Yosys proves a
//!   survivor's module equal to the original, or fails to.
//!
//! By concern: [`list`] (the list and the classification), [`judge`] (the
//! checks and the verdicts), [`equiv`] (Yosys' proof), [`report`] (a
//! campaign's summary and report).

use crate::campaign::fuzz::generate;
use crate::campaign::shard::Shard;
use crate::check::cosim::{self, CosimOptions};
use crate::check::fp_check;
use crate::check::operands;
use crate::design::fp_unit::{FpUnit, UnitKind};
use crate::design::pixel_proc::PixelProcessor;
use crate::design::processor::{Driver, ProcessorKind};
use crate::design::top::Stall;
use crate::design::{Design, Flavour, PpError};
use crate::scenes::with_methods;
use golden::fp::Method;
use golden::scene::Scene;
use golden::window::Window;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

pub use crate::design::processor::MutantFiles as Files;

impl Files {
    /// `processor`'s files (its row's).
    pub fn of(processor: ProcessorKind) -> Files {
        processor.row().mutants
    }
}

/// The script that lists mutants, writes the netlist and proves survivors
/// equivalent.
pub fn script() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("rtl/mutate/mutants.sh")
}

/// The tool name in shard files.
pub const TOOL: &str = "mutate";

/// Whether this build carries the mutant netlist (cargo feature `mutation`).
pub const BUILT: bool = cfg!(feature = "mutation");

mod equiv;
mod judge;
mod list;
mod report;
#[cfg(test)]
mod tests;

pub use equiv::*;
pub use judge::*;
pub use list::*;
pub use report::*;
