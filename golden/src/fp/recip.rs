//! Mirror of `rtl/fp/fp_recip.v`.
//!
//! For a mantissa `m` in `(1, 2)` the unit wants `Q = floor(2^27 / m)`, the
//! reciprocal with 27 significant bits (24 kept, one guard bit, two more), and
//! whether `2^27 / m` is exact.
//!
//! 1. Seed: `y0 ~ 1/m` from a table of `2^SEED_BITS` entries of `SEED_WIDTH`
//!    bits, indexed by the top fraction bits (relative error about 2^-13).
//! 2. One Newton-Raphson step `y1 = y0 * (2 - m * y0)` in fixed point. It
//!    always lands at or below `1/m`, so the truncated `q` is `Q - 3 ..= Q`
//!    (measured over all 2^23 mantissas by the ignored test
//!    `recip_estimate_is_within_three_below`).
//! 3. `Method::Fast` rounds `q` directly: error below 3/8 + 1/2 ULP.
//!    `Method::Exact` computes the remainder `2^50 - M * q` exactly, steps
//!    `q` up by `floor(remainder / M)` (0..=3), and rounds with the sticky bit
//!    "remainder nonzero": correctly rounded, subnormal results included.

use super::round::round_pack;
use super::unpack::{unpack, Operand};
use super::{Method, CANONICAL_NAN};

/// Index bits of the seed table.
pub(crate) const SEED_BITS: u32 = 12;
/// Fraction bits of a seed entry (entries lie in (0.5, 1)).
pub(crate) const SEED_WIDTH: u32 = 16;
/// Fraction bits kept of `2 - m * y0`.
const CORR_FRAC: u32 = 30;

/// `round(2^SEED_WIDTH / m_mid)` for the midpoint `m_mid` of each interval,
/// in integers only, exactly as the Verilog constant function computes it.
pub(crate) const fn seed_entry(index: u32) -> u32 {
    let d = (1u64 << (SEED_BITS + 1)) + 2 * index as u64 + 1;
    ((((1u64 << (SEED_WIDTH + SEED_BITS + 2)) / d) + 1) >> 1) as u32
}

static SEED: [u16; 1 << SEED_BITS] = {
    let mut table = [0u16; 1 << SEED_BITS];
    let mut i = 0;
    while i < table.len() {
        table[i] = seed_entry(i as u32) as u16;
        i += 1;
    }
    table
};

/// The Newton-Raphson estimate of `floor(2^50 / m)` for `m` in `(2^23, 2^24)`.
pub(crate) fn estimate(m: u64) -> u64 {
    let y0 = SEED[((m >> (23 - SEED_BITS)) & ((1 << SEED_BITS) - 1)) as usize] as u64;
    // 2 - m*y0, fraction 23 + SEED_WIDTH bits, truncated to CORR_FRAC bits.
    let corr = ((1u64 << (24 + SEED_WIDTH)) - m * y0) >> (23 + SEED_WIDTH - CORR_FRAC);
    (y0 * corr) >> (SEED_WIDTH + CORR_FRAC - 27)
}

/// The exact method's correction of the estimate `q` of `floor(2^50 / m)`:
/// the steps of `m` it adds (0 to 3) and the remainder left.
pub(crate) fn correct(m: u64, q: u64) -> (u64, u64) {
    let rem = (1u64 << 50) - m * q;
    let steps = (rem >= m) as u64 + (rem >= 2 * m) as u64 + (rem >= 3 * m) as u64;
    (steps, rem - steps * m)
}

/// The steps the exact method's correction takes for finite `a` whose
/// mantissa is not a power of two (0 to 3); `None` for the others.
pub(crate) fn correction_steps(a: u32) -> Option<u64> {
    match unpack(a) {
        Operand::Finite { m, .. } if m != 1 << 23 => {
            let m = m as u64;
            Some(correct(m, estimate(m)).0)
        }
        _ => None,
    }
}

pub(crate) fn recip_bits(a: u32, method: Method) -> u32 {
    let (sign, e, m) = match unpack(a) {
        Operand::Nan => return CANONICAL_NAN,
        Operand::Inf { sign } => return (sign as u32) << 31,
        Operand::Zero { sign } => return (sign as u32) << 31 | 0x7F80_0000,
        Operand::Finite { sign, e, m } => (sign, e, m as u64),
    };
    // 1/x = (2^27/m) / 2^26 * 2^(126 - e): biased result exponent 253 - e.
    if m == 1 << 23 {
        // A power of two: exact, and 2^27/m = 2^27 would not fit in 27 bits.
        return round_pack(sign, 254 - e, 1 << 26, false);
    }
    let q = estimate(m);
    match method {
        Method::Fast => round_pack(sign, 253 - e, q as u32, false),
        Method::Exact => {
            let (steps, rem) = correct(m, q);
            round_pack(sign, 253 - e, (q + steps) as u32, rem != 0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_entries_lie_in_half_open_unit_interval() {
        for i in 0..(1 << SEED_BITS) {
            let y = SEED[i as usize] as u32;
            assert!(
                y > 1 << (SEED_WIDTH - 1) && y < 1 << SEED_WIDTH,
                "entry {i} = {y}"
            );
        }
    }

    #[test]
    #[ignore = "2^23 mantissas; run with --release --ignored"]
    fn recip_estimate_is_within_three_below() {
        for m in (1u64 << 23) + 1..1 << 24 {
            let exact = (1u64 << 50) / m;
            let q = estimate(m);
            assert!(
                q <= exact && exact - q <= 3,
                "m = {m:#x}: q = {q}, exact = {exact}"
            );
            assert!(q >> 26 == 1, "m = {m:#x}: estimate {q:#x} not normalized");
        }
    }
}
