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
/// binary units (and the pairs of [`FAST_ADD_MUTANT_KILLERS`],
/// [`FAST_MUL_MUTANT_KILLERS`]); the edge values (and, for `fp_itof`, the
/// edge integers with both signs; for `fp_exp`, [`EXP_EDGES`] with both
/// signs and their neighbours; the mutant killers) for unary ones. `b` is
/// empty for unary units. A pipelined unit gets its arithmetic's.
pub fn edge_cases(kind: UnitKind) -> (Vec<u32>, Vec<u32>) {
    let values = edge_values();
    if kind.is_binary() {
        let mut a: Vec<u32> = values
            .iter()
            .flat_map(|&x| values.iter().map(move |_| x))
            .collect();
        let mut b: Vec<u32> = values.iter().flat_map(|_| values.iter().copied()).collect();
        let killers = match kind.arithmetic() {
            UnitKind::Add => FAST_ADD_MUTANT_KILLERS,
            UnitKind::Mul => FAST_MUL_MUTANT_KILLERS,
            _ => &[],
        };
        a.extend(killers.iter().map(|&(x, _, _)| x));
        b.extend(killers.iter().map(|&(_, y, _)| y));
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
    // The mutant killers: both processors' lists, for either's unit.
    let killers: [&[(u32, u16)]; 2] = match kind {
        UnitKind::Recip(_) => [RECIP_MUTANT_KILLERS, FAST_RECIP_MUTANT_KILLERS],
        UnitKind::Sqrt(_) => [SQRT_MUTANT_KILLERS, FAST_SQRT_MUTANT_KILLERS],
        UnitKind::Exp => [EXP_MUTANT_KILLERS, FAST_EXP_MUTANT_KILLERS],
        _ => [&[], &[]],
    };
    a.extend(killers.into_iter().flatten().map(|&(v, _)| v));
    (a, Vec::new())
}

/// `fp_recip` operands that kill mutants the other edge cases and the
/// random operands miss, each the smallest bit pattern that does, found by
/// exhaustive simulation (`examples/mutant_exhaustive.rs`, docs/mutation.md),
/// with the mutant. (In every `*_MUTANT_KILLERS` the mutant IDs are of the
/// lists of commit bf3ae96; today's lists, drawn again for refraction,
/// number their mutants otherwise. The operands stay edge cases.) Two are results below the normal range (a of exponent
/// field 253 or 254), where the rounding drops one or two more bits.
pub const RECIP_MUTANT_KILLERS: &[(u32, u16)] = &[
    (0x7F00_1001, 89),   // 3M's bit 13 inverted (fp_recip.v:145): 1 operand of 25.2M
    (0x3F8E_FA43, 393),  // bit 2 of M inverted in rem_q - M (:157): 7
    (0x3F81_64B0, 420),  // rem_q[6] flipped when rem_q[3] is 0 (:125): 14
    (0x3F95_BF00, 474),  // bit 10 of the 2-step arm's rem_fixed (:152): 8
    (0x3F80_A4DA, 768),  // bit 12 of M*q forced in 2^50 - M*q (:134): 323
    (0x7E9B_C000, 1087), // rem_fixed[17] cleared in the sticky (:171): 2
];

/// `fp_sqrt` operands that kill mutants the other edge cases miss; see
/// [`RECIP_MUTANT_KILLERS`].
pub const SQRT_MUTANT_KILLERS: &[(u32, u16)] = &[
    (0x3F84_4570, 686), // rem_full[13] flipped by bit 8 (fp_sqrt.v:152): 43 operands of 16.8M
    (0x406E_9372, 872), // rem_full[8] inverted into rem_q (:232): 1
];

/// `fp_exp` operands that kill mutants the other edge cases and the random
/// operands miss, found by `examples/mutant_exhaustive.rs` (its exponent
/// sweep, then one operand for each value of the unit's fixed-point input
/// below |a| = 128): each the smallest that differs in the first batch that
/// had one; see [`RECIP_MUTANT_KILLERS`].
pub const EXP_MUTANT_KILLERS: &[(u32, u16)] = &[
    (0xB4AE_553E, 58),  // u_q[6] forced 1 in p = 1 + g*u (fp_exp.v:113)
    (0x3951_2AB0, 287), // u_next[2] inverted (:124)
    (0x3980_0400, 425), // in_man[4] inverted into x_right (:85)
    (0x399E_81E8, 655), // u_next[1] flipped by bit 19 (:124)
    (0x3380_8000, 859), // s[35] inverted: the sticky or sig's low bit (:128)
];

/// The fast processor's (`rtl/mutate/fast_pp.mutants`): `fast_fp_recip`
/// operands that kill mutants its other edge cases and random operands
/// miss, each the smallest that differs in the first batch that had one,
/// found by `examples/mutant_exhaustive.rs --processor fast` (7, 89 and 531
/// are mutants of its fast_delay instances, run with `--unit
/// fast_fp_recip`). Every unit with recip's arithmetic gets them.
pub const FAST_RECIP_MUTANT_KILLERS: &[(u32, u16)] = &[
    (0x3F80_A7F4, 311), // fast_fp_recip.v:128
    (0x3F86_908F, 845), // :207
    (0x3F80_1B24, 7),   // a fast_delay of it (fast_delay.v:24)
    (0x3F81_7000, 89),  // a fast_delay of it (fast_delay.v:16)
    (0x3F80_A7F4, 531), // a fast_delay of it (fast_delay.v:16): 311's operand
];

/// `fast_fp_sqrt`'s; see [`FAST_RECIP_MUTANT_KILLERS`].
pub const FAST_SQRT_MUTANT_KILLERS: &[(u32, u16)] = &[
    (0x3F83_3A4E, 378), // fast_fp_sqrt.v:231
    (0x3FCB_41E9, 631), // :235
];

/// `fast_fp_exp`'s; see [`FAST_RECIP_MUTANT_KILLERS`].
pub const FAST_EXP_MUTANT_KILLERS: &[(u32, u16)] = &[
    (0x37DD_7F80, 74),   // fast_fp_exp.v:276
    (0x3F2C_8077, 129),  // :158
    (0x3A8D_4A82, 146),  // :236
    (0x3BD5_6D2F, 150),  // :231
    (0xBF27_1688, 223),  // :184
    (0x3CBF_9A43, 408),  // :150
    (0x3AA9_EDD0, 474),  // :244
    (0x3ACA_95EC, 663),  // :188
    (0x3ACA_95EC, 967),  // :188: 663's operand
    (0x4100_4000, 701),  // :154
    (0x3B5A_8F9C, 771),  // :157
    (0xB945_EC10, 818),  // :124
    (0x3E11_6DA6, 832),  // :137
    (0x3F55_4A6A, 1060), // :167
];

/// The fast processor's `fast_fp_add` operand pairs `(a, b, mutant)` that
/// kill mutants its other edge cases and random operands miss, each the
/// counterexample of `mutants.sh miter` (the pair that entered the
/// pipeline a latency before the outputs differed).
pub const FAST_ADD_MUTANT_KILLERS: &[(u32, u32, u16)] = &[
    (0xA980_0000, 0x1D20_0000, 271), // fast_fp_add.v:117
];

/// `fast_fp_mul`'s; see [`FAST_ADD_MUTANT_KILLERS`] (375 and 585 are of
/// fast_fp_round, which every unit has; the miter showed them in the
/// multiplier's subnormal results).
pub const FAST_MUL_MUTANT_KILLERS: &[(u32, u32, u16)] = &[
    (0x0000_0003, 0x400C_0000, 375), // fast_fp_round.v:61
    (0x3700_0000, 0x0021_0008, 585), // fast_fp_round.v:61
    (0x0000_0241, 0x3C00_0000, 635), // fast_fp_round.v:57
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
    fn binary_edge_cases_are_all_ordered_pairs_then_the_killers() {
        let n = edge_values().len();
        for (kind, killers) in [
            (UnitKind::Add, FAST_ADD_MUTANT_KILLERS),
            (UnitKind::FastMul, FAST_MUL_MUTANT_KILLERS),
        ] {
            let (a, b) = edge_cases(kind);
            let len = n * n + killers.len();
            assert_eq!((a.len(), b.len()), (len, len), "{kind}");
            assert_eq!((a[1], b[1]), (edge_values()[0], edge_values()[1]));
            for (i, &(x, y, _)) in killers.iter().enumerate() {
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
