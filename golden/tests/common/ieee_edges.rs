//! IEEE-754 binary32 results of `1/x` and `sqrt(x)` at the edges of the
//! range, worked out by hand from the standard (round to nearest even,
//! gradual underflow, overflow to infinity), not taken from any model.
//! Shared by `golden/tests/stability.rs` (golden::fp) and
//! `tests/stability.rs` (the verilated units).
//!
//! Bits: sign 1, exponent 8 (bias 127), fraction 23. A subnormal
//! `0x000mmmmm` is `m * 2^-149`.
// Each test crate uses its own part of this module.
#![allow(dead_code)]

/// How a method may answer a row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Edge {
    /// A special case (zero, infinity, NaN, invalid, an exact power of
    /// two): every method gives exactly the IEEE bits.
    Special,
    /// A rounded result: the exact method gives the IEEE bits, the fast one
    /// is within 1 ULP of them (docs/fp.md).
    Rounded,
}

/// `(x, 1/x, kind, why)`.
pub const RECIP: &[(u32, u32, Edge, &str)] = &[
    (0x0000_0000, 0x7F80_0000, Edge::Special, "1/+0 = +inf"),
    (0x8000_0000, 0xFF80_0000, Edge::Special, "1/-0 = -inf"),
    (0x7F80_0000, 0x0000_0000, Edge::Special, "1/+inf = +0"),
    (0xFF80_0000, 0x8000_0000, Edge::Special, "1/-inf = -0"),
    (0x7FC0_0000, 0x7FC0_0000, Edge::Special, "NaN in, canonical NaN out"),
    (0xFF80_0001, 0x7FC0_0000, Edge::Special, "negative signalling NaN in"),
    (0x3F80_0000, 0x3F80_0000, Edge::Special, "1/1 = 1"),
    (0xC000_0000, 0xBF00_0000, Edge::Special, "1/-2 = -0.5"),
    (0x0000_0001, 0x7F80_0000, Edge::Special, "1/2^-149 = 2^149 overflows"),
    (0x0020_0000, 0x7F80_0000, Edge::Special, "1/2^-128 = 2^128 overflows"),
    (0x0040_0000, 0x7F00_0000, Edge::Special, "1/2^-127 = 2^127, the largest power of two"),
    (0x0080_0000, 0x7E80_0000, Edge::Special, "1/2^-126 (min normal) = 2^126"),
    (0x7F00_0000, 0x0040_0000, Edge::Special, "1/2^127 = 2^-127, subnormal"),
    (0x7E80_0000, 0x0080_0000, Edge::Special, "1/2^126 = 2^-126, min normal"),
    (
        0x007F_FFFF,
        0x7E80_0001,
        Edge::Rounded,
        "1/(2^-126 (1 - 2^-23)) = 2^126 (1 + 2^-23 + 2^-46 ...): rounds down to 1 ULP above 2^126",
    ),
    (
        0x7F7F_FFFF,
        0x0020_0000,
        Edge::Rounded,
        "1/(2^128 (1 - 2^-24)) = 2^-128 (1 + 2^-24 ...): subnormal, the excess 2^-152 is below half of 2^-149",
    ),
    (
        0x7F40_0000,
        0x002A_AAAB,
        Edge::Rounded,
        "1/(1.5 * 2^127) = 2^-128 * 4/3 = 2796202.67 * 2^-149: subnormal, rounds up",
    ),
    (0x4040_0000, 0x3EAA_AAAB, Edge::Rounded, "1/3 = 0.0101...b, rounds up"),
];

/// `(x, sqrt x, kind, why)`.
pub const SQRT: &[(u32, u32, Edge, &str)] = &[
    (0x0000_0000, 0x0000_0000, Edge::Special, "sqrt(+0) = +0"),
    (0x8000_0000, 0x8000_0000, Edge::Special, "sqrt(-0) = -0"),
    (0x7F80_0000, 0x7F80_0000, Edge::Special, "sqrt(+inf) = +inf"),
    (0xFF80_0000, 0x7FC0_0000, Edge::Special, "sqrt(-inf) is invalid: NaN"),
    (0xBF80_0000, 0x7FC0_0000, Edge::Special, "sqrt(-1) is invalid: NaN"),
    (0x8000_0001, 0x7FC0_0000, Edge::Special, "sqrt(-2^-149) is invalid: NaN"),
    (0x7FC0_0000, 0x7FC0_0000, Edge::Special, "NaN in, canonical NaN out"),
    (0x3F80_0000, 0x3F80_0000, Edge::Special, "sqrt(1) = 1"),
    (0x4080_0000, 0x4000_0000, Edge::Rounded, "sqrt(4) = 2"),
    (0x3E80_0000, 0x3F00_0000, Edge::Rounded, "sqrt(0.25) = 0.5"),
    (0x0080_0000, 0x2000_0000, Edge::Rounded, "sqrt(2^-126) = 2^-63"),
    (0x0000_0002, 0x1A80_0000, Edge::Rounded, "sqrt(2^-148) = 2^-74"),
    (
        0x0000_0001,
        0x1A35_04F3,
        Edge::Rounded,
        "sqrt(2^-149) = 2^-75 * sqrt 2; sqrt 2 = 0x3FB504F3 in binary32",
    ),
    (
        0x007F_FFFF,
        0x1FFF_FFFF,
        Edge::Rounded,
        "sqrt(2^-126 (1 - 2^-23)) = 2^-63 (1 - 2^-24 - 2^-49 ...): 1 ULP below 2^-63",
    ),
    (
        0x7F7F_FFFF,
        0x5F7F_FFFF,
        Edge::Rounded,
        "sqrt(2^128 (1 - 2^-24)) = 2^64 - 2^39 - tiny: just below the tie, rounds down to 2^64 - 2^40",
    ),
    (0x4000_0000, 0x3FB5_04F3, Edge::Rounded, "sqrt(2) = 1.0110101000001001111001100110011...b"),
];

/// A value the units must handle at every binade's ends: each exponent
/// (0 = subnormal, 255 = inf/NaN) with fractions 0, 1, half, all-but-one,
/// all ones, both signs (2560 values).
pub fn boundary_values() -> Vec<u32> {
    let fractions = [0, 1, 0x40_0000, 0x7F_FFFE, 0x7F_FFFF];
    (0..=1u32)
        .flat_map(|s| (0..=255u32).flat_map(move |e| fractions.map(|f| s << 31 | e << 23 | f)))
        .collect()
}

/// IEEE `1/x` in binary32 computed through f64: the f64 quotient has 53
/// bits, more than 2 * 24 + 2, so rounding it again to binary32 (normal or
/// subnormal) gives the correctly rounded result; NaN canonical.
pub fn recip_via_f64(x: u32) -> u32 {
    canonical((1.0 / f64::from(f32::from_bits(x))) as f32)
}

/// IEEE `sqrt(x)` in binary32 through f64 (same argument as `recip_via_f64`).
pub fn sqrt_via_f64(x: u32) -> u32 {
    canonical(f64::from(f32::from_bits(x)).sqrt() as f32)
}

fn canonical(y: f32) -> u32 {
    if y.is_nan() {
        0x7FC0_0000
    } else {
        y.to_bits()
    }
}

/// ULPs between two binary32 values of one sign (both finite or equal
/// infinities), counted on their bit patterns; `None` across signs or with
/// a NaN.
pub fn ulps_apart(a: u32, b: u32) -> Option<u32> {
    let nan = |x: u32| x & 0x7FFF_FFFF > 0x7F80_0000;
    if nan(a) || nan(b) || (a ^ b) >> 31 != 0 {
        return (a == b).then_some(0);
    }
    Some(a.abs_diff(b))
}

/// Whether `got` is an acceptable answer of a method to a row expecting
/// `want`: the bits for the exact method and for special cases, within 1
/// ULP otherwise.
pub fn acceptable(got: u32, want: u32, edge: Edge, exact: bool) -> bool {
    if exact || edge == Edge::Special {
        got == want
    } else {
        ulps_apart(got, want).is_some_and(|u| u <= 1)
    }
}
