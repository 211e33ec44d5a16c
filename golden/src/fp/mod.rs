//! Bit-exact models of the float32 units in `rtl/fp/`.
//!
//! The RTL offers each multi-cycle unit in several [`Method`]s. A correctly
//! rounded method is, by definition, bit-identical to the native f32 operation,
//! so its model *is* the native operation. The approximate methods are modelled
//! here integer step by integer step, mirroring the Verilog register by
//! register, so that their results (including where they are off by one ULP)
//! are reproduced bit for bit.
//!
//! # One NaN rule
//!
//! Every float unit, RTL and model alike, returns the canonical quiet NaN
//! [`CANONICAL_NAN`] (`0x7FC00000`, as RISC-V does) for every operation whose
//! IEEE result is NaN: an invalid operation or a NaN operand, whatever its
//! payload or sign. The host's own NaN differs (x86 makes `0xFFC00000` for
//! `inf - inf`, and propagates payloads), so the models built on native
//! operations canonicalize ([`canonical`]). A sign flip *after* a unit (the
//! ALU's negated product, `NEG`) flips the NaN's sign too, in both. So the
//! RTL and the models agree on NaN bits, sign included, and on every flag
//! read from them; the co-simulation compares NaN lanes bit for bit.
//! [`ulp::UlpDistance`] treats every NaN as equal to every other NaN: it is
//! for accuracy against the f64 reference, not for bit-exactness.

mod exp;
mod recip;
mod round;
mod sqrt;
pub mod ulp;
mod unpack;

pub use ulp::{ulp_distance, UlpDistance};

/// The quiet NaN every RTL float unit returns for an invalid operation or a
/// NaN operand.
pub const CANONICAL_NAN: u32 = 0x7FC0_0000;

/// How a multi-cycle float unit (reciprocal, square root) computes its result.
///
/// Mirrors the `METHOD` parameter of `fp_recip` and `fp_sqrt`; the numeric
/// codes live in `rtl/fp/fp_defs.vh` (`FP_METHOD_*`) and the root crate's build
/// script checks that both sides agree.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Method {
    /// Correctly rounded (round to nearest even): bit-identical to `1.0 / x`
    /// and `x.sqrt()`. Seed table + one Newton-Raphson step + an exact
    /// remainder check that fixes the last bits.
    Exact,
    /// Seed table + one Newton-Raphson step, rounded directly: at most 1 ULP
    /// from the correctly rounded result, one cycle faster than [`Method::Exact`].
    Fast,
}

impl Method {
    /// Every method, in the order tables and charts list them.
    pub const ALL: [Method; 2] = [Method::Exact, Method::Fast];

    /// The lower-case name used on the command line and in docs.
    pub const fn name(self) -> &'static str {
        match self {
            Method::Exact => "exact",
            Method::Fast => "fast",
        }
    }

    /// The code of this method in `rtl/fp/fp_defs.vh` (`FP_METHOD_EXACT`,
    /// `FP_METHOD_FAST`).
    pub const fn code(self) -> u32 {
        match self {
            Method::Exact => 0,
            Method::Fast => 1,
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// `x`, or [`CANONICAL_NAN`] if `x` is any NaN.
///
/// Decided on the bits, not with `is_nan()`: LLVM treats NaN payloads as
/// unspecified, and folds a float `select(isnan(x), NaN, x)` into `x`
/// (observed in the dev profile, where the harness inlines this), which
/// would hand on the host's NaN.
#[inline]
pub fn canonical(x: f32) -> f32 {
    let bits = x.to_bits();
    f32::from_bits(if bits & 0x7FFF_FFFF > 0x7F80_0000 {
        CANONICAL_NAN
    } else {
        bits
    })
}

/// `fp_add`: correctly rounded, so the model is the native operation (NaN
/// canonical).
#[inline]
pub fn add(a: f32, b: f32) -> f32 {
    canonical(a + b)
}

/// `fp_mul`: correctly rounded, so the model is the native operation (NaN
/// canonical).
#[inline]
pub fn mul(a: f32, b: f32) -> f32 {
    canonical(a * b)
}

/// `fp_itof`: signed 32-bit integer to float, round to nearest even.
#[inline]
pub fn itof(a: i32) -> f32 {
    a as f32
}

/// `fp_recip` with the given method: `1 / a`.
#[inline]
pub fn recip(a: f32, method: Method) -> f32 {
    match method {
        Method::Exact => canonical(1.0 / a),
        Method::Fast => f32::from_bits(recip::recip_bits(a.to_bits(), Method::Fast)),
    }
}

/// `fp_sqrt` with the given method: `sqrt(a)`.
#[inline]
pub fn sqrt(a: f32, method: Method) -> f32 {
    match method {
        Method::Exact => canonical(a.sqrt()),
        Method::Fast => f32::from_bits(sqrt::sqrt_bits(a.to_bits(), Method::Fast)),
    }
}

/// The integer datapath of `fp_recip`, for either method, exactly as the RTL
/// computes it. For [`Method::Exact`] it equals `1.0 / a` on every input
/// (checked exhaustively by `golden`'s ignored tests); [`recip`] uses the
/// native division for that method because it is the definition.
pub fn recip_datapath(a: u32, method: Method) -> u32 {
    recip::recip_bits(a, method)
}

/// The integer datapath of `fp_sqrt`, for either method; see [`recip_datapath`].
pub fn sqrt_datapath(a: u32, method: Method) -> u32 {
    sqrt::sqrt_bits(a, method)
}

/// How many steps of the mantissa `fp_recip`'s exact method adds to its
/// Newton estimate for `a` (0 to 3; `None` where no estimate is made: NaN,
/// infinities, zeros and powers of two). Operands for each step count are
/// edge cases of the unit (harness `operands`).
pub fn recip_correction(a: u32) -> Option<u64> {
    recip::correction_steps(a)
}

/// The step `fp_sqrt`'s exact method takes from its estimate for `a`: -1,
/// 0 or +1 (`None` for NaN, infinities, zeros and negative operands).
pub fn sqrt_correction(a: u32) -> Option<i64> {
    sqrt::correction_step(a)
}

/// `fp_exp`: `e^a`, within 1 ULP of the correctly rounded result over
/// every input (not correctly rounded; the method is in the `exp` module
/// and docs/fp.md, the error measured by the ignored test
/// `exp_error_over_every_f32_input`). NaN gives [`CANONICAL_NAN`], `-inf`
/// and `a < -103.97` give `+0` (through the subnormals), `+-0` gives 1,
/// `a > 88.72` gives `+inf`.
#[inline]
pub fn exp(a: f32) -> f32 {
    f32::from_bits(exp::exp_bits(a.to_bits()))
}

/// `e^a` correctly rounded to f32 as far as f64 can tell: the f64 `exp`
/// (within an f64 ULP) rounded once to f32. The truth [`exp`]'s error is
/// measured against (NaN canonical).
pub fn exp_reference(a: f32) -> f32 {
    canonical(f64::from(a).exp() as f32)
}

/// Cycles from the clock edge that samples `in_valid` to the edge after which
/// `out_valid` is high, for `fp_recip`. The latency does not depend on the
/// operand.
pub const fn recip_latency(method: Method) -> u32 {
    match method {
        Method::Exact => 5,
        Method::Fast => 4,
    }
}

/// Latency of `fp_exp` in cycles (it has one method); see [`recip_latency`].
pub const fn exp_latency() -> u32 {
    5
}

/// Latency of `fp_sqrt` in cycles; see [`recip_latency`].
pub const fn sqrt_latency(method: Method) -> u32 {
    match method {
        Method::Exact => 7,
        Method::Fast => 6,
    }
}

/// The fast processor's pipelined units (`rtl/fast/`, `fast_defs.vh`):
/// clock edges from the operands to the result, a new operation entering
/// every cycle. Their results are this module's functions bit for bit;
/// `tests/rtl_lint.rs` checks these figures against `fast_defs.vh`, and the
/// units' test (`fp-check`) reads each result this many edges after its
/// operands, so a wrong figure is a mismatch.
pub mod pipelined {
    /// `fast_fp_add`: y = a + b.
    pub const ADD_LATENCY: u32 = 10;
    /// `fast_fp_mul`: y = a * b.
    pub const MUL_LATENCY: u32 = 9;
    /// `fast_fp_itof`: y = a as i32 as f32.
    pub const ITOF_LATENCY: u32 = 7;
    /// `fast_fp_recip`: y = 1 / a, either method.
    pub const RECIP_LATENCY: u32 = 18;
    /// `fast_fp_sqrt`: y = sqrt(a), either method.
    pub const SQRT_LATENCY: u32 = 22;
    /// `fast_fp_exp`: y = e^a.
    pub const EXP_LATENCY: u32 = 20;
}

#[cfg(test)]
mod nan_tests {
    use super::*;

    /// Every way to a NaN gives the one canonical NaN, sign bit clear,
    /// whatever the operands' payloads and signs.
    #[test]
    fn every_nan_result_is_the_canonical_nan() {
        let inf = f32::INFINITY;
        let payload = f32::from_bits(0xFFC0_1234);
        let cases = [
            add(inf, -inf),
            add(-inf, inf),
            add(payload, 1.0),
            add(1.0, f32::from_bits(0x7F80_0001)),
            mul(0.0, inf),
            mul(-inf, -0.0),
            mul(payload, payload),
            recip(payload, Method::Exact),
            recip(payload, Method::Fast),
            sqrt(-1.0, Method::Exact),
            sqrt(-1.0, Method::Fast),
            sqrt(-inf, Method::Exact),
            sqrt(payload, Method::Exact),
        ];
        for (i, y) in cases.iter().enumerate() {
            assert_eq!(
                y.to_bits(),
                CANONICAL_NAN,
                "case {i}: {:#010x}",
                y.to_bits()
            );
        }
        // The host itself does not make it: that is why the models canonicalize.
        let host = std::hint::black_box(inf) - std::hint::black_box(inf);
        assert!(host.is_nan());
        // Numbers pass through untouched.
        assert_eq!(add(1.5, -0.5), 1.0);
        assert_eq!(mul(-0.0, 3.0).to_bits(), 0x8000_0000);
        assert_eq!(canonical(-0.0).to_bits(), 0x8000_0000);
    }
}
