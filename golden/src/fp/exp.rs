//! Mirror of `rtl/fp/fp_exp.v`: `e^x` for binary32, in fixed point.
//!
//! Range reduction `e^x = 2^t = 2^k * 2^f`, `t = x * log2(e)`, `k` integer,
//! `f` in `[0, 1)`, then `2^f = T[f_hi] * 2^g` with a table of `2^(i/256)`
//! and a quadratic for `2^g`, `g = f_lo < 2^-8`:
//!
//! 1. input: `|x|` as a fixed-point number `X` with [`X_FRAC`] fraction
//!    bits (truncated; `|x| >= 128` is decided here: `+0` or `+inf`).
//! 2. reduce: `t = +-(X * LOG2E) >> LOG2E_FRAC`, [`T_FRAC`] fraction bits;
//!    `k = floor(t)`, `f = t - k` (the two's complement bits).
//! 3. poly 1: `u = ln2 + g * ln2^2/2`.
//! 4. poly 2: `p = 1 + g * u`, i.e. `2^g ~ 1 + g ln2 + (g ln2)^2 / 2`.
//! 5. round: `s = T[f_hi] * p` in `[1, 2]`, normalized, rounded by
//!    `round_pack` at biased exponent `k + 127` (subnormal results and
//!    underflow to zero, overflow to infinity included).
//!
//! Not correctly rounded: the truncations and the dropped cubic term
//! `(g ln2)^3 / 6 < 2^-28.2` leave a relative error below about 2^-27.5
//! before rounding, so the result is within 1 ULP of `e^x` rounded to
//! nearest; `exp_error_over_every_f32_input` measures it.

use super::round::round_pack;
use super::CANONICAL_NAN;

/// Fraction bits of the fixed-point `|x|`.
pub(crate) const X_FRAC: u32 = 32;
/// `round(log2(e) * 2^40)`.
pub(crate) const LOG2E: u64 = 0x171_5476_52B8;
/// Fraction bits of [`LOG2E`].
pub(crate) const LOG2E_FRAC: u32 = 40;
/// Fraction bits of `t` (and so of `f`).
pub(crate) const T_FRAC: u32 = 32;
/// Index bits of the table (`f_hi`, the top bits of `f`).
pub(crate) const TABLE_BITS: u32 = 8;
/// Fraction bits of a table entry `round(2^(i / 256) * 2^30)`.
pub(crate) const TABLE_FRAC: u32 = 30;
/// `round(ln 2 * 2^32)`.
pub(crate) const LN2: u64 = 0xB172_17F8;
/// `round(ln(2)^2 / 2 * 2^32)`.
pub(crate) const LN2_SQ_HALF: u64 = 0x3D7F_7BFF;

/// `round(2^(index / 256) * 2^30)` in IEEE double, exactly as the Verilog
/// constant function evaluates it (`$rtoi(2.0 ** (index / 256.0) *
/// 2.0 ** 30 + 0.5)`: `**` is the C library's `pow`).
pub(crate) fn table_entry(index: u32) -> u32 {
    let scale = f64::from(1u32 << TABLE_FRAC);
    (2f64.powf(f64::from(index) / f64::from(1u32 << TABLE_BITS)) * scale + 0.5) as u32
}

fn table() -> &'static [u32; 1 << TABLE_BITS] {
    static TABLE: std::sync::OnceLock<[u32; 1 << TABLE_BITS]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|i| table_entry(i as u32)))
}

pub(crate) fn exp_bits(a: u32) -> u32 {
    let sign = a >> 31 == 1;
    let field = (a >> 23) & 0xFF;
    let frac = a & 0x7F_FFFF;
    if field == 0xFF {
        return match (frac, sign) {
            (0, true) => 0,
            (0, false) => 0x7F80_0000,
            _ => CANONICAL_NAN,
        };
    }
    // |x| >= 128: e^x is below the smallest subnormal or above the largest
    // float (e^-103.98 and e^88.73 are the limits).
    if field >= 127 + 7 {
        return if sign { 0 } else { 0x7F80_0000 };
    }
    // |x| = m * 2^(e - 150); X = |x| * 2^32 = m * 2^(e - 118), truncated.
    let (m, e) = if field == 0 {
        (u64::from(frac), 1)
    } else {
        (u64::from(frac | 1 << 23), field)
    };
    let e0 = 150 - X_FRAC; // the field whose ULP is 2^-X_FRAC
    let x_fixed = if e >= e0 {
        m << (e - e0)
    } else {
        m.checked_shr(e0 - e).unwrap_or(0)
    };
    // t = +-|x| * log2(e), 32 fraction bits (|t| < 185: 40 bits).
    let t_mag = ((u128::from(x_fixed) * u128::from(LOG2E)) >> LOG2E_FRAC) as i64;
    let t = if sign { -t_mag } else { t_mag };
    let k = (t >> T_FRAC) as i32;
    let f = (t as u64) & ((1 << T_FRAC) - 1);
    let hi = (f >> (T_FRAC - TABLE_BITS)) as usize;
    let lo = f & ((1 << (T_FRAC - TABLE_BITS)) - 1);
    // 2^g, g = lo / 2^32: u = ln2 + g ln2^2/2, p = 1 + g u (32 fraction bits).
    let u = LN2 + ((lo * LN2_SQ_HALF) >> 32);
    let p = (1u64 << 32) + ((lo * u) >> 32);
    // s = T[hi] * p, 62 fraction bits, in [1, 2] (2 only by rounding).
    let s = u64::from(table()[hi]) * p;
    let (exp, sig, sticky) = if s >> 63 == 1 {
        (k + 128, (s >> 37) as u32, s & ((1 << 37) - 1) != 0)
    } else {
        (k + 127, (s >> 36) as u32, s & ((1 << 36) - 1) != 0)
    };
    round_pack(false, exp, sig, sticky)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table is computed with the C library's `pow` on both sides; an
    /// entry is safe from a last-bit difference between libraries when its
    /// scaled value is not within 2^-20 of a rounding tie.
    #[test]
    fn table_entries_are_far_from_rounding_ties() {
        for i in 0..1u32 << TABLE_BITS {
            let v = 2f64.powf(f64::from(i) / 256.0) * f64::from(1u32 << TABLE_FRAC);
            let tie_distance = ((v - v.floor()) - 0.5).abs();
            assert!(tie_distance > 1.0 / f64::from(1u32 << 20), "entry {i}: {v}");
            assert!(table_entry(i) >> TABLE_FRAC == 1, "entry {i} not in [1, 2)");
        }
    }

    #[test]
    fn the_constants_are_the_rounded_values() {
        let close = |c: u64, frac: u32, want: f64| {
            (c as f64 / 2f64.powi(frac as i32) - want).abs() <= 2f64.powi(-(frac as i32) - 1)
        };
        assert!(close(LOG2E, LOG2E_FRAC, std::f64::consts::LOG2_E));
        assert!(close(LN2, 32, std::f64::consts::LN_2));
        assert!(close(
            LN2_SQ_HALF,
            32,
            std::f64::consts::LN_2 * std::f64::consts::LN_2 / 2.0
        ));
    }

    /// How far [`exp_bits`] is from [`super::super::exp_reference`] over a
    /// range of input bit patterns: inputs at 0, 1 and more ULPs, NaN
    /// mismatches, the worst distance and where, and the worst error in
    /// fractions of an ULP against the f64 value (before its rounding).
    #[derive(Debug, Default, Clone, Copy)]
    struct ExpTally {
        by_ulps: [u64; 3],
        nan_mismatches: u64,
        worst: u32,
        worst_input: u32,
        worst_fraction: f64,
        worst_fraction_input: u32,
    }

    impl ExpTally {
        fn merge(mut self, o: ExpTally) -> ExpTally {
            for i in 0..3 {
                self.by_ulps[i] += o.by_ulps[i];
            }
            self.nan_mismatches += o.nan_mismatches;
            if o.worst > self.worst {
                (self.worst, self.worst_input) = (o.worst, o.worst_input);
            }
            if o.worst_fraction > self.worst_fraction {
                (self.worst_fraction, self.worst_fraction_input) =
                    (o.worst_fraction, o.worst_fraction_input);
            }
            self
        }
    }

    fn tally(bits: std::ops::Range<u64>) -> ExpTally {
        use crate::fp::{exp_reference, ulp_distance, UlpDistance};
        use rayon::prelude::*;
        let chunks = bits.start / (1 << 20)..bits.end.div_ceil(1 << 20);
        chunks
            .into_par_iter()
            .map(|c| {
                let mut t = ExpTally::default();
                let lo = (c << 20).max(bits.start);
                let hi = ((c + 1) << 20).min(bits.end);
                for b in lo..hi {
                    let b = b as u32;
                    let x = f32::from_bits(b);
                    let got = f32::from_bits(exp_bits(b));
                    match ulp_distance(got, exp_reference(x), false) {
                        UlpDistance::NanMismatch => t.nan_mismatches += 1,
                        UlpDistance::Ulps(d) => {
                            t.by_ulps[d.min(2) as usize] += 1;
                            if d > t.worst {
                                (t.worst, t.worst_input) = (d, b);
                            }
                        }
                    }
                    let truth = f64::from(x).exp();
                    if got.is_finite() && truth.is_finite() && truth > 0.0 {
                        // One ULP of f32 at the true value (subnormal spacing below).
                        let ulp = 2f64.powi((truth.log2().floor() as i32).max(-126) - 23);
                        let fraction = (f64::from(got) - truth).abs() / ulp;
                        if fraction > t.worst_fraction {
                            (t.worst_fraction, t.worst_fraction_input) = (fraction, b);
                        }
                    }
                }
                t
            })
            .reduce(ExpTally::default, ExpTally::merge)
    }

    /// The exhaustive measurement docs/fp.md reports: every f32 with the
    /// sign bit set (all of x <= -0, -inf and the NaNs included), and every
    /// positive input too. Run with
    /// `cargo test --release -p golden --lib exp_error -- --ignored --nocapture`.
    #[test]
    #[ignore = "2^32 inputs; run with --release --ignored (about 2.5 minutes on two cores)"]
    fn exp_error_over_every_f32_input() {
        for (name, range) in [
            ("x <= -0 (sign set)", 0x8000_0000u64..1 << 32),
            ("x >= +0 (sign clear)", 0..0x8000_0000),
        ] {
            let t = tally(range);
            println!(
                "{name}: 0 ulp {}, 1 ulp {}, >1 ulp {}, NaN mismatches {}, worst {} ulp at {:#010x} ({:e}), worst {:.4} ulp of the f64 value at {:#010x} ({:e})",
                t.by_ulps[0],
                t.by_ulps[1],
                t.by_ulps[2],
                t.nan_mismatches,
                t.worst,
                t.worst_input,
                f32::from_bits(t.worst_input),
                t.worst_fraction,
                t.worst_fraction_input,
                f32::from_bits(t.worst_fraction_input)
            );
            assert_eq!(t.nan_mismatches, 0, "{name}");
            assert!(t.worst <= 1, "{name}: worst {} ulp", t.worst);
        }
    }

    /// Values from the definition, not from the model: special inputs and
    /// e^x at points whose f32 result is known.
    #[test]
    fn special_inputs_and_known_values() {
        let e = |x: f32| f32::from_bits(exp_bits(x.to_bits()));
        assert_eq!(e(0.0).to_bits(), 1.0f32.to_bits());
        assert_eq!(e(-0.0).to_bits(), 1.0f32.to_bits());
        assert_eq!(e(f32::NEG_INFINITY).to_bits(), 0);
        assert_eq!(e(f32::INFINITY).to_bits(), 0x7F80_0000);
        assert_eq!(exp_bits(0xFFC0_1234), CANONICAL_NAN);
        assert_eq!(exp_bits(0x7F80_0001), CANONICAL_NAN);
        assert_eq!(e(-200.0).to_bits(), 0);
        assert_eq!(e(-104.0).to_bits(), 0); // e^-104 < 2^-150: rounds to +0
        assert_eq!(e(89.0).to_bits(), 0x7F80_0000);
        assert_eq!(e(f32::from_bits(1)).to_bits(), 1.0f32.to_bits());
        // e^-103 = 1.3e-45 ~ 0.93 * 2^-149: the smallest subnormal.
        assert_eq!(e(-103.0).to_bits(), 1);
        // e^-1 = 0.36787944117..., f32 0x3EBC5AB2 (0.36787945).
        let d = |x: f32, want: u32| {
            let got = e(x).to_bits();
            assert!(
                got.abs_diff(want) <= 1,
                "e^{x}: {got:#010x}, want {want:#010x}"
            );
        };
        d(-1.0, 0x3EBC_5AB2);
        d(1.0, 0x402D_F854); // 2.7182817
        d(-0.5, 0x3F1B_4598); // 0.60653067
        d(-10.0, 0x383E_6BCE); // 4.539993e-5
    }
}
