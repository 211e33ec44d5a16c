//! The fast processor's ALU (`rtl/fast/fast_alu.v`) verilated alone, driven
//! one cycle's inputs at a time from a list (`crate::check::alu_check`
//! builds the lists and checks the results against golden's micro-op ALU).
//!
//! # The cycle contract
//!
//! An opcode enters in the cycle its inputs are set with `in_valid` (the
//! rising edge ending that cycle takes it). Its result shows on the output
//! port, `out_valid` high, exactly [`fast_latency`] cycles later, whatever
//! the opcode: results leave in the order their opcodes entered. The ALU
//! keeps F per context; its contract with whoever issues (the barrel's
//! rule, docs/fast.md):
//!
//! * a context's next opcode enters no earlier than the cycle its last
//!   one's result shows;
//! * EXP enters only while `exp_ready` is high, i.e. not within two cycles
//!   of another EXP (one `fp_exp` is shared by the three lanes).
//!
//! A context's opcodes keep the contract only if the list does:
//! `crate::check::alu_check::Schedule` keeps it (or breaks it on purpose
//! for the checker's own tests).

use crate::design::bridge::ffi;
use cxx::UniquePtr;
use golden::fp::Method;
use golden::micro::alu::fast_latency;

pub use ffi::{AluIn, AluOut};

/// What went wrong building or running the verilated ALU.
#[derive(Debug, thiserror::Error)]
pub enum AluError {
    /// No model of this variant is in this build (harness/design/models.rs).
    #[error(
        "no fast ALU model for recip {recip:?}, sqrt {sqrt:?}, exposure {exposure}: {message}"
    )]
    Build {
        recip: Method,
        sqrt: Method,
        exposure: bool,
        message: String,
    },
    /// The model stopped (`$stop`, `$fatal`) or the driver refused.
    #[error("fast ALU model: {0}")]
    Model(String),
}

/// A verilated fast ALU.
pub struct FastAlu {
    inner: UniquePtr<ffi::FastAlu>,
    recip: Method,
    sqrt: Method,
    exposure: bool,
}

impl FastAlu {
    /// The variant verilated with these methods and exposure, reset.
    pub fn new(recip: Method, sqrt: Method, exposure: bool) -> Result<FastAlu, AluError> {
        let build = |message: String| AluError::Build {
            recip,
            sqrt,
            exposure,
            message,
        };
        let class = crate::design::models::fast_alu_class(recip.name(), sqrt.name(), exposure);
        crate::design::built::require(&class).map_err(build)?;
        let inner = ffi::new_fast_alu(&class).map_err(|e| build(e.what().to_string()))?;
        Ok(FastAlu {
            inner,
            recip,
            sqrt,
            exposure,
        })
    }

    /// The methods and exposure it was built with.
    pub fn build(&self) -> (Method, Method, bool) {
        (self.recip, self.sqrt, self.exposure)
    }

    /// Cycles from an opcode entering to its result showing.
    pub fn latency(&self) -> u32 {
        fast_latency(self.exposure)
    }

    /// Resets the model and drives `cycles` (one cycle's inputs each) from
    /// cycle 0, then as many idle cycles as the last result needs to show.
    pub fn run(&mut self, cycles: &[AluIn]) -> Result<Ran, AluError> {
        let drain = self.latency() + 1;
        self.inner.pin_mut().reset();
        let mut out = Vec::new();
        let mut exp_ready = Vec::new();
        self.inner
            .pin_mut()
            .run(cycles, drain, &mut out, &mut exp_ready)
            .map_err(|e| AluError::Model(e.what().to_string()))?;
        Ok(Ran { out, exp_ready })
    }
}

/// What the port showed over a run.
#[derive(Debug, Clone, Default)]
pub struct Ran {
    /// Every cycle with out_valid high, in order.
    pub out: Vec<AluOut>,
    /// exp_ready in each cycle of the schedule.
    pub exp_ready: Vec<bool>,
}
