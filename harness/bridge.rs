//! The cxx bridge to the verilated models (C++ side in `harness/cpp/`).
//!
//! The C++ side runs the clock loop over whole batches of operands, so one FFI
//! call covers thousands of evaluations. Every model has its own
//! `VerilatedContext`; the handles are `!Send` (cxx opaque types), which keeps
//! each model on the thread that built it, as Verilator requires.

#[cxx::bridge(namespace = "rtcosim")]
pub(crate) mod ffi {
    /// The separately verilated float units (one model per unit and method).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
    enum FpModel {
        Add,
        Mul,
        Itof,
        RecipExact,
        RecipFast,
        SqrtExact,
        SqrtFast,
    }

    unsafe extern "C++" {
        include!("fp_units.h");

        /// One verilated float unit.
        type FpUnit;

        /// Builds and resets a model. Fails if the model cannot be constructed.
        fn new_fp_unit(model: FpModel) -> Result<UniquePtr<FpUnit>>;

        /// Evaluates `y[i] = unit(a[i], b[i])` for every `i`; `b` is ignored by
        /// unary units. For multi-cycle units, `cycles[i]` receives the clock
        /// edges from the one sampling `in_valid` to the one after which
        /// `out_valid` is high (0 for combinational units). Fails on slices of
        /// different lengths, on a unit that does not answer within
        /// `timeout_cycles`, or on a fatal error inside the model.
        fn eval(
            self: Pin<&mut FpUnit>,
            a: &[u32],
            b: &[u32],
            y: &mut [u32],
            cycles: &mut [u32],
            timeout_cycles: u32,
        ) -> Result<()>;
    }
}
