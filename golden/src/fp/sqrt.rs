//! Mirror of `rtl/fp/fp_sqrt.v`.
//!
//! The operand is scaled to `m'` in `[1, 4)` so that its exponent is even
//! (`m' = m` or `2m`). The unit wants `Q = floor(sqrt(m') * 2^26)`, i.e.
//! `isqrt(M' * 2^29)` for the integer mantissa `M'`, and whether it is exact.
//!
//! 1. Seed: `y0 ~ 1/sqrt(m')` from a table indexed by the exponent parity and
//!    the top `SEED_BITS` fraction bits.
//! 2. One Newton-Raphson step for the reciprocal square root,
//!    `y1 = y0 * (3 - m' * y0^2) / 2`, then `s = m' * y1`; the truncated
//!    estimate `q` is within one of `Q` (measured over every mantissa and
//!    parity by the ignored test `sqrt_estimate_is_within_one`). It is
//!    clamped up to `2^26`, the least possible `Q`: `m' = 1` undershoots.
//! 3. `Method::Fast` rounds `q` directly. `Method::Exact` computes the
//!    remainder `M' * 2^29 - q^2` exactly, moves `q` by one when the remainder
//!    says so, and rounds with the sticky bit "remainder nonzero".

use super::round::round_pack;
use super::unpack::{unpack, Operand};
use super::{Method, CANONICAL_NAN};
use std::sync::LazyLock;

/// Fraction-index bits of the seed table (plus one bit for the parity).
pub(crate) const SEED_BITS: u32 = 12;
/// Fraction bits of a seed entry (entries lie in (0.5, 1)).
pub(crate) const SEED_WIDTH: u32 = 16;
/// Fraction bits kept of `m' * y0^2` and of `y1`.
const STEP_FRAC: u32 = 32;

/// `round(2^SEED_WIDTH / sqrt(m_mid))`, in IEEE double with the same
/// operations, in the same order, as the Verilog elaboration-time function;
/// `odd` selects the `[2, 4)` half of the table.
pub(crate) fn seed_entry(odd: bool, index: u32) -> u32 {
    let m_mid = (1.0 + (index as f64 + 0.5) / (1u32 << SEED_BITS) as f64) * (odd as u32 + 1) as f64;
    ((1u32 << SEED_WIDTH) as f64 / m_mid.sqrt() + 0.5) as u32
}

static SEED: LazyLock<Vec<u16>> = LazyLock::new(|| {
    (0..2u32 << SEED_BITS)
        .map(|i| seed_entry(i >> SEED_BITS == 1, i & ((1 << SEED_BITS) - 1)) as u16)
        .collect()
});

/// The estimate of `isqrt(mp * 2^29)`, `mp = m` (even) or `2m` (odd).
pub(crate) fn estimate(m: u64, odd: bool) -> u64 {
    let index = (odd as u64) << SEED_BITS | (m >> (23 - SEED_BITS)) & ((1 << SEED_BITS) - 1);
    let y0 = SEED[index as usize] as u64;
    let mp = m << odd as u32;
    let y0_sq = y0 * y0; // fraction 2 * SEED_WIDTH = 32 bits
    let t = (mp * y0_sq) >> (23 + 2 * SEED_WIDTH - STEP_FRAC);
    let h = (3u64 << STEP_FRAC) - t;
    let y1 = (y0 * h) >> (1 + SEED_WIDTH); // fraction STEP_FRAC
    let q = (mp * y1) >> (23 + STEP_FRAC - 26);
    // sqrt(m') >= 1, so Q >= 2^26; only m' = 1 itself undershoots, to 2^26 - 1.
    q.max(1 << 26)
}

/// The exact method's correction of the estimate `q` of `isqrt(n)`: within
/// one, so `q - 1`, `q` or `q + 1`, and the remainder `n - q'^2`.
fn correct(n: u64, q: u64) -> (u64, u64) {
    let sq = q * q;
    if sq > n {
        (q - 1, n + 2 * q - 1 - sq)
    } else if n - sq > 2 * q {
        (q + 1, n - sq - 2 * q - 1)
    } else {
        (q, n - sq)
    }
}

/// The step the exact method's correction takes for positive finite `a`:
/// -1 (the estimate overshoots), 0 or +1 (it undershoots); `None` for the
/// others.
pub(crate) fn correction_step(a: u32) -> Option<i64> {
    match unpack(a) {
        Operand::Finite { sign: false, e, m } => {
            let (m, odd) = (m as u64, e & 1 == 0);
            let q = estimate(m, odd);
            Some(correct((m << odd as u32) << 29, q).0 as i64 - q as i64)
        }
        _ => None,
    }
}

pub(crate) fn sqrt_bits(a: u32, method: Method) -> u32 {
    let (e, m) = match unpack(a) {
        Operand::Nan | Operand::Inf { sign: true } | Operand::Finite { sign: true, .. } => {
            return CANONICAL_NAN
        }
        Operand::Inf { sign: false } => return 0x7F80_0000,
        Operand::Zero { sign } => return (sign as u32) << 31,
        Operand::Finite { sign: false, e, m } => (e, m as u64),
    };
    // x = m * 2^(e - 127); the unbiased exponent is odd exactly when e is even.
    let odd = e & 1 == 0;
    let exp = (e + 127) >> 1;
    let q = estimate(m, odd);
    match method {
        Method::Fast => round_pack(false, exp, q as u32, false),
        Method::Exact => {
            let (q, rem) = correct((m << odd as u32) << 29, q);
            round_pack(false, exp, q as u32, rem != 0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_entries_lie_in_half_open_unit_interval() {
        for (i, &y) in SEED.iter().enumerate() {
            let y = y as u32;
            assert!(
                y > 1 << (SEED_WIDTH - 1) && y < 1 << SEED_WIDTH,
                "entry {i} = {y}"
            );
        }
    }

    /// Bit-by-bit integer square root, independent of the estimate under test.
    fn isqrt(v: u64) -> u64 {
        let mut root = 0u64;
        for b in (0..32).rev() {
            let trial = root | 1 << b;
            if trial * trial <= v {
                root = trial;
            }
        }
        root
    }

    #[test]
    #[ignore = "2^24 mantissas; run with --release --ignored"]
    fn sqrt_estimate_is_within_one() {
        for odd in [false, true] {
            for m in 1u64 << 23..1 << 24 {
                let exact = isqrt((m << odd as u32) << 29);
                let q = estimate(m, odd);
                assert!(
                    q.abs_diff(exact) <= 1,
                    "m = {m:#x} odd = {odd}: q = {q}, exact = {exact}"
                );
                assert!(
                    q >> 26 == 1,
                    "m = {m:#x} odd = {odd}: estimate {q:#x} not normalized"
                );
            }
        }
    }
}
