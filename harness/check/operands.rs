//! Operands for the float units: TestFloat-style edge cases and seeded random
//! streams that favour the places where float hardware goes wrong.
//!
//! Every random stream is a pure function of `(seed, chunk index)`, so a run
//! is reproducible whatever the thread count, and a failing chunk can be
//! replayed alone.

use crate::design::fp_unit::UnitKind;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Operands per chunk of a random or exhaustive stream.
pub const CHUNK: usize = 1 << 16;

/// Magnitudes (bit patterns, sign clear) that float units get wrong first.
const EDGE_MAGNITUDES: &[u32] = &[
    0x0000_0000, // zero
    0x0000_0001, // min subnormal
    0x0000_0002,
    0x0000_0003,
    0x0040_0000, // half the min normal
    0x007F_FFFF, // max subnormal
    0x0080_0000, // min normal
    0x0080_0001,
    0x00FF_FFFF,
    0x0100_0000,
    0x0D00_0000, // products land near the underflow threshold
    0x1F80_0000, // 2^-64: squares to 2^-128 (subnormal)
    0x2000_0000,
    0x3380_0000, // 2^-24: 1 + this is a rounding tie
    0x3380_0001,
    0x337F_FFFF,
    0x3400_0000, // 2^-23: one ULP of 1.0
    0x3DCC_CCCD, // 0.1
    0x3F00_0000, // 0.5
    0x3F35_04F3, // 1/sqrt(2)
    0x3F7F_FFFF, // 1 - 2^-24
    0x3F80_0000, // 1.0
    0x3F80_0001, // 1 + 2^-23
    0x3FAA_AAAB, // 4/3: alternating mantissa
    0x3FB5_04F3, // sqrt(2)
    0x3FC0_0000, // 1.5
    0x3FD5_5555,
    0x3FFF_FFFF, // 2 - 2^-23: mantissa of all ones
    0x4000_0000, // 2.0
    0x4040_0000, // 3.0
    0x4049_0FDB, // pi
    0x4B7F_FFFF, // 2^24 - 1
    0x4B80_0000, // 2^24: where integers stop being exact
    0x4B80_0001,
    0x5F80_0000, // 2^64: squares to 2^128 (overflow)
    0x7E80_0000, // 2^126
    0x7EFF_FFFF,
    0x7F00_0000, // 2^127
    0x7F7F_FFFE,
    0x7F7F_FFFF, // max normal
    0x7F80_0000, // infinity
    0x7F80_0001, // signalling NaN
    0x7FC0_0000, // quiet NaN
    0x7FFF_FFFF,
];

/// Integers that stress `fp_itof`: exactness limits and rounding ties.
const EDGE_INTEGERS: &[i32] = &[
    0,
    1,
    2,
    3,
    0x00FF_FFFF,
    0x0100_0000,
    0x0100_0001, // tie, rounds to even (down)
    0x0100_0003, // tie, rounds to even (up)
    0x0200_0002,
    0x0200_0006,
    0x7FFF_FF7F,
    0x7FFF_FFC0, // tie at the top
    0x7FFF_FFFF,
    i32::MIN,
    i32::MIN + 1,
];

/// The edge magnitudes with both signs and their bit-pattern neighbours.
pub fn edge_values() -> Vec<u32> {
    let mut values: Vec<u32> = EDGE_MAGNITUDES
        .iter()
        .flat_map(|&m| {
            [
                m,
                m.wrapping_add(1) & 0x7FFF_FFFF,
                m.wrapping_sub(1) & 0x7FFF_FFFF,
            ]
        })
        .flat_map(|m| [m, m | 0x8000_0000])
        .collect();
    values.sort_unstable();
    values.dedup();
    values
}

/// Inputs where `fp_exp` changes regime (bit patterns): e^x's underflow to
/// the smallest subnormal and to zero (x = ln 2^-149 = -103.279, x =
/// ln 2^-150 = -103.972), overflow (x = ln(f32::MAX) = 88.7228), |x| = 128
/// (decided at the input), the smallest |x| the fixed-point input keeps
/// (2^-32) and those where e^x rounds away from 1 (2^-25, 2^-24), and
/// multiples of ln 2 (k steps, f = 0 and f just below 1).
const EXP_EDGES: &[u32] = &[
    0xC2CE_8ED0, // -103.279
    0xC2CF_F1B4, // -103.972
    0x42B1_7218, // 88.7228
    0x4300_0000, // 128
    0x2F80_0000, // 2^-32
    0x3300_0000, // 2^-25
    0x3380_0000, // 2^-24
    0x3F31_7218, // ln 2
    0x3FB1_7218, // 2 ln 2
    0x42AE_AC50, // 126 ln 2 = 87.3365
];

/// Edge-case operands for `kind`: every ordered pair of [`edge_values`] for
/// binary units (and the pairs of [`ADD_HARD_OPERANDS`],
/// [`MUL_HARD_OPERANDS`]); the edge values (and, for `fp_itof`, the edge
/// integers with both signs; for `fp_exp`, [`EXP_EDGES`] with both signs
/// and their neighbours; the hard operands) for unary ones. `b` is empty
/// for unary units. A pipelined unit gets its arithmetic's.
pub fn edge_cases(kind: UnitKind) -> (Vec<u32>, Vec<u32>) {
    let values = edge_values();
    if kind.is_binary() {
        let mut a: Vec<u32> = values
            .iter()
            .flat_map(|&x| values.iter().map(move |_| x))
            .collect();
        let mut b: Vec<u32> = values.iter().flat_map(|_| values.iter().copied()).collect();
        let hard = match kind.arithmetic() {
            UnitKind::Add => ADD_HARD_OPERANDS,
            UnitKind::Mul => MUL_HARD_OPERANDS,
            _ => &[],
        };
        a.extend(hard.iter().map(|&(x, _)| x));
        b.extend(hard.iter().map(|&(_, y)| y));
        return (a, b);
    }
    let mut a = values;
    let kind = kind.arithmetic();
    if kind == UnitKind::Itof {
        a.extend(
            EDGE_INTEGERS
                .iter()
                .flat_map(|&i| [i as u32, i.wrapping_neg() as u32]),
        );
    }
    if kind == UnitKind::Exp {
        a.extend(
            EXP_EDGES
                .iter()
                .flat_map(|&m| (m - 2..=m + 2).flat_map(|v| [v, v | 0x8000_0000])),
        );
    }
    if let UnitKind::Recip(_) | UnitKind::Sqrt(_) = kind {
        a.extend(correction_edges(kind));
    }
    a.extend_from_slice(match kind {
        UnitKind::Recip(_) => RECIP_HARD_OPERANDS,
        UnitKind::Sqrt(_) => SQRT_HARD_OPERANDS,
        UnitKind::Exp => EXP_HARD_OPERANDS,
        _ => &[],
    });
    (a, Vec::new())
}

/// `fp_recip` operands that caught a fault the other edge cases and the
/// random operands miss, each the smallest bit pattern that does, found by
/// exhaustive simulation of a mutant (`examples/mutant_exhaustive.rs`,
/// docs/mutation.md), with the fault: an edge case of the reciprocal's
/// arithmetic from then on. Two are results below the normal range (a of
/// exponent field 253 or 254), where the rounding drops one or two more
/// bits. [`MUTANT_KILLERS`] names the mutants of today's lists that hard
/// operands kill.
pub const RECIP_HARD_OPERANDS: &[u32] = &[
    0x7F00_1001, // 3M's bit 13 inverted (fp_recip.v:145): 1 operand of 25.2M
    0x3F8E_FA43, // bit 2 of M inverted in rem_q - M (:157): 7
    0x3F81_64B0, // rem_q[6] flipped when rem_q[3] is 0 (:125): 14
    0x3F95_BF00, // bit 10 of the 2-step arm's rem_fixed (:152): 8
    0x3F80_A4DA, // bit 12 of M*q forced in 2^50 - M*q (:134): 323
    0x7E9B_C000, // rem_fixed[17] cleared in the sticky (:171): 2
    0x3F81_1FFA, // 3M's bit 19 flipped where bit 1 is 1 (:145): 4 in the first batch
    // fast_fp_recip:
    0x3F80_A7F4, // fast_fp_recip.v:128
    0x3F86_908F, // :207
    0x3F80_1B24, // a fast_delay of it (fast_delay.v:24)
    0x3F81_7000, // a fast_delay of it (fast_delay.v:16)
];

/// `fp_sqrt`'s and `fast_fp_sqrt`'s; see [`RECIP_HARD_OPERANDS`].
pub const SQRT_HARD_OPERANDS: &[u32] = &[
    0x3F84_4570, // rem_full[13] flipped by bit 8 (fp_sqrt.v:152): 43 operands of 16.8M
    0x406E_9372, // rem_full[8] inverted into rem_q (:232): 1
    0x3F83_3A4E, // fast_fp_sqrt.v:231
    0x3FCB_41E9, // :235
];

/// `fp_exp`'s and `fast_fp_exp`'s, found by `examples/mutant_exhaustive.rs`
/// (its exponent sweep, then one operand for each value of the unit's
/// fixed-point input below |a| = 128): each the smallest that differs in
/// the first batch that had one; see [`RECIP_HARD_OPERANDS`].
pub const EXP_HARD_OPERANDS: &[u32] = &[
    0xB4AE_553E, // u_q[6] forced 1 in p = 1 + g*u (fp_exp.v:113)
    0x3E52_B78F, // bit 1 of table_rom[76] forced 1 (:127): 292 in the first batch
    0x3951_2AB0, // u_next[2] inverted (:124)
    0x3980_0400, // in_man[4] inverted into x_right (:85)
    0x399E_81E8, // u_next[1] flipped by bit 19 (:124)
    0x3380_8000, // s[35] inverted: the sticky or sig's low bit (:128)
    0x37DD_7F80, // fast_fp_exp.v:276
    0x3F2C_8077, // :158
    0x3A8D_4A82, // :236
    0x3BD5_6D2F, // :231
    0xBF27_1688, // :184
    0x3CBF_9A43, // :150
    0x3AA9_EDD0, // :244
    0x3ACA_95EC, // :188
    0x4100_4000, // :154
    0x3B5A_8F9C, // :157
    0xB945_EC10, // :124
    0x3E11_6DA6, // :137
    0x3F55_4A6A, // :167
];

/// Operand pairs `(a, b)` of the adders and of the multipliers that
/// caught a fault the other edge cases and random operands miss, each the
/// counterexample of `mutants.sh miter` (for a pipelined unit, the pair
/// that entered a latency before the outputs differed); see
/// [`RECIP_HARD_OPERANDS`].
pub const ADD_HARD_OPERANDS: &[(u32, u32)] = &[
    (0xA980_0000, 0x1D20_0000), // fast_fp_add.v:117
];

/// The multipliers'; see [`ADD_HARD_OPERANDS`] (the fp_round ones show in
/// the multiplier's subnormal results).
pub const MUL_HARD_OPERANDS: &[(u32, u32)] = &[
    (0x0000_0003, 0x400C_0000), // fast_fp_round.v:61
    (0x3700_0000, 0x0021_0008), // fast_fp_round.v:61
    (0x0000_0241, 0x3C00_0000), // fast_fp_round.v:57
    (0x3BC0_0DAB, 0x00C0_0000), // fp_round.v:62: bit 21 of the subnormal shift
];

/// A hard operand (pair) and a mutant of today's lists it kills: the unit
/// as the judge gets it, carrying the mutant, gives another result than
/// golden (`FpUnit::new_mutant`; a `Fast*` kind names a mutant of the fast
/// processor's list, any other the compact one's). Checked by
/// `tests/mutation.rs`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Killer {
    pub unit: UnitKind,
    pub a: u32,
    /// 0 for a unary unit.
    pub b: u32,
    pub mutant: u16,
}

/// The hard operands that kill a mutant of today's lists
/// (rtl/mutate/*.mutants), with the mutant.
pub const MUTANT_KILLERS: &[Killer] = &[
    Killer {
        unit: UnitKind::Mul,
        a: 0x3BC0_0DAB,
        b: 0x00C0_0000,
        mutant: 545,
    },
    Killer {
        unit: UnitKind::Recip(golden::fp::Method::Exact),
        a: 0x3F81_1FFA,
        b: 0,
        mutant: 194,
    },
    Killer {
        unit: UnitKind::Exp,
        a: 0x3E52_B78F,
        b: 0,
        mutant: 8,
    },
];

/// Operands of each step count of the exact methods' correction (for either
/// method: the estimate is the same): for `fp_recip`, mantissas whose Newton
/// estimate lies 0, 1, 2 and 3 below `floor(2^50 / m)`, with both signs;
/// for `fp_sqrt`, estimates one over, exact and one under, with both
/// exponent parities. The first [`CORRECTION_EDGES`] of each, in mantissa
/// order ([`golden::fp::recip_correction`], [`golden::fp::sqrt_correction`]):
/// the rarer steps are the remainder fix-ups no scene reaches.
fn correction_edges(kind: UnitKind) -> Vec<u32> {
    use std::sync::OnceLock;
    static RECIP: OnceLock<Vec<u32>> = OnceLock::new();
    static SQRT: OnceLock<Vec<u32>> = OnceLock::new();
    // The first of each class among `bases | frac`, frac = 1, 2, ...
    let first = |bases: &[u32], class: &dyn Fn(u32) -> Option<i64>, classes: &[i64]| {
        let mut found = Vec::new();
        for &base in bases {
            for &want in classes {
                found.extend(
                    (1..1u32 << 23)
                        .map(|frac| base | frac)
                        .filter(|&a| class(a) == Some(want))
                        .take(CORRECTION_EDGES),
                );
            }
        }
        found
    };
    match kind {
        UnitKind::Recip(_) => RECIP
            .get_or_init(|| {
                let steps = |a| golden::fp::recip_correction(a).map(|s| s as i64);
                let a = first(&[0x3F80_0000], &steps, &[0, 1, 2, 3]);
                a.iter().flat_map(|&v| [v, v | 0x8000_0000]).collect()
            })
            .clone(),
        UnitKind::Sqrt(_) => SQRT
            .get_or_init(|| {
                // Exponents 127 and 128: both parities of the unbiased one.
                first(
                    &[0x3F80_0000, 0x4000_0000],
                    &golden::fp::sqrt_correction,
                    &[-1, 0, 1],
                )
            })
            .clone(),
        _ => Vec::new(),
    }
}

/// Operands of each correction step in [`edge_cases`].
const CORRECTION_EDGES: usize = 4;

/// A float with a sign, an exponent drawn from the whole range or from its
/// edges, and a mantissa drawn uniformly or from patterns (all ones, all
/// zeros, a single bit, a run of ones) that exercise carries and ties.
fn structured(rng: &mut ChaCha8Rng) -> u32 {
    let sign = (rng.random::<bool>() as u32) << 31;
    let exp: u32 = match rng.random_range(0..4) {
        0 => rng.random_range(0..=255),
        1 => rng.random_range(0..=3),
        2 => rng.random_range(120..=134),
        _ => rng.random_range(250..=255),
    };
    let mantissa: u32 = match rng.random_range(0..6) {
        0 | 1 => rng.random::<u32>(),
        2 => u32::MAX,
        3 => 0,
        4 => 1 << rng.random_range(0..23),
        _ => {
            let lo = rng.random_range(0..23);
            let hi = rng.random_range(lo..23);
            ((1u32 << (hi + 1)) - 1) & !((1u32 << lo) - 1)
        }
    };
    sign | exp << 23 | (mantissa & 0x7F_FFFF)
}

/// A second operand related to `a` so that the pair is hard: exponents close
/// (alignment, cancellation), `b` within a few ULPs of `-a` (massive
/// cancellation), or exponents summing to the edge of the range (products
/// that underflow or overflow).
fn partner(rng: &mut ChaCha8Rng, a: u32) -> u32 {
    let a_exp = (a >> 23) & 0xFF;
    match rng.random_range(0..5) {
        0 => rng.random(),
        1 => structured(rng),
        2 => {
            let exp = (a_exp as i32 + rng.random_range(-3..=3)).clamp(0, 254) as u32;
            (rng.random::<u32>() & 0x807F_FFFF) | exp << 23
        }
        3 => (a ^ 0x8000_0000)
            .wrapping_add(rng.random_range(0..8))
            .wrapping_sub(4),
        _ => {
            // a_exp + b_exp - 127 near 0 or 254.
            let target: i32 = if rng.random() {
                rng.random_range(-25..=3)
            } else {
                rng.random_range(250..=258)
            };
            let exp = (target + 127 - a_exp as i32).clamp(0, 254) as u32;
            (rng.random::<u32>() & 0x807F_FFFF) | exp << 23
        }
    }
}

/// Chunk `index` of the random operand stream `seed` for `kind`: `len`
/// operands (`b` empty for unary units). Half uniform random bits, half
/// [`structured`]; binary units pair them with [`partner`]s.
pub fn random_chunk(kind: UnitKind, seed: u64, index: u64, len: usize) -> (Vec<u32>, Vec<u32>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(index);
    let mut a = Vec::with_capacity(len);
    let mut b = Vec::with_capacity(if kind.is_binary() { len } else { 0 });
    for _ in 0..len {
        let x = if rng.random() {
            rng.random()
        } else {
            structured(&mut rng)
        };
        a.push(x);
        if kind.is_binary() {
            b.push(partner(&mut rng, x));
        }
    }
    (a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_correction_edges_take_every_step() {
        use golden::fp::{recip_correction, sqrt_correction};
        let (a, _) = edge_cases(UnitKind::Recip(golden::fp::Method::Exact));
        for steps in 0..=3 {
            let n = a
                .iter()
                .filter(|&&v| recip_correction(v) == Some(steps))
                .count();
            assert!(
                n >= 2 * CORRECTION_EDGES,
                "recip: {n} operands of {steps} steps"
            );
        }
        let (a, _) = edge_cases(UnitKind::Sqrt(golden::fp::Method::Exact));
        for step in -1..=1 {
            for parity in [0x3F80_0000u32, 0x4000_0000] {
                let n = a
                    .iter()
                    .filter(|&&v| v & 0xFF80_0000 == parity && sqrt_correction(v) == Some(step))
                    .count();
                assert!(
                    n >= CORRECTION_EDGES,
                    "sqrt: {n} operands of step {step} at {parity:#x}"
                );
            }
        }
    }

    #[test]
    fn edge_values_cover_both_signs_and_the_specials() {
        let v = edge_values();
        for bits in [
            0x0000_0000,
            0x8000_0000,
            0x0000_0001,
            0x7F80_0000,
            0xFF80_0000,
            0x7FC0_0000,
        ] {
            assert!(v.contains(&bits), "{bits:#010x} missing");
        }
    }

    #[test]
    fn binary_edge_cases_are_all_ordered_pairs_then_the_hard_ones() {
        let n = edge_values().len();
        for (kind, hard) in [
            (UnitKind::Add, ADD_HARD_OPERANDS),
            (UnitKind::FastMul, MUL_HARD_OPERANDS),
        ] {
            let (a, b) = edge_cases(kind);
            let len = n * n + hard.len();
            assert_eq!((a.len(), b.len()), (len, len), "{kind}");
            assert_eq!((a[1], b[1]), (edge_values()[0], edge_values()[1]));
            for (i, &(x, y)) in hard.iter().enumerate() {
                assert_eq!((a[n * n + i], b[n * n + i]), (x, y), "{kind}");
            }
        }
    }

    #[test]
    fn random_chunks_are_reproducible_and_distinct() {
        let one = random_chunk(UnitKind::Mul, 7, 3, 100);
        assert_eq!(one, random_chunk(UnitKind::Mul, 7, 3, 100));
        assert_ne!(one, random_chunk(UnitKind::Mul, 7, 4, 100));
        assert_ne!(one, random_chunk(UnitKind::Mul, 8, 3, 100));
    }
}
