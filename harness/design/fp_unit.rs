//! The float units of `rtl/fp/` (the compact processor's) and the
//! pipelined ones of `rtl/fast/` (the fast processor's), each verilated on
//! its own.

use crate::design::bridge::ffi;
use cxx::UniquePtr;
use golden::fp::Method;

/// A float unit of `rtl/fp/`, with the method for the multi-cycle ones.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum UnitKind {
    /// `fp_add`: `y = a + b`, combinational.
    Add,
    /// `fp_mul`: `y = a * b`, combinational.
    Mul,
    /// `fp_itof`: `y = a as i32 as f32`, combinational.
    Itof,
    /// `fp_recip`: `y = 1 / a`, multi-cycle.
    Recip(Method),
    /// `fp_sqrt`: `y = sqrt(a)`, multi-cycle.
    Sqrt(Method),
    /// `fp_exp`: `y = e^a`, multi-cycle, one method (within 1 ULP).
    Exp,
    /// `fast_fp_add`: [`UnitKind::Add`] pipelined (`rtl/fast/`).
    FastAdd,
    /// `fast_fp_mul`: [`UnitKind::Mul`] pipelined (`rtl/fast/`).
    FastMul,
    /// `fast_fp_itof`: [`UnitKind::Itof`] pipelined (`rtl/fast/`).
    FastItof,
    /// `fast_fp_recip`: [`UnitKind::Recip`] pipelined (`rtl/fast/`).
    FastRecip(Method),
    /// `fast_fp_sqrt`: [`UnitKind::Sqrt`] pipelined (`rtl/fast/`).
    FastSqrt(Method),
    /// `fast_fp_exp`: [`UnitKind::Exp`] pipelined (`rtl/fast/`).
    FastExp,
}

impl UnitKind {
    /// Every unit and method of `rtl/fp/`, in table order (the mutant
    /// netlist cuts these).
    pub const ALL: [UnitKind; 8] = [
        UnitKind::Add,
        UnitKind::Mul,
        UnitKind::Itof,
        UnitKind::Recip(Method::Exact),
        UnitKind::Recip(Method::Fast),
        UnitKind::Sqrt(Method::Exact),
        UnitKind::Sqrt(Method::Fast),
        UnitKind::Exp,
    ];

    /// The pipelined units of `rtl/fast/`, in table order.
    pub const PIPELINED: [UnitKind; 8] = [
        UnitKind::FastAdd,
        UnitKind::FastMul,
        UnitKind::FastItof,
        UnitKind::FastRecip(Method::Exact),
        UnitKind::FastRecip(Method::Fast),
        UnitKind::FastSqrt(Method::Exact),
        UnitKind::FastSqrt(Method::Fast),
        UnitKind::FastExp,
    ];

    /// Every unit that is verilated: [`UnitKind::ALL`], then
    /// [`UnitKind::PIPELINED`].
    pub fn every() -> impl Iterator<Item = UnitKind> {
        UnitKind::ALL.into_iter().chain(UnitKind::PIPELINED)
    }

    /// The unit of `rtl/fp/` with the same arithmetic: a pipelined unit's
    /// results are its results bit for bit; itself for the others.
    pub const fn arithmetic(self) -> UnitKind {
        match self {
            UnitKind::FastAdd => UnitKind::Add,
            UnitKind::FastMul => UnitKind::Mul,
            UnitKind::FastItof => UnitKind::Itof,
            UnitKind::FastRecip(m) => UnitKind::Recip(m),
            UnitKind::FastSqrt(m) => UnitKind::Sqrt(m),
            UnitKind::FastExp => UnitKind::Exp,
            other => other,
        }
    }

    /// Whether the unit is pipelined: no handshake, an operation entering
    /// every cycle, each result [`UnitKind::latency`] edges after it.
    pub const fn is_pipelined(self) -> bool {
        matches!(
            self,
            UnitKind::FastAdd
                | UnitKind::FastMul
                | UnitKind::FastItof
                | UnitKind::FastRecip(_)
                | UnitKind::FastSqrt(_)
                | UnitKind::FastExp
        )
    }

    /// The Verilog module.
    pub const fn module(self) -> &'static str {
        match self {
            UnitKind::Add => "fp_add",
            UnitKind::Mul => "fp_mul",
            UnitKind::Itof => "fp_itof",
            UnitKind::Recip(_) => "fp_recip",
            UnitKind::Sqrt(_) => "fp_sqrt",
            UnitKind::Exp => "fp_exp",
            UnitKind::FastAdd => "fast_fp_add",
            UnitKind::FastMul => "fast_fp_mul",
            UnitKind::FastItof => "fast_fp_itof",
            UnitKind::FastRecip(_) => "fast_fp_recip",
            UnitKind::FastSqrt(_) => "fast_fp_sqrt",
            UnitKind::FastExp => "fast_fp_exp",
        }
    }

    /// The method of a multi-cycle unit; `None` for the combinational ones,
    /// which are always correctly rounded, and for `fp_exp`, which has one.
    pub const fn method(self) -> Option<Method> {
        match self {
            UnitKind::Recip(m)
            | UnitKind::Sqrt(m)
            | UnitKind::FastRecip(m)
            | UnitKind::FastSqrt(m) => Some(m),
            _ => None,
        }
    }

    /// Whether the unit reads operand `b`.
    pub const fn is_binary(self) -> bool {
        matches!(self.arithmetic(), UnitKind::Add | UnitKind::Mul)
    }

    /// Clock edges from `in_valid` to `out_valid` that the golden model
    /// promises, or from the operands to the result of a pipelined unit; 0
    /// for combinational units.
    pub const fn latency(self) -> u32 {
        match self {
            UnitKind::Recip(m) => golden::fp::recip_latency(m),
            UnitKind::Sqrt(m) => golden::fp::sqrt_latency(m),
            UnitKind::Exp => golden::fp::exp_latency(),
            UnitKind::FastAdd => golden::fp::pipelined::ADD_LATENCY,
            UnitKind::FastMul => golden::fp::pipelined::MUL_LATENCY,
            UnitKind::FastItof => golden::fp::pipelined::ITOF_LATENCY,
            UnitKind::FastRecip(_) => golden::fp::pipelined::RECIP_LATENCY,
            UnitKind::FastSqrt(_) => golden::fp::pipelined::SQRT_LATENCY,
            UnitKind::FastExp => golden::fp::pipelined::EXP_LATENCY,
            _ => 0,
        }
    }

    /// What the golden model says the unit returns for `(a, b)`, as raw bits.
    pub fn golden(self, a: u32, b: u32) -> u32 {
        use golden::fp;
        let (fa, fb) = (f32::from_bits(a), f32::from_bits(b));
        match self.arithmetic() {
            UnitKind::Itof | UnitKind::FastItof => fp::itof(a as i32).to_bits(),
            UnitKind::Recip(m) | UnitKind::FastRecip(m) => fp::recip(fa, m).to_bits(),
            UnitKind::Sqrt(m) | UnitKind::FastSqrt(m) => fp::sqrt(fa, m).to_bits(),
            UnitKind::Exp | UnitKind::FastExp => fp::exp(fa).to_bits(),
            // arithmetic() is never a pipelined unit.
            UnitKind::Add | UnitKind::FastAdd => fp::add(fa, fb).to_bits(),
            UnitKind::Mul | UnitKind::FastMul => fp::mul(fa, fb).to_bits(),
        }
    }

    /// The correctly rounded result (the truth that error is measured
    /// against; for `fp_exp`, f64 `exp` rounded to f32).
    pub fn correctly_rounded(self, a: u32, b: u32) -> u32 {
        match self.arithmetic() {
            UnitKind::Recip(_) => UnitKind::Recip(Method::Exact).golden(a, b),
            UnitKind::Sqrt(_) => UnitKind::Sqrt(Method::Exact).golden(a, b),
            UnitKind::Exp => golden::fp::exp_reference(f32::from_bits(a)).to_bits(),
            other => other.golden(a, b),
        }
    }

    /// Its class in the model table (`Vfp_recip_exact`).
    pub fn class(self) -> String {
        crate::design::models::unit_class(self.module(), self.method().map(Method::name))
    }

    fn model(self) -> ffi::FpModel {
        match self {
            UnitKind::Add => ffi::FpModel::Add,
            UnitKind::Mul => ffi::FpModel::Mul,
            UnitKind::Itof => ffi::FpModel::Itof,
            UnitKind::Recip(Method::Exact) => ffi::FpModel::RecipExact,
            UnitKind::Recip(Method::Fast) => ffi::FpModel::RecipFast,
            UnitKind::Sqrt(Method::Exact) => ffi::FpModel::SqrtExact,
            UnitKind::Sqrt(Method::Fast) => ffi::FpModel::SqrtFast,
            UnitKind::Exp => ffi::FpModel::Exp,
            UnitKind::FastAdd => ffi::FpModel::FastAdd,
            UnitKind::FastMul => ffi::FpModel::FastMul,
            UnitKind::FastItof => ffi::FpModel::FastItof,
            UnitKind::FastRecip(Method::Exact) => ffi::FpModel::FastRecipExact,
            UnitKind::FastRecip(Method::Fast) => ffi::FpModel::FastRecipFast,
            UnitKind::FastSqrt(Method::Exact) => ffi::FpModel::FastSqrtExact,
            UnitKind::FastSqrt(Method::Fast) => ffi::FpModel::FastSqrtFast,
            UnitKind::FastExp => ffi::FpModel::FastExp,
        }
    }
}

impl std::fmt::Display for UnitKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.method() {
            Some(m) => write!(f, "{}({m})", self.module()),
            None => f.write_str(self.module()),
        }
    }
}

/// Errors from a verilated unit.
#[derive(Debug, thiserror::Error)]
pub enum UnitError {
    /// The model could not be built.
    #[error("cannot build the verilated {unit}: {message}")]
    Build { unit: UnitKind, message: String },
    /// The model failed while evaluating: a hang, a fatal error inside the
    /// model, or bad slices.
    #[error("verilated {unit} failed: {message}")]
    Eval { unit: UnitKind, message: String },
}

/// One verilated float unit with its own `VerilatedContext`. Not `Send`: a
/// model stays on the thread that built it.
pub struct FpUnit {
    kind: UnitKind,
    inner: UniquePtr<ffi::FpUnit>,
    poisoned: bool,
}

/// Clock edges a multi-cycle unit may take before it counts as hung.
pub const DEFAULT_TIMEOUT_CYCLES: u32 = 1000;

impl FpUnit {
    /// Builds and resets the verilated model of `kind`.
    pub fn new(kind: UnitKind) -> Result<FpUnit, UnitError> {
        if kind.is_pipelined() {
            // Each result is read the promised number of edges after its
            // operands: a unit that takes more or fewer mismatches.
            return Self::new_pipelined(kind, kind.latency());
        }
        Self::require(kind)?;
        Self::wrap(kind, ffi::new_fp_unit(kind.model()))
    }

    /// Refuses a unit this build did not verilate, with the features that
    /// do.
    fn require(kind: UnitKind) -> Result<(), UnitError> {
        crate::design::built::require(&kind.class()).map_err(|message| UnitError::Build {
            unit: kind,
            message,
        })
    }

    /// A pipelined unit read `latency` edges after each operation enters;
    /// [`FpUnit::new`] reads it at [`UnitKind::latency`]. Another latency is
    /// the checker's self-test. An error for a unit that is not pipelined.
    pub fn new_pipelined(kind: UnitKind, latency: u32) -> Result<FpUnit, UnitError> {
        Self::require(kind)?;
        Self::wrap(kind, ffi::new_fp_unit_pipelined(kind.model(), latency))
    }

    /// The unit as cut from its processor's mutant netlist (cargo feature
    /// `mutation`; the exact methods only), with mutant `id` selected (0:
    /// the design as written), for mutation testing; a pipelined one is
    /// read at its [`UnitKind::latency`].
    pub fn new_mutant(kind: UnitKind, id: u16) -> Result<FpUnit, UnitError> {
        crate::design::built::require(&crate::design::models::mutant_unit_class(kind.module()))
            .map_err(|message| UnitError::Build {
                unit: kind,
                message,
            })?;
        Self::wrap(kind, ffi::new_fp_unit_mut(kind.model(), id, kind.latency()))
    }

    fn wrap(
        kind: UnitKind,
        made: Result<UniquePtr<ffi::FpUnit>, cxx::Exception>,
    ) -> Result<FpUnit, UnitError> {
        let inner = made.map_err(|e| UnitError::Build {
            unit: kind,
            message: e.what().to_string(),
        })?;
        Ok(FpUnit {
            kind,
            inner,
            poisoned: false,
        })
    }

    /// Which unit this is.
    pub fn kind(&self) -> UnitKind {
        self.kind
    }

    /// Evaluates the unit on every operand: `y[i] = unit(a[i], b[i])` (an empty
    /// `b` for unary units). Returns the results and, per operand, the clock
    /// edges the unit took (all 0 for combinational units).
    ///
    /// After an error the model's state is unknown, so later calls fail too.
    pub fn eval(&mut self, a: &[u32], b: &[u32]) -> Result<(Vec<u32>, Vec<u32>), UnitError> {
        self.eval_with_timeout(a, b, DEFAULT_TIMEOUT_CYCLES)
    }

    /// [`FpUnit::eval`], with a multi-cycle unit counting as hung when it has
    /// not raised `out_valid` after `timeout_cycles` clock edges.
    pub fn eval_with_timeout(
        &mut self,
        a: &[u32],
        b: &[u32],
        timeout_cycles: u32,
    ) -> Result<(Vec<u32>, Vec<u32>), UnitError> {
        let err = |message: String| UnitError::Eval {
            unit: self.kind,
            message,
        };
        if self.poisoned {
            return Err(err(
                "an earlier error left the model in an unknown state".into()
            ));
        }
        if self.kind.is_binary() && a.len() != b.len() {
            return Err(err(format!(
                "{} a-operands but {} b-operands",
                a.len(),
                b.len()
            )));
        }
        let mut y = vec![0; a.len()];
        let mut cycles = vec![0; a.len()];
        let b = if self.kind.is_binary() { b } else { a };
        let result = self
            .inner
            .pin_mut()
            .eval(a, b, &mut y, &mut cycles, timeout_cycles);
        if let Err(e) = result {
            self.poisoned = true;
            return Err(err(e.what().to_string()));
        }
        Ok((y, cycles))
    }
}
